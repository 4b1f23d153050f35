"""The duplex in water held at a tension it is told (build-md --axial-tension-pN): is the tension
measured the one set, and does the duplex stretch by the amount its own stiffness predicts?

    python bench/water_tension.py [--tensions 0 30] [--ps 200] [--work /tmp/water_tension]
                                  [--threads 2] [--gmx gmx] [--out bench/results]

What runs (dna21.toml with A_v = 0, an equilibrium duplex; seed 4; per tension T):
1. `dnarod build-md --solvent tip3p --salt-mM 150 --minimize --thermostat --axial-tension-pN T`,
   h-bond constraints, 2 fs, smooth vdW, PME, v-rescale (tau-t 1 ps) at 300 K, semi-isotropic
   C-rescale (1 bar across, ref_p_z = 1 - 10 T / A_xy), the 20-ps equilibration stage;
2. --ps of MD, energies (pressure tensor, box) every 10 steps, frames every 0.2 ps.
Each stage is skipped when its build.json / md.done is in WORK, so the script continues.

Measured, after DISCARD_PS:
- the tension (P_perp - P_zz) A (mdbridge/md/gromacs/tension.py, the water formula), its mean
  and error (tension.mean_with_error): test 1, |<F> - T| < 2 sigma_T with sigma_T <= 3 pN;
- the box length L along the axis (= n_bp x the mean rise projected on the axis, exactly, for
  the ligated periodic duplex) and the duplex's stretch modulus from the 0-pN run's length
  fluctuation, S = kT <L> / var(L) (the isotension ensemble that semi-isotropic C-rescale
  samples); test 2: <L>(T) - <L>(0) against the prediction <L>(0) T / S (the barostat
  holds the same virial in both runs, so test 1 alone would be circular: test 2 asks the
  DNA), and the 3DNA mean rise of `dnarod coarse-grain` of both runs.

Writes WORK/* and OUT/water_tension.json; the CPU time and ns/day of every stage.

Cost (estimated before running; bench/water_speed.py measures the speed): the 21-bp solvated
box has ~18,000 atoms; at the ~10-20 ns/day such a system runs on 2 cores, each tension costs
the minimisation (minutes), 20 ps of equilibration and --ps of MD, i.e. ~20-40 min of both
cores for the default 2 x 200 ps. Resolution, from the same estimate: the box length's
standard deviation at S ~ 1100 pN is sqrt(kT L / S) ~ 0.16 nm, so over 180 ps with ~10-ps
correlation the mean length is known to ~0.04 nm per run, about the 0.06 nm that 30 pN should
add (a ~1-sigma test); the tension's error at 200 ps is expected well above 3 pN (pressure
fluctuations of ~150 bar over ~26 nm^2 are ~400 pN per frame). Both want ns, not 200 ps.
"""
from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np

from dna_models.units import BOLTZMANN
from md_tension import cg_summary, coarse_grain, cpu_s, scene_av0
from mdbridge.md.gromacs.run import _set_keys, run_md
from mdbridge.md.gromacs.tension import mean_with_error, tension_series

REPO = Path(__file__).resolve().parents[1]
N_BP = 21
SEED = 4
DISCARD_PS = 20.0
SIGMA_T_MAX_PN = 3.0
BUILD = ["--solvent", "tip3p", "--salt-mM", "150", "--minimize", "--thermostat", "--constraints", "h-bonds",
         "--dt", "0.002", "--cutoffs", "smooth", "--temperature", "300", "--seed", str(SEED), "--ps", "1"]


def build(work: Path, T: float, a) -> Path:
    d = work / f"T{T:g}"
    if not (d / "build.json").is_file():
        subprocess.run([sys.executable, "-m", "dnarod.cli", "build-md", str(scene_av0(work)), "-o", str(d), *BUILD,
                        "--axial-tension-pN", str(T), "--gmx", a.gmx, "--threads", str(a.threads)], check=True)
    return d


def run(d: Path, a) -> dict:
    if (d / "md.done").is_file():
        return json.loads((d / "md.done").read_text())
    mdp = (d / "md.mdp").read_text()
    (d / "md.mdp").write_text(_set_keys(mdp, {"nstenergy": 10, "nstcalcenergy": 10, "nstxout-compressed": 100,
                                              "nstlog": 5000}))
    c0 = cpu_s()
    rec = run_md(d, ps=a.ps, gmx=a.gmx, threads=a.threads, checks=False, stream=None)
    rec["cpu_s"] = cpu_s() - c0
    return rec


def measure(d: Path, T: float, a) -> dict:
    s = tension_series(d, a.gmx)
    t = s["time"]
    F = mean_with_error(t, s["tension_pN"], discard_ps=DISCARD_PS)
    L = mean_with_error(t, s["length_nm"], discard_ps=DISCARD_PS)
    keep = t >= t[0] + DISCARD_PS
    var = float(np.var(s["length_nm"][keep], ddof=1))
    v = mean_with_error(t[keep], (s["length_nm"][keep] - s["length_nm"][keep].mean()) ** 2)
    kT = BOLTZMANN * 300.0
    S = kT * L["mean"] * 1e-9 / (var * 1e-18) * 1e12
    cg = cg_summary(coarse_grain(d, "conf.gro", "md.xtc", N_BP, discard=int(DISCARD_PS / 0.2)), N_BP,
                    constrained=False)
    return {"tension_set_pN": T, "formula": s["formula"], "tension_pN": F,
            "test_1": {"sigma_T_pN": F["sem"], "sigma_T_ok": F["sem"] <= SIGMA_T_MAX_PN,
                       "within_2_sigma": abs(F["mean"] - T) < 2.0 * F["sem"]},
            "box_length_nm": L, "area_nm2_mean": float(np.mean(s["area_nm2"][keep])),
            "S_from_length_fluctuation_pN": S,
            "S_err_pN": S * math.hypot(v["sem"] / v["mean"], L["sem"] / L["mean"]), "coarse_grained": cg}


def compare(rows: list[dict]) -> dict:
    """Test 2: the length gained between the lowest and the highest tension against <L>0 dT / S0."""
    lo, hi = rows[0], rows[-1]
    L0, L1 = lo["box_length_nm"], hi["box_length_nm"]
    dT = hi["tension_set_pN"] - lo["tension_set_pN"]
    S0, S0_err = lo["S_from_length_fluctuation_pN"], lo["S_err_pN"]
    predicted = L0["mean"] * dT / S0
    measured = L1["mean"] - L0["mean"]
    err = math.hypot(L0["sem"], L1["sem"])
    pred_err = predicted * S0_err / S0
    return {"delta_tension_pN": dT, "delta_length_nm": measured, "delta_length_err_nm": err,
            "predicted_nm": predicted, "predicted_err_nm": pred_err,
            "delta_rise_A": 10.0 * measured / N_BP, "predicted_delta_rise_A": 10.0 * predicted / N_BP,
            "consistent_2_sigma": abs(measured - predicted) < 2.0 * math.hypot(err, pred_err),
            "resolved_from_zero_2_sigma": measured > 2.0 * err}


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--tensions", type=float, nargs="+", default=[0.0, 30.0])
    ap.add_argument("--ps", type=float, default=200.0)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--work", type=Path, default=Path("/tmp/water_tension"))
    ap.add_argument("--gmx", default="gmx")
    ap.add_argument("--out", type=Path, default=REPO / "bench" / "results")
    a = ap.parse_args()
    a.work.mkdir(parents=True, exist_ok=True)
    rows = []
    for T in sorted(a.tensions):
        d = build(a.work, T, a)
        done = run(d, a)
        keys = ("ns_per_day", "cpu_s", "length_ps", "wall_s")
        rows.append({**measure(d, T, a), "run": {k: done.get(k) for k in keys}})
    out = {"rows": rows, "stretch": compare(rows) if len(rows) > 1 else None,
           "setting": " ".join(BUILD), "discard_ps": DISCARD_PS}
    a.out.mkdir(parents=True, exist_ok=True)
    (a.out / "water_tension.json").write_text(json.dumps(out, indent=1, default=float) + "\n")
    print(json.dumps(out.get("stretch"), indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
