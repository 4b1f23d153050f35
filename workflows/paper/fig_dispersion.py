"""Figs 1, 2 and 5 of the paper: closed-form dispersion branches and ratios.

Fig 1: the four branches omega_+/-^{p,m}(k) of Eq (26), Omega03 = 1, Gamma03 = 1, D1 = 1.21,
       with the two parabolic points at k = Omega03 (kappa_m = 0) marked.
Fig 2: the shear/bend energy ratio of Eq (27) on those branches.
Fig 5: |Gamma1| / |Omega2| of the untwisted wave (Eqs 40-43) for omega_+ and omega_-.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from dnarod.paper import theory
from dnarod.paper.common import finish, plt, write_json

D1, G03, O03 = theory.D1_PAPER, 1.0, 1.0
STYLE = {("plus", "p"): ("C0", "-"), ("minus", "p"): ("C1", "-"),
         ("plus", "m"): ("C0", "--"), ("minus", "m"): ("C1", "--")}


def _branches(k):
    kp, km = theory.modified_wavenumbers(k, O03)
    return {(b, pm): (kap, theory.omega(kap, b, D1, G03))
            for pm, kap in (("p", kp), ("m", km)) for b in ("plus", "minus")}


def fig1(outdir: Path, quick: bool = False) -> dict:
    k = np.linspace(0.0, 4.0, 101 if quick else 801)
    br = _branches(k)
    fig, ax = plt().subplots(figsize=(5, 3.6))
    for (b, pm), (kap, w) in br.items():
        c, ls = STYLE[(b, pm)]
        ax.plot(k, w, color=c, ls=ls, label=rf"$\omega_{{{'+' if b == 'plus' else '-'}}}^{{{pm}}}$")
    dots = {"omega_minus_m": float(theory.omega(0.0, "minus", D1, G03)),
            "omega_plus_m": float(theory.omega(0.0, "plus", D1, G03))}
    ax.plot([O03, O03], [dots["omega_minus_m"], dots["omega_plus_m"]], "ko", ms=5)
    png = finish(fig, ax, outdir / "fig1.png", "k", r"$\omega$",
                 r"Fig 1: Eq (26), $\Omega_{03}=1$, $\Gamma_{03}=1$, $D_1=1.21$", legend=8)
    data = {"figure": 1, "equation": "26", "D1": D1, "Gamma03": G03, "Omega03": O03,
            "parabolic_points_at_k_equal_Omega03": dots,
            "samples": {f"omega_{b}_{pm}": {"k": [0.0, 1.0, 2.0, 4.0],
                                            "omega": theory.omega(theory.modified_wavenumbers(
                                                np.array([0.0, 1.0, 2.0, 4.0]), O03)[0 if pm == "p" else 1],
                                                b, D1, G03)}
                        for b in ("plus", "minus") for pm in ("p", "m")}}
    write_json(outdir / "fig1.json", data)
    return {"png": png, "json": outdir / "fig1.json", "data": data}


def fig2(outdir: Path, quick: bool = False) -> dict:
    k = np.linspace(0.0, 4.0, 101 if quick else 801)
    k = k[np.abs(k - O03) > 1e-9]  # Eq 27 is 0/0 or inf exactly at kappa_m = 0
    br = _branches(k)
    fig, ax = plt().subplots(figsize=(5, 3.6))
    out = {}
    for (b, pm), (kap, w) in br.items():
        r = theory.energy_ratio(w, kap, D1, G03)
        c, ls = STYLE[(b, pm)]
        ax.semilogy(k, r, color=c, ls=ls, label=rf"$\omega_{{{'+' if b == 'plus' else '-'}}}^{{{pm}}}$")
        out[f"{b}_{pm}"] = {"k_near_Omega03": float(k[np.argmin(np.abs(k - O03))]),
                            "ratio_near_Omega03": float(r[np.argmin(np.abs(k - O03))]),
                            "ratio_at_k_max": float(r[-1])}
    ax.axhline(1.0, color="gray", lw=0.5)
    png = finish(fig, ax, outdir / "fig2.png", "k", r"$\Gamma_\perp^2 / (D_1 \Omega_\perp^2)$",
                 "Fig 2: shear/bend energy ratio, Eq (27)", legend=8)
    data = {"figure": 2, "equation": "27", "D1": D1, "Gamma03": G03, "Omega03": O03, "branches": out}
    write_json(outdir / "fig2.json", data)
    return {"png": png, "json": outdir / "fig2.json", "data": data}


def fig5(outdir: Path, quick: bool = False) -> dict:
    k = np.logspace(-2, 2, 81 if quick else 401)
    fig, ax = plt().subplots(figsize=(5, 3.6))
    out = {}
    for b, c in (("plus", "C0"), ("minus", "C1")):
        w = theory.omega(k, b, D1, G03)
        r = theory.shear_bend_amplitude_ratio(w, k, D1, G03)
        ax.loglog(k, r, color=c, label=rf"$\omega_{{{'+' if b == 'plus' else '-'}}}$")
        out[b] = {"k": [float(k[0]), float(k[-1])], "ratio": [float(r[0]), float(r[-1])]}
    ax.axhline(1.0, color="gray", lw=0.5)
    png = finish(fig, ax, outdir / "fig5.png", "k", r"$|\Gamma_1| / |\Omega_2|$",
                 r"Fig 5: $|\omega^2 - D_1 k^2| / (k \Gamma_{03})$ from Eqs (40)-(43)", legend=8)
    data = {"figure": 5, "equations": "40-43", "D1": D1, "Gamma03": G03, "ends": out,
            "formula": "|Gamma1|/|Omega2| = |w^2 - D1 k^2| / (k Gamma03)"}
    write_json(outdir / "fig5.json", data)
    return {"png": png, "json": outdir / "fig5.json", "data": data}
