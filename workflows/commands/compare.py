"""`dnarod compare`: the scripted rod-vs-MD comparison (Snakemake pipeline)."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from dna_models.errors import ExternalToolError, InputError

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

Configuration (YAML): workflows/config/default.yaml documents every key. Shipped:
  default.yaml  the 158-bp scene: A_v = 1 A/ps with 600 ps of MD (a wave period) and an
                A_v = 0 equilibrium run of 150 ps (estimated ~55 min with setup, 2 cores)
  paper.yaml    the paper's 600 ps of MD for A_v = 0, 1, 5, three seeds (~38 h, 2 cores)
  tiny.yaml     21 bp, a few ps (CI)

Examples:
  dnarod compare --out compare-default
  dnarod compare --config workflows/config/tiny.yaml --out /tmp/tiny --cores 2
  dnarod compare --config my.yaml --out runs/x -- --dry-run      (extra Snakemake options after --)
"""

ROOT = Path(__file__).resolve().parents[2]


def add_arguments(p):
    p.add_argument("--config", default=str(ROOT / "workflows" / "config" / "default.yaml"),
                   help="workflow configuration (YAML); default: workflows/config/default.yaml")
    p.add_argument("--out", default="compare-out", help="output directory (default: ./compare-out)")
    p.add_argument("--cores", type=int, default=2, help="cores Snakemake may use at once (default 2)")
    p.add_argument("snakemake_args", nargs="*", help="extra Snakemake options, after `--`")


def _run_showing_md_progress(cmd, env, out: Path, poll_s: float = 5.0) -> int:
    """Run Snakemake; meanwhile show the progress of every running MD job, read from
    the plain progress lines `dnarod run-md` writes into md/*/run-md.log
    (workflows/progress.py): every 15 s on a terminal, every minute in a log."""
    from dnarod.progress import Progress, last_progress, md_rate
    every = 15.0 if sys.stderr.isatty() else 60.0
    shown: dict[str, Progress] = {}
    proc = subprocess.Popen(cmd, env=env)
    while True:
        try:
            rc = proc.wait(timeout=poll_s)
            break
        except subprocess.TimeoutExpired:
            pass
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
                                                        every_s=every, redraw=False)
            bar.update(float(p["done"]))
    return rc


def run(args) -> int:
    from dnarod.configuration import load
    cfg = Path(args.config)
    load(cfg)  # every key checked before anything runs (workflows/config/schema.yaml)
    if args.cores < 1:
        raise InputError(f"--cores {args.cores}: must be at least 1")
    out = Path(args.out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    bin_dir = os.environ.get("DNAROD_BIN_DIR") or str(ROOT / "build" / "bin")
    cmd = [sys.executable, "-m", "snakemake", "-s", str(ROOT / "workflows" / "Snakefile"),
           "--configfile", str(cfg.resolve()), "--config", f"bin_dir={bin_dir}", f"python={sys.executable}",
           "--directory", str(out), "--cores", str(args.cores), "--printshellcmds",
           "--rerun-incomplete", "--keep-going"] + list(args.snakemake_args)
    rc = _run_showing_md_progress(cmd, dict(os.environ), out)
    if rc != 0:
        raise ExternalToolError(f"the workflow stopped (snakemake exit {rc}); the failing step's log is "
                                f"named above (under {out}); rerun the same command to resume")
    print(f"report: {out / 'report' / 'index.html'}\nresults: {out / 'results.json'}")
    return 0
