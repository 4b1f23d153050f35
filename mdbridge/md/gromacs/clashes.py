"""Closest non-bonded atom pair of a structure (periodic minimum image).

Nucleotides are placed as rigid templates and pdb2gmx adds hydrogens at ideal
positions, so steps with shear or bend can put an H within ~1.2 A of an atom
of the next nucleotide. MD started from such a contact explodes at step 0;
build-md reports the closest contact and the restrained minimisation removes it.
"""
from __future__ import annotations

import numpy as np

from .topology import Molecule

CLASH_A = 1.5   # closer than this between atoms beyond 1-4: MD will not start


def excluded_pairs(mols: list[Molecule]) -> set[tuple[int, int]]:
    """1-2, 1-3 and 1-4 pairs (0-based, system numbering) of the molecules in order."""
    out: set[tuple[int, int]] = set()
    offset = 0
    for m in mols:
        for kind, ends in (("bonds", (0, 1)), ("angles", (0, 2)), ("pairs", (0, 1)),
                           ("proper_dihedrals", (0, 3))):
            for t in m.terms.get(kind, []):
                a, b = t[ends[0]] - 1 + offset, t[ends[1]] - 1 + offset
                out.add((min(a, b), max(a, b)))
        offset += len(m.atomname)
    return out


def closest_contact(x_A, box_A, mols: list[Molecule], names, resids, cutoff_A: float = 2.5) -> dict:
    from scipy.spatial import cKDTree
    x = np.mod(np.asarray(x_A, float), box_A)
    tree = cKDTree(x, boxsize=np.asarray(box_A, float))
    pairs = tree.query_pairs(cutoff_A, output_type="ndarray")
    if len(pairs) == 0:
        return {"min_distance_A": None, "atoms": None}
    excl = excluded_pairs(mols)
    keep = np.array([(int(a), int(b)) not in excl for a, b in pairs], dtype=bool)
    pairs = pairs[keep]
    if len(pairs) == 0:
        return {"min_distance_A": None, "atoms": None}
    d = x[pairs[:, 1]] - x[pairs[:, 0]]
    d -= box_A * np.round(d / box_A)
    r = np.linalg.norm(d, axis=1)
    k = int(np.argmin(r))
    a, b = pairs[k]
    return {"min_distance_A": float(r[k]),
            "atoms": [f"{resids[a]}:{names[a]}", f"{resids[b]}:{names[b]}"],
            "n_below_clash": int((r < CLASH_A).sum()), "clash_threshold_A": CLASH_A}
