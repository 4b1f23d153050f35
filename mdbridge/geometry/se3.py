"""SE(3) helpers: the rigid step between two frames as the exponential of one
constant-strain rod piece (docs/contracts.md, "Discrete <-> continuous";
mdbridge/rod/frames.py derives the formulas).

    R_rel = exp([v]x),   d_rel = J(v) w,
    J(v) = I + (1 - cos t)/t^2 [v]x + (t - sin t)/t^3 [v]x^2,  t = |v|  (SO(3) left Jacobian).

Vectorised over leading axes, like mdbridge.geometry.rotations.
"""
from __future__ import annotations

import numpy as np

from .rotations import rotation_exp, rotation_log


def step_log(R_rel, d_rel):
    """SE(3) logarithm of one rigid step: (v, w) with R_rel = exp([v]x) and
    d_rel = J(v) w, i.e. the constant strains of a rod piece of length ds that
    makes this step are Omega = v / ds, Gamma = w / ds (d_rel in frame 1)."""
    v = rotation_log(R_rel)
    return v, np.einsum("...ij,...j->...i", inverse_left_jacobian(v), np.asarray(d_rel, dtype=float))


def step_exp(v, w):
    """Inverse of step_log: (R_rel, d_rel) = (exp([v]x), J(v) w)."""
    v = np.asarray(v, dtype=float)
    return rotation_exp(v), np.einsum("...ij,...j->...i", _left_jacobian(v), np.asarray(w, dtype=float))


def skew(v):
    """[v]x (..., 3, 3): skew(v) @ u = v x u."""
    K = np.zeros(v.shape[:-1] + (3, 3))
    K[..., 0, 1], K[..., 0, 2], K[..., 1, 2] = -v[..., 2], v[..., 1], -v[..., 0]
    K[..., 1, 0], K[..., 2, 0], K[..., 2, 1] = v[..., 2], -v[..., 1], v[..., 0]
    return K


def _left_jacobian(v):
    """J(v) = I + (1 - cos t)/t^2 [v]x + (t - sin t)/t^3 [v]x^2, t = |v| (series below 1e-4)."""
    t = np.linalg.norm(v, axis=-1)
    small = t < 1e-4
    ts = np.where(small, 1.0, t)
    a = np.where(small, 0.5 - t * t / 24.0, (1.0 - np.cos(ts)) / ts**2)
    b = np.where(small, 1.0 / 6.0 - t * t / 120.0, (ts - np.sin(ts)) / ts**3)
    K = skew(v)
    return np.eye(3) + a[..., None, None] * K + b[..., None, None] * (K @ K)


def inverse_left_jacobian(v):
    """J(v)^-1 = I - [v]x / 2 + (1/t^2 - (1 + cos t) / (2 t sin t)) [v]x^2, t = |v|."""
    t = np.linalg.norm(v, axis=-1)
    small = t < 1e-4
    ts = np.where(small, 1.0, t)
    coef = np.where(small, 1.0 / 12.0 + t * t / 720.0,
                    1.0 / ts**2 - (1.0 + np.cos(ts)) / (2.0 * ts * np.sin(ts)))
    K = skew(v)
    return np.eye(3) - 0.5 * K + coef[..., None, None] * (K @ K)
