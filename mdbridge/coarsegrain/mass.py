"""Mass and inertia of each base pair, and the rod's rho and I.

The atoms of base pair i are those of its two nucleotides (base, sugar and
phosphate; hydrogens if the topology has them). Positions are taken relative to
the base-pair frame's origin o_i (3DNA's base-pair origin, the mid-point of the two
base origins, which sits on the rod's centreline: mdbridge.rod.frames puts base pair i
at r(s_i)) and expressed in the base-pair axes (x = d1 toward the major groove,
y = d2, z = d3 along the helix), as minimum images when there is a box.

* mass (amu) and the full inertia tensor about o_i, sum m (|r|^2 1 - r r^T) (amu A^2),
  averaged over frames (what the per-step file stores);
* the rod's densities per unit length, with the thin-slice convention of a rod's
  cross-section (the paper's I* = diag(1, 1, 2)): the z extent of a base pair is
  along the rod and does not count, so I_11 = sum m y^2, I_22 = sum m x^2,
  I_33 = sum m (x^2 + y^2), I_12 = -sum m x y, each divided by the mean rise;
  rho = mass / mean rise.
"""
from __future__ import annotations

import numpy as np

from .constants import AMU, ANGSTROM


def pair_atom_indices(pairs) -> list[np.ndarray]:
    """Atom indices of the two nucleotides of each pair [(res_I, res_II)]."""
    return [np.concatenate([r1.atoms.indices, r2.atoms.indices]) for r1, r2 in pairs]


def frame_inertia(positions, masses, origin, R, box=None):
    """(mass, full inertia (3, 3), slice inertia (3, 3)) of one base pair in one frame:
    positions (n, 3) A, masses (n,), origin (3,), R (3, 3) columns = axes."""
    from mdbridge.geometry.pbc import minimum_image
    d = positions - origin
    if box is not None:
        d = minimum_image(d, box)
    r = d @ R                                 # coordinates in the base-pair axes
    m = masses
    full = np.eye(3) * np.sum(m * np.sum(r * r, axis=1)) - np.einsum("n,ni,nj->ij", m, r, r)
    xy = r.copy()
    xy[:, 2] = 0.0
    sl = np.eye(3) * np.sum(m * np.sum(xy * xy, axis=1)) - np.einsum("n,ni,nj->ij", m, xy, xy)
    return float(m.sum()), full, sl


def rod_densities(mass_amu, slice_inertia_amuA2, rise_A):
    """rho (kg/m) and I (3, 3) (kg m) per unit length from a base pair's mass and
    slice inertia and the rise."""
    rho = mass_amu * AMU / (rise_A * ANGSTROM)
    I = np.asarray(slice_inertia_amuA2) * AMU * ANGSTROM ** 2 / (rise_A * ANGSTROM)
    return rho, I
