"""Does the coarse-grained stiffness depend on the MD integration setting? It must stay
within its errors when the time step is halved or gmx_d is used; measured once on the
21-bp duplex.

    python bench/md_cg_settings.py [--work /tmp/md_tension] [--ps 400] [--gmx gmx] [--gmx-d gmx_d]

From the equilibrated start at the built length that bench/md_tension.py makes (WORK/base:
dna21.toml with A_v = 0, seed 4, `--minimize`, 20-ps v-rescale stage at 300 K; built here if
missing), three NVE runs of --ps each, the same coordinates and velocities:

* `nve_default`: the main job's setting: smooth cut-offs, h-bond constraints, 2 fs, mixed
  precision (`gmx`);
* `nve_dt1`: the same with 1-fs steps;
* `nve_double`: the same with `gmx_d` (2 fs).

Each gets the drift of `mdbridge.md.gromacs.checks.fit_drift` (the one definition), the mean
temperature, the tension (`mdbridge.md.gromacs.tension`) and `dnarod coarse-grain` (T from the
run's .edr; pairs open in more than 5 % of the frames excluded). For every m the stretch
modulus, bend persistence length, torsional modulus, twist-stretch coupling and the mean rise
and twist are compared with the default's: z = (x - x_default) / sqrt(err^2 + err_default^2).
The three runs share their start, so the first ~10 ps are correlated; the estimator discards
its equilibration stretch, and the errors are the bootstrap errors of each run.
Writes bench/results/md_cg_settings.json.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time

import numpy as np

from md_tension import build, cg_summary, coarse_grain, common_arguments, fixed_box_run
from mdbridge.md.gromacs.checks import energy_drift
from mdbridge.md.gromacs.tension import mean_with_error, tension_series

VARIANTS = {"nve_default": ({}, "gmx"), "nve_dt1": ({"dt": 0.001}, "gmx"),
            "nve_double": ({}, "gmx_d")}
QUANTITIES = ("S_pN", "bend_persistence_length", "torsional_modulus", "twist_stretch_coupling")


def common_step_means(params: dict) -> dict:
    """Mean rise and twist over the steps that no run excludes (the runs fray differently, so
    their own sequence averages cover different steps), with errors from the per-step ones."""
    usable = [{s["step"]: s for s in p["steps"] if "mean" in s and not s.get("excluded")}
              for p in params.values()]
    common = sorted(set.intersection(*(set(u) for u in usable)))
    out: dict = {"steps": common}
    for name, u in zip(params, usable):
        row = {}
        for i, q in ((2, "rise_A"), (5, "twist_deg")):
            v = [u[k]["mean"][i] for k in common]
            e = [u[k]["mean_err"][i] for k in common]
            row[q] = {"value": float(np.mean(v)), "err": float(np.sqrt(np.sum(np.square(e)))) / len(common)}
        out[name] = row
    return out


def _val(r: dict, q: str):
    if q == "S_pN":
        return r["S_pN"], r["S_err_pN"]
    return (r[q]["value"], r[q]["err"]) if q in r else (float("nan"), float("nan"))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    common_arguments(ap, "md_cg_settings.json")
    ap.add_argument("--gmx-d", default="gmx_d")
    a = ap.parse_args(argv)
    work = a.work.resolve()
    work.mkdir(parents=True, exist_ok=True)
    t0 = time.time()
    base, _ = build(work, "base", ["--equilibrate-ps", "20"], a.gmx)
    n = int(json.loads((base / "build.json").read_text())["n_bp"])
    out: dict = {"command": "python bench/md_cg_settings.py " + " ".join(argv or sys.argv[1:]),
                 "system": "dna21.toml, A_v = 0, seed 4, --minimize, 20-ps v-rescale stage at 300 K, "
                           "then NVE at the built length (7.098 nm), 1 thread",
                 "runs": {}}
    for name, (keys, which) in VARIANTS.items():
        exe = a.gmx if which == "gmx" else a.gmx_d
        d = work / name
        rec = fixed_box_run(base, d, 1.0, a.ps, exe, keys=keys, energy_every=10)
        n_atoms = int(json.loads((d / "build.json").read_text())["n_atoms"])
        e = energy_drift(d, exe, n_atoms)
        s = tension_series(d, exe)
        cg = coarse_grain(d, "md.tpr", "md.xtc", n, min_effective=a.min_effective,
                          temperature=["--edr", str(d / "md.edr")], discard=a.cg_discard)
        out["runs"][name] = {
            "gmx": exe, "dt_ps": rec["dt_ps"], "ps": rec["length_ps"], "cpu_s": rec["cpu_s"],
            "ns_per_cpu_day": rec["length_ps"] / 1000.0 / (rec["cpu_s"] / 86400.0),
            "drift_kJ_mol_per_ns_per_atom": e["drift_kJ_mol_per_ns_per_atom"],
            "temperature_K": e["temperature_K"], "cg_temperature_K": cg["temperature_K"],
            "tension_pN": mean_with_error(s["time"], s["tension_pN"], discard_ps=min(20.0, 0.2 * a.ps)),
            "coarse_grain": cg_summary(cg, n, constrained=True)}
    params = {name: json.loads((work / name / "cg" / "params.json").read_text()) for name in VARIANTS}
    if (work / "nvt_1.000" / "cg" / "params.json").is_file():     # bench/md_tension.py's NVT run
        params["nvt_1.000"] = json.loads((work / "nvt_1.000" / "cg" / "params.json").read_text())
    cs = common_step_means(params)
    for name in params:
        if name != "steps" and name != "nve_default":
            for q in ("rise_A", "twist_deg"):
                a_, b_ = cs[name][q], cs["nve_default"][q]
                a_["z_vs_default"] = (a_["value"] - b_["value"]) / math.hypot(a_["err"], b_["err"])
    out["common_step_means"] = cs
    ref = out["runs"]["nve_default"]["coarse_grain"]
    cmp: dict = {}
    for name in ("nve_dt1", "nve_double"):
        cg = out["runs"][name]["coarse_grain"]
        rows = {}
        for m, r in cg["by_m"].items():
            if m not in ref["by_m"]:
                continue
            row = {}
            for q in QUANTITIES:
                x, ex = _val(r, q)
                y, ey = _val(ref["by_m"][m], q)
                row[q] = {"value": x, "err": ex, "default": y, "default_err": ey,
                          "z": (x - y) / math.hypot(ex, ey) if ex and ey else float("nan")}
            rows[m] = row
        for q, i in (("mean_rise_A", 2), ("mean_twist_deg", 5)):
            rows[q] = {"value": cg[q], "default": ref[q]}
        zs = [abs(v["z"]) for r in rows.values() if isinstance(r, dict)
              for v in r.values() if isinstance(v, dict) and "z" in v and np.isfinite(v["z"])]
        cmp[name] = {"by_m": rows, "max_abs_z": max(zs) if zs else float("nan"),
                     "n_compared": len(zs), "n_beyond_2": int(sum(z > 2 for z in zs)),
                     "n_beyond_3": int(sum(z > 3 for z in zs))}
    out["comparison_with_default"] = cmp
    out["wall_s"] = time.time() - t0
    out["load_avg_1min"] = os.getloadavg()[0]
    a.out.write_text(json.dumps(out, indent=1, default=float))
    for name, r in out["runs"].items():
        print(name, f"drift {r['drift_kJ_mol_per_ns_per_atom']:.3f}", f"T {r['temperature_K']['mean']:.1f}",
              {m: round(v["S_pN"]) for m, v in r["coarse_grain"]["by_m"].items()})
    print(json.dumps({k: {kk: vv for kk, vv in v.items() if kk != "by_m"} for k, v in cmp.items()}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
