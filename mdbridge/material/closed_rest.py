"""The closed, pre-stressed rest state of a sequence-dependent periodic rod.

A sequence-dependent intrinsic shape (Gamma0(s), Omega0(s)) composed over one
period is a screw motion, not the pure translation by the box vector that a
ligated DNA in a periodic box needs. The rest state is the minimiser of the
elastic energy

    E = sum_j ds/2 (x_j - x0_j)^T K_j (x_j - x0_j),  x = (Gamma, Omega),  ds = L/N

over the grid values, under the closure constraint: the frame at L equals the
frame at 0 and the end-to-end vector has the box length b (its direction, the
helix axis, is free). The constraint is evaluated on the trigonometric
interpolant of the grid fields, refined `refine` times (product of SE(3)
exponentials of the midpoint strains; error O((ds/refine)^2)).

A minimiser of the continuum energy satisfies the statics
D n + Omega x n = 0, D m + Omega x m + Gamma x n = 0 with (n, m) = K (x - x0).
The semi-discrete statics (D the solver's spectral or FD4 derivative) have,
near a closed equilibrium, a two-parameter family of nearly-equilibria (the
continuum's screw motions about the force axis: every stress invariant under
the monodromy is periodic), which the discretisation breaks only weakly. So
the exact semi-discrete equilibrium and exact closure cannot both hold at a
finite N; the two differ by the discretisation error. Two modes:

* closure_weight = 0 (default, "equilibrium"): the constrained minimiser
  (Lagrange-Newton: constraint linearised, quadratic energy minimised exactly)
  is polished by Levenberg-Marquardt (scipy least_squares, analytic Jacobian)
  on the semi-discrete statics:
  an equilibrium of the solver's equations to round-off (it stays at rest),
  closed to the discretisation error (measured: ClosedRest.closure_*).
* closure_weight > 0 ("closed"): the polish adds the closure (weight / ds):
  closed to round-off, statics to the discretisation error (1e-6 at one point
  per base pair, 3e-7 at two, for 21 bp under Olson 1998).

The residual stress: with N = R n and the closure direction b_hat, the tension
is n . R^T b_hat and the torque about the axis m . R^T b_hat (both constant
along s at an exact equilibrium with N || b_hat).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from dna_models.errors import InputError
from dna_models.units import Units
from mdbridge.geometry.rotations import rotation_log
from mdbridge.rodframes import step_exp, trig_interpolate


def derivative(f, L, space):
    """d/ds of periodic grid data f (N, ...) as rodcore does it: Fourier with the
    Nyquist mode zeroed ("spectral") or the 4th-order central difference ("fd4")."""
    N = f.shape[0]
    if space == "spectral":
        k = np.fft.rfftfreq(N, d=L / N) * 2 * np.pi
        if N % 2 == 0:
            k[-1] = 0.0
        return np.fft.irfft(1j * k.reshape((-1,) + (1,) * (f.ndim - 1)) * np.fft.rfft(f, axis=0), n=N, axis=0)
    if space == "fd4":
        h = L / N
        return (-np.roll(f, -2, 0) + 8 * np.roll(f, -1, 0) - 8 * np.roll(f, 1, 0) + np.roll(f, 2, 0)) / (12 * h)
    raise InputError(f"space {space!r}: allowed 'spectral', 'fd4'")


def derivative_matrix(N, L, space):
    """The operator of `derivative` as a dense (N, N) matrix."""
    return derivative(np.eye(N), L, space)


def _cross_matrix(v):
    Z = np.zeros(v.shape[:-1] + (3, 3))
    Z[..., 0, 1], Z[..., 0, 2], Z[..., 1, 2] = -v[..., 2], v[..., 1], -v[..., 0]
    Z[..., 1, 0], Z[..., 2, 0], Z[..., 2, 1] = v[..., 2], -v[..., 1], v[..., 0]
    return Z


def statics_jacobian(x, g, L, space, Dmat=None):
    """d(statics_residual)/dx as (6N, 6N): block (j, i) = D_ji K_i + delta_ij B_j."""
    N = x.shape[0]
    D = derivative_matrix(N, L, space) if Dmat is None else Dmat
    K = g["K"]
    n, m = stress(x, g)
    G, O = x[:, :3], x[:, 3:]
    XO, Xn, Xm, XG = _cross_matrix(O), _cross_matrix(n), _cross_matrix(m), _cross_matrix(G)
    B = np.zeros((N, 6, 6))
    B[:, :3, :] = XO @ K[:, :3, :]
    B[:, :3, 3:] -= Xn
    B[:, 3:, :] = XO @ K[:, 3:, :] + XG @ K[:, :3, :]
    B[:, 3:, 3:] -= Xm
    B[:, 3:, :3] -= Xn
    J = D[:, None, :, None] * np.swapaxes(K, 0, 1)[None, :, :, :]      # (j, a, i, b) = D_ji K_i[a, b]
    J[np.arange(N), :, np.arange(N), :] += B
    return J.reshape(6 * N, 6 * N)


def stress(x, g):
    """(n, m) = K (x - x0), (N, 3) each; x (N, 6) = (Gamma, Omega)."""
    x0 = np.concatenate([g["Gamma0"], g["Omega0"]], axis=1)
    w = np.einsum("jab,jb->ja", g["K"], x - x0)
    return w[:, :3], w[:, 3:]


def statics_residual(x, g, L, space):
    """(N, 6): D n + Omega x n and D m + Omega x m + Gamma x n."""
    n, m = stress(x, g)
    G, O = x[:, :3], x[:, 3:]
    return np.concatenate([derivative(n, L, space) + np.cross(O, n),
                           derivative(m, L, space) + np.cross(O, m) + np.cross(G, n)], axis=1)


def _chain_product(A):
    """Ordered product A[..., 0, :, :] @ A[..., 1, :, :] @ ... of (..., M, 4, 4), pairwise."""
    while A.shape[-3] > 1:
        if A.shape[-3] % 2:
            A = np.concatenate([A, np.broadcast_to(np.eye(4), A.shape[:-3] + (1, 4, 4))], axis=-3)
        A = A[..., 0::2, :, :] @ A[..., 1::2, :, :]
    return A[..., 0, :, :]


def _cell_matrix(N, L, refine):
    """(M, N): grid values -> the trigonometric interpolant at the refine*N cell midpoints."""
    M = refine * N
    return trig_interpolate(np.eye(N), 0.0, L / N, (np.arange(M) + 0.5) * L / M)


def _monodromy_cells(xm, h):
    """Product of the SE(3) exponentials of the cell strains xm (..., M, 6): (R (..., 3, 3), d (..., 3))."""
    R, d = step_exp(xm[..., 3:] * h, xm[..., :3] * h)
    T = np.zeros(xm.shape[:-1] + (4, 4))
    T[..., :3, :3], T[..., :3, 3], T[..., 3, 3] = R, d, 1.0
    P = _chain_product(T)
    return P[..., :3, :3], P[..., :3, 3]


def monodromy(x, L, refine=16):
    """(R_total, d_total): frame at L relative to the frame at 0, of the trigonometric
    interpolant of the grid strains x (N, 6), by midpoint exponentials on refine*N cells."""
    N = x.shape[0]
    return _monodromy_cells(_cell_matrix(N, L, refine) @ x, L / (refine * N))


def closure_defect(x, L, box_length, refine=16):
    """(4,): rotation vector of R_total (rad) and |d_total| - box_length."""
    R, d = monodromy(x, L, refine)
    return np.concatenate([rotation_log(R), [np.linalg.norm(d) - box_length]])


@dataclass
class ClosedRest:
    Gamma: np.ndarray        # (N, 3)
    Omega: np.ndarray        # (N, 3)
    n: np.ndarray            # (N, 3) stress, body frame
    m: np.ndarray            # (N, 3) moment, body frame
    axis0: np.ndarray        # unit end-to-end direction in the frame at s = 0
    tension: float           # n . R^T axis (mean over s)
    torque: float            # m . R^T axis (mean over s)
    statics_residual: float  # max |statics residual| (solver's operator)
    closure_rotation_rad: float
    closure_length_error: float
    energy: float
    space: str


def closed_rest_state(g, L, box_length=None, space="spectral", refine=8, tol=1e-14, maxiter=100,
                      closure_weight=0.0, polish_iterations=200):
    """Closed, pre-stressed equilibrium of the grid material g (steps_to_rod.grid_material).

    box_length: end-to-end length (rod units), default L (the fiducial length).
    Returns a ClosedRest. Raises InputError when scipy does not converge."""
    N = g["K"].shape[0]
    b = float(L if box_length is None else box_length)
    x0 = np.concatenate([g["Gamma0"], g["Omega0"]], axis=1).ravel()
    ds = L / N
    Kds = g["K"] * ds
    Hinv = np.linalg.inv(Kds)                       # the energy's Hessian is block diagonal

    def energy(z):
        dx = z.reshape(N, 6) - x0.reshape(N, 6)
        return 0.5 * np.einsum("ja,jab,jb->", dx, Kds, dx)

    def c(z):
        return closure_defect(z.reshape(N, 6), L, b, refine)

    B = _cell_matrix(N, L, refine)
    hc = L / (refine * N)

    def c_jac(z, eps=1e-5, batch=48):
        """Closure defect and its central-difference Jacobian (4, 6N), perturbations batched."""
        xm0 = B @ z.reshape(N, 6)
        c0 = c(z)
        Jc = np.empty((4, z.size))
        for k0 in range(0, z.size, batch):
            ks = np.arange(k0, min(k0 + batch, z.size))
            cks = []
            for sign in (1.0, -1.0):
                xm = np.repeat(xm0[None], len(ks), axis=0)
                xm[np.arange(len(ks)), :, ks % 6] += sign * eps * B[:, ks // 6].T
                R, d = _monodromy_cells(xm, hc)
                cks.append(np.concatenate([rotation_log(R), (np.linalg.norm(d, axis=-1) - b)[:, None]], axis=1))
            Jc[:, ks] = ((cks[0] - cks[1]) / (2 * eps)).T
        return c0, Jc

    # Minimise E subject to c = 0: the KKT conditions H (x - x0) = C^T lam, c(x) = 0,
    # solved by Newton on the constraint with the exact (quadratic) energy: at each
    # iterate the constraint is linearised and the quadratic problem solved exactly.
    z = x0.copy()
    for it in range(maxiter):
        c0, Jc = c_jac(z)
        HC = np.einsum("jab,kjb->kja", Hinv, Jc.reshape(4, N, 6)).reshape(4, -1)   # H^-1 C^T, as rows
        lam = np.linalg.solve(Jc @ HC.T, -c0 - Jc @ (x0 - z))
        z_new = x0 + HC.T @ lam
        dz = np.max(np.abs(z_new - z))
        if dz < 1e-10 and np.max(np.abs(c0)) < 1e-12:
            z = z_new
            break
        z = z_new
    else:
        raise InputError(f"closed rest state: the constrained energy minimisation did not converge in "
                         f"{maxiter} iterations (closure defect {np.max(np.abs(c(z))):.3g})")
    # Polish on the solver's statics: Newton with minimum-norm steps (lstsq), so the
    # state moves only as far as the semi-discrete equations need and stays closed to
    # their discretisation error. closure_weight > 0 adds the closure (scaled by 1/ds).
    from scipy.optimize import least_squares
    Dmat = derivative_matrix(N, L, space)
    w_c = closure_weight / ds

    def fun(zz):
        r = statics_residual(zz.reshape(N, 6), g, L, space).ravel()
        return np.concatenate([r, w_c * c(zz)]) if w_c > 0 else r

    def jac(zz):
        J = statics_jacobian(zz.reshape(N, 6), g, L, space, Dmat)
        return np.vstack([J, w_c * c_jac(zz)[1]]) if w_c > 0 else J

    x = z.copy()
    for _ in range(3):          # restarts: MINPACK's lm stops on its own tolerances
        ls = least_squares(fun, x, jac=jac, method="lm", xtol=1e-15, ftol=1e-15, gtol=1e-15,
                           max_nfev=polish_iterations)
        x = ls.x
        if np.max(np.abs(statics_residual(x.reshape(N, 6), g, L, space))) < tol:
            break
    x = x.reshape(N, 6)
    n, m = stress(x, g)
    R, d = monodromy(x, L, refine)
    axis0 = d / np.linalg.norm(d)
    # director frames at the grid points (same interpolant, refined), to project on the axis
    Rs = _frames_on_grid(x, L, refine)
    a_body = np.einsum("jki,k->ji", Rs, axis0)
    cd = closure_defect(x, L, b, refine)
    n, m = stress(x, g)
    return ClosedRest(Gamma=x[:, :3].copy(), Omega=x[:, 3:].copy(), n=n, m=m, axis0=axis0,
                      tension=float(np.mean(np.sum(n * a_body, axis=1))),
                      torque=float(np.mean(np.sum(m * a_body, axis=1))),
                      statics_residual=float(np.max(np.abs(statics_residual(x, g, L, space)))),
                      closure_rotation_rad=float(np.linalg.norm(cd[:3])),
                      closure_length_error=float(abs(cd[3])), energy=float(energy(x.ravel())), space=space)


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
