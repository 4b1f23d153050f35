"""Base-pair integrity of an MD duplex: are the Watson-Crick pairs still paired?

A pair counts as intact when the distance between the purine N1 and the pyrimidine N3
(the central hydrogen bond of both A-T and G-C) is below 3.5 A (~2.9 A in B-DNA).
Distances are minimum images (MDAnalysis `calc_bonds` with the frame's box): a ligated,
periodic duplex keeps its atoms wrapped (docs/md.md). The one definition for the MD's own
checks.json (mdbridge/md/gromacs/checks.py), the comparison's analysis and the
coarse-graining's exclusion of open pairs.
"""
from __future__ import annotations

import numpy as np
from MDAnalysis.lib.distances import calc_bonds

from dna_models.errors import InputError
from dna_models.nucleotides import PURINES

INTACT_CUTOFF_A = 3.5


def _central_atom(residue):
    base = residue.resname.strip().upper().lstrip("D")[:1]
    if base in PURINES:
        name = "N1"
    elif base in ("C", "T", "U"):
        name = "N3"
    else:
        raise InputError(f"residue {residue.resname}{residue.resid}: not a DNA base "
                         "(allowed: DA DC DG DT and A C G T)")
    sel = residue.atoms.select_atoms(f"name {name}")
    if len(sel) != 1:
        raise InputError(f"residue {residue.resname}{residue.resid}: atom {name} not found")
    return sel[0]


def central_atoms(pairs):
    """(AtomGroup of strand I's, AtomGroup of strand II's) central N1/N3 atoms of PAIRS
    [(residue of strand I, residue of strand II)]."""
    import MDAnalysis as mda
    return (mda.AtomGroup([_central_atom(r1) for r1, _ in pairs]),
            mda.AtomGroup([_central_atom(r2) for _, r2 in pairs]))


def pair_distances(a_A, b_A, dimensions=None) -> np.ndarray:
    """N1-N3 distances [A] of paired atom positions (n, 3), minimum image in the box
    `dimensions` (MDAnalysis: a, b, c, alpha, beta, gamma); no box when None or empty."""
    box = dimensions if dimensions is not None and np.all(np.asarray(dimensions)[:3] > 0) else None
    return calc_bonds(a_A, b_A, box=box)


def bp_intact_fraction(universe, pairs, start=None, stop=None, step=None,
                       cutoff_A: float = INTACT_CUTOFF_A, progress=None):
    """(times_ps (T,), fraction intact (T,), N1-N3 distances (T, n_bp)).
    progress, if given: progress(frames_done, frames_total) after each frame.

    pairs: [(residue of strand I, residue of strand II)], e.g. `BasePairFrames(u).pairs`.
    """
    a, b = central_atoms(pairs)
    times, per_frame = [], []
    frames = universe.trajectory[start:stop:step]
    for ts in frames:
        per_frame.append(pair_distances(a.positions, b.positions, ts.dimensions))
        times.append(ts.time)
        if progress is not None:
            progress(len(times), len(frames))
    dist = np.array(per_frame)
    return np.array(times), np.mean(dist < cutoff_A, axis=1), dist
