"""`dnarod coarse-grain` on a real third-party MD ensemble and on bad input.

tests/data/md_sample_3dna/sample_md0.pdb.gz: 3DNA's example MD ensemble, 21 models of a 12-bp hairpin
(AMBER names), pairs in bpfile.dat; model_00.bp_step.par is 3DNA v2.3's own analysis
of model 0 (3 printed decimals). Truth for the per-frame step parameters the
estimator starts from; the 21-model means and stiffness are reported with the
caveat that 21 frames are few (N_eff ~ 20: stiffness errors ~ 30 % or more).
"""
import json
import warnings

import MDAnalysis
import numpy as np
import pytest

from cg_truth import DATA
from mdbridge.geometry.x3dna import read_bp_step_par
from dnarod.cli import main

TOL3 = 0.0005 + 2e-4   # 3 printed decimals + float32 coordinates (test_geometry_3dna.py)


@pytest.fixture(scope="module")
def ensemble():
    from mdbridge.coarsegrain.reader import read_ensemble
    from mdbridge.geometry.structure import read_pairs_file
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        u = MDAnalysis.Universe(str(DATA / "md_sample_3dna" / "sample_md0.pdb.gz"))
        pairs, numbering = read_pairs_file(DATA / "md_sample_3dna" / "bpfile.dat")
        return read_ensemble(u, pairs, numbering, max_open_fraction=0.0)


def test_model0_step_parameters_equal_3dna(ensemble):
    ens, _ = ensemble
    _, _, ref = read_bp_step_par(DATA / "md_sample_3dna" / "model_00.bp_step.par")
    assert ens.n_frames == 21 and ens.sequence == "CCTAATAGAAAT" and not ens.closed
    assert np.abs(ens.q[0] - ref).max() < TOL3


def test_opened_pairs_are_marked_for_the_rule_and_kept(ensemble):
    """N1-N3 > 3.5 A occurs in single models for pairs 6, 7 and 10 (6.46 A for pair 6):
    the strict rule (any frame) marks their steps for its sensitivity; every step is used."""
    ens, extras = ensemble
    assert list(extras["opened_pairs"] + 1) == [6, 7, 10]
    assert list(np.flatnonzero(ens.opened) + 1) == [5, 6, 7, 9, 10]
    assert not ens.excluded.any()


def _run(tmp_path, *extra):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        d = DATA / "md_sample_3dna"
        return main(["coarse-grain", str(d / "sample_md0.pdb.gz"), "--pairs", str(d / "bpfile.dat"),
                     "-o", str(tmp_path), *extra])


def test_21_models_reported_with_caveat(tmp_path, capsys):
    # m <= 4: a window's steps are left out in the models where they touch an open pair
    # (frame by frame), and the 6-step windows over pairs 6-10 keep 18 of the 21 models, too
    # few for a 6x6 covariance
    rc = _run(tmp_path, "--temperature", "300", "--min-effective", "5", "--discard", "0",
              "--max-open-fraction", "0", "-m", "4", "--m-max", "4", "--leave-out-open-frames")
    assert rc == 0
    p = json.loads((tmp_path / "params.json").read_text())
    assert p["temperature_source"] == "given" and p["frames_used"] == 21
    assert any("below the default" in c for c in p["caveats"])
    assert len(p["steps"]) == 11 and not any(s["excluded"] for s in p["steps"])
    # the strict rule's steps are used, and left out only for the sensitivity beside the rod's K
    assert p["opening_rule"]["steps"] == [5, 6, 7, 9, 10]
    assert p["average"]["opening_rule"]["steps_left_out"] == [5, 6, 7, 9, 10]
    assert (tmp_path / "q_stiffness.png").stat().st_size > 10000
    avg = np.array(p["average"]["mean"])
    # mean rise and twist of this hairpin (3DNA's model 0 alone: 3.45 A, 31.0 deg)
    assert 3.3 < avg[2] < 3.6 and 27 < avg[5] < 34
    assert np.all(np.isfinite(np.array(p["average"]["stiffness_err"])))
    assert p["physical_m"] == 4 and p["physical"]["bend_persistence_length"]["unit"] == "nm"
    assert 0 < p["opening_rule"]["open_step_frames"] < 0.05
    assert 0.5 < p["mass_inertia"]["rho"]["ratio"] < 1.2 and p["mass_inertia"]["hydrogens_in_topology"]
    out = capsys.readouterr().out
    assert "caveat" in out and "params.json" in out
    # the headline persistence length is the rod's (K(q -> 0), docs/coarse-graining.md), not the
    # m-step segments' (which grow with m); the others are labelled as not the rod's
    lb = p["rod"]["constants"]["bend_persistence_length"]
    first = next(ln for ln in out.splitlines() if ln.startswith("the rod (K(q -> 0)"))
    assert f"bend persistence length {lb['value']:.4g} +- {lb['err']:.2g} nm" in first
    assert "not the rod's" in out


def test_too_few_frames_names_the_need(tmp_path, capsys):
    assert _run(tmp_path, "--temperature", "300", "--max-open-fraction", "0.05") == 2
    err = capsys.readouterr().err
    assert "too few frames" in err and "at least 50 are needed" in err


@pytest.mark.parametrize("args, msg", [
    (["--temperature", "-3"], "--temperature '-3': must be a positive temperature in K"),
    (["--temperature", "300", "--min-effective", "5", "-m", "40"], "--length 40: allowed 1.."),
    ([], "no velocities in the trajectory"),
    (["--temperature", "300", "--max-open-fraction", "1.5"],
     "--max-open-fraction: 1.5: out of range (allowed: >= 0 and < 1)"),
    (["--edr", "nope.edr"], "nope.edr: energy file not found"),
])
def test_bad_input_is_a_clear_error(tmp_path, capsys, args, msg):
    assert _run(tmp_path, *args) == 2
    assert msg in capsys.readouterr().err


def test_missing_file(tmp_path, capsys):
    assert main(["coarse-grain", str(tmp_path / "nope.pdb"), "-o", str(tmp_path)]) == 2
    assert "nope.pdb: file not found" in capsys.readouterr().err
