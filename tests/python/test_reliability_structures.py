"""No accepted bad input, structures: cases the geometry owners'
tests (tests/python/test_geometry_structure.py) do not cover. The truth is
by construction: an all-atom duplex built by mdbridge.md.builder with a nucleotide
removed has a broken strand; a pair list naming a nucleotide twice or with
itself is impossible; a G-T pair is not Watson-Crick."""
import warnings

import pytest

import MDAnalysis as mda

from dna_models.errors import InputError  # noqa: E402
from mdbridge.md.builder import build_duplex, ideal_frames, write_pdb  # noqa: E402
from mdbridge.geometry.structure import BasePairFrames  # noqa: E402

SEQ = "GATTCAGC"


@pytest.fixture(scope="module")
def duplex_pdb(tmp_path_factory):
    R, o = ideal_frames(len(SEQ))
    path = tmp_path_factory.mktemp("dup") / "dup.pdb"
    write_pdb(path, build_duplex(SEQ, o, R))
    return path


def test_intact_duplex_passes_the_new_checks(duplex_pdb):
    with warnings.catch_warnings():
        warnings.simplefilter("error", UserWarning)  # no non-Watson-Crick warning either
        b = BasePairFrames(mda.Universe(str(duplex_pdb)))
    assert b.n_bp == len(SEQ)


def test_missing_nucleotide_is_a_broken_chain(duplex_pdb):
    u = mda.Universe(str(duplex_pdb))
    strand_I = u.select_atoms("segid I").residues
    gone = strand_I[3]
    v = mda.Merge(u.atoms - gone.atoms)
    with pytest.raises(InputError, match=r"broken chain: .*3.* O3. and .*5.* P are ([5-9]|[1-9][0-9])\.[0-9]+ A apart"):
        BasePairFrames(v)


def test_whole_base_pair_missing_is_a_broken_chain(duplex_pdb):
    # both partners gone: every remaining base is paired, only the backbone tells
    u = mda.Universe(str(duplex_pdb))
    b = BasePairFrames(u)
    i, j = b.pairs[3]
    v = mda.Merge(u.atoms - i.atoms - j.atoms)
    with pytest.raises(InputError, match="broken chain"):
        BasePairFrames(v)


def test_nucleotide_paired_with_itself_or_twice(duplex_pdb):
    u = mda.Universe(str(duplex_pdb))
    r = [res.resid for res in u.residues]
    with pytest.raises(InputError, match="cannot pair with itself"):
        BasePairFrames(u, pairs=[(r[0], r[0])], pair_numbering="resid")
    with pytest.raises(InputError, match="is in two base pairs"):
        BasePairFrames(u, pairs=[(1, 16), (2, 16)], pair_numbering="serial")


def test_mismatched_explicit_pair_is_flagged(duplex_pdb):
    u = mda.Universe(str(duplex_pdb))
    # serial 1 is G (strand I, 5' end); serial 9 is the first of strand II:
    # the complement of SEQ[-1] = C, i.e. G: G-G is not Watson-Crick
    with pytest.warns(UserWarning, match=r"is not Watson-Crick \(G-G\)"):
        BasePairFrames(u, pairs=[(1, 9)], pair_numbering="serial")
