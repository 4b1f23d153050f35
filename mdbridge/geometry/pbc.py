"""Minimum-image vectors for periodic boxes (MDAnalysis `dimensions`:
a, b, c [A], alpha, beta, gamma [deg]), vectorised over leading axes.

Periodic, ligated duplexes (GROMACS `periodic-molecules`) keep atoms wrapped
into the box and no tool can make an infinite molecule whole, so every vector
inside a base, across a pair, and along a step is taken as a minimum image.
Rounding fractional coordinates gives the true minimum image for any vector
shorter than half the smallest box height, which is all we need (bonds, base
sizes, base-pair steps).
"""
from __future__ import annotations

import numpy as np


def box_matrix(dimensions):
    """Box vectors as ROWS (..., 3, 3) from (..., 6) dimensions (GROMACS/MDAnalysis
    convention: a along x, b in the xy plane)."""
    d = np.asarray(dimensions, dtype=float)
    a, b, c = d[..., 0], d[..., 1], d[..., 2]
    al, be, ga = np.radians(d[..., 3]), np.radians(d[..., 4]), np.radians(d[..., 5])
    M = np.zeros(d.shape[:-1] + (3, 3))
    M[..., 0, 0] = a
    M[..., 1, 0] = b * np.cos(ga)
    M[..., 1, 1] = b * np.sin(ga)
    cx = c * np.cos(be)
    cy = c * (np.cos(al) - np.cos(be) * np.cos(ga)) / np.sin(ga)
    M[..., 2, 0] = cx
    M[..., 2, 1] = cy
    M[..., 2, 2] = np.sqrt(np.maximum(c * c - cx * cx - cy * cy, 0.0))
    return M


def minimum_image(v, dimensions):
    """Minimum-image version of vectors v (..., 3) in the box `dimensions`
    (broadcastable (..., 6)). Returns v unchanged where the box is absent
    (all zeros), as MDAnalysis reports for non-periodic files."""
    v = np.asarray(v, dtype=float)
    if dimensions is None:
        return v
    d = np.asarray(dimensions, dtype=float)
    M = box_matrix(d)                                   # rows = box vectors
    valid = np.all(d[..., :3] > 0, axis=-1)
    Msafe = np.where(valid[..., None, None], M, np.eye(3))
    frac = np.einsum("...i,...ij->...j", v, np.linalg.inv(Msafe))
    frac = frac - np.where(valid[..., None], np.round(frac), 0.0)
    return np.einsum("...j,...ji->...i", frac, Msafe)
