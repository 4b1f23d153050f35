"""All-atom double-stranded DNA from base-pair frames, as 3DNA's `rebuild` does.

Each nucleotide is a rigid B-form template (base + C2'-endo sugar-phosphate
backbone, heavy atoms, 3DNA's x3dna_std/BDNA_*.pdb with CHARMM27 names, served
by dna_models.nucleotides) given in its own standard base reference frame
(Olson et al. 2001). Placing it is one rigid motion: x_lab = o + R_base x_std.

Base frames from the base-pair frame (origin o_i, axes R_i = [x y z] columns):
  strand I  : R_I  = R_i
  strand II : R_II = R_i diag(1,-1,-1)  (y and z reversed: its base points the
              other way and its strand runs antiparallel)
and with non-zero base-pair parameters (shear ... opening) the two base frames
are the two halves of a 3DNA "step" whose middle frame is R_i
(mdbridge.geometry.base_frames_from_pair),
which is exactly how 3DNA defines the base-pair frame (the middle frame of
strand I's base frame and strand II's flipped one), so analysing the built
structure gives the input frames back.

Strand II is written 5'->3', i.e. from base pair n down to base pair 1, and
numbered n+1..2n (3DNA's convention). Every residue carries P, O1P, O2P,
including the 5' ones: pdb2gmx needs the first P to close a periodic strand
into a ring (see docs/builder.md) and deletes it itself for a linear 5' end.
"""
from __future__ import annotations

import numpy as np

from dna_models import sequence as dna_sequence
from mdbridge.md.forcefields import BUILDER
from dna_models.errors import InputError
from mdbridge.md.builder.structure import Structure
from dna_models.templates import nucleotide_template

FLIP = np.diag([1.0, -1.0, -1.0])  # strand II base frame relative to the bp frame


def base_pairs(n: int) -> list[tuple[int, int]]:
    """The built duplex's base pairs as (residue I, residue II) numbers: pair k
    (1..n) joins strand I residue k and strand II residue 2n + 1 - k. Analyses of
    the toolkit's own MD pass these instead of pairing by distance, which fails
    as soon as a pair frays in the run."""
    return [(k, 2 * n + 1 - k) for k in range(1, n + 1)]


def _check_frames(origins, R, n: int):
    origins = np.asarray(origins, dtype=float)
    R = np.asarray(R, dtype=float)
    if origins.shape != (n, 3) or R.shape != (n, 3, 3):
        raise InputError(f"frames: need origins ({n}, 3) and R ({n}, 3, 3) for {n} base pairs, "
                         f"got {origins.shape} and {R.shape}")
    if not (np.all(np.isfinite(origins)) and np.all(np.isfinite(R))):
        raise InputError("frames: origins or R contain NaN/Inf")
    err = np.abs(np.einsum("nji,njk->nik", R, R) - np.eye(3)).max(axis=(1, 2))
    det = np.linalg.det(R)
    bad = np.flatnonzero((err > 1e-6) | (det < 0))
    if len(bad):
        i = bad[0]
        raise InputError(f"frames: R of base pair {i + 1} is not a proper rotation "
                         f"(|R^T R - 1| = {err[i]:.2e}, det = {det[i]:.6f})")
    return origins, R


def _box(periodic_box):
    if periodic_box is None:
        return None
    box = np.atleast_1d(np.asarray(periodic_box, dtype=float))
    if box.shape == (1,):
        box = np.array([0.0, 0.0, box[0]])
    if box.shape != (3,) or np.any(box < 0) or not np.any(box > 0) or not np.all(np.isfinite(box)):
        raise InputError(f"periodic_box: {periodic_box!r} is not allowed; give the box length "
                         "along z in A (helix along z) or three orthorhombic edges (a, b, c) "
                         "in A, 0 for a non-periodic direction")
    return box


def base_frames(origins, R, base_pair_params=None):
    """Base frames (o_I, R_I), (o_II, R_II) of both strands for each base pair.

    base_pair_params (n, 6): shear, stretch, stagger (A), buckle, propeller,
    opening (degrees), 3DNA's definition: they are the "step" from strand II's
    flipped base frame to strand I's, whose middle frame is the base-pair frame.
    None means all zero (both base frames coincide with the bp frame up to FLIP).
    """
    origins = np.asarray(origins, dtype=float)
    R = np.asarray(R, dtype=float)
    if base_pair_params is None:
        return origins, R, origins.copy(), R @ FLIP
    from mdbridge.geometry.steps import base_frames_from_pair  # 3DNA's inverse, H3's code
    p = np.asarray(base_pair_params, dtype=float)
    if p.shape != (len(origins), 6) or not np.all(np.isfinite(p)):
        raise InputError(f"base_pair_params: need finite values of shape ({len(origins)}, 6), "
                         f"got {p.shape}")
    R_I, o_I, R_II, o_II = base_frames_from_pair(p, R, origins)
    return o_I, R_I, o_II, R_II


def build_duplex(sequence, origins, R, *, periodic_box=None, hydrogens=False,
                 base_pair_params=None, close_backbone=False, ring=False) -> Structure:
    """Build the all-atom duplex of `sequence` (strand I, 5'->3') on base-pair
    frames origins (n, 3) in A and R (n, 3, 3) (columns = x, y, z axes in the lab).

    periodic_box: None for a linear duplex, or the box (A): a scalar L (helix
    periodic along z) or (a, b, c) with 0 for non-periodic directions. The
    structure is then one period: strand I's last O3' bonds to its first P in
    the next image (and strand II likewise); coordinates stay whole.
    ring: a duplex closed in space (a minicircle: the frames go once round a closed
    curve, base pair n followed by base pair 1): strand I's last O3' bonds to its first
    P, strand II likewise, with no box (periodic_box must be None).
    hydrogens: False gives heavy atoms only (the GROMACS route: pdb2gmx -ignh
    adds hydrogens); True adds CHARMM27 hydrogens from templates.
    base_pair_params: optional (n, 6) shear..opening (see base_frames).
    close_backbone: close every O3'-P link outside 1.5-1.8 A by turning the next
    nucleotide's 5' end (backbone.py); False places the templates rigidly, as 3DNA's
    rebuild does.
    """
    seq = dna_sequence.validate(sequence)
    comp = dna_sequence.complement(seq)
    n = len(seq)
    origins, R = _check_frames(origins, R, n)
    box = _box(periodic_box)
    if ring and box is not None:
        raise InputError("build_duplex: a ring is closed in space; give periodic_box=None with ring=True")
    o_I, R_I, o_II, R_II = base_frames(origins, R, base_pair_params)

    # (base, strand, resid, base-frame origin, base-frame axes) in output order:
    # strand I 5'->3', then strand II 5'->3' (= base pairs n..1)
    residues = [(seq[i], "I", i + 1, o_I[i], R_I[i]) for i in range(n)]
    residues += [(comp[i], "II", 2 * n - i, o_II[i], R_II[i])
                 for i in range(n - 1, -1, -1)]

    names, resnames, resids, strands, elements, bonds = [], [], [], [], [], []
    coords: list[np.ndarray] = []
    start_of = {}
    for base, strand, resid, o, Rb in residues:
        t = nucleotide_template(base, hydrogens=hydrogens)
        k0 = sum(len(c) for c in coords)
        start_of[resid] = (k0, t)
        names.append(t.names)
        resnames.append(np.full(len(t.names), BUILDER.residue_names[base]))
        resids.append(np.full(len(t.names), resid))
        strands.append(np.full(len(t.names), strand))
        elements.append(t.elements)
        coords.append(o + t.coords @ Rb.T)
        bonds.append(t.bonds + k0)

    def atom(resid, name):
        k0, t = start_of[resid]
        return k0 + t.index[name]

    # backbone links O3'(i) - P(i+1) within each strand, and through the box
    for first, last in ((1, n), (n + 1, 2 * n)):
        for r in range(first, last):
            bonds.append(np.array([[atom(r, "O3'"), atom(r + 1, "P")]]))
        if box is not None or ring:
            bonds.append(np.array([[atom(last, "O3'"), atom(first, "P")]]))

    xyz = np.concatenate(coords)
    all_names, all_resids = np.concatenate(names), np.concatenate(resids)
    if close_backbone:
        from .backbone import close_links, duplex_links
        xyz = close_links(xyz, duplex_links(all_names, all_resids, n, periodic=box is not None or ring), box)
    return Structure(names=all_names, resnames=np.concatenate(resnames),
                     resids=all_resids, strands=np.concatenate(strands),
                     elements=np.concatenate(elements), coords=xyz,
                     bonds=np.concatenate(bonds).astype(int), box=box, ring=bool(ring),
                     base_origins=np.array([r[3] for r in sorted(residues, key=lambda r: r[2])]),
                     base_R=np.array([r[4] for r in sorted(residues, key=lambda r: r[2])]))
