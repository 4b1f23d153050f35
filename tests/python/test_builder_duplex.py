"""The builder on its own terms: chemistry of ideal B-DNA, the helix and
antiparallel strands, periodic closure, round trips through PDB + MDAnalysis
+ the 3DNA-exact analysis, and error messages. Truths used: the analytic
uniform helix, Watson-Crick pairing distances, screw symmetry, the O3'-P
covalent bond length, and the input parameters themselves."""
import numpy as np
import pytest

from dna_models.errors import InputError
from mdbridge.md.builder import (build_duplex, check_chemistry, frames_from_steps, ideal_frames,
                            read_pdb, write_pdb)
from mdbridge.md.builder.chemistry import excluded_pairs

SEQ12 = "CGCGAATTCGCG"


def rz(deg):
    c, s = np.cos(np.radians(deg)), np.sin(np.radians(deg))
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1.0]])


def test_ideal_frames_are_the_analytic_helix():
    R, o = ideal_frames(7, 3.38, 36.0)
    for i in range(7):
        np.testing.assert_allclose(o[i], [0, 0, 3.38 * i], atol=1e-12)
        np.testing.assert_allclose(R[i], rz(36.0 * i), atol=1e-12)


@pytest.mark.parametrize("n,twist,periodic", [(12, 36.0, False), (158, 360 * 15 / 158, True),
                                              (20, 36.0, True)])
def test_ideal_bdna_chemistry(n, twist, periodic):
    rng = np.random.default_rng(1)
    seq = "".join(rng.choice(list("ACGT"), n))
    R, o = ideal_frames(n, 3.38, twist)
    s = build_duplex(seq, o, R, periodic_box=n * 3.38 if periodic else None)
    rep = check_chemistry(s)
    for links in rep.links:
        assert links.n_links == (n if periodic else n - 1)
        assert abs(links.shortest.distance - 1.6) <= 0.1
        assert abs(links.longest.distance - 1.6) <= 0.1
        assert (links.junction is not None) == periodic
    assert rep.closest_nonbonded.distance > 2.2
    assert rep.closest_between_nucleotides.distance > 2.2
    assert rep.ok()
    assert "verdict: OK" in str(rep)


def test_links_measured_independently():
    """The report's worst link is the O3'-P distance computed here by atom names."""
    R, o = ideal_frames(6)
    s = build_duplex("ACGTTG", o, R)
    rep = check_chemistry(s)
    d = [np.linalg.norm(s.coords[s.index(r + 1, "P")] - s.coords[s.index(r, "O3'")])
         for r in range(1, 6)]
    assert rep.links[0].longest.distance == pytest.approx(max(d), abs=1e-12)
    assert rep.links[0].shortest.distance == pytest.approx(min(d), abs=1e-12)
    assert rep.links[0].longest.atom_a.endswith(":O3'")


def test_strand_II_is_antiparallel_and_watson_crick_paired():
    R, o = ideal_frames(len(SEQ12))
    s = build_duplex(SEQ12, o, R)
    n = len(SEQ12)
    comp = {"A": "T", "C": "G", "G": "C", "T": "A"}
    for i, b in enumerate(SEQ12):
        j = 2 * n - i  # residue of strand II paired with base pair i+1
        assert s.resnames[s.resids == j][0] == "D" + comp[b]
        pur, pyr = (i + 1, j) if b in "AG" else (j, i + 1)
        # Watson-Crick: purine N1 to pyrimidine N3 ~2.9 A, C1'-C1' ~10.5 A
        d = np.linalg.norm(s.coords[s.index(pur, "N1")] - s.coords[s.index(pyr, "N3")])
        assert 2.7 < d < 3.1
        c1 = np.linalg.norm(s.coords[s.index(i + 1, "C1'")] - s.coords[s.index(j, "C1'")])
        assert 10.0 < c1 < 11.0
    # strand II runs 5'->3' along -z (antiparallel): its P atoms descend
    zP = [s.coords[s.index(r, "P")][2] for r in range(n + 1, 2 * n + 1)]
    assert np.all(np.diff(zP) < 0)
    zP1 = [s.coords[s.index(r, "P")][2] for r in range(1, n + 1)]
    assert np.all(np.diff(zP1) > 0)
    # every residue, the 5' ones included, carries its phosphate
    for r in range(1, 2 * n + 1):
        for a in ("P", "O1P", "O2P"):
            s.index(r, a)


def test_periodic_junction_equals_interior_link_by_screw_symmetry():
    """20 bp, twist 36: two full turns, so base pair 21 would be base pair 1
    shifted by the box: the junction link must equal the link 1 -> 2 in the
    same sequence context (ACGT... repeats with period 4 and 20 = 5 x 4)."""
    seq = "ACGT" * 5
    R, o = ideal_frames(20, 3.38, 36.0)
    s = build_duplex(seq, o, R, periodic_box=20 * 3.38)
    rep = check_chemistry(s)
    # O3'(T20)-P(A1) through the box vs O3'(T4)-P(A5) inside
    inner = np.linalg.norm(s.coords[s.index(5, "P")] - s.coords[s.index(4, "O3'")])
    assert rep.links[0].junction.distance == pytest.approx(inner, abs=1e-9)
    # the wrong box (one base pair too long) breaks the junction, and the report says so
    bad = check_chemistry(build_duplex(seq, o, R, periodic_box=21 * 3.38))
    assert bad.links[0].junction.distance > 2.5
    assert not bad.ok()
    assert "verdict: PROBLEM" in str(bad)


def test_bent_input_is_reported_bad():
    """Roll 25 degrees at every step (strongly kinked) stretches the backbone
    and brings atoms into contact; the report must say so."""
    steps = np.tile([0, 0, 3.38, 0, 25.0, 36.0], (9, 1))
    R, o = frames_from_steps(steps)
    rep = check_chemistry(build_duplex("ACGTACGTAC", o, R))
    assert rep.worst_link_deviation() > 0.3
    assert not rep.ok()


def test_round_trip_through_pdb_and_mdanalysis(tmp_path):
    """Build from random smooth step and base-pair parameters, write PDB, read
    it with MDAnalysis, analyse with mdbridge.geometry.BasePairFrames: the
    input comes back to the PDB's 3-decimal precision."""
    import MDAnalysis as mda
    from mdbridge.geometry.structure import BasePairFrames
    rng = np.random.default_rng(7)
    n = 15
    steps = np.array([0, 0, 3.38, 0, 0, 34.0]) + rng.normal(0, 1, (n - 1, 6)) * [0.3, 0.3, 0.1, 2, 3, 3]
    bp = rng.normal(0, 1, (n, 6)) * [0.2, 0.1, 0.2, 5, 8, 3]
    seq = "".join(rng.choice(list("ACGT"), n))
    R, o = frames_from_steps(steps)
    s = build_duplex(seq, o, R, base_pair_params=bp)
    write_pdb(tmp_path / "x.pdb", s)
    u = mda.Universe(str(tmp_path / "x.pdb"))
    assert len(u.atoms) == s.n_atoms
    assert sorted(set(u.atoms.segids)) == ["I", "II"]
    bpf = BasePairFrames(u).run()
    got = bpf.step_parameters()[0]
    err = np.abs(got - steps).max(axis=0)
    assert np.all(err[:3] < 2e-3), err      # A (measured 7e-4)
    assert np.all(err[3:] < 0.05), err      # degrees (measured 0.012)
    np.testing.assert_allclose(bpf.results.origins[0], o, atol=3e-3)


def test_pdb_written_is_read_back_exactly(tmp_path):
    R, o = ideal_frames(4)
    s = build_duplex("GATC", o, R, periodic_box=4 * 3.38)
    write_pdb(tmp_path / "y.pdb", s)
    back = read_pdb(tmp_path / "y.pdb")
    assert back["names"].tolist() == s.names.tolist()
    assert back["segids"].tolist() == s.strands.tolist()
    np.testing.assert_allclose(back["coords"], s.coords, atol=5e-4 + 1e-9)
    assert "H5'1" not in back["names"]  # heavy atoms only by default


def test_excluded_pairs_on_a_chain():
    # chain 0-1-2-3: 1-2 pairs (0,1),(1,2),(2,3); 1-3 pairs (0,2),(1,3); (0,3) is 1-4
    ex = excluded_pairs(4, np.array([[0, 1], [1, 2], [2, 3]]))
    assert ex == {0 * 4 + 1, 1 * 4 + 2, 2 * 4 + 3, 0 * 4 + 2, 1 * 4 + 3}


@pytest.mark.parametrize("kwargs,match", [
    (dict(sequence="ACXT"), "letter 'X' at position 3"),
    (dict(origins=np.zeros((3, 3))), r"origins \(4, 3\)"),
    (dict(R=np.tile(np.diag([1.0, 1.0, -1.0]), (4, 1, 1))), "not a proper rotation"),
    (dict(periodic_box=-5.0), "periodic_box"),
    (dict(base_pair_params=np.zeros((3, 6))), "base_pair_params"),
])
def test_errors_name_what_is_wrong(kwargs, match):
    R, o = ideal_frames(4)
    args = dict(sequence="ACGT", origins=o, R=R)
    args.update(kwargs)
    with pytest.raises(InputError, match=match):
        build_duplex(args.pop("sequence"), args.pop("origins"), args.pop("R"), **args)
