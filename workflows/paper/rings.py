"""Section 5.1 ring tests with analytic expectations (scenes workflows/scenes/paper_ring_*.toml).

rotating_ring: balanced rotation of an intrinsically straight rod closed into a ring.
  Independent truth: Gamma3 solves C3 Gamma3^2 - C3 Gamma03 Gamma3 - gamma3^2 = 0 (the force
  balance gamma3^2 / Gamma3 = C3 (Gamma3 - Gamma03)), the radius R = Gamma3 L / (2 pi) stays
  constant and the material point s = 0 turns around the centre at gamma3 / R.
twisting_ring: no intrinsic bend, Eq (46) solved in closed form: omega3 constant,
  Omega1 = A sin(omega3 t), Omega2 = A cos(omega3 t).
twisting_bent_ring: intrinsic bend Omega02: Eq (46) (with the factor 1/I3 the torque balance
  Eq 12 gives) integrated by scipy's DOP853 at rtol 1e-12 -- an ODE integration independent
  of rodcore -- and compared with the uniform fields of the rod run.
"""
from __future__ import annotations

import tomllib
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

from mdbridge.rod.run import run_scene
from mdbridge.rod.scene import resolve_scene

SCENES = Path(__file__).resolve().parents[1] / "scenes"


def load(name: str) -> dict:
    with open(SCENES / name, "rb") as f:
        return tomllib.load(f)


def _material(sc):
    """(C, D, I) of the scene, rodcore's defaults filled in."""
    m = resolve_scene(sc, "ring scene")["material"]
    return m["C"], m["D"], m["I"]


def rotating_ring(quick: bool = False) -> dict:
    sc = load("paper_ring_rotating.toml")
    if quick:
        sc["output"].update(t_end=5.0, frames=11)
    C, _, _ = _material(sc)
    C3, G03, L = C[2], sc["rod"]["Gamma0"][2], sc["rod"]["length"]
    g3 = sc["initial"]["gamma3"]
    Gamma3 = (C3 * G03 + np.sqrt((C3 * G03) ** 2 + 4 * C3 * g3 ** 2)) / (2 * C3)
    R = Gamma3 * L / (2 * np.pi)
    run = run_scene(sc)
    assert run.centerline is not None and run.directors is not None and run.energy is not None
    assert run.time is not None
    c = run.centerline
    centre = c.mean(axis=1, keepdims=True)
    radius = np.linalg.norm(c - centre, axis=2)
    p0 = c[:, 0, :] - centre[:, 0, :]
    # angle of the material point s = 0 in the ring's plane (normal d1 of the ring, constant)
    n = run.directors[0, 0, :, 0]
    e1 = p0[0] / np.linalg.norm(p0[0])
    e2 = np.cross(n, e1)
    ang = np.unwrap(np.arctan2(p0 @ e2, p0 @ e1))
    rate = float(np.polyfit(run.time, ang, 1)[0])
    return {"check": "Sec 5.1 balanced rotating ring", "gamma3": g3, "Gamma3_theory": float(Gamma3),
            "Gamma3_run_max_dev": float(np.max(np.abs(run.fields["Gamma"][..., 2] - Gamma3))),
            "radius_theory": float(R), "radius_max_dev": float(np.max(np.abs(radius - R))),
            "turn_rate_theory": float(g3 / R), "turn_rate_run": abs(rate),
            "turn_rate_rel_diff": float(abs(abs(rate) - g3 / R) / (g3 / R)),
            "relative_energy_drift": float(np.max(np.abs(run.energy - run.energy[0])) / run.energy[0]),
            "t_end": float(run.time[-1])}


def twisting_ring(quick: bool = False) -> dict:
    sc = load("paper_ring_twisting.toml")
    if quick:
        sc["output"].update(t_end=5.0, frames=11)
    L, w3 = sc["rod"]["length"], sc["initial"]["omega3"]
    A = sc["initial"]["A"] or 2 * np.pi / L
    run = run_scene(sc)
    assert run.time is not None
    t = run.time[:, None]
    Om, om = run.fields["Omega"], run.fields["omega"]
    err = max(float(np.max(np.abs(Om[..., 0] - A * np.sin(w3 * t)))),
              float(np.max(np.abs(Om[..., 1] - A * np.cos(w3 * t)))),
              float(np.max(np.abs(om[..., 2] - w3))))
    return {"check": "Sec 5.1 twisting ring, no intrinsic bend (Eq 46)", "omega3": w3, "A": A,
            "max_abs_error_vs_closed_form": err, "t_end": float(run.time[-1])}


def eq46(t, omega3_0, Omega1_0, Omega2_0, D1, Omega02, I3):
    """Eq (46) with the 1/I3 of the torque balance: I3 omega3' = -D1 Omega02 Omega1,
    Omega1' = omega3 Omega2, Omega2' = -omega3 Omega1 (scipy DOP853, rtol 1e-12)."""
    def rhs(_, y):
        w3, O1, O2 = y
        return [-D1 * Omega02 * O1 / I3, w3 * O2, -w3 * O1]
    sol = solve_ivp(rhs, (0.0, float(np.max(t))), [omega3_0, Omega1_0, Omega2_0], method="DOP853",
                    t_eval=np.asarray(t, float), rtol=1e-12, atol=1e-14)
    return sol.y


def twisting_bent_ring(quick: bool = False, I3: float | None = None) -> dict:
    sc = load("paper_ring_twisting_bent.toml")
    if quick:
        sc["output"].update(t_end=8.0, frames=33)
    if I3 is not None:
        C, D, I = _material(sc)
        sc["material"] = {"C": list(C), "D": list(D), "I": [I[0], I[1], I3]}
    _, D, I = _material(sc)
    L, w3 = sc["rod"]["length"], sc["initial"]["omega3"]
    A = sc["initial"]["A"] or 2 * np.pi / L
    O02 = sc["rod"]["Omega0"][1]
    run = run_scene(sc)
    assert run.time is not None
    w3_ode, O1_ode, O2_ode = eq46(run.time, w3, 0.0, A, D[0], O02, I[2])
    Om, om = run.fields["Omega"], run.fields["omega"]
    err = max(float(np.max(np.abs(om[..., 2] - w3_ode[:, None]))),
              float(np.max(np.abs(Om[..., 0] - O1_ode[:, None]))),
              float(np.max(np.abs(Om[..., 1] - O2_ode[:, None]))))
    # Eq 46 exactly as printed (no 1/I3) for comparison: right only when I3 = 1
    w3_p, O1_p, O2_p = eq46(run.time, w3, 0.0, A, D[0], O02, 1.0)
    err_printed = float(np.max(np.abs(om[..., 2] - w3_p[:, None])))
    return {"check": "Sec 5.1 twisting ring with intrinsic bend (Eq 46, elliptic)", "omega3_0": w3, "A": A,
            "Omega02": O02, "I3": I[2], "D1": D[0], "max_abs_error_vs_ode": err,
            "max_abs_error_vs_eq46_as_printed": err_printed,
            "omega3_range": [float(om[..., 2].min()), float(om[..., 2].max())],
            "t_end": float(run.time[-1])}


def check(outdir: Path | None = None, quick: bool = False) -> dict:
    from dnarod.paper.common import write_json
    data = {"rotating_ring": rotating_ring(quick), "twisting_ring": twisting_ring(quick),
            "twisting_bent_ring": twisting_bent_ring(quick),
            "twisting_bent_ring_I3_1": twisting_bent_ring(quick, I3=1.0)}
    if outdir is not None:
        write_json(outdir / "rings.json", data)
    return data
