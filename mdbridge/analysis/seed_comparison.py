"""Realisations of one duplex that differ in tension, compared mode by mode after the tension is
taken out (docs/dispersion.md, "Tension-corrected differences").

The vacuum duplex's tension is a property of the realisation (how much contour its opened pairs
and thermal bends store: 22.0 +- 3.2 and 43.7 pN over the same 1000-3000 ps of two seeds), and
the low bend modes follow it (d ln omega / dT ~ 1 / (2 (T + B k^2)) per pN). Two seeds' raw
differences then hold the tension's effect beside their sampling scatter. Here each
realisation's frequency becomes a residual,

    r_i = omega_md,i - omega_rod(T_i),   err_i^2 = err_md,i^2 + (d omega_rod / dT (T_i) dT_i)^2,

the linear rod's frequency at that realisation's own virial tension T_i +- dT_i
(dispersion_prediction.frequencies; its slope by a central difference of +-TENSION_STEP_PN).
What the rod gets wrong at both tensions alike (its stiffness, its length) cancels in the
difference r_a - r_b; what is left is the sampling scatter, the tensions' errors, and whatever
the rod's slope d omega / dT gets wrong. The chi^2 of the differences, sum of
(r_a - r_b)^2 / (err_a^2 + err_b^2), per kind and pooled over kinds, is ~dof when the errors
cover the scatter between realisations.

The MD's side is the undamped frequency omega0 = sqrt(omega^2 + gamma^2) (what a rod without
friction has: dispersion_prediction.md_natural_frequency), with either its fit error or its
block error (mdbridge/analysis/block_errors.py, err_chi2: Student-t inflated).
"""
from __future__ import annotations

import math

from mdbridge.analysis.dispersion_prediction import Duplex, frequencies
from mdbridge.rod.linear import UniformMaterial

KINDS = ("bend", "twist", "stretch")
TENSION_STEP_PN = 0.5


def rod_frequency_and_slope(mat: UniformMaterial, duplex: Duplex, tension_pN: float, n_max: int = 14) -> dict:
    """{(kind, n): (omega [rad/ps], d omega / dT [rad/ps/pN])} of the rod of `mat` at tension_pN."""
    c = frequencies(mat, duplex, tension_pN, n_max)
    hi = frequencies(mat, duplex, tension_pN + TENSION_STEP_PN, n_max)
    lo = frequencies(mat, duplex, tension_pN - TENSION_STEP_PN, n_max)
    return {(k, n): (c[k][n][0], (hi[k][n][0] - lo[k][n][0]) / (2 * TENSION_STEP_PN))
            for k in KINDS for n in c[k] if n in hi[k] and n in lo[k]}


def residuals(md: dict, tension_pN: float, tension_err_pN: float, rod: dict | None) -> dict:
    """{(kind, n): (r, err, the tension's part of err)} of one realisation: md maps (kind, n) to
    (omega, err) [rad/ps] (None when not measured); rod is rod_frequency_and_slope at this
    realisation's tension, or None for the raw frequencies (no correction: the control)."""
    out = {}
    for key, v in md.items():
        if v is None or v[0] is None or v[1] is None:
            continue
        w, e = v
        if rod is None:
            out[key] = (float(w), float(e), 0.0)
        elif key in rod:
            w_rod, slope = rod[key]
            e_T = abs(slope) * tension_err_pN
            out[key] = (float(w - w_rod), math.hypot(e, e_T), e_T)
    return out


def differences_by_kind(a: dict, b: dict) -> dict:
    """The chi^2 of the differences b - a of two realisations' residuals (`residuals`) over the
    modes both have, per kind, in the shape of dnarod.steps.dispersion.differences_by_kind
    ({kind: {chi2, dof, n}}), with each mode's z, and `pooled` over the kinds."""
    out: dict = {}
    for key in sorted(set(a) & set(b), key=lambda k: (KINDS.index(k[0]), k[1])):
        kind, n = key
        z = (b[key][0] - a[key][0]) / math.hypot(a[key][1], b[key][1])
        e = out.setdefault(kind, {"chi2": 0.0, "dof": 0, "n": [], "z": []})
        e["chi2"] += float(z * z)
        e["dof"] += 1
        e["n"].append(int(n))
        e["z"].append(float(z))
    chi2 = sum(v["chi2"] for v in out.values())
    dof = sum(v["dof"] for v in out.values())
    for v in out.values():
        v["chi2_per_dof"] = v["chi2"] / v["dof"]
    out["pooled"] = {"chi2": chi2, "dof": dof, "chi2_per_dof": chi2 / dof if dof else None}
    return out


def compare_realisations(md: list[dict], tensions: list[tuple[float, float]], mats: list[UniformMaterial] | None,
                         duplex: Duplex, n_max: int = 14) -> dict:
    """Every realisation against the first (the reference): the tension-corrected chi^2 per
    kind (`differences_by_kind` of `residuals` with the rod of mats[i] at realisation i's
    tension: one material per realisation, since box_rod.paper_rod_box depends on the tension),
    or the raw one when mats is None. md: per realisation {(kind, n): (omega, err)}; tensions:
    per realisation (T, dT) [pN]."""
    rods: list[dict | None] = [None] * len(md)
    if mats is not None:
        rods = [rod_frequency_and_slope(mat, duplex, T, n_max) for mat, (T, _) in zip(mats, tensions)]
    res = [residuals(m, T, dT, rod) for m, (T, dT), rod in zip(md, tensions, rods)]
    return {"residuals": [{f"{k}_{n}": list(v) for (k, n), v in r.items()} for r in res],
            "differences_by_kind": [differences_by_kind(res[0], r) for r in res[1:]]}
