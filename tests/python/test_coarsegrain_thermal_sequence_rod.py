"""The closed loop on a sequence rod: coarse-grain a thermal Olson 1998 rod and recover its
sequence-dependent material (docs/coarse-graining.md, "A thermal rod through the estimator").

The rod is `dnarod dna-rod` of a 42-bp sequence under Olson et al. 1998 (per-point coupled
6 x 6 K, `--shape exact`: read at its base pairs the intrinsic shape has Olson's step
parameters), two grid points per base pair (docs/dna-rod.md: one point per bp under-resolves
the sequence's fields; the uniform loop, tests/python/test_coarsegrain_thermal_rod.py, shows
what one point per bp does to the per-step stiffness). It starts from its intrinsic, curved,
stress-free shape and runs as a Langevin rod at the Olson table's temperature (dt = 0.025:
why, test_sequence_rod_returns_its_rest_shape) without the closure projection
(`keep_closure = false`). Why without: a box-held rod at 298 K carries a slack tension (and
the closed state of `dna-rod` a pre-stress, 28 pN here) that adds F / k^2 to the bend
stiffness of the long laboratory bends, which the q -> 0 fit's base-pair-frame modes contain
(measured: tilt and roll K(q -> 0) 6 % stiff, z = 2.3 and 2.9, with the box kept). Without
the box the rod's holonomy is free, the Liouville argument of docs/thermal.md still holds,
and the stationary distribution is exp(-E / kT) of the material alone: independent grid
strains N(x0_i, kT K_i^-1 / h). Known answers:

* K(q -> 0) (`params.json` `average.stiffness`, per step, kT units) is the series
  (compliance) average of the per-step stiffness over the kept steps, (mean_j F_j^-1)^-1,
  with F_j from Olson's table here. Control: the arithmetic mean of F_j (1.24x in rise) must
  fail the same check.
* The mean step parameters are the step parameters of the exact stationary distribution,
  computed by Monte Carlo (mdbridge/rod/material/thermal_steps.py: independent Gaussian grid
  strains, composed along the trigonometric interpolant, read with the 3DNA definitions):
  Olson's shape plus its O(kT) thermal shift, given the run's holonomy. Without the box the
  holonomy moves only by the semi-discrete rod's closure defect, a slow random walk (a run's
  total twist wanders by up to ~0.8 deg per step over 16000 rod times), so a run samples the
  distribution conditioned on its own holonomy, whose mean moves along six directions
  K^-1 B^T e_k that spread the holonomy's change over the steps by their
  (sequence-dependent) compliance. Those six are fitted out (holonomy_directions).
  Control: the sequence-averaged shape must fail.
"""
import json
import shutil
import subprocess

import h5py
import numpy as np
import pytest

from benchscripts import load_bench
from dnarod.cli import main
from mdbridge.rod.material.parameter_sets import dimers, olson1998_table
from mdbridge.rod.material.thermal_steps import holonomy_directions, off_holonomy, stationary_step_means

LOOP = load_bench("cg_sequence_seeds.py")   # the rod and scene of the loop, one home
N_BP = LOOP.N_BP
TABLE = olson1998_table()
CHI2_MAX = 1.8   # chi^2_41 / 41 above it: p = 0.13 % per parameter, 0.8 % for any of six


@pytest.fixture(scope="module")
def loop(tmp_path_factory, rodsim):
    d = tmp_path_factory.mktemp("thermal_sequence_rod")
    rod, material, sequence, L, N = LOOP.make_rod(d)
    (rod / "thermal.toml").write_text(LOOP.scene_text(L, N, 0.025, 11, TABLE["temperature_K"]))
    h5 = d / "thermal.h5"
    subprocess.run([str(rodsim), "run", str(rod / "thermal.toml"), "-o", str(h5)], check=True, capture_output=True)
    with h5py.File(h5, "r") as f:
        kT = float(f.attrs["kT"])
    out = d / "cg"
    assert main(["coarse-grain", str(h5), "-o", str(out), "--discard", "0", "--m-max", "2", "--bootstrap", "100"]) == 0
    return {"params": json.loads((out / "params.json").read_text()), "sequence": sequence,
            "material": material, "L": L, "kT": kT, "h5": h5}


def olson_steps(sequence):
    """Olson's per-step mean (n, 6) and stiffness F (n, 6, 6) of the closed duplex, kT units."""
    rows = [TABLE["steps"][xy] for xy in dimers(sequence, closed=True)]
    return np.array([r[0] for r in rows]), np.array([r[1] for r in rows])


def z_scores(K, err, truth):
    iu = np.triu_indices(6)
    return ((K - truth) / err)[iu]


def test_sequence_rod_returns_its_series_stiffness(loop):
    """K(q -> 0) of the rod's steps is the compliance average of Olson's F over the kept steps:
    all 21 elements within 4 of their errors (21 z-scores: a false alarm below 1 % even with
    the bootstrap's errors ~15 % small, docs/coarse-graining.md "Errors")."""
    p = loop["params"]
    assert p["temperature_K"] == TABLE["temperature_K"] and p["temperature_source"].startswith("rod file")
    assert p["excluded"]["steps"] == [N_BP]                 # the closing step
    _, F = olson_steps(loop["sequence"])
    kept = F[:-1]
    series = np.linalg.inv(np.mean(np.linalg.inv(kept), axis=0))
    K, err = np.array(p["average"]["stiffness"]), np.array(p["average"]["stiffness_err"])
    assert np.all(np.diag(err) < 0.05 * np.diag(K))        # the run resolves K to a few %
    z = z_scores(K, err, series)
    print("z (series average):", np.round(z, 2))
    assert np.abs(z).max() < 4.0, z


def test_control_arithmetic_mean_stiffness_is_rejected(loop):
    """Must fail the test above: the arithmetic mean of the per-step F is stiff in rise by
    Olson's step-to-step variation (1.24x here) and many errors away in several elements."""
    p = loop["params"]
    _, F = olson_steps(loop["sequence"])
    kept = F[:-1]
    series = np.linalg.inv(np.mean(np.linalg.inv(kept), axis=0))
    arithmetic = kept.mean(axis=0)
    assert 1.15 < arithmetic[2, 2] / series[2, 2] < 1.35
    z = z_scores(np.array(p["average"]["stiffness"]), np.array(p["average"]["stiffness_err"]), arithmetic)
    print("z (arithmetic mean):", np.round(z, 2))
    assert np.abs(z).max() > 10.0, z


@pytest.fixture(scope="module")
def rest_shape(loop):
    p = loop["params"]
    steps = [s for s in p["steps"] if not s["excluded"]]
    mean = np.array([s["mean"] for s in steps])
    err = np.array([s["mean_err"] for s in steps])
    truth, mc_err = stationary_step_means(loop["material"], loop["L"], loop["kT"], N_BP)
    q_olson, _ = olson_steps(loop["sequence"])
    directions = holonomy_directions(loop["material"], loop["L"], N_BP)[:, :-1]
    return mean, np.hypot(err, mc_err[:-1]), truth[:-1], q_olson[:-1], directions


def test_sequence_rod_returns_its_rest_shape(rest_shape):
    """The mean step parameters are the stationary distribution's given the run's holonomy,
    step by step: per parameter chi^2 / 41 below CHI2_MAX after the six holonomy directions are
    fitted out (sampling theory for exact errors: 1 +- 0.22; CHI2_MAX = 1.8 is p = 0.13 % per
    parameter). Why the holonomy: without the box it is held only by the semi-discrete rod's
    closure defect, so each run sits on its own slowly wandering holonomy (the total twist
    wanders by up to ~0.8 deg per step over the run), and the conditional mean spreads that
    over the steps by their compliance, which is sequence-dependent. Why dt = 0.025: at 0.05
    (friction 0.05) the Langevin step biases the long-wave grid strain means by ~1 % of their
    thermal spread, 0.9 of a run's error of the per-step mean (docs/coarse-graining.md).
    The thermal shift itself is small against the sequence's: the truth is within 0.05 A
    and 0.2 deg of Olson's shape."""
    mean, err, truth, q_olson, directions = rest_shape
    assert np.abs(truth - q_olson)[:, :3].max() < 0.05 and np.abs(truth - q_olson)[:, 3:].max() < 0.2
    chi2 = (off_holonomy(mean - truth, err, directions) ** 2).mean(axis=0)
    print("chi2 / n per parameter:", np.round(chi2, 2))
    assert np.all(chi2 < CHI2_MAX), chi2


def test_control_sequence_averaged_shape_is_rejected(rest_shape):
    """Must fail the test above: a uniform rod's shape (the sequence average of the truth)
    misses every parameter's sequence dependence by far more than the errors."""
    mean, err, truth, _, directions = rest_shape
    uniform = np.broadcast_to(truth.mean(axis=0), truth.shape)
    chi2 = (off_holonomy(mean - uniform, err, directions) ** 2).mean(axis=0)
    print("chi2 / n per parameter, sequence-averaged shape:", np.round(chi2, 1))
    assert np.all(chi2 > 30.0), chi2


def test_missing_material_file_is_an_input_error(loop, tmp_path, capsys):
    """A sequence rod's base pairs come from the material file its run names: when that file
    is gone, exit 2 naming the attribute, before any work."""
    h5 = tmp_path / "moved.h5"
    shutil.copy(loop["h5"], h5)
    with h5py.File(h5, "r+") as f:
        f.attrs["material.material_file"] = str(tmp_path / "gone.h5")
    assert main(["coarse-grain", str(h5), "-o", str(tmp_path / "cg")]) == 2
    err = capsys.readouterr().err
    assert "gone.h5" in err and "material.material_file" in err
    assert not (tmp_path / "cg").exists()
