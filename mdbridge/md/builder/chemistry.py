"""Is a built duplex chemically sane? Two numbers, with the atoms named.

1. Backbone links: the O3'(i) - P(i+1) distance along each strand (and
   through the box when periodic). A covalent O3'-P bond is 1.6 A (CHARMM27
   equilibrium 1.61 A); rigid templates placed on arbitrary frames stretch or
   compress it, so the worst link says how far the frames are from what the
   sugar-phosphate backbone can join.
2. Closest non-bonded heavy-atom pair: all heavy pairs that are neither 1-2
   nor 1-3 bonded (bonds from the template bond lists + the O3'-P links), by
   minimum image when periodic. Below ~2.2 A atoms overlap (van der Waals
   contact of C, N, O is ~3 A; a hydrogen bond donor-acceptor pair ~2.8 A).
   In a rigid ideal nucleotide the closest such pair is a 1-4 pair across a
   base ring (~2.6 A), which no input can change, so the pair between
   DIFFERENT nucleotides is reported as well: that one measures the frames.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from mdbridge.md.builder.structure import Structure

O3P_IDEAL = 1.60  # A, covalent O3'-P bond
SEARCH_RADIUS = 4.0  # A, non-bonded search (DNA always has heavy pairs closer than this)


@dataclass(frozen=True)
class AtomPair:
    distance: float
    atom_a: str
    atom_b: str

    def __str__(self):
        return f"{self.distance:.3f} A ({self.atom_a} - {self.atom_b})"


@dataclass(frozen=True)
class StrandLinks:
    strand: str
    n_links: int
    shortest: AtomPair
    longest: AtomPair
    worst: AtomPair  # largest |d - 1.60 A|
    junction: AtomPair | None  # the last -> first link (through the box, or closing a ring)


@dataclass(frozen=True)
class ChemistryReport:
    links: tuple          # StrandLinks per strand
    closest_nonbonded: AtomPair | None               # any two atoms
    closest_between_nucleotides: AtomPair | None     # atoms of different residues
    periodic: bool

    def worst_link_deviation(self) -> float:
        return max(abs(s.worst.distance - O3P_IDEAL) for s in self.links if s.n_links)

    def ok(self, link_tolerance: float = 0.1, min_nonbonded: float = 2.2) -> bool:
        """True when every O3'-P link is 1.6 +/- link_tolerance A and no two
        non-bonded heavy atoms are closer than min_nonbonded A."""
        links_ok = all(abs(s.worst.distance - O3P_IDEAL) <= link_tolerance
                       for s in self.links if s.n_links)
        nb = self.closest_nonbonded
        return links_ok and (nb is None or nb.distance >= min_nonbonded)

    def __str__(self):
        lines = ["chemistry check" + (" (periodic, minimum image)" if self.periodic else "")]
        for s in self.links:
            if not s.n_links:
                lines.append(f"  strand {s.strand}: no O3'-P links (single nucleotide)")
                continue
            lines.append(f"  strand {s.strand}: {s.n_links} O3'-P links, "
                         f"shortest {s.shortest}, longest {s.longest}")
            if s.junction is not None:
                lines.append(f"    junction {'through the box' if self.periodic else 'closing the ring'}: "
                             f"{s.junction}")
        nb = self.closest_nonbonded
        none = f"none within {SEARCH_RADIUS} A"
        lines.append("  closest non-bonded heavy atoms (not 1-2 or 1-3 bonded): "
                     + (str(nb) if nb else none))
        nb2 = self.closest_between_nucleotides
        lines.append("    of them between different nucleotides: " + (str(nb2) if nb2 else none))
        verdict = "OK" if self.ok() else "PROBLEM"
        lines.append(f"  verdict: {verdict} (O3'-P = {O3P_IDEAL} +/- 0.1 A and no non-bonded "
                     "heavy pair below 2.2 A)")
        return "\n".join(lines)


def _links(s: Structure, strand: str) -> StrandLinks:
    sel = s.strands == strand
    resids = np.unique(s.resids[sel])
    o3 = [s.index(r, "O3'") for r in resids]
    p = [s.index(r, "P") for r in resids]
    pairs = list(zip(o3[:-1], p[1:]))
    junction_pair = (o3[-1], p[0]) if s.closed and len(resids) > 1 else None
    if junction_pair is not None:
        pairs.append(junction_pair)
    if not pairs:
        dummy = AtomPair(float("nan"), "", "")
        return StrandLinks(strand, 0, dummy, dummy, dummy, None)
    a, b = np.array(pairs).T
    d = np.linalg.norm(s.minimum_image(s.coords[b] - s.coords[a]), axis=1)
    pair = [AtomPair(float(d[k]), s.label(a[k]), s.label(b[k])) for k in range(len(d))]
    return StrandLinks(strand, len(d), pair[int(np.argmin(d))], pair[int(np.argmax(d))],
                       pair[int(np.argmax(np.abs(d - O3P_IDEAL)))],
                       pair[-1] if junction_pair is not None else None)


def excluded_pairs(n_atoms: int, bonds: np.ndarray) -> set:
    """Pairs (i < j) that are 1-2 or 1-3 bonded, as keys i * n_atoms + j."""
    neighbours: list[list[int]] = [[] for _ in range(n_atoms)]
    for i, j in bonds:
        neighbours[i].append(j)
        neighbours[j].append(i)
    out: set[int] = set()
    for i in range(n_atoms):
        reach = set(neighbours[i])
        for j in neighbours[i]:
            reach.update(neighbours[j])
        reach.discard(i)
        out.update(min(i, j) * n_atoms + max(i, j) for j in reach)
    return out


def closest_nonbonded_heavy(s: Structure) -> tuple[AtomPair | None, AtomPair | None]:
    """Closest heavy pair that is not 1-2 or 1-3 bonded: (any two atoms, atoms
    of different nucleotides); None when nothing is within SEARCH_RADIUS."""
    heavy = np.flatnonzero(s.elements != "H")
    x = s.coords[heavy]
    if s.box is None:
        tree = cKDTree(x)
    else:
        # cKDTree's periodic mode needs every coordinate in [0, boxsize); give
        # the non-periodic directions a box wider than the molecule plus the
        # search radius so nothing meets itself across them.
        box = np.asarray(s.box, dtype=float)
        periodic = box > 0
        lo = x.min(axis=0)
        x = x - lo
        span = x.max(axis=0) + 2 * SEARCH_RADIUS + 1.0
        size = np.where(periodic, box, span)
        x = np.where(periodic, np.mod(x, size), x)
        x = np.where(x >= size, 0.0, x)  # mod can round up to size itself
        tree = cKDTree(x, boxsize=size)
    pairs = tree.query_pairs(SEARCH_RADIUS, output_type="ndarray")
    if len(pairs) == 0:
        return None, None
    a, b = heavy[pairs[:, 0]], heavy[pairs[:, 1]]
    lo_, hi_ = np.minimum(a, b), np.maximum(a, b)
    excl = excluded_pairs(s.n_atoms, s.bonds)
    keep = np.array([int(i) * s.n_atoms + int(j) not in excl for i, j in zip(lo_, hi_)], dtype=bool)
    a, b = lo_[keep], hi_[keep]
    d = np.linalg.norm(s.minimum_image(s.coords[b] - s.coords[a]), axis=1)

    def closest(mask):
        if not mask.any():
            return None
        k = np.flatnonzero(mask)[np.argmin(d[mask])]
        return AtomPair(float(d[k]), s.label(int(a[k])), s.label(int(b[k])))

    return closest(np.ones(len(d), dtype=bool)), closest(s.resids[a] != s.resids[b])


def check_chemistry(s: Structure) -> ChemistryReport:
    """O3'-P links per strand and the closest non-bonded heavy pair of `s`."""
    any_pair, between = closest_nonbonded_heavy(s)
    return ChemistryReport(links=tuple(_links(s, st) for st in ("I", "II")),
                           closest_nonbonded=any_pair, closest_between_nucleotides=between,
                           periodic=s.box is not None)
