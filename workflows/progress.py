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
"""
from __future__ import annotations

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


class Progress:
    def __init__(self, label: str, total: float, unit: str = "", *, stream=sys.stderr,
                 rate=None, every_s: float = 60.0, redraw: bool | None = None,
                 clock=time.monotonic):
        self.label, self.total, self.unit = label, float(total), unit
        self.stream = stream
        self.rate = rate or (lambda per_s: f"{per_s:.3g} {unit}/s")
        self.every_s = every_s
        self.clock = clock
        # redraw in place on a terminal unless told otherwise (several concurrent
        # progress lines, e.g. `dnarod compare`, use plain lines on a terminal too)
        self.tty = bool(stream is not None and hasattr(stream, "isatty") and stream.isatty()) \
            if redraw is None else redraw
        self._first: tuple[float, float] | None = None   # (time, done) of the first update
        self._last_plain: float | None = None             # time of the last plain line
        self._drawn = False
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
                out += f", {self.rate(per_s)}, {duration((self.total - self.done) / per_s)} left"
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
            self.stream.write("\r\033[K" + self.text())
            self.stream.flush()
            self._drawn = True
        elif force or now - self._last_plain >= self.every_s:
            self._last_plain = now
            self._wrote_plain = True
            self.stream.write(self.text() + "\n")
            self.stream.flush()

    def close(self) -> None:
        if self.stream is None:
            return
        if self.tty:
            if self._drawn:
                self.stream.write("\n")
        elif self._wrote_plain:
            self.stream.write(self.text() + "\n")
        self.stream.flush()
