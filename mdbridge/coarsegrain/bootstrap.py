"""Moving-block bootstrap of frame-correlated data (Kuensch 1989 Ann Stat 17:1217).

Frames are drawn in blocks of b consecutive frames (b from the autocorrelation
time, `block_length`), so each replicate keeps the correlation inside a block and
the scatter of a statistic over replicates estimates its scatter over independent
trajectories. The same blocks serve every step and parameter, so correlations
between steps survive (needed by the m-step and sequence-averaged quantities).
b = 1 is the ordinary bootstrap that treats frames as independent: the control the
tests show to be wrong for correlated frames.

A replicate is stored as frame counts w_t (how often frame t was drawn); means and
covariances of all replicates are then two matrix products with the per-frame
vectors and their outer products (BLAS), instead of copying frames.
"""
from __future__ import annotations

import math

import numpy as np

BLOCK_TAUS = 6.0   # b = 6 tau_int. The moving-block variance is low by ~ sum_k k rho(k) / (b tau_int);
                   # measured on AR(1) series with phi = 0.9 (test_coarsegrain_synthetic.py), the
                   # scatter over realisations / stated error is 1.18 at b = 4 tau, 1.14 at 6 tau,
                   # 1.12 at 8 tau, so 6 tau, with T / b >= 8 blocks at the minimum length


def block_length(tau_max: float, n_frames: int) -> int:
    """ceil(BLOCK_TAUS tau_max) frames, at least 1 and at most n_frames // 8."""
    b = int(math.ceil(BLOCK_TAUS * float(tau_max)))
    return max(1, min(b, max(1, n_frames // 8)))


def block_weights(n_frames: int, b: int, n_boot: int, rng: np.random.Generator) -> np.ndarray:
    """(n_boot, T) frame counts of moving-block replicates of T frames (blocks of b
    frames with random starts in [0, T - b], the last block cut to length)."""
    n_blocks = int(math.ceil(n_frames / b))
    starts = rng.integers(0, n_frames - b + 1, size=(n_boot, n_blocks))
    idx = (starts[:, :, None] + np.arange(b)[None, None, :]).reshape(n_boot, -1)[:, :n_frames]
    W = np.zeros((n_boot, n_frames))
    rows = np.repeat(np.arange(n_boot), n_frames)
    np.add.at(W, (rows, idx.ravel()), 1.0)
    return W


def weighted_moments(q: np.ndarray, W: np.ndarray):
    """Means (n_w, ..., p) and covariances (n_w, ..., p, p) of q (T, ..., p) under
    frame weights W (n_w, T) (counts; normalisation sum(w) - 1). Only the p (p + 1) / 2
    distinct products enter the matrix product."""
    q = np.asarray(q, dtype=float)
    T, p = q.shape[0], q.shape[-1]
    shape = q.shape[1:-1]
    ref = q.mean(axis=0)
    d = (q - ref).reshape(T, -1, p)
    iu, ju = np.triu_indices(p)
    n = W.sum(axis=1)
    m = (W @ d.reshape(T, -1)).reshape(len(W), -1, p) / n[:, None, None]
    s2u = (W @ (d[:, :, iu] * d[:, :, ju]).reshape(T, -1)).reshape(len(W), -1, len(iu))
    covu = (s2u - n[:, None, None] * m[:, :, iu] * m[:, :, ju]) / (n - 1)[:, None, None]
    cov = np.empty((len(W), d.shape[1], p, p))
    cov[:, :, iu, ju] = covu
    cov[:, :, ju, iu] = covu
    return (ref + m.reshape((len(W),) + shape + (p,)),
            cov.reshape((len(W),) + shape + (p, p)))


def spread(samples: np.ndarray, axis: int = 0) -> np.ndarray:
    """Bootstrap standard error as half the central 68.3 % interval of the replicates:
    the standard deviation for a normal distribution, but not blown up by the rare
    replicate whose few distinct frames make a covariance nearly singular."""
    lo, hi = np.percentile(samples, [15.865, 84.135], axis=axis)
    return 0.5 * (hi - lo)
