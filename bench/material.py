"""RHS cost by material kind: diagonal uniform, coupled
uniform and coupled per point, at N = 158, 1000, 1024, both operators, and
the diagonal kernel of this build against a base build (e.g. the commit
before the general material); optionally the same material benchmarks of a
"before" build (this code before a change), side by side. The builds run
interleaved round by round, in alternating order, so that all see the same
machine load. Each number is the minimum CPU time per RHS call over the
rounds and repetitions (the least disturbed one); the load average is
recorded with every round. Writes results/material.json.

  /usr/bin/python3 bench/material.py --build build --base-build /path/to/base/build \
      [--before-build /path/to/before/build] [--rounds 5]
"""
import argparse
import json
import os
import subprocess
from pathlib import Path

SIZES = (158, 1000, 1024)
SPACES = ("fd4", "spectral")
KINDS = ("diagonal", "coupled", "per_point")


def run(exe, pattern, min_time, repetitions):
    out = subprocess.run([str(exe), f"--benchmark_filter={pattern}", f"--benchmark_min_time={min_time}",
                          f"--benchmark_repetitions={repetitions}", "--benchmark_format=json"],
                         capture_output=True, text=True, check=True).stdout
    best = {}
    for b in json.loads(out)["benchmarks"]:
        if b.get("run_type", "iteration") == "iteration":
            name = b.get("run_name", b["name"])
            best[name] = min(best.get(name, float("inf")), b["cpu_time"])  # ns
    return best


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", type=Path, required=True)
    ap.add_argument("--base-build", type=Path, help="a build of the base commit (its bin/rodbench)")
    ap.add_argument("--before-build", type=Path, help="a build of this code before a change (its bin/rodbench)")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--repetitions", type=int, default=3, help="repetitions per benchmark and round")
    ap.add_argument("--min-time", default="0.05")
    ap.add_argument("--out", type=Path, default=Path(__file__).parent / "results")
    a = ap.parse_args()
    sizes = "|".join(map(str, SIZES))
    mine_pat = f"^(RHS/(fd4|spectral)|MaterialRHS/.*)/({sizes})$"
    base_pat = f"^RHS/(fd4|spectral)/({sizes})$"
    best = {}
    load = []
    runs = [("this", a.build, mine_pat)]
    if a.before_build:
        runs.append(("before", a.before_build, mine_pat))
    if a.base_build:
        runs.append(("base", a.base_build, base_pat))
    for r in range(a.rounds):
        load.append(os.getloadavg()[0])
        for tag, build, pat in (runs[::-1] if r % 2 else runs):
            for name, t in run(build / "bin" / "rodbench", pat, a.min_time, a.repetitions).items():
                key = f"{tag}:{name}"
                best[key] = min(best.get(key, float("inf")), t)
    load.append(os.getloadavg()[0])
    table = []
    for space in SPACES:
        for N in SIZES:
            row = {"space": space, "N": N}
            for kind in KINDS:
                row[kind + "_us"] = best[f"this:MaterialRHS/{space}_{kind}/{N}"] / 1e3
            row["coupled_ratio"] = row["coupled_us"] / row["diagonal_us"]
            row["per_point_ratio"] = row["per_point_us"] / row["diagonal_us"]
            if a.before_build:
                for kind in KINDS:
                    row["before_" + kind + "_us"] = best[f"before:MaterialRHS/{space}_{kind}/{N}"] / 1e3
                row["before_coupled_ratio"] = row["before_coupled_us"] / row["before_diagonal_us"]
                row["before_per_point_ratio"] = row["before_per_point_us"] / row["before_diagonal_us"]
            row["RHS_this_us"] = best[f"this:RHS/{space}/{N}"] / 1e3
            if a.base_build:
                row["RHS_base_us"] = best[f"base:RHS/{space}/{N}"] / 1e3
                row["this_over_base"] = row["RHS_this_us"] / row["RHS_base_us"]
            table.append(row)
    a.out.mkdir(parents=True, exist_ok=True)
    meta = {"rounds": a.rounds, "repetitions": a.repetitions, "min_time_s": float(a.min_time),
            "time": "CPU time per RHS call (Google Benchmark cpu_time), minimum over rounds x repetitions",
            "load_average_1min": load, "builds": {tag: str(build) for tag, build, _ in runs}}
    (a.out / "material.json").write_text(json.dumps({**meta, "rows": table}, indent=1))
    print(f"load average (1 min) over the rounds: {min(load):.1f}-{max(load):.1f}")
    hdr = "| operator | N | diagonal (us) | coupled (us) | per point (us) | coupled / diag | per point / diag |"
    if a.before_build:
        hdr += " before: diag, coupled, per point (us) | before: coupled / diag, per point / diag |"
    if a.base_build:
        hdr += " RHS this / base |"
    print(hdr)
    print("|" + "---|" * (hdr.count("|") - 1))
    for row in table:
        line = (f"| {row['space']} | {row['N']} | {row['diagonal_us']:.1f} | {row['coupled_us']:.1f} | "
                f"{row['per_point_us']:.1f} | {row['coupled_ratio']:.2f} | {row['per_point_ratio']:.2f} |")
        if a.before_build:
            line += (f" {row['before_diagonal_us']:.1f}, {row['before_coupled_us']:.1f}, "
                     f"{row['before_per_point_us']:.1f} | {row['before_coupled_ratio']:.2f}, "
                     f"{row['before_per_point_ratio']:.2f} |")
        if a.base_build:
            line += f" {row['this_over_base']:.3f} |"
        print(line)


if __name__ == "__main__":
    main()
