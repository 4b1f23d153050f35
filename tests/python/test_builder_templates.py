"""Template bonds and atoms against the force field: the bonds the builder
derives by distance on the ideal templates must be exactly the heavy-atom
bonds of GROMACS charmm27.ff/dna.rtp, and the atom names exactly its heavy
atoms (so pdb2gmx needs no renaming)."""
import re
import shutil
from pathlib import Path

import numpy as np
import pytest

from dna_models.templates import nucleotide_template


def _charmm27_dir():
    gmx = shutil.which("gmx")
    cands = [Path("/usr/share/gromacs/top/charmm27.ff")]
    if gmx:
        cands.insert(0, Path(gmx).resolve().parents[1] / "share" / "gromacs" / "top" / "charmm27.ff")
    for c in cands:
        if (c / "dna.rtp").is_file():
            return c
    pytest.fail("GROMACS charmm27.ff/dna.rtp not found: scripts/setup.sh installs the Debian package gromacs")


def _rtp_residue(resname):
    text = (_charmm27_dir() / "dna.rtp").read_text()
    block = re.search(r"^\[ %s \]\n(.*?)(?=^\[ D[ACGT] \]|\Z)" % resname, text, re.S | re.M).group(1)
    sections = {}
    current = None
    for line in block.splitlines():
        line = line.split(";")[0].strip()
        if not line:
            continue
        m = re.match(r"\[ (\w+) \]", line)
        if m:
            current = m.group(1)
            sections[current] = []
        elif current:
            sections[current].append(line.split())
    atoms = [a[0] for a in sections["atoms"]]
    bonds = {frozenset(b[:2]) for b in sections["bonds"]
             if not any(x[0] in "+-" for x in b[:2])}
    return atoms, bonds


@pytest.mark.parametrize("base", "ACGT")
def test_template_bonds_are_the_force_field_bonds(base):
    atoms, bonds = _rtp_residue("D" + base)
    heavy = {a for a in atoms if not a.startswith("H")}
    t = nucleotide_template(base)
    assert set(t.names.tolist()) == heavy
    ours = {frozenset((t.names[i], t.names[j])) for i, j in t.bonds}
    theirs = {b for b in bonds if not any(x.startswith("H") for x in b)}
    assert ours == theirs


@pytest.mark.parametrize("base", "ACGT")
def test_distance_criterion_is_unambiguous(base):
    """Bonded pairs are all below 1.65 A and every other pair above 2.1 A (1-3
    pairs in the five-membered rings are the closest, 2.13 A), far
    from the 1.9 A cut: the derived bond list cannot depend on the cut."""
    t = nucleotide_template(base)
    d = np.linalg.norm(t.coords[:, None] - t.coords[None, :], axis=-1)
    bonded = np.zeros_like(d, dtype=bool)
    bonded[t.bonds[:, 0], t.bonds[:, 1]] = True
    bonded |= bonded.T
    off = ~bonded & ~np.eye(len(d), dtype=bool)
    assert d[bonded].max() < 1.65
    assert d[off].min() > 2.1
