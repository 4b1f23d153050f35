"""hydrogens=True against GROMACS: on a structure the hydrogen templates were
not made from (355D step and base-pair parameters), every templated
hydrogen must sit where `gmx pdb2gmx -ff charmm27 -ignh` puts it (charmm27's
dna.hdb rules applied to our heavy atoms), and each residue must have
charmm27's atom count."""
import tempfile
from pathlib import Path

import numpy as np
import pytest

from mdbridge.md.builder import build_duplex, check_chemistry, frames_from_steps, ideal_frames, read_pdb, write_pdb
from mdbridge.md.builder.params import read_3dna_par

SIZES = {"DA": 32, "DT": 32, "DG": 33, "DC": 30}


def test_hydrogen_count_and_bonds():
    R, o = ideal_frames(4)
    s = build_duplex("ACGT", o, R, hydrogens=True)
    for r in range(1, 9):
        sel = s.resids == r
        assert sel.sum() == SIZES[s.resnames[sel][0]]
    # each hydrogen has exactly one bond, to a heavy atom of its own residue
    h = np.flatnonzero(s.elements == "H")
    for k in h:
        partners = s.bonds[(s.bonds == k).any(axis=1)].ravel()
        partners = partners[partners != k]
        assert len(partners) == 1 and s.elements[partners[0]] != "H"
        assert s.resids[partners[0]] == s.resids[k]
    rep = check_chemistry(s)
    assert rep.ok()


def test_hydrogens_match_pdb2gmx_on_355d(refdata):
    from mdbridge.md.builder.hydrogens import run_pdb2gmx_ignh
    import shutil
    if shutil.which("gmx") is None:
        pytest.fail("gmx not found: scripts/setup.sh installs the Debian package gromacs")
    p = read_3dna_par(refdata / "rebuild_3dna_bdna/355d_with_bp_params/in_step.par")
    R, o = frames_from_steps(p.steps)
    seq = p.sequence
    heavy = build_duplex(seq, o, R, base_pair_params=p.base_pair_params)
    ours = build_duplex(seq, o, R, base_pair_params=p.base_pair_params, hydrogens=True)
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        write_pdb(tmp / "heavy.pdb", heavy)
        gmx = read_pdb(run_pdb2gmx_ignh(tmp / "heavy.pdb", tmp))
    n = len(seq)
    dists = []
    for resid in range(1, 2 * n + 1):
        for k in np.flatnonzero((ours.resids == resid) & (ours.elements == "H")):
            name = ours.names[k]
            hit = np.flatnonzero((gmx["resids"] == resid) & (gmx["names"] == name))
            assert len(hit) == 1, (resid, name)
            dists.append(float(np.linalg.norm(gmx["coords"][hit[0]] - ours.coords[k])))
    assert len(dists) == (ours.elements == "H").sum()
    print(f"hydrogens vs pdb2gmx: rms {np.sqrt(np.mean(np.square(dists))):.2e} A, "
          f"max {max(dists):.2e} A over {len(dists)} atoms")
    # pdb2gmx reads our heavy atoms rounded to 3 decimals, computes in single
    # precision and writes 3 decimals; the one-H-on-a-tetrahedral-carbon rule
    # (H1', H3', H4') amplifies that rounding. Measured: rms 1.5e-3 A, max 5.0e-3 A.
    # A wrong template or frame would be off by tenths of an A or more.
    dists = np.array(dists)
    assert np.sqrt(np.mean(dists ** 2)) < 2.5e-3, np.sqrt(np.mean(dists ** 2))
    assert dists.max() < 1e-2, dists.max()


def test_stored_templates_are_what_pdb2gmx_gives_now():
    """dna_models/data/h_charmm27_bdna.json is not stale: regenerating it with
    the installed GROMACS and the current heavy-atom templates gives the same
    positions (to the 1e-4 A the file stores)."""
    import json
    import shutil
    if shutil.which("gmx") is None:
        pytest.fail("gmx not found: scripts/setup.sh installs the Debian package gromacs")
    from mdbridge.md.builder.hydrogens import generate
    from dna_models.templates import H_DATA
    stored = json.loads(H_DATA.read_text())["nucleotides"]
    fresh = generate()["nucleotides"]
    assert stored.keys() == fresh.keys()
    for res in stored:
        assert stored[res].keys() == fresh[res].keys()
        for name in stored[res]:
            np.testing.assert_allclose(stored[res][name], fresh[res][name], atol=2e-4)


def test_template_generator_finds_gmx_like_every_gromacs_step(tmp_path, monkeypatch):
    """The hydrogen generator runs gmx through mdbridge.md.gromacs.gmx (so DNAROD_GMX and
    --gmx are honoured, and failures name them) instead of its own PATH lookup."""
    from dna_models.errors import ExternalToolError
    from mdbridge.md.builder.hydrogens import run_pdb2gmx_ignh
    monkeypatch.setenv("DNAROD_GMX", str(tmp_path / "no-such-gmx"))
    with pytest.raises(ExternalToolError, match=r"gmx given by DNAROD_GMX .*no-such-gmx"):
        run_pdb2gmx_ignh(tmp_path / "x.pdb", tmp_path)
    with pytest.raises(ExternalToolError, match=r"gmx given by --gmx .*also-missing"):
        run_pdb2gmx_ignh(tmp_path / "x.pdb", tmp_path, str(tmp_path / "also-missing"))
