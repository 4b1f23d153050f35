"""`dnarod compare`: the scripted rod-vs-MD comparison (Snakemake pipeline)."""
from __future__ import annotations

import os
import re
import subprocess
import sys
import threading
from pathlib import Path

from dna_models.errors import ExternalToolError, InputError
from dnarod import validate
from dnarod.commands._options import add_output

NAME = "compare"
HELP = "rod vs all-atom MD: run the whole comparison workflow and write a report"
DESCRIPTION = """\
Run the comparison of paper Sec 6 as one resumable Snakemake workflow
(workflows/Snakefile):

  rod scene (per A_v) -> rodsim run -> dnarod build-md (per seed) -> dnarod run-md
  -> the same analysis on rod and MD (helical axis, u(s, t), wave speed, planarity,
     base-pair integrity) -> rod-vs-MD fit -> DIR/results.json, DIR/report/index.html

plus a rod-only sweep of the wave speed over the velocity amplitude A_v. Runs that
are already done are not repeated (rerun the same command after an interruption);
independent runs go in parallel up to --cores. An interrupted MD continues from
its last checkpoint; the progress of every running MD (ps, ns/day, time left) is
printed while the workflow runs.

Configuration (YAML): workflows/config/default.yaml documents every key; each
shipped file says at its top what it runs and what it costs. Shipped (workflows/config/):
  default.yaml          the main job (scripts/run.sh): 158 bp, A_v = 0 and 1 A/ps, a wave period of MD
  dispersion.yaml       158 bp unkicked, 5 ns at 300 K: the MD's mode spectra against the rods' (docs/dispersion.md)
  dispersion_water.yaml the same in TIP3P water, 150 mM NaCl, at 20 pN: for a cluster (docs/workflow.md)
  headline.yaml         default.yaml restricted to A_v = 1 A/ps (the README's worked example)
  paper.yaml            the paper's MD: 600 ps for A_v = 0, 1, 5 A/ps, three seeds each
  prediction.yaml       default.yaml with an A_v = 0 run long enough for the coarse-grained prediction
  small_amplitude.yaml  small kicks (A_v = 0, 0.1, 0.2 A/ps), ns of MD, four seeds each
  tiny.yaml             21 bp, a few ps of MD (CI)

Examples:
  dnarod compare                                   (default.yaml, into out/compare)
  dnarod compare --config workflows/config/tiny.yaml -o /tmp/tiny --cores 2
  dnarod compare --config my.yaml -o runs/x -- --dry-run      (extra Snakemake options after --)
"""

ROOT = Path(__file__).resolve().parents[2]


def add_arguments(p):
    p.add_argument("--config", default=str(ROOT / "workflows" / "config" / "default.yaml"),
                   help="workflow configuration (YAML); default: workflows/config/default.yaml")
    add_output(p, metavar="DIR", required=False, default="out/compare",
               help="output directory (default: out/compare, the README's)")
    p.add_argument("--cores", type=validate.integer(min=1), default=2,
                   help="cores Snakemake may use at once (default 2)")
    p.add_argument("snakemake_args", nargs="*", help="extra Snakemake options, after `--`")


JOB_STATS_TOTAL = re.compile(r"^total\s+(\d+)\b")
JOB_RULE = re.compile(r"^(?:local)?(?:rule|checkpoint) (\S+):\s*$")
JOB_ERROR = re.compile(r"^Error in rule (\S+):\s*$")
JOB_ID = re.compile(r"^\s+jobid: (\d+)\s*$")
JOB_WILDCARDS = re.compile(r"^\s+wildcards: (.*)$")
JOB_FINISHED = re.compile(r"^Finished job (\d+)\.")
JOBS_DONE = re.compile(r"^(\d+) of (\d+) steps \(\d+%\) done")


class WorkflowProgress:
    """Jobs done / total and the running jobs, read from Snakemake 7's own log lines
    ("Job stats: ... total N", "rule NAME:" + "jobid: J" + "wildcards: ...",
    "Finished job J.", "Error in rule NAME:", "N of M steps (P%) done"), with one
    dnarod.progress.Progress labelled by the running jobs. Every line is passed on
    unchanged (above the live line on a terminal); `line_stream` is where other
    progress lines (the MD's) go so that they do not break the live line."""

    def __init__(self, stream=None, every_s: float = 60.0):
        from dnarod.progress import Progress
        self.stream = stream = stream if stream is not None else sys.stderr
        self.lock = threading.Lock()
        self.running: dict[str, str] = {}
        self._block: tuple[str, str | None] | None = None   # ("rule"|"error", jobid) being read
        self._rule = ""
        self.bar = Progress("compare", 0, "jobs", stream=stream, every_s=every_s,
                            rate=lambda per_s: f"{per_s * 60:.2g} jobs/min")
        self.total: int | None = None

    def _label(self) -> str:
        jobs = list(self.running.values())
        if not jobs:
            return "compare"
        shown = ", ".join(jobs[:2]) + (f" +{len(jobs) - 2} more" if len(jobs) > 2 else "")
        return f"compare [running {shown}]"

    def _show(self) -> None:
        if self.total:
            self.bar.label = self._label()
            self.bar.update(self.bar.done, force=False)

    def line(self, text: str) -> None:
        """One line of Snakemake's output: pass it on, then update the counts."""
        ln = text.rstrip("\n")
        with self.lock:
            self.bar.above(ln)
            m = JOB_STATS_TOTAL.match(ln)
            if m and self.total is None:
                self.total = int(m.group(1))
                self.bar.total = float(self.total)
            elif (m := JOB_RULE.match(ln)):
                self._rule, self._block = m.group(1), ("rule", None)
            elif (m := JOB_ERROR.match(ln)):
                self._rule, self._block = m.group(1), ("error", None)
            elif self._block and (m := JOB_ID.match(ln)):
                kind = self._block[0]
                self._block = (kind, m.group(1))
                if kind == "rule":
                    self.running[m.group(1)] = self._rule
                else:
                    self.running.pop(m.group(1), None)
            elif self._block and self._block[1] and (m := JOB_WILDCARDS.match(ln)):
                if self._block[0] == "rule":
                    self.running[self._block[1]] = f"{self._rule} ({m.group(1).strip()})"
            elif (m := JOB_FINISHED.match(ln)):
                self.running.pop(m.group(1), None)
            elif (m := JOBS_DONE.match(ln)):
                self.total = int(m.group(2))
                self.bar.total = float(self.total)
                self.bar.done = float(m.group(1))
            if not ln.strip():
                self._block = None
            self._show()

    def tick(self) -> None:
        """Called while waiting: a plain line when one is due (in a pipe, every every_s)."""
        with self.lock:
            self._show()

    def above(self, text: str) -> None:
        with self.lock:
            self.bar.above(text.rstrip("\n"))

    def close(self) -> None:
        with self.lock:
            if self.total:
                self.bar.close()


class _Above:
    """A stream for other progress lines: each written line goes above the live line."""

    def __init__(self, watch: WorkflowProgress):
        self.watch = watch

    def write(self, text: str) -> None:
        for ln in text.splitlines():
            self.watch.above(ln)

    def flush(self) -> None:
        pass

    def isatty(self) -> bool:
        return False


def _run_showing_progress(cmd, env, out: Path, poll_s: float = 5.0) -> int:
    """Run Snakemake, passing its output (stderr) on, and show the progress of the
    workflow (WorkflowProgress: jobs done / total, the running jobs) and of every
    running MD job, read from the plain progress lines `dnarod run-md` writes into
    md/*/run-md.log (workflows/progress.py): on a terminal the jobs as a live line and
    each MD every 15 s above it; in a pipe or log a plain line of each every minute."""
    from dnarod.progress import Progress, last_progress, md_rate
    tty = sys.stderr.isatty()
    every = 15.0 if tty else 60.0
    watch = WorkflowProgress(sys.stderr)
    shown: dict[str, Progress] = {}
    proc = subprocess.Popen(cmd, env=env, stderr=subprocess.PIPE, text=True, bufsize=1,
                            errors="replace")

    def forward():
        assert proc.stderr is not None
        for ln in proc.stderr:
            watch.line(ln)

    reader = threading.Thread(target=forward, daemon=True)
    reader.start()
    try:
        while True:
            try:
                rc = proc.wait(timeout=poll_s)
                break
            except subprocess.TimeoutExpired:
                pass
            watch.tick()
            for log in sorted(out.glob("md/*/run-md.log")):
                if (log.parent / "md.done").exists():
                    shown.pop(log.parent.name, None)
                    continue
                p = last_progress(log)
                if p is None:
                    continue
                bar = shown.get(log.parent.name)
                if bar is None:
                    bar = shown[log.parent.name] = Progress(f"compare: md/{log.parent.name}",
                                                            float(p["total"]), p["unit"], rate=md_rate,
                                                            every_s=every, redraw=False,
                                                            stream=_Above(watch))
                bar.update(float(p["done"]))
        reader.join(timeout=30)
    except KeyboardInterrupt:
        # Ctrl-C reached Snakemake too: keep passing on its shutdown messages until it exits
        try:
            proc.wait(timeout=120)
            reader.join(timeout=10)
        except (KeyboardInterrupt, subprocess.TimeoutExpired):
            proc.kill()
        raise
    finally:
        watch.close()
    return rc


def run(args) -> int:
    from dnarod.configuration import load
    cfg = validate.input_file(args.config, "--config", "YAML")
    load(cfg)  # every key checked before anything runs (workflows/config/schema.yaml)
    if args.cores < 1:
        raise InputError(f"--cores {args.cores}: must be at least 1")
    out = validate.output_folder(args.output, command="compare").resolve()
    bin_dir = os.environ.get("DNAROD_BIN_DIR") or str(ROOT / "build" / "bin")
    cmd = [sys.executable, "-m", "snakemake", "-s", str(ROOT / "workflows" / "Snakefile"),
           "--configfile", str(cfg.resolve()), "--config", f"bin_dir={bin_dir}", f"python={sys.executable}",
           "--directory", str(out), "--cores", str(args.cores), "--printshellcmds",
           "--rerun-incomplete", "--keep-going"] + list(args.snakemake_args)
    rc = _run_showing_progress(cmd, dict(os.environ), out)
    if rc != 0:
        raise ExternalToolError(f"the workflow stopped (snakemake exit {rc}); the failing step's log is "
                                f"named above (under {out}); rerun the same command to resume")
    print(f"report: {out / 'report' / 'index.html'}\nresults: {out / 'results.json'}")
    return 0
