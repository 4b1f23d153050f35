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
from dna_models.nucleotides import PURINES, WATSON_CRICK_HBONDS
from mdbridge.geometry.analysis_base import AnalysisBase, UniverseFrames
from mdbridge.geometry.structure import dna_base

INTACT_CUTOFF_A = 3.5
UNSTACKED_RISE_A = 4.5   # 3DNA's rise of a stacked B-DNA step is 3.3-3.4 A with a spread of ~0.2-0.3 A
                         # (Olson et al. 1998, PNAS 95:11163); above 4.5 A the step's bases no longer
                         # stack, a kink, whatever its pairs do (docs/intact.md)


def _base(residue) -> str:
    return dna_base(residue.resname, f"residue {residue.resname}{residue.resid}")


def _named(residue, name: str):
    sel = residue.atoms.select_atoms(f"name {name}")
    if len(sel) != 1:
        raise InputError(f"residue {residue.resname}{residue.resid}: atom {name} not found")
    return sel[0]


def _central_atom(residue):
    return _named(residue, "N1" if _base(residue) in PURINES else "N3")


def central_atoms(pairs):
    """(AtomGroup of strand I's, AtomGroup of strand II's) central N1/N3 atoms of PAIRS
    [(residue of strand I, residue of strand II)]."""
    import MDAnalysis as mda
    return (mda.AtomGroup([_central_atom(r1) for r1, _ in pairs]),
            mda.AtomGroup([_central_atom(r2) for _, r2 in pairs]))


def hbond_atoms(pairs):
    """(AtomGroup a, AtomGroup b, index (m,) of the pair each H-bond belongs to, slot (m,)
    0..2 within its pair, names [(a, b)]) of every Watson-Crick H-bond of PAIRS
    [(residue of strand I, residue of strand II)]: the donor-acceptor heavy atoms of
    dna_models.nucleotides.WATSON_CRICK_HBONDS, the purine's first, N1-N3 in slot 0."""
    import MDAnalysis as mda
    a, b, pair, slot, names = [], [], [], [], []
    for k, (r1, r2) in enumerate(pairs):
        pu, py = (r1, r2) if _base(r1) in PURINES else (r2, r1)
        for j, (na, nb) in enumerate(WATSON_CRICK_HBONDS[_base(pu)]):
            a.append(_named(pu, na))
            b.append(_named(py, nb))
            pair.append(k)
            slot.append(j)
            names.append((na, nb))
    return mda.AtomGroup(a), mda.AtomGroup(b), np.array(pair), np.array(slot), names


def n1_n3_columns(pair, slot) -> np.ndarray:
    """The columns of hbond_atoms' H-bonds that are each pair's N1-N3 (slot 0), in pair order."""
    return np.flatnonzero(slot == 0)[np.argsort(pair[slot == 0])]


def hbond_table(pairs, distances_A) -> np.ndarray:
    """The H-bond distances (T, m) of hbond_atoms(PAIRS) as (T, n_pairs, 3), NaN where a pair
    has fewer than three (A-T: two)."""
    _, _, pair, slot, _ = hbond_atoms(pairs)
    d = np.asarray(distances_A, float)
    out = np.full(d.shape[:-1] + (len(pairs), 3), np.nan)
    out[..., pair, slot] = d
    return out


def pair_distances(a_A, b_A, dimensions=None) -> np.ndarray:
    """N1-N3 distances [A] of paired atom positions (n, 3), minimum image in the box
    `dimensions` (MDAnalysis: a, b, c, alpha, beta, gamma); no box when None or empty."""
    box = dimensions if dimensions is not None and np.all(np.asarray(dimensions)[:3] > 0) else None
    return calc_bonds(a_A, b_A, box=box)


class PairIntegrity(AnalysisBase):
    """N1-N3 distance of every base pair in every selected frame, an analysis of the one loop
    (mdbridge/geometry/analysis_base.py): PairIntegrity(universe, pairs).run(start, stop,
    step, progress=...).results has distance_A (T, n_bp) and fraction_intact (T,), the
    fraction of pairs below cutoff_A; the frames' times are `times_ps`. With hbonds=True it
    measures every Watson-Crick H-bond (hbond_atoms) and reads N1-N3 from their slot 0:
    results.hbond_distance_A (T, m) and hbond_A (T, n_bp, 3) (hbond_table) beside.

    pairs: [(residue of strand I, residue of strand II)], e.g. `BasePairFrames(u).pairs`.
    """

    def __init__(self, universe, pairs, cutoff_A: float = INTACT_CUTOFF_A, verbose: bool = False,
                 hbonds: bool = False):
        super().__init__(UniverseFrames(universe), verbose)
        self.universe, self.pairs, self.hbonds = universe, pairs, hbonds
        if hbonds:
            self._a, self._b, pair, slot, self.hbond_names = hbond_atoms(pairs)
            self._n1_n3 = n1_n3_columns(pair, slot)
        else:
            self._a, self._b = central_atoms(pairs)
        self.cutoff_A = cutoff_A

    def _prepare(self):
        self._dist = np.empty((self.n_frames, len(self._a)))

    def _single_frame(self):
        self._dist[self._frame_index] = pair_distances(self._a.positions, self._b.positions,
                                                       self.universe.dimensions)

    def _conclude(self):
        if self.hbonds:
            self.results.hbond_distance_A = self._dist
            self.results.hbond_A = hbond_table(self.pairs, self._dist)
            self.results.distance_A = self._dist[:, self._n1_n3]
        else:
            self.results.distance_A = self._dist
        self.results.fraction_intact = np.mean(self.results.distance_A < self.cutoff_A, axis=1)


def bp_intact_fraction(universe, pairs, start=None, stop=None, step=None,
                       cutoff_A: float = INTACT_CUTOFF_A, progress=None):
    """(times_ps (T,), fraction intact (T,), N1-N3 distances (T, n_bp)) of PairIntegrity.
    progress, if given: progress(frames_done, frames_total) after each frame."""
    a = PairIntegrity(universe, pairs, cutoff_A).run(start, stop, step, progress=progress)
    return a.times_ps, a.results.fraction_intact, a.results.distance_A


def junction_pairs(n_bp: int) -> list[int]:
    """The pairs (0-based) on both sides of the ligation junction of a periodic duplex: the
    two steps that touch it are n-1 -> 0 (the junction) and its neighbours."""
    return [n_bp - 2, n_bp - 1, 0, 1]


def _beyond(values, times_ps, cutoff: float, discard_ps: float, what: str):
    """(times (T,), above cutoff (T, n) bool, the frames kept after discard_ps (T,) bool) of a (T, n) record."""
    v = np.asarray(values, float)
    t = np.asarray(times_ps, float)
    if v.ndim != 2 or v.shape[0] != t.size or t.size == 0:
        raise InputError(f"{what}: values {v.shape} do not match {t.size} frame times")
    above = v > cutoff
    keep = t >= t[0] + discard_ps
    if not keep.any():
        raise InputError(f"{what}: --discard-ps {discard_ps} leaves no frame of {t[0]:g}-{t[-1]:g} ps")
    return t, above, keep


def integrity_summary(distance_A, times_ps, discard_ps: float = 0.0,
                      cutoff_A: float = INTACT_CUTOFF_A) -> dict:
    """The open fraction of N1-N3 distances (T, n_bp) at times_ps: over time, per pair (after
    discard_ps) and at the junction against the interior (the record of checks.json's
    `integrity` and of results' integrity.json)."""
    t, open_, keep = _beyond(distance_A, times_ps, cutoff_A, discard_ps, "integrity")
    per_pair = open_[keep].mean(axis=0)
    jp = junction_pairs(open_.shape[1])
    interior = np.setdiff1d(np.arange(open_.shape[1]), jp)
    return {"criterion": f"open: N1(purine)-N3(pyrimidine) > {cutoff_A} A, minimum image",
            "discard_ps": float(discard_ps), "times_ps": t.tolist(),
            "open_fraction_time": open_.mean(axis=1).tolist(),
            "open_fraction": float(open_[keep].mean()),
            "open_fraction_per_pair": per_pair.tolist(),
            "junction_pairs": jp,
            "junction_open_fraction": float(per_pair[jp].mean()),
            "interior_open_fraction": float(per_pair[interior].mean())}


def stacking_summary(rise_A, times_ps, discard_ps: float = 0.0, cutoff_A: float = UNSTACKED_RISE_A) -> dict:
    """The unstacked fraction of step rises (T, n_steps) at times_ps (rise > cutoff_A): over
    time, per step (after discard_ps) and overall; the steps that are unstacked in more than
    half of the kept frames are listed (0-based, step i joins pairs i and i + 1)."""
    t, un, keep = _beyond(rise_A, times_ps, cutoff_A, discard_ps, "stacking")
    per_step = un[keep].mean(axis=0)
    return {"criterion": f"unstacked: 3DNA rise > {cutoff_A} A", "discard_ps": float(discard_ps),
            "unstacked_fraction": float(un[keep].mean()),
            "unstacked_fraction_per_step": per_step.tolist(),
            "mostly_unstacked_steps": np.flatnonzero(per_step > 0.5).tolist(),
            "unstacked_fraction_time": un.mean(axis=1).tolist(), "times_ps": t.tolist()}
