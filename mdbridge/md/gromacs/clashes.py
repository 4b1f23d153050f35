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
# Heavy atoms (mass > 1.5 u) beyond 1-4 closer than this overlap: the shortest contact
# between non-bonded heavy atoms of DNA is a hydrogen bond's donor-acceptor distance,
# 2.6-3.0 A.
HEAVY_CLASH_A = 2.2
SEARCH_A = 3.0  # pairs are looked for within this distance


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


def closest_contact(x_A, box_A, mols: list[Molecule], names, resids, cutoff_A: float = SEARCH_A) -> dict:
    """The closest non-bonded pair (beyond 1-4) of any atoms and of heavy atoms (mass >
    1.5 u), with the numbers of pairs closer than CLASH_A and HEAVY_CLASH_A; distances None
    when no pair is within cutoff_A."""
    from scipy.spatial import cKDTree
    x = np.mod(np.asarray(x_A, float), box_A)
    tree = cKDTree(x, boxsize=np.asarray(box_A, float))
    pairs = tree.query_pairs(cutoff_A, output_type="ndarray")
    excl = excluded_pairs(mols)
    keep = np.array([(int(a), int(b)) not in excl for a, b in pairs], dtype=bool)
    pairs = pairs[keep] if len(pairs) else pairs
    if len(pairs) == 0:
        r = np.zeros(0)
    else:
        d = x[pairs[:, 1]] - x[pairs[:, 0]]
        d -= box_A * np.round(d / box_A)
        r = np.linalg.norm(d, axis=1)
    heavy = np.concatenate([np.asarray(m.mass, float) for m in mols]) > 1.5
    both = heavy[pairs[:, 0]] & heavy[pairs[:, 1]] if len(pairs) else np.zeros(0, bool)

    def closest(mask):
        if not mask.any():
            return None, None
        k = int(np.flatnonzero(mask)[np.argmin(r[mask])])
        a, b = pairs[k]
        return float(r[k]), [f"{resids[a]}:{names[a]}", f"{resids[b]}:{names[b]}"]
    d_any, atoms_any = closest(np.ones(len(r), bool))
    d_heavy, atoms_heavy = closest(both)
    return {"min_distance_A": d_any, "atoms": atoms_any,
            "n_below_clash": int((r < CLASH_A).sum()), "clash_threshold_A": CLASH_A,
            "heavy": {"min_distance_A": d_heavy, "atoms": atoms_heavy,
                      "n_below_clash": int((r[both] < HEAVY_CLASH_A).sum()), "clash_threshold_A": HEAVY_CLASH_A},
            "searched_within_A": float(cutoff_A)}


def clashes(contact: dict) -> int:
    """Pairs of a `closest_contact` record that clash: any atoms closer than CLASH_A plus heavy
    atoms closer than HEAVY_CLASH_A (a heavy pair below CLASH_A counts in both)."""
    return int(contact["n_below_clash"] + contact["heavy"]["n_below_clash"])


def contact_words(contact: dict) -> str:
    """The closest pairs and the clash counts in words."""
    def one(c, what):
        if c["min_distance_A"] is None:
            return f"no {what} pair within {contact['searched_within_A']:g} A"
        return (f"closest {what} pair {c['atoms'][0]}-{c['atoms'][1]} at {c['min_distance_A']:.2f} A, "
                f"{c['n_below_clash']} closer than {c['clash_threshold_A']:g} A")
    return one(contact, "atom") + "; " + one(contact["heavy"], "heavy-atom") + " (non-bonded, beyond 1-4)"
