"""Numerical dispersion check: frequencies measured from small-amplitude runs of the full
nonlinear solver vs Eqs (26)/(39).

The initial state is NOT built from the dispersion relation: a rod at rest with a single
Fourier mode of shear and bend, Gamma1 = eps cos(k s), Omega2 = eps sin(k s) (eps = 1e-4),
which excites every branch at that wavenumber. The mode-k amplitudes of all transverse
fields are recorded in time; their frequencies are found from the power spectrum (peaks)
and refined by a joint least-squares fit of cos/sin terms. Untwisted rod: two branches
omega_+/-(k). Twisted rod (Omega03 = 1): four, omega_+/-(k + Omega03) and
omega_+/-(k - Omega03) -- the body-frame mode k is a laboratory wave of the modified
wavenumbers (Eq 24).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from dnarod.paper import theory
from dnarod.paper.common import find_frequencies, finish, mode_amplitude, plt, write_json
from mdbridge.rod.run import run_scene
from mdbridge.rod.scene import new_scene, straight_rod

EPS = 1e-4
TRANSVERSE = [(f, c) for f in ("gamma", "omega", "Gamma", "Omega") for c in (0, 1)]


def predicted(k: float, Omega03: float):
    """[(label, kappa, omega)] of the branches present at body wavenumber k."""
    kaps = [("", k)] if Omega03 == 0 else [("p", k + Omega03), ("m", k - Omega03)]
    return [(f"{b}{'_' + pm if pm else ''}", kap, float(theory.omega(kap, b))) for pm, kap in kaps
            for b in ("minus", "plus")]


def measure(k: float, Omega03: float, N: int = 16, periods: float = 6.0) -> dict:
    pred = predicted(k, Omega03)
    w_sorted = sorted(p[2] for p in pred)
    gap = min(np.diff(w_sorted)) if len(w_sorted) > 1 else w_sorted[0]
    t_end = max(periods * 2 * np.pi / w_sorted[0], 12 * np.pi / gap)
    dt = min(2 * np.pi / w_sorted[-1] / 12, t_end / 200)
    frames = int(np.ceil(t_end / dt)) + 1
    L = 2 * np.pi / k
    s = np.arange(N) * L / N
    z = np.zeros(N)
    fields = {"gamma": np.column_stack([z, z, z]), "omega": np.column_stack([z, z, z]),
              "Gamma": np.column_stack([EPS * np.cos(k * s), z, 1.0 + z]),
              "Omega": np.column_stack([z, EPS * np.sin(k * s), Omega03 + z])}
    run = run_scene(new_scene(straight_rod(L, N, 1.0, Omega03), None, t_end=t_end, frames=frames,
                          fields=("internal",), rtol=1e-12), initial=fields)
    amplitudes = []
    for f, c in TRANSVERSE:
        a = mode_amplitude(run.fields[f][..., c], 1)
        amplitudes += [a.real, a.imag]
    sig = np.array(amplitudes) / EPS
    w_fit, rel = find_frequencies(run.time, sig, len(pred))
    rows = []
    for label, kap, w in pred:
        j = int(np.argmin(np.abs(w_fit - w)))
        rows.append({"k": k, "Omega03": Omega03, "branch": label, "kappa": kap, "omega_theory": w,
                     "omega_measured": float(w_fit[j]), "rel_diff": float(abs(w_fit[j] - w) / w)})
    return {"rows": rows, "fit_rel_residual": rel, "t_end": t_end, "frames": frames, "N": N}


def check(outdir: Path | None = None, quick: bool = False) -> dict:
    ks_untwisted = [1.0, 4.0] if quick else [0.25, 0.5, 1.0, 2.0, 4.0, 8.0]
    ks_twisted = [2.0] if quick else [0.5, 2.0, 3.0, 5.0]
    rows, fits = [], []
    for O3, ks in ((0.0, ks_untwisted), (1.0, ks_twisted)):
        for k in ks:
            m = measure(k, O3)
            rows += m["rows"]
            fits.append({"k": k, "Omega03": O3, "fit_rel_residual": m["fit_rel_residual"], "t_end": m["t_end"]})
    data = {"check": "numerical dispersion vs Eqs 26/39", "amplitude": EPS, "D1": theory.D1_PAPER,
            "Gamma03": 1.0, "rows": rows, "fits": fits,
            "max_rel_diff": max(r["rel_diff"] for r in rows)}
    if outdir is not None:
        fig, ax = plt().subplots(figsize=(5.5, 3.8))
        q = np.linspace(0, max(abs(r["kappa"]) for r in rows) * 1.05, 300)
        for b, c in (("plus", "C0"), ("minus", "C1")):
            ax.plot(q, theory.omega(q, b), color=c, lw=1, label=rf"Eq (39) $\omega_{{{'+' if b == 'plus' else '-'}}}$")
        for r in rows:
            mk = "o" if r["Omega03"] == 0 else "s"
            ax.plot(abs(r["kappa"]), r["omega_measured"], mk, mfc="none",
                    color="C0" if r["branch"].startswith("plus") else "C1", ms=5)
        ax.plot([], [], "ko", mfc="none", label="run, untwisted (k)")
        ax.plot([], [], "ks", mfc="none", label=r"run, twisted ($|\kappa_{p,m}|$)")
        finish(fig, ax, outdir / "dispersion_check.png", r"$|\kappa|$", r"$\omega$",
               f"measured frequencies vs Eqs (26)/(39): max rel. diff {data['max_rel_diff']:.1e}", legend=7)
        write_json(outdir / "dispersion_check.json", data)
    return data
