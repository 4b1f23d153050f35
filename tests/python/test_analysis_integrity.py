"""Base-pair integrity (N1-N3 < 3.5 A, minimum image) on a real crystal structure:
all 12 Watson-Crick pairs of the Dickerson-Drew dodecamer (355D) are paired, also
after its atoms are wrapped into a small periodic box, where plain distances fail."""
import numpy as np
import pytest

from mdbridge.md.integrity import _central_atom, bp_intact_fraction


def test_dodecamer_pairs_intact_also_when_wrapped(refdata):
    import MDAnalysis as mda
    from mdbridge.geometry.structure import BasePairFrames
    u = mda.Universe(str(refdata / "355d" / "355d.pdb"))
    u = mda.Merge(u.select_atoms("nucleic"))
    pairs = BasePairFrames(u).pairs
    assert len(pairs) == 12
    _, frac, dist = bp_intact_fraction(u, pairs)
    assert frac[0] == 1.0
    assert np.all((dist > 2.6) & (dist < 3.2))  # Watson-Crick N1-N3 ~2.9 A
    # wrap into a box smaller than the duplex: only minimum images keep the pairs
    u.dimensions = [16.0, 16.0, 16.0, 90.0, 90.0, 90.0]
    u.atoms.wrap(compound="atoms")
    _, frac_w, dist_w = bp_intact_fraction(u, pairs)
    np.testing.assert_allclose(dist_w, dist, atol=1e-3)
    a = np.array([_central_atom(p[0]).position for p in pairs])
    b = np.array([_central_atom(p[1]).position for p in pairs])
    assert np.mean(np.linalg.norm(a - b, axis=1) < 3.5) < 1.0  # naive distances break


def test_wrong_residue_is_named(refdata):
    import MDAnalysis as mda
    from dna_models.errors import InputError
    u = mda.Universe(str(refdata / "355d" / "355d.pdb"))
    water = u.select_atoms("resname HOH").residues[:1]
    nuc = u.select_atoms("nucleic").residues[:1]
    with pytest.raises(InputError, match="HOH"):
        bp_intact_fraction(u, [(water[0], nuc[0])])


def test_every_watson_crick_hbond_of_the_dodecamer(refdata):
    """CGCGAATTCGCG: 8 G-C pairs (three H-bonds) and 4 A-T pairs (two), all at H-bond
    distances in the crystal (2.6-3.3 A), N1-N3 in the first slot."""
    import MDAnalysis as mda
    from mdbridge.geometry.structure import BasePairFrames
    from mdbridge.md.integrity import hbond_atoms, hbond_table, pair_distances
    u = mda.Universe(str(refdata / "355d" / "355d.pdb"))
    u = mda.Merge(u.select_atoms("nucleic"))
    pairs = BasePairFrames(u).pairs
    a, b, pair, slot, names = hbond_atoms(pairs)
    assert len(a) == 8 * 3 + 4 * 2
    d = pair_distances(a.positions, b.positions)
    assert np.all((d > 2.6) & (d < 3.3)), d
    table = hbond_table(pairs, d[None])
    assert table.shape == (1, 12, 3)
    _, _, n13 = bp_intact_fraction(u, pairs)
    np.testing.assert_allclose(table[0, :, 0], n13[0], atol=1e-6)     # slot 0 is N1-N3
    assert np.isnan(table[0, 4:8, 2]).all() and not np.isnan(table[0, :4, 2]).any()  # AATT: two


def test_integrity_summary_junction_against_interior():
    """Open fractions from distances with a known pattern: the junction pairs [n-2, n-1, 0,
    1] open half the time, pair 10 always, the rest never."""
    from mdbridge.md.integrity import integrity_summary
    n, T = 20, 8
    d = np.full((T, n), 2.9)
    d[::2, [18, 19, 0, 1]] = 4.0
    d[:, 10] = 5.0
    s = integrity_summary(d, np.arange(T) * 0.5)
    assert s["junction_pairs"] == [18, 19, 0, 1]
    assert s["junction_open_fraction"] == 0.5
    assert s["interior_open_fraction"] == pytest.approx(1 / 16)
    assert s["open_fraction"] == pytest.approx((4 * 0.5 + 1) / n)
    assert s["open_fraction_per_pair"][10] == 1.0 and s["open_fraction_per_pair"][5] == 0.0
    # after a 1-ps discard frames 2..7 remain: the same fractions
    s2 = integrity_summary(d, np.arange(T) * 0.5, discard_ps=1.0)
    assert s2["junction_open_fraction"] == 0.5 and len(s2["open_fraction_time"]) == T
    # control: a pair exactly at the rule is closed (open means beyond 3.5 A)
    d[:, 3] = 3.5
    assert integrity_summary(d, np.arange(T))["open_fraction_per_pair"][3] == 0.0


def test_hbond_path_reads_the_same_n1_n3(refdata):
    """PairIntegrity(hbonds=True) measures every H-bond and reads N1-N3 from their slot 0
    (what checks.json and the pair-hold screen use): equal to the direct N1-N3 measure."""
    import MDAnalysis as mda
    from mdbridge.geometry.structure import BasePairFrames
    from mdbridge.md.integrity import PairIntegrity
    u = mda.Merge(mda.Universe(str(refdata / "355d" / "355d.pdb")).select_atoms("nucleic"))
    pairs = BasePairFrames(u).pairs
    direct = PairIntegrity(u, pairs).run().results
    both = PairIntegrity(u, pairs, hbonds=True).run().results
    np.testing.assert_array_equal(both.distance_A, direct.distance_A)
    assert both.hbond_A.shape == (1, 12, 3) and both.hbond_distance_A.shape == (1, 8 * 3 + 4 * 2)


def test_stacking_of_the_dodecamer_and_a_kink(refdata):
    """No step of the crystal dodecamer (355D) is unstacked (3DNA rise 3.1-3.6 A there); a step
    whose rise is set to a kink's (6 A, as the vacuum MD's kinked steps) in half the frames is
    counted, per step and over time (the control: the same series without it counts none)."""
    import MDAnalysis as mda
    from mdbridge.geometry.structure import BasePairFrames
    from mdbridge.md.integrity import stacking_summary
    u = mda.Merge(mda.Universe(str(refdata / "355d" / "355d.pdb")).select_atoms("nucleic"))
    rise = BasePairFrames(u).run().step_parameters()[:, :, 2]
    assert stacking_summary(rise, [0.0])["unstacked_fraction"] == 0.0
    series = np.repeat(rise, 10, axis=0)
    kinked = series.copy()
    kinked[5:, 4] = 6.0
    s = stacking_summary(kinked, np.arange(10.0))
    assert s["unstacked_fraction"] == pytest.approx(5 / (10 * 11))
    assert s["unstacked_fraction_per_step"][4] == 0.5 and s["mostly_unstacked_steps"] == []
    assert s["unstacked_fraction_time"][:5] == [0.0] * 5 and s["unstacked_fraction_time"][5] == pytest.approx(1 / 11)
    assert stacking_summary(kinked, np.arange(10.0), discard_ps=5)["mostly_unstacked_steps"] == [4]
    assert stacking_summary(series, np.arange(10.0))["unstacked_fraction"] == 0.0
