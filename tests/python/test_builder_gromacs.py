"""The built PDB goes through GROMACS 2022 `pdb2gmx -ff charmm27 -ignh`:
as a linear duplex (termini chosen with -ter) and as a periodic one whose
strands pdb2gmx closes into rings (-lb longer than the box; docs/md.md).
Truths: charmm27's residue sizes (DA 32, DT 32, DG 33, DC 30 atoms with
hydrogens), its termini (5' removes P, O1P, O2P and adds H5T; 3' adds H3T),
and the charge of -1 e per phosphate."""
import re
import shutil
import subprocess

import pytest

from mdbridge.md.builder import build_duplex, ideal_frames, write_pdb

ATOMS = {"A": 32, "T": 32, "G": 33, "C": 30}
COMP = {"A": "T", "C": "G", "G": "C", "T": "A"}


def _gmx():
    gmx = shutil.which("gmx")
    if gmx is None:
        pytest.fail("gmx not found: scripts/setup.sh installs the Debian package gromacs")
    return gmx


def _pdb2gmx(tmp_path, pdb, answers, extra=()):
    cmd = [_gmx(), "pdb2gmx", "-f", str(pdb), "-o", "conf.gro", "-p", "topol.top",
           "-ff", "charmm27", "-water", "none", "-ter", "-ignh", *extra]
    r = subprocess.run(cmd, input=answers, cwd=tmp_path, capture_output=True, text=True,
                       timeout=120)
    log = r.stdout + r.stderr
    assert r.returncode == 0, log[-3000:]
    natoms = int((tmp_path / "conf.gro").read_text().splitlines()[1])
    charge = float(re.search(r"Total charge in system (-?[\d.]+) e", log).group(1))
    return log, natoms, charge


def test_pdb2gmx_accepts_a_linear_duplex(tmp_path):
    seq = "ACGTAC"
    R, o = ideal_frames(len(seq))
    write_pdb(tmp_path / "lin.pdb", build_duplex(seq, o, R))
    # charmm27 lists the protein termini before the DNA ones: start 2 = 5', end 4 = 3'
    log, natoms, charge = _pdb2gmx(tmp_path, tmp_path / "lin.pdb", "2\n4\n2\n4\n")
    assert len(re.findall(r"Start terminus D[ACGT]-\d+: 5'", log)) == 2, log
    assert len(re.findall(r"End terminus D[ACGT]-\d+: 3'", log)) == 2, log
    full = sum(ATOMS[b] + ATOMS[COMP[b]] for b in seq)
    assert natoms == full - 2 * 3 + 2 * 1 + 2 * 1   # 5': -P,O1P,O2P +H5T; 3': +H3T
    assert charge == pytest.approx(-2 * (len(seq) - 1))


def test_pdb2gmx_closes_a_periodic_duplex_into_two_rings(tmp_path):
    seq = "ACGTTGCAAC"   # 10 bp, one full turn at twist 36
    R, o = ideal_frames(len(seq), 3.38, 36.0)
    s = build_duplex(seq, o, R, periodic_box=len(seq) * 3.38)
    write_pdb(tmp_path / "ring.pdb", s)
    # -lb (nm) longer than the box: pdb2gmx links last O3' to first P, no termini
    log, natoms, charge = _pdb2gmx(tmp_path, tmp_path / "ring.pdb", "", extra=["-lb", "4.0"])
    assert "Start terminus" not in log and "End terminus" not in log
    assert natoms == sum(ATOMS[b] + ATOMS[COMP[b]] for b in seq)
    assert charge == pytest.approx(-2 * len(seq))
    # the junction bonds are in the topology: O3' of each strand's last residue
    # bonded to P of its first (strand I: 10 -> 1, strand II: 20 -> 11)
    for chain, last, first in (("A", 10, 1), ("B", 20, 11)):
        atoms, bonds = _itp(tmp_path / f"topol_DNA_chain_{chain}.itp")
        assert frozenset((atoms[(last, "O3'")], atoms[(first, "P")])) in bonds


def _itp(path):
    """{(resid, name): atom number} and the set of bonds of a pdb2gmx .itp."""
    atoms, bonds, section = {}, set(), None
    for line in path.read_text().splitlines():
        line = line.split(";")[0].strip()
        if line.startswith("["):
            section = line.strip("[] ")
        elif line and section == "atoms":
            f = line.split()
            atoms[(int(f[2]), f[4])] = int(f[0])
        elif line and section == "bonds":
            f = line.split()
            bonds.add(frozenset((int(f[0]), int(f[1]))))
    return atoms, bonds
