"""Calibration of the errors of `dnarod modes` (mdbridge/analysis/mode_spectra.py fit_mode:
the band, the debiased Whittle fit of the damped oscillator, the line refinement, the
observed-information errors) on series of known frequency and damping.

An input is a function that returns realisations (x (M, N) real series, dt_ps, omega,
gamma): the truth beside each record. Today's input is `oscillator_input`, the exact
discrete-time damped oscillator (mdbridge/analysis/spectrum.py simulate) at the record of
the dispersion MD (4 ns of 0.5-ps frames), M = 4 series (bend: two quadratures, two
directions), and a white floor of 1 % of the mode's variance. The second input
(--thermal-rod) is thermal-rod series: Langevin runs of the paper's 158-bp rod at 0.03 K
with frictions that give damped modes of Q ~ 1.5-30, each through `dnarod modes`' own code
path (the rod file read as the command reads it, mode_table on each run alone), against the
eigenvalues of the linearised damped operator (mdbridge/rod/linear.py damped_modes); the
same statistics (`calibration_summary`) per kind and n.

For each case: over the R realisations that the command would report (not refused: the
refusals are counted), the bias, the RMS error about the truth, and the
calibration ratio stated / RMS = sqrt(mean stated^2) / sqrt(mean (estimate - truth)^2) of
omega (and of gamma when the mode is damped), with the ratio's own 68 % interval (bootstrap
over the realisations). Pass: 0.7 <= ratio <= 1.4.
The control: every mode taken as a sinusoid in white noise (spectrum.py line="always":
the least-squares frequency and its white-noise error, what a wave fit does), which a
damped mode's wandering amplitude and phase must defeat somewhere in the table.

    /usr/bin/python3 bench/mode_spectrum_calibration.py [--realisations 60] [--out bench/results]
    nice -n 10 /usr/bin/python3 bench/mode_spectrum_calibration.py --thermal-rod --realisations 30 \
        [--seed 1] [--raw raw.json]     (~40 s of CPU per realisation)
"""
from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

import numpy as np

RECORD_PS = 4000.0
DT_PS = 0.5
N_SERIES = 4
FLOOR = 0.01
LOW, HIGH = 0.7, 1.4
# (period [ps], Q): periods 12-1100 ps (the bend modes n = 15..1 of notes-science), Q from 1
# to infinity; Q = 3-30 around gamma T = 1-4, where the line refinement takes over
CASES = [(1100, 3), (1100, 10), (1100, math.inf), (375, 3), (375, 30), (375, math.inf),
         (111, 1), (111, 10), (111, math.inf), (32, 1), (32, 3), (32, 100), (12, 3), (12, 30), (12, math.inf)]


def gamma_of(period_ps: float, Q: float):
    """(omega, gamma) [1/ps] of the oscillator of natural period 2 pi / omega0 and quality Q."""
    w0 = 2 * math.pi / period_ps
    g = 0.0 if math.isinf(Q) else w0 / (2 * Q)
    return math.sqrt(w0 * w0 - g * g), g


def oscillator_input(period_ps: float, Q: float, n_real: int, seed: int, record_ps=RECORD_PS, dt_ps=DT_PS,
                     n_series=N_SERIES, floor=FLOOR):
    """Realisations of the damped oscillator: (x, dt_ps, omega, gamma) each."""
    from mdbridge.analysis.spectrum import simulate
    rng = np.random.default_rng(seed)
    w, g = gamma_of(period_ps, Q)
    n = int(round(record_ps / dt_ps))
    for _ in range(n_real):
        x = simulate(rng, n_series, n, dt_ps, w, g, 1.0, floor)
        yield x - x.mean(axis=1, keepdims=True), dt_ps, w, g


# -- MD-like spectra: dispersive modes on a common background ------------------------------
# The 158-bp MD's mode spectra (docs/modes.md) are each mode's damped
# oscillator on top of motion that is the same at every n: slow red noise (an exponential
# autocovariance, as pairs opening and closing give) and the broad band of the base-pair
# steps' own vibration (an overdamped oscillator near 1.8 ps), plus a white floor. These
# records have all three, at every n the same, under dispersive modes of known omega_n, Q.
LOCAL_BAND = (3.5, 0.9)        # (omega [rad/ps], Q) of the local band
RED_TAU_PS = 300.0


# Two MD-like kinds: twist-like (omega ~ n, broad: Q = 2, peaks 3x the background under
# them, as the MD's twist n = 1-8) and bend-like (the MD's bend periods, Q = 3, peaks 10x
# the background, under red noise 30x stronger that tops the lowest bins of every high n)
TWIST_LIKE = {"omegas": [0.09 * n for n in range(1, 15)], "Qs": [2.0] * 14, "peak_over_background": [3.0] * 14}
BEND_LIKE = {"omegas": [2 * math.pi / p for p in (500, 210, 128, 78, 60, 44, 34, 27, 22, 19, 17.5, 15.4, 13, 11)],
             "Qs": [3.0] * 14, "peak_over_background": [10.0] * 14, "red": 30.0}


def red_noise(rng, n_series: int, n: int, dt_ps: float, tau_ps: float) -> np.ndarray:
    """Unit-variance stationary records of the exponential autocovariance exp(-|t| / tau)
    (the discrete-time AR(1) process, exact at the samples)."""
    from scipy.signal import lfilter
    phi = math.exp(-dt_ps / tau_ps)
    e = rng.standard_normal((n_series, n)) * math.sqrt(1 - phi * phi)
    e[:, 0] = rng.standard_normal(n_series)
    return lfilter([1.0], [1.0, -phi], e, axis=1)


def md_like_modes(omegas, Qs, peak_over_background, red=1.0, local=1.0, floor=0.05,
                  record_ps=RECORD_PS, dt_ps=DT_PS, n_series=N_SERIES, tau_ps=RED_TAU_PS):
    """The truth of an MD-like kind: per mode n (index i) the oscillator's (omega, gamma) and
    its variance, set so that its expected power at its peak stands peak_over_background[i]
    times above the background there; the background (red, local, floor variances) is the
    same for every mode."""
    from mdbridge.analysis.spectrum import expected_periodogram
    n = int(round(record_ps / dt_ps))
    k = np.arange(n)
    red_acvf = (1 - k / n) * np.exp(-k * dt_ps / tau_ps)
    G = red * (2 * np.fft.rfft(red_acvf).real - 1.0) + local * expected_periodogram(n, dt_ps, *gamma_of(
        2 * math.pi / LOCAL_BAND[0], LOCAL_BAND[1])) + floor
    modes = []
    for w0, Q, r in zip(omegas, Qs, peak_over_background):
        w, g = gamma_of(2 * math.pi / w0, Q)
        F = expected_periodogram(n, dt_ps, w, g)
        jmax = int(np.argmax(F[1:])) + 1
        modes.append({"omega": w, "gamma": g, "variance": r * G[jmax] / F[jmax]})
    return {"modes": modes, "red": red, "local": local, "floor": floor, "n": n, "dt_ps": dt_ps,
            "n_series": n_series, "tau_ps": tau_ps}


def md_like_realisation(rng, truth: dict) -> list:
    """One realisation: the pooled real series (n_series, N) of every mode (md_like_modes)."""
    from mdbridge.analysis.spectrum import simulate
    n, dt, M = truth["n"], truth["dt_ps"], truth["n_series"]
    wl, gl = gamma_of(2 * math.pi / LOCAL_BAND[0], LOCAL_BAND[1])
    xs = []
    for m in truth["modes"]:
        x = simulate(rng, M, n, dt, m["omega"], m["gamma"], m["variance"], truth["floor"]) \
            + math.sqrt(truth["local"]) * simulate(rng, M, n, dt, wl, gl) \
            + math.sqrt(truth["red"]) * red_noise(rng, M, n, dt, truth["tau_ps"])
        xs.append(x - x.mean(axis=1, keepdims=True))
    return xs


def md_like_input(truth: dict, n_real: int, seed: int, modes, background: bool = True):
    """{mode index: [(OscillatorFit or None, reason, omega, gamma), ...]}: the modes (indices)
    of n_real MD-like records (md_like_realisation) fitted as `dnarod modes` fits them (all
    modes of a realisation together: mdbridge/analysis/mode_spectra.py fit_kind), or, the
    control, one at a time with today's rule before the common background (background=False:
    fit_mode alone)."""
    from mdbridge.analysis.mode_spectra import fit_kind, fit_mode
    rng = np.random.default_rng(seed)
    out: dict = {i: [] for i in modes}
    for _ in range(n_real):
        xs = md_like_realisation(rng, truth)
        if background:
            fits = fit_kind(xs, truth["dt_ps"], wanted=[i in modes for i in range(len(xs))])
        else:
            fits = [fit_mode(x, truth["dt_ps"]) if i in modes else None for i, x in enumerate(xs)]
        for i in modes:
            m = truth["modes"][i]
            fit, why = fits[i]
            out[i].append((fit, why, xs[i].shape[1] * truth["dt_ps"], m["omega"], m["gamma"]))
    return out


def fitted(realisations, line: str = "auto"):
    """(fit, reason, record_ps, omega, gamma) of each realisation (x, dt_ps, omega, gamma) of
    one mode, fitted alone (mode_spectra.fit_mode)."""
    from mdbridge.analysis.mode_spectra import fit_mode
    for x, dt, w, g in realisations:
        fit, why = fit_mode(x, dt, errors="hessian", line=line)
        yield fit, why, x.shape[1] * dt, w, g


def calibrate(realisations, line: str = "auto") -> dict:
    """Bias, RMS error and stated / RMS of omega and gamma over the realisations: records
    (x, dt_ps, omega, gamma) of one mode, fitted alone, or fits (fit, reason, record_ps,
    omega, gamma) (md_like_input)."""
    from mdbridge.analysis.mode_spectra import refusal
    est = []
    refused = []
    lines = 0
    realisations = list(realisations)
    items = realisations if realisations and len(realisations[0]) == 5 else fitted(realisations, line)
    for fit, why, record_ps, w, g in items:
        why = why or refusal(fit, record_ps)
        if why:
            refused.append(why)
        if fit is not None and fit.line is not None:
            lines += 1
        if fit is None or why:
            est.append((np.nan, np.nan, np.nan, np.nan, w, g, np.nan, np.nan))
            continue
        est.append((fit.omega_per_ps, fit.omega_err_per_ps, fit.damping_per_ps, fit.damping_err_per_ps, w, g,
                    fit.Q, fit.Q_err))
    return calibration_summary(est, refused, lines)


def calibration_summary(est, refused: list, lines: int) -> dict:
    """The statistics of `calibrate` from one row per realisation, (omega, omega_err, gamma,
    gamma_err, omega_true, gamma_true, Q, Q_err) [1/ps], NaN where the mode was refused."""
    e = np.array(est, float)
    w_true, g_true = e[0, 4], e[0, 5]
    ok = np.isfinite(e[:, 0]) & np.isfinite(e[:, 1])
    if ok.sum() < 2:
        return {"realisations": len(e), "fitted": int(ok.sum()), "refused": refused, "taken_as_line": lines,
                "omega_true_per_ps": w_true, "gamma_true_per_ps": g_true, "omega_ratio": None, "omega_pass": False}
    dw = e[ok, 0] - w_true
    out = {"realisations": len(e), "fitted": int(ok.sum()), "refused": refused, "taken_as_line": lines,
           "omega_true_per_ps": w_true,
           "gamma_true_per_ps": g_true,
           "omega_bias_rel": float(dw.mean() / w_true), "omega_rms_rel": float(np.sqrt(np.mean(dw ** 2)) / w_true),
           "omega_ratio": float(np.sqrt(np.mean(e[ok, 1] ** 2)) / np.sqrt(np.mean(dw ** 2))),
           "omega_ratio_68": _ratio_interval(e[ok, 1], dw),
           "omega_within_1_sigma": float(np.mean(np.abs(dw) <= e[ok, 1]))}
    if g_true > 0:
        okg = ok & np.isfinite(e[:, 3])
        dg = e[okg, 2] - g_true
        out.update(gamma_bias_rel=float(dg.mean() / g_true), gamma_rms_rel=float(np.sqrt(np.mean(dg ** 2)) / g_true),
                   gamma_ratio=float(np.sqrt(np.mean(e[okg, 3] ** 2)) / np.sqrt(np.mean(dg ** 2)))
                   if okg.sum() >= 2 else None)
        okq = ok & np.isfinite(e[:, 7])
        Q_true = math.hypot(w_true, g_true) / (2 * g_true)
        dQ = e[okq, 6] - Q_true
        out.update(Q_true=Q_true, Q_bias_rel=float(dQ.mean() / Q_true) if okq.any() else None,
                   Q_ratio=float(np.sqrt(np.mean(e[okq, 7] ** 2)) / np.sqrt(np.mean(dQ ** 2)))
                   if okq.sum() >= 2 else None)
    out["omega_pass"] = bool(LOW <= out["omega_ratio"] <= HIGH)
    return out


# -- thermal-rod series: the Langevin rod, whose frequencies linear theory gives ----------
# The paper's 158-bp rod (the duplex of the dispersion MD: 14 modes of each kind, so that
# the common-background rule of `dnarod modes` sees what it sees there), unkicked, Langevin
# at 0.03 K, where the slack tension moves bend n = 1 by < 0.5 % and higher n by that over
# n^2 (docs/modes.md, "The cold rod") and the other modes not at linear order:
# far below the statistical errors (>= 0.05 % here). The frictions (rod units, per length)
# are chosen for damped modes of Q ~ 1.5-30 as the MD's (across: bend Q = 1.4 at n = 2 to
# 27 at n = 14; about the axis: twist Q = 1.5 n; along: stretch Q = 2 n); bend n = 1 is
# overdamped. The record: 4 ns (the dispersion MD's), frames every 2 tau (1.88 ps: the
# rod's shear lines, up to ~1.5 rad/ps, stay below the Nyquist frequency).
ROD_BP, ROD_TURNS = 158, 15
ROD_TEMPERATURE_K = 0.03
ROD_FRICTION_TRANSLATIONAL = (0.032, 0.01)     # [along, across]
ROD_FRICTION_ROTATIONAL = (0.079, 0.05)        # [about the axis, across]
ROD_DT, ROD_FRAME, ROD_FRAMES = 0.1, 2.0, 2126  # tau; 4002 ps


def thermal_rod_scene(seed: int) -> dict:
    return {"initial": {"kind": "dna_planar", "bp": ROD_BP, "turns": ROD_TURNS, "A_v_A_per_ps": 0.0, "A_A": 0.0},
            "solver": {"space": "spectral", "time": "langevin", "dt": ROD_DT},
            "output": {"t_end": ROD_FRAME * (ROD_FRAMES - 1), "frames": ROD_FRAMES,
                       "fields": ["internal", "centerline", "directors"]},
            # keep_closure false: no projection in the dynamics that linear theory lacks
            "thermal": {"temperature_K": ROD_TEMPERATURE_K, "seed": int(seed), "keep_closure": False,
                        "friction_translational": list(ROD_FRICTION_TRANSLATIONAL),
                        "friction_rotational": list(ROD_FRICTION_ROTATIONAL)}}


def thermal_rod_truth() -> dict:
    """{(kind, n): (omega, gamma) [1/ps]} of the linearised damped operator of the scene's
    rod (mdbridge/rod/linear.py LinearRod.damped_modes: rodcore's own linear operator with
    the Langevin frictions), at zero tension (the rod holds its rest length); absent where
    the mode is overdamped. Bend's four eigenvalues per n (two handednesses, two body
    wavenumbers) are degenerate for this isotropic material; their spread is checked."""
    from dna_models.units import Units
    from mdbridge.rod.linear import LinearRod, UniformMaterial
    u = Units.paper()
    L = ROD_BP * u.length_to_rod(u.rise_A)
    rod = LinearRod(UniformMaterial.paper(2 * math.pi * ROD_TURNS / L), L, ROD_BP, 0.0, turns=ROD_TURNS)
    by_mode: dict = {}
    for m in rod.damped_modes(ROD_FRICTION_TRANSLATIONAL, ROD_FRICTION_ROTATIONAL, ROD_TURNS - 1):
        if m["kind"] != "shear" and m["n"] >= 1:
            by_mode.setdefault((m["kind"], m["n"]), []).append((m["omega"], m["damping"]))
    out = {}
    for key, wg in by_mode.items():
        wg_arr = np.array(wg)
        if np.ptp(wg_arr, axis=0).max() > 1e-9 * wg_arr.max():
            raise AssertionError(f"{key}: the damped eigenvalues of one mode differ: {wg}")
        out[key] = tuple(u.angular_velocity_to_rad_per_ps(v) for v in wg_arr.mean(axis=0))
    return out


def thermal_rod_realisation(seed: int, workdir) -> dict:
    """One Langevin rod run through `dnarod modes`' code path (the rod file read as the
    command reads it, mode_table on it alone), and the control on the same series: each
    mode alone as a sinusoid in white noise (line="always"). {"kind n": {omega, omega_err,
    gamma, gamma_err, Q, Q_err, reason, undamped, oscillator_variance, oscillator_variance_err,
    length_A, control_omega, control_omega_err, control_reason}}, numbers in 1/ps (variances in
    modes.json's units)."""
    from mdbridge.analysis.mode_run import ModeInput
    from mdbridge.analysis.mode_spectra import fit_mode, mode_table, refusal
    from mdbridge.rod.run import run_scene
    h5 = Path(workdir) / f"thermal_rod_{seed}.h5"
    run_scene(thermal_rod_scene(seed), output=h5)
    series = ModeInput(str(h5)).mode_series(lambda *a, **k: None)
    h5.unlink()
    table = mode_table(series)
    s = series[0]
    out = {}
    for e in table["modes"]:
        row = {"omega": e["omega_per_ps"], "omega_err": e["omega_err_per_ps"], "gamma": e["damping_per_ps"],
               "gamma_err": e["damping_err_per_ps"], "Q": e["Q"], "Q_err": e["Q_err"], "reason": e["reason"],
               "undamped": e.get("undamped"), "oscillator_variance": e.get("oscillator_variance"),
               "oscillator_variance_err": e.get("oscillator_variance_err"), "length_A": table["length_A"]}
        fit, why = fit_mode(s.real_series(e["kind"], e["n"] - 1), s.dt_ps, line="always")
        why = why or refusal(fit, table["record_ps"])
        row.update(control_omega=None if why else fit.omega_per_ps,
                   control_omega_err=None if why else fit.omega_err_per_ps, control_reason=why)
        out[f"{e['kind']} {e['n']}"] = row
    return out


def thermal_rod_inertia_truth() -> dict:
    """{"twist": I3, "stretch": rho} of the scene's rod (the paper's material), rod units."""
    from mdbridge.rod.linear import UniformMaterial
    mat = UniformMaterial.paper()
    return {"twist": float(np.asarray(mat.I)[2, 2]), "stretch": float(mat.rho)}


def inertia_summary(rows: list, key: str, truth: float) -> dict:
    """Kinetic equipartition of one axial mode over the realisations: the inertia per length
    that each realisation's fitted oscillator implies (dispersion_prediction.axial_inertia),
    over the truth. Pass: the mean within 3 standard errors of 1, and stated / RMS within
    LOW-HIGH. The control: the damped frequency omega in place of omega0 (the usual slip),
    which the low-Q modes must fail."""
    from mdbridge.analysis.dispersion_prediction import axial_inertia
    kind, n = key.split()
    val, err, ctl = [], [], []
    for r in rows:
        if r[key]["reason"] is not None or not r[key].get("oscillator_variance"):
            continue
        entry = {"kind": kind, "n": int(n), "omega_per_ps": r[key]["omega"], "omega_err_per_ps": r[key]["omega_err"],
                 "damping_per_ps": r[key]["gamma"], "damping_err_per_ps": r[key]["gamma_err"],
                 "oscillator_variance": r[key]["oscillator_variance"],
                 "oscillator_variance_err": r[key]["oscillator_variance_err"]}
        v, e = axial_inertia(entry, ROD_BP, r[key]["length_A"], ROD_TEMPERATURE_K)
        val.append(v / truth)
        err.append(e / truth)
        g = r[key]["gamma"] or 0.0
        ctl.append(v / truth * r[key]["omega"] ** 2 / (r[key]["omega"] ** 2 + g ** 2))
    if len(val) < 3:
        return {"fitted": len(val), "pass": False}

    def stats(x, stated):
        x = np.asarray(x)
        se = float(x.std(ddof=1) / math.sqrt(len(x)))
        ratio = float(np.sqrt(np.mean(np.asarray(stated) ** 2)) / np.sqrt(np.mean((x - 1) ** 2)))
        return {"mean": float(x.mean()), "mean_err": se, "z": (float(x.mean()) - 1) / se, "stated_over_rms": ratio,
                "pass": bool(abs(x.mean() - 1) < 3 * se and LOW <= ratio <= HIGH)}
    return {"fitted": len(val), "truth_rod_units": truth, **stats(val, err), "control": stats(ctl, err)}


def thermal_rod_calibration(rows: list, truth: dict) -> list:
    """Per kind and n: `calibration_summary` of the command's numbers and of the control
    over the realisations (rows: thermal_rod_realisation's), against the truth."""
    num = (lambda v: np.nan if v is None else v)
    cases = []
    for kind in ("bend", "twist", "stretch"):
        for n in range(1, ROD_TURNS):
            key = f"{kind} {n}"
            if (kind, n) not in truth:
                cases.append({"kind": kind, "n": n, "overdamped": True,
                              "refused": [r[key]["reason"] for r in rows if r[key]["reason"]]})
                continue
            w, g = truth[(kind, n)]
            fit = [(num(r[key]["omega"]), num(r[key]["omega_err"]), num(r[key]["gamma"]), num(r[key]["gamma_err"]),
                    w, g, num(r[key]["Q"]), num(r[key]["Q_err"])) for r in rows]
            # (the control states no damping: its rows carry gamma_true 0, which skips gamma)
            ctl = [(num(r[key]["control_omega"]), num(r[key]["control_omega_err"]), np.nan, np.nan, w, 0.0,
                    np.nan, np.nan) for r in rows]
            case = {"kind": kind, "n": n, "overdamped": False,
                    "fit": calibration_summary(fit, [r[key]["reason"] for r in rows if r[key]["reason"]],
                                               sum(bool(r[key]["undamped"]) for r in rows)),
                    "control": calibration_summary(ctl, [r[key]["control_reason"] for r in rows
                                                         if r[key]["control_reason"]], 0)}
            if kind != "bend" and all("oscillator_variance" in r[key] for r in rows):
                case["inertia"] = inertia_summary(rows, key, thermal_rod_inertia_truth()[kind])
            cases.append(case)
    return cases


def halves_z(records, dt_ps: float, line: str = "auto") -> list:
    """The halves test of `dnarod modes` (mode_spectra._halves) on records (x, ...) of one
    mode: the signed z = (omega_2 - omega_1) / sqrt(err_1^2 + err_2^2) of each record's two
    halves, fitted alone; None where a half is refused."""
    from mdbridge.analysis.mode_spectra import fit_mode, refusal
    out = []
    for x, *_ in records:
        h = x.shape[1] // 2
        w, e = [], []
        for part in (x[:, :h], x[:, h:2 * h]):
            part = part - part.mean(axis=1, keepdims=True)
            fit, why = fit_mode(part, dt_ps, line=line)
            if why or refusal(fit, h * dt_ps):
                break
            w.append(fit.omega_per_ps)
            e.append(fit.omega_err_per_ps)
        out.append((w[1] - w[0]) / math.hypot(*e) if len(w) == 2 else None)
    return out


def stepped_input(period_ps: float, Q: float, step: float, n_real: int, seed: int, record_ps=RECORD_PS,
                  dt_ps=DT_PS, n_series=N_SERIES, floor=FLOOR):
    """Records that are not stationary: the oscillator of period_ps in the first half and of
    period_ps / (1 + step) in the second (each half its own stationary record)."""
    from mdbridge.analysis.spectrum import simulate
    rng = np.random.default_rng(seed)
    h = int(round(record_ps / dt_ps)) // 2
    for _ in range(n_real):
        parts = [simulate(rng, n_series, h, dt_ps, *gamma_of(period_ps / f, Q), 1.0, floor) for f in (1.0, 1.0 + step)]
        x = np.concatenate(parts, axis=1)
        yield x - x.mean(axis=1, keepdims=True), dt_ps


def _ratio_interval(stated, dev, n_boot=2000, seed=0):
    """The central 68 % interval of stated / RMS over bootstrap resamples of the
    realisations: the ratio's own sampling error (large for lines, whose error scales as
    1 / amplitude and the amplitude is random)."""
    rng = np.random.default_rng(seed)
    i = rng.integers(0, len(dev), (n_boot, len(dev)))
    r = np.sqrt(np.mean(stated[i] ** 2, axis=1)) / np.sqrt(np.mean(dev[i] ** 2, axis=1))
    return [float(v) for v in np.percentile(r, [16, 84])]


def thermal_rod_main(a) -> None:
    """--thermal-rod: a.realisations Langevin rods (seeds a.seed, a.seed + 1, ...), each run
    and analysed in turn (each realisation's numbers kept in --raw, so an interrupted run
    resumes), then the table against linear theory."""
    import json
    import tempfile
    from mdbridge.jsonio import write_json
    raw = Path(a.raw) if a.raw else None
    rows = json.loads(raw.read_text()) if raw is not None and raw.is_file() else {}
    t0, cpu0 = time.time(), time.process_time()
    with tempfile.TemporaryDirectory(prefix="modecal-") as tmp:
        for seed in range(a.seed, a.seed + a.realisations):
            if str(seed) in rows:
                continue
            t = time.process_time()
            rows[str(seed)] = thermal_rod_realisation(seed, tmp)
            print(f"seed {seed}: {time.process_time() - t:.1f} s", flush=True)
            if raw is not None:
                write_json(raw, rows)
    truth = thermal_rod_truth()
    cases = thermal_rod_calibration([rows[str(s)] for s in range(a.seed, a.seed + a.realisations)], truth)
    for c in cases:
        if c["overdamped"]:
            print(f"{c['kind']:7s} {c['n']:2d}: overdamped in linear theory; refused in {len(c['refused'])}")
            continue
        d, k = c["fit"], c["control"]
        r68 = d.get("omega_ratio_68") or [math.nan, math.nan]
        bias, rms = 100 * d.get("omega_bias_rel", math.nan), 100 * d.get("omega_rms_rel", math.nan)
        print(f"{c['kind']:7s} {c['n']:2d}: Q {d.get('Q_true', math.inf):5.1f}, omega bias {bias:+6.2f} %, "
              f"rms {rms:5.2f} %, "
              f"stated/rms {d['omega_ratio'] or math.nan:.2f} ({r68[0]:.2f}-{r68[1]:.2f}), gamma stated/rms "
              f"{d.get('gamma_ratio') or math.nan:.2f} [{len(d['refused'])} refused] | control "
              f"{k['omega_ratio'] or math.nan:.2f}", flush=True)
        if c.get("inertia", {}).get("mean") is not None:
            i = c["inertia"]
            print(f"          inertia / truth {i['mean']:.3f} +- {i['mean_err']:.3f}, stated/rms "
                  f"{i['stated_over_rms']:.2f} pass {i['pass']} | control {i['control']['mean']:.3f} "
                  f"(z {i['control']['z']:+.1f}) pass {i['control']['pass']}", flush=True)
    damped = [c for c in cases if not c["overdamped"]]
    from dna_models.units import Units
    res = {"what": "calibration of dnarod modes' frequency errors on thermal-rod series against the linearised "
                   "damped operator (bench/mode_spectrum_calibration.py --thermal-rod)",
           "scene": thermal_rod_scene(a.seed), "seeds": [a.seed, a.seed + a.realisations - 1],
           "record_ps": Units.paper().time_to_ps(ROD_FRAME * (ROD_FRAMES - 1)), "pass_band": [LOW, HIGH],
           "realisations": a.realisations, "cases": cases,
           "all_pass": all(c["fit"]["omega_pass"] for c in damped),
           "failing": [f"{c['kind']} {c['n']}" for c in damped if not c["fit"]["omega_pass"]],
           "control_fails": all(not c["control"]["omega_pass"] for c in damped),
           "inertia_all_pass": all(c["inertia"]["pass"] for c in damped if "inertia" in c),
           "inertia_failing": [f"{c['kind']} {c['n']}" for c in damped if "inertia" in c and not c["inertia"]["pass"]],
           "inertia_control_fails": [f"{c['kind']} {c['n']}" for c in damped
                                     if "inertia" in c and not c["inertia"]["control"]["pass"]],
           "cpu_s_this_call": time.process_time() - cpu0, "wall_s_this_call": time.time() - t0}
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    write_json(out / "mode_spectrum_calibration_thermal_rod.json", res)
    print(f"all pass: {res['all_pass']} (failing: {res['failing']}); control fails everywhere: "
          f"{res['control_fails']}; wrote {out / 'mode_spectrum_calibration_thermal_rod.json'}")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--realisations", type=int, default=60)
    ap.add_argument("--out", default=str(Path(__file__).resolve().parent / "results"))
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--thermal-rod", action="store_true",
                    help="the thermal-rod series instead (writes mode_spectrum_calibration_thermal_rod.json)")
    ap.add_argument("--raw", default=None, metavar="JSON",
                    help="with --thermal-rod: keep each realisation's numbers here and resume from them")
    a = ap.parse_args(argv)
    if a.thermal_rod:
        return thermal_rod_main(a)
    rows = []
    t0 = time.time()
    for i, (P, Q) in enumerate(CASES):
        row = {"period_ps": P, "Q": None if math.isinf(Q) else Q}
        for name, line in (("fit", "auto"), ("control", "always")):
            row[name] = calibrate(oscillator_input(P, Q, a.realisations, a.seed + 100 * i), line)
        rows.append(row)
        d, c = row["fit"], row["control"]
        print(f"P = {P:5g} ps, Q = {Q:>4}: omega bias {100 * d['omega_bias_rel']:+6.2f} %, rms "
              f"{100 * d['omega_rms_rel']:5.2f} %, stated/rms {d['omega_ratio']:.2f} "
              f"({d['omega_ratio_68'][0]:.2f}-{d['omega_ratio_68'][1]:.2f})"
              + (f", gamma stated/rms {d['gamma_ratio']:.2f}" if d.get("gamma_ratio") else "")
              + f" [{len(d['refused'])} refused, {d['taken_as_line']} lines]"
              + f" | control: stated/rms {c['omega_ratio']:.2f}, bias {100 * c['omega_bias_rel']:+.2f} %",
              flush=True)
    res = {"what": "calibration of dnarod modes' frequency errors on damped-oscillator series "
                   "(bench/mode_spectrum_calibration.py)",
           "record_ps": RECORD_PS, "dt_ps": DT_PS, "n_series": N_SERIES, "floor_over_variance": FLOOR,
           "pass_band": [LOW, HIGH], "realisations": a.realisations, "seed": a.seed, "cases": rows,
           "all_pass": all(r["fit"]["omega_pass"] for r in rows),
           "control_fails": any(not r["control"]["omega_pass"] for r in rows),
           "cpu_s": time.process_time(), "wall_s": time.time() - t0}
    from mdbridge.jsonio import write_json
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    write_json(out / "mode_spectrum_calibration.json", res)
    print(f"all pass: {res['all_pass']}; control fails: {res['control_fails']}; "
          f"wrote {out / 'mode_spectrum_calibration.json'}")


if __name__ == "__main__":
    main()
