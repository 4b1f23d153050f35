"""A rod closed into a ring at a chosen linking number: the t = 0 state of a minicircle.

The relaxed rod (the grid material's intrinsic strains x0 = (Gamma0, Omega0)) turns
Lk0 = (1/2 pi) int Omega0_3 ds times about its axis over its length L: N / (bp per turn)
for DNA (`relaxed_turns`). A closed ring must carry an integer linking number Lk, so it
is twisted by Delta Lk = Lk - Lk0 in all.

The ring (`ring_state`) starts as the planar circle of Lk turns: the directors are
R(s) = Rc(s) Rz(phi(s)), Rc a turn about lab e1 by 2 pi s / L (d3 along the circle in the
lab's y-z plane) and Rz(phi) the twist about d3, phi' = Omega0_3 + 2 pi Delta Lk / L. Then
R^T R' = Rz^T [kappa e1]x Rz + [phi' e3]x, so

    Omega = Omega0 + (kappa cos phi, -kappa sin phi, 2 pi Delta Lk / L),  kappa = 2 pi / L,
    Gamma = Gamma0,

exactly closed (holonomy = identity) for a uniform straight material (the intrinsic strains
of the paper's DNA) and Lk = Tw = Lk0 + Delta Lk, Wr = 0. A sequence-dependent material
(intrinsic bends, shift and slide) does not close this way: the holonomy (frame and position
at L relative to s = 0, the composition of closed_rest.py, holonomy_jacobian) is driven to
the identity by Newton steps of least elastic energy, dx = -W^-1 C^T (C W^-1 C^T)^-1 c with
W = K h per point (`close_ring`), which change x by the least strain energy that closes it.
The ring is a closed, pre-stressed state, not an equilibrium: the scene relaxes it
(docs/topology.md, "A supercoiled minicircle").
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from dna_models.errors import InputError
from mdbridge.geometry.rotations import rotation_log
from mdbridge.geometry.topology import ribbon_topology

from .closed_rest import holonomy_jacobian
from .composition import cell_matrix, compose_cells, compose_stretches

REFINE = 16     # midpoint cells per grid cell of the holonomy (closed_rest.py; error O((h/16)^2))


def relaxed_turns(g, L) -> float:
    """Lk0: the turns of the relaxed rod about its axis, (1/2 pi) int Omega0_3 ds (the mean of
    the grid values times L: exact for the trigonometric interpolant)."""
    return float(np.mean(g["Omega0"][:, 2]) * L / (2.0 * np.pi))


def twist_angle(Omega3, L):
    """phi(s_j) = int_0^s_j Omega3 ds of the trigonometric interpolant of the grid values (N,)."""
    N = len(Omega3)
    k = np.fft.fftfreq(N, d=1.0 / N)
    F = np.fft.fft(Omega3 - Omega3.mean())
    F[0] = 0.0
    if N % 2 == 0:
        F[N // 2] = 0.0     # the Nyquist cosine integrates to a sine that vanishes on the grid
    k[0] = 1.0
    a = np.real(np.fft.ifft(F / (2j * np.pi * k / L)))
    s = np.arange(N) * L / N
    return Omega3.mean() * s + a - a[0]


def planar_ring(g, L, Lk: int):
    """x (N, 6) = (Gamma, Omega) of the planar circle of Lk turns (module docstring)."""
    Omega0 = np.asarray(g["Omega0"], float)
    Omega3 = Omega0[:, 2] + 2.0 * np.pi * (Lk - relaxed_turns(g, L)) / L
    phi = twist_angle(Omega3, L)
    kappa = 2.0 * np.pi / L
    Omega = np.stack([Omega0[:, 0] + kappa * np.cos(phi), Omega0[:, 1] - kappa * np.sin(phi), Omega3], axis=1)
    return np.concatenate([np.asarray(g["Gamma0"], float), Omega], axis=1)


def ring_defect(x, L, refine=REFINE, B=None, jacobian=True):
    """(6,): rotation vector of the holonomy (rad) and its translation (rod units), and the
    Jacobian (6, 6N) of both with respect to x (N, 6) (None unless asked for). B: the cell
    matrix (composition.cell_matrix), if the caller keeps it."""
    from mdbridge.geometry.se3 import inverse_left_jacobian
    N = x.shape[0]
    B = cell_matrix(N, L, refine) if B is None else B
    if not jacobian:
        RT, dT = compose_cells(B @ x, L / (refine * N))
        return np.concatenate([rotation_log(RT), dT]), None
    RT, dT, dzeta = holonomy_jacobian(x, L, refine, B)
    phi = rotation_log(RT)
    C = np.concatenate([inverse_left_jacobian(-phi) @ dzeta[:3], RT @ dzeta[3:]])
    return np.concatenate([phi, dT]), C


def close_ring(x, g, L, refine=REFINE, tol=1e-12, maxiter=30):
    """x (N, 6) moved to a closed ring (holonomy = identity to tol) by least-energy Newton
    steps (module docstring), each halved until the defect falls. Returns (x, iterations)."""
    N = x.shape[0]
    h = L / N
    B = cell_matrix(N, L, refine)
    Winv = np.linalg.inv(np.asarray(g["K"], float) * h)           # (N, 6, 6)
    scale = np.array([L / (2 * np.pi)] * 3 + [1.0] * 3)           # rotation counted as arc length

    def size(c):
        return float(np.linalg.norm(c * scale))

    x = np.asarray(x, float).copy()
    c, _ = ring_defect(x, L, refine, B, jacobian=False)
    for it in range(maxiter + 1):
        if size(c) < tol * L:
            return x, it
        if it == maxiter:
            break
        _, C = ring_defect(x, L, refine, B)
        Cb = C.reshape(6, N, 6)
        WCt = np.einsum("jab,kjb->jak", Winv, Cb).reshape(6 * N, 6)   # W^-1 C^T
        dx = -(WCt @ np.linalg.solve(C @ WCt, c)).reshape(N, 6)
        for lam in 0.5 ** np.arange(12):
            cn, _ = ring_defect(x + lam * dx, L, refine, B, jacobian=False)
            if size(cn) < size(c):
                break
        else:
            break
        x, c = x + lam * dx, cn
    raise InputError(f"minicircle: the ring did not close (holonomy defect {size(c):.3g} l after "
                     f"{maxiter} Newton steps); the intrinsic shape is too far from a circle")


def grid_frames(x, L, refine=REFINE):
    """Directors R (N, 3, 3) and centreline r (N, 3) at the grid points of the strains x,
    frame (identity, 0) at s = 0, composed as the holonomy is."""
    N = x.shape[0]
    xm = cell_matrix(N, L, refine) @ x
    Rs, ds = compose_stretches(xm, L / (refine * N), refine)
    R, r = np.empty((N, 3, 3)), np.empty((N, 3))
    R[0], r[0] = np.eye(3), 0.0
    for j in range(1, N):
        R[j] = R[j - 1] @ Rs[j - 1]
        r[j] = r[j - 1] + R[j - 1] @ ds[j - 1]
    return R, r


@dataclass
class RingState:
    Gamma: np.ndarray           # (N, 3)
    Omega: np.ndarray           # (N, 3)
    Lk0: float                  # turns of the relaxed rod
    Lk: int                     # linking number of the ring
    Tw: float                   # of the t = 0 ring (ribbon d1 about the tangent)
    Wr: float
    closure_defect: float       # |holonomy - identity| (rod units, rotation as arc length)
    newton_steps: int
    energy: float               # elastic energy of the ring, sum h e.K.e / 2

    @property
    def delta_Lk(self) -> float:
        return self.Lk - self.Lk0


def ring_state(g, L, Lk: int, refine=REFINE) -> RingState:
    """The closed ring of linking number Lk of the grid material g (steps_to_rod.grid_material).
    Its Lk is measured on the composed frames (mdbridge.geometry.topology) and must be Lk."""
    N = g["K"].shape[0]
    x, steps = close_ring(planar_ring(g, L, Lk), g, L, refine)
    c, _ = ring_defect(x, L, refine, jacobian=False)
    R, r = grid_frames(x, L, refine)
    top = ribbon_topology(r, R[:, :, 0], None, 1)
    if top["Lk"] != Lk:
        raise InputError(f"minicircle: the closed ring links {top['Lk']} times, not the {Lk} asked for "
                         "(the closure moved it too far)")
    e = x - np.concatenate([g["Gamma0"], g["Omega0"]], axis=1)
    return RingState(Gamma=x[:, :3].copy(), Omega=x[:, 3:].copy(), Lk0=relaxed_turns(g, L), Lk=int(top["Lk"]),
                     Tw=float(top["Tw"]), Wr=float(top["Wr"]),
                     closure_defect=float(np.linalg.norm(c * np.array([L / (2 * np.pi)] * 3 + [1.0] * 3))),
                     newton_steps=steps, energy=float(0.5 * (L / N) * np.einsum("ja,jab,jb->", e, g["K"], e)))
