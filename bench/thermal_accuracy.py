#!/usr/bin/python3
"""Accuracy of the Langevin rod (docs/thermal.md): its error in dt, and the slack tension.

1. dt: the paper's 158-bp DNA rod in water at 300 K ("water" frictions), started from its
   exact Boltzmann sample, run 2000 time units at each dt. Per class of degree of freedom
   (translational and rotational kinetic energy, shear, stretch, bend, twist) the mean energy
   against the exact value kT/2 per degree for the velocities, and for the strains against
   the smallest dt (the box-held rod at 300 K is not at its linear equilibrium: its slack
   tension, part 2, moves the strain energies away from the sample's). Errors from 20
   blocks. The dt for 1 % error is the largest one whose classes are all within 1 %
   (beyond their 3-sigma statistical error).
2. slack tension: the same rod held in its box (periodic, its period vector fixed by the
   dynamics) stores contour in thermal bending and so pulls on the box. Self-consistently
   F = EA s(F), s(F) = (2 kT / L) sum_n 1 / (B k_n^2 + F) over the resolved modes
   n = 1 .. N/2; to be measured as the mean n3 = C3 <Gamma3 - 1> of a run with weak
   translational friction (near critical damping of the n = 1 bend). The run also records
   the box it should keep (the period vector and the holonomy angle), kept by the closure
   projection (docs/thermal.md, "Closure in a run"; its test: tests/python/test_thermal_closure.py).

3. drift: the box over 500 time units for spectral, spectral + dealias, fd4 and at 30 K,
   without the closure projection (thermal.keep_closure = false; docs/thermal.md).

    /usr/bin/python3 bench/thermal_accuracy.py [--part dt|slack|drift|both] [--out bench/results/thermal_accuracy.json]

Needs the Python module rodcore on PYTHONPATH (build/python); about 4 minutes on 2 cores.
"""
from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

import numpy as np
import rodcore

from dna_models.units import Units
from mdbridge.jsonio import write_json
from mdbridge.rod.slack import slack_tension

HERE = Path(__file__).resolve().parent

U = Units.paper()
KT = U.kT_to_rod(300.0)
C = np.array([1.0, 1.0, 1.19])
D = np.array(U.D_star)
I3 = np.array(U.I_star)


def dna158(thermal: dict, t_end: float, dt: float, frame: float) -> dict:
    return {"initial": {"kind": "dna_planar", "bp": 158, "turns": 15, "A_v_A_per_ps": 0.0},
            "thermal": {"temperature_K": 300.0, **thermal},
            "solver": {"dt": dt, "space": "spectral"},
            "output": {"t_end": t_end, "frames": int(round(t_end / frame)) + 1}}


def class_energies(f, Gamma0, Omega0, h):
    """Mean energy per point of each class, in kT, over frames (T,) series."""
    g, w = f["gamma"], f["omega"]
    eG, eO = f["Gamma"] - Gamma0, f["Omega"] - Omega0
    return {"translational": 0.5 * h * (g ** 2).sum(-1).mean(-1) / KT,
            "rotational": 0.5 * h * (w ** 2 * I3).sum(-1).mean(-1) / KT,
            "shear": 0.5 * h * (eG[..., :2] ** 2 * C[:2]).sum(-1).mean(-1) / KT,
            "stretch": 0.5 * h * (eG[..., 2] ** 2 * C[2]).mean(-1) / KT,
            "bend": 0.5 * h * (eO[..., :2] ** 2 * D[:2]).sum(-1).mean(-1) / KT,
            "twist": 0.5 * h * (eO[..., 2] ** 2 * D[2]).mean(-1) / KT}


def dt_study(dts=(0.025, 0.05, 0.1, 0.2, 0.4), t_end=2000.0) -> dict:
    """The first (smallest) dt is the strains' reference: their dt -> 0 limit within its errors."""
    water = {"friction_translational": "water", "friction_rotational": "water"}
    L = 158 * U.rise_A / U.ell_A
    h, Omega03 = L / 158, 2 * math.pi * 15 / L
    G0, O0 = np.array([0, 0, 1.0]), np.array([0, 0, Omega03])
    rows, reference = [], None
    for dt in dts:
        try:
            out = rodcore.run(dna158({"seed": 2, **water}, t_end, dt, 2.0))
        except rodcore.NumericalError as e:
            rows.append({"dt": dt, "error": str(e).splitlines()[0]})
            continue
        skip = 50  # frames: 100 time units, the slack's tension settles
        e = class_energies({k: v[skip:] for k, v in out["fields"].items()}, G0, O0, h)
        means = {}
        for k, x in e.items():
            blocks = np.array([b.mean() for b in np.array_split(x, 20)])
            means[k] = (blocks.mean(), blocks.std(ddof=1) / math.sqrt(20))
        if reference is None:
            reference = {k: (1.5, 0.0) if k in ("translational", "rotational") else v for k, v in means.items()}
        row = {"dt": dt, "dt_ps": dt * U.tau_ps, "kinetic_kT": float(out["kinetic_kT"][skip:].mean() / KT)}
        ok = True
        for k, (m, err) in means.items():
            ref, ref_err = reference[k]
            rel = m / ref - 1
            err = math.hypot(err, ref_err if dt != dts[0] else 0.0) / ref
            row[k] = {"mean_kT": float(m), "relative_error": float(rel), "statistical_error": float(err)}
            ok = ok and abs(rel) - 3 * err < 0.01
        row["within_1_percent"] = ok
        rows.append(row)
        print(f"dt = {dt:6.3f} ({dt * U.tau_ps:.3f} ps): kinetic {row['kinetic_kT']:.4f}; " + ", ".join(
            f"{k} {row[k]['relative_error']:+.4f}+-{row[k]['statistical_error']:.4f}" for k in e), flush=True)
    good = [r["dt"] for r in rows if r.get("within_1_percent")]
    return {"rows": rows, "t_end": t_end, "dt_for_1_percent": max(good) if good else None,
            "reference": "velocities: kT/2 per degree; strains: the dt = %g run" % dts[0]}


def slack_prediction(L: float, N: int) -> float:
    """F = EA s(F), s(F) = (2 kT / L) sum_{n=1}^{N/2} 1 / (B k_n^2 + F), in rod units
    (mdbridge/rod/slack.py's shear-free mean field)."""
    return slack_tension(L, N, KT, D[0], C[0], C[2], samples=1000).shear_free


def slack_study(t_end=4000.0, dt=0.04) -> dict:
    """The measured tension, and the period vector |r(L) - r(0)| and holonomy angle that the
    box should keep: the semi-discrete rod keeps them only to its spatial error, which for
    thermal fields (content at every resolved wavenumber) is not small (docs/thermal.md)."""
    thermal = {"seed": 3, "friction_translational": 0.008, "friction_rotational": "water"}
    sc = dna158(thermal, t_end, dt, 4.0)
    sc["output"]["fields"] = ["internal", "centerline"]
    sim = rodcore.Simulation(sc)
    n3, period, angle = [], [], []
    sim.add_observer(lambda f: (n3.append(C[2] * (f["fields"]["Gamma"][:, 2].mean() - 1.0)),
                                period.append(float(np.linalg.norm(f["end_to_end"]))),
                                angle.append(float(f["end_rotation"]))))
    sim.run()
    L = 158 * U.rise_A / U.ell_A
    n3 = np.array(n3)
    skip = int(0.1 * len(n3))
    blocks = np.array([b.mean() for b in np.array_split(n3[skip:], 20)])
    force_pN = U.C * 1e12
    measured, err = blocks.mean() * force_pN, blocks.std(ddof=1) / math.sqrt(20) * force_pN
    predicted = slack_prediction(L, 158) * force_pN
    print(f"slack tension of the box-held 158-bp rod at 300 K: measured {measured:.1f} +- {err:.1f} pN, "
          f"predicted {predicted:.1f} pN (slack {predicted / force_pN / C[2]:.4f}; {L / (12 * D[0] / KT):.4f} "
          f"at zero tension); the box: |period| {period[0]:.3f} -> {period[-1]:.3f} (rest {L:.3f}), "
          f"holonomy angle up to {max(angle):.3f} rad", flush=True)
    return {"measured_pN": float(measured), "statistical_error_pN": float(err), "predicted_pN": float(predicted),
            "period_start": period[0], "period_end": period[-1], "period_rest": L,
            "max_holonomy_angle_rad": max(angle), "t_end": t_end, "dt": dt, "thermal": thermal,
            "EA_pN": float(C[2] * force_pN)}


def drift_study(t_end=500.0, dt=0.04) -> dict:
    """The box (period vector, holonomy angle) of the 158-bp rod over 500 time units from its
    sample: spectral, spectral with the 2/3 filter, fd4 at 300 K, and spectral at 30 K."""
    rows = []
    for space, dealias, T in (("spectral", False, 300.0), ("spectral", True, 300.0), ("fd4", False, 300.0),
                              ("spectral", False, 30.0)):
        sc = dna158({"seed": 3, "friction_translational": 0.008, "friction_rotational": "water",
                     "keep_closure": False}, t_end, dt, 25 * dt)
        sc["thermal"]["temperature_K"] = T
        sc["solver"].update({"space": space, "dealias": dealias})
        sc["output"]["fields"] = ["centerline"]
        sim = rodcore.Simulation(sc)
        period, angle = [], []
        sim.add_observer(lambda f: (period.append(float(np.linalg.norm(f["end_to_end"]))),
                                    angle.append(float(f["end_rotation"]))))
        sim.run()
        row = {"space": space, "dealias": dealias, "temperature_K": T, "period_start": period[0],
               "period_half": period[len(period) // 2], "period_end": period[-1], "max_angle_rad": max(angle)}
        rows.append(row)
        print(f"{space}{' + dealias' if dealias else ''} at {T:g} K: |period| {period[0]:.3f} -> "
              f"{row['period_half']:.3f} -> {period[-1]:.3f}, holonomy angle up to {max(angle):.3f} rad", flush=True)
    return {"rows": rows, "t_end": t_end, "dt": dt}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--part", choices=["dt", "slack", "drift", "both"], default="both")
    ap.add_argument("--out", type=Path, default=HERE / "results" / "thermal_accuracy.json")
    args = ap.parse_args(argv)
    result = json.loads(args.out.read_text()) if args.out.is_file() else {}
    if args.part in ("dt", "both"):
        result["dt"] = dt_study()
        print("dt for 1 % error:", result["dt"]["dt_for_1_percent"])
    if args.part in ("slack", "both"):
        result["slack"] = slack_study()
    if args.part in ("drift", "both"):
        result["drift"] = drift_study()
    result["command"] = "/usr/bin/python3 bench/thermal_accuracy.py"
    write_json(args.out, result)
    return 0


if __name__ == "__main__":
    sys.exit(main())
