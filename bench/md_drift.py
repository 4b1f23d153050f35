"""NVE energy drift and speed of the MD settings, side by side on one build.

    /usr/bin/python3 bench/md_drift.py BUILD_DIR --ps 12 [--only NAME ...] [--gmx gmx]

BUILD_DIR is a `dnarod build-md` directory (docs/md.md uses the 158-bp default
build: `dnarod build-md workflows/scenes/dna158.toml -o b158 --seed 1
--constraints h-bonds --dt 0.001 --minimize`). Each setting runs in its own copy
BUILD_DIR.drift/NAME from the same conf.gro (same coordinates and velocities),
for --ps of NVE with energies every --output-ps (0.1 ps); the drift is the one definition of
mdbridge/md/gromacs/checks.py (fit_drift: slope from 10 % of the run to its end).
Results are appended as JSON lines to bench/results/md_drift.jsonl and printed
as a Markdown table. Speed: wall-clock ns/day (mdrun's "Performance") and ns per
CPU-day from the CPU time grompp + mdrun used (getrusage), the fair comparison
on a shared machine. On an oversubscribed machine use --threads 1: OpenMP threads that
wait for each other's descheduled partner run many times slower.
"""
from __future__ import annotations

import argparse
import json
import os
import resource
import shutil
import sys
import time
from pathlib import Path

from mdbridge.md.gromacs.checks import energy_drift
from mdbridge.md.gromacs.mdp import SMOOTH_RLIST_NM, SWITCH_NM
from mdbridge.md.gromacs.run import _set_keys, run_md

SMOOTH = {"coulombtype": "Reaction-field", "epsilon-rf": 0, "vdw-modifier": "Force-switch",
          "rvdw-switch": SWITCH_NM, "rlist": SMOOTH_RLIST_NM}
LINCS = {"lincs-order": 8, "lincs-iter": 2}
HALF = {"dt": 0.0005}
DT2 = {"dt": 0.002}
NOCON = {"constraints": "none", "continuation": "yes"}

# name: (mdp keys changed relative to the build's md.mdp, precision)
VARIANTS = {
    "build": ({}, "mixed"),
    "build_double": ({}, "double"),
    "lincs8x2": (LINCS, "mixed"),
    "dt0.5": (HALF, "mixed"),
    "smooth": (SMOOTH, "mixed"),
    "smooth_double": (SMOOTH, "double"),
    "smooth_lincs8x2": ({**SMOOTH, **LINCS}, "mixed"),
    "smooth_dt0.5": ({**SMOOTH, **HALF}, "mixed"),
    "smooth_noconstr": ({**SMOOTH, **NOCON}, "mixed"),
    "smooth_dt2": ({**SMOOTH, **DT2}, "mixed"),
    "smooth_double_lincs8x2": ({**SMOOTH, **LINCS}, "double"),
    "smooth_double_dt0.5": ({**SMOOTH, **HALF}, "double"),
    "smooth_double_noconstr": ({**SMOOTH, **NOCON}, "double"),
    "smooth_double_dt2": ({**SMOOTH, **DT2}, "double"),
    "smooth_noconstr_dt0.5": ({**SMOOTH, **NOCON, **HALF}, "mixed"),
    "smooth_dt2_lincs8x2": ({**SMOOTH, **DT2, **LINCS}, "mixed"),
    "paper_noconstr": (NOCON, "mixed"),
}

INPUTS = ("conf.gro", "topol.top", "build.json")


def run_variant(build: Path, name: str, ps: float, gmx: str, gmx_d: str, threads: int,
                output_ps: float = 0.1) -> dict:
    keys, precision = VARIANTS[name]
    d = build.parent / (build.name + ".drift") / name
    if d.exists():
        shutil.rmtree(d)
    d.mkdir(parents=True)
    for f in build.iterdir():
        if f.name in INPUTS or f.suffix == ".itp":
            shutil.copy2(f, d / f.name)
    (d / "md.mdp").write_text(_set_keys((build / "md.mdp").read_text(), keys))
    exe = gmx_d if precision == "double" else gmx
    t0 = time.time()
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    rec = run_md(d, ps=ps, gmx=exe, threads=threads, output_ps=output_ps, checks=False, stream=None)
    n_atoms = json.loads((d / "build.json").read_text())["n_atoms"]
    # CPU time actually used by grompp + mdrun (mdrun's own "Core t" is wall x threads):
    # speed per CPU-day, which a loaded machine distorts far less than wall-clock ns/day
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    core_s = (r1.ru_utime + r1.ru_stime) - (r0.ru_utime + r0.ru_stime)
    e = energy_drift(d, exe, n_atoms)
    return {"name": name, "mdp_changes": keys, "precision": precision, "gmx": exe,
            "ps": rec["length_ps"], "dt_ps": rec["dt_ps"], "ns_per_day": rec["ns_per_day"],
            "wall_s": round(time.time() - t0, 1), "n_atoms": n_atoms, "threads": threads,
            "cpu_s": round(core_s, 2), "ns_per_cpu_day": rec["length_ps"] / 1000.0 / (core_s / 86400.0),
            "drift_kJ_mol_per_ns_per_atom": e["drift_kJ_mol_per_ns_per_atom"],
            "drift_fit_ps": [e["drift_fit_from_ps"], e["drift_fit_to_ps"]],
            "fluctuation_rms_kJ_mol": e["fluctuation_rms_kJ_mol"],
            "start_jump_kJ_mol": e["max_abs_deviation_kJ_mol"],
            "temperature_K": e["temperature_K"], "load_avg_1min": os.getloadavg()[0]}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("build", type=Path)
    ap.add_argument("--ps", type=float, default=12.0)
    ap.add_argument("--only", nargs="*", choices=sorted(VARIANTS), default=None)
    ap.add_argument("--gmx", default="gmx")
    ap.add_argument("--gmx-d", default="gmx_d")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--output-ps", type=float, default=0.1, help="energy output interval, ps")
    ap.add_argument("--out", type=Path, default=Path(__file__).parent / "results" / "md_drift.jsonl")
    a = ap.parse_args(argv)
    rows = []
    for name in a.only or list(VARIANTS):
        r = run_variant(a.build.resolve(), name, a.ps, a.gmx, a.gmx_d, a.threads, a.output_ps)
        rows.append(r)
        with open(a.out, "a") as f:
            f.write(json.dumps(r) + "\n")
        print(f"| {name} | {r['precision']} | {r['dt_ps'] * 1000:g} fs | "
              f"{r['drift_kJ_mol_per_ns_per_atom']:.3f} | {r['ns_per_cpu_day']:.3g} | {r['ns_per_day']} "
              f"| load {r['load_avg_1min']:.1f} |",
              flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
