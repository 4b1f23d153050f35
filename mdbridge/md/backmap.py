"""Rod frames -> molecules a viewer reads (docs/viewing.md).

All-atom: every rod frame is rebuilt into the MD build's own atoms, in its order and
with its names, by the builder's rule (mdbridge/md/builder/duplex.py): each nucleotide is
its rigid template placed on its base frame, x = o_b + R_b x_std, strand I on the
base-pair frame R_i and strand II on R_i diag(1, -1, -1). The template of every atom
of the MD structure is found once (by residue and atom name, hydrogens included: the
templates carry the very hydrogens pdb2gmx adds, dna_models/data/h_charmm27_bdna.json),
so one frame is one gather and one batched matrix product. Then, as the builder does,
every O3'-P link outside 1.5-1.8 A is closed by turning the next nucleotide's 5' end
(mdbridge/md/builder/backbone.py), so that a rod frame's atoms are the atoms build-md
would make of it.

Coarse: one pseudo-atom per base pair at the frame origin (the rod's centreline)
and one at the tip of its d1 director (toward the major groove), bonded by CONECT
records, so VMD and PyMOL draw the rod and its twist.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from dna_models import sequence as dna_sequence
from dna_models.errors import InputError
from mdbridge.md.builder.backbone import BackboneLinks, close_links, duplex_links
from mdbridge.md.builder.duplex import FLIP
from dna_models.templates import nucleotide_template


@dataclass(frozen=True)
class AtomMap:
    """For each atom of an MD structure: the base frame that carries it and its
    coordinates in that frame; and the structure's O3'-P links and periodic box."""
    frame_of_atom: np.ndarray   # (n_atoms,) index into the 2 n_bp base frames
    x_std: np.ndarray           # (n_atoms, 3) A, standard base frame
    n_bp: int
    links: BackboneLinks
    box_A: np.ndarray | None    # (3,) the MD box, for the links that close through it

    def place(self, R, origins) -> np.ndarray:
        """All-atom coordinates (T, n_atoms, 3) [A] from base-pair frames R (T, n_bp, 3, 3)
        and origins (T, n_bp, 3) [A]."""
        R = np.asarray(R, dtype=float)
        o = np.asarray(origins, dtype=float)
        if R.ndim == 3:
            R, o = R[None], o[None]
        if R.shape[1:] != (self.n_bp, 3, 3) or o.shape[1:] != (self.n_bp, 3):
            raise InputError(f"rod frames carry {R.shape[1]} base pairs, the MD structure {self.n_bp}")
        Rb = np.concatenate([R, R @ FLIP], axis=1)       # strand I frames, then strand II
        ob = np.concatenate([o, o], axis=1)
        Ra, oa = Rb[:, self.frame_of_atom], ob[:, self.frame_of_atom]
        return close_links(oa + np.einsum("tajk,ak->taj", Ra, self.x_std), self.links, self.box_A)


def atom_map(universe, sequence: str) -> AtomMap:
    """AtomMap of an MD structure built by `dnarod build-md` (residues 1..n strand I
    5'->3', n+1..2n strand II 5'->3', i.e. base pairs n..1; mdbridge/md/builder/duplex.py)."""
    seq = dna_sequence.validate(sequence)
    comp = dna_sequence.complement(seq)
    n = len(seq)
    residues = universe.residues
    if len(residues) != 2 * n:
        raise InputError(f"the MD structure has {len(residues)} residues; a duplex of the build's "
                         f"{n}-bp sequence has {2 * n}")
    frame_of_atom = np.empty(universe.atoms.n_atoms, dtype=int)
    x_std = np.empty((universe.atoms.n_atoms, 3))
    for k, res in enumerate(residues):
        if k < n:
            bp, base, frame = k, seq[k], k
        else:
            bp = 2 * n - 1 - k
            base, frame = comp[bp], n + bp
        t = nucleotide_template(base, hydrogens=True)
        for atom in res.atoms:
            row = t.index.get(atom.name)
            if row is None:
                raise InputError(f"MD structure, residue {res.resid} {res.resname}, atom {atom.name}: no "
                                 f"such atom in the {base} template (allowed: {', '.join(t.names)})")
            frame_of_atom[atom.index] = frame
            x_std[atom.index] = t.coords[row]
    # residues in file order are the builder's numbering (strand I 1..n, strand II n+1..2n)
    links = duplex_links(universe.atoms.names, universe.atoms.resindices + 1, n, periodic=True)
    box = None if universe.dimensions is None else np.asarray(universe.dimensions[:3], dtype=float)
    return AtomMap(frame_of_atom=frame_of_atom, x_std=x_std, n_bp=n, links=links, box_A=box)


# What rod-to-atoms --like checks in what it wrote (exit 2 beyond): the builder's link
# range (backbone.LINK_RANGE_A), no two non-bonded heavy atoms closer than CONTACT_MIN_A
# (overlapping atoms: van der Waals contact of C, N, O is ~3 A), and frame 0 (t = 0) within
# RMS_T0_MAX_A of the build's own structure before any minimisation (the same frames through
# the same builder rule give the same atoms, to round-off).
CONTACT_MIN_A = 1.5
RMS_T0_MAX_A = 1.0


def rms_to_build_A(universe, x0, build_pdb) -> float:
    """RMS distance [A] between frame x0 (n_atoms, 3) and the build's heavy atoms before
    pdb2gmx and any minimisation (build-md's duplex_in.pdb), atoms matched by residue
    (file order) and name."""
    from mdbridge.md.pdbio import read_pdb
    ref = read_pdb(build_pdb)
    where = {(int(r), str(a)): k for k, (r, a) in enumerate(zip(ref["resids"], ref["names"]))}
    mine, theirs = [], []
    for k, (r, a) in enumerate(zip(universe.atoms.resindices + 1, universe.atoms.names)):
        j = where.get((int(r), str(a)))
        if j is not None:
            mine.append(k)
            theirs.append(j)
    if len(mine) < len(ref["names"]) // 2:
        raise InputError(f"{build_pdb}: its atoms are not the MD structure's (matched {len(mine)} of "
                         f"{len(ref['names'])} by residue and name)")
    d = np.asarray(x0, dtype=float)[mine] - ref["coords"][theirs]
    return float(np.sqrt((d * d).sum(axis=1).mean()))


# the resolution of a length between float32 coordinates of a duplex in its box [A]
FLOAT32_LENGTH_A = 1e-4


def overlay_problems(rms_t0_A: float, links_A, contact_A, times_ps) -> list[str]:
    """The limits a rod-to-atoms overlay breaks, each as a sentence naming the number and
    its likely cause (empty: all hold). links_A (T, L), contact_A (T,) or None when not
    computed."""
    from mdbridge.md.builder.backbone import LINK_RANGE_A
    out = []
    if rms_t0_A > RMS_T0_MAX_A:
        out.append(f"frame 0 (t = {times_ps[0]:g} ps) is {rms_t0_A:.2f} A rms from the build's own atoms "
                   f"(limit {RMS_T0_MAX_A} A): the rod run and the MD build are not of the same scene, or the "
                   "rod file does not start at the build's t = 0 state")
    if links_A is not None:
        lo, hi = LINK_RANGE_A
        d = np.asarray(links_A)
        # The builder keeps a link inside LINK_RANGE_A as placed, in float64; the overlay's
        # coordinates are float32 (a step of ~3e-5 A at 500 A from the origin), so a link
        # placed at the edge reads up to ~1e-4 A beyond it (measured: 1.8000019 A)
        if d.min() < lo - FLOAT32_LENGTH_A or d.max() > hi + FLOAT32_LENGTH_A:
            t = int(np.argmax(np.maximum(lo - d, d - hi).max(axis=1)))
            out.append(f"O3'-P links {d.min():.2f}-{d.max():.2f} A (limits {lo}-{hi} A), worst at t = "
                       f"{times_ps[t]:g} ps: the rod's base-pair steps there are further from B-DNA than "
                       "the backbone can follow, or the rod and the build are of different DNA")
    if contact_A is not None:
        c = np.asarray(contact_A, dtype=float)
        if np.nanmin(c) < CONTACT_MIN_A:
            t = int(np.nanargmin(c))
            out.append(f"closest non-bonded heavy-atom contact {c[t]:.2f} A at t = {times_ps[t]:g} ps "
                       f"(limit {CONTACT_MIN_A} A): atoms overlap, the rod there bends or twists beyond what "
                       "rigid nucleotides on its frames can hold apart")
    return out


def _excluded_keys(universe) -> np.ndarray:
    """Sorted keys a * n + b (a < b) of atom pairs 1-2 or 1-3 bonded."""
    n = universe.atoms.n_atoms
    b = universe.bonds.indices.astype(np.int64)
    import scipy.sparse as sp
    A = sp.coo_matrix((np.ones(len(b)), (b[:, 0], b[:, 1])), shape=(n, n))
    A = ((A + A.T) > 0).astype(np.int8)
    near = ((A + A @ A) > 0).tocoo()
    keys = np.minimum(near.row, near.col).astype(np.int64) * n + np.maximum(near.row, near.col)
    return np.unique(keys)


def closest_nonbonded(universe, xyz, cutoff_A: float = 4.0, progress=None) -> np.ndarray:
    """Closest distance [A] per frame between heavy atoms that are neither bonded nor
    share a bonded neighbour (1-2 and 1-3 excluded), minimum image along the box;
    inf when no such pair is closer than cutoff_A. progress(done, total) per frame."""
    from scipy.spatial import cKDTree
    n = universe.atoms.n_atoms
    heavy = np.flatnonzero(~np.char.startswith(universe.atoms.names.astype(str), "H"))
    excluded = _excluded_keys(universe)
    box = np.asarray(universe.dimensions[:3], dtype=float)
    out = np.full(len(xyz), np.inf)
    for t, x in enumerate(xyz):
        if progress is not None:
            progress(t, len(xyz))
        pos = np.mod(x[heavy], box)
        pairs = cKDTree(pos, boxsize=box).query_pairs(cutoff_A, output_type="ndarray")
        if not len(pairs):
            continue
        a, b = heavy[pairs[:, 0]].astype(np.int64), heavy[pairs[:, 1]].astype(np.int64)
        keys = np.minimum(a, b) * n + np.maximum(a, b)
        keep = ~np.isin(keys, excluded, assume_unique=False)
        if keep.any():
            d = pos[pairs[keep, 0]] - pos[pairs[keep, 1]]
            d -= box * np.round(d / box)
            out[t] = np.sqrt((d * d).sum(-1)).min()
    if progress is not None:
        progress(len(xyz), len(xyz))
    return out


def write_coarse_pdb(path, R, origins, *, tip_A: float = 5.0, box=None) -> None:
    """Multi-model PDB: per base pair a pseudo-atom 'C' at the origin (residue BP) and
    one 'D1' at origin + tip_A d1, bonded by CONECT (centreline chain and tip spokes)."""
    R = np.asarray(R, dtype=float)
    o = np.asarray(origins, dtype=float)
    if R.ndim == 3:
        R, o = R[None], o[None]
    T, n = o.shape[:2]
    tips = o + tip_A * R[..., :, 0]
    lines = ["REMARK   1 dnarod coarse rod: C = base-pair origin on the centreline, D1 = tip of d1"]
    cryst1 = None
    if box is not None:
        a, b, c = (float(x) for x in box)
        cryst1 = f"CRYST1{a:9.3f}{b:9.3f}{c:9.3f}  90.00  90.00  90.00 P 1           1"
    for t in range(T):
        lines.append(f"MODEL     {t + 1:4d}")
        if cryst1:   # in every model: MDAnalysis reads a model's box only from inside it
            lines.append(cryst1)
        serial = 0
        for i in range(n):
            for name, x in (("C", o[t, i]), ("D1", tips[t, i])):
                serial += 1
                el = "C" if name == "C" else "O"
                lines.append(f"HETATM{serial:5d} {name:<4s} BP  A{i + 1:4d}    "
                             f"{x[0]:8.3f}{x[1]:8.3f}{x[2]:8.3f}  1.00  0.00          {el:>2s}")
        lines.append("ENDMDL")
    for i in range(n):
        c, d = 2 * i + 1, 2 * i + 2
        partners = [d] + ([2 * i + 3] if i + 1 < n else [])
        if i > 0:
            partners.append(2 * i - 1)
        lines.append("CONECT" + "".join(f"{x:5d}" for x in [c] + partners))
        lines.append(f"CONECT{d:5d}{c:5d}")
    lines.append("END")
    Path(path).write_text("\n".join(lines) + "\n")


def relax(md_dir, universe, xyz, *, steps: int, gmx: str, workdir, progress=None) -> np.ndarray:
    """A short restrained steepest descent per frame, for viewing only: the MD build's
    own em.mdp (base heavy atoms held by posre_bases_*.itp, -DPOSRES_BASES) with nsteps
    = steps, each frame its own reference. Returns the relaxed coordinates [A].
    progress, if given: progress(frames_done, frames_total) after each frame."""
    from mdbridge.md.gromacs.gmx import run_gmx
    md_dir, workdir = Path(md_dir), Path(workdir)
    workdir.mkdir(parents=True, exist_ok=True)
    mdp = (md_dir / "em.mdp").read_text()
    import re
    mdp = re.sub(r"(?m)^nsteps\s*=.*$", f"nsteps                  = {int(steps)}", mdp)
    mdp = re.sub(r"(?m)^nstenergy\s*=.*$", "nstenergy               = 0", mdp)
    (workdir / "relax.mdp").write_text(mdp)
    for f in md_dir.glob("*.itp"):
        (workdir / f.name).write_text(f.read_text())
    (workdir / "topol.top").write_text((md_dir / "topol.top").read_text())
    out = np.empty_like(xyz)
    for k, x in enumerate(xyz):
        universe.atoms.positions = x
        universe.atoms.write(str(workdir / "frame.gro"))
        run_gmx(gmx, ["grompp", "-f", "relax.mdp", "-c", "frame.gro", "-r", "frame.gro", "-p", "topol.top",
                      "-o", "relax.tpr", "-po", "relax_out.mdp", "-maxwarn", "1"], workdir,
                log_name="gmx_grompp_relax.log")
        run_gmx(gmx, ["mdrun", "-s", "relax.tpr", "-deffnm", "relax", "-nt", "1", "-c", "relaxed.gro"],
                workdir, log_name="gmx_mdrun_relax.log")
        import MDAnalysis as mda
        out[k] = mda.Universe(str(workdir / "relaxed.gro")).atoms.positions
        if progress is not None:
            progress(k + 1, len(xyz))
    return out
