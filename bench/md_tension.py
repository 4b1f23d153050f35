"""Validate the MD tension on the 21-bp duplex: the zero-tension length of
the axis-only barostat, and the tension difference between two fixed box lengths against
the stretch modulus of the same MD.

    python bench/md_tension.py [--work /tmp/md_tension] [--ps 400] [--stretch 1.03]
                               [--baro-ps 300] [--gmx gmx]

What runs (all `dna21.toml` with A_v = 0, seed 4, `--minimize`, smooth cut-offs, 2-fs steps,
h-bond constraints, mixed precision, 300 K, one thread; each stage is skipped when its
`md.done` / `build.json` is already in WORK, so the script can be continued):

1. `base`: `dnarod build-md` with the 20-ps v-rescale stage at the built length
   (21 x 3.38 A = 7.098 nm): the equilibrated start of the fixed-box runs (and of
   bench/md_cg_settings.py).
2. `baro`: the same build with `--axial-pressure --equilibrate-ps BARO_PS`: Parrinello-Rahman
   along the helix axis only, reference pressure 0. Its box length L(t) after the first
   third (the approach) gives the zero-tension length L0 (blocking standard error; converged
   when the two halves of that window agree within 3 standard errors of their difference),
   and its fluctuation the stretch modulus of the whole periodic duplex at zero tension,
   S_box = kT <L> / var(L) (the isotension ensemble; the barostat's mass sets only the
   dynamics), if the box mode is thermal (it was not in the recorded run: docs/md.md).
   The mean tension over the same window must be ~0 (a check of the sign and of
   the barostat).
3. `nvt_1.000`, `nvt_STRETCH`: NVT (v-rescale, tau-t 1 ps) for --ps in the box of `base`
   and in the same box scaled affinely by --stretch along the axis
   (`mdbridge.md.gromacs.tension.stretch_box`), energies (pressure tensor) every 5 steps,
   frames every 0.2 ps. Tension F = -P_yy A (pN, F > 0 = tension,
   `mdbridge.md.gromacs.tension`), mean after 20 ps, blocking error.
4. `dnarod coarse-grain` of each fixed-box run and of the barostat run (T = 300 K given):
   the stretch modulus S_m of m-step segments (summed rise and twist: stiffness at fixed
   twist, which a ligated box holds).

Compared: dF = F(stretched) - F(built) against S x strain (strain = box difference / L0; S
from the barostat's fluctuations and from coarse-graining, per m), and the zero-tension
length where F, linear between the two boxes, crosses zero, against the barostat's L0. The fixed box also fixes the
duplex's total length, which removes length fluctuation from long segments: for a
ring of n independent steps the variance of an m-step sum is m s^2 (1 - m / n), so the
fixed-box S_m is high by 1 / (1 - m / n) (31 % at m = 5 of 21); the table gives S_m and
S_m (1 - m / n). The barostat ensemble has no such constraint.

Writes WORK/* and bench/results/md_tension.json; CPU time of every MD stage is recorded.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import resource
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from dna_models.units import BOLTZMANN
from mdbridge.md.gromacs.run import _set_keys, run_md
from mdbridge.md.gromacs.tension import mean_with_error, stretch_box, tension_series

REPO = Path(__file__).resolve().parents[1]
SEED = 4
DISCARD_PS = 20.0
EQ_FRAME_PS = 0.1        # the equilibration stage writes frames every 0.1 ps (equilibrate.py)
BUILD = ["--seed", str(SEED), "--constraints", "h-bonds", "--dt", "0.002", "--cutoffs", "smooth",
         "--minimize", "--threads", "1", "--ps", "1"]


def cpu_s() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def dnarod(*args: str) -> None:
    subprocess.run([sys.executable, "-m", "dnarod.cli", *args], check=True)


def scene_av0(work: Path) -> Path:
    """dna21.toml with A_v = 0: an equilibrium duplex, no kick."""
    text = (REPO / "workflows/scenes/dna21.toml").read_text()
    out = work / "dna21_av0.toml"
    out.write_text(text.replace("A_v_A_per_ps = 1.0", "A_v_A_per_ps = 0.0"))
    return out


def build(work: Path, name: str, extra: list[str], gmx: str) -> tuple[Path, float]:
    d = work / name
    if (d / "build.json").is_file():
        return d, 0.0
    c0 = cpu_s()
    dnarod("build-md", str(scene_av0(work)), "-o", str(d), *BUILD, "--gmx", gmx, *extra)
    return d, cpu_s() - c0


def fixed_box_run(base: Path, d: Path, factor: float, ps: float, gmx: str, *, keys: dict,
                  energy_every: int = 5, xtc_ps: float = 0.2, conf: str = "conf.gro") -> dict:
    """--ps of MD of BASE's start in a box scaled by FACTOR along the axis, with the mdp KEYS
    (e.g. the thermostat) and energies every ENERGY_EVERY steps; returns md.done + CPU time."""
    if (d / "md.done").is_file():
        rec = json.loads((d / "md.done").read_text())
        rec["cpu_s"] = json.loads((d / "bench.json").read_text())["cpu_s"]
        return rec
    stretch_box(base, d, factor, conf=conf)
    mdp = (d / "md.mdp").read_text()
    dt = float(keys.get("dt") or next(ln.split("=")[1] for ln in mdp.splitlines()
                                      if ln.split("=")[0].strip() == "dt"))
    every = max(1, int(round(xtc_ps / dt)))
    (d / "md.mdp").write_text(_set_keys(mdp, {**keys, "nstenergy": energy_every,
                                              "nstcalcenergy": energy_every,
                                              "nstxout-compressed": every, "nstlog": every * 50}))
    c0 = cpu_s()
    rec = run_md(d, ps=ps, gmx=gmx, threads=1, checks=False, stream=None)
    rec["cpu_s"] = cpu_s() - c0
    (d / "bench.json").write_text(json.dumps({"cpu_s": rec["cpu_s"], "factor": factor, "keys": keys}))
    return rec


# vacuum, full charges: base pairs fray now and then; a pair open in more than 5 % of the
# frames is excluded with its steps (docs/coarse-graining.md), as for the 158-bp try
CG_ARGS = ["--max-open-fraction", "0.05"]


def coarse_grain(d: Path, structure: str, traj: str, n: int, out: str = "cg",
                 min_effective: int = 50, temperature: list[str] | None = None,
                 discard: int | None = None) -> dict:
    """`dnarod coarse-grain` of D/TRAJ (T = 300 K given unless TEMPERATURE, e.g.
    ["--edr", "md.edr"] for an NVE run)."""
    if not (d / out / "params.json").is_file():
        # the build's pairing (build.json residue_to_base_pair): strand I residue k with strand
        # II residue 2n + 1 - k, given explicitly because a pair open in the first frame
        # defeats the estimator's automatic pairing
        (d / "pairs.txt").write_text("".join(f"{k} {2 * n + 1 - k}\n" for k in range(1, n + 1)))
        try:
            dnarod("coarse-grain", str(d / structure), str(d / traj), *CG_ARGS,
                   "--pairs", str(d / "pairs.txt"), *(temperature or ["--temperature", "300"]),
                   "--min-effective", str(min_effective), "-o", str(d / out),
                   *(["--discard", str(discard)] if discard is not None else []))
        except subprocess.CalledProcessError as e:      # refused (too few samples): say so
            return {"refused": f"dnarod coarse-grain exit status {e.returncode} (its message above)"}
    return json.loads((d / out / "params.json").read_text())


def cg_summary(p: dict, n_steps: int, constrained: bool) -> dict:
    """Stretch modulus per m (and the fixed-length correction), the other headline constants."""
    if "refused" in p:
        return {"by_m": {}, **p}
    rows = {}
    for r in p["by_length"]:
        m = int(r["m"])
        ph = r.get("physical") or {}
        S = ph.get("stretch_modulus") or {}
        if not S:
            continue
        f = (1.0 - m / n_steps) if constrained else 1.0
        rows[m] = {"S_pN": S["value"], "S_err_pN": S["err"], "S_corrected_pN": S["value"] * f,
                   "S_corrected_err_pN": S["err"] * f,
                   **{k: {"value": ph[k]["value"], "err": ph[k]["err"], "unit": ph[k].get("unit")}
                      for k in ("bend_persistence_length", "torsional_modulus", "twist_stretch_coupling")
                      if k in ph}}
    return {"by_m": rows, "effective_samples": p.get("effective_samples"),
            "frames_used": p.get("frames_used"), "tau_int_max_frames": p.get("tau_int_max_frames"),
            "excluded_steps": (p.get("excluded") or {}).get("steps"),
            "mean_rise_A": p["average"]["mean"][2], "mean_twist_deg": p["average"]["mean"][5],
            "caveats": p.get("caveats")}


def zero_tension(baro: Path, gmx: str, ps: float, axis: int) -> dict:
    s = tension_series(baro, gmx, edr="eq.edr", axis=axis)
    t, L = s["time"], s["length_nm"]
    ps = float(t[-1] - t[0])           # the stage as far as it ran (see --baro-stopped)
    discard = ps / 3.0
    L0 = mean_with_error(t, L, discard_ps=discard)
    F = mean_with_error(t, s["tension_pN"], discard_ps=discard)
    keep = t >= t[0] + discard
    var = float(np.var(L[keep], ddof=1))
    # error of var(L) by blocking the series (L - <L>)^2
    v = mean_with_error(t[keep], (L[keep] - L[keep].mean()) ** 2)
    kT = BOLTZMANN * 300.0
    S = kT * L0["mean"] * 1e-9 / (var * 1e-18) * 1e12
    S_err = S * math.hypot(v["sem"] / v["mean"], L0["sem"] / L0["mean"])
    bj = json.loads((baro / "build.json").read_text()) if (baro / "build.json").is_file() else None
    return {"stage_ps": ps, "discard_ps": discard, "built_length_nm": float(L[0]),
            "zero_tension_length_nm": L0, "tension_during_barostat_pN": F,
            "length_range_nm": [float(L[keep].min()), float(L[keep].max())],
            "length_std_nm": math.sqrt(var), "S_from_length_fluctuation_pN": S,
            "S_from_length_fluctuation_err_pN": S_err,
            "convergence_test": "the means of the two halves of the window after the first third "
                                "of the stage differ by < 3 x the standard error of the difference "
                                "(each half blocked on its own)",
            "converged": L0["halves"]["stationary"],
            "build_json_estimate": bj["equilibration"]["axial_pressure"] if bj else
            "none: the stage was stopped before build-md finished (--baro-stopped)"}


def common_arguments(ap, results_name: str) -> None:
    """The options this script and bench/md_cg_settings.py share."""
    ap.add_argument("--work", type=Path, default=Path("/tmp/md_tension"))
    ap.add_argument("--ps", type=float, default=400.0, help="length of each fixed-box run, ps")
    ap.add_argument("--gmx", default="gmx")
    ap.add_argument("--min-effective", type=int, default=50, help="dnarod coarse-grain's (50)")
    ap.add_argument("--cg-discard", type=int, default=None, metavar="FRAMES",
                    help="dnarod coarse-grain --discard (default: its own equilibration rule)")
    ap.add_argument("--out", type=Path, default=REPO / "bench" / "results" / results_name)


def comparison(res: dict, runs: dict, stretch: float) -> dict:
    """The two fixed boxes' tension difference against every stiffness's prediction, and the
    zero-tension length they imply against the barostat's."""
    F1, F2 = runs[1.0]["tension_pN"], runs[stretch]["tension_pN"]
    dF, dF_err = F2["mean"] - F1["mean"], math.hypot(F1["sem"], F2["sem"])
    L1, L2 = runs[1.0]["box_length_nm"], runs[stretch]["box_length_nm"]
    zt = res["zero_tension"]
    L0, L0e = zt["zero_tension_length_nm"]["mean"], zt["zero_tension_length_nm"]["sem"]
    strain = (L2 - L1) / L0
    cmp = {"dF_measured_pN": dF, "dF_err_pN": dF_err, "strain_between_boxes": strain,
           "S_from_dF_pN": dF / strain, "S_from_dF_err_pN": dF_err / strain, "predictions": {}}
    Sb, Sbe = zt["S_from_length_fluctuation_pN"], zt["S_from_length_fluctuation_err_pN"]
    preds = {"barostat length fluctuation": (Sb, Sbe)}
    for f in (1.0, stretch):
        for m, r in runs[f]["coarse_grain"]["by_m"].items():
            preds[f"coarse-grain, box {f:.3f} (fixed-length corrected), m = {m}"] = (
                r["S_corrected_pN"], r["S_corrected_err_pN"])
    for m, r in res["coarse_grain_barostat"]["by_m"].items():
        preds[f"coarse-grain, barostat run, m = {m}"] = (r["S_pN"], r["S_err_pN"])
    for k, (S, Se) in preds.items():
        p, pe = S * strain, Se * strain
        cmp["predictions"][k] = {"S_pN": S, "S_err_pN": Se, "dF_pred_pN": p, "dF_pred_err_pN": pe,
                                 "z": (dF - p) / math.hypot(dF_err, pe)}
    # the zero-tension length the two fixed boxes imply (F linear in L between them), against
    # the barostat's; F1 and F2 are independent runs
    k = dF / (L2 - L1)                                  # pN/nm
    L0f = L2 - F2["mean"] / k
    dL0_dF1 = -F2["mean"] / (dF ** 2) * (L2 - L1)       # d L0f / d F1
    dL0_dF2 = -(L2 - L1) / dF + F2["mean"] / (dF ** 2) * (L2 - L1)
    L0f_err = math.hypot(dL0_dF1 * F1["sem"], dL0_dF2 * F2["sem"])
    cmp["zero_tension_length_from_fixed_boxes_nm"] = {
        "value": L0f, "err": L0f_err, "barostat": L0, "barostat_err": L0e,
        "z": (L0f - L0) / math.hypot(L0f_err, L0e),
        "how": "L2 - F2 (L2 - L1) / (F2 - F1): F linear in L between the two boxes"}
    return cmp


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    common_arguments(ap, "md_tension.json")
    ap.add_argument("--baro-ps", type=float, default=300.0, help="axis-only barostat stage, ps")
    ap.add_argument("--stretch", type=float, default=1.03)
    ap.add_argument("--extend-ps", type=float, default=0.0,
                    help="continue the stretched box from its final state for this long (a check "
                         "that its tension has relaxed)")
    ap.add_argument("--baro-stopped", action="store_true",
                    help="WORK/baro's stage was stopped early (build-md did not finish): analyse "
                         "its eq.edr/eq.xtc as far as they go instead of building again")
    a = ap.parse_args(argv)
    work = a.work.resolve()
    work.mkdir(parents=True, exist_ok=True)
    t0 = time.time()
    res: dict = {"command": "python bench/md_tension.py " + " ".join(argv or sys.argv[1:]),
                 "system": "dna21.toml, A_v = 0, seed 4, --minimize, 1,335 atoms; smooth cut-offs, "
                           "2 fs, h-bonds, mixed precision, 300 K, 1 thread",
                 "sign": "F > 0 = tension (duplex pulls the box faces together), pN"}
    base, c_base = build(work, "base", ["--equilibrate-ps", "20"], a.gmx)
    if a.baro_stopped and (work / "baro" / "eq.edr").is_file():
        baro, c_baro = work / "baro", None          # its CPU time: see docs/md.md
    else:
        baro, c_baro = build(work, "baro", ["--axial-pressure", "--equilibrate-ps", str(a.baro_ps)], a.gmx)
    res["cpu_s"] = {"build_base_incl_20ps_stage": c_base, "build_baro_incl_stage": c_baro}
    n = int(json.loads((base / "build.json").read_text())["n_bp"])
    axis = int(json.loads((base / "build.json").read_text())["box"]["axis"])
    res["zero_tension"] = zero_tension(baro, a.gmx, a.baro_ps, axis)
    nvt = {"tcoupl": "V-rescale", "tc-grps": "System", "tau-t": 1.0, "ref-t": 300}
    runs = {}
    for f in (1.0, a.stretch):
        d = work / f"nvt_{f:.3f}"
        rec = fixed_box_run(base, d, f, a.ps, a.gmx, keys=nvt)
        res["cpu_s"][d.name] = rec["cpu_s"]
        s = tension_series(d, a.gmx)
        runs[f] = {"dir": str(d), "box_length_nm": float(s["length_nm"][0]),
                   "area_nm2": float(s["area_nm2"][0]), "ps": rec["length_ps"],
                   "ns_per_day": rec.get("ns_per_day"),
                   "tension_pN": mean_with_error(s["time"], s["tension_pN"], discard_ps=min(DISCARD_PS, 0.2 * a.ps)),
                   "tension_instantaneous_std_pN": float(np.std(s["tension_pN"]))}
        runs[f]["coarse_grain"] = cg_summary(coarse_grain(d, "md.tpr", "md.xtc", n, min_effective=a.min_effective,
                                                          discard=a.cg_discard),
                                             n, constrained=True)
    res["coarse_grain_barostat"] = cg_summary(coarse_grain(baro, "eq.tpr", "eq.xtc", n, min_effective=a.min_effective,
                     discard=int(round(res["zero_tension"]["discard_ps"] / EQ_FRAME_PS))), n,
                                              constrained=False)
    res["fixed_box"] = {f"{f:.3f}": r for f, r in runs.items()}
    if a.extend_ps > 0:                 # the stretched box continued from its confout.gro
        src = work / f"nvt_{a.stretch:.3f}"
        d = work / f"nvt_{a.stretch:.3f}_continued"
        rec = fixed_box_run(src, d, 1.0, a.extend_ps, a.gmx, keys=nvt, conf="confout.gro")
        res["cpu_s"][d.name] = rec["cpu_s"]
        s = tension_series(d, a.gmx)
        res["stretched_continued"] = {"dir": str(d), "ps": rec["length_ps"],
                                      "tension_pN": mean_with_error(s["time"], s["tension_pN"])}
    res["comparison"] = cmp = comparison(res, runs, a.stretch)
    res["wall_s"] = time.time() - t0
    res["load_avg_1min"] = os.getloadavg()[0]
    a.out.parent.mkdir(parents=True, exist_ok=True)
    a.out.write_text(json.dumps(res, indent=1, default=float))
    print(json.dumps({"L0": res["zero_tension"]["zero_tension_length_nm"], "F": {k: v["tension_pN"]["mean"]
                      for k, v in res["fixed_box"].items()}, "comparison": cmp}, indent=1, default=float))
    return 0


if __name__ == "__main__":
    sys.exit(main())
