"""Standard bases and B-DNA nucleotide templates in the standard reference frame.

Data (with citations) live in `dna_models/data/standard_bases.json` (Olson et
al. 2001 frame, Clowney 1996 geometry, 3DNA v2.3 Atomic_?.pdb) and
`dna_models/data/bdna_nucleotides.json` (3DNA v2.3 BDNA_?.pdb, CHARMM27 names).
Frame: x toward the major groove, y toward the strand I backbone, z = x cross y;
coordinates in Angstrom.
"""
from __future__ import annotations

import json
from functools import lru_cache
from pathlib import Path

import numpy as np

from .errors import InputError

DATA = Path(__file__).resolve().parent / "data"
BASES = ("A", "C", "G", "T")
PURINES = ("A", "G")
#: GROMACS charmm27.ff residue names of the DNA nucleotides
CHARMM_RESNAME = {"A": "DA", "C": "DC", "G": "DG", "T": "DT"}
#: The Watson-Crick hydrogen bonds of each pair, keyed by its purine, as (purine donor or
#: acceptor, pyrimidine partner) heavy-atom names; N1-N3 first, the central bond of both
#: pairs and the one that defines an open pair (mdbridge/md/integrity.py). Saenger,
#: "Principles of Nucleic Acid Structure" (1984), Fig. 6-1.
WATSON_CRICK_HBONDS = {"A": (("N1", "N3"), ("N6", "O4")),
                       "G": (("N1", "N3"), ("O6", "N4"), ("N2", "O2"))}


@lru_cache(maxsize=None)
def _load(name):
    with open(DATA / name) as f:
        return json.load(f)


def _check_base(name: str) -> str:
    b = str(name).upper()
    if b not in BASES:
        raise InputError(f"unknown base {name!r}: allowed A, C, G, T")
    return b


def ring_atom_names(base: str) -> tuple:
    """Ring atoms 3DNA fits (Lu & Olson 2003): nine for purines, six for pyrimidines,
    in the order C4 N3 C2 N1 C6 C5 [N7 C8 N9]."""
    b = _check_base(base)
    rings = _load("standard_bases.json")["ring_atoms"]
    return tuple(rings["purine" if b in PURINES else "pyrimidine"])


def standard_base(name: str) -> dict:
    """{atom: {"xyz": np.array(3), "ring": bool}} for standard base A, C, G or T
    (base atoms + C1') in the standard reference frame."""
    b = _check_base(name)
    ring = set(ring_atom_names(b))
    atoms = _load("standard_bases.json")["bases"][b]
    return {a: {"xyz": np.array(x, dtype=float), "ring": a in ring} for a, x in atoms.items()}


def standard_ring_coordinates(name: str) -> np.ndarray:
    """(n_ring, 3) standard coordinates of the ring atoms, order of ring_atom_names."""
    b = _check_base(name)
    atoms = _load("standard_bases.json")["bases"][b]
    return np.array([atoms[a] for a in ring_atom_names(b)], dtype=float)


def bdna_nucleotide(name: str) -> dict:
    """{atom: np.array(3)} heavy atoms of a B-DNA nucleotide (base + sugar +
    5' phosphate) in the base's standard frame; CHARMM27 atom names (O1P, O2P, C5M).
    The GROMACS residue name is CHARMM_RESNAME[name]."""
    b = _check_base(name)
    atoms = _load("bdna_nucleotides.json")["nucleotides"][b]
    return {a: np.array(x, dtype=float) for a, x in atoms.items()}
