"""The closed, pre-stressed rest state of a sequence-dependent periodic rod.

A sequence-dependent intrinsic shape (Gamma0(s), Omega0(s)) composed over one
period is a screw motion, not the pure translation by the box vector that a
ligated DNA in a periodic box needs. The rest state is the static equilibrium
of the solver's own semi-discrete balance laws under the closure constraint:
the frame at L equals the frame at 0 and the end-to-end vector has the box
length b (its direction, the helix axis, is free).

The balance laws are never written here: the statics residual is rodcore's
RHS at zero velocity (`SolverStatics`: rho d gamma/dt = D n + Omega x n,
I d omega/dt = D m + Omega x m + Gamma x n with D the solver's spectral or FD4
operator), through `rodcore.Simulation(scene).rhs`. At zero velocity that
residual is a quadratic function of the strains x = (Gamma, Omega) (n, m are
linear in x, the cross products bilinear), so central differences with UNIT
steps give its Jacobian exactly (no truncation error; round-off only).

The closure is evaluated on the trigonometric interpolant of the grid strains
(the field the spectral operator sees), composed as the product of SE(3)
exponentials of its values at the midpoints of `refine` sub-cells per grid
cell (mdbridge/rod/material/composition.py; error O((ds/refine)^2)). Its
Jacobian is analytic (`closure_jacobian`): the derivative of the product of
exponentials through SE(3) adjoints of the suffix products and the right
Jacobian of each cell's exponential.

Near a closed equilibrium the semi-discrete statics have a two-parameter
family of near-solutions (the continuum's periodic equilibria: every wrench
invariant under the monodromy screw, parametrised by its angle and pitch),
which the discretisation breaks only weakly, so exact statics and exact
closure cannot both hold at a finite N (docs/dna-rod.md, "The closed,
pre-stressed rest state"). Two modes:

* rest = "closed" (the `dnarod dna-rod` default, the MD build's): Gauss-Newton
  on min |statics residual|^2 subject to the closure as an exact equality
  constraint (null-space method), from the continuum's closed energy minimiser
  (below): closed to round-off, the statics to the discretisation error.
* rest = "equilibrium": then Newton (Levenberg-Marquardt safeguard) on the
  statics alone, from the closed state: an equilibrium of the solver's
  equations to round-off (it stays at rest in rodsim), closed only to the
  discretisation error.

The start, the continuum's closed minimiser, is found by multiple shooting
(`_shooting_minimiser`): its unknowns are the six numbers of the lab force N
and moment M (the closure's multipliers) and, per segment after the first,
its starting frame and position; the segments are matched at the joins. One
shot over the whole period (the single shooting, K = 1) fails for long rods:
under the tension T the closure causes, the linearised statics are hyperbolic
(a bent rod under tension: perturbations grow like exp(s sqrt(T / B)), B the
bend stiffness): at 158 bp (tension 0.03 C, B ~ 1.4 C l^2, L = 107 l) the
estimate is exp(L sqrt(T / B)) ~ 1e7 for the whole period, and Levenberg-
Marquardt on the six numbers did not converge (docs/dna-rod.md). Segments of at
most SEGMENT_LENGTH = 16 l (8 nm, 24 bp; growth ~10 at that tension) keep
each shot well conditioned, all segments are shot together (a batch), and
the 6 K unknowns are few enough for a dense Jacobian. Rods up to 16 l (21 bp)
are one segment, i.e. the single shooting. The alternatives were not taken:
the constrained Gauss-Newton started from the intrinsic shape converges at
158 bp but not at 40 bp (docs/dna-rod.md), and a homotopy in the intrinsic
shape's deviation from uniform would still need the long single shot at
every step.

The residual stress: with N = R n and the closure direction b_hat, the tension
is n . R^T b_hat and the torque about the axis m . R^T b_hat (both constant
along s at an exact equilibrium with N || b_hat).
"""
from __future__ import annotations

import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from dna_models.errors import InputError
from dna_models.units import Units
from mdbridge.geometry.rotations import rotation_exp, rotation_log
from mdbridge.geometry.se3 import inverse_left_jacobian, skew, step_exp
from mdbridge.rod.frames import trig_interpolate

from .composition import cell_matrix as _cell_matrix, compose_cells as _monodromy_cells

MODES = ("closed", "equilibrium")
# longest segment of the multiple shooting (rod units, l = 5 A: 8 nm, 24 bp; module docstring)
SEGMENT_LENGTH = 16.0


class SolverStatics:
    """The solver's statics residual and its exact Jacobian, from rodcore's RHS.

    One rodcore.Simulation of the grid material g (steps_to_rod.grid_material) on
    a rod of length L with the operator `space`; residual(x) for x (N, 6) =
    (Gamma, Omega) is (N, 6) = (rho d gamma/dt, I d omega/dt) at zero velocity."""

    def __init__(self, g, L, space="spectral"):
        import rodcore
        from .gridfile import write_grid_material
        self.N = int(g["K"].shape[0])
        self.rho = np.asarray(g["rho"], dtype=float)
        self.I = np.asarray(g["I"], dtype=float)
        scene = {"rod": {"length": float(L), "points": self.N},
                 "solver": {"space": space, "reduce": "off"},
                 "output": {"t_end": 1.0, "frames": 2, "fields": ["internal"]}}
        with tempfile.TemporaryDirectory(prefix="dnarod-rest-") as d:
            path = write_grid_material(Path(d) / "material.h5", g, source="closed_rest")
            scene["material"] = {"material_file": str(path)}
            self.sim = rodcore.Simulation(scene)          # reads the file now

    def residual(self, x):
        x = np.asarray(x, dtype=float).reshape(self.N, 6)
        y = np.concatenate([np.zeros((6, self.N)), x.T]).ravel()   # rows gamma, omega, Gamma, Omega
        f = np.asarray(self.sim.rhs(y)).reshape(12, self.N)
        return np.concatenate([self.rho[:, None] * f[0:3].T, np.einsum("jab,bj->ja", self.I, f[3:6])], axis=1)

    def jacobian(self, x):
        """(6N, 6N) d residual / d x, exact: the residual is quadratic in x, so
        (F(x + e_k) - F(x - e_k)) / 2 is column k with no truncation error."""
        x = np.asarray(x, dtype=float).ravel()
        J = np.empty((x.size, x.size))
        for k in range(x.size):
            xp, xm = x.copy(), x.copy()
            xp[k] += 1.0
            xm[k] -= 1.0
            J[:, k] = 0.5 * (self.residual(xp) - self.residual(xm)).ravel()
        return J


def monodromy(x, L, refine=16):
    """(R_total, d_total): frame at L relative to the frame at 0, of the trigonometric
    interpolant of the grid strains x (N, 6), by midpoint exponentials on refine*N cells."""
    N = x.shape[0]
    return _monodromy_cells(_cell_matrix(N, L, refine) @ x, L / (refine * N))


def closure_defect(x, L, box_length, refine=16):
    """(4,): rotation vector of R_total (rad) and |d_total| - box_length."""
    R, d = monodromy(x, L, refine)
    return np.concatenate([rotation_log(R), [np.linalg.norm(d) - box_length]])


def _ad(u):
    """SE(3) adjoint ad_u (..., 6, 6) of twists u = (rotation, translation)."""
    A = np.zeros(u.shape[:-1] + (6, 6))
    W, V = skew(u[..., :3]), skew(u[..., 3:])
    A[..., :3, :3] = W
    A[..., 3:, 3:] = W
    A[..., 3:, :3] = V
    return A


def _right_jacobian_se3(u, terms=14):
    """J_r(u) = sum_k (-ad_u)^k / (k + 1)!: exp(u + du) = exp(u) exp(J_r(u) du) + O(du^2).
    The series is for the small cell twists here (|u| < 0.2: 14 terms are exact to round-off)."""
    A = -_ad(u)
    term = np.broadcast_to(np.eye(6), A.shape).copy()
    J = term.copy()
    for k in range(1, terms):
        term = term @ A / (k + 1)
        J += term
    return J


def holonomy_jacobian(x, L, refine=16, B=None):
    """The holonomy (R_T (3, 3), d_T (3,)) of the grid strains x (N, 6), as monodromy, and
    the body twist of a change of x, dzeta (6, 6N) (rotation rows first), analytic.
    B: the cell matrix cell_matrix(N, L, refine), if the caller keeps it.

    T = T_1 ... T_M with T_c = exp(h xi_c), xi_c = (Omega, Gamma) of the interpolant
    at cell c. A change d xi_c moves T to T exp(Ad_{S_c^-1} h J_r(h xi_c) d xi_c),
    S_c = T_{c+1} ... T_M."""
    N = x.shape[0]
    M = refine * N
    h = L / M
    B = _cell_matrix(N, L, refine) if B is None else B  # (M, N)
    xm = B @ x                                            # (M, 6) = (Gamma, Omega)
    xi = np.concatenate([xm[:, 3:], xm[:, :3]], axis=1)   # (Omega, Gamma): rotation first
    Rc, dc = step_exp(h * xi[:, :3], h * xi[:, 3:])
    # suffix products S_c = T_{c+1} ... T_M (S_M = identity), and T = T_1 S_1
    RS = np.empty((M, 3, 3))
    pS = np.empty((M, 3))
    R, p = np.eye(3), np.zeros(3)
    for c in range(M - 1, -1, -1):
        RS[c], pS[c] = R, p
        p = Rc[c] @ p + dc[c]
        R = Rc[c] @ R
    # Ad of S^-1 = (R^T, -R^T p): [[R^T, 0], [[-R^T p]x R^T, R^T]]
    RSt = np.swapaxes(RS, -1, -2)
    Ad = np.zeros((M, 6, 6))
    Ad[:, :3, :3] = RSt
    Ad[:, 3:, 3:] = RSt
    Ad[:, 3:, :3] = skew(-np.einsum("cji,cj->ci", RS, pS)) @ RSt
    G = Ad @ _right_jacobian_se3(h * xi) * h              # (M, 6, 6): d body twist / d xi_c
    G = np.concatenate([G[:, :, 3:], G[:, :, :3]], axis=2)   # columns in (Gamma, Omega) order
    # body twist of T per grid value: sum_c G[c, a, b] B[c, j] -> (a, j, b), as one matrix product
    dzeta = (G.reshape(M, 36).T @ B).reshape(6, 6, N).transpose(0, 2, 1).reshape(6, 6 * N)
    return R, p, dzeta


def closure_jacobian(x, L, box_length, refine=16):
    """Closure defect c (4,) (as closure_defect) and its Jacobian (4, 6N), analytic: from
    the body twist (d theta, d v) of the holonomy (holonomy_jacobian),
    d log R = J_r^SO3(log R)^-1 d theta and d |d| = d_hat . R d v."""
    N = x.shape[0]
    RT, dT, dzeta = holonomy_jacobian(x, L, refine)
    phi = rotation_log(RT)
    c = np.concatenate([phi, [np.linalg.norm(dT) - box_length]])
    C = np.empty((4, 6 * N))
    C[:3] = inverse_left_jacobian(-phi) @ dzeta[:3]
    C[3] = (dT / np.linalg.norm(dT)) @ RT @ dzeta[3:]
    return c, C


@dataclass
class ClosedRest:
    Gamma: np.ndarray        # (N, 3)
    Omega: np.ndarray        # (N, 3)
    n: np.ndarray            # (N, 3) stress, body frame
    m: np.ndarray            # (N, 3) moment, body frame
    axis0: np.ndarray        # unit end-to-end direction in the frame at s = 0
    tension: float           # n . R^T axis (mean over s)
    torque: float            # m . R^T axis (mean over s)
    statics_residual: float  # max |statics residual| (solver's operator, rodcore's RHS)
    closure_rotation_rad: float
    closure_length_error: float
    energy: float
    space: str
    mode: str = "closed"
    iterations: int = 0


def stress(x, g):
    """(n, m) = K (x - x0), (N, 3) each; x (N, 6) = (Gamma, Omega) (for the report)."""
    x0 = np.concatenate([g["Gamma0"], g["Omega0"]], axis=1)
    w = np.einsum("jab,jb->ja", g["K"], x - x0)
    return w[:, :3], w[:, 3:]


def _shooting_minimiser(g, L, b, refine=2, tol=1e-8, maxiter=30, segment_length=None):
    """Grid strains (N, 6) of the closed energy minimiser of the continuum rod whose
    compliance and intrinsic strains are linear between grid points, by multiple shooting.

    The minimiser's stationarity conditions are the continuum statics with the
    closure's multipliers as lab-frame force N and moment M: n = R^T N,
    m = R^T (M - r x N), x = x0 + K^-1 (n, m). The period is split at grid points into
    K segments no longer than segment_length (default SEGMENT_LENGTH; module
    docstring: one shot over a long, tensioned rod amplifies its errors exponentially).
    Each segment is shot along s (midpoint rule on SE(3), refine cells per grid cell)
    from its own frame and position, R_k = Rref_k exp([theta_k]x), r_k = rref_k + dr_k
    (references: the intrinsic shape, the shot at N = M = 0), under the common (N, M).
    Unknowns p = (N, M, theta_k, dr_k for k = 1 .. K-1); conditions: each segment ends
    at the next one's start (rotation log R_k^T R_end, R_k^T (r_end - r_k)), the last
    at R(L) = I, |r(L)| = b and N || r(L). Levenberg-Marquardt (scipy, MINPACK) with a
    central-difference Jacobian whose shots (all segments of all 12 K perturbations)
    are integrated together. K = 1 is the single shooting."""
    from scipy.optimize import least_squares
    sh = _Shooting(g, L, b, refine, SEGMENT_LENGTH if segment_length is None else segment_length)
    K = sh.K
    eps = 1e-7
    E = np.vstack([eps * np.eye(6 * K), -eps * np.eye(6 * K)])

    def jac(p):
        Rr = sh.residual(p[None] + E)
        return ((Rr[:6 * K] - Rr[6 * K:]) / (2 * eps)).T

    sol = least_squares(lambda p: sh.residual(p[None])[0], np.zeros(6 * K), jac=jac, method="lm",
                        xtol=1e-3 * tol, ftol=1e-3 * tol, gtol=1e-15, max_nfev=50 * maxiter)
    p = sol.x
    f = sh.residual(p[None])[0]
    if np.max(np.abs(f)) > tol:
        raise InputError(f"closed rest state: shooting for the closed minimiser did not converge "
                         f"({K} segments, closure and join residual {np.max(np.abs(f)):.3g})")
    R0, r0 = sh.starts(p[None])
    return sh.shoot(R0, r0, p[None, :6], grid=True)


def _cross(a, b):
    return a[:, [1, 2, 0]] * b[:, [2, 0, 1]] - a[:, [2, 0, 1]] * b[:, [1, 2, 0]]


def _shot_strains(R, r, Nf, Mm, xs0, C_):
    """x = x0 + C (R^T N, R^T (M - r x N)), batched over shots: R (B, 3, 3)."""
    st = np.concatenate([np.einsum("bji,bj->bi", R, Nf),
                         np.einsum("bji,bj->bi", R, Mm - _cross(r, Nf))], axis=1)
    return xs0 + np.einsum("bij,bj->bi", C_, st)


def _se3_exp_lean(v, w):
    """SE(3) exponential (R, J(v) w) of (B, 3) twists, lean (the shot's inner loop)."""
    t2 = np.einsum("bi,bi->b", v, v)
    t = np.sqrt(t2)
    small = t < 1e-3
    ts = np.where(small, 1.0, t)
    a = np.where(small, 1 - t2 / 6, np.sin(ts) / ts)
    bb = np.where(small, 0.5 - t2 / 24, (1 - np.cos(ts)) / ts**2)
    cc = np.where(small, 1 / 6 - t2 / 120, (ts - np.sin(ts)) / ts**3)
    V = skew(v)
    V2 = V @ V
    R = np.eye(3) + a[:, None, None] * V + bb[:, None, None] * V2
    Jw = w + bb[:, None] * np.einsum("bij,bj->bi", V, w) + cc[:, None] * np.einsum("bij,bj->bi", V2, w)
    return R, Jw


class _Shooting:
    """The multiple shooting of _shooting_minimiser: the rod's compliance and intrinsic
    strains linear between grid points (refine cells per grid cell), K segments between
    grid points jb[k] .. jb[k + 1], their reference starts (the intrinsic shape), the
    shot and the residual of the unknowns p = (N, M, theta_k, dr_k for k = 1 .. K-1)."""

    def __init__(self, g, L, b, refine, segment_length):
        N = g["K"].shape[0]
        self.N, self.b, self.refine = N, b, refine
        self.x0 = np.concatenate([g["Gamma0"], g["Omega0"]], axis=1)
        self.Cg = np.linalg.inv(g["K"])                          # compliance, SPD
        self.M = refine * N
        self.hc = L / self.M
        t = (np.arange(self.M) + 0.5) / refine                   # cell midpoints in grid units
        j0 = np.floor(t).astype(int) % N
        w = (t - np.floor(t))[:, None]
        j1 = (j0 + 1) % N
        self.xc0 = (1 - w) * self.x0[j0] + w * self.x0[j1]      # linear in s: convex, so the
        self.Cc = (1 - w[..., None]) * self.Cg[j0] + w[..., None] * self.Cg[j1]  # compliance stays SPD
        K = self.K = max(1, min(N, int(np.ceil(L / segment_length))))
        self.jb = np.round(np.linspace(0, N, K + 1)).astype(int)  # segment k: grid points jb[k] .. jb[k+1]
        self.c0, self.nc = refine * self.jb[:-1], refine * np.diff(self.jb)  # its first cell, its cells
        # references: the intrinsic shape at the segment starts (at N = M = 0 the strains do not
        # depend on the frame, so each segment's motion is shot from the identity and chained)
        Rs, rs = self.shoot(np.broadcast_to(np.eye(3), (1, K, 3, 3)), np.zeros((1, K, 3)), np.zeros((1, 6)))
        self.Rref, self.rref = np.empty((K, 3, 3)), np.empty((K, 3))
        self.Rref[0], self.rref[0] = np.eye(3), 0.0
        for k in range(1, K):
            self.Rref[k] = self.Rref[k - 1] @ Rs[0, k - 1]
            self.rref[k] = self.rref[k - 1] + self.Rref[k - 1] @ rs[0, k - 1]

    def shoot(self, R, r, P, grid=False):
        """Ends (R, r) (B, K, 3, 3), (B, K, 3) of the K segments of B shots from the
        starts R, r (same shapes) under P (B, 6) = (N, M); grid=True (B = 1): the
        strains at the grid points instead."""
        K, refine, hc, xc0, Cc = self.K, self.refine, self.hc, self.xc0, self.Cc
        B = len(P)
        R, r = R.reshape(B * K, 3, 3).copy(), r.reshape(B * K, 3).copy()
        Nf, Mm = np.repeat(P[:, :3], K, axis=0), np.repeat(P[:, 3:], K, axis=0)
        seg = np.tile(np.arange(K), B)
        out = np.empty((self.N, 6))
        for c in range(int(self.nc.max())):
            live = c < self.nc[seg]                          # segments may differ by a grid cell
            cell = np.minimum(self.c0[seg] + c, self.M - 1)
            if grid and c % refine == 0:
                j = self.jb[seg[live]] + c // refine
                out[j] = _shot_strains(R[live], r[live], Nf[live], Mm[live], self.x0[j], self.Cg[j])
            # midpoint rule; the mid-cell frame by a first-order predictor (its O(h^2)
            # error changes the midpoint strains at the order of the rule itself)
            xs = _shot_strains(R, r, Nf, Mm, xc0[cell], Cc[cell])
            Rm = R + 0.5 * hc * R @ skew(xs[:, 3:])
            xm = _shot_strains(Rm, r + 0.5 * hc * np.einsum("bij,bj->bi", R, xs[:, :3]), Nf, Mm,
                               xc0[cell], Cc[cell])
            Rc, dc = _se3_exp_lean(hc * xm[:, 3:], hc * xm[:, :3])
            r = np.where(live[:, None], r + np.einsum("bij,bj->bi", R, dc), r)
            R = np.where(live[:, None, None], R @ Rc, R)
        return out if grid else (R.reshape(B, K, 3, 3), r.reshape(B, K, 3))

    def starts(self, Z):
        """Segment starts (B, K, 3, 3), (B, K, 3) of the unknowns Z (B, 6 K)."""
        B, K = len(Z), self.K
        u = Z[:, 6:].reshape(B, K - 1, 6)
        R = np.broadcast_to(self.Rref, (B, K, 3, 3)).copy()
        r = np.broadcast_to(self.rref, (B, K, 3)).copy()
        R[:, 1:] = R[:, 1:] @ rotation_exp(u[..., :3])
        r[:, 1:] += u[..., 3:]
        return R, r

    def residual(self, Z):
        """(B, 6 K) conditions: each segment ends at the next one's start, the last at
        R(L) = I, |r(L)| = b and N || r(L)."""
        R0, r0 = self.starts(Z)
        R1, r1 = self.shoot(R0, r0, Z[:, :6])
        Rt = np.swapaxes(R0[:, 1:], -1, -2)
        joins = np.concatenate([rotation_log(Rt @ R1[:, :-1]),
                                np.einsum("bkij,bkj->bki", Rt, r1[:, :-1] - r0[:, 1:])], axis=2)
        Re, re = R1[:, -1], r1[:, -1]
        close = np.concatenate([rotation_log(Re), np.cross(re, Z[:, :3]) / self.b,
                                (np.linalg.norm(re, axis=1) - self.b)[:, None]], axis=1)
        return np.concatenate([joins.reshape(len(Z), -1), close], axis=1)


def _closed_step(J, F, C, c, mu=0.0):
    """min |J dx + F|^2 + mu |dx_free|^2 subject to C dx = -c (null-space method: C^T = Q R)."""
    import scipy.linalg
    Q, Rr = np.linalg.qr(C.T, mode="complete")
    k = C.shape[0]
    dx1 = Q[:, :k] @ np.linalg.solve(Rr[:k].T, -c)
    A = J @ Q[:, k:]
    rhs = -(F + J @ dx1)
    if mu > 0:
        A = np.vstack([A, np.sqrt(mu) * np.eye(A.shape[1])])
        rhs = np.concatenate([rhs, np.zeros(A.shape[1])])
    y2 = scipy.linalg.lstsq(A, rhs, lapack_driver="gelsy", check_finite=False)[0]
    return dx1 + Q[:, k:] @ y2


def _equilibrium_from(S, x, tol, maxiter, n_soft=2):
    """An exact root of the solver's statics near x (Lyapunov-Schmidt reduction).

    The Jacobian at x has n_soft tiny singular values (the soft family), so a Newton
    step moves far along a curved valley and leaves it. Split with the SVD of J at x,
    J = U diag(sigma) V^T: for given soft coordinates p (n_soft), the hard equations
    U_h^T F(x + V_s p + V_h y) = 0 are solved for y by Newton (well conditioned), which
    keeps the iterate on the valley floor; then g(p) = U_s^T F = 0 by Newton in n_soft
    unknowns (central-difference Jacobian). Returns (x, Newton steps)."""
    x0 = np.asarray(x, dtype=float).ravel()
    F = S.residual(x0).ravel()
    if np.max(np.abs(F)) < tol:
        return x0, 0
    U, sig, Vt = np.linalg.svd(S.jacobian(x0))
    Us, Vs, Uh, Vh = U[:, -n_soft:], Vt[-n_soft:].T, U[:, :-n_soft], Vt[:-n_soft].T
    steps = [0]
    cache = {"y": np.zeros(Vh.shape[1])}

    def valley(p):
        y = cache["y"].copy()
        for _ in range(maxiter):
            x = x0 + Vs @ p + Vh @ y
            F = S.residual(x).ravel()
            r = Uh.T @ F
            steps[0] += 1
            if np.max(np.abs(r)) < 0.1 * tol:
                break
            y = y - np.linalg.solve(Uh.T @ S.jacobian(x) @ Vh, r)
        else:
            raise InputError(f"equilibrium rest state: the hard part did not converge (residual "
                             f"{np.max(np.abs(r)):.3g})")
        cache["y"] = y
        return x, Us.T @ F, F

    p = np.zeros(n_soft)
    x, gp, F = valley(p)
    for _ in range(maxiter):
        if np.max(np.abs(F)) < tol:
            return x, steps[0]
        h = 1e-4
        G = np.empty((n_soft, n_soft))
        for k in range(n_soft):
            e = np.zeros(n_soft)
            e[k] = h
            G[:, k] = (valley(p + e)[1] - valley(p - e)[1]) / (2 * h)
        dp = np.linalg.solve(G, -gp)
        for lam in 0.5 ** np.arange(6):          # backtracking on |g|
            xn, gn, Fn = valley(p + lam * dp)
            if np.linalg.norm(gn) < np.linalg.norm(gp):
                break
        p, x, gp, F = p + lam * dp, xn, gn, Fn
    raise InputError(f"equilibrium rest state: Newton did not converge in {maxiter} iterations "
                     f"(residual {np.max(np.abs(F)):.3g})")


def closed_rest_state(g, L, box_length=None, space="spectral", refine=8, mode="closed", tol=1e-13,
                      maxiter=40, statics: SolverStatics | None = None):
    """Closed, pre-stressed rest state of the grid material g (steps_to_rod.grid_material).

    box_length: end-to-end length (rod units), default L (the fiducial length).
    mode: "closed" or "equilibrium" (module docstring). Returns a ClosedRest.
    Raises InputError when the iteration does not converge."""
    if mode not in MODES:
        raise InputError(f"rest state mode {mode!r}: allowed {', '.join(MODES)}")
    N = g["K"].shape[0]
    b = float(L if box_length is None else box_length)
    S = SolverStatics(g, L, space) if statics is None else statics
    # closed: the continuum's closed minimiser (shooting, 6 unknowns), then
    # Gauss-Newton on the solver's statics with the closure as an equality constraint
    x = _shooting_minimiser(g, L, b).ravel()
    x, c, C, it = _constrained_gauss_newton(S, x, L, b, refine, maxiter)
    x = _close_to_round_off(x, c, C, L, b, refine)
    if mode == "equilibrium":
        x, it2 = _equilibrium_from(S, x, tol, maxiter)
        it += it2
    return _rest_state(x.reshape(N, 6), g, L, b, refine, S, space, mode, it)


def _constrained_gauss_newton(S, x, L, b, refine, maxiter):
    """Levenberg-Marquardt on the solver's statics with the closure as an equality
    constraint, from x (N 6): a step is kept when it lowers the merit |F|^2 + (w |c|)^2
    (w: the closure counts as much as the statics). Returns x, the closure defect c and
    its Jacobian C at x, and the iterations.

    The damping follows the gain ratio rho (actual / predicted decrease; Nielsen's
    update: mu *= max(1/3, 1 - (2 rho - 1)^3) on success, doubling factors on
    failure): near the soft family the undamped step overshoots along the curved
    valley, and the rate of convergence is set by how small a damping still works,
    so mu is found adaptively rather than reset to 0 after every kept step
    (which costs two rejected solves per iteration)."""
    N = len(x) // 6
    w = 1e3 / (L / N)

    def merit(F, c):
        return float(F @ F + (w * c) @ (w * c))

    F = S.residual(x).ravel()
    c, C = closure_jacobian(x.reshape(N, 6), L, b, refine)
    phi = merit(F, c)
    mu, nu, it = 0.0, 2.0, 0
    for it in range(1, maxiter + 1):
        J = S.jacobian(x)
        scale = np.max(np.abs(J)) ** 2
        while True:
            dx = _closed_step(J, F, C, c, mu)
            xn = x + dx
            Fn = S.residual(xn).ravel()
            cn, Cn = closure_jacobian(xn.reshape(N, 6), L, b, refine)
            phin = merit(Fn, cn)
            if phin <= phi * (1 + 1e-12):
                break
            mu, nu = (1e-10 * scale, 2.0) if mu == 0 else (mu * nu, 2 * nu)
            if mu > 1e4 * scale:
                break
        if mu > 1e4 * scale:         # no descent left: at the optimum to round-off, or stuck
            if np.max(np.abs(c)) < 1e-12 * max(1.0, b):
                break
            raise InputError(f"closed rest state: no descent (statics residual {np.max(np.abs(F)):.3g}, "
                             f"closure defect {np.max(np.abs(c)):.3g})")
        gain = phi - phin
        predicted = phi - merit(F + J @ dx, c + C @ dx)
        if mu > 0:
            rho = gain / predicted if predicted > 0 else 0.0
            mu, nu = mu * max(1 / 3, 1 - (2 * rho - 1) ** 3), 2.0
        x, F, c, C, phi = xn, Fn, cn, Cn, phin
        # done when nearly closed and the residual no longer falls (the optimum's residual
        # is the discretisation error; GN approaches it only linearly, and so the closure)
        if np.max(np.abs(c)) < 1e-8 * max(1.0, b) and gain <= 1e-6 * phi:
            break
    else:
        # the cap: along the soft family the residual can keep falling slowly for many
        # iterations (158 bp) while it is already at its discretisation-error floor;
        # nearly closed is accepted then, anything else is a failure
        if not np.max(np.abs(c)) < 1e-8 * max(1.0, b):
            raise InputError(f"closed rest state: Gauss-Newton did not converge in {maxiter} iterations "
                             f"(last step {np.max(np.abs(dx)):.3g}, closure defect {np.max(np.abs(c)):.3g})")
    return x, c, C, it


def _close_to_round_off(x, c, C, L, b, refine):
    """The last digits of the closure: minimum-norm Newton steps on c alone (quadratic; a
    step of the closure's size moves the statics residual far below its discretisation error)."""
    N = len(x) // 6
    for _ in range(8):
        if np.max(np.abs(c)) < 1e-12 * max(1.0, b):
            return x
        x = x + np.linalg.lstsq(C, -c, rcond=None)[0]
        c, C = closure_jacobian(x.reshape(N, 6), L, b, refine)
    raise InputError(f"closed rest state: the closure did not converge (defect {np.max(np.abs(c)):.3g})")


def _rest_state(x, g, L, b, refine, S, space, mode, iterations) -> ClosedRest:
    """The ClosedRest of the grid strains x (N, 6): stresses, the helix axis, tension and
    torque along it, residuals, closure, energy."""
    N = len(x)
    n, m = stress(x, g)
    R, d = monodromy(x, L, refine)
    axis0 = d / np.linalg.norm(d)
    Rs = _frames_on_grid(x, L, refine)     # director frames at the grid points, to project on the axis
    a_body = np.einsum("jki,k->ji", Rs, axis0)
    cd = closure_defect(x, L, b, refine)
    dx0 = x - np.concatenate([g["Gamma0"], g["Omega0"]], axis=1)
    return ClosedRest(Gamma=x[:, :3].copy(), Omega=x[:, 3:].copy(), n=n, m=m, axis0=axis0,
                      tension=float(np.mean(np.sum(n * a_body, axis=1))),
                      torque=float(np.mean(np.sum(m * a_body, axis=1))),
                      statics_residual=float(np.max(np.abs(S.residual(x)))),
                      closure_rotation_rad=float(np.linalg.norm(cd[:3])),
                      closure_length_error=float(abs(cd[3])),
                      energy=float(0.5 * (L / N) * np.einsum("ja,jab,jb->", dx0, g["K"], dx0)),
                      space=space, mode=mode, iterations=iterations)


def _frames_on_grid(x, L, refine):
    """R(s_j) (N, 3, 3), R(0) = identity, along the refined interpolant."""
    N = x.shape[0]
    M = refine * N
    h = L / M
    xm = trig_interpolate(x, 0.0, L / N, (np.arange(M) + 0.5) * h)
    Rc, _ = step_exp(xm[:, 3:] * h, xm[:, :3] * h)
    out = np.empty((N, 3, 3))
    R = np.eye(3)
    for c in range(M):
        if c % refine == 0:
            out[c // refine] = R
        R = R @ Rc[c]
    return out


def tension_torque_physical(rest: ClosedRest, units=None):
    """(tension [pN], torque [pN nm]): n* C and m* C l."""
    u = Units.paper() if units is None else units
    return rest.tension * u.C * 1e12, rest.torque * u.C * u.ell_m * 1e21
