"""Debian's gmx against the GROMACS built for this machine (scripts/build_gromacs.sh).

    /usr/bin/python3 bench/gromacs_simd.py BUILD_DIR [--ps 5] [--repeats 2] [--threads 2]

Runs the same MD (the default settings of docs/md.md on a `dnarod build-md`
directory, the 158-bp default build in docs/md.md) alternately with both
binaries, REPEATS times each, interleaved so that a change of machine load
hits both alike, and reports each run's ns/day (mdrun's "Performance", wall
clock) and ns per CPU-day (mdrun's CPU time), and the ratio built/Debian of
the medians. Appends JSON lines to bench/results/gromacs_simd.jsonl.
"""
from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
from pathlib import Path

from md_drift import run_variant   # bench/ is the script's directory

from mdbridge.gromacs.gmx import built_gmx


def simd_of(gmx: str) -> str:
    out = subprocess.run([gmx, "--version"], capture_output=True, text=True)
    for ln in (out.stdout + out.stderr).splitlines():
        if ln.startswith("SIMD instructions:"):
            return ln.split(":", 1)[1].strip()
    return "unknown"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("build", type=Path)
    ap.add_argument("--ps", type=float, default=5.0)
    ap.add_argument("--repeats", type=int, default=2)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--variant", default="smooth", help="a setting of bench/md_drift.py (smooth)")
    ap.add_argument("--debian", default="/usr/bin/gmx")
    ap.add_argument("--built", default=None, help="default: scripts/build_gromacs.sh's gmx")
    ap.add_argument("--out", type=Path, default=Path(__file__).parent / "results" / "gromacs_simd.jsonl")
    a = ap.parse_args(argv)
    built = a.built or built_gmx()
    if not built:
        print("no built GROMACS: run scripts/build_gromacs.sh first (or give --built)", file=sys.stderr)
        return 2
    runs = {"debian": [], "built": []}
    for k in range(a.repeats):
        for label, exe in (("debian", a.debian), ("built", built)):
            r = run_variant(a.build.resolve(), a.variant, a.ps, exe, exe, a.threads)
            r.update(label=label, simd=simd_of(exe), repeat=k)
            runs[label].append(r)
            with open(a.out, "a") as f:
                f.write(json.dumps(r) + "\n")
            print(f"{label:6s} {r['simd']:10s} {r['ns_per_day']} ns/day, "
                  f"{r['ns_per_cpu_day']:.3g} ns/CPU-day, load {r['load_avg_1min']:.1f}", flush=True)
    med = {k: statistics.median(x["ns_per_day"] for x in v) for k, v in runs.items()}
    medc = {k: statistics.median(x["ns_per_cpu_day"] for x in v) for k, v in runs.items()}
    print(f"ratio built/Debian: {med['built'] / med['debian']:.2f} (wall ns/day), "
          f"{medc['built'] / medc['debian']:.2f} (per CPU-day)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
