"""RHS cost by material kind (issue 13 item 4): diagonal uniform, coupled
uniform and coupled per point, at N = 158, 1000, 1024, both operators, and
the diagonal kernel of this build against a base build (e.g. the commit
before the general material), interleaved round by round so that both see
the same machine load. Each number is the minimum CPU time per RHS call over
the rounds (the least disturbed one). Writes results/material.json.

  /usr/bin/python3 bench/material.py --build build --base-build /path/to/base/build [--rounds 5]
"""
import argparse
import json
import subprocess
from pathlib import Path

SIZES = (158, 1000, 1024)
SPACES = ("fd4", "spectral")
KINDS = ("diagonal", "coupled", "per_point")


def run(exe, pattern, min_time):
    out = subprocess.run([str(exe), f"--benchmark_filter={pattern}", f"--benchmark_min_time={min_time}",
                          "--benchmark_format=json"], capture_output=True, text=True, check=True).stdout
    return {b["name"]: b["cpu_time"] for b in json.loads(out)["benchmarks"]}  # ns


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", type=Path, required=True)
    ap.add_argument("--base-build", type=Path, help="a build of the base commit (its bin/rodbench)")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--min-time", default="0.2")
    ap.add_argument("--out", type=Path, default=Path(__file__).parent / "results")
    a = ap.parse_args()
    sizes = "|".join(map(str, SIZES))
    mine_pat = f"^(RHS/(fd4|spectral)|MaterialRHS/.*)/({sizes})$"
    base_pat = f"^RHS/(fd4|spectral)/({sizes})$"
    best = {}
    for r in range(a.rounds):
        runs = [("this", a.build, mine_pat)] + ([("base", a.base_build, base_pat)] if a.base_build else [])
        if r % 2:
            runs.reverse()
        for tag, build, pat in runs:
            for name, t in run(build / "bin" / "rodbench", pat, a.min_time).items():
                key = f"{tag}:{name}"
                best[key] = min(best.get(key, float("inf")), t)
    table = []
    for space in SPACES:
        for N in SIZES:
            row = {"space": space, "N": N}
            for kind in KINDS:
                row[kind + "_us"] = best[f"this:MaterialRHS/{space}_{kind}/{N}"] / 1e3
            row["coupled_ratio"] = row["coupled_us"] / row["diagonal_us"]
            row["per_point_ratio"] = row["per_point_us"] / row["diagonal_us"]
            row["RHS_this_us"] = best[f"this:RHS/{space}/{N}"] / 1e3
            if a.base_build:
                row["RHS_base_us"] = best[f"base:RHS/{space}/{N}"] / 1e3
                row["this_over_base"] = row["RHS_this_us"] / row["RHS_base_us"]
            table.append(row)
    a.out.mkdir(parents=True, exist_ok=True)
    (a.out / "material.json").write_text(json.dumps({"rounds": a.rounds, "rows": table}, indent=1))
    hdr = "| operator | N | diagonal (us) | coupled (us) | per point (us) | coupled / diag | per point / diag |"
    if a.base_build:
        hdr += " RHS this / base |"
    print(hdr)
    print("|" + "---|" * (hdr.count("|") - 1))
    for row in table:
        line = (f"| {row['space']} | {row['N']} | {row['diagonal_us']:.1f} | {row['coupled_us']:.1f} | "
                f"{row['per_point_us']:.1f} | {row['coupled_ratio']:.2f} | {row['per_point_ratio']:.2f} |")
        if a.base_build:
            line += f" {row['this_over_base']:.3f} |"
        print(line)


if __name__ == "__main__":
    main()
