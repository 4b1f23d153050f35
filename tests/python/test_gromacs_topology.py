"""pdb2gmx ring closure, the junction check, and GROMACS errors, with the real gmx.

Test system, independent of dnarod's builder: base pairs 1-10 of 3DNA's
rebuilt ideal B-DNA (refdata/rebuild_3dna_bdna/rebuilt_ideal_B.pdb; twist 36,
rise 3.38 A). Ten 36-degree steps are one exact turn, so those ten pairs are
one period of an infinite duplex with period 33.8 A along z: each strand's
last O3' sits one bond length from its first P shifted by one period.
Known facts (docs/md.md, measured with GROMACS 2022.5 charmm27): a closed
strand's junction carries 1 bond, 4 angles, 7 proper dihedrals and 7 pairs.
"""
import json

import numpy as np
import pytest

from dna_models.errors import ExternalToolError
from mdbridge.md.gromacs.gmx import error_block, find_gmx
from mdbridge.md.gromacs.junction import junction_report
from mdbridge.md.gromacs.topology import parse_itp, read_pdb_chains, run_pdb2gmx, write_pdb2gmx_input

PERIOD_A = 33.8


@pytest.fixture(scope="module")
def one_turn_chains(refdata):
    chains = read_pdb_chains(refdata / "rebuild_3dna_bdna" / "rebuilt_ideal_B.pdb")
    a, b = chains
    assert [r[0] for r in a["residues"]] == list(range(1, 13))
    # strand II residue 25 - k pairs with strand I residue k: keep pairs 1..10
    a["residues"] = a["residues"][:10]
    b["residues"] = [r for r in b["residues"] if r[0] >= 15]
    return chains


def _atom(chains, cid, resid, name):
    for ch in chains:
        if ch["id"] == cid:
            for r in ch["residues"]:
                if r[0] == resid:
                    return np.array(dict(r[2])[name])
    raise KeyError((cid, resid, name))


def test_test_system_is_one_exact_period(one_turn_chains):
    # strand I runs up z, so its first P is one period above; strand II runs down
    for cid, first, last, sign in (("A", 1, 10, 1), ("B", 15, 24, -1)):
        shift = np.array([0, 0, sign * PERIOD_A])
        link = _atom(one_turn_chains, cid, first, "P") + shift - _atom(one_turn_chains, cid, last, "O3'")
        assert 1.5 < np.linalg.norm(link) < 1.7


@pytest.mark.parametrize("ff", ["charmm27", "amber99sb-ildn"])
def test_ring_closure_gives_exactly_the_interior_junction_terms(gmx, one_turn_chains, tmp_path, ff):
    pdb = tmp_path / "in.pdb"
    write_pdb2gmx_input(pdb, one_turn_chains, ff)
    top = run_pdb2gmx(gmx, pdb, tmp_path, ff, lb_nm=2 * PERIOD_A / 10 + 1)
    mols = [parse_itp(p) for p in top["itps"]]
    assert len(mols) == 2
    for m in mols:
        rep = junction_report(m)
        assert rep["ok"], json.dumps(rep, indent=1)
        c = rep["junction_counts"]
        assert (c["bonds"], c["angles"], c["proper_dihedrals"], c["pairs"]) == (1, 4, 7, 7)
        assert rep["junction_total"] == 19
        # cyclic: no termini, exactly -1 e per nucleotide (10 per strand)
        assert m.charge.sum() == pytest.approx(-10.0, abs=1e-6)
        assert not {"H5T", "H3T", "HO5'", "HO3'"} & set(m.atomname)


def test_junction_check_catches_a_missing_or_extra_term(gmx, one_turn_chains, tmp_path):
    pdb = tmp_path / "in.pdb"
    write_pdb2gmx_input(pdb, one_turn_chains, "charmm27")
    top = run_pdb2gmx(gmx, pdb, tmp_path, "charmm27", lb_nm=8.0)
    m = parse_itp(top["itps"][0])
    first, last = m.residues[0], m.residues[-1]
    link = [b for b in m.terms["bonds"] if {int(m.resnr[a - 1]) for a in b} == {first, last}]
    assert len(link) == 1
    names = sorted(m.atomname[a - 1] for a in link[0])
    assert names == ["O3'", "P"]
    m.terms["bonds"].remove(link[0])                     # a ring that was not closed
    rep = junction_report(m)
    assert not rep["ok"] and rep["junction_counts"]["bonds"] == 0
    assert rep["mismatch"][0]["kind"] == "bonds"
    m.terms["bonds"].append(link[0])
    assert junction_report(m)["ok"]
    dup = [a for a in m.terms["angles"] if {int(m.resnr[i - 1]) for i in a} == {first, last}][0]
    m.terms["angles"].append(dup)                        # one junction angle counted twice
    rep = junction_report(m)
    assert not rep["ok"] and rep["junction_counts"]["angles"] == 5


def test_gmx_discovery_errors_say_how_to_fix(monkeypatch):
    monkeypatch.setenv("DNAROD_GMX", "/nonexistent/gmx")
    with pytest.raises(ExternalToolError, match="DNAROD_GMX.*apt-get install gromacs"):
        find_gmx()
    monkeypatch.delenv("DNAROD_GMX")
    monkeypatch.setenv("PATH", "/nonexistent")
    monkeypatch.setenv("DNAROD_GROMACS_PREFIX", "/nonexistent")   # nor a project build
    with pytest.raises(ExternalToolError, match="not found on PATH.*--gmx"):
        find_gmx()
    with pytest.raises(ExternalToolError, match="--gmx"):
        find_gmx("/nonexistent/bin/gmx")


def test_error_block_keeps_the_reason_and_drops_the_banner():
    text = """                :-) GROMACS - gmx grompp, 2022.5 (-:
Executable:   /usr/bin/gmx

NOTE 1 [file md.mdp]:
  harmless

ERROR 1 [file md.mdp, line 3]:
  Invalid enum 'bogus' for variable integrator, using 'md'

-------------------------------------------------------
Program:     gmx grompp, version 2022.5
Fatal error:
There was 1 error in input file(s)

For more information and tips for troubleshooting, please check the GROMACS
website at http://www.gromacs.org/Documentation/Errors
-------------------------------------------------------

GROMACS reminds you: "quote"
"""
    b = error_block(text)
    assert "Invalid enum 'bogus' for variable integrator" in b
    assert "There was 1 error" in b
    assert "harmless" not in b and "reminds you" not in b and "Executable" not in b
