"""Integrated autocorrelation times of stationary series (the frame spacing that
makes two frames independent), vectorised over any trailing axes.

tau_int = 1/2 + sum_{k>=1} rho(k), so that var(mean of N frames) = 2 tau_int var / N
and N / (2 tau_int) is the number of effectively independent frames. The sum is cut
at Sokal's self-consistent window (the first W with W >= c tau_int(W), c = 5), which
keeps the estimate's own noise small while a geometric tail is still summed to
within e^-5 of it (Sokal 1997, "Monte Carlo methods in statistical mechanics",
Sec 3; the same rule as emcee's `integrated_time`).
"""
from __future__ import annotations

import numpy as np

SOKAL_C = 5.0


def autocorrelation(x: np.ndarray) -> np.ndarray:
    """Normalised autocorrelation rho(k), k = 0..T-1, along axis 0 of x (T, ...),
    by FFT with zero padding (no circular wrap). A constant series gives rho = 1 at
    k = 0 and 0 elsewhere."""
    x = np.asarray(x, dtype=float)
    T = x.shape[0]
    d = x - x.mean(axis=0)
    n = 1 << int(np.ceil(np.log2(2 * T)))
    f = np.fft.rfft(d, n=n, axis=0)
    acf = np.fft.irfft(f * np.conj(f), n=n, axis=0)[:T]
    c0 = acf[0]
    safe = np.where(c0 > 0, c0, 1.0)
    rho = acf / safe
    rho[:, ...] = np.where(c0 > 0, rho, 0.0)
    if T:
        rho[0] = 1.0
    return rho


def integrated_time(x: np.ndarray, c: float = SOKAL_C) -> np.ndarray:
    """tau_int (in frames, >= 1/2) of each series along axis 0 of x (T, ...)."""
    rho = autocorrelation(x)
    T = rho.shape[0]
    # cumulative tau(W) = 1/2 + sum_{k=1}^{W} rho(k); window: first W >= c tau(W)
    tau_w = np.cumsum(rho, axis=0) - 0.5
    W = np.arange(T).reshape((T,) + (1,) * (rho.ndim - 1))
    ok = W >= c * tau_w
    first = np.where(ok.any(axis=0), ok.argmax(axis=0), T - 1)
    tau = np.take_along_axis(tau_w, first[None], axis=0)[0]
    return np.maximum(tau, 0.5)


def effective_samples(n_frames: int, tau) -> np.ndarray:
    """N / (2 tau_int): the number of independent frames the series is worth."""
    return n_frames / (2.0 * np.asarray(tau, dtype=float))
