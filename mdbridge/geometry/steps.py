"""Step and base-pair parameters from two frames, and frames from parameters.

Definitions are 3DNA's (Lu & Olson 2003 NAR 31:5108; "3DNA technical
details", sections 4, 5, 7), i.e. the CEHS scheme (El Hassan & Calladine
1995) with the standard reference frame of Olson et al. 2001 JMB 313:229:

* bend ("RollTilt") angle Gamma = angle between z1 and z2; hinge axis
  h = z1 x z2 / |z1 x z2|;
* frame 1 is rotated by +Gamma/2 and frame 2 by -Gamma/2 about h, which makes
  their z axes coincide (the mid-step z axis);
* twist = signed angle from y1' to y2' about that z axis;
* the mid-step triad Rm is half-way between the two rotated frames and its
  origin is (o1 + o2) / 2;
* phase phi = signed angle from h to y_m; roll = Gamma cos(phi),
  tilt = Gamma sin(phi) (equivalently: (tilt, roll) = Gamma (h.x_m, h.y_m));
* (shift, slide, rise) = (o2 - o1) projected on x_m, y_m, z_m.

The inverse (tech-details Eqs 6-8), with phi = atan2(tilt, roll):
    Rm = Rz(twist/2 - phi) Ry(Gamma/2) Rz(phi)
    R2 = R1 Rz(twist/2 - phi) Ry(Gamma) Rz(twist/2 + phi)
    o2 = o1 + R1 Rm (shift, slide, rise)

Numerics: 3DNA takes angles with arccos, which loses half the digits near
0 deg; here every angle comes from atan2 of a sine-like and a cosine-like
quantity, so frames -> parameters -> frames closes to ~1e-15.

Frames are (..., 3, 3) arrays whose COLUMNS are the x, y, z axes in the
laboratory frame; origins are (..., 3). Every function broadcasts over
leading axes (trajectory frames, steps). Angles are returned in DEGREES and
lengths in the units of the origins (Angstrom for structures).

Parameter order everywhere: STEP_NAMES = shift, slide, rise, tilt, roll, twist
and BP_NAMES = shear, stretch, stagger, buckle, propeller, opening.
"""
from __future__ import annotations

import numpy as np

from dna_models.errors import InputError

from .rotations import axis_angle_matrix, rot_y, rot_z, transpose

STEP_NAMES = ("shift", "slide", "rise", "tilt", "roll", "twist")
BP_NAMES = ("shear", "stretch", "stagger", "buckle", "propeller", "opening")

_TINY = 1e-300


def _cross(a, b):
    return np.cross(a, b)


def _dot(a, b):
    return np.einsum("...i,...i->...", a, b)


def cehs(R1, o1, R2, o2):
    """The CEHS analysis of frame 2 relative to frame 1.

    Returns (params, Rm, om): params (..., 6) = (Dx, Dy, Dz [length],
    tau, rho, Omega [deg]) i.e. (shift, slide, rise, tilt, roll, twist) for two
    base pairs and (shear, stretch, stagger, buckle, propeller, opening) for the
    two bases of a pair; Rm (..., 3, 3) the middle frame; om (..., 3) its origin.
    """
    R1 = np.asarray(R1, dtype=float)
    R2 = np.asarray(R2, dtype=float)
    o1 = np.asarray(o1, dtype=float)
    o2 = np.asarray(o2, dtype=float)
    R1, R2 = np.broadcast_arrays(R1, R2)
    z1 = R1[..., :, 2]
    z2 = R2[..., :, 2]
    n = _cross(z1, z2)                       # sin(Gamma) h
    s = np.linalg.norm(n, axis=-1)
    c = _dot(z1, z2)
    bend = np.arctan2(s, c)                  # Gamma in [0, pi]
    safe = s > _TINY
    s_safe = np.where(safe, s, 1.0)
    # hinge: any unit vector will do when Gamma = 0 (rotations by 0 below)
    h = np.where(safe[..., None], n / s_safe[..., None], R1[..., :, 0])
    R1p = axis_angle_matrix(h, 0.5 * bend) @ R1
    R2p = axis_angle_matrix(h, -0.5 * bend) @ R2
    # After the symmetric rotations z1' = z2'; average to take the round-off out.
    zm = R1p[..., :, 2] + R2p[..., :, 2]
    zm /= np.linalg.norm(zm, axis=-1, keepdims=True)
    y1, y2 = R1p[..., :, 1], R2p[..., :, 1]
    twist = np.arctan2(_dot(_cross(y1, y2), zm), _dot(y1, y2))
    # Middle frame: frame 1' turned by twist/2 about the common z axis.
    Rm = R1p @ rot_z(0.5 * twist)
    # (tilt, roll) = Gamma (h.x_m, h.y_m) = (Gamma / sin Gamma) (n.x_m, n.y_m);
    # Gamma / sin Gamma -> 1 as Gamma -> 0, which keeps small bends exact.
    ratio = np.where(safe, bend / s_safe, 1.0)
    tilt = ratio * _dot(n, Rm[..., :, 0])
    roll = ratio * _dot(n, Rm[..., :, 1])
    om = 0.5 * (o1 + o2)
    d = np.einsum("...i,...ij->...j", o2 - o1, Rm)
    params = np.concatenate([d, np.degrees(np.stack([tilt, roll, twist], axis=-1))], axis=-1)
    return params, Rm, om


def step_parameters(R1, o1, R2, o2):
    """(shift, slide, rise, tilt, roll, twist) of base pair 2 relative to 1.

    Shapes (..., 3, 3) and (..., 3); returns (..., 6) in (length, degrees).
    """
    return cehs(R1, o1, R2, o2)[0]


def step_parameters_along(R, o, box=None, periodic=False):
    """Step parameters of consecutive frames along axis -3 of R (..., n, 3, 3).

    o (..., n, 3). With periodic=True the closing step n-1 -> 0 is appended
    (output (..., n, 6)); with `box` (MDAnalysis dimensions, (..., 6)) the
    translations o[i+1] - o[i] are taken as minimum-image vectors, which is
    what a periodic, ligated duplex with wrapped atoms needs.
    """
    R = np.asarray(R, dtype=float)
    o = np.asarray(o, dtype=float)
    if periodic:
        R2 = np.roll(R, -1, axis=-3)
        o2n = np.roll(o, -1, axis=-2)
        R1, o1 = R, o
    else:
        R1, o1, R2, o2n = R[..., :-1, :, :], o[..., :-1, :], R[..., 1:, :, :], o[..., 1:, :]
    if box is not None:
        from .pbc import minimum_image
        b = np.asarray(box, dtype=float)
        if b.ndim == 2:           # (T, 6) -> broadcast over the step axis
            b = b[:, None, :]
        o2n = o1 + minimum_image(o2n - o1, b)
    return step_parameters(R1, o1, R2, o2n)


def unwrap_twist_deg(twist_deg, reference_deg):
    """Each twist (deg) on the branch nearest its reference: reference + (twist - reference)
    wrapped into [-180, 180). 3DNA's twist lies in (-180, 180]; a step whose pairs are broken
    can cross that cut between two frames, a 360-degree jump that is no motion at all."""
    t = np.asarray(twist_deg, float)
    r = np.asarray(reference_deg, float)
    return t + 360.0 * np.round((r - t) / 360.0)     # exactly t where no turn is added


def circular_mean_deg(angles_deg, axis=0):
    """The direction of the mean unit vector of angles (deg), in (-180, 180]."""
    a = np.radians(np.asarray(angles_deg, float))
    return np.degrees(np.arctan2(np.sin(a).mean(axis=axis), np.cos(a).mean(axis=axis)))


def twist_continuous_in_time(q):
    """Step parameters (T, ..., 6) with each step's twist on the branch nearest its circular
    mean over time: the cut moves from +-180 degrees to the mean +- 180 (about -146 and 214
    degrees for B-DNA), where no step, closed or frayed, goes between frames; a broken step
    that crosses +-180 is then continuous. Not np.unwrap along time: a broken step's twist
    can wander across the cut several times, and unwrapping would carry a 360-degree offset
    into the frames after the pair has closed again. Where twist enters a time-series
    analysis (mode spectra, coarse-graining) it comes through here or through
    unwrap_twist_deg with the same kind of reference; a single structure keeps 3DNA's
    convention."""
    out = np.array(q, dtype=float, copy=True)
    if out.shape[0] > 1:
        out[..., 5] = unwrap_twist_deg(out[..., 5], circular_mean_deg(out[..., 5], axis=0))
    return out


def step_transform(params):
    """Frame of base pair 2 in the frame of base pair 1 (tech-details Eqs 6-8).

    params (..., 6) = (shift, slide, rise, tilt, roll, twist) in (length, deg).
    Returns (R_rel (..., 3, 3), o_rel (..., 3), Rm_rel (..., 3, 3)): base pair 2
    has axes R1 @ R_rel and origin o1 + R1 @ o_rel; the mid-step frame has
    axes R1 @ Rm_rel and origin o1 + R1 @ o_rel / 2.
    """
    p = np.asarray(params, dtype=float)
    tilt, roll, twist = np.radians(p[..., 3]), np.radians(p[..., 4]), np.radians(p[..., 5])
    bend = np.hypot(tilt, roll)
    phi = np.arctan2(tilt, roll)
    Rm = rot_z(0.5 * twist - phi) @ rot_y(0.5 * bend) @ rot_z(phi)
    R_rel = rot_z(0.5 * twist - phi) @ rot_y(bend) @ rot_z(0.5 * twist + phi)
    o_rel = np.einsum("...ij,...j->...i", Rm, p[..., :3])
    return R_rel, o_rel, Rm


def next_frame(R1, o1, params):
    """Frame (R2, o2) of the base pair that follows (R1, o1) by `params`."""
    R_rel, o_rel, _ = step_transform(params)
    R1 = np.asarray(R1, dtype=float)
    return R1 @ R_rel, np.asarray(o1, dtype=float) + np.einsum("...ij,...j->...i", R1, o_rel)


def frames_from_steps(params, R0=None, o0=None):
    """Chain of base-pair frames from step parameters (3DNA `rebuild`).

    params (..., n_steps, 6); R0 (..., 3, 3) and o0 (..., 3) the first frame
    (identity and zero by default). Returns R (..., n_steps + 1, 3, 3) and
    o (..., n_steps + 1, 3). Vectorised over leading axes; the loop runs over
    steps only, which are sequential by nature.
    """
    p = np.asarray(params, dtype=float)
    if p.ndim < 2 or p.shape[-1] != 6:
        raise InputError(f"step parameters: need (..., n_steps, 6) (shift, slide, rise, tilt, roll, "
                         f"twist), got shape {p.shape}")
    if not np.all(np.isfinite(p)):
        raise InputError("step parameters contain NaN/Inf")
    lead = p.shape[:-2]
    n = p.shape[-2]
    R_rel, o_rel, _ = step_transform(p)
    R = np.empty(lead + (n + 1, 3, 3))
    o = np.empty(lead + (n + 1, 3))
    R[..., 0, :, :] = np.eye(3) if R0 is None else R0
    o[..., 0, :] = 0.0 if o0 is None else o0
    for i in range(n):
        Ri = R[..., i, :, :]
        o[..., i + 1, :] = o[..., i, :] + np.einsum("...ij,...j->...i", Ri, o_rel[..., i, :])
        R[..., i + 1, :, :] = Ri @ R_rel[..., i, :, :]
    return R, o


def flip_strand_II(R):
    """Strand II base frame with its y and z axes reversed (a 180-degree turn
    about x), so that it points like strand I's (Olson et al. 2001)."""
    F = np.array(R, dtype=float, copy=True)
    F[..., :, 1:] *= -1.0
    return F


def base_pair_parameters(R_I, o_I, R_II, o_II):
    """Base-pair parameters and the base-pair frame, 3DNA's way.

    R_I, o_I: base frame of the strand I base; R_II, o_II: base frame of the
    strand II base AS FITTED (this function reverses its y and z axes). As in
    3DNA, the CEHS analysis runs from the (flipped) strand II base to the
    strand I base; the middle frame is the base-pair frame.
    Returns (params (..., 6) = shear, stretch, stagger [length], buckle,
    propeller, opening [deg]; R_bp (..., 3, 3); o_bp (..., 3)).
    """
    return cehs(flip_strand_II(R_II), o_II, R_I, o_I)


def base_pair_frames(R_I, o_I, R_II, o_II):
    """Base-pair frames (R_bp, o_bp) from the two base frames (see base_pair_parameters)."""
    _, Rbp, obp = base_pair_parameters(R_I, o_I, R_II, o_II)
    return Rbp, obp


def base_frames_from_pair(params, R_bp, o_bp):
    """Inverse of base_pair_parameters: the two base frames (R_I, o_I, R_II, o_II)
    (R_II as fitted, i.e. un-flipped) from the base-pair frame and the six
    base-pair parameters."""
    R_rel, o_rel, Rm_rel = step_transform(params)
    R_bp = np.asarray(R_bp, dtype=float)
    # The pair frame is the middle frame: R_IIf = R_bp Rm_rel^T, o_IIf = o_bp - R_IIf o_rel / 2.
    R_IIf = R_bp @ transpose(Rm_rel)
    o_II = np.asarray(o_bp, dtype=float) - 0.5 * np.einsum("...ij,...j->...i", R_IIf, o_rel)
    R_I = R_IIf @ R_rel
    o_I = o_II + np.einsum("...ij,...j->...i", R_IIf, o_rel)
    return R_I, o_I, flip_strand_II(R_IIf), o_II
