"""The stated error of the wave analysis's frequency (mdbridge/analysis/wavespeed.py,
mode_error.py) against its independent truth: the RMS error about the frequency put into
synthetic standing modes, over independent noise realisations
(bench/wave_error_calibration.py).

* the committed grid (noise / mode 0.03-1, correlation time 2-400 ps, 0.75-3 periods):
  stated / RMS error within 0.7-1.4 at every point, with enough numbers reported there;
* a fast subset rerun with fixed seeds: the short correlated record (0.75 period, tau =
  40 ps, where the residual's autocorrelation had the error at 0.6 of the real one) and
  noise as large as the mode (white, 1.5 periods);
* the control must fail: on the same records, the linearised error (least squares with the
  same estimated noise) is far below the real error where the noise is as large as the
  mode, i.e. this check can tell a wrong error from a right one.
"""
from __future__ import annotations

import json
from pathlib import Path

import pytest

from benchscripts import load_bench

ROOT = Path(__file__).resolve().parents[2]
CAL = load_bench("wave_error_calibration.py")
LOW, HIGH = CAL.BAND


def test_committed_grid_is_calibrated_at_every_point():
    res = json.loads((ROOT / "bench/results/wave_error_calibration.json").read_text())
    rows = {(r["periods"], r["noise_rel"], r["tau_ps"]): r for r in res["grid"]}
    wanted = {(P, nr, tau) for P in CAL.PERIODS for nr in CAL.NOISE_REL for tau in CAL.TAU_PS}
    assert set(rows) == wanted, "the committed grid is not the bench's grid: rerun the bench"
    for key, r in rows.items():
        # a ratio of RMS values over fewer numbers than this is not a measurement
        assert r["n_reported"] >= 20, (key, r["n_reported"], r["n_refused"], r["n_no_fit"])
        assert LOW <= r["stated_over_rms"] <= HIGH, (key, r)
        assert abs(r["bias_over_rms"]) < 0.5, (key, r)
    assert res["points_in_band"] == res["points"] == len(wanted)


# (periods, noise / mode, tau [ps]): 30 realisations, 50 bootstrap records each; the ratio's
# own sampling error is ~1 / sqrt(2 x 30) = 13 %, so the band is 3 of its standard errors
SUBSET = [(0.75, 0.3, 40.0), (1.5, 1.0, 2.0)]


@pytest.fixture(scope="module", params=SUBSET, ids=lambda p: f"{p[0]}per-noise{p[1]}-tau{p[2]:g}")
def rerun(request):
    P, nr, tau = request.param
    return CAL.grid_point(P, nr, tau, n_real=30, seed=17, n_boot=50)


def test_subset_rerun_is_calibrated(rerun):
    assert rerun["n_reported"] >= 20, rerun
    assert LOW <= rerun["stated_over_rms"] <= HIGH, rerun
    assert abs(rerun["bias_over_rms"]) < 0.5, rerun


def test_linearised_error_control_fails(rerun):
    """The same records with the linearised error instead of the bootstrap: where the noise
    is as large as the mode it states a fraction of the real error and must leave the band."""
    if rerun["noise_rel"] < 1.0:
        assert LOW <= rerun["linear_over_rms"], rerun  # (weak noise: linear holds, as it should)
    else:
        assert rerun["linear_over_rms"] < LOW, rerun
