"""The closed loop: coarse-grain a thermal rod of a known material and recover it.

A Langevin rod of the paper's material (docs/thermal.md) at 300 K samples the Boltzmann
distribution of its discrete energy: strains at the grid points independent, covariance
kT K^-1 / h. Its output file goes through `dnarod coarse-grain` as a trajectory would. The
rod's frames are reconstructed from the strains with an interpolant, which averages each
grid cell with its neighbours (a cell's rotation variance is ~0.77 of the grid strain's):
per-step stiffness is high at short wavelength, while the long waves keep the grid's. So the
rod's own constants from K(q -> 0) must return the material's (Sec 2.1 at 300 K: bend
persistence 66.4 nm, torsional modulus 459 pN nm^2, stretch modulus C3 = 1080.5 pN) within
their stated errors, and the per-step compliance average (the control) must miss them: by
~1.29x at one grid point per base pair and ~1.1x at two.

Friction 0.05 (rod units) keeps every mode underdamped, so the slow laboratory bends that
the fit's base-pair-frame modes contain decorrelate within a few frames.
"""
import json
import subprocess

import pytest

from dnarod.cli import main

TRUTH = {"bend_persistence_length": 66.4, "torsional_modulus": 459.0, "stretch_modulus": 1080.5}


def _thermal_rod(tmp_path, rodsim, points_per_bp, seed):
    scene = tmp_path / f"rod{points_per_bp}.toml"
    scene.write_text(f"""[initial]
kind = "dna_planar"
bp = 42
turns = 4
A_v_A_per_ps = 0.0

[rod]
points = {42 * points_per_bp}

[solver]
time = "langevin"
dt = 0.05

[output]
t_end = 16000.0
frames = 4001
fields = ["centerline", "directors", "internal"]

[thermal]
temperature_K = 300
seed = {seed}
friction_translational = 0.05
friction_rotational = 0.05
""")
    h5 = tmp_path / f"rod{points_per_bp}.h5"
    subprocess.run([str(rodsim), "run", str(scene), "-o", str(h5)], check=True, capture_output=True)
    out = tmp_path / f"cg{points_per_bp}"
    assert main(["coarse-grain", str(h5), "-o", str(out), "--discard", "0", "--m-max", "2", "--bootstrap", "100"]) == 0
    return json.loads((out / "params.json").read_text())


@pytest.fixture(scope="module")
def coarse_grained(tmp_path_factory, rodsim):
    d = tmp_path_factory.mktemp("thermal_rod")
    return {ppb: _thermal_rod(d, rodsim, ppb, 10 + ppb) for ppb in (1, 2)}


@pytest.mark.parametrize("ppb", [1, 2])
def test_thermal_rod_returns_its_material(coarse_grained, ppb):
    """K(q -> 0) of the rod's base-pair steps gives the material's constants (|z| < 3.5)."""
    p = coarse_grained[ppb]
    assert p["temperature_source"].startswith("rod file") and p["temperature_K"] == 300.0
    assert p["excluded"]["steps"] == [42]                  # the closing step (holonomy drift)
    c = p["rod"]["constants"]
    for k, v in TRUTH.items():
        assert abs(c[k]["value"] - v) < 3.5 * c[k]["err"], (ppb, k, c[k], v)
        assert c[k]["err"] < 0.1 * v


@pytest.mark.parametrize("ppb, low, high", [(1, 1.15, 1.45), (2, 1.04, 1.2)])
def test_control_per_step_compliance_average_is_stiff(coarse_grained, ppb, low, high):
    """Must fail the test above: the per-step compliance average's bend persistence and
    stretch modulus are high by the reconstruction's short-wave averaging, many errors away."""
    c = coarse_grained[ppb]["rod"]["constants_compliance_average"]
    for k in ("bend_persistence_length", "stretch_modulus"):
        assert low < c[k]["value"] / TRUTH[k] < high, (ppb, k, c[k]["value"] / TRUTH[k])
        assert (c[k]["value"] - TRUTH[k]) / c[k]["err"] > 5, (ppb, k, c[k])
