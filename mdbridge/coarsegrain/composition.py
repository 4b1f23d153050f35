"""m-step composition: m consecutive rigid-body steps as one step.

Each step q = (shift, slide, rise, tilt, roll, twist) is the rigid motion from base
pair i to i + 1 (mdbridge.geometry.step_transform, 3DNA's definitions), i.e. the 4x4
homogeneous transform G_i = [[R_rel, o_rel], [0, 1]]. The motion from base pair i to
i + m is the product G_i G_{i+1} ... G_{i+m-1}, and its six parameters, taken by the
same CEHS analysis (mdbridge.geometry.step_parameters), are the m-step's parameters:
the composition SerraNA (Velasco-Berrelleza et al. 2020 NAR 48:e124) and Noy &
Golestanian (2012 PRL 109:228101) use to reach the continuum limit. For frames that
come from a structure this equals the step parameters between base pairs i and i + m
directly (tested); composing steps also serves ensembles given as step parameters.
"""
from __future__ import annotations

import numpy as np

from dna_models.errors import InputError
from mdbridge.geometry.steps import step_parameters, step_transform


def step_matrices(q: np.ndarray) -> np.ndarray:
    """4x4 transforms (..., 4, 4) of steps q (..., 6)."""
    R, o, _ = step_transform(q)
    G = np.zeros(q.shape[:-1] + (4, 4))
    G[..., :3, :3] = R
    G[..., :3, 3] = o
    G[..., 3, 3] = 1.0
    return G


def parameters_of(G: np.ndarray) -> np.ndarray:
    """Step parameters (..., 6) of the rigid motions G (..., 4, 4)."""
    eye = np.broadcast_to(np.eye(3), G.shape[:-2] + (3, 3))
    return step_parameters(eye, np.zeros(G.shape[:-2] + (3,)), G[..., :3, :3], G[..., :3, 3])


def windows(n_steps: int, m: int, closed: bool) -> np.ndarray:
    """First step of every window of m consecutive steps (wrapping when closed)."""
    if m < 1 or (not closed and m > n_steps) or (closed and m >= n_steps):
        raise InputError(f"coarse-graining length m = {m}: allowed 1..{n_steps - 1 if closed else n_steps} "
                         f"for {n_steps} steps")
    return np.arange(n_steps if closed else n_steps - m + 1)


def compose(q: np.ndarray, m_values, closed: bool = False) -> dict:
    """{m: (..., n_windows(m), 6) parameters of every m-step window} for steps q
    (..., n_steps, 6). Window j of length m joins base pairs j and j + m. The
    products are accumulated one step at a time, so all m up to max(m_values)
    cost one 4x4 product per window and step."""
    q = np.asarray(q, dtype=float)
    n = q.shape[-2]
    m_values = sorted(set(int(m) for m in m_values))
    for m in m_values:
        windows(n, m, closed)
    G1 = step_matrices(q)
    start = np.arange(n)
    G = G1.copy()
    out = {}
    for m in range(1, m_values[-1] + 1):
        if m > 1:
            # windows running past the last step (open duplex) are dropped by `windows`
            nxt = np.minimum((start + m - 1) % n if closed else start + m - 1, n - 1)
            G = G @ G1[..., nxt, :, :]
        if m in m_values:
            w = windows(n, m, closed)
            out[m] = parameters_of(G[..., w, :, :])
    return out
