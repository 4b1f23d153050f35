"""The noise of a fitted mode amplitude c(t): an Ornstein-Uhlenbeck process, estimated from
the fit's residual with what the fit absorbed accounted for, and drawn again for the
parametric bootstrap of the fit (mdbridge/analysis/wavespeed.py).

Model: c(t) = m(t; theta) + z(t), the real and the imaginary part of z independent, each
stationary OU of variance s2 and correlation time tau,

    <z(t) z(t')> = s2 exp(-|t - t'| / tau),

i.e. an exact AR(1) at the sampled times, phi_i = exp(-(t_i - t_{i-1}) / tau), which need not be
uniform. Thermal noise of a mode amplitude that is not the oscillating mode itself is close to
this; white noise is the limit tau -> 0.

Why not the residual's own autocorrelation: the fit absorbs the part of the noise that
looks like the model (a slow noise is largely taken up by the static offset and by the
frequency), so the residual is less correlated and smaller than the noise, the more so the
shorter the record. Restricted maximum likelihood (REML) estimates (s2, tau) from the
likelihood of the residual alone -- the data projected off the columns of the linearised
model X -- which counts exactly what those columns absorb:

    -2 l(tau) = (N - p) log q(tau) + log|R(tau)| + log|X^T R^-1 X| + const,

N the number of real data (2 per frame), p the columns of X, R the OU correlation matrix,
q the generalised least-squares residual sum of squares r^T R^-1 r after projecting off X,
and s2 = q / (N - p) at the best tau. R^-1 is applied by the AR(1) whitening
w_0 = y_0, w_i = (y_i - phi_i y_{i-1}) / sqrt(1 - phi_i^2), and log|R| = sum log(1 - phi_i^2).
"""
from __future__ import annotations

import math

import numpy as np
from scipy.optimize import minimize_scalar

PHI_MAX = 1.0 - 1e-9       # keeps the whitening finite when tau is far above the step
TAU_SCAN = 48              # log-spaced tau of the global REML scan before the refinement


def ar1_phi(times_ps: np.ndarray, tau_ps: float) -> np.ndarray:
    """phi_i = exp(-(t_i - t_{i-1}) / tau) for i >= 1 (length T - 1)."""
    dt = np.diff(np.asarray(times_ps, float))
    if tau_ps <= 0:
        return np.zeros_like(dt)
    return np.minimum(np.exp(-dt / tau_ps), PHI_MAX)


def whiten(y: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """W y along axis 0 (T, ...) with W^T W = R^-1, R the unit-variance OU correlation."""
    y = np.asarray(y, float)
    out = np.empty_like(y)
    out[0] = y[0]
    shape = (-1,) + (1,) * (y.ndim - 1)
    out[1:] = (y[1:] - phi.reshape(shape) * y[:-1]) / np.sqrt(1.0 - phi ** 2).reshape(shape)
    return out


def _reml_objective(times_ps, X: np.ndarray, r: np.ndarray, tau_ps: float):
    """-2 l(tau) + const and q(tau) for the stacked real data r (T, 2) and columns X (T, 2, p)."""
    T = len(times_ps)
    phi = ar1_phi(times_ps, tau_ps)
    p = X.shape[-1]
    Wx = whiten(X, phi).reshape(2 * T, p)
    Wr = whiten(r, phi).reshape(2 * T)
    beta, *_ = np.linalg.lstsq(Wx, Wr, rcond=None)
    q = float(np.sum((Wr - Wx @ beta) ** 2))
    sign, logdet_xrx = np.linalg.slogdet(Wx.T @ Wx)
    logdet_r = 2.0 * float(np.sum(np.log1p(-phi ** 2)))
    N = 2 * T
    return (N - p) * math.log(max(q, 1e-300)) + logdet_r + logdet_xrx, q


def fit_ou_noise(times_ps, residual: np.ndarray, columns: np.ndarray) -> dict:
    """REML estimate of (s2, tau) of the complex residual (T,) of a fit whose linearised
    model has the complex columns `columns` (T, p) with real coefficients.

    Returns noise_rms_A (sqrt s2, per part), noise_tau_ps and noise_phi_median (the AR(1)
    coefficient at the median step)."""
    t = np.asarray(times_ps, float)
    r = np.asarray(residual, complex)
    J = np.asarray(columns, complex)
    rr = np.stack([r.real, r.imag], axis=1)                     # (T, 2)
    X = np.stack([J.real, J.imag], axis=1)                      # (T, 2, p)
    T, p = len(t), J.shape[1]
    if 2 * T <= p + 1 or not np.any(rr):
        return {"noise_rms_A": float(np.sqrt(np.mean(np.abs(r) ** 2) / 2)), "noise_tau_ps": 0.0,
                "noise_phi_median": 0.0}
    dt = float(np.median(np.diff(t)))
    span = float(t[-1] - t[0])
    lo, hi = math.log(dt / 20.0), math.log(20.0 * span)
    grid = np.linspace(lo, hi, TAU_SCAN)
    obj = [_reml_objective(t, X, rr, math.exp(g))[0] for g in grid]
    j = int(np.argmin(obj))
    a, b = grid[max(j - 1, 0)], grid[min(j + 1, TAU_SCAN - 1)]
    best = minimize_scalar(lambda g: _reml_objective(t, X, rr, math.exp(g))[0], bounds=(a, b),
                           method="bounded", options={"xatol": 1e-4})
    log_tau = float(best.x) if best.fun <= obj[j] else float(grid[j])
    tau = math.exp(log_tau)
    _, q = _reml_objective(t, X, rr, tau)
    s2 = q / (2 * T - p)
    return {"noise_rms_A": math.sqrt(s2), "noise_tau_ps": tau,
            "noise_phi_median": float(math.exp(-dt / tau))}


def ou_apply(times_ps, tau_ps: float, X: np.ndarray) -> np.ndarray:
    """R X (T, ...) with R_ij = exp(-|t_i - t_j| / tau), without forming R: the correlation
    is a product of the steps' phi_i, so R X = F + B - X with the forward sums
    F_i = X_i + phi_i F_{i-1} and the backward sums B_i = X_i + phi_{i+1} B_{i+1}
    (O(T) memory: a 5-ns record of 0.5-ps frames would need 800 MB for R)."""
    X = np.asarray(X, float)
    if tau_ps <= 0:
        return X.copy()
    phi = np.exp(-np.diff(np.asarray(times_ps, float)) / tau_ps).reshape((-1,) + (1,) * (X.ndim - 1))
    F, B = X.copy(), X.copy()
    for i in range(1, len(X)):
        F[i] += phi[i - 1] * F[i - 1]
    for i in range(len(X) - 2, -1, -1):
        B[i] += phi[i] * B[i + 1]
    return F + B - X


def draw_ou(rng: np.random.Generator, times_ps, rms_A: float, tau_ps: float, n_draws: int) -> np.ndarray:
    """n_draws complex OU series (n_draws, T), stationary from the first sample."""
    t = np.asarray(times_ps, float)
    phi = ar1_phi(t, tau_ps)
    e = rng.standard_normal((2, n_draws, len(t)))
    z = np.empty_like(e)
    z[..., 0] = e[..., 0]
    kick = np.sqrt(1.0 - phi ** 2)
    for i in range(1, len(t)):
        z[..., i] = phi[i - 1] * z[..., i - 1] + kick[i - 1] * e[..., i]
    return rms_A * (z[0] + 1j * z[1])
