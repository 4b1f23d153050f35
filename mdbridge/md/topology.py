"""Linking number, twist and writhe of an all-atom DNA duplex, frame by frame
(docs/topology.md).

An MD folder of the toolkit (`dnarod build-md`, `dnarod run-md`): md.tpr + md.xtc when
the run has been made, else the built conf.gro. The strands are the C1' atoms, paired as
the builder numbers them (`mdbridge.md.builder.duplex.base_pairs`: residue k of strand I
with residue 2n + 1 - k of strand II). Atoms are wrapped in the box, so each strand is
followed by minimum-image steps and strand II is placed by the minimum image of each
pair; the sum of the steps around strand I is 0 for a ring closed inside the box, and
the box vector the duplex spans for the ligated, box-periodic duplex.
The numbers themselves are mdbridge.geometry.topology's `duplex_topology`.
"""
from __future__ import annotations

import warnings

import numpy as np

from dna_models.errors import InputError
from mdbridge.geometry.pbc import minimum_image
from mdbridge.geometry.structure import load_universe
from mdbridge.geometry.topology import duplex_topology

from .builder.duplex import base_pairs
from .folder import md_files

STRAND_ATOM = ("C1'", "C1*")


def strand_atoms(universe, source: str):
    """(strand I atoms, strand II atoms), one C1' per base pair, both in the order of
    strand I."""
    import MDAnalysis as mda
    residues = {int(r.resid): r for r in universe.residues}
    if len(residues) < 8 or len(residues) % 2:
        raise InputError(f"{source}: {len(residues)} residues; a duplex of n >= 4 base pairs has 2 n, "
                         "residues 1..n strand I and n+1..2n strand II (the builder's numbering)")
    n = len(residues) // 2

    def c1(resid):
        if resid not in residues:
            raise InputError(f"{source}: residue {resid} missing (expected residues 1..{2 * n})")
        sel = [a for a in residues[resid].atoms if a.name in STRAND_ATOM]
        if len(sel) != 1:
            r = residues[resid]
            raise InputError(f"{source}: residue {r.resname}{resid} has {len(sel)} atoms named C1' "
                             "(or C1*); exactly one is needed")
        return sel[0]
    pairs = base_pairs(n)
    return (mda.AtomGroup([c1(i) for i, _ in pairs]), mda.AtomGroup([c1(j) for _, j in pairs]))


def unwrapped_strands(I, II, dimensions):
    """Strands I and II (n, 3) made continuous, and the period vector (3,) or None for a
    ring closed in the box: minimum-image steps along strand I (the closing step
    included: their sum is the period) and across each pair."""
    box = None if dimensions is None or not np.all(np.asarray(dimensions)[:3] > 0) else dimensions
    steps = minimum_image(np.roll(I, -1, axis=0) - I, box)
    length = np.linalg.norm(steps, axis=1)
    if length[-1] > 2.0 * length[:-1].max():
        raise InputError(f"strand I is not joined from its last base pair to its first: {length[-1]:.1f} A "
                         f"between their C1' atoms, the other steps at most {length[:-1].max():.1f} A; "
                         "Lk, Tw and Wr need a ring or a duplex ligated across the box (docs/topology.md)")
    xI = I[0] + np.concatenate([np.zeros((1, 3)), np.cumsum(steps[:-1], axis=0)])
    xII = xI + minimum_image(II - I, box)
    period = steps.sum(axis=0)
    return xI, xII, (None if np.linalg.norm(period) < 1.0 else period)


def md_topology(folder) -> dict:
    """Per frame of the MD folder: time_ps, Lk, Tw, Wr, Wr_bp_centres, bp_per_turn
    (lists), and closed, n_bp."""
    files = md_files(folder)
    u = load_universe(*files)
    source = " + ".join(str(f) for f in files)
    a, b = strand_atoms(u, source)
    out: dict = {k: [] for k in ("time_ps", "Lk", "Tw", "Wr", "Wr_bp_centres", "bp_per_turn")}
    closed = None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # "Reader has no dt information" for a GRO file
        for ts in u.trajectory:
            try:
                xI, xII, period = unwrapped_strands(a.positions.astype(float), b.positions.astype(float),
                                                    ts.dimensions)
            except InputError as e:
                raise InputError(f"{source}, frame {ts.frame}: {e}") from None
            if closed is None:
                closed = period is None
            elif closed != (period is None):
                raise InputError(f"{source}: frame {ts.frame} is {'box-periodic' if closed else 'a ring'}, "
                                 f"frame 0 {'a ring' if closed else 'box-periodic'}")
            r = duplex_topology(xI, xII, period)
            out["time_ps"].append(float(ts.time))
            for k in ("Lk", "Tw", "Wr", "Wr_bp_centres", "bp_per_turn"):
                out[k].append(r[k])
    out.update(closed=bool(closed), n_bp=len(a))
    return out
