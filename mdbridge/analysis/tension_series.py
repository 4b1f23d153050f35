"""The bend frequencies against the tension, across MD runs of one duplex
(docs/results.md, "Frequencies against tension").

A string-beam of mass mu per length under tension T has mu omega_n^2 = T k_n^2 + B k_n^4, so
across runs that differ in tension only (other seeds, other box lengths) omega_n^2 is a
straight line in T of slope k_n^2 / mu: a number with no stiffness in it and no fitted
parameter. The rod adds shear compliance and rotary inertia; the predicted slope here is
the linear rod's own, d omega_n^2 / dT by central differences of
dispersion_prediction.bend_frequencies at the runs' mean tension. For the paper's material
and 158 bp it is below k^2 / mu, and falls slowly with T: 0.95, 0.92, 0.86 of it at n = 1
and 20, 40, 80 pN; 0.83, 0.81, 0.76 at n = 4 (the tension also strains the shear), so
over the MD's 20-80 pN a straight line is the rod's to a few per cent of the slope.

The measured slope: a straight line through the runs' (T_i +- dT_i, omega_i^2 +- d(omega_i^2))
with both errors, minimising chi^2 with the effective variance sigma_y^2 + s^2 sigma_x^2 (the
functional errors-in-variables model), its error from chi^2_min + 1, and the chi^2 about it.
"""
from __future__ import annotations

import math

import numpy as np

from dna_models.errors import InputError

from mdbridge.analysis.dispersion_prediction import Duplex, bend_frequencies
from mdbridge.rod.linear import UniformMaterial

TENSION_STEP_PN = 1.0


def line_with_errors(x, ex, y, ey) -> dict:
    """y = a + s x through points with errors in both (module doc): {slope, slope_err,
    intercept, intercept_err, chi2, dof}. chi^2(s) = sum (y - a(s) - s x)^2 / (ey^2 + s^2 ex^2),
    a(s) its minimum over a, is minimised over s itself (the fixed point of re-weighted
    least squares is not its minimum, and is biased low when the x errors dominate); the
    errors from chi^2 + 1 (s) and the weights at the minimum (a)."""
    from scipy.optimize import brentq, minimize_scalar
    x, ex, y, ey = (np.asarray(v, float) for v in (x, ex, y, ey))
    if len(x) < 2:
        raise InputError(f"a line needs at least 2 points; got {len(x)}")
    if np.ptp(x) <= 0:
        raise InputError("every point has the same tension: no slope to measure")

    def at(s):
        w = 1.0 / (ey ** 2 + s ** 2 * ex ** 2)
        a = float((w * (y - s * x)).sum() / w.sum())
        return float((w * (y - a - s * x) ** 2).sum()), a, w

    # the ordinary weighted slope sets the scale of the search
    w0 = 1.0 / ey ** 2
    xm = (w0 * x).sum() / w0.sum()
    s0 = float((w0 * (x - xm) * y).sum() / (w0 * (x - xm) ** 2).sum())
    scale = abs(s0) + float(np.sqrt(1.0 / (w0 * (x - xm) ** 2).sum()))
    s = float(minimize_scalar(lambda v: at(v)[0], bracket=(s0 - scale, s0 + scale)).x)
    chi2, a, w = at(s)
    # chi^2 + 1 on each side (chi^2 grows without bound only if the x errors are small; where
    # it levels off below chi^2 + 1 the slope is unbounded on that side: the error says so)
    errs = []                                  # distance from s to chi^2 + 1: above, below
    for sign in (1, -1):
        far = s + sign * scale
        for _ in range(60):
            if at(far)[0] >= chi2 + 1:
                break
            far = s + 2 * (far - s)
        errs.append(abs(brentq(lambda v: at(v)[0] - chi2 - 1, s, far) - s) if at(far)[0] >= chi2 + 1
                    else math.inf)
    s_err = 0.5 * (errs[0] + errs[1])
    xw = (w * x).sum() / w.sum()
    return {"slope": s, "slope_err": s_err, "slope_err_interval": [s - errs[1], s + errs[0]],
            "intercept": a, "intercept_err": float(math.sqrt(1 / w.sum() + xw ** 2 * s_err ** 2)),
            "chi2": chi2, "dof": len(x) - 2}


def predicted_slope(mat: UniformMaterial, duplex: Duplex, tension_pN: float, ns) -> np.ndarray:
    """d omega_n^2 / dT [(rad/ps)^2 / pN] of the linear rod of `mat` at `tension_pN`, lab bend
    modes `ns` (central differences of TENSION_STEP_PN)."""
    hi = bend_frequencies(mat, duplex, tension_pN + TENSION_STEP_PN, ns)
    lo = bend_frequencies(mat, duplex, tension_pN - TENSION_STEP_PN, ns)
    return (hi ** 2 - lo ** 2) / (2 * TENSION_STEP_PN)


def frequency_against_tension(runs: list, mat: UniformMaterial, duplex: Duplex, ns) -> list:
    """Per bend mode n in `ns`: the measured slope of omega0^2 against the virial tension
    over `runs` ([{name, tension_pN, tension_err_pN, omega0: {n: (omega0, err)}}], rad/ps),
    the runs that measure it, the rod's predicted slope at their mean tension, and
    z = (measured - predicted) / measured error."""
    out = []
    for n in ns:
        use = [r for r in runs if r["omega0"].get(n) and r["omega0"][n][0] is not None and r["omega0"][n][1]]
        row = {"n": int(n), "runs": [r["name"] for r in use]}
        if len(use) < 3 or len({r["tension_pN"] for r in use}) < 2:
            row["reason"] = f"{len(use)} runs measure bend n = {n}: a slope with an error needs 3 or more"
            out.append(row)
            continue
        T = np.array([r["tension_pN"] for r in use])
        eT = np.array([r["tension_err_pN"] for r in use])
        w = np.array([r["omega0"][n][0] for r in use])
        ew = np.array([r["omega0"][n][1] for r in use])
        fit = line_with_errors(T, eT, w ** 2, 2 * w * ew)
        pred = float(predicted_slope(mat, duplex, float(T.mean()), [n])[0])
        row.update(fit, predicted_slope=pred, slope_over_predicted=fit["slope"] / pred,
                   z=(fit["slope"] - pred) / fit["slope_err"], reason=None)
        out.append(row)
    return out
