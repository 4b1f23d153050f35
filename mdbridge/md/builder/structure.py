"""`Structure`: a built duplex as plain numpy arrays (one row per atom)."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass
class Structure:
    """Atoms of a double-stranded DNA, strand I then strand II, each 5'->3'.

    names     CHARMM27 atom names (O1P, O2P, C5M, H5'1, ...)
    resnames  DA, DC, DG, DT
    resids    1..n on strand I, n+1..2n on strand II (3DNA's numbering:
              residue n+1 pairs with base pair n, residue 2n with base pair 1)
    strands   "I" or "II" (written as chain A / B and segid I / II)
    elements  element symbols
    coords    (n_atoms, 3) in A, whole (never wrapped into the box)
    bonds     (n_bonds, 2) atom indices of covalent bonds between the atoms
              present (template bonds + O3'(i)-P(i+1) links, + the junction
              links through the box when periodic)
    base_origins, base_R  (2n, 3), (2n, 3, 3): the base frame each residue
              was placed with (row resid - 1): x_atom = o + R x_template
    box       None (not periodic) or (3,) orthorhombic box edges in A, 0 for a
              non-periodic direction (e.g. (0, 0, L) for a helix periodic along z)
    ring      True: a duplex closed in space (a minicircle), each strand's last O3'
              bonded to its first P with no box
    """

    names: np.ndarray
    resnames: np.ndarray
    resids: np.ndarray
    strands: np.ndarray
    elements: np.ndarray
    coords: np.ndarray
    bonds: np.ndarray = field(default_factory=lambda: np.zeros((0, 2), dtype=int))
    box: np.ndarray | None = None
    base_origins: np.ndarray | None = None
    base_R: np.ndarray | None = None
    ring: bool = False

    @property
    def closed(self) -> bool:
        """Each strand's last residue is bonded to its first: through the box (periodic)
        or in space (a ring)."""
        return self.box is not None or self.ring

    @property
    def n_atoms(self) -> int:
        return len(self.names)

    def label(self, k: int) -> str:
        """Human name of atom k, e.g. "I:DG2:O3'" (strand:residue:atom)."""
        return f"{self.strands[k]}:{self.resnames[k]}{self.resids[k]}:{self.names[k]}"

    def index(self, resid: int, name: str) -> int:
        """Index of atom `name` of residue `resid`; KeyError if absent."""
        hit = np.flatnonzero((self.resids == resid) & (self.names == name))
        if len(hit) != 1:
            raise KeyError(f"atom {name} of residue {resid}: {len(hit)} matches")
        return int(hit[0])

    def residue_frame(self, resid: int):
        """(origin, R) of the base frame residue `resid` was placed with."""
        if self.base_origins is None or self.base_R is None:
            raise ValueError("this structure carries no base frames (it was not built by the builder)")
        return self.base_origins[resid - 1], self.base_R[resid - 1]

    def minimum_image(self, d: np.ndarray) -> np.ndarray:
        """Difference vectors d (..., 3) reduced to the minimum image along the
        periodic directions of the box (unchanged if not periodic)."""
        if self.box is None:
            return d
        box = np.asarray(self.box, dtype=float)
        periodic = box > 0
        d = np.array(d, dtype=float, copy=True)
        d[..., periodic] -= box[periodic] * np.round(d[..., periodic] / box[periodic])
        return d
