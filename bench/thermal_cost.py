#!/usr/bin/python3
"""Cost of the thermal rod per force (RHS) evaluation, against the deterministic rod, side by side.

The Langevin step (solver.time = "langevin": an exact friction-and-noise step of dt/2, one
RK4 step, another of dt/2; docs/thermal.md) against plain RK4 at the same dt on the same rod:
wall seconds per RHS evaluation from the run's own summary, runs taken in turn (rk4,
langevin, rk4, ...) and the ratio taken pair by pair, median and range quoted. The paper's
DNA material in water at 300 K, straight and twisted (the diagonal kernel: the cheapest RHS,
so the largest ratio), for N = 158 (the 158-bp rod, one point per bp), 1024 and 4096.
Target (docs/thermal.md): <= 1.3x.

    /usr/bin/python3 bench/thermal_cost.py [--pairs 7] [--out bench/results/thermal_cost.json]

Needs the Python module rodcore on PYTHONPATH (build/python).
"""
from __future__ import annotations

import argparse
import statistics
import sys
from pathlib import Path

import rodcore

from mdbridge.jsonio import write_json

HERE = Path(__file__).resolve().parent


def scene(N: int, method: str, steps: int) -> dict:
    L = N * 3.38 / 5.0                      # one point per base pair (rise 3.38 A, l = 5 A)
    dt = 0.02
    twist = 2 * 3.141592653589793 / 10.5 * N / L  # 10.5 bp per turn
    sc = {"rod": {"length": L, "points": N, "Gamma0": [0, 0, 1.0], "Omega0": [0, 0, twist]},
          "solver": {"time": method, "dt": dt, "space": "spectral"},
          "output": {"t_end": steps * dt, "frames": 2}}
    if method == "langevin":
        sc["thermal"] = {"temperature_K": 300.0, "friction_translational": "water", "friction_rotational": "water",
                         "sample_initial": False}
    return sc


def per_eval(N: int, method: str, steps: int) -> float:
    s = rodcore.run(scene(N, method, steps))["summary"]
    return s["wall_seconds"] / s["rhs_evaluations"]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--pairs", type=int, default=7)
    ap.add_argument("--out", type=Path, default=HERE / "results" / "thermal_cost.json")
    args = ap.parse_args(argv)
    rows = []
    for N, steps in ((158, 4000), (1024, 1000), (4096, 300)):
        per_eval(N, "rk4", steps // 4)                  # warm-up (FFTW plans, caches)
        per_eval(N, "langevin", steps // 4)
        det, lan = [], []
        for _ in range(args.pairs):
            det.append(per_eval(N, "rk4", steps))
            lan.append(per_eval(N, "langevin", steps))
        ratios = [b / a for a, b in zip(det, lan)]
        row = {"N": N, "steps": steps, "rk4_us_per_eval": 1e6 * statistics.median(det),
               "langevin_us_per_eval": 1e6 * statistics.median(lan),
               "ratio_median": statistics.median(ratios), "ratio_min": min(ratios), "ratio_max": max(ratios)}
        rows.append(row)
        print(f"N = {N:5d}: rk4 {row['rk4_us_per_eval']:8.2f} us/eval, langevin {row['langevin_us_per_eval']:8.2f}"
              f" us/eval, ratio {row['ratio_median']:.3f} (range {row['ratio_min']:.3f}-{row['ratio_max']:.3f})")
    write_json(args.out, {"what": __doc__.splitlines()[0], "pairs": args.pairs, "rows": rows,
                          "command": "/usr/bin/python3 bench/thermal_cost.py"})
    return 0


if __name__ == "__main__":
    sys.exit(main())
