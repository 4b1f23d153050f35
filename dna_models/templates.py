"""Rigid nucleotide templates in the standard base frame, with their bonds.

Heavy atoms come from dna_models.nucleotides (3DNA's B-DNA set, C2'-endo,
chi = -110 deg, CHARMM27 names). Hydrogens, when asked for, come from
dna_models/data/h_charmm27_bdna.json: the positions GROMACS pdb2gmx gives the
CHARMM27 hydrogens on these very templates (see that file's provenance).

Bonds are derived once per template by a distance criterion on the ideal
geometry: heavy-heavy < 1.9 A, X-H < 1.3 A. The ideal templates have all
covalent bonds below 1.65 A and every other heavy pair above 2.1 A, so the
criterion is unambiguous (tests/python/test_builder_templates.py checks it).
"""
from __future__ import annotations

import json
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np

from dna_models.errors import InputError

HEAVY_BOND_MAX = 1.9  # A
H_BOND_MAX = 1.3  # A
H_DATA = Path(__file__).resolve().parent / "data" / "h_charmm27_bdna.json"


@dataclass(frozen=True)
class NucleotideTemplate:
    base: str
    names: np.ndarray      # (m,) CHARMM27 atom names
    elements: np.ndarray   # (m,)
    coords: np.ndarray     # (m, 3) A, standard base frame
    bonds: np.ndarray      # (b, 2) indices into names
    index: dict            # name -> row


def _heavy_atoms(base: str) -> dict:
    """{name: xyz} of the B-DNA nucleotide `base` from dna_models.nucleotides."""
    from dna_models import nucleotides
    nt = nucleotides.bdna_nucleotide(base)
    atoms = getattr(nt, "atoms", nt)
    return {str(k): np.asarray(v, dtype=float) for k, v in atoms.items()}


def _hydrogens(base: str) -> dict:
    if not H_DATA.is_file():
        raise InputError(f"hydrogen templates {H_DATA} are missing; build heavy atoms only "
                         "(hydrogens=False) and let gmx pdb2gmx -ignh add them")
    data = json.loads(H_DATA.read_text())
    return {k: np.asarray(v, dtype=float) for k, v in data["nucleotides"]["D" + base].items()}


def element_of(name: str) -> str:
    # CHARMM27 nucleic-acid names start with their element (C, N, O, P, H)
    return name[0]


def bonds_by_distance(names, coords) -> np.ndarray:
    """Covalent bonds of one ideal residue: heavy-heavy < 1.9 A, X-H < 1.3 A."""
    el = np.array([element_of(n) for n in names])
    d = np.linalg.norm(coords[:, None, :] - coords[None, :, :], axis=-1)
    is_h = el == "H"
    cutoff = np.where(is_h[:, None] | is_h[None, :], H_BOND_MAX, HEAVY_BOND_MAX)
    i, j = np.nonzero(np.triu(d < cutoff, k=1))
    return np.stack([i, j], axis=1)


@lru_cache(maxsize=None)
def nucleotide_template(base: str, hydrogens: bool = False) -> NucleotideTemplate:
    base = base.upper()
    if base not in "ACGT" or len(base) != 1:
        raise InputError(f"nucleotide {base!r}: allowed A, C, G, T")
    atoms = _heavy_atoms(base)
    if hydrogens:
        atoms.update(_hydrogens(base))
    names = np.array(list(atoms))
    coords = np.array([atoms[n] for n in names])
    coords.setflags(write=False)
    return NucleotideTemplate(base=base, names=names,
                              elements=np.array([element_of(n) for n in names]),
                              coords=coords, bonds=bonds_by_distance(names, coords),
                              index={n: k for k, n in enumerate(names)})
