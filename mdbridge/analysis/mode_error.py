"""Frequency of the fundamental mode with an error model that holds for short, standing,
offset records (the MD's regime), the classification standing / travelling, and the rule
that refuses a number.

Model of the complex mode amplitude c(t) (wavespeed.mode_amplitude):

    c(t) = A_+ e^{-i w t} + A_- e^{+i w t} + B + z(t)

B is the static deformation of the mode (intrinsic curvature of a sequence, a bent start):
it is ALWAYS fitted, for rod and MD alike -- leaving it out biases w by many standard
errors on a record shorter than a period (tests/python/test_analysis_mode_error.py has
that control). z is the noise, an Ornstein-Uhlenbeck process estimated from the residual
(mode_noise.py). w, its fit error and the classification come from
`wavespeed.fit_with_replicates`; the record term and the refusal are here.

The stated error of w combines three parts, each reported:

1. fit: the parametric bootstrap of wavespeed.py -- records drawn from the fitted model
   plus the fitted noise, refitted by the same estimator, RMS about the fitted w. It holds
   where a linearised error does not (noise as large as the mode, a fraction of a period).
2. record: the finite record. Half the difference Delta of the frequencies fitted to the
   first and the last RECORD_WINDOW of the record, beyond what the noise alone explains:
   1/2 sqrt(Delta^2 - (2 d)^2), d the RMS of the same difference over the bootstrap
   records (which are harmonic, so their Delta is noise only). A record that holds a
   fraction of a period of an anharmonic (nonlinear) oscillation, or a frequency that
   drifts, gives windows that disagree. Counted only when |Delta| > RECORD_SIGMA d, so that
   a harmonic record (where |Delta| is noise) does not inflate the error.
3. seeds: the scatter between n >= 2 seeds (`combine_seeds`), as floor / sqrt(n) with the floor
   of mdbridge/analysis/realisation_floor.py (the extra scatter between realisations beyond
   each run's own error; below 6 seeds the upper end of its 68 % interval): the plain
   std / sqrt(n) of 2-3 seeds has 1-2 degrees of freedom and leaves |z| > 2 in 14 % and 9 %
   of sets (tests/python/test_analysis_mode_error.py, the control); with one seed it cannot be
   estimated and the result says so (the report then takes the floor of the setting's
   committed realisations: workflows/report/realisations.py).

Total = sqrt(fit^2 + record^2) per run; `combine_seeds` adds the seed part.

Refusal (`refusal`, the one rule of the workflow and of WaveAnalysis). No number -- speed
NaN with the reason, the fit kept under `unreported` -- when
1. the fit is a drift (under a quarter period, or the scan's minimum at its lowest step);
2. no oscillation stands above the noise: the fitted line explains no more of the record's
   variance than the fitted noise alone gives the same fit (its DETECTION_QUANTILE);
3. the record does not select one frequency: more than OTHER_PEAK_MAX of the bootstrap
   records find another peak (the stated error, the RMS over the records on the fitted
   peak, then leaves out a second mode of the error; every record that gives a number at
   the calibrated grid points has none on another peak);
4. a standing mode is shorter than REPORT_MIN_PERIODS even at the upper end of its
   interval, (w + REFUSE_SIGMA err) span / 2 pi < REPORT_MIN_PERIODS;
5. the noise rms per part exceeds NOISE_MAX_REL of the mode amplitude |A_+| + |A_-|: there
   the error model is not calibrated (bench/wave_error_calibration.py, docs/analysis.md).
Rules 2-4 judge the information in the record, not where the fitted w fell. Refusing every
record that FITS to fewer than 0.75 periods (the former rule) keeps, of the records that
truly hold 0.75 periods, only those fitted too fast, and so biases the numbers reported;
by the interval only the ~2 % tail is dropped. Why rule 4 at all: the rod's A_v >= 0.1 A/ps
oscillation is not harmonic (tension-stiffened); its own noise-free record cut to 0.5
period gives a frequency tens of standard errors off the full-record value, with both
sub-records agreeing on the wrong value (tests/python/test_analysis_mode_error.py,
test_rod_record_cut_short), while records of >= 0.75 period are covered by the stated
error. A travelling wave (|A_+| and |A_-| differ) keeps |c| constant and its phase turns
uniformly even when the wave is nonlinear, so rule 4 does not apply to it. `min_periods`
lowers the threshold of rule 4 for studies of harmonic data.
"""
from __future__ import annotations

import math

import numpy as np

from mdbridge.analysis.realisation_floor import between_realisation_floor
from mdbridge.analysis.wavespeed import DETECTION_QUANTILE, MIN_PERIODS, fit_frequencies, fit_with_replicates, fitted

REPORT_MIN_PERIODS = 0.75  # a standing record shorter than this (at REFUSE_SIGMA) is refused
REFUSE_SIGMA = 2.0         # ... judged at the upper end of w + REFUSE_SIGMA err
OTHER_PEAK_MAX = 0.02      # refused when more bootstrap records than this find another peak
RECORD_WINDOW = 2.0 / 3    # the two sub-records of the record term
RECORD_SIGMA = 4.0         # ... counted when their difference exceeds this many noise RMS
N_BOOT = 200               # bootstrap records of the fit error
NOISE_MAX_REL = 0.45       # refused when the noise rms per part exceeds this of |A_+| + |A_-|


def refusal(fit: dict, span_ps: float, min_periods: float = REPORT_MIN_PERIODS) -> str | None:
    """Why no number may be reported for the fit `fit` (wavespeed.fit_wave_speed's result)
    of a record of span_ps (module doc, "Refusal"), or None. WaveAnalysis and
    standing_mode_fit refuse with it."""
    if fit.get("reason"):
        return f"refused: {fit['reason']}"
    power, null = fit.get("line_power"), fit.get("noise_only_line_power")
    if power is not None and null is not None and power <= null:
        return (f"refused: no oscillation above the noise: the fitted line explains {100 * power:.0f} % of "
                f"the record's variance, no more than the noise alone gives the same fit ({100 * null:.0f} %, "
                f"its {100 * DETECTION_QUANTILE:g} % quantile); run longer or kick harder")
    noise, mode = fit.get("noise_rms_A"), fit.get("amplitude_forward_A", 0.0) + fit.get("amplitude_backward_A", 0.0)
    if noise is not None and noise > NOISE_MAX_REL * mode:
        return (f"refused: the noise ({noise:.3g} A rms per part) exceeds {NOISE_MAX_REL:g} of the mode's "
                f"amplitude ({mode:.3g} A): the error model is not calibrated there (docs/analysis.md, "
                "bench/results/wave_error_calibration.json); kick harder or average seeds")
    other = fit.get("bootstrap_other_peak_fraction", 0.0)
    if other > OTHER_PEAK_MAX:
        return (f"refused: the record does not select one frequency: {100 * other:.0f} % of the records "
                f"drawn from the fit and its noise find another peak (more than {100 * OTHER_PEAK_MAX:g} %); "
                "the noise is too large or too slow for this record length (docs/analysis.md); run longer")
    w, err = fit["omega_per_ps"], fit["omega_err_per_ps"]
    upper = (w + REFUSE_SIGMA * err) * span_ps / (2 * math.pi)
    if fit["wave_kind"] == "standing" and upper < min_periods:
        return (f"refused: the record ({span_ps:.3g} ps) holds {fit['periods_in_record']:.2f} periods "
                f"of the fitted standing oscillation (at most {upper:.2f} at {REFUSE_SIGMA:g} standard "
                f"errors), fewer than {min_periods:g}; over less than ~0.6 period a sinusoid fit of an "
                "anharmonic oscillation is biased far beyond any error it can state (docs/analysis.md); "
                "run longer")
    return None


def _record_term(t, c, replicates) -> dict:
    """Frequencies of the first and the last RECORD_WINDOW of the record, their difference
    Delta, its noise-only RMS d over the bootstrap records, and the record term
    1/2 sqrt(Delta^2 - (2 d)^2), counted only when |Delta| > RECORD_SIGMA d (module doc)."""
    n = len(t)
    m = max(int(round(RECORD_WINDOW * n)), 8)
    nan = float("nan")
    ws, wb = [], []
    for sl in (slice(0, m), slice(n - m, n)):
        w, _ = fit_frequencies(t[sl], c[None, sl], True)
        if not fitted(t[sl], w[0]):
            return {"omega_err_record_per_ps": nan,
                    "reason": f"the sub-records ({RECORD_WINDOW:.2g} of the record) hold fewer "
                              f"than {MIN_PERIODS} periods: the record-length term cannot be "
                              "estimated; the stated error is the fit part only"}
        ws.append(float(w[0]))
        wb.append(fit_frequencies(t[sl], replicates[:, sl], True)[0])
    delta = ws[0] - ws[1]
    ok = fitted(t[:m], wb[0]) & fitted(t[n - m:], wb[1])
    d = float(np.sqrt(np.mean((wb[0] - wb[1])[ok] ** 2))) if np.any(ok) else float("inf")
    significant = bool(abs(delta) > RECORD_SIGMA * d)
    return {"omega_first_per_ps": ws[0], "omega_last_per_ps": ws[1], "delta_per_ps": delta,
            "delta_noise_rms_per_ps": d, "significant": significant,
            "omega_err_record_per_ps": 0.5 * math.sqrt(delta ** 2 - (2.0 * d) ** 2) if significant else 0.0}


def standing_mode_fit(times_ps, c, k_per_A: float, record_term: bool = True,
                      min_periods: float = REPORT_MIN_PERIODS, n_boot: int = N_BOOT, seed: int = 0) -> dict:
    """Fit c(t) (always with the static offset B) and state the error model above.

    Returns omega [rad/ps], speed = omega / k [A/ps], the three error parts, the amplitudes
    and the classification; or speed NaN with `reason` when the record is too short."""
    t = np.asarray(times_ps, float)
    c = np.asarray(c, complex)
    nan = float("nan")
    span = float(t[-1] - t[0])
    f, replicates = fit_with_replicates(t, c, k_per_A, offset=True, n_boot=max(n_boot, 2), seed=seed)
    if not math.isfinite(f["speed_A_per_ps"]):
        return {"speed_A_per_ps": nan, "speed_err_A_per_ps": nan, "omega_per_ps": nan,
                "periods_in_record": f["periods_in_record"], "offset_fitted": True,
                "min_periods": MIN_PERIODS, "omega_at_bound_per_ps": f["omega_at_bound_per_ps"],
                "reason": refusal(f, span)}
    w, w_err_fit = f["omega_per_ps"], f["omega_err_per_ps"]
    rec = _record_term(t, c, replicates) if record_term else {}
    w_err_rec = rec.get("omega_err_record_per_ps", nan)
    w_err = math.hypot(w_err_fit, w_err_rec) if math.isfinite(w_err_rec) else w_err_fit
    standing = f["wave_kind"] == "standing"
    out = {
        "method": "LS fit of c(t) = A+ e^{-iwt} + A- e^{iwt} + B (offset always fitted); "
                  "error: parametric bootstrap with REML OU noise (fit) + sub-record difference (record)",
        "quantity": ("oscillation frequency / phase speed of the standing mode" if standing
                     else "wave speed (travelling wave)"),
        "wave_kind": f["wave_kind"],
        "omega_per_ps": w, "omega_err_per_ps": w_err,
        "omega_err_fit_per_ps": w_err_fit, "omega_err_record_per_ps": w_err_rec,
        "omega_err_linear_per_ps": f["omega_err_cov_per_ps"], "record_term": rec,
        "speed_A_per_ps": w / k_per_A, "speed_err_A_per_ps": w_err / k_per_A,
        "speed_err_fit_A_per_ps": w_err_fit / k_per_A,
        "speed_err_record_A_per_ps": w_err_rec / k_per_A,
        "period_ps": 2 * math.pi / w, "periods_in_record": f["periods_in_record"],
        "min_periods": MIN_PERIODS, "n_boot": f["n_boot"],
        "bootstrap_other_peak_fraction": f["bootstrap_other_peak_fraction"],
        "line_power": f["line_power"], "noise_only_line_power": f["noise_only_line_power"],
        "noise_rms_A": f["noise_rms_A"], "noise_tau_ps": f["noise_tau_ps"],
        "amplitude_forward_A": f["amplitude_forward_A"], "amplitude_backward_A": f["amplitude_backward_A"],
        "amplitude_difference_A": f["amplitude_difference_A"],
        "amplitude_difference_err_A": f["amplitude_difference_err_A"],
        "mode_amplitude_A": f["amplitude_forward_A"] + f["amplitude_backward_A"],
        "offset_A": f["offset_A"], "offset_fitted": True,
    }
    reason = refusal(dict(f, omega_err_per_ps=w_err), span, min_periods)
    if reason:
        return {"speed_A_per_ps": nan, "speed_err_A_per_ps": nan, "omega_per_ps": nan,
                "periods_in_record": out["periods_in_record"], "offset_fitted": True,
                "min_periods": min_periods, "wave_kind": out["wave_kind"], "quantity": out["quantity"],
                "mode_amplitude_A": out["mode_amplitude_A"], "reason": reason, "unreported": out}
    return out


def _finite(x) -> bool:
    return isinstance(x, (int, float)) and math.isfinite(x)


def combine_seeds(fits: list[dict]) -> dict:
    """Mean over seeds of the speed, with the three error parts: fit and record (each run's,
    combined as the error of the mean) and the between-seed scatter std / sqrt(n)."""
    ok = [f for f in fits if f and _finite(f.get("speed_A_per_ps"))]  # (JSON writes NaN as null)
    nan = float("nan")
    if not ok:
        reasons = sorted({f.get("reason", "no fit") for f in fits if f})
        return {"speed_A_per_ps": nan, "speed_err_A_per_ps": nan, "n_seeds": 0,
                "reason": "; ".join(reasons) or "no runs"}
    v = np.array([f["speed_A_per_ps"] for f in ok])
    n = len(v)
    fit = math.sqrt(sum(f["speed_err_fit_A_per_ps"] ** 2 for f in ok)) / n
    rec_parts = [f["speed_err_record_A_per_ps"] for f in ok if _finite(f.get("speed_err_record_A_per_ps"))]
    rec = math.sqrt(sum(x * x for x in rec_parts)) / n if rec_parts else 0.0
    out = {"speed_A_per_ps": float(v.mean()), "n_seeds": n,
           "speed_err_fit_A_per_ps": fit, "speed_err_record_A_per_ps": rec,
           "omega_per_ps": float(np.mean([f["omega_per_ps"] for f in ok])),
           "wave_kind": "standing" if all(f["wave_kind"] == "standing" for f in ok) else
           ("travelling" if all(f["wave_kind"] == "travelling" for f in ok) else "mixed"),
           "mode_amplitude_A": float(np.mean([f["mode_amplitude_A"] for f in ok]))}
    out["quantity"] = ("oscillation frequency / phase speed of the standing mode"
                       if out["wave_kind"] == "standing" else "wave speed")
    if n >= 2:
        own = np.array([math.hypot(f["speed_err_fit_A_per_ps"], f.get("speed_err_record_A_per_ps") or 0.0)
                        for f in ok])
        if np.all(own > 0) and np.ptp(v) > 0:
            floor = between_realisation_floor(v, own)
            seeds = floor["floor"] / math.sqrt(n)
            out["speed_err_seeds_rule"] = f"floor / sqrt(n), floor: {floor['floor_rule']}"
        else:       # no spread, or no error to weigh the runs by: the plain scatter
            seeds = float(np.std(v, ddof=1) / math.sqrt(n))
            out["speed_err_seeds_rule"] = "std / sqrt(n)"
        out["speed_err_seeds_A_per_ps"] = seeds
        out["speed_err_A_per_ps"] = math.sqrt(fit ** 2 + rec ** 2 + seeds ** 2)
    else:
        out["speed_err_seeds_A_per_ps"] = None
        out["speed_err_seeds_note"] = ("between-seed scatter cannot be estimated from a single "
                                       "seed; the stated error omits it (see "
                                       "workflows/config/paper.yaml or small_amplitude.yaml "
                                       "for multi-seed runs)")
        out["speed_err_A_per_ps"] = math.sqrt(fit ** 2 + rec ** 2)
    return out
