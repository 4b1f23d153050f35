"""Base-pair frames, step and base-pair parameters against 3DNA v2.3's own
output on real structures (independent truth: 3DNA, refdata/).

3DNA prints step/base-pair parameters with 3 decimals (bp_step.par), frames
with 4 (ref_frames.dat) and its published analysis with 2 (.out): the bounds
below are half a unit of the last printed decimal plus 2e-4 because
MDAnalysis stores coordinates in float32 (which moves angles by up to ~2e-4
deg); with the PDB's coordinates read in double precision the agreement is
within half a unit of the last printed decimal
(test_md_ensemble_exact_with_double_coordinates), i.e. exact to what 3DNA prints.
"""
import gzip
import warnings

import numpy as np
import pytest

import MDAnalysis

from mdbridge.geometry.structure import BasePairFrames  # noqa: E402
from mdbridge.geometry.x3dna import read_bp_step_par, read_out_table, read_ref_frames  # noqa: E402

TOL3 = 0.0005 + 2e-4   # 3 printed decimals
TOL4 = 0.00005 + 1e-5  # 4 printed decimals (frames: unit vectors and origins)
TOL2 = 0.005 + 2e-4    # 2 printed decimals


def _universe(path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return MDAnalysis.Universe(str(path))


def _analyse(path, **kw):
    return BasePairFrames(_universe(path), **kw).run()


@pytest.fixture(scope="module")
def d355(refdata):
    return _analyse(refdata / "355d" / "355d.pdb")


def test_355d_step_parameters_equal_3dna(d355, refdata):
    _, bp_ref, step_ref = read_bp_step_par(refdata / "355d" / "bp_step.par")
    steps = d355.step_parameters()[0]
    assert d355.sequence == "CGCGAATTCGCG"
    assert steps.shape == (11, 6)
    err = np.abs(steps - step_ref)
    assert err.max() < TOL3, f"max deviation from 3DNA {err.max(axis=0)}"


def test_355d_base_pair_parameters_equal_3dna(d355, refdata):
    _, bp_ref, _ = read_bp_step_par(refdata / "355d" / "bp_step.par")
    err = np.abs(d355.results.bp_parameters[0] - bp_ref)
    assert err.max() < TOL3, f"max deviation {err.max(axis=0)}"


def test_355d_frames_equal_3dna(d355, refdata):
    o_ref, R_ref = read_ref_frames(refdata / "355d" / "ref_frames.dat")
    assert np.abs(d355.results.origins[0] - o_ref).max() < TOL4
    assert np.abs(d355.results.R[0] - R_ref).max() < TOL4


def test_355d_published_analysis(d355, refdata):
    """bdl084_published_v2.0.out: 3DNA's published NDB analysis, 2 decimals."""
    out = refdata / "355d" / "bdl084_published_v2.0.out"
    _, steps_ref = read_out_table(out, "Local base-pair step parameters")
    _, bp_ref = read_out_table(out, "Local base-pair parameters")
    assert np.abs(d355.step_parameters()[0] - steps_ref).max() < TOL2
    assert np.abs(d355.results.bp_parameters[0] - bp_ref).max() < TOL2


def test_fiber_bdna_equals_3dna(refdata):
    d = refdata / "fiber_bdna"
    r = _analyse(d / "fiber_B_CGCGAATTCGCG.pdb")
    _, bp_ref, step_ref = read_bp_step_par(d / "bp_step.par")
    o_ref, R_ref = read_ref_frames(d / "ref_frames.dat")
    assert np.abs(r.step_parameters()[0] - step_ref).max() < TOL3
    assert np.abs(r.results.bp_parameters[0] - bp_ref).max() < TOL3
    assert np.abs(r.results.origins[0] - o_ref).max() < TOL4
    assert np.abs(r.results.R[0] - R_ref).max() < TOL4


def test_fiber_bdna_is_a_10_fold_helix(refdata):
    """Arnott B-DNA: 10 bp per turn, 3.375 A per bp along the helix axis
    (dna_models.bdna). The twists of consecutive steps sum to 360 deg per
    10 steps only approximately (local twists), but the end-to-end rotation of
    base-pair frames 0 -> 10 is exactly one turn about the helix axis."""
    from dna_models import bdna
    r = _analyse(refdata / "fiber_bdna" / "fiber_B_CGCGAATTCGCG.pdb")
    R, o = r.results.R[0], r.results.origins[0]
    rel = R[0].T @ R[10]          # ten steps: identity up to the sequence-independent screw
    assert np.allclose(rel, np.eye(3), atol=2e-3)
    axis_rise = np.linalg.norm(o[10] - o[0]) / 10
    assert axis_rise == pytest.approx(bdna.FIBRE_RISE_A, abs=1e-3)
    assert np.mean(r.step_parameters()[0][:, 5]) == pytest.approx(bdna.TWIST_DEG, abs=0.5)


def test_md_ensemble_model_0_equals_3dna(refdata):
    """21-model MD PDB of a 12-bp hairpin (AMBER names C1*, O1P), pairs from
    3DNA's bpfile.dat; model 0 against 3DNA's analysis of model 0."""
    from mdbridge.geometry.structure import read_pairs_file
    d = refdata / "md_sample_3dna"
    pairs, numbering = read_pairs_file(d / "bpfile.dat")
    assert numbering == "serial" and len(pairs) == 12
    r = BasePairFrames(_universe(d / "sample_md0.pdb.gz"), pairs=pairs, pair_numbering=numbering).run()
    assert r.results.R.shape == (21, 12, 3, 3)
    _, bp_ref, step_ref = read_bp_step_par(d / "model_00.bp_step.par")
    o_ref, R_ref = read_ref_frames(d / "model_00.ref_frames.dat")
    assert np.abs(r.step_parameters()[0] - step_ref).max() < TOL3
    assert np.abs(r.results.bp_parameters[0] - bp_ref).max() < TOL3
    assert np.abs(r.results.origins[0] - o_ref).max() < TOL4
    assert np.abs(r.results.R[0] - R_ref).max() < TOL4
    # automatic pairing of the hairpin finds the same pairs
    auto = BasePairFrames(_universe(d / "sample_md0.pdb.gz"))
    assert [(i + 1, j + 1) for i, j in auto.pair_index] == pairs


def test_md_ensemble_exact_with_double_coordinates(refdata):
    """Same as above with model 0's coordinates parsed in double precision:
    every parameter within half a unit of 3DNA's last printed decimal."""
    from mdbridge.geometry.steps import step_parameters_along
    from mdbridge.geometry.structure import read_pairs_file
    d = refdata / "md_sample_3dna"
    pairs, numbering = read_pairs_file(d / "bpfile.dat")
    bpf = BasePairFrames(_universe(d / "sample_md0.pdb.gz"), pairs=pairs, pair_numbering=numbering)
    xyz = []
    for ln in gzip.open(d / "sample_md0.pdb.gz", "rt"):
        if ln.startswith("ENDMDL"):
            break
        if ln.startswith(("ATOM", "HETATM")):
            xyz.append([float(ln[30:38]), float(ln[38:46]), float(ln[46:54])])
    X = np.array(xyz)[bpf._atom_index][None]
    res = bpf.frames_from_positions(X)
    _, bp_ref, step_ref = read_bp_step_par(d / "model_00.bp_step.par")
    assert np.abs(res["bp_parameters"][0] - bp_ref).max() <= 0.0005 + 1e-9
    assert np.abs(step_parameters_along(res["R"], res["origins"])[0] - step_ref).max() <= 0.0005 + 1e-9


def test_1kx5_nucleosome_runs(refdata):
    """147-bp nucleosome DNA (two DNA chains among 8 protein chains): runs,
    pairs all 147 bp, and gives B-like numbers (mean rise ~3.3-3.4 A, mean twist
    ~34-35 deg, strong roll variation from the wrapping)."""
    r = _analyse(refdata / "1kx5" / "1kx5.pdb.gz")
    assert r.n_bp == 147
    s = r.step_parameters()[0]
    assert np.all(np.isfinite(s))
    assert 3.2 < s[:, 2].mean() < 3.5
    assert 33.0 < s[:, 5].mean() < 36.5
    assert s[:, 4].std() > 4.0
    assert np.all(r.results.rmsd < 0.3)


@pytest.mark.parametrize("pdb,par", [("rebuilt_ideal_B.pdb", "ideal_B_36_3.38.par"),
                                     ("rebuilt_355d_steps_zero_bp.pdb", "355d_steps_zero_bp.par")])
def test_3dna_rebuilt_structures_give_back_their_parameters(refdata, pdb, par):
    """3DNA `rebuild` made these duplexes from known step parameters (and zero
    base-pair parameters); analysing them returns those parameters up to the
    PDB's 3-decimal coordinate rounding (~0.01 deg over a base's ~5 A lever)."""
    d = refdata / "rebuild_3dna_bdna"
    r = _analyse(d / pdb)
    _, bp_ref, step_ref = read_bp_step_par(d / par)
    err = np.abs(r.step_parameters()[0] - step_ref)
    assert err[:, :3].max() < 0.002 and err[:, 3:].max() < 0.02, err.max(axis=0)
    assert np.abs(r.results.bp_parameters[0] - bp_ref).max() < 0.03
