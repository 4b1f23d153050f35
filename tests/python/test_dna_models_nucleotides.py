"""Standard bases and B-DNA templates against what defines them: the standard
reference frame of Olson et al. 2001 (bases planar in z = 0, C1' positions),
3DNA's files, CHARMM27 atom counts (GROMACS 2022.5 charmm27: heavy atoms DA 21, DC 19,
DG 22, DT 20 of 32/30/33/32 with hydrogens)."""
import numpy as np
import pytest

from dna_models import nucleotides as nt
from dna_models.errors import InputError


@pytest.mark.parametrize("b", "ACGT")
def test_standard_base_is_planar_in_xy_plane(b):
    atoms = nt.standard_base(b)
    xyz = np.array([a["xyz"] for a in atoms.values()])
    assert np.abs(xyz[:, 2]).max() <= 0.001
    ring = [k for k, a in atoms.items() if a["ring"]]
    assert tuple(ring) == tuple(a for a in atoms if a in nt.ring_atom_names(b))
    assert len(ring) == (9 if b in "AG" else 6)


@pytest.mark.parametrize("b", "ACGT")
def test_c1_prime_geometry(b):
    """Olson 2001: C1' of every base sits at ~(-2.48, 5.38) (the frame is defined
    so that C1'...C1' of an ideal pair is 10.7 A and parallel to y-ish)."""
    c1 = nt.standard_base(b)["C1'"]["xyz"]
    assert c1[0] == pytest.approx(-2.479, abs=0.005)
    assert 5.34 < c1[1] < 5.41


@pytest.mark.parametrize("b,n", [("A", 21), ("C", 19), ("G", 22), ("T", 20)])
def test_bdna_nucleotide_heavy_atoms_charmm_names(b, n):
    atoms = nt.bdna_nucleotide(b)
    assert len(atoms) == n
    for name in ("P", "O1P", "O2P", "O5'", "C5'", "C4'", "O4'", "C3'", "O3'", "C2'", "C1'"):
        assert name in atoms
    assert ("C5M" in atoms) == (b == "T")
    assert nt.CHARMM_RESNAME[b] == "D" + b


@pytest.mark.parametrize("b", "ACGT")
def test_bdna_base_matches_standard_base(b, refdata):
    """The template's base atoms coincide with the standard base (to 0.06 A:
    3DNA's BDNA set carries the same Clowney geometry, re-rounded) and the
    data files equal 3DNA's PDB files."""
    std = nt.standard_base(b)
    tpl = nt.bdna_nucleotide(b)
    for a in std:
        assert np.linalg.norm(std[a]["xyz"] - tpl[a]) < 0.06
    for fname, table in ((f"Atomic_{b}.pdb", {k: v["xyz"] for k, v in std.items()}),
                         (f"BDNA_{b}.pdb", tpl)):
        for ln in open(refdata / "x3dna_std" / fname):
            if ln.startswith("ATOM"):
                xyz = np.array([float(ln[30:38]), float(ln[38:46]), float(ln[46:54])])
                assert np.array_equal(table[ln[12:16].strip()], xyz)


def test_bond_lengths_of_template_are_chemical():
    t = nt.bdna_nucleotide("G")
    for a, b, d in (("P", "O5'", 1.59), ("C1'", "N9", 1.47), ("C3'", "O3'", 1.43), ("C4'", "C5'", 1.51)):
        assert np.linalg.norm(t[a] - t[b]) == pytest.approx(d, abs=0.05)


def test_unknown_base():
    with pytest.raises(InputError, match="allowed A, C, G, T"):
        nt.standard_base("U")
