"""Frequency of the fundamental mode with an error model that holds for short, standing,
offset records (the MD's regime), and the classification standing / travelling.

Model of the complex mode amplitude c(t) (wavespeed.mode_amplitude):

    c(t) = A_+ e^{-i w t} + A_- e^{+i w t} + B

B is the static deformation of the mode (intrinsic curvature of a sequence, a bent start):
it is ALWAYS fitted, for rod and MD alike -- leaving it out biases w by many standard
errors on a record shorter than a period (tests/python/test_analysis_mode_error.py has
that control). w comes from `wavespeed.fit_wave_speed` (global scan + refinement);
everything else is here.

The stated error of w combines three parts, each reported:

1. fit: the linearised least-squares covariance with the residual taken as AR(1) noise
   (real and imaginary parts independent, same coefficient phi, estimated from the
   residual's lag-1 autocorrelation), i.e. the sandwich
   cov = (J^T J)^-1 J^T Sigma J (J^T J)^-1, Sigma_ij = s^2 phi^|i - j|.
   White-noise least squares understates the error of correlated thermal noise by
   ~sqrt((1 + phi) / (1 - phi)); the sandwich does not.
2. record: the finite record. Half the difference of the frequencies fitted to the first
   and the last RECORD_WINDOW of the record, beyond what the noise alone explains
   (`_record_term`). A record that holds a fraction of a period of
   an anharmonic (nonlinear) oscillation, or a frequency that drifts, gives windows that
   disagree; a long harmonic record gives a small term (noise only).
3. seeds: the between-seed scatter, std / sqrt(n) over n >= 2 seeds (`combine_seeds`); with
   one seed it cannot be estimated and the result says so.

Total = sqrt(fit^2 + record^2) per run; `combine_seeds` adds the seed part.

Refusal. The error model is calibrated for a harmonic oscillation down to 0.3 periods
(tests/python/test_analysis_mode_error.py). The rod's A_v >= 0.1 A/ps oscillation is not
harmonic (tension-stiffened): its own noise-free record cut to 0.5 period gives a frequency
27-36 standard errors off the full-record value (A_v = 0.1, 1, 2, 5), with both sub-records
agreeing on the wrong value, while records of >= 0.6 period are covered by the stated error
(tests/python/test_analysis_mode_error.py, test_rod_record_cut_short). A sinusoid fitted to
less than ~0.6 period of an anharmonic oscillation overestimates the number of periods it
holds (0.5 true -> ~0.7 fitted), so the number is refused -- `speed_A_per_ps` NaN with the
reason, the unreportable fit kept under `unreported` -- when the FITTED record holds fewer
than REPORT_MIN_PERIODS = 0.75 periods and the mode is standing. A travelling wave (|A_+| and
|A_-| differ) keeps |c| constant and its phase turns uniformly even when the wave is
nonlinear, so for it only MIN_PERIODS applies. `min_periods` lowers the threshold for
studies of harmonic data.

Standing or travelling: the fitted |A_+| and |A_-| are compared with the standard error of
their difference (from the same sandwich); equal within 2 sigma -> "standing": the number is
the oscillation frequency / phase speed of the standing mode (nothing propagates);
otherwise "travelling" -> a wave speed.
"""
from __future__ import annotations

import math

import numpy as np

from mdbridge.analysis.wavespeed import fit_wave_speed

MIN_PERIODS = 0.25       # below: no fit at all (cannot tell a frequency from a slow drift)
REPORT_MIN_PERIODS = 0.75  # below: the number is refused (module doc, "Refusal")
RECORD_WINDOW = 2.0 / 3  # the two sub-records of the record term
STANDING_SIGMA = 2.0     # |A_+| - |A_-| within this many standard errors -> standing


def _design(tc, w):
    e = np.exp(-1j * w * tc)
    return np.stack([e, np.conj(e), np.ones_like(e)], axis=1)


def _linear_fit(tc, c, w):
    E = _design(tc, w)
    A = np.linalg.lstsq(E, c, rcond=None)[0]
    return A, c - E @ A


def _jacobian(tc, w, A):
    """d(model)/d(w, Re A_+, Im A_+, Re A_-, Im A_-, Re B, Im B), stacked (real; imag)."""
    E = _design(tc, w)
    dw = -1j * tc * A[0] * E[:, 0] + 1j * tc * A[1] * E[:, 1]
    cols = [dw]
    for j in range(3):
        cols += [E[:, j], 1j * E[:, j]]
    J = np.stack(cols, axis=1)
    return np.concatenate([J.real, J.imag])


def ar1_coefficient(r: np.ndarray) -> float:
    """Lag-1 autocorrelation of a complex residual (real and imaginary parts pooled)."""
    r = r - r.mean()
    den = float(np.vdot(r, r).real)
    if den == 0 or len(r) < 3:
        return 0.0
    return float(np.clip(np.vdot(r[:-1], r[1:]).real / den, 0.0, 0.99))


def _sandwich(J, n, s2, phi):
    idx = np.arange(n)
    S = s2 * phi ** np.abs(idx[:, None] - idx[None, :])
    Z = np.zeros_like(S)
    Sig = np.block([[S, Z], [Z, S]])
    H = np.linalg.pinv(J.T @ J)
    return H @ (J.T @ Sig @ J) @ H


def _fit_w(t, c, k):
    return fit_wave_speed(t, c, k, offset=True, n_boot=0)


def _w_gradient(tc, w, A):
    """Row of the linearised LS map giving delta w from the stacked (real; imag) data."""
    J = _jacobian(tc, w, A)
    return (np.linalg.pinv(J.T @ J) @ J.T)[0]


def _record_term(t, c, k, w_full, s2, phi) -> dict:
    """Frequencies of the first and the last RECORD_WINDOW of the record, their difference
    Delta and the standard error of Delta that the AR(1) noise alone gives (the two windows
    share data, so their noise is correlated: the gradients of both fits are embedded in
    the full record and contracted with one Sigma). The record term is the part of |Delta| / 2
    beyond 2 of those standard errors, 1/2 sqrt(Delta^2 - (2 sd)^2): zero when the sub-records
    agree within noise, ~|Delta| / 2 when they disagree by much more (an anharmonic or
    drifting oscillation)."""
    n = len(t)
    m = max(int(round(RECORD_WINDOW * n)), 8)
    nan = float("nan")
    gs, ws = [], []
    for sl in (slice(0, m), slice(n - m, n)):
        f = _fit_w(t[sl], c[sl], k)
        wa = f.get("omega_per_ps", nan)
        if not math.isfinite(wa):
            return {"omega_err_record_per_ps": nan,
                    "reason": f"the sub-records ({RECORD_WINDOW:.2g} of the record) hold fewer "
                              f"than {MIN_PERIODS} periods: the record-length term cannot be "
                              "estimated; the stated error is the fit part only"}
        ts = t[sl] - t[sl].mean()
        A, _ = _linear_fit(ts, c[sl], wa)
        g = np.zeros(2 * n)
        ga = _w_gradient(ts, wa, A)
        idx = np.arange(n)[sl]
        g[idx] = ga[:m]
        g[n + idx] = ga[m:]
        gs.append(g)
        ws.append(wa)
    d = gs[0] - gs[1]
    lag = np.abs(np.arange(n)[:, None] - np.arange(n)[None, :])
    S = s2 * phi ** lag
    var = float(d[:n] @ S @ d[:n] + d[n:] @ S @ d[n:])
    delta = ws[0] - ws[1]
    sd = math.sqrt(max(var, 0.0))
    significant = abs(delta) > 2.0 * sd
    return {"omega_first_per_ps": ws[0], "omega_last_per_ps": ws[1], "delta_per_ps": delta,
            "delta_noise_err_per_ps": sd, "significant": bool(significant),
            "omega_err_record_per_ps": 0.5 * math.sqrt(max(delta ** 2 - (2.0 * sd) ** 2, 0.0))}


def standing_mode_fit(times_ps, c, k_per_A: float, record_term: bool = True,
                      min_periods: float = REPORT_MIN_PERIODS) -> dict:
    """Fit c(t) (always with the static offset B) and state the error model above.

    Returns omega [rad/ps], speed = omega / k [A/ps], the three error parts, the amplitudes
    and the classification; or speed NaN with `reason` when the record is too short."""
    t = np.asarray(times_ps, float)
    c = np.asarray(c, complex)
    nan = float("nan")
    f = _fit_w(t, c, k_per_A)
    span = float(t[-1] - t[0])
    w = f.get("omega_per_ps", nan)
    if not math.isfinite(w):
        w_b = f.get("omega_at_bound_per_ps", nan)
        return {"speed_A_per_ps": nan, "speed_err_A_per_ps": nan, "omega_per_ps": nan,
                "periods_in_record": f.get("periods_in_record", nan), "offset_fitted": True,
                "min_periods": MIN_PERIODS, "omega_at_bound_per_ps": w_b,
                "reason": f"refused: the record ({span:.3g} ps) holds "
                          f"{f.get('periods_in_record', nan):.2f} periods, fewer than the "
                          f"{MIN_PERIODS} needed to tell an oscillation from a drift; run longer"}
    tc = t - t.mean()
    A, r = _linear_fit(tc, c, w)
    n = len(t)
    J = _jacobian(tc, w, A)
    dof = max(2 * n - J.shape[1], 1)
    s2 = float(np.vdot(r, r).real) / dof
    phi = ar1_coefficient(r)
    cov = _sandwich(J, n, s2, phi)
    w_err_fit = float(math.sqrt(max(cov[0, 0], 0.0)))
    w_err_white = float(math.sqrt(max(np.linalg.pinv(J.T @ J)[0, 0] * s2, 0.0)))
    # |A_+| - |A_-|: gradient wrt (Re, Im) of A_+ and A_-
    g = np.zeros(J.shape[1])
    for j, sign in ((0, 1.0), (1, -1.0)):
        a = abs(A[j])
        if a > 0:
            g[1 + 2 * j] = sign * A[j].real / a
            g[2 + 2 * j] = sign * A[j].imag / a
    d_amp = float(abs(A[0]) - abs(A[1]))
    d_amp_err = float(math.sqrt(max(g @ cov @ g, 0.0)))
    standing = abs(d_amp) <= STANDING_SIGMA * d_amp_err
    rec = _record_term(t, c, k_per_A, w, s2, phi) if record_term else {}
    w_err_rec = rec.get("omega_err_record_per_ps", nan)
    parts = [w_err_fit] + ([w_err_rec] if math.isfinite(w_err_rec) else [])
    w_err = float(math.sqrt(sum(p * p for p in parts)))
    periods = w * span / (2 * math.pi)
    kind = "standing" if standing else "travelling"
    out = {
        "method": "LS fit of c(t) = A+ e^{-iwt} + A- e^{iwt} + B (offset always fitted); "
                  "error: AR(1) sandwich (fit) + sub-record difference (record)",
        "quantity": ("oscillation frequency / phase speed of the standing mode" if standing
                     else "wave speed (travelling wave)"),
        "wave_kind": kind,
        "omega_per_ps": w, "omega_err_per_ps": w_err,
        "omega_err_fit_per_ps": w_err_fit, "omega_err_record_per_ps": w_err_rec,
        "omega_err_white_per_ps": w_err_white, "record_term": rec,
        "speed_A_per_ps": w / k_per_A, "speed_err_A_per_ps": w_err / k_per_A,
        "speed_err_fit_A_per_ps": w_err_fit / k_per_A,
        "speed_err_record_A_per_ps": w_err_rec / k_per_A,
        "period_ps": 2 * math.pi / w, "periods_in_record": periods, "min_periods": MIN_PERIODS,
        "residual_ar1": phi, "residual_rms": math.sqrt(s2),
        "amplitude_forward_A": float(abs(A[0])), "amplitude_backward_A": float(abs(A[1])),
        "amplitude_difference_A": d_amp, "amplitude_difference_err_A": d_amp_err,
        "mode_amplitude_A": float(abs(A[0]) + abs(A[1])),
        "offset_A": float(abs(A[2])), "offset_fitted": True,
    }
    if periods < min_periods and standing:
        return {"speed_A_per_ps": nan, "speed_err_A_per_ps": nan, "omega_per_ps": nan,
                "periods_in_record": periods, "offset_fitted": True, "min_periods": min_periods,
                "wave_kind": kind, "quantity": out["quantity"],
                "mode_amplitude_A": out["mode_amplitude_A"],
                "reason": f"refused: the record ({span:.3g} ps) holds {periods:.2f} periods of the "
                          f"fitted oscillation, fewer than {min_periods:g}; over less than ~0.6 "
                          "period a sinusoid fit of an anharmonic oscillation is biased far beyond "
                          "any error it can state (docs/analysis.md); run longer",
                "unreported": out}
    return out


def refusal(times_ps, c, k_per_A: float) -> str | None:
    """Why no speed may be reported for the mode amplitude c(t), by the rule the workflow
    reports with (standing_mode_fit: fewer than MIN_PERIODS, or a standing mode with fewer
    than REPORT_MIN_PERIODS fitted periods), or None. WaveAnalysis refuses with it."""
    return standing_mode_fit(times_ps, c, k_per_A, record_term=False).get("reason")


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
        seeds = float(np.std(v, ddof=1) / math.sqrt(n))
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
