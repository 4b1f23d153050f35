"""Minimal fixed-column PDB reading and writing for built nucleic acids.

Why our own and not MDAnalysis's writer: the builder needs exact control of
the columns GROMACS reads (4-character atom names such as H5'1 starting in
column 13, chain IDs that make pdb2gmx see two molecules, TER between the
strands, CRYST1 for a periodic box), and the reader must accept 3DNA's output
(OP1/OP2, C7) so tests can compare with 3DNA's rebuild. Both are a few lines.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from dna_models.errors import InputError
from mdbridge.md.forcefields import PDBV3_TO_BUILDER as PDBV3_TO_CHARMM27


def read_pdb(path, *, charmm_names: bool = True) -> dict:
    """Read ATOM/HETATM records of the first model.

    Returns numpy arrays: names, resnames, chains, resids, coords (A), and
    segids. With charmm_names, PDBv3 names (OP1, OP2, C7, H2'') become the
    CHARMM27 ones (O1P, O2P, C5M, H2'2) and '*' becomes "'" (old style C1*).
    """
    path = Path(path)
    names, resnames, chains, resids, segids, xyz = [], [], [], [], [], []
    try:
        lines = path.read_text().splitlines()
    except OSError as e:
        raise InputError(f"{path}: cannot read PDB file ({e.strerror})") from e
    for lineno, line in enumerate(lines, 1):
        if line.startswith("ENDMDL"):
            break
        if not line.startswith(("ATOM  ", "HETATM")):
            continue
        try:
            name = line[12:16].strip()
            x, y, z = float(line[30:38]), float(line[38:46]), float(line[46:54])
            resid = int(line[22:26])
        except ValueError as e:
            raise InputError(f"{path}:{lineno}: malformed ATOM record ({e})") from e
        if charmm_names:
            name = name.replace("*", "'")
            name = PDBV3_TO_CHARMM27.get(name, name)
        names.append(name)
        resnames.append(line[17:21].strip())
        chains.append(line[21:22])
        resids.append(resid)
        segids.append(line[72:76].strip() if len(line) > 72 else "")
        xyz.append((x, y, z))
    if not names:
        raise InputError(f"{path}: no ATOM/HETATM records found")
    return {"names": np.array(names), "resnames": np.array(resnames),
            "chains": np.array(chains), "resids": np.array(resids),
            "segids": np.array(segids), "coords": np.array(xyz, dtype=float)}


def _atom_name_field(name: str) -> str:
    # PDB convention: 1-letter elements start in column 14, 4-character
    # names fill columns 13-16 (H5'1, H2'2). GROMACS and MDAnalysis read both.
    return f"{name:<4s}" if len(name) >= 4 else f" {name:<3s}"


def cryst1_edges(box, coords) -> np.ndarray | None:
    """The three edges (A) a CRYST1 record gives for BOX (the builder's: 0 for a
    non-periodic direction), None without a box. A PDB cell cannot leave a direction
    out, so a non-periodic edge becomes twice the atoms' extent along it plus
    VACUUM_A: then no minimum image changes a vector between two atoms of the
    structure, and readers (MDAnalysis, dnarod helical-params --periodic) still find
    the period along the periodic edges."""
    if box is None:
        return None
    b = np.asarray(box, dtype=float)
    if not np.any(b > 0):
        return None
    x = np.asarray(coords, dtype=float)
    extent = x.max(axis=0) - x.min(axis=0)
    return np.where(b > 0, b, 2.0 * extent + VACUUM_A)


VACUUM_A = 10.0   # added to twice the extent of a non-periodic CRYST1 edge


def write_pdb(path, structure, *, remarks=()) -> None:
    """Write a `Structure` (mdbridge.md.builder) as PDB: one chain per strand
    (A = strand I, B = strand II, segid I / II), TER after each strand,
    CRYST1 when the structure is periodic (cryst1_edges), coordinates in A."""
    s = structure
    out = [f"REMARK   {r}" for r in remarks]
    edges = cryst1_edges(getattr(s, "box", None), s.coords)
    if edges is not None:
        a, b, c = edges
        out.append(f"CRYST1{a:9.3f}{b:9.3f}{c:9.3f}{90:7.2f}{90:7.2f}{90:7.2f} P 1           1")
    chain_of = {"I": "A", "II": "B"}
    serial = 0
    n = len(s.names)
    for k in range(n):
        serial += 1
        x, y, z = s.coords[k]
        if max(abs(x), abs(y), abs(z)) >= 1e4:
            raise InputError(f"{path}: coordinate of atom {k + 1} ({x:.1f}, {y:.1f}, {z:.1f}) "
                             "does not fit the PDB format (|x| < 10000 A)")
        seg = str(s.strands[k])
        out.append(
            f"ATOM  {serial % 100000:5d} {_atom_name_field(str(s.names[k]))}"
            f"{'':1s}{str(s.resnames[k]):>3s} {chain_of.get(seg, seg[:1])}"
            f"{int(s.resids[k]) % 10000:4d}    {x:8.3f}{y:8.3f}{z:8.3f}"
            f"{1.0:6.2f}{0.0:6.2f}      {seg:<4s}{str(s.elements[k]):>2s}")
        if k == n - 1 or s.strands[k + 1] != s.strands[k]:
            out.append("TER")
    out.append("END")
    Path(path).write_text("\n".join(out) + "\n")
