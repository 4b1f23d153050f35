"""The damping a viscoelastic material predicts for a mode (docs/coarse-graining.md,
"Compliance by timescale", rule 2).

The standard linear solid in its creep form: an elastic compliance J_u that responds at once
(the fast elastic motions, ps) in series with a retarded one J_r of retardation time tau,

    J(t) = J_u + J_r (1 - e^{-t / tau})     (t above the fast motions' correlation time),
    J*(omega) = J_u + J_r / (1 + i omega tau) = J' - i J''.

By fluctuation-dissipation J(t) is the equilibrium creep compliance of timescale.py
(the mean-square displacement over 2 kT), so the three numbers are fitted to it
(`fit_sls`). A mode of frequency omega_0 on this material, m omega^2 = K*(omega) =
1 / J*(omega), oscillates as e^{i omega t} with omega = omega_0 (1 + i tan(delta) / 2) for a
small loss tangent tan(delta) = J'' / J' = K'' / K': its damping constant (x'' + gamma x' +
omega_0^2 x = 0, amplitude decay gamma / 2) is gamma = omega_0 tan(delta(omega_0))
(`predicted_gamma`); `mode_root` solves m omega^2 = K*(omega) exactly.

A rod's mode on a 6x6 K* = K' + i K'' (`mode_decay_rate`): omega^2 = w(K')^2 + i Delta to
first order, Delta = d w^2 / d eps of K' + eps K'' (a central difference), so the amplitude
decays at Im(omega) = Delta / (2 omega): half the damping constant above, and the
`damping_per_ps` of `dnarod modes` (x'' + 2 gamma x' + omega0^2 x = 0).
"""
from __future__ import annotations

import numpy as np

from dna_models.errors import InputError


def sls_creep(t_ps, J_u: float, J_r: float, tau_ps: float):
    """J(t) = J_u + J_r (1 - e^{-t / tau})."""
    return J_u + J_r * (1.0 - np.exp(-np.asarray(t_ps, dtype=float) / tau_ps))


def sls_dynamic(omega_per_ps, J_u: float, J_r: float, tau_ps: float):
    """J*(omega) = J_u + J_r / (1 + i omega tau) (J' - i J''); omega may be complex."""
    return J_u + J_r / (1.0 + 1j * np.asarray(omega_per_ps) * tau_ps)


def fit_sls(t_ps, J, t_min_ps: float) -> dict:
    """Least-squares fit of sls_creep to the creep compliance J at lags t_ps >= t_min_ps:
    {J_u, J_r, tau_ps, rms} (unweighted: the lags' errors are strongly correlated, so the
    error of a fit comes from refitting independent pieces of the record, not from here)."""
    from scipy.optimize import curve_fit
    t = np.asarray(t_ps, dtype=float)
    y = np.asarray(J, dtype=float)
    ok = t >= t_min_ps
    if ok.sum() < 4:
        raise InputError(f"standard linear solid: {int(ok.sum())} lags at or above {t_min_ps:g} ps; need at least 4")
    t, y = t[ok], y[ok]
    p0 = (max(y[0], 1e-12), max(y[-1] - y[0], 1e-12), max((t[-1] - t[0]) / 5.0, 1e-6))
    p, _ = curve_fit(sls_creep, t, y, p0=p0, bounds=([0.0, 0.0, 1e-6], [np.inf, np.inf, np.inf]), maxfev=20000)
    return {"J_u": float(p[0]), "J_r": float(p[1]), "tau_ps": float(p[2]),
            "rms": float(np.sqrt(np.mean((sls_creep(t, *p) - y) ** 2)))}


def predicted_gamma(omega_per_ps, J_u: float, J_r: float, tau_ps: float):
    """gamma = omega tan(delta(omega)) = omega J'' / J' (per ps): the damping constant of a mode
    of frequency omega on this material, to first order in the loss."""
    Js = sls_dynamic(omega_per_ps, J_u, J_r, tau_ps)
    return np.asarray(omega_per_ps, dtype=float) * (-Js.imag) / Js.real


def mode_root(mass: float, J_u: float, J_r: float, tau_ps: float, omega0_per_ps: float) -> complex:
    """The complex root omega near omega0 of mass omega^2 = 1 / J*(omega) (Newton); the mode
    decays as e^{-Im(omega) t}, so its damping constant is 2 Im(omega)."""
    w = complex(omega0_per_ps)
    for _ in range(100):
        f = mass * w * w - 1.0 / sls_dynamic(w, J_u, J_r, tau_ps)
        h = 1e-7 * abs(w)
        df = (mass * (w + h) ** 2 - 1.0 / sls_dynamic(w + h, J_u, J_r, tau_ps) - f) / h
        step = f / df
        w -= step
        if abs(step) < 1e-13 * abs(w):
            break
    return w


LOSS_STEP = 0.01          # eps of mode_decay_rate's central difference (Delta exact to ~eps^2)


def mode_decay_rate(K_storage, K_loss, omega_per_ps: float, material_of, frequency_of) -> float:
    """The amplitude decay rate [1/ps] that the loss stiffness K'' gives a mode of frequency
    omega (module doc); material_of(K) is the rod of stiffness K, frequency_of(rod) the mode's w."""
    K_storage, K_loss = np.asarray(K_storage, float), np.asarray(K_loss, float)
    w_plus = frequency_of(material_of(K_storage + LOSS_STEP * K_loss))
    w_minus = frequency_of(material_of(K_storage - LOSS_STEP * K_loss))
    return float((w_plus ** 2 - w_minus ** 2) / (2.0 * LOSS_STEP) / (2.0 * omega_per_ps))
