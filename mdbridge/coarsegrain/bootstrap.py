"""Moving-block bootstrap of frame-correlated data (Kuensch 1989 Ann Stat 17:1217).

Frames are drawn in blocks of b consecutive frames (b from the autocorrelation
time, `block_length`), so each replicate keeps the correlation inside a block and
the scatter of a statistic over replicates estimates its scatter over independent
trajectories. The same blocks serve every step and parameter, so correlations
between steps survive (needed by the m-step and sequence-averaged quantities).
b = 1 is the ordinary bootstrap that treats frames as independent: the control the
tests show to be wrong for correlated frames.

A replicate is a list of block starts; its sums of q and of the distinct products
q_i q_j come from cumulative sums (one difference per block), so no frame is copied.
"""
from __future__ import annotations

import math

import numpy as np

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
    iu, ju = np.triu_indices(p)
    B = len(s1)
    m = s1.reshape(B, -1, p) / n[:, None, None]
    covu = (s2u.reshape(B, -1, len(iu)) - n[:, None, None] * m[:, :, iu] * m[:, :, ju]) / (n - 1)[:, None, None]
    cov = np.empty((B, m.shape[1], p, p))
    cov[:, :, iu, ju] = covu
    cov[:, :, ju, iu] = covu
    return ref + m.reshape((B,) + shape + (p,)), cov.reshape((B,) + shape + (p, p))


def _centred(q):
    q = np.asarray(q, dtype=float)
    T, p = q.shape[0], q.shape[-1]
    ref = q.mean(axis=0)
    d = (q - ref).reshape(T, -1, p)
    iu, ju = np.triu_indices(p)
    return ref, d.reshape(T, -1), (d[:, :, iu] * d[:, :, ju]).reshape(T, -1), p, q.shape[1:-1]


def replicate_moments(q: np.ndarray, starts: np.ndarray, b: int):
    """Means (n_boot, ..., p) and covariances (n_boot, ..., p, p) of the moving-block
    replicates of q (T, ..., p). Only the p (p + 1) / 2 distinct products are summed."""
    ref, d, outer, p, shape = _centred(q)
    n = np.full(len(starts), float(q.shape[0]))
    return _moments(ref, block_sums(d, starts, b), block_sums(outer, starts, b), n, p, shape)


def weighted_moments(q: np.ndarray, W: np.ndarray):
    """Means and covariances of q (T, ..., p) under a few frame weightings W (n_w, T)
    (counts; normalisation sum(w) - 1): halves, prefixes."""
    ref, d, outer, p, shape = _centred(q)
    return _moments(ref, W @ d, W @ outer, W.sum(axis=1), p, shape)


def spread(samples: np.ndarray, axis: int = 0) -> np.ndarray:
    """Bootstrap standard error as half the central 68.3 % interval of the replicates:
    the standard deviation for a normal distribution, but not blown up by the rare
    replicate whose few distinct frames make a covariance nearly singular."""
    lo, hi = np.percentile(samples, [15.865, 84.135], axis=axis)
    return 0.5 * (hi - lo)
