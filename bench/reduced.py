#!/usr/bin/python3
"""Speed-up of the reduced planar system (solver.reduce = "auto" vs "off").

P3 (bench/scenes/p3_untwisted_wave.toml, t_end = 10 x 1024 / N, the untwisted wave of Sec 5.2, which
lies in the planar subspace) run by rodsim with each spatial operator and N,
both ways; best of `repeat` process CPU times (user + sys, insensitive to the
machine's load) and wall times. The two runs give the same numbers (tested in
tests/cpp/test_stress_reduced_run.cpp), so only time is compared.

    reduced.py --build BUILD --out bench/results [--quick]
"""
import argparse
import json
import tempfile
from pathlib import Path

from costs import rodsim_wall  # bench/costs.py: a script's own folder is on its sys.path

HERE = Path(__file__).resolve().parent

P3 = HERE / "scenes" / "p3_untwisted_wave.toml"


def main():
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--build", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--quick", action="store_true")
    a = ap.parse_args()
    rodsim = Path(a.build) / "bin" / "rodsim"
    repeat = 2 if a.quick else 5
    sizes = [64, 256] if a.quick else [64, 256, 1024]
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "o.h5"
        for space in ("spectral", "fd4"):
            for N in sizes:
                # t_end ~ 1/N so that every run costs about the same and
                # start-up (~10 ms) is a small part of it.
                t_end = (10.0 if not a.quick else 2.0) * 1024 / N
                base = [f"rod.points={N}", f"solver.space={space}", f"output.t_end={t_end}"]
                w_off, c_off = rodsim_wall(rodsim, P3, base + ["solver.reduce=off"], out, repeat)
                w_red, c_red = rodsim_wall(rodsim, P3, base + ["solver.reduce=auto"], out, repeat)
                rows.append(dict(space=space, N=N, cpu_full_s=c_off, cpu_reduced_s=c_red, wall_full_s=w_off,
                                 wall_reduced_s=w_red, speedup_cpu=c_off / c_red, speedup_wall=w_off / w_red))
                print(f"{space:8s} N = {N:5d}: full {c_off:.3f} s CPU, reduced {c_red:.3f} s CPU, "
                      f"speed-up {c_off / c_red:.2f}x CPU, {w_off / w_red:.2f}x wall", flush=True)
    Path(a.out).mkdir(parents=True, exist_ok=True)
    problem = "P3, t_end = 10 x 1024 / N, DOP853 rtol = atol = 1e-8"
    (Path(a.out) / "reduced.json").write_text(json.dumps(dict(problem=problem, rows=rows), indent=1) + "\n")


if __name__ == "__main__":
    main()
