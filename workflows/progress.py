"""Progress of a long step, one mechanism for every dnarod command.

`Progress(label, total, unit)` takes `update(done)` calls and shows them:
- on a terminal, one line redrawn in place: done/total, percent, rate, time left;
- anywhere else (a pipe, a Snakemake log), a plain line every `every_s` seconds
  from the first update on, and one at the end if any was written: logs of long
  steps show progress without a flood, and a short step stays quiet in a pipe.
The plain line has one fixed format, `LABEL: progress D/T UNIT (P %), RATE, T left`
(`parse_line` reads it back), so that a command that only sees another
command's log, e.g. `dnarod compare` watching its MD jobs, can show it too.

Rates: `rate` turns units per second into text; `md_rate` gives ns/day for ps.

`Stages(command)` is the progress of a command made of stages (build-md: the rod run,
the minimisation, the equilibration): called as stages(stage, done, total, unit) (and
time_left=False for a stage whose total is a limit, not a length: a minimisation), it
keeps one `Progress` labelled `COMMAND: STAGE` and closes it when the next stage
starts. `Progress.above(text)` prints other output (e.g. Snakemake's, in `dnarod
compare`) above a live line without breaking it.
"""
from __future__ import annotations

import os
import re
import sys
import time


def md_rate(ps_per_s: float) -> str:
    return f"{ps_per_s * 86400.0 / 1000.0:.3g} ns/day"


def duration(s: float) -> str:
    s = max(0, int(round(s)))
    h, m = divmod(s, 3600)
    m, s = divmod(m, 60)
    return f"{h}:{m:02d}:{s:02d}" if h else f"{m}:{s:02d}"


LINE = re.compile(r"^(?P<label>.+?): progress (?P<done>[0-9.eE+-]+)/(?P<total>[0-9.eE+-]+) (?P<unit>\S+)"
                  r" \((?P<pct>[0-9.]+) %\)(?:, (?P<rate>[^,]+))?(?:, (?P<left>\S+) left)?\s*$")


def parse_line(line: str) -> dict | None:
    """The fields of a plain progress line, or None if LINE is not one."""
    m = LINE.match(line.strip())
    return m.groupdict() if m else None


def last_progress(path) -> dict | None:
    """The last plain progress line of a log file (None if there is none)."""
    try:
        with open(path, errors="replace") as f:
            lines = f.read().splitlines()
    except OSError:
        return None
    for ln in reversed(lines):
        p = parse_line(ln)
        if p:
            return p
    return None


REDRAW_S = 0.1   # a live line is redrawn at most this often
STDERR = object()   # the default stream: sys.stderr at the time a Progress is made


class Progress:
    def __init__(self, label: str, total: float, unit: str = "", *, stream=STDERR,
                 rate=None, every_s: float = 60.0, redraw: bool | None = None,
                 clock=time.monotonic, time_left: bool = True):
        self.label, self.total, self.unit = label, float(total), unit
        # False for a stage whose total is only a limit (a minimisation stops when it
        # converges, usually far below its step limit): no time left is shown then
        self.time_left = time_left
        # sys.stderr as it is now (a caller may have replaced it), None for silence
        self.stream = sys.stderr if stream is STDERR else stream
        self.rate = rate or (lambda per_s: f"{per_s:.3g} {unit}/s")
        self.every_s = every_s
        self.clock = clock
        # redraw in place on a terminal unless told otherwise (several concurrent
        # progress lines, e.g. `dnarod compare`, use plain lines on a terminal too)
        self.tty = bool(self.stream is not None and hasattr(self.stream, "isatty") and self.stream.isatty()) \
            if redraw is None else redraw
        self._first: tuple[float, float] | None = None   # (time, done) of the first update
        self._last_plain: float | None = None             # time of the last plain line
        self._drawn = False
        self._pending = False                             # an update not yet drawn (tty)
        self._last_draw: float | None = None
        self._wrote_plain = False
        self.done = 0.0

    def text(self) -> str:
        pct = 100.0 * self.done / self.total if self.total > 0 else 0.0
        out = f"{self.label}: progress {self.done:g}/{self.total:g} {self.unit} ({pct:.1f} %)"
        if self._first is not None:
            dt = self.clock() - self._first[0]
            dd = self.done - self._first[1]
            if dt > 0 and dd > 0:
                per_s = dd / dt
                out += f", {self.rate(per_s)}"
                if self.time_left:
                    out += f", {duration((self.total - self.done) / per_s)} left"
        return out

    def update(self, done: float, *, force: bool = False) -> None:
        self.done = float(done)
        now = self.clock()
        if self._first is None:
            self._first = (now, self.done)
        if self._last_plain is None:
            self._last_plain = now  # the first plain line comes every_s after the start
        if self.stream is None:
            return
        if self.tty:
            # redrawn at most every REDRAW_S (mdrun reports every step), the last state at close
            if force or self._last_draw is None or now - self._last_draw >= REDRAW_S:
                self._draw(now)
            else:
                self._pending = True
        elif force or now - self._last_plain >= self.every_s:
            self._last_plain = now
            self._wrote_plain = True
            self.stream.write(self.text() + "\n")
            self.stream.flush()

    def _live(self) -> str:
        """The live line, cut to the terminal's width: a wrapped line could not be
        redrawn in place."""
        text = self.text()
        try:
            width = os.get_terminal_size(self.stream.fileno()).columns
        except (AttributeError, OSError, ValueError):
            width = 0
        return text[:width - 1] if width > 20 and len(text) >= width else text

    def _draw(self, now: float) -> None:
        assert self.stream is not None
        self.stream.write("\r\033[K" + self._live())
        self.stream.flush()
        self._drawn, self._pending, self._last_draw = True, False, now

    def above(self, text: str) -> None:
        """Write TEXT (whole lines) to the stream; on a terminal the live line is wiped
        first and redrawn after it, so other output and the live line do not mix."""
        if self.stream is None:
            return
        if self.tty and self._drawn:
            self.stream.write("\r\033[K" + text + ("" if text.endswith("\n") else "\n") + self._live())
        else:
            self.stream.write(text + ("" if text.endswith("\n") else "\n"))
        self.stream.flush()

    def close(self) -> None:
        if self.stream is None:
            return
        if self.tty:
            if self._pending:
                self._draw(self.clock())
            if self._drawn:
                self.stream.write("\n")
                self._drawn = False
        elif self._wrote_plain:
            self.stream.write(self.text() + "\n")
            self._wrote_plain = False
        self.stream.flush()


class Stages:
    """One Progress per stage of a command: stages(stage, done, total, unit, rate=None)
    updates the stage's line (label `COMMAND: STAGE`), closing the previous stage's
    first. Use as a context manager (or call close()) so that the last line is ended
    before anything else, an error message included, is printed."""

    def __init__(self, command: str, **kwargs):
        self.command, self.kwargs = command, kwargs
        self.stage: str | None = None
        self.bar: Progress | None = None

    def __call__(self, stage: str, done: float, total: float, unit: str = "", rate=None,
                 time_left: bool = True) -> None:
        if self.bar is None or stage != self.stage:
            self.close()
            self.stage = stage
            self.bar = Progress(f"{self.command}: {stage}", total, unit, rate=rate, time_left=time_left,
                                **self.kwargs)
        self.bar.update(done)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
        self.bar = None

    def __enter__(self) -> "Stages":
        # a warning printed while a live line is drawn would run on from it: end the line
        import warnings
        self._showwarning = warnings.showwarning

        def show(*args, **kwargs):
            self.close()
            self._showwarning(*args, **kwargs)
        warnings.showwarning = show
        return self

    def __exit__(self, *exc) -> None:
        import warnings
        warnings.showwarning = self._showwarning
        self.close()
