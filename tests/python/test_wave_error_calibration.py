"""The stated error of the wave analysis's frequency (mdbridge/analysis/wavespeed.py,
mode_error.py) against its independent truth: the RMS error about the frequency put into
synthetic standing modes, over independent noise realisations
(bench/wave_error_calibration.py).

* the committed grid (noise / mode 0.03-1, correlation time 2-400 ps, 0.75-3 periods):
  at every point either the stated / RMS error is within 0.7-1.4 over enough reported
  numbers, or the analysis refuses (nearly) every record there -- no point gives numbers
  with an uncalibrated error;
* a fast subset rerun with fixed seeds: the short correlated record (0.75 period, tau =
  40 ps, where the residual's own autocorrelation had the error at 0.6 of the real one) is
  in band; white noise as large as the mode on the same length is refused;
* the control must fail: on the same records, the linearised error with the estimated
  noise taken as white (an error model that ignores the noise's correlation) is far below
  the real error, i.e. this check can tell a wrong error from a right one.
"""
from __future__ import annotations

import json
from pathlib import Path

import pytest

from benchscripts import load_bench

ROOT = Path(__file__).resolve().parents[2]
CAL = load_bench("wave_error_calibration.py")
LOW, HIGH = CAL.BAND


def test_committed_grid_is_calibrated_or_refused_at_every_point():
    res = json.loads((ROOT / "bench/results/wave_error_calibration.json").read_text())
    rows = {(r["periods"], r["noise_rel"], r["tau_ps"]): r for r in res["grid"]}
    wanted = {(P, nr, tau) for P in CAL.PERIODS for nr in CAL.NOISE_REL for tau in CAL.TAU_PS}
    assert set(rows) == wanted, "the committed grid is not the bench's grid: rerun the bench"
    for key, r in rows.items():
        status = CAL.status(r)
        assert status in ("in band", "refused"), (key, status, r)
        if status == "in band":
            assert abs(r["bias_over_rms"]) < 0.5, (key, r)
    assert res["points_in_band"] == sum(CAL.status(r) == "in band" for r in rows.values())


# 30 realisations, 50 bootstrap records each, fixed seeds: the ratio's own sampling error is
# ~1 / sqrt(2 x 30) = 13 %, so the band is ~3 of its standard errors
@pytest.fixture(scope="module")
def short_correlated():
    """0.75 period, noise 0.3 of the mode, correlated over 40 ps (8 frames)."""
    return CAL.grid_point(0.75, 0.3, 40.0, n_real=30, seed=17, n_boot=50)


def test_short_correlated_record_is_calibrated(short_correlated):
    assert CAL.status(short_correlated) == "in band", short_correlated
    assert abs(short_correlated["bias_over_rms"]) < 0.5, short_correlated


def test_white_noise_error_control_fails(short_correlated):
    """The same records with the error of least squares under WHITE noise of the estimated
    variance: for noise correlated over 8 frames it states a fraction of the real error and
    must leave the band, where the stated error stays in it."""
    assert short_correlated["white_over_rms"] < LOW, short_correlated


def test_noise_as_large_as_the_mode_is_refused():
    """Where the error model is not calibrated (noise as large as the mode, here white on
    0.75 period) the analysis refuses, mostly by the noise rule, instead of stating an error."""
    r = CAL.grid_point(0.75, 1.0, 2.0, n_real=30, seed=17, n_boot=50)
    assert CAL.status(r) == "refused", r
    assert r["refused_by"]["noise"] > r["n_refused"] // 2, r
