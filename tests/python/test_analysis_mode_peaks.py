"""`dnarod modes` on MD-like spectra (mdbridge/analysis/mode_spectra.py: common_background,
fit_kind, off_branch, common_drift, the halves test): each mode's damped oscillator on top
of what is the same at every n (red noise, the base-pair steps' broad local band, a white
floor), synthetic with known omega_n and Q (bench/mode_spectrum_calibration.py md_like_*).

* The modes are found on their dispersive branch with calibrated errors; the control, each
  mode fitted alone with the rule before the common background, locks onto the local band
  or the red noise, as it did on the 158-bp MD (docs/modes.md).
* The halves test is calibrated on stationary records of the MD's Q and length (signed z of
  RMS 0.7-1.4, false refusals at the nominal rate), and refuses a record whose frequency
  steps; the control, errors half as large, fails the window.
* A drift common to a kind's modes is told from scatter of random sign, even when the
  halves' errors are too small; the control, the bare weighted mean, is fooled by that.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from benchscripts import load_bench

CAL = load_bench("mode_spectrum_calibration.py")


def _z_and_misses(truth, n_real, seed, background):
    """Signed z = (omega - truth) / stated error of every mode that is not refused, and the
    relative misses |omega / truth - 1| of the fitted ones (refused or not)."""
    from mdbridge.analysis.mode_spectra import refusal
    fits = CAL.md_like_input(truth, n_real, seed, range(len(truth["modes"])), background=background)
    z, miss, refused = [], [], 0
    for i, rows in fits.items():
        for fit, why, record_ps, w, _ in rows:
            if fit is not None:
                miss.append(abs(fit.omega_per_ps / w - 1))
            if fit is None or why or refusal(fit, record_ps):
                refused += 1
                continue
            z.append((fit.omega_per_ps - w) / fit.omega_err_per_ps)
    return np.array(z), np.array(miss), refused


@pytest.mark.parametrize("name", ["TWIST_LIKE", "BEND_LIKE"])
def test_md_like_modes_are_found_on_their_branch(name):
    """Two realisations of 14 modes (2 ns of 0.5-ps frames, 2 series each, as the MD's twist;
    28 estimates): at most 4 refused, every estimate within 4 of its errors of the truth, and
    the RMS of z (stated / RMS error) within 0.7-1.4 (28 values: the RMS's own sampling
    error is 13 %). Control: the same records, each mode fitted alone without the common
    background, miss the truth by more than 30 % in at least 4 modes (the local band or the
    red noise taken for the mode)."""
    spec = getattr(CAL, name)
    truth = CAL.md_like_modes(spec["omegas"], spec["Qs"], spec["peak_over_background"], red=spec.get("red", 1.0),
                              record_ps=2000.0, n_series=2)
    z, miss, refused = _z_and_misses(truth, 2, 17, background=True)
    assert refused <= 4, refused
    assert np.all(np.abs(z) < 4.0), z
    assert 0.7 <= math.sqrt(np.mean(z ** 2)) <= 1.4, z
    _, miss_alone, _ = _z_and_misses(truth, 2, 17, background=False)
    assert np.sum(miss_alone > 0.3) >= 4, miss_alone


# -- the halves test (mode_spectra._halves): calibrated where the MD's bend modes lie ---------
@pytest.mark.parametrize("period_ps, Q, step", [(210.0, 3.0, 0.35), (60.0, 30.0, 0.10)])
def test_halves_test_is_calibrated_on_stationary_records(period_ps, Q, step):
    """30 stationary records of 2 ns of 0.5-ps frames, 4 series (bend n = 2 and 5 of the
    158-bp MD: periods 210 and 60 ps, Q 3 and 30): the halves' signed z has RMS within
    0.7-1.4 (30 values: the RMS's own sampling error is 13 %) and at most one exceeds
    STATIONARY_Z (false refusals: 0.3 % nominal, 0.08 expected). Controls: the same z with
    errors half as large fail the RMS window; records whose frequency steps between the halves
    by about four errors of the difference (35 % at Q = 3, ~5 periods a half; 10 % at Q = 30)
    are refused in most realisations."""
    from mdbridge.analysis.mode_spectra import STATIONARY_Z
    z = np.array([v for v in CAL.halves_z(CAL.oscillator_input(period_ps, Q, 30, 5, record_ps=2000.0), 0.5)
                  if v is not None])
    assert len(z) >= 27, len(z)
    rms = math.sqrt(np.mean(z ** 2))
    assert 0.7 <= rms <= 1.4, z
    assert np.sum(np.abs(z) > STATIONARY_Z) <= 1, z
    assert 2 * rms > 1.4                                  # control: errors too small by 2 are caught
    stepped = [v for v in CAL.halves_z(CAL.stepped_input(period_ps, Q, step, 10, 6, record_ps=2000.0), 0.5)
               if v is not None]
    assert sum(abs(v) > STATIONARY_Z for v in stepped) >= 7, stepped


def _halves_entries(shifts, errs, omega=1.0):
    return [{"halves": {"omega_per_ps": [omega, omega * (1 + d)], "omega_err_per_ps": [omega * e / math.sqrt(2)] * 2}}
            for d, e in zip(shifts, errs)]


def test_common_drift_is_told_from_scatter():
    """Ten modes' relative shifts between the halves. Scatter of random sign with stated
    errors 4x too small (each |z| ~ 4: the halves test would refuse most) is no drift, since
    the mean's error takes the Birge ratio of the scatter; the control, the bare weighted
    mean, calls it a drift. Every mode shifted by +2 % with 0.5 % errors is a drift."""
    from mdbridge.analysis.mode_spectra import STATIONARY_Z, common_drift
    rng = np.random.default_rng(3)
    true_err = 0.02
    shifts = rng.standard_normal(10) * true_err
    shifts += true_err / math.sqrt(10) - shifts.mean()   # a mean of one true error of the mean
    d = common_drift(_halves_entries(shifts, [true_err / 4] * 10))
    assert d["modes"] == 10 and not d["drifts"], d
    assert d["birge_ratio"] > 2.5, d
    assert abs(d["relative_shift"] / (d["relative_shift_err"] / d["birge_ratio"])) > STATIONARY_Z   # control
    d = common_drift(_halves_entries(0.02 + rng.standard_normal(10) * 0.005, [0.005] * 10))
    assert d["drifts"] and d["positive"] == 10, d


@pytest.mark.parametrize("period_ps, Q", [(78.0, 4.0), (17.5, 1.8)])
def test_Q_error_is_calibrated(period_ps, Q):
    """Q = omega0 / (2 gamma) and its error (through the covariance of omega and gamma) on 40
    records of 2 ns, 4 series, at the MD's bend n = 4 and 11 (periods 78 and 17.5 ps, Q 4 and
    1.8): stated / RMS error of Q within 0.7-1.4 (40 values: 11 % sampling error), bias under
    10 % (Q's error is 10-15 % here). Control: errors half as large fail the window."""
    r = CAL.calibrate(CAL.oscillator_input(period_ps, Q, 40, 11, record_ps=2000.0))
    assert len(r["refused"]) <= 2, r["refused"]
    assert 0.7 <= r["Q_ratio"] <= 1.4, r
    assert abs(r["Q_bias_rel"]) < 0.10, r
    assert not 0.7 <= r["Q_ratio"] / 2 <= 1.4        # control
