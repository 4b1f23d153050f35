"""Rod <-> base-pair frames (docs/contracts.md, "Discrete <-> continuous"): the one place
where a rod is sampled at its base pairs (frames, origins, the cross-sections' lab
velocities, the period vector) and where base-pair frames become rod strains.

Rod -> base pairs: base pair i (i = 0 .. n_bp - 1) sits at the fiducial
arclength s_i = i L / n_bp; its frame is the rod's directors there
(d1 = x toward the major groove, d2 = y toward strand I, d3 = z along the
helix) and its origin is r(s_i), converted to Angstrom by dna_models.units.
The rod grid is s_j = j L / N (rodcore), so s_i is a grid point exactly when
N is a multiple of n_bp; we require that (no interpolation error is then
introduced). Step parameters come from the exact relative rotation and
translation of consecutive frames (mdbridge.geometry.steps), never from
Omega * ds.

Base pairs -> rod: the rigid motion from frame i to frame i+1 is the
exponential of one constant-strain rod piece of length ds (SE(3) logarithm):

    R_i^T R_{i+1} = exp(ds [Omega]x),
    R_i^T (o_{i+1} - o_i) = int_0^ds exp(u [Omega]x) du Gamma = ds J(ds Omega) Gamma,

with J(v) = I + (1 - cos t)/t^2 [v]x + (t - sin t)/t^3 [v]x^2, t = |v| (the
SO(3) left Jacobian). So Omega = log(R_i^T R_{i+1}) / ds and Gamma =
J^-1 R_i^T (o_{i+1} - o_i) / ds, assigned to the step midpoint s_{i+1/2}
(body-frame components; ds Omega has the same components in frames i and i+1
because it is the rotation's own axis). For a uniform helix (constant Gamma,
Omega) this is exact. For a smooth rod the SE(3) logarithm equals the
integral of the strains plus Magnus commutator terms of order ds^3, so both
are midpoint values with error O(ds^2) (tested: the error falls 4x per
doubling of n_bp; Gamma = R_mid^T (o_{i+1} - o_i)/ds would be O(ds^2) too but
not exact for a helix). The midpoint values are then interpolated to the rod grid
(trigonometric interpolation for a periodic rod, spectrally accurate; a cubic
spline otherwise).
"""
from __future__ import annotations

import numpy as np

from dna_models.errors import InputError
from dna_models.units import Units
from mdbridge.geometry.rotations import transpose
from mdbridge.geometry.se3 import step_log
from mdbridge.geometry.steps import step_parameters_along


# -- rod -> base pairs -----------------------------------------------------
def bp_frames_from_rod(centerline, directors, n_bp, ell_A=None):
    """Base-pair frames from rod output arrays.

    centerline (..., N, 3) in rod length units; directors (..., N, 3, 3) with
    directors[..., j, :, k] = d_k (rodcore HDF5 layout). Returns (R (..., n_bp,
    3, 3), origins (..., n_bp, 3) in Angstrom). N must be a multiple of n_bp.
    """
    r = np.asarray(centerline, dtype=float)
    D = np.asarray(directors, dtype=float)
    stride = bp_stride(r.shape[-2], n_bp)
    ell = Units.paper().ell_A if ell_A is None else float(ell_A)
    return D[..., ::stride, :, :], r[..., ::stride, :] * ell


def bp_stride(N: int, n_bp: int) -> int:
    """Grid points per base pair: base pair i is grid point i N / n_bp (N a multiple of n_bp)."""
    if n_bp < 1 or N % n_bp != 0:
        raise InputError(f"rod grid of N = {N} points cannot place {n_bp} base pairs on grid points: "
                         f"N must be a multiple of n_bp (s_i = i L / n_bp must equal a grid point j L / N)")
    return N // n_bp


def bp_lab_velocities(directors, gamma, omega, n_bp):
    """The rigid-body velocities of the base pairs' cross-sections in the laboratory frame,
    d_k gamma_k and d_k omega_k at s_i = i L / n_bp (solver units).

    directors (..., N, 3, 3) as in bp_frames_from_rod; gamma, omega (..., N, 3) in the
    internal (body) frame, as the rod writes them. Returns (v (..., n_bp, 3),
    w (..., n_bp, 3))."""
    D = np.asarray(directors, dtype=float)
    stride = bp_stride(D.shape[-3], n_bp)
    D = D[..., ::stride, :, :]
    v = np.einsum("...nik,...nk->...ni", D, np.asarray(gamma, dtype=float)[..., ::stride, :])
    w = np.einsum("...nik,...nk->...ni", D, np.asarray(omega, dtype=float)[..., ::stride, :])
    return v, w


def period_vector(directors, Gamma, ds):
    """P = int_0^L d_k Gamma_k ds (Eq 1: dr/ds = T Gamma), the end-to-end vector of one
    period, by the periodic trapezoid rule (spectrally accurate for a smooth periodic rod).
    directors (..., N, 3, 3), Gamma (..., N, 3) on the whole grid; returns (..., 3)."""
    return np.einsum("...ixk,...ik->...x", np.asarray(directors, dtype=float),
                     np.asarray(Gamma, dtype=float)) * ds


def rod_step_parameters(centerline, directors, n_bp, ell_A=None):
    """(..., n_bp - 1, 6) step parameters (A, deg) of the base pairs a rod carries."""
    R, o = bp_frames_from_rod(centerline, directors, n_bp, ell_A)
    return step_parameters_along(R, o)


# -- base pairs -> rod -------------------------------------------------------
def midpoint_strains(R, o, ds, closing=None):
    """Omega and Gamma (body frame) at the step midpoints from frames.

    R (n, 3, 3), o (n, 3) in the same length unit as ds. closing=(R_n, o_n):
    the frame that follows the last one (periodic rod: the first frame moved by
    the period); with it there are n steps, otherwise n - 1. Returns
    (Omega (m, 3), Gamma (m, 3))."""
    R = np.asarray(R, dtype=float)
    o = np.asarray(o, dtype=float)
    if closing is not None:
        Rn, on = closing
        R = np.concatenate([R, np.asarray(Rn, dtype=float)[None]], axis=0)
        o = np.concatenate([o, np.asarray(on, dtype=float)[None]], axis=0)
    d_local = np.einsum("...ji,...j->...i", R[:-1], o[1:] - o[:-1])   # R_i^T (o_{i+1} - o_i)
    v, w = step_log(transpose(R[:-1]) @ R[1:], d_local)
    return v / ds, w / ds


def trig_interpolate(values, x0, h, x):
    """Trigonometric interpolant through values[k] at x0 + k h (period n h), at x."""
    n = values.shape[0]
    L = n * h
    c = np.fft.fft(values, axis=0) / n
    k = np.fft.fftfreq(n, d=1.0 / n)
    xx = (np.asarray(x, dtype=float) - x0)[:, None]
    basis = np.exp(2j * np.pi * k[None, :] * xx / L)
    if n % 2 == 0:  # Nyquist mode: the real cosine that matches the samples
        basis[:, n // 2] = np.cos(np.pi * n * xx[:, 0] / L)
    return np.real(basis @ c)


def rod_strains_from_frames(R, o_A, L=None, N=None, periodic=True, closing=None, units=None):
    """The rod's Gamma, Omega (dimensionless, body frame) on its grid from base-pair frames.

    R (n_bp, 3, 3), o_A (n_bp, 3) [Angstrom]; L the dimensionless rod length
    (default n_bp * rise / ell, so that ideal B-DNA has Gamma3 = 1); N grid
    points (default n_bp). periodic=True: the rod closes and `closing` =
    (R_n, o_n [A]) is the frame that follows the last one -- for a ligated
    duplex in a box, (R_0, o_0 + the box vector along the helix); by default
    (R_0, o_0), a closed ring. periodic=False: n_bp - 1 steps, cubic spline.
    Returns (s (N), Gamma (N, 3), Omega (N, 3)).
    """
    u = Units.paper() if units is None else units
    R = np.asarray(R, dtype=float)
    o = np.asarray(o_A, dtype=float) / u.ell_A
    n = R.shape[0]
    if L is None:
        L = n * u.length_to_rod(u.rise_A)
    N = n if N is None else int(N)
    ds = L / n
    s = np.arange(N) * L / N
    if periodic:
        if closing is None:
            closing = (R[0], o[0] * u.ell_A)   # a closed ring
        Rn, on = closing
        Om, Ga = midpoint_strains(R, o, ds, closing=(Rn, np.asarray(on, dtype=float) / u.ell_A))
        Omega = trig_interpolate(Om, 0.5 * ds, ds, s)
        Gamma = trig_interpolate(Ga, 0.5 * ds, ds, s)
    else:
        from scipy.interpolate import CubicSpline
        Om, Ga = midpoint_strains(R, o, ds)
        sm = (np.arange(n - 1) + 0.5) * ds
        if len(sm) < 2:
            raise InputError("need at least 3 base-pair frames for an open rod")
        Omega = CubicSpline(sm, Om, axis=0)(s)
        Gamma = CubicSpline(sm, Ga, axis=0)(s)
    return s, Gamma, Omega
