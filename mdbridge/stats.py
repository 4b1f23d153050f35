"""Errors of correlated series: the one home of every estimator the toolkit uses for the
error of a mean (or of a fit) from frames that are not independent.

Blocking
  `block_sem`: Flyvbjerg & Petersen 1989, the first plateau of the halving curve;
  `sem_longest_blocks`: the means of the longest blocks that leave 8 (for a series whose
  slow part gives the halving curve a false early plateau, docs/md.md, "Tension");
  `time_block_sem`: the means of blocks of a fixed length in time.

Autocorrelation
  `integrated_time` (from `autocorrelation`; `effective_samples`): integrated
  autocorrelation times of stationary series (the frame spacing that
  makes two frames independent), vectorised over any trailing axes.

  tau_int = 1/2 + sum_{k>=1} rho(k), so that var(mean of N frames) = 2 tau_int var / N
  and N / (2 tau_int) is the number of effectively independent frames. The sum is cut
  at Sokal's self-consistent window (the first W with W >= c tau_int(W), c = 5), which
  keeps the estimate's own noise small while a geometric tail is still summed to
  within e^-5 of it (Sokal 1997, "Monte Carlo methods in statistical mechanics",
  Sec 3; the same rule as emcee's `integrated_time`).
  `e_folding_lag`: the lag at which the autocorrelation falls below 1/e.

Moving-block bootstrap
  `block_length`, `block_starts`, `replicate_moments`, `weighted_moments`, `spread`:
  the moving-block bootstrap of frame-correlated data (Kuensch 1989 Ann Stat 17:1217).

  Frames are drawn in blocks of b consecutive frames (b from the autocorrelation
  time, `block_length`), so each replicate keeps the correlation inside a block and
  the scatter of a statistic over replicates estimates its scatter over independent
  trajectories. The same blocks serve every step and parameter, so correlations
  between steps survive (needed by the m-step and sequence-averaged quantities).
  b = 1 is the ordinary bootstrap that treats frames as independent: the control the
  tests show to be wrong for correlated frames.

  A replicate is a list of block starts; its sums of q and of the distinct products
  q_i q_j come from cumulative sums (one difference per block), so no frame is copied.
  `circular_block_indices`: one replicate of the circular variant (blocks wrap around the
  end), the residual bootstrap of mdbridge/analysis/wavespeed.py.
"""
from __future__ import annotations

import math

import numpy as np


# -- blocking ---------------------------------------------------------------------------
def block_sem(x) -> dict:
    """Standard error of the mean of a correlated series by blocking: the series is halved
    into block means repeatedly; the naive SEM of the block means rises with the block length
    until the blocks are longer than the correlation time and then levels off. The value
    returned is at the first level whose SEM is not exceeded by the next level's by more
    than the next level's own statistical error (sem / sqrt(2 (n_blocks - 1))); levels with
    fewer than 8 blocks are not used, and if no plateau is reached before that the largest
    SEM is returned with plateau = False."""
    x = np.asarray(x, float)
    x = x[np.isfinite(x)]
    n0 = len(x)
    if n0 < 16:
        return {"mean": float(np.mean(x)) if n0 else float("nan"), "sem": float("nan"),
                "n": n0, "reason": f"{n0} samples; block averaging needs at least 16"}
    levels = []
    y = x.copy()
    while len(y) >= 8:
        nb = len(y)
        sem = float(np.std(y, ddof=1) / math.sqrt(nb))
        levels.append((nb, sem, sem / math.sqrt(2 * (nb - 1))))
        y = 0.5 * (y[: 2 * (nb // 2)][0::2] + y[: 2 * (nb // 2)][1::2])
    pick, plateau = None, False
    for i in range(len(levels) - 1):
        if levels[i + 1][1] - levels[i][1] <= levels[i + 1][2]:
            pick, plateau = i, True
            break
    if pick is None:
        pick = int(np.argmax([s for _, s, _ in levels]))
    nb, sem, sem_err = levels[pick]
    return {"mean": float(np.mean(x)), "sem": sem, "sem_err": sem_err, "n": n0,
            "block_length": n0 // nb, "plateau": plateau,
            "naive_sem": levels[0][1]}


def sem_longest_blocks(y, min_blocks: int = 8) -> float:
    """Standard error of the mean from the means of the longest blocks that still leave
    MIN_BLOCKS of them (halving the series, as `block_sem` does)."""
    y = np.asarray(y, float)
    sem = float("nan")
    while len(y) >= min_blocks:
        sem = float(np.std(y, ddof=1) / np.sqrt(len(y)))
        y = 0.5 * (y[: 2 * (len(y) // 2)][0::2] + y[: 2 * (len(y) // 2)][1::2])
    return sem


def time_block_sem(t, y, block_ps: float = 1.0) -> float:
    """Standard error of the mean of y(t) from the means of consecutive blocks of block_ps
    (time units of t): std(block means) / sqrt(n_blocks); with fewer than 2 blocks, the
    naive std(y) / sqrt(n)."""
    edges = np.arange(t[0], t[-1] + 1e-9, block_ps)
    means = [y[(t >= a) & (t < a + block_ps)].mean() for a in edges
             if ((t >= a) & (t < a + block_ps)).sum() > 0]
    if len(means) < 2:
        return float(np.std(y) / np.sqrt(max(len(y), 1)))
    return float(np.std(means, ddof=1) / np.sqrt(len(means)))


def stationarity(t, y, sem=None, floor: float = 0.0) -> dict:
    """The stated test of a series' end: the means of y over the third and the fourth
    quarter of t differ by less than twice the standard error of that difference, or by
    less than FLOOR (a change too small to matter: a series without fluctuations, such as a
    relaxation at zero temperature, has no standard error to compare with). sem(t, y): the
    standard error of one quarter's mean (default: the means of 1-unit time blocks,
    `time_block_sem`). A two-sided test at ~95 % for a stationary series."""
    t, y = np.asarray(t, float), np.asarray(y, float)
    sem = sem or time_block_sem
    t0, t1 = t[0], t[-1]
    q3 = (t >= t0 + 0.5 * (t1 - t0)) & (t < t0 + 0.75 * (t1 - t0))
    q4 = t >= t0 + 0.75 * (t1 - t0)
    h = q3 | q4
    diff = float(y[q4].mean() - y[q3].mean())
    se = float(np.hypot(sem(t[q3], y[q3]), sem(t[q4], y[q4])))
    return {"mean_second_half": float(y[h].mean()), "change_between_quarters": diff,
            "standard_error_of_change": se, "floor": float(floor),
            "stationary": bool(abs(diff) < max(2.0 * se, float(floor)))}


# -- autocorrelation ----------------------------------------------------------------------
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


def e_folding_lag(r: np.ndarray) -> int:
    """The first lag at which the autocorrelation of r (real or complex) falls below 1/e,
    the block length of a residual bootstrap; n // 4 if it never does, 1 for a constant."""
    r = r - r.mean()
    var = np.vdot(r, r).real
    if var == 0:
        return 1
    n = len(r)
    for lag in range(1, n // 4):
        rho = np.vdot(r[:-lag], r[lag:]).real / var
        if rho < np.exp(-1):
            return lag
    return max(1, n // 4)


# -- moving-block bootstrap ------------------------------------------------------------------
BLOCK_TAUS = 6.0   # b = 6 tau_int. The moving-block variance is low by ~ sum_k k rho(k) / (b tau_int);
                   # measured on AR(1) series with phi = 0.9 (bench/cg_block_length.py), the scatter
                   # over realisations / stated error is 1.25 at b = 2 tau, 1.17 at 4, 1.15 at 6,
                   # 1.14 at 8, 1.12-1.14 from 12 to 26 (= T / 8): a plateau no block length removes,
                   # so 6 tau, with T / b >= 8 blocks at the minimum length


def block_length(tau_max: float, n_frames: int) -> int:
    """ceil(BLOCK_TAUS tau_max) frames, at least 1 and at most n_frames // 8."""
    b = int(math.ceil(BLOCK_TAUS * float(tau_max)))
    return max(1, min(b, max(1, n_frames // 8)))


def block_starts(n_frames: int, b: int, n_boot: int, rng: np.random.Generator) -> np.ndarray:
    """(n_boot, ceil(T / b)) random block starts in [0, T - b]: a replicate is the
    blocks [s, s + b) glued together, the last one cut to T frames in all."""
    n_blocks = int(math.ceil(n_frames / b))
    return rng.integers(0, n_frames - b + 1, size=(n_boot, n_blocks))


def block_sums(x: np.ndarray, starts: np.ndarray, b: int, chunk: int = 16) -> np.ndarray:
    """(n_boot, F) sums of x (T, F) over each replicate's frames, from cumulative sums:
    a block costs one difference, so a replicate costs T / b row additions instead of
    T (the reference BLAS of the platform makes the equivalent counts @ x product slow)."""
    T = x.shape[0]
    C = np.concatenate([np.zeros((1,) + x.shape[1:]), np.cumsum(x, axis=0)])
    n_full = T // b
    rem = T - n_full * b
    out = np.empty((len(starts),) + x.shape[1:])
    for i in range(0, len(starts), chunk):
        st = starts[i:i + chunk]
        full = st[:, :n_full]
        acc = (C[full + b] - C[full]).sum(axis=1)
        if rem:
            last = st[:, n_full]
            acc += C[last + rem] - C[last]
        out[i:i + chunk] = acc
    return out


def _moments(ref, s1, s2u, n, p, shape):
    """n: frames per replicate (B,), or per replicate and series (B, K) under a mask."""
    iu, ju = np.triu_indices(p)
    B = len(s1)
    n = np.asarray(n, dtype=float).reshape(B, -1, 1)
    m = s1.reshape(B, -1, p) / n
    covu = (s2u.reshape(B, -1, len(iu)) - n * m[:, :, iu] * m[:, :, ju]) / (n - 1)
    cov = np.empty((B, m.shape[1], p, p))
    cov[:, :, iu, ju] = covu
    cov[:, :, ju, iu] = covu
    return ref + m.reshape((B,) + shape + (p,)), cov.reshape((B,) + shape + (p, p))


def _centred(q, mask=None):
    """q's reference mean, centred values and their distinct products, flattened per frame.
    mask (T, ...) of q.shape[:-1]: frames to leave out of each series (False), which then
    contribute nothing; the reference is the mean over the frames kept."""
    q = np.asarray(q, dtype=float)
    T, p = q.shape[0], q.shape[-1]
    if mask is None:
        ref = q.mean(axis=0)
        d = (q - ref).reshape(T, -1, p)
    else:
        w = np.asarray(mask, dtype=float)[..., None]
        ref = (w * q).sum(axis=0) / np.maximum(w.sum(axis=0), 1.0)
        d = (w * (q - ref)).reshape(T, -1, p)
    iu, ju = np.triu_indices(p)
    return ref, d.reshape(T, -1), (d[:, :, iu] * d[:, :, ju]).reshape(T, -1), p, q.shape[1:-1]


def replicate_moments(q: np.ndarray, starts: np.ndarray, b: int, mask=None):
    """Means (n_boot, ..., p) and covariances (n_boot, ..., p, p) of the moving-block
    replicates of q (T, ..., p). Only the p (p + 1) / 2 distinct products are summed.
    mask (T, ...): per series, the frames it keeps (a replicate's moments are over the kept
    frames among its blocks)."""
    ref, d, outer, p, shape = _centred(q, mask)
    if mask is None:
        n = np.full(len(starts), float(q.shape[0]))
    else:
        n = block_sums(np.asarray(mask, dtype=float).reshape(q.shape[0], -1), starts, b)
    return _moments(ref, block_sums(d, starts, b), block_sums(outer, starts, b), n, p, shape)


def weighted_moments(q: np.ndarray, W: np.ndarray, mask=None):
    """Means and covariances of q (T, ..., p) under a few frame weightings W (n_w, T)
    (counts; normalisation sum(w) - 1): halves, prefixes. mask as replicate_moments."""
    ref, d, outer, p, shape = _centred(q, mask)
    n = W.sum(axis=1) if mask is None else W @ np.asarray(mask, dtype=float).reshape(q.shape[0], -1)
    return _moments(ref, W @ d, W @ outer, n, p, shape)


def spread(samples: np.ndarray, axis: int = 0) -> np.ndarray:
    """Bootstrap standard error as half the central 68.3 % interval of the replicates:
    the standard deviation for a normal distribution, but not blown up by the rare
    replicate whose few distinct frames make a covariance nearly singular. A replicate
    that has no value (NaN: too few frames kept under a mask) is left out."""
    samples = np.asarray(samples, dtype=float)
    if np.isnan(samples).any():
        lo, hi = np.nanpercentile(samples, [15.865, 84.135], axis=axis)
        return 0.5 * (hi - lo)
    lo, hi = np.percentile(samples, [15.865, 84.135], axis=axis)
    return 0.5 * (hi - lo)


def circular_block_indices(n: int, b: int, rng: np.random.Generator) -> np.ndarray:
    """Frame indices (n,) of one circular moving-block replicate: ceil(n / b) random starts
    in [0, n), each followed by b consecutive frames wrapping around the end."""
    starts = rng.integers(0, n, size=int(np.ceil(n / b)))
    return (starts[:, None] + np.arange(b)[None, :]).ravel()[:n] % n
