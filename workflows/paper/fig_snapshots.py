"""Figs 3, 4 and 6: tube snapshots of real simulations (rodcore), shaded tubes oriented
by the directors, with cross-section rings and a stripe along d1.

Fig 3: the exact twisted-rod wave of Eq (24): Gamma_1^A = 0.5, k = 2, Omega03 = 1,
       Gamma03 = 1, omega_+^p; five snapshots over one period 2 pi / omega (the paper
       says t = 1.25; we print what Eq 26 gives).
Fig 4: pure shear oscillation of a twisted rod (Sec 3.1.1): s-independent strongly
       sheared state, Omega0 = (0, 0, 1).
Fig 6: untwisted-rod wave of Eqs (40)-(45), omega_+, k = 2, eps = 0.5, Gamma03 = 1,
       snapshots at t = 0, 0.9, 1.8, 2.7, 3.6.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from dnarod.paper import theory
from dnarod.paper.common import write_json
from mdbridge.rod.run import run_scene
from mdbridge.rod.scene import new_scene, straight_rod
from dnarod.paper.tubes import close_periodic, snapshot_figure

FIELDS_3D = ("internal", "energy", "energy_parts", "centerline", "directors")


def _frames(run, idx):
    out = []
    for i in idx:
        c, d = close_periodic(run.centerline[i], run.directors[i], run.fields["Gamma"][i], run.s)
        out.append((c, d))
    return out


def fig3(outdir: Path, quick: bool = False) -> dict:
    k, A, O03, G03 = 2.0, 0.5, 1.0, 1.0
    kappa = k + O03
    w = float(theory.omega(kappa, "plus", theory.D1_PAPER, G03))
    T = 2 * np.pi / w
    mode = 2  # two wavelengths on the periodic rod, L = 2 pi mode / k
    L = 2 * np.pi * mode / k
    N = 32 if quick else 96
    sc = new_scene(straight_rod(L, N, G03, O03),
               {"kind": "twisted_wave", "mode": mode, "A": A, "kappa": "p", "branch": "plus"},
               t_end=T, frames=5, fields=FIELDS_3D, rtol=1e-11)
    run = run_scene(sc)
    assert run.energy is not None and run.time is not None
    # after exactly one period the exact wave is back where it started (Eq 24)
    err = max(float(np.max(np.abs(run.fields[f][-1] - run.fields[f][0]))) for f in run.fields)
    drift = float(np.max(np.abs(run.energy - run.energy[0])) / run.energy[0])
    titles = [f"t = {t:.3f}" for t in run.time]
    png = outdir / "fig3.png"
    snapshot_figure(png, _frames(run, range(len(run.time))), radius=0.12, titles=titles,
                    suptitle=rf"Fig 3: exact twisted wave, $\omega_+^p$ = {w:.4f}, period {T:.4f}",
                    rings_every=4 if quick else 8)
    data = {"figure": 3, "k": k, "Gamma1A": A, "Omega03": O03, "Gamma03": G03, "kappa_p": kappa,
            "omega_plus_p": w, "period_2pi_over_omega": T, "paper_period": 1.25,
            "snapshot_times": run.time, "N": N, "L": L,
            "max_field_error_after_one_period": err, "relative_energy_drift": drift,
            "phase_speed_omega_over_kappa": w / kappa, "phase_speed_omega_over_k": w / k}
    write_json(outdir / "fig3.json", data)
    return {"png": png, "json": outdir / "fig3.json", "data": data}


def shear_oscillation_ode(t, omega0: float, Gamma1_0: float, Gamma3_0: float, Gamma03: float = 1.0,
                          C3: float = theory.C3_PAPER, I1: float = 1.0):
    """Eqs (28)-(30) (C1 = 1) integrated independently with scipy (DOP853, rtol 1e-12):
    I1 omega2' = -C3 Gamma1 (Gamma3 - Gamma03) + Gamma1 Gamma3, Gamma1' = -omega2 Gamma3,
    Gamma3' = omega2 Gamma1. Returns (omega2, Gamma1, Gamma3) at times t."""
    from scipy.integrate import solve_ivp

    def rhs(_, y):
        w2, g1, g3 = y
        return [(-C3 * g1 * (g3 - Gamma03) + g1 * g3) / I1, -w2 * g3, w2 * g1]
    sol = solve_ivp(rhs, (0.0, float(np.max(t))), [omega0, Gamma1_0, Gamma3_0], method="DOP853",
                    t_eval=np.asarray(t, float), rtol=1e-12, atol=1e-14)
    return sol.y


def fig4(outdir: Path, quick: bool = False) -> dict:
    O03, G03, omega0 = 1.0, 1.0, 1.0  # starts unsheared and spinning: spin turns into shear
    L, N = 2 * np.pi, 16 if quick else 48
    t_end = 6.0
    # The rodcore kind puts the s-independent motion of Eqs 28-30 on the twisted
    # rod seen through the twist: omega = omega2 (sin O03 s, cos O03 s, 0),
    # Gamma = (Gamma1 cos O03 s, -Gamma1 sin O03 s, Gamma3) (docs/numerics.md).
    sc = new_scene(straight_rod(L, N, G03, O03),
               {"kind": "shear_oscillation", "omega2": omega0, "Gamma1": 0.0, "Gamma3": G03},
               t_end=t_end, frames=7 if quick else 61, fields=FIELDS_3D, rtol=1e-11)
    run = run_scene(sc)
    assert run.energy is not None and run.time is not None
    G, W, Om = run.fields["Gamma"], run.fields["omega"], run.fields["Omega"]
    shear = np.hypot(G[..., 0], G[..., 1])       # |Gamma_perp|
    spin = np.hypot(W[..., 0], W[..., 1])         # |omega_perp|
    w2, g1, g3 = shear_oscillation_ode(run.time, omega0, 0.0, G03)
    ode_err = max(float(np.max(np.abs(shear - np.abs(g1)[:, None]))),
                  float(np.max(np.abs(G[..., 2] - g3[:, None]))),
                  float(np.max(np.abs(spin - np.abs(w2)[:, None]))))
    bend = float(np.max(np.hypot(Om[..., 0], Om[..., 1])))
    i_max = int(np.argmax(shear[:, 0]))
    pick = np.unique(np.linspace(0, i_max, 5).round().astype(int))
    png = outdir / "fig4.png"
    snapshot_figure(png, _frames(run, pick), radius=0.3, titles=[f"t = {run.time[i]:.2f}" for i in pick],
                    suptitle="Fig 4: pure shear oscillation of a twisted rod", view=(20, -60),
                    rings_every=2 if quick else 4)
    data = {"figure": 4, "Omega03": O03, "Gamma03": G03, "initial_spin_omega_perp": omega0,
            "t": run.time, "shear_Gamma_perp_at_s0": shear[:, 0], "Gamma3_at_s0": G[:, 0, 2],
            "max_shear_angle_deg": float(np.degrees(np.max(np.arctan2(shear[:, 0], G[:, 0, 2])))),
            "max_bend_Omega_perp": bend,
            "max_error_vs_ode_eqs_28_30": ode_err,
            "relative_energy_drift": float(np.max(np.abs(run.energy - run.energy[0])) / run.energy[0])}
    write_json(outdir / "fig4.json", data)
    return {"png": png, "json": outdir / "fig4.json", "data": data}


def fig6(outdir: Path, quick: bool = False) -> dict:
    k, eps, G03 = 2.0, 0.5, 1.0
    w = float(theory.omega(k, "plus", theory.D1_PAPER, G03))
    mode = 1
    L = 2 * np.pi * mode / k
    N = 32 if quick else 64
    sc = new_scene(straight_rod(L, N, G03, 0.0),
               {"kind": "untwisted_wave", "mode": mode, "epsilon": eps, "branch": "plus"},
               t_end=3.6, frames=5, fields=FIELDS_3D, rtol=1e-11)
    run = run_scene(sc)
    assert run.energy is not None and run.time is not None
    png = outdir / "fig6.png"
    snapshot_figure(png, _frames(run, range(len(run.time))), radius=0.1,
                    titles=[f"t = {t:.1f}" for t in run.time],
                    suptitle=r"Fig 6: untwisted wave, $\omega_+$, k = 2, $\epsilon$ = 0.5",
                    view=(15, -80), rings_every=2 if quick else 4)
    Om2, G1 = run.fields["Omega"][..., 1], run.fields["Gamma"][..., 0]
    data = {"figure": 6, "k": k, "epsilon": eps, "Gamma03": G03, "omega_plus": w,
            "period_2pi_over_omega": 2 * np.pi / w, "paper_snapshot_span": 3.6,
            "snapshot_times": run.time, "max_abs_Omega2": float(np.max(np.abs(Om2))),
            "max_abs_Gamma1": float(np.max(np.abs(G1))),
            "relative_energy_drift": float(np.max(np.abs(run.energy - run.energy[0])) / run.energy[0]),
            "planar": float(np.max(np.abs(run.fields["Gamma"][..., 1]))) == 0.0}
    write_json(outdir / "fig6.json", data)
    return {"png": png, "json": outdir / "fig6.json", "data": data}
