"""From 3DNA step parameters to the rod: the exact map, its Jacobian for the
stiffness, the unit factors, and the map onto rodsim's grid.

Strains. A step p = (shift, slide, rise [A], tilt, roll, twist [deg]) is the
rigid motion (R_rel, d_rel) of base pair i+1 relative to base pair i
(mdbridge.geometry.steps.step_transform, 3DNA's rebuild). The rod piece of
fiducial length h with CONSTANT strains (Gamma, Omega) that makes exactly this
motion is its SE(3) logarithm (mdbridge.geometry.se3.step_log):

    h Omega = log(R_rel),   h Gamma = J(h Omega)^-1 d_rel,

J the SO(3) left Jacobian. This is not (tilt, roll, twist)/h: the rotation
vector of Rz(tw/2 - phi) Ry(bend) Rz(tw/2 + phi) differs from (tilt, roll,
twist) at second order in the bend times the twist, and d_rel = Rm (shift,
slide, rise) is in the mid-step frame, not in frame i. The inverse
(`steps_from_strains`) is step_exp followed by the 3DNA analysis (cehs), so a
round trip closes to round-off.

Stiffness. A step's energy is 1/2 dp^T F dp [kT] (F in kT/A^2, kT/(A deg),
kT/deg^2). The same piece of rod has energy h * 1/2 dx^T K dx with
x = (Gamma, Omega) in the rod's units. With J = dx/dp at the step's rest
value (6x6, p in A and deg, x dimensionless):

    K* = J^-T F J^-1 * kT* / h*,    kT* = k_B T / (C l),  h* = h / l

(dna_models.units: the energy unit C l, the length unit l; the deg -> rad
factor is inside J because p is in degrees). J is computed by 4th-order
central differences of the exact map (error ~1e-12 relative).

Mass. A base pair of mass m [amu] and inertia I_bp [amu A^2] spread over its
length h gives rho* = (m / h) / rho_paper and I* = (I_bp / h) / I_paper.

Grid (docs/dna-rod.md, "On the grid"): steps sit at the midpoints
(i + 1/2) h, base pairs at i h, the rod has L = n_bp h and N = m n_bp points.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from dna_models.errors import InputError
from dna_models.units import Units
from mdbridge.geometry.steps import step_parameters, step_transform
from mdbridge.geometry.se3 import step_exp, step_log
from mdbridge.rod.frames import trig_interpolate

from .composition import compose_stretches

from .stepfile import StepMaterial

INTERPOLATIONS = ("trig", "smooth", "step")
SHAPES = ("exact", "interpolated")


def _units(units):
    return Units.paper() if units is None else units


# -- the exact map -------------------------------------------------------------
def strains_from_steps(step_params, h_A, units=None):
    """(Gamma (..., 3), Omega (..., 3)) dimensionless, of constant-strain rod pieces
    of fiducial length h_A [A] that make the steps exactly."""
    u = _units(units)
    R_rel, d_rel, _ = step_transform(step_params)
    v, w = step_log(R_rel, d_rel / u.ell_A)
    h = u.length_to_rod(h_A)
    return w / h, v / h


def steps_from_strains(Gamma, Omega, h_A, units=None):
    """Inverse of strains_from_steps: (..., 6) step parameters (A, deg) by the 3DNA analysis."""
    u = _units(units)
    h = u.length_to_rod(h_A)
    R_rel, d_rel = step_exp(np.asarray(Omega, dtype=float) * h, np.asarray(Gamma, dtype=float) * h)
    I = np.broadcast_to(np.eye(3), R_rel.shape)
    return step_parameters(I, np.zeros(d_rel.shape), R_rel, d_rel * u.ell_A)


def strain_jacobian(step_params, h_A, units=None):
    """J = dx/dp (..., 6, 6): x = (Gamma1..3, Omega1..3) rod units, p in (A, deg)."""
    p = np.asarray(step_params, dtype=float)
    delta = np.array([1e-3, 1e-3, 1e-3, 0.05, 0.05, 0.05])   # A, deg (0.05 deg ~ 1e-3 rad)

    def x(q):
        G, O = strains_from_steps(q, h_A, units)
        return np.concatenate([G, O], axis=-1)

    J = np.empty(p.shape[:-1] + (6, 6))
    for k in range(6):
        e = np.zeros(6)
        e[k] = delta[k]
        J[..., :, k] = (-x(p + 2 * e) + 8 * x(p + e) - 8 * x(p - e) + x(p - 2 * e)) / (12 * delta[k])
    return J


def rod_stiffness(F, step_params, temperature_K, h_A, units=None):
    """K* (..., 6, 6) on (Gamma, Omega) from the step stiffness F [kT units at temperature_K]."""
    u = _units(units)
    J = strain_jacobian(step_params, h_A, u)
    Jinv = np.linalg.inv(J)
    K = np.swapaxes(Jinv, -1, -2) @ np.asarray(F, dtype=float) @ Jinv
    K *= u.kT_to_rod(temperature_K) / u.length_to_rod(h_A)
    return 0.5 * (K + np.swapaxes(K, -1, -2))


def step_stiffness(K_star, step_params, temperature_K, h_A, units=None):
    """Inverse of rod_stiffness: F = J^T K* J h* / kT*."""
    u = _units(units)
    J = strain_jacobian(step_params, h_A, u)
    F = np.swapaxes(J, -1, -2) @ np.asarray(K_star, dtype=float) @ J
    F *= u.length_to_rod(h_A) / u.kT_to_rod(temperature_K)
    return 0.5 * (F + np.swapaxes(F, -1, -2))


# -- a whole DNA -----------------------------------------------------------------
@dataclass
class RodMaterial:
    """A StepMaterial in the rod's units, before it is put on a grid.
    Per step (at s = (i + 1/2) h): Gamma0, Omega0 (n_steps, 3), K (n_steps, 6, 6);
    per base pair (at s = i h): rho (n_bp), I (n_bp, 3, 3)."""
    sequence: str
    closed: bool
    h: float            # fiducial step length (rod units)
    h_A: float
    Gamma0: np.ndarray
    Omega0: np.ndarray
    K: np.ndarray
    rho: np.ndarray
    I: np.ndarray
    source: str

    @property
    def n_bp(self):
        return len(self.sequence)

    @property
    def length(self):
        return self.n_bp * self.h


def rod_material(sm: StepMaterial, h_A=None, units=None) -> RodMaterial:
    """Map a StepMaterial onto the rod (exact strains, Jacobian stiffness, densities).
    h_A: fiducial step length [A], default the paper's rise (dna_models.units: 3.38 A),
    so that a uniform B-DNA of that rise has Gamma3 = 1."""
    u = _units(units)
    sm.validate()
    h_A = u.rise_A if h_A is None else float(h_A)
    if not h_A > 0:
        raise InputError(f"fiducial step length h_A = {h_A}: must be > 0 A")
    G0, O0 = strains_from_steps(sm.step_params, h_A, u)
    K = rod_stiffness(sm.stiffness, sm.step_params, sm.temperature_K, h_A, u)
    rho = u.mass_amu_per_length_A_to_rod(sm.mass, h_A)
    I = u.inertia_amu_A2_per_length_A_to_rod(sm.inertia, h_A)
    return RodMaterial(sequence=sm.sequence, closed=sm.closed, h=u.length_to_rod(h_A), h_A=h_A,
                       Gamma0=G0, Omega0=O0, K=K, rho=rho, I=I, source=sm.source)


# -- onto the grid ---------------------------------------------------------------
def _step_profile(values, n, N, offset):
    """Piecewise-constant profile on the grid j L / N: value k on the open cell
    ((k + offset) - 1/2, (k + offset) + 1/2) h; grid points on a cell boundary
    take the mean of the two cells."""
    m = N // n
    x = np.arange(N) / m - offset + 0.5           # position in cells, cell k = [k, k + 1)
    k = np.floor(x).astype(int) % n
    on_edge = np.isclose(x, np.round(x), atol=1e-12)
    out = values[k].copy()
    kl = (np.round(x).astype(int) - 1) % n
    kr = np.round(x).astype(int) % n
    out[on_edge] = 0.5 * (values[kl[on_edge]] + values[kr[on_edge]])
    return out


def _gaussian_cell_weights(n, N, L, offset, sigma):
    """W (N, n): mass of the periodic Gaussian of width sigma centred on s_j in cell k
    ((k + offset - 1/2) h, (k + offset + 1/2) h). Positive, rows sum to 1."""
    from scipy.special import ndtr
    h = L / n
    s = np.arange(N) * L / N
    a = (np.arange(n) + offset - 0.5) * h
    W = np.zeros((N, n))
    reach = int(np.ceil(8 * sigma / L)) + 1
    for p in range(-reach, reach + 1):
        W += ndtr((a[None, :] + h + p * L - s[:, None]) / sigma) - ndtr((a[None, :] + p * L - s[:, None]) / sigma)
    return W / W.sum(axis=1, keepdims=True)


def _on_grid(values, n, N, L, offset, interpolation, sigma):
    v = np.asarray(values, dtype=float)
    flat = v.reshape(n, -1)
    if interpolation == "trig":
        h = L / n
        out = trig_interpolate(flat, offset * h, h, np.arange(N) * L / N)
    elif interpolation == "smooth":
        out = _gaussian_cell_weights(n, N, L, offset, sigma) @ flat
    else:
        out = _step_profile(flat, n, N, offset)
    return out.reshape((N,) + v.shape[1:])


def exact_shape_samples(rm: RodMaterial, refine=32, tol=1e-13, maxiter=30):
    """(n_bp, 6) values of (Gamma0, Omega0) at the step midpoints s = (i + 1/2) h whose
    trigonometric interpolant, composed over each step (mdbridge.rod.material.composition), is exactly
    that step's rigid motion: the rod read at its base pairs has the step parameters.
    Newton on the 6 n_bp step residuals (SE(3) log of target^-1 composed motion),
    from the interpolated per-step values; batched central-difference Jacobian."""
    n, h = rm.n_bp, rm.h
    Rt, dt = step_exp(rm.Omega0 * h, rm.Gamma0 * h)
    RtT = np.swapaxes(Rt, -1, -2)
    B = trig_interpolate(np.eye(n), 0.5 * h, h, (np.arange(n * refine) + 0.5) * h / refine)
    hc = h / refine

    def resid(Y):                                   # Y (..., n, 6) -> (..., 6 n)
        R, d = compose_stretches(np.einsum("cj,...jk->...ck", B, Y), hc, refine)
        v, w = step_log(RtT @ R, np.einsum("...ij,...j->...i", RtT, d - dt))
        return np.concatenate([w, v], axis=-1).reshape(Y.shape[:-2] + (6 * n,))

    Y = np.concatenate([rm.Gamma0, rm.Omega0], axis=1)     # samples at the step midpoints
    eps, batch = 1e-6, 24
    for _ in range(maxiter):
        r = resid(Y)
        if np.max(np.abs(r)) < tol:
            break
        J = np.empty((6 * n, 6 * n))
        for k0 in range(0, 6 * n, batch):
            ks = np.arange(k0, min(k0 + batch, 6 * n))
            Yp = np.repeat(Y[None], len(ks), axis=0)
            Ym = Yp.copy()
            Yp[np.arange(len(ks)), ks // 6, ks % 6] += eps
            Ym[np.arange(len(ks)), ks // 6, ks % 6] -= eps
            J[:, ks] = ((resid(Yp) - resid(Ym)) / (2 * eps)).T
        Y = Y - np.linalg.solve(J, r).reshape(n, 6)
    else:
        raise InputError(f"exact intrinsic shape: Newton did not converge (residual {np.max(np.abs(r)):.3g})")
    return Y


def _spd_log(A):
    lam, V = np.linalg.eigh(A)
    return (V * np.log(lam)[..., None, :]) @ np.swapaxes(V, -1, -2)


def _spd_exp(A):
    lam, V = np.linalg.eigh(0.5 * (A + np.swapaxes(A, -1, -2)))
    return (V * np.exp(lam)[..., None, :]) @ np.swapaxes(V, -1, -2)


def grid_material(rm: RodMaterial, N=None, interpolation="trig", sigma=None, shape="interpolated") -> dict:
    """Per-grid-point K, I, rho, Gamma0, Omega0 (and s) on N = m n_bp points.

    interpolation: "trig" (trigonometric interpolation of the per-step and
    per-base-pair values; of log K, log I, log rho for the positive ones),
    "smooth" (the piecewise-constant profile convolved with a periodic
    Gaussian of width sigma, default h/2, evaluated exactly at the grid
    points: a convex combination, so K and I stay positive definite, and one
    C-infinity field whatever N), "step" (piecewise constant: Gibbs oscillations
    under the spectral operator)."""
    if not rm.closed:
        raise InputError("the rod solver is periodic: only a closed (ligated) step file maps onto its grid "
                         "(dataset 'closed' is false)")
    n = rm.n_bp
    N = n if N is None else int(N)
    if N < n or N % n:
        raise InputError(f"grid points N = {N}: must be a positive multiple of n_bp = {n} "
                         "(base pair i sits on grid point i N / n_bp)")
    if shape not in SHAPES:
        raise InputError(f"shape {shape!r}: allowed {', '.join(SHAPES)}")
    if interpolation not in INTERPOLATIONS:
        raise InputError(f"interpolation {interpolation!r}: allowed {', '.join(INTERPOLATIONS)}")
    L = rm.length
    sigma = 0.5 * rm.h if sigma is None else float(sigma)
    # "trig" interpolates K, I and rho through their logarithms (log-Euclidean):
    # positive definite by construction, equal to the samples on them, and still
    # analytic, so the spectral derivative of K(s) (x - x0) converges exponentially.
    pos = _spd_log if interpolation == "trig" else (lambda a: a)
    back = _spd_exp if interpolation == "trig" else (lambda a: a)
    lg = (lambda a: np.log(a)) if interpolation == "trig" else (lambda a: a)
    ex = (lambda a: np.exp(a)) if interpolation == "trig" else (lambda a: a)
    g = {"s": np.arange(N) * L / N,
         "Gamma0": _on_grid(rm.Gamma0, n, N, L, 0.5, interpolation, sigma),
         "Omega0": _on_grid(rm.Omega0, n, N, L, 0.5, interpolation, sigma),
         "K": back(_on_grid(pos(rm.K), n, N, L, 0.5, interpolation, sigma)),
         "I": back(_on_grid(pos(rm.I), n, N, L, 0.0, interpolation, sigma)),
         "rho": ex(_on_grid(lg(rm.rho), n, N, L, 0.0, interpolation, sigma))}
    if shape == "exact":
        Y = exact_shape_samples(rm)
        if N == n and n % 2 == 0:
            raise InputError(f"shape = 'exact' with an even n_bp = {n} needs N >= 2 n_bp: the grid at the "
                             "base pairs cannot hold the interpolant's Nyquist mode")
        shp = trig_interpolate(Y, 0.5 * rm.h, rm.h, g["s"])
        g["Gamma0"], g["Omega0"] = shp[:, :3], shp[:, 3:]
    for name in ("K", "I"):
        A = g[name] = 0.5 * (g[name] + np.swapaxes(g[name], -1, -2))
        ev = np.linalg.eigvalsh(A)[:, 0]
        if np.any(ev <= 0):
            j = int(np.argmin(ev))
            raise InputError(f"{interpolation} interpolation of {name} is not positive definite at grid point "
                             f"{j} (eigenvalue {ev[j]:.3g}); use interpolation = 'smooth' (always positive)")
    if np.any(g["rho"] <= 0):
        raise InputError(f"{interpolation} interpolation of rho is not positive; use 'smooth'")
    return g
