#!/usr/bin/python3
"""Costs outside the work-precision diagrams:

1. cost per RHS evaluation and per DOP853 step vs N (from rodbench's JSON):
   FD4 should be linear in N, spectral N log N; plotted as time / N;
2. output cost: the DNA scene with 2 vs 101 output frames (internal fields,
   then every field incl. energy, centerline and directors);
3. whole-system speed: the 158-bp DNA rod for 600 ps (the paper's MD length)
   vs all-atom MD of the same physical time at the GROMACS speed the main job measured
   (results/main_job.json, md_ns_per_day: the 158-bp duplex, 2 fs, h-bond constraints, 2 threads).

    costs.py --build BUILD --rhs-json bench/results/rhs_bench.json --out bench/results
"""
import argparse
import json
import math
import resource
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
DNA = HERE.parent / "workflows" / "scenes" / "dna158.toml"
MAIN_JOB = HERE.parent / "results" / "main_job.json"   # the main job's measured MD speed


def children_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def rodsim_wall(rodsim, scene, sets, out, repeat=3):
    """Best (wall, user+sys CPU) seconds of `rodsim run` over `repeat` runs."""
    cmd = [str(rodsim), "run", str(scene), "-o", str(out), "--quiet"]
    for s in sets:
        cmd += ["--set", s]
    best, best_cpu = math.inf, math.inf
    for _ in range(repeat):
        c0, t0 = children_cpu(), time.perf_counter()
        subprocess.run(cmd, check=True, capture_output=True)
        best = min(best, time.perf_counter() - t0)
        best_cpu = min(best_cpu, children_cpu() - c0)
    return best, best_cpu


def output_cost(rodsim, tmp, repeat):
    base = ["output.t_end=100", "rod.points=160"]
    rows = {}
    for label, sets in (("2 frames, internal", ["output.frames=2", 'output.fields=["internal"]']),
                        ("101 frames, internal", ["output.frames=101", 'output.fields=["internal"]']),
                        ("101 frames, internal+energy+centerline+directors",
                         ["output.frames=101", 'output.fields=["internal","energy","centerline","directors"]'])):
        rows[label] = rodsim_wall(rodsim, DNA, base + sets, tmp / "out.h5", repeat)
    ref_w, ref_c = rows["2 frames, internal"]
    return {k: dict(wall_s=w, cpu_s=c, overhead_wall=(w - ref_w) / ref_w, overhead_cpu=(c - ref_c) / ref_c)
            for k, (w, c) in rows.items()}


def rod_vs_md(rodsim, tmp, repeat):
    # The workflow scene as it stands: 637.2 tau = 600 ps, 601 frames of every
    # field (N = 158: one point per base pair), and on an FFT-friendly N = 160.
    wall, cpu = rodsim_wall(rodsim, DNA, [], tmp / "dna600.h5", repeat)
    wall_n160, cpu_n160 = rodsim_wall(rodsim, DNA, ["rod.points=160"], tmp / "dna600.h5", repeat)
    md_ns_per_day = json.loads(MAIN_JOB.read_text())["md_ns_per_day"]
    md = [0.6 / r * 86400.0 for r in md_ns_per_day]  # wall seconds for 0.6 ns on 2 cores
    return dict(rod_wall_s_N158=wall, rod_cpu_s_N158=cpu, rod_wall_s_N160=wall_n160, rod_cpu_s_N160=cpu_n160,
                md_wall_s_range=md, speedup_wall_N158=[md[1] / wall, md[0] / wall],
                speedup_wall_N160=[md[1] / wall_n160, md[0] / wall_n160])


def scaling(rhs_json, out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    data = json.loads(Path(rhs_json).read_text())
    series = {}
    for b in data["benchmarks"]:
        if b.get("run_type") == "aggregate":
            continue
        kind, space, N = b["name"].split("/")[:3]
        if kind == "PlanarRun":
            continue
        series.setdefault((kind, space), []).append((int(N), b["cpu_time"] * {"ns": 1e-9, "us": 1e-6,
                                                                              "ms": 1e-3, "s": 1.0}[b["time_unit"]]))
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    table = {}
    for (kind, space), pts in sorted(series.items()):
        pts.sort()
        Ns = [p[0] for p in pts]
        per = [p[1] / p[0] * 1e9 for p in pts]
        table[f"{kind}/{space}"] = {str(n): t for n, t in zip(Ns, per)}
        ax.loglog(Ns, per, "o-" if space == "fd4" else "s--", ms=3, label=f"{kind} {space}")
    Ns = [32, 131072]
    ax.set_xlabel("N")
    ax.set_ylabel("CPU time per grid point [ns]")
    ax.set_title("cost / N: flat = linear in N (FD4), slow rise = N log N (spectral)")
    ax.grid(True, which="both", lw=0.2)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(Path(out) / "scaling.png", dpi=110)
    return table


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--build", required=True)
    p.add_argument("--rhs-json", default=None)
    p.add_argument("--out", default=str(HERE / "results"))
    p.add_argument("--quick", action="store_true")
    a = p.parse_args(argv)
    rodsim = Path(a.build) / "bin" / "rodsim"
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    repeat = 1 if a.quick else 3
    import tempfile
    res = {}
    with tempfile.TemporaryDirectory(prefix="dnarod-costs-") as td:
        res["output_cost"] = output_cost(rodsim, Path(td), repeat)
        print("output cost:", json.dumps(res["output_cost"], indent=1), flush=True)
        res["rod_vs_md"] = rod_vs_md(rodsim, Path(td), repeat)
        print("rod vs MD:", json.dumps(res["rod_vs_md"], indent=1), flush=True)
    if a.rhs_json:
        res["per_point_ns"] = scaling(a.rhs_json, out)
    (out / "costs.json").write_text(json.dumps(res, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
