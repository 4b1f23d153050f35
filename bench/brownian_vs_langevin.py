#!/usr/bin/python3
"""The overdamped rod (solver.time = "brownian") against the inertial Langevin rod on the same coarse
rod, in the same run: a box-held straight DNA rod of 1050 bp at 10 bp per point (N = 105, the paper's
material, untwisted), water at 300 K, started from rest (no thermal sample), for the same simulated
time. Each at its own step: Langevin at 0.5 of its RK4 stability limit (the sound crossing of a
cell), brownian at `--dt-ps`. Quoted: wall seconds from the runs' summaries (pairs in turn, median
and range), bp us per CPU second, and the mean elastic energy over the second half against
equipartition's (6 N - 6) kT / 2 (Langevin: the strain part only).

    /usr/bin/python3 bench/brownian_vs_langevin.py [--ns 20] [--dt-ps 100] [--pairs 3]
        [--out bench/results/brownian_vs_langevin.json]

Needs the Python module rodcore on PYTHONPATH (build/python).
"""
from __future__ import annotations

import argparse
import re
import statistics
import sys
from pathlib import Path

import numpy as np
import rodcore

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
from dna_models.units import Units  # noqa: E402
from mdbridge.jsonio import write_json  # noqa: E402

UNITS = Units.paper()
BP, BP_PER_POINT = 1050, 10
RISE_ROD = 0.34 / 0.5  # rod length units per bp (3.4 A per bp, l = 5 A)


def scene(method: str, t_end: float, dt: float, frames: int) -> dict:
    N = BP // BP_PER_POINT
    return {"rod": {"length": BP * RISE_ROD, "points": N, "Gamma0": [0, 0, 1.0], "Omega0": [0, 0, 0.0]},
            "material": {"K": np.diag(np.r_[1.0, 1.0, 1.19, UNITS.D_star]).tolist(),
                         "I": np.diag(UNITS.I_star).tolist()},
            "thermal": {"temperature_K": 300.0, "seed": 7, "sample_initial": False,
                        "friction_translational": "water", "friction_rotational": "water"},
            "solver": {"time": method, "dt": dt, **({"space": "fd4"} if method == "langevin" else {})},
            "output": {"t_end": t_end, "frames": frames, "fields": ["internal", "energy_parts"]}}


def langevin_dt(t_end: float, frames: int) -> float:
    try:
        rodcore.Simulation(scene("langevin", 1e9, 1e9, 2)).step_to(1.0)
        raise RuntimeError("no stability limit reported")
    except FloatingPointError as e:  # the message names the largest safe dt
        limit = float(re.search(r"solver.dt <= ([0-9.e+-]+)", str(e)).group(1))
    interval = t_end / (frames - 1)
    return interval / np.ceil(interval / (0.5 * limit))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--ns", type=float, default=20.0)
    ap.add_argument("--dt-ps", type=float, default=100.0)
    ap.add_argument("--pairs", type=int, default=3)
    ap.add_argument("--out", type=Path)
    a = ap.parse_args()
    tau = UNITS.tau_ps
    t_end = a.ns * 1000 / tau
    frames = int(round(a.ns * 10)) + 1  # every 100 ps
    dt_b = t_end / (frames - 1) / round(t_end / (frames - 1) / (a.dt_ps / tau))
    dt_l = langevin_dt(t_end, frames)
    kT = UNITS.kT_to_rod(300.0)
    N = BP // BP_PER_POINT
    walls: dict[str, list[float]] = {"brownian": [], "langevin": []}
    energy = {}
    for _ in range(a.pairs):
        for method, dt in (("brownian", dt_b), ("langevin", dt_l)):
            out = rodcore.run(scene(method, t_end, dt, frames))
            walls[method].append(out["summary"]["wall_seconds"])
            parts = out["energy_parts"]
            elastic = sum(parts[k] for k in ("shear", "extension", "bend", "twist") if k in parts)
            half = len(elastic) // 2
            energy[method] = float(np.mean(elastic[half:]) / ((6 * N - 6) * kT / 2))
    ratio = [lw / bw for bw, lw in zip(walls["brownian"], walls["langevin"])]
    res = {"rod": f"{BP} bp, {BP_PER_POINT} bp per point (N = {N}), box-held, untwisted, paper material, "
                  "water 300 K, from rest",
           "simulated_ns": a.ns, "dt_ps": {"brownian": dt_b * tau, "langevin": dt_l * tau},
           "wall_s_median": {m: statistics.median(w) for m, w in walls.items()},
           "wall_s_range": {m: [min(w), max(w)] for m, w in walls.items()},
           "langevin_over_brownian_wall_median": statistics.median(ratio),
           "langevin_over_brownian_wall_range": [min(ratio), max(ratio)],
           "bp_us_per_cpu_s": {m: BP * a.ns * 1e-3 / statistics.median(w) for m, w in walls.items()},
           "elastic_energy_over_equipartition_second_half": energy}
    print(res)
    if a.out:
        write_json(a.out, res)


if __name__ == "__main__":
    main()
