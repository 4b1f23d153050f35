"""Fast versions of the stability stress tests (bench/stress/stability.py).

Independent truths: RK4's stability region meets the imaginary axis at
+-2 sqrt 2; the spectrum of the semi-discrete system linearised about the rest
state (eigenvalues of the Jacobian of the independent numpy RHS) is purely
imaginary (skew operators, conserved energy); the semi-discrete energy is
conserved exactly, so an adaptive run's energy drift is set by its tolerance."""
import math

import numpy as np
import pytest
from benchscripts import load_bench

stability = load_bench("stress/stability.py")


@pytest.mark.parametrize("space", ["fd4", "spectral"])
def test_rk4_stability_boundary_is_the_exact_spectral_radius(rodsim, tmp_path, space):
    N, L = 32, 2 * math.pi
    r = stability.dt_sweep(rodsim, tmp_path, N, L, (0, 0, 1.0), (0, 0, 0.0), space, [0.95, 1.05], steps=400)
    assert abs(r["max_real_part"]) < 1e-8 * r["lambda_max"]  # rest-state spectrum is imaginary
    stable, unstable = r["runs"]
    assert stable["returncode"] == 0, stable.get("message")
    assert stable["growth"] < 10.0
    # Above the boundary rodsim must never return a silently amplified result:
    # it refuses the dt, or stops on the blow-up with its message (exit 3).
    if unstable["returncode"] == 0:
        pytest.fail(f"dt = 1.05 dt* ran to the end (noise growth {unstable['growth']:.3g})")
    assert unstable["returncode"] == 3
    assert "stability limit" in unstable["message"] or "blew up" in unstable["message"]


def test_fold_stops_with_clear_message(rodsim, tmp_path):
    rows = stability.fold_sweep(rodsim, tmp_path, [0.5, 2.0], t_end=5.0)
    assert rows[0]["returncode"] == 0 and rows[0]["min_Gamma3_last_frame"] > 0
    assert rows[1]["returncode"] == 3
    assert "folded" in rows[1]["message"] and "Gamma3" in rows[1]["message"]


def test_energy_drift_at_tight_tolerance(rodsim, tmp_path):
    r = stability.long_run(rodsim, tmp_path, t_end=400.0, rtol=1e-12, frames=21)
    assert "error" not in r, r.get("error")
    assert r["steps"] > 500
    assert r["max_drift"] <= 1e-10, r["max_drift"]


@pytest.mark.parametrize("space,dealias", [("fd4", False), ("spectral", False), ("spectral", True)])
def test_discontinuous_initial_field_conserves_energy(rodsim, tmp_path, space, dealias):
    N, L, G0, O0 = 64, 2 * math.pi, (0, 0, 1.0), (0, 0, 0.0)
    y0 = stability.rest_state(N, G0, O0)
    y0[0, : N // 2] = 0.1  # a step in gamma1: every Fourier mode excited
    ic = tmp_path / "step.h5"
    stability.write_initial(ic, y0, L)
    scene = tmp_path / "step.toml"
    stability.write_scene(scene, N, L, G0, O0, ic, {"space": space, "time": "dop853", "rtol": 1e-10,
                                                    "atol": 1e-10, "dealias": dealias},
                          t_end=5.0, frames=6, fields=("internal", "energy"))
    r = stability.run(rodsim, scene, tmp_path / "step_out.h5")
    assert r["returncode"] == 0, r["stderr"]
    assert np.all(np.isfinite(r["y_last"]))
    assert r["energy_drift"] < 1e-7, r["energy_drift"]
