"""Debian's gmx against the GROMACS built for this machine (scripts/build_gromacs.sh).

    python bench/gromacs_simd.py BUILD_DIR [--ps 10] [--repeats 3] [--threads 2] [--double]

BUILD_DIR is a `dnarod build-md` directory; docs/md.md uses the 158-bp system
with the main job's MD setting (smooth cut-offs, 2 fs, h-bond constraints):
`dnarod build-md workflows/scenes/dna158.toml -o b158 --seed 1 --constraints
h-bonds --dt 0.002 --cutoffs smooth --minimize`. Each run is that build's own
md.mdp (bench/md_drift.py's setting "build", or "build_double" with --double:
Debian's gmx_d against the built gmx_d), --ps of NVE from the same conf.gro,
with --threads (mdrun -nt). The two binaries alternate, in the order
A B, B A, A B, ... so that a drift of the machine's load or clock hits both
alike. Reported per run: ns/day (mdrun's "Performance", wall clock), ns per
CPU-day (CPU time of grompp + mdrun), the SIMD level of the binary and the
ranks x OpenMP threads mdrun chose; then the ratio built/Debian of the medians
and the range of the ratios of the pairs run next to each other. Appends JSON
lines (one per run, one summary) to bench/results/gromacs_simd.jsonl.
"""
from __future__ import annotations

import argparse
import json
import os
import re
import statistics
import subprocess
import sys
from pathlib import Path

from md_drift import run_variant   # bench/ is the script's directory

from mdbridge.md.gromacs.gmx import built_gmx


def simd_of(gmx: str) -> str:
    out = subprocess.run([gmx, "--version"], capture_output=True, text=True)
    for ln in (out.stdout + out.stderr).splitlines():
        if ln.startswith("SIMD instructions:"):
            return ln.split(":", 1)[1].strip()
    return "unknown"


def parallel_layout(md_log: Path) -> str:
    """'R ranks x T OpenMP threads' as mdrun's log states it."""
    text = md_log.read_text(errors="replace") if md_log.is_file() else ""
    ranks = re.search(r"Using (\d+) MPI thread", text)
    omp = re.search(r"Using (\d+) OpenMP thread", text)
    return f"{ranks.group(1) if ranks else 1} ranks x {omp.group(1) if omp else '?'} OpenMP threads"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("build", type=Path)
    ap.add_argument("--ps", type=float, default=10.0)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--double", action="store_true", help="gmx_d against gmx_d")
    ap.add_argument("--variant", default=None,
                    help="a setting of bench/md_drift.py (default: build, or build_double with --double)")
    ap.add_argument("--output-ps", type=float, default=1.0, help="energy/coordinate output interval, ps")
    ap.add_argument("--debian", default=None, help="default: /usr/bin/gmx (/usr/bin/gmx_d with --double)")
    ap.add_argument("--built", default=None, help="default: scripts/build_gromacs.sh's gmx (gmx_d)")
    ap.add_argument("--out", type=Path, default=Path(__file__).parent / "results" / "gromacs_simd.jsonl")
    a = ap.parse_args(argv)
    variant = a.variant or ("build_double" if a.double else "build")
    debian = a.debian or ("/usr/bin/gmx_d" if a.double else "/usr/bin/gmx")
    built = a.built or built_gmx(double=a.double)
    if not built:
        print("no built GROMACS: run scripts/build_gromacs.sh" + (" --double" if a.double else "")
              + " first (or give --built)", file=sys.stderr)
        return 2
    build = a.build.resolve()
    runs: dict[str, list[dict]] = {"debian": [], "built": []}
    pairs = [("debian", debian), ("built", built)]
    for k in range(a.repeats):
        for label, exe in (pairs if k % 2 == 0 else pairs[::-1]):
            r = run_variant(build, variant, a.ps, exe, exe, a.threads, a.output_ps)
            r.update(label=label, simd=simd_of(exe), repeat=k,
                     layout=parallel_layout(build.parent / (build.name + ".drift") / variant / "md.log"))
            runs[label].append(r)
            with open(a.out, "a") as f:
                f.write(json.dumps(r) + "\n")
            print(f"{label:6s} {r['simd']:8s} {r['ns_per_day']:7.2f} ns/day, "
                  f"{r['ns_per_cpu_day']:6.2f} ns/CPU-day, {r['layout']}, "
                  f"load {r['load_avg_1min']:.1f}", flush=True)
    med = {k: statistics.median(x["ns_per_day"] for x in v) for k, v in runs.items()}
    medc = {k: statistics.median(x["ns_per_cpu_day"] for x in v) for k, v in runs.items()}
    pair_ratios = [b["ns_per_day"] / d["ns_per_day"] for d, b in zip(runs["debian"], runs["built"])]
    summary = {"summary": True, "build": str(build), "variant": variant, "ps": a.ps,
               "threads": a.threads, "repeats": a.repeats, "debian": debian, "built": built,
               "simd": {"debian": runs["debian"][0]["simd"], "built": runs["built"][0]["simd"]},
               "median_ns_per_day": med, "median_ns_per_cpu_day": medc,
               "ratio_wall": med["built"] / med["debian"], "ratio_cpu": medc["built"] / medc["debian"],
               "pair_ratios_wall": pair_ratios, "n_atoms": runs["debian"][0]["n_atoms"],
               "load_avg_1min": os.getloadavg()[0]}
    with open(a.out, "a") as f:
        f.write(json.dumps(summary) + "\n")
    print(f"median ns/day: Debian {med['debian']:.2f}, built {med['built']:.2f}; ratio built/Debian "
          f"{summary['ratio_wall']:.2f} (wall; pairs {min(pair_ratios):.2f}-{max(pair_ratios):.2f}), "
          f"{summary['ratio_cpu']:.2f} (per CPU-day)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
