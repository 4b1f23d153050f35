"""The relaxation time of a mode from its equilibrium time series: the integrated
autocorrelation time, with its error from blocks (docs/modes.md, "Overdamped modes").

Why the integral. A damped harmonic mode x'' + Gamma x' + omega0^2 x = noise (Gamma the
friction per mass, zeta / m; omega0^2 = k / m) has the autocorrelation rho(t) = C(t) / C(0),
and in every regime

    tau = int_0^inf rho(t) dt = Gamma / omega0^2 = zeta / k,

since its spectrum at zero frequency, 2 kT Gamma / (m omega0^4), is 2 C(0) tau with C(0) =
kT / (m omega0^2). No model of the decay is fitted: an overdamped mode (Gamma > 2 omega0)
decays as two exponentials, at the roots lambda_+- = Gamma / 2 +- (Gamma^2 / 4 -
omega0^2)^1/2, and tau = 1 / lambda_+ + 1 / lambda_- (the slow root's 1 / lambda_- ~
Gamma / omega0^2 dominates when Gamma >> 2 omega0). What a mode's friction and stiffness
predict (zeta / k) is what is measured, with no fitted parameter.

The estimator. The series x (M, N) (Re and Im of each direction's c_n, per realisation;
each with its record mean removed) give the pooled autocorrelation rho_k at lag k dt, and

    tau = dt (1 / 2 + sum_{k=1}^{W} rho_k)            (the trapezoid rule),

W the smallest lag with W dt >= WINDOW tau(W) (Sokal's self-consistent window: the tail
beyond it, ~ exp(-WINDOW) of tau for an exponential decay, is left out, and the noise of the
lags past it is not summed). Removing each record's mean lowers every C_k by the variance
of that mean, V ~ 2 C(0) tau / T for a record T long: rho_k is taken as (rho_k + b) / (1 + b),
b = 2 tau / T, to first order in tau / T (tau solved with it self-consistently).

The error. Each series is cut into contiguous blocks at least BLOCK_OVER_WINDOW windows
long; a lag product x_t x_(t+k) belongs to the block of t. The estimate is redone leaving out one block at a time
(jackknife, with the same window), and the error is the jackknife's: blocks much longer
than the window are nearly independent, and the spread of the delete-one estimates carries both the
noise of the correlation's tail and the variance's (tests/python/test_modes_overdamped.py
holds it to the scatter between seeds).

Resolved. A relaxation time needs a record much longer than itself (MIN_RELAXATIONS:
each block then holds a few relaxations) and longer than the frame interval; otherwise
`resolved` is false and `reason` says why. An overdamped mode's autocorrelation is positive
at every lag; one that swings below -RHO_SWING within the window is an oscillation whose peak
the record does not resolve (a few periods at most), and its integral (the oscillation's
cancelling lobes) is no relaxation time: not resolved either.
"""
from __future__ import annotations

import math

import numpy as np

WINDOW = 6.0               # the window W dt >= WINDOW tau (module doc)
FINE_BLOCKS = 40           # per series; the jackknife joins runs of them (relaxation_time)
BLOCK_OVER_WINDOW = 5.0    # a jackknife block is at least this many windows long
MIN_BLOCKS = 8             # a resolved tau needs at least this many blocks
MIN_RELAXATIONS = 50.0     # a resolved tau: the record is at least this many tau long
MIN_TAU_OVER_DT = 1.0      # and tau is at least the frame interval
MAX_RELATIVE_ERR = 1.0 / 3.0   # and known to within a third (3 standard errors from zero)
RHO_SWING = 0.3            # an autocorrelation below -RHO_SWING within the window oscillates


def _block_products(x: np.ndarray, max_lag: int, blocks: int) -> tuple[np.ndarray, np.ndarray]:
    """(S (M * blocks, max_lag + 1), n (M * blocks, max_lag + 1)): per series and block, the
    sum of the lag products x_t x_(t+k) with t in the block, and how many there are."""
    M, N = x.shape
    edges = np.linspace(0, N, blocks + 1).astype(int)
    S = np.zeros((M * blocks, max_lag + 1))
    cnt = np.zeros((M * blocks, max_lag + 1))
    for k in range(max_lag + 1):
        prod = x[:, :N - k] * x[:, k:]                     # (M, N - k), indexed by t
        c = np.concatenate([np.zeros((M, 1)), np.cumsum(prod, axis=1)], axis=1)
        lo = np.minimum(edges[:-1], N - k)
        hi = np.minimum(edges[1:], N - k)
        S[:, k] = (c[:, hi] - c[:, lo]).ravel()
        cnt[:, k] = np.tile(hi - lo, M)
    return S, cnt


def _tau_from(C: np.ndarray, dt: float, record: float, window: int | None = None) -> tuple[float, int]:
    """(tau, W) from the pooled autocovariance C_k (module doc); window: a fixed W."""
    rho = C / C[0]
    tau = dt / 2
    for _ in range(50):                    # the mean's correction 2 tau / T, self-consistent
        b = 2 * tau / record
        r = (rho + b) / (1 + b)
        csum = dt * (np.cumsum(r) - 0.5)   # tau(W) for W = 0, 1, ...
        if window is None:
            lags = np.arange(len(r)) * dt
            ok = np.flatnonzero(lags >= WINDOW * csum)
            W = int(ok[0]) if len(ok) else len(r) - 1
        else:
            W = window
        new = float(csum[W])
        if abs(new - tau) <= 1e-10 * max(abs(new), dt):
            break
        tau = new
    return tau, W


def relaxation_time(x: np.ndarray, dt_ps: float) -> dict:
    """The integrated autocorrelation time of the real series x (M, N) sampled every dt_ps
    (module doc): {tau_ps, tau_err_ps, window_ps, record_ps, rho_min (the autocorrelation's
    least value within the window), relaxations_in_record, blocks, resolved, reason}."""
    x = np.atleast_2d(np.asarray(x, float))
    x = x - x.mean(axis=1, keepdims=True)
    M, N = x.shape
    record = N * dt_ps
    f = np.fft.rfft(x, n=2 * N, axis=1)
    C = np.fft.irfft(np.abs(f) ** 2, axis=1)[:, :N // 2 + 1].sum(axis=0) / (M * (N - np.arange(N // 2 + 1)))
    if not C[0] > 0:
        return {"tau_ps": None, "tau_err_ps": None, "window_ps": None, "record_ps": record,
                "rho_min": None, "relaxations_in_record": None, "blocks": 0, "resolved": False,
                "reason": "no signal (zero variance)"}
    tau, W = _tau_from(C, dt_ps, record)
    fine = max(2, min(FINE_BLOCKS, N // 4))
    # the jackknife's blocks: runs of the fine blocks, each at least BLOCK_OVER_WINDOW windows
    # long (a lag product reaches W past its block: shorter blocks would share their noise)
    run = max(1, math.ceil(BLOCK_OVER_WINDOW * (W + 1) / (N / fine)))
    per_series = max(1, fine // run)
    nb = M * per_series
    rho_min = float(np.min(C[:W + 1]) / C[0])
    out: dict = {"tau_ps": tau, "tau_err_ps": None, "window_ps": W * dt_ps, "record_ps": record,
                 "rho_min": rho_min, "relaxations_in_record": record / tau if tau > 0 else None, "blocks": nb,
                 "resolved": True, "reason": None}
    if nb >= 2 and W < N // 2:
        S, cnt = _block_products(x, W, fine)
        group = np.minimum(np.arange(fine) // run, per_series - 1)
        label = (np.arange(M)[:, None] * per_series + group[None, :]).ravel()
        Sg = np.array([S[label == g].sum(axis=0) for g in range(nb)])
        cg = np.array([cnt[label == g].sum(axis=0) for g in range(nb)])
        jack = []
        for b in range(nb):
            keep = np.arange(nb) != b
            Cb = np.concatenate([Sg[keep].sum(axis=0) / cg[keep].sum(axis=0), [0.0]])
            jack.append(_tau_from(Cb, dt_ps, record, window=W)[0])
        out["tau_err_ps"] = math.sqrt((nb - 1) / nb * float(np.sum((np.array(jack) - np.mean(jack)) ** 2)))
    err = out["tau_err_ps"]
    if not tau > 0 or W >= N // 2:
        why = "the autocorrelation does not decay within a block of the record"
    elif record < MIN_RELAXATIONS * tau:
        why = f"the record holds {record / tau:.1f} relaxation times (< {MIN_RELAXATIONS:g})"
    elif nb < MIN_BLOCKS:
        why = f"{nb} blocks of {BLOCK_OVER_WINDOW:g} windows ({W * dt_ps:.3g} ps) fit the records (< {MIN_BLOCKS})"
    elif rho_min < -RHO_SWING:
        why = (f"the autocorrelation swings to {rho_min:.2f} within the window: an oscillation (too slow for "
               "the record to resolve its peak), not a relaxation")
    elif tau < MIN_TAU_OVER_DT * dt_ps:
        why = f"tau {tau:.3g} ps is shorter than the frame interval {dt_ps:g} ps"
    elif err is None or err > MAX_RELATIVE_ERR * tau:
        why = f"tau {tau:.3g} +- {err:.2g} ps: known to worse than {MAX_RELATIVE_ERR:.2g} of itself"
    else:
        why = None
    if why:
        out.update(resolved=False, reason=why)
    return out
