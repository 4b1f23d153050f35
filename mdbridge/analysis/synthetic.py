"""Synthetic base-pair trajectories with a known axis and a known displacement field.

Used by the tests (and useful to check the analysis on a new machine): a closed,
periodic duplex of n base pairs along e_axis = Y, rise `rise_A`, uniform twist
2 pi turns / n, whose axis point of base pair i at time t is

    a_i(t) = x_i e_axis + u_in(x_i, t) e_in + u_out(x_i, t) e_out,   x_i = i rise,

with the base-pair origin offset from the axis by `offset_A` along the base pair's own
x axis (the 3DNA x-displacement: a helix around the axis). Optionally the origins are
wrapped into an orthorhombic box, as in MD of a ligated duplex.
"""
from __future__ import annotations

import numpy as np

from dna_models.bdna import RISE_A
from mdbridge.geometry.trajectory import BasePairTrajectory

E_AXIS = np.array([0.0, 1.0, 0.0])
E_IN = np.array([0.0, 0.0, 1.0])
E_OUT = np.cross(E_AXIS, E_IN)  # = +X


def helix_trajectory(times_ps, u_in, u_out=None, n=158, turns=15, rise_A=RISE_A, offset_A=0.0,
                     noise_A=0.0, box_A=None, seed=0, e_in=E_IN):
    """times_ps (T,); u_in, u_out: callables f(x_A (n,), t_ps) -> (n,) [A].

    Returns a BasePairTrajectory (through `from_periodic_box` if box_A is given)
    and the exact axis points (T, n, 3)."""
    rng = np.random.default_rng(seed)
    times_ps = np.asarray(times_ps, float)
    e_in = np.asarray(e_in, float) / np.linalg.norm(e_in)
    e_out = np.cross(E_AXIS, e_in)
    x = np.arange(n) * rise_A
    L = n * rise_A
    phi = 2 * np.pi * turns * np.arange(n) / n
    T = len(times_ps)
    axis = np.empty((T, n, 3))
    R = np.empty((T, n, 3, 3))
    h = 1e-4 * rise_A
    for t, tt in enumerate(times_ps):
        uo = (lambda xx: u_out(xx, tt)) if u_out is not None else (lambda xx: 0.0 * xx)
        ui = lambda xx: u_in(xx, tt)  # noqa: E731
        axis[t] = x[:, None] * E_AXIS + ui(x)[:, None] * e_in + uo(x)[:, None] * e_out
        tangent = (E_AXIS + ((ui(x + h) - ui(x - h)) / (2 * h))[:, None] * e_in
                   + ((uo(x + h) - uo(x - h)) / (2 * h))[:, None] * e_out)
        z = tangent / np.linalg.norm(tangent, axis=1, keepdims=True)
        x0 = np.cos(phi)[:, None] * E_IN + np.sin(phi)[:, None] * E_OUT
        xa = x0 - np.sum(x0 * z, axis=1, keepdims=True) * z
        xa /= np.linalg.norm(xa, axis=1, keepdims=True)
        ya = np.cross(z, xa)
        R[t] = np.stack([xa, ya, z], axis=2)
    origins = axis + offset_A * R[..., 0] + noise_A * rng.standard_normal(axis.shape)
    P = np.tile(L * E_AXIS, (T, 1))
    if box_A is None:
        return BasePairTrajectory(times_ps, origins, R, P, source="synthetic"), axis
    box = np.array([box_A, L, box_A], float)
    shift = rng.uniform(-1, 1, 3) * box  # an arbitrary origin of the box
    wrapped = np.mod(origins + shift, box)
    traj = BasePairTrajectory.from_periodic_box(times_ps, wrapped, R, box, source="synthetic-box")
    return traj, axis
