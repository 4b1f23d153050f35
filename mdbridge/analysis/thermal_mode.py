"""Thermal motion of the fundamental bend mode and when a kicked frequency is measurable
(issue 15, item 4: small amplitudes).

Thermal amplitude (equipartition). For u_in(s) = q_c cos(ks) + q_s sin(ks) on a closed rod
of length L under axial force T, the bend + tension energy is
(1/2)(D k^4 + T k^2)(L/2)(q_c^2 + q_s^2), so each quadrature holds kT/2 and the complex mode
amplitude c = q_c - i q_s (wavespeed.mode_amplitude) has
    <|c|^2> = 4 kT / ((D k^4 + T k^2) L).
For the paper's D (persistence length 66 nm at 300 K), 158 bp x 3.38 A and T = 0 this is
24 A rms -- as large as the response to A_v = 0.1 A/ps (A_v / omega ~ 15-25 A).

Synthetic study (`kicked_mode_study`). Each spatial quadrature of the mode is an underdamped
Langevin oscillator at omega with quality factor Q (its coupling to the other modes; not
known a priori: measure it from the A_v = 0 MD's autocorrelation of c(t)), at the thermal
rms above, sampled exactly (discrete-time transition of the linear SDE). The kick adds a
deterministic a_kick e^{-gamma t / 2} sin(omega_d t) in one quadrature (the same damping, by
fluctuation-dissipation), plus AR(1) local noise as in test_analysis_mode_error.py. The
frequency is then fitted by mode_error.standing_mode_fit and its scatter and bias recorded.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.linalg import expm

KB = 1.380649e-23


def thermal_mode_rms_A(length_A: float, D_J_m: float, T_K: float = 300.0, tension_pN: float = 0.0) -> float:
    """rms |c| [A] of the fundamental in one transverse direction (module doc)."""
    L = length_A * 1e-10
    k = 2 * math.pi / L
    return math.sqrt(4 * KB * T_K / ((D_J_m * k ** 4 + tension_pN * 1e-12 * k ** 2) * L)) * 1e10


def _oscillator(rng, n_real, n, dt, omega, Q, rms_quadrature):
    """Stationary underdamped Langevin oscillator x'' + g x' + w^2 x = noise, exact in time."""
    g = omega / Q
    A = np.array([[0.0, 1.0], [-omega ** 2, -g]])
    F = expm(A * dt)
    S = np.diag([rms_quadrature ** 2, (omega * rms_quadrature) ** 2])  # stationary covariance
    Qd = S - F @ S @ F.T
    Lq = np.linalg.cholesky(Qd + 1e-300 * np.eye(2))
    Ls = np.linalg.cholesky(S)
    x = np.empty((n_real, n))
    st = rng.standard_normal((n_real, 2)) @ Ls.T
    for i in range(n):
        x[:, i] = st[:, 0]
        st = st @ F.T + rng.standard_normal((n_real, 2)) @ Lq.T
    return x


def kicked_mode_study(a_kick_A: float, a_thermal_A: float, omega: float, Q: float, record_ps: float,
                      dt_ps: float = 4.0, n_real: int = 20, k_per_A: float = 1.0, seed: int = 0,
                      local_noise_A: float = 1.0, local_tau_ps: float = 5.0) -> dict:
    """Scatter, bias and stated error of the fitted frequency over n_real realisations."""
    from scipy.signal import lfilter
    from mdbridge.analysis.mode_error import standing_mode_fit
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, record_ps, dt_ps)
    n = len(t)
    q = a_thermal_A / math.sqrt(2)
    xc = _oscillator(rng, n_real, n, dt_ps, omega, Q, q)
    xs = _oscillator(rng, n_real, n, dt_ps, omega, Q, q)
    g = omega / Q
    wd = math.sqrt(max(omega ** 2 - g ** 2 / 4, 0.0))
    kick = a_kick_A * np.exp(-g * t / 2) * np.sin(wd * t)
    phi = math.exp(-dt_ps / local_tau_ps)
    e = rng.standard_normal((2, n_real, n))
    e[..., 0] /= math.sqrt(1 - phi ** 2)
    ln = lfilter([math.sqrt(1 - phi ** 2) * local_noise_A], [1, -phi], e, axis=-1)
    est_list, err, refused = [], [], 0
    for r in range(n_real):
        c = (xc[r] + kick) - 1j * xs[r] + ln[0, r] + 1j * ln[1, r]
        f = standing_mode_fit(t, c, k_per_A, record_term=False)
        if not math.isfinite(f["speed_A_per_ps"]):
            refused += 1
            continue
        est_list.append(f["omega_per_ps"])
        err.append(f["omega_err_per_ps"])
    est = np.array(est_list)
    ok = len(est) >= 3
    return {"a_kick_A": a_kick_A, "a_thermal_A": a_thermal_A,
            "snr": a_kick_A / a_thermal_A if a_thermal_A else math.inf,
            "Q": Q, "record_ps": record_ps, "n_real": n_real, "refused": refused,
            "omega_true_per_ps": wd,
            "rel_bias": float(est.mean() / wd - 1) if ok else float("nan"),
            "rel_scatter": float(np.std(est, ddof=1) / wd) if ok else float("nan"),
            "rel_stated_err": float(np.mean(err) / wd) if ok else float("nan")}
