#!/usr/bin/python3
"""Two rodsim builds on the shipped 10.5-kbp ring (workflows/scenes/dna10k_water.toml, solver.time =
"brownian"), side by side in one run: the CPU seconds per 100-ps step of each, from the child
process's own accounting (user + sys), as (CPU of a run of --steps steps - CPU of a run of 1 step) /
(--steps - 1), so the start (the exact sample, its closure) cancels. The builds run in turn, old then
new, --pairs times; quoted: each build's median and range, and the new/old ratio pair by pair.

    /usr/bin/python3 bench/brownian_solver.py --old OLD/bin/rodsim --new NEW/bin/rodsim
        [--steps 200] [--pairs 3] [--old-label COMMIT] [--new-label COMMIT]
        [--out bench/results/brownian_solver.json]
"""
from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from kilobase_ring import DT, SCENE, report  # noqa: E402  (the shipped ring and its own step)


def cpu_of_run(rodsim: str, steps: int, out: Path) -> float:
    """CPU seconds (user + sys) of one rodsim run of `steps` steps, 2 frames."""
    p = subprocess.Popen([rodsim, "run", str(SCENE), "-o", str(out), "--set", f"output.t_end={steps * DT!r}",
                          "--set", "output.frames=2"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    _, status, ru = os.wait4(p.pid, 0)
    if status != 0:
        raise RuntimeError(f"{rodsim} exited with status {status}")
    return ru.ru_utime + ru.ru_stime


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--old", required=True)
    ap.add_argument("--new", required=True)
    ap.add_argument("--steps", type=int, default=200)
    ap.add_argument("--pairs", type=int, default=3)
    ap.add_argument("--old-label", default="", help="what the old build is (a commit)")
    ap.add_argument("--new-label", default="", help="what the new build is (a commit)")
    ap.add_argument("--out", type=Path)
    a = ap.parse_args(argv)
    per_step: dict[str, list[float]] = {"old": [], "new": []}
    with tempfile.TemporaryDirectory() as tmp:
        for _ in range(a.pairs):
            for name in ("old", "new"):
                exe = getattr(a, name)
                one = cpu_of_run(exe, 1, Path(tmp) / "one.h5")
                many = cpu_of_run(exe, a.steps, Path(tmp) / "many.h5")
                per_step[name].append((many - one) / (a.steps - 1))
    ratio = [n / o for o, n in zip(per_step["old"], per_step["new"])]
    res = {"scene": str(SCENE.relative_to(HERE.parent)), "steps": a.steps, "pairs": a.pairs,
           "builds": {"old": a.old_label, "new": a.new_label},
           "command": "/usr/bin/python3 bench/brownian_solver.py " + " ".join(sys.argv[1:] if argv is None else argv),
           "cpu_s_per_step_median": {k: statistics.median(v) for k, v in per_step.items()},
           "cpu_s_per_step_range": {k: [min(v), max(v)] for k, v in per_step.items()},
           "new_over_old_median": statistics.median(ratio), "new_over_old_range": [min(ratio), max(ratio)],
           "one_us_cpu_s_new": statistics.median(per_step["new"]) * 10000}
    report(res, a.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
