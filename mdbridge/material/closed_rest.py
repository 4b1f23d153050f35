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

The constrained minimiser comes from its stationarity conditions, the
continuum statics with the closure's multipliers as lab-frame force N and
moment M: n = R^T N, m = R^T (M - r x N), x = x0 + K^-1 (n, m), shot along s
for the 6 numbers (N, M) until R(L) = I, |r(L)| = b, N || r(L) (scipy
least_squares). Then:

* closure_weight = 0 (default, "equilibrium"): the minimiser is polished by Levenberg-Marquardt
  (scipy least_squares, analytic Jacobian)
  on the semi-discrete statics:
  an equilibrium of the solver's equations to round-off (it stays at rest),
  closed to the discretisation error (measured: ClosedRest.closure_*).
  The exact semi-discrete root can sit far along the soft family (measured:
  0.04 rad for 21 bp, 0.09 rad and 1.4 A for 80 bp), so this mode is for
  checking the solver's rest, not for building MD.
* closure_weight > 0 ("closed", the `dnarod dna-rod` default): the polish adds
  the closure (weight / ds): closed to round-off, statics to the
  discretisation error (1.8e-6 at one point per base pair, 2.9e-7 at two, for
  21 bp under Olson 1998; 1.2e-5 for 80 bp).

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
from mdbridge.rodframes import skew, step_exp, trig_interpolate

from .composition import cell_matrix as _cell_matrix, compose_cells as _monodromy_cells


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


def statics_jacobian(x, g, L, space, Dmat=None):
    """d(statics_residual)/dx as (6N, 6N): block (j, i) = D_ji K_i + delta_ij B_j."""
    N = x.shape[0]
    D = derivative_matrix(N, L, space) if Dmat is None else Dmat
    K = g["K"]
    n, m = stress(x, g)
    G, O = x[:, :3], x[:, 3:]
    XO, Xn, Xm, XG = skew(O), skew(n), skew(m), skew(G)
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


def _shooting_minimiser(g, L, b, refine):
    """Grid strains (N, 6) of the closed minimiser by shooting (see closed_rest_state)."""
    from scipy.optimize import least_squares
    N = g["K"].shape[0]
    x0 = np.concatenate([g["Gamma0"], g["Omega0"]], axis=1)
    Cg = np.linalg.inv(g["K"])                               # compliance, SPD
    M = refine * N
    hc = L / M
    t = (np.arange(M) + 0.5) / refine                        # cell midpoints in grid units
    j0 = np.floor(t).astype(int) % N
    w = (t - np.floor(t))[:, None]
    j1 = (j0 + 1) % N
    xc0 = (1 - w) * x0[j0] + w * x0[j1]                       # linear in s: convex, so the
    Cc = (1 - w[..., None]) * Cg[j0] + w[..., None] * Cg[j1]  # compliance stays SPD

    def strains(R, r, Nf, Mm, x0_, C_):
        st = np.concatenate([R.T @ Nf, R.T @ (Mm - np.cross(r, Nf))])
        return x0_ + C_ @ st

    def shoot(p, grid=False):
        Nf, Mm = p[:3], p[3:]
        R, r = np.eye(3), np.zeros(3)
        out = np.empty((N, 6)) if grid else None
        for c in range(M):
            if grid and c % refine == 0:
                out[c // refine] = strains(R, r, Nf, Mm, x0[c // refine], Cg[c // refine])
            # midpoint rule: predict the mid-cell frame with the start-of-cell strains
            xs = strains(R, r, Nf, Mm, xc0[c], Cc[c])
            Rh, dh = step_exp(0.5 * hc * xs[3:], 0.5 * hc * xs[:3])
            xm = strains(R @ Rh, r + R @ dh, Nf, Mm, xc0[c], Cc[c])
            Rc, dc = step_exp(hc * xm[3:], hc * xm[:3])
            r = r + R @ dc
            R = R @ Rc
        return out if grid else (R, r)

    def resid(p):
        R, r = shoot(p)
        Nf = p[:3]
        return np.concatenate([rotation_log(R), np.cross(r, Nf) / b, [np.linalg.norm(r) - b]])

    sol = least_squares(resid, np.zeros(6), method="lm", xtol=1e-15, ftol=1e-15, gtol=1e-15)
    if np.max(np.abs(resid(sol.x))) > 1e-9:
        raise InputError(f"closed rest state: shooting for the closed minimiser did not converge "
                         f"(closure residual {np.max(np.abs(resid(sol.x))):.3g})")
    return shoot(sol.x, grid=True)


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

    # The constrained minimiser: its stationarity conditions are the continuum
    # statics with lab-frame force N and moment M (the multipliers of the closure):
    # n(s) = R^T N, m(s) = R^T (M - r x N), x = x0 + K^-1 (n, m). Shooting in s
    # for (N, M) (6 unknowns) with the closure R(L) = I, |r(L)| = b and N || r(L)
    # (the axis is free), solved by least squares; the minimiser is unique near
    # the intrinsic shape (E is strictly convex, the constraint smooth).
    z = _shooting_minimiser(g, L, b, refine).ravel()
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
    if w_c > 0:                 # closed: Gauss-Newton to the least-squares optimum near the start
        for _ in range(4):
            x = x + np.linalg.lstsq(jac(x), -fun(x), rcond=1e-13)[0]
    for _ in range(3 if w_c == 0 else 0):   # equilibrium: restarts, MINPACK stops on its own tolerances
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
