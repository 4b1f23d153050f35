"""Synthetic duplexes with known parameters, for tests and benchmarks.

Builds the bases (standard base atoms of Olson et al. 2001, no backbone) of a
duplex whose base-pair frames follow given step parameters and whose bases
follow given base-pair parameters, as an in-memory MDAnalysis Universe
(optionally a trajectory). The exact parameters are known by construction:
an independent truth for the analysis code.
"""
from __future__ import annotations

import numpy as np

from dna_models.nucleotides import CHARMM_RESNAME, standard_base
from dna_models.sequence import complement, validate

from .steps import base_frames_from_pair, frames_from_steps


def duplex_atoms(sequence, step_params, bp_params=None, R0=None, o0=None):
    """Atom positions of the two strands' bases.

    sequence: strand I (n bases); step_params (..., n-1, 6); bp_params (..., n, 6)
    or None (zeros). Returns (names, resnames, strand_of_atom, residue_of_atom,
    positions (..., n_atoms, 3)); strand II residues run antiparallel (its first
    residue pairs with strand I's last)."""
    seq = validate(sequence)
    n = len(seq)
    step_params = np.asarray(step_params, dtype=float)
    lead = step_params.shape[:-2]
    if bp_params is None:
        bp_params = np.zeros(lead + (n, 6))
    R, o = frames_from_steps(step_params, R0, o0)
    R_I, o_I, R_II, o_II = base_frames_from_pair(bp_params, R, o)
    comp = complement(seq)
    names, resn, strand, resi, pos = [], [], [], [], []
    for s, (bases, Rb, ob, order) in enumerate(((seq, R_I, o_I, range(n)),
                                                (comp, R_II, o_II, range(n - 1, -1, -1)))):
        for k, i in enumerate(order):
            atoms = standard_base(bases[i])
            for a, v in atoms.items():
                names.append(a)
                resn.append(CHARMM_RESNAME[bases[i]])
                strand.append(s)
                resi.append(s * n + k)
                pos.append(np.einsum("...ij,j->...i", Rb[..., i, :, :], v["xyz"]) + ob[..., i, :])
    return names, resn, np.array(strand), np.array(resi), np.stack(pos, axis=-2)


def duplex_universe(sequence, step_params, bp_params=None, box=None):
    """In-memory MDAnalysis Universe of the duplex's bases; step_params
    (T, n-1, 6) gives a T-frame trajectory (MemoryReader). box: (6,) dimensions
    for every frame or None."""
    import MDAnalysis as mda
    from MDAnalysis.coordinates.memory import MemoryReader

    step_params = np.asarray(step_params, dtype=float)
    if step_params.ndim == 2:
        step_params = step_params[None]
    if bp_params is not None:
        bp_params = np.asarray(bp_params, dtype=float)
        if bp_params.ndim == 2:
            bp_params = np.broadcast_to(bp_params, step_params.shape[:1] + bp_params.shape)
    names, resn, strand, resi, pos = duplex_atoms(sequence, step_params, bp_params)
    n_res = resi.max() + 1
    u = mda.Universe.empty(len(names), n_residues=n_res, n_segments=2, atom_resindex=resi,
                           residue_segindex=[0] * (n_res // 2) + [1] * (n_res // 2), trajectory=False)
    u.add_TopologyAttr("name", names)
    res_names = [None] * n_res
    for r, nm in zip(resi, resn):
        res_names[r] = nm
    u.add_TopologyAttr("resname", res_names)
    u.add_TopologyAttr("resid", np.arange(1, n_res + 1))
    u.add_TopologyAttr("segid", ["A", "B"])
    dims = None if box is None else np.tile(np.asarray(box, dtype=float), (pos.shape[0], 1))
    u.load_new(pos.astype(np.float32), format=MemoryReader, dimensions=dims)
    return u
