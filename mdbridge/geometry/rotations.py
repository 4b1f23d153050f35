"""Small rotation helpers, vectorised over leading axes (..., 3, 3).

Conventions: a frame R holds its axes as COLUMNS (x = R[..., :, 0], ...),
expressed in the laboratory frame; rotations are active (R v rotates v).
"""
from __future__ import annotations

import numpy as np


def axis_angle_matrix(axis, angle):
    """Rotation by `angle` (rad) about unit `axis` (Rodrigues; tech-details Eq 1)."""
    axis = np.asarray(axis, dtype=float)
    angle = np.asarray(angle, dtype=float)
    ux, uy, uz = axis[..., 0], axis[..., 1], axis[..., 2]
    c, s = np.cos(angle), np.sin(angle)
    t = 1.0 - c
    R = np.empty(np.broadcast(ux, angle).shape + (3, 3))
    R[..., 0, 0] = c + t * ux * ux
    R[..., 0, 1] = t * ux * uy - s * uz
    R[..., 0, 2] = t * ux * uz + s * uy
    R[..., 1, 0] = t * ux * uy + s * uz
    R[..., 1, 1] = c + t * uy * uy
    R[..., 1, 2] = t * uy * uz - s * ux
    R[..., 2, 0] = t * ux * uz - s * uy
    R[..., 2, 1] = t * uy * uz + s * ux
    R[..., 2, 2] = c + t * uz * uz
    return R


def rot_z(angle):
    angle = np.asarray(angle, dtype=float)
    c, s = np.cos(angle), np.sin(angle)
    R = np.zeros(angle.shape + (3, 3))
    R[..., 0, 0] = c
    R[..., 0, 1] = -s
    R[..., 1, 0] = s
    R[..., 1, 1] = c
    R[..., 2, 2] = 1.0
    return R


def rot_y(angle):
    angle = np.asarray(angle, dtype=float)
    c, s = np.cos(angle), np.sin(angle)
    R = np.zeros(angle.shape + (3, 3))
    R[..., 0, 0] = c
    R[..., 0, 2] = s
    R[..., 2, 0] = -s
    R[..., 2, 2] = c
    R[..., 1, 1] = 1.0
    return R


def transpose(R):
    return np.swapaxes(R, -1, -2)


def rotation_log(R):
    """Rotation vector theta*u of R (|theta| <= pi), accurate for small angles.

    Uses the antisymmetric part for the axis*sin and atan2 for the angle, so it
    keeps full relative precision near theta = 0 (where arccos would lose
    half the digits)."""
    R = np.asarray(R, dtype=float)
    w = np.stack([R[..., 2, 1] - R[..., 1, 2],
                  R[..., 0, 2] - R[..., 2, 0],
                  R[..., 1, 0] - R[..., 0, 1]], axis=-1)  # = 2 sin(theta) u
    s2 = np.linalg.norm(w, axis=-1)                      # 2 sin(theta)
    tr = R[..., 0, 0] + R[..., 1, 1] + R[..., 2, 2]      # 1 + 2 cos(theta)
    theta = np.arctan2(s2, tr - 1.0)
    with np.errstate(invalid="ignore", divide="ignore"):
        factor = np.where(s2 > 1e-300, theta / np.where(s2 > 1e-300, s2, 1.0), 0.5)
    v = w * factor[..., None]
    # Near theta = pi the antisymmetric part vanishes: take the axis from the
    # symmetric part instead (rare for DNA steps, but keep it right).
    near_pi = theta > np.pi - 1e-6
    if np.any(near_pi):
        Rp = R[near_pi]
        B = (Rp + transpose(Rp)) / 2.0 - np.eye(3) * ((np.trace(Rp, axis1=-2, axis2=-1) - 1.0) / 2.0)[:, None, None]
        # B = (1 - cos) u u^T; take the largest column
        idx = np.argmax(np.diagonal(B, axis1=-2, axis2=-1), axis=-1)
        u = B[np.arange(len(Rp)), :, idx]
        u /= np.linalg.norm(u, axis=-1, keepdims=True)
        sign = np.sign(np.einsum("...i,...i->...", u, w[near_pi]))
        sign[sign == 0] = 1.0
        v[near_pi] = u * (sign * theta[near_pi])[:, None]
    return v


def rotation_exp(v):
    """Rotation matrix exp([v]x) of rotation vector v."""
    v = np.asarray(v, dtype=float)
    theta = np.linalg.norm(v, axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        u = np.where(theta[..., None] > 0, v / np.where(theta > 0, theta, 1.0)[..., None], 0.0)
    u = np.where(theta[..., None] > 0, u, np.array([0.0, 0.0, 1.0]))
    return axis_angle_matrix(u, theta)
