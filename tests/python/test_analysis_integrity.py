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
