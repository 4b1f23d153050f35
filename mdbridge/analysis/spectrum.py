"""Frequency and damping of a mode from its equilibrium time series: the damped oscillator's
exact discrete-time spectrum fitted by Whittle likelihood (docs/modes.md, "Frequency and damping").

Model. Each real series x(t) (one quadrature of one mode) is a damped harmonic oscillator
driven by white noise, x'' + 2 gamma x' + omega0^2 x = noise, sampled every dt, plus white
noise of its own (the floor: base-pair jitter that is not the mode). Its autocovariance is

    C(tau) = var e^{-gamma |tau|} [cos(omega tau) + (gamma / omega) sin(omega |tau|)],

omega = sqrt(omega0^2 - gamma^2) the damped frequency (the centre of the power peak) and
gamma the amplitude's decay rate (half the full width of the power peak). Sampled, the
oscillator is exactly an ARMA(2,1) process: AR roots exp((-gamma +- i omega) dt). Q =
omega0 / (2 gamma); gamma = 0 is the undamped mode (a line).

Likelihood. The debiased Whittle likelihood (Sykulski et al., Biometrika 106:251, 2019):
the periodogram I_j = |sum_t x_t e^{-i lambda_j t}|^2 / N of each series is compared with
its EXPECTED value for a record of N samples,

    E[I_j] = sum_{|k| < N} (1 - |k| / N) C(k dt) e^{-i lambda_j k}   (+ the floor),

i.e. the spectrum convolved with the record's Fejer kernel. This is what makes a line
(gamma -> 0) and a peak a few bins wide fit without bias: the plain Whittle likelihood
compares the periodogram with the spectrum itself and cannot describe leakage. The series
of one fit share (omega, gamma); each has its own variance and floor (a kicked rod puts
all of its motion in one quadrature), which are profiled out.

Background. An MD mode's spectrum is the oscillator on top of motion that is not the mode:
slow red noise (pairs opening, the duplex's drift) and the fast, broad band of the base-pair
steps' own vibration. Both are the same at every n (non-dispersive); the caller measures
their shape G(lambda) once from all n of a kind (mdbridge/analysis/mode_spectra.py,
common_background) and passes it as `background`: each series then gets G with an
amplitude of its own, E_j = a F_j + c G_j + b.

Errors. The observed information: the inverse Hessian of the negative log-likelihood at
the fit, every parameter free (Q's and omega0's through the covariance of omega and
gamma). A line (a mode that keeps its phase over the record, which
the damping fit cannot resolve) is refined by least squares instead (`line_fit`, with the
finite-record Cramer-Rao error at the local noise level). Both are calibrated
(bench/mode_spectrum_calibration.py): stated / RMS error 0.7-1.4 for periods 12-1100 ps
and Q from 1 to infinity in 4-ns records of 0.5-ps frames.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize

# Q above which a fitted mode counts as undamped (gamma consistent with zero is reported
# as such anyway; this only bounds the search).
GAMMA_OVER_OMEGA_MIN = 1e-7
GAMMA_OVER_OMEGA_MAX = 1.0     # Q >= 1/2: an oscillation; below it there is no peak
LINE_GAMMA_T = 3.0             # a line is tried when the fitted gamma T is below this, and
LINE_RESIDUAL = 0.01           # taken when one sinusoid leaves less than this of the power near it
NOT_LINE_MIN_GAMMA_T = 0.5     # a mode that is not a line has gamma T above this (it leaves ~gamma T / 3)


def oscillator_acvf(lag_ps, omega: float, gamma: float, var: float = 1.0) -> np.ndarray:
    """Autocovariance of the damped oscillator at the lags `lag_ps` (module doc)."""
    tau = np.abs(np.asarray(lag_ps, float))
    return var * np.exp(-gamma * tau) * (np.cos(omega * tau) + (gamma / omega) * np.sin(omega * tau))


def variance_sampling_err(fit: "OscillatorFit") -> float:
    """The sampling error of mean_s a_s (the oscillator's variance averaged over M independent
    series of N samples) that the oscillator itself implies: the sample variance of a
    Gaussian series has variance (2 / N^2) sum_k (N - |k|) C(k)^2, so the mean over series has
    (2 / (M N^2)) sum_k (N - |k|) C(k)^2, ~ a^2 / (gamma T M) for a narrow peak. The observed
    information misses it when the record holds only a few coherence times (gamma T ~ 2): the
    periodogram's bins under a peak one bin wide are not independent
    (tests/python/test_statics.py)."""
    N, M = fit.n_samples, len(fit.variance)
    k = np.arange(1 - N, N)
    rho = oscillator_acvf(k * fit.dt_ps, fit.omega_per_ps, fit.damping_per_ps)
    rel2 = 2.0 * float(np.sum((N - np.abs(k)) * rho ** 2)) / (M * N * N)
    return float(np.mean(fit.variance)) * math.sqrt(rel2)


def periodogram(x: np.ndarray) -> np.ndarray:
    """I_j = |sum_t x_t e^{-2 pi i j t / N}|^2 / N of each row of x (M, N), j = 0..N//2."""
    x = np.atleast_2d(np.asarray(x, float))
    return np.abs(np.fft.rfft(x, axis=-1)) ** 2 / x.shape[-1]


def expected_periodogram(n: int, dt_ps: float, omega: float, gamma: float) -> np.ndarray:
    """E[I_j], j = 0..n//2, of a unit-variance oscillator record of n samples (module doc)."""
    k = np.arange(n)
    a = (1.0 - k / n) * oscillator_acvf(k * dt_ps, omega, gamma)
    return 2.0 * np.fft.rfft(a).real - a[0]


def frequencies_per_ps(n: int, dt_ps: float) -> np.ndarray:
    """The angular frequencies lambda_j / dt [rad/ps] of periodogram(), j = 0..n//2."""
    return 2 * np.pi * np.arange(n // 2 + 1) / (n * dt_ps)


@dataclass
class OscillatorFit:
    """One fit: the shared omega and gamma [1/ps], each series' variance and floor (in the
    units of the series squared, the floor as the white noise's variance per sample),
    the band [rad/ps], the negative log-likelihood and the bootstrap errors."""
    omega_per_ps: float
    damping_per_ps: float
    variance: np.ndarray
    floor: np.ndarray
    band_per_ps: tuple
    nll: float
    n_samples: int
    dt_ps: float
    omega_err_per_ps: float = float("nan")
    damping_err_per_ps: float = float("nan")
    Q_err: float = float("nan")
    omega0_err_per_ps: float = float("nan")
    mean_variance_err: float = float("nan")         # error of mean(variance) over the series
    line: dict | None = None
    background: np.ndarray | None = None             # G on the band's bins (module doc)
    background_amplitude: np.ndarray | None = None   # c of each series

    @property
    def omega0_per_ps(self) -> float:
        return math.hypot(self.omega_per_ps, self.damping_per_ps)

    @property
    def Q(self) -> float:
        return self.omega0_per_ps / (2 * self.damping_per_ps) if self.damping_per_ps > 0 else math.inf

    @property
    def record_ps(self) -> float:
        return self.n_samples * self.dt_ps

    def peak_to_floor(self) -> float:
        """The oscillator's largest expected power on the band over what lies beneath it
        there: the floor, and the background when there is one."""
        j = band_indices(self.n_samples, self.dt_ps, self.band_per_ps)
        f = expected_periodogram(self.n_samples, self.dt_ps, self.omega_per_ps, self.damping_per_ps)[j]
        i = int(np.argmax(f))
        under = float(np.sum(self.floor))
        if self.background is not None and self.background_amplitude is not None:
            under += float(np.sum(self.background_amplitude)) * float(self.background[i])
        return float(np.sum(self.variance)) * float(f[i]) / max(under, 1e-300)


def band_indices(n: int, dt_ps: float, band_per_ps) -> np.ndarray:
    lam = frequencies_per_ps(n, dt_ps)
    lo, hi = band_per_ps
    j = np.flatnonzero((lam >= lo) & (lam <= hi))
    return j[(j > 0) & (j < n / 2)]    # no mean, no Nyquist bin


def fit_oscillator(x: np.ndarray, dt_ps: float, band_per_ps=None, omega_guess=None,
                   errors: str = "hessian", line: str = "auto", background=None) -> OscillatorFit:
    """Fit the damped oscillator to the rows of x (M, N) (real series, mean removed by the
    caller) sampled every dt_ps, on the band (lo, hi) [rad/ps] (default: all of it).
    omega_guess: where to start (default: the pooled periodogram's peak in the band).
    background: None, or the shape G (N//2+1,) >= 0 of the motion that is not the mode, on
    the periodogram's frequencies, entered with a free amplitude per series (module doc).
    errors: "hessian" (observed information) or "none". line: "auto" (a line when the record is one, line_fit)
    or "always": every mode taken as a sinusoid in white noise, the control of the
    calibration (bench/mode_spectrum_calibration.py), whose errors a damped mode defeats."""
    x = np.atleast_2d(np.asarray(x, float))
    n = x.shape[1]
    lam = frequencies_per_ps(n, dt_ps)
    if band_per_ps is None:
        band_per_ps = (0.0, lam[-1])
    j = band_indices(n, dt_ps, band_per_ps)
    if len(j) < 6:
        raise ValueError(f"the band {band_per_ps} rad/ps holds {len(j)} frequencies of a {n}-sample "
                         "record; at least 6 are needed")
    I = periodogram(x)[:, j]
    G = None
    if background is not None:
        G = np.maximum(np.asarray(background, float)[j], 0.0)
        # unit mean on the band: the amplitudes are free, and stay O(1) in the fit
        G = G / G.mean() if np.any(G > 0) else None
    if line == "auto" and omega_guess is not None:
        sinusoid = line_fit(x, dt_ps, omega_guess)
        if sinusoid["residual_near"] < LINE_RESIDUAL:
            # a line at the guess (an undamped mode): the Whittle fit starts on it, where
            # its narrow start wins, rather than on a broad start elsewhere on the band
            fit = _fit_periodogram(I, j, n, dt_ps, lam, sinusoid["omega_per_ps"], G=G)
            fit.band_per_ps = (float(band_per_ps[0]), float(band_per_ps[1]))
            return _as_line(fit, sinusoid, errors, I, j)
    fit = _fit_periodogram(I, j, n, dt_ps, lam, omega_guess, G=G)
    fit.band_per_ps = (float(band_per_ps[0]), float(band_per_ps[1]))
    if line == "always" or fit.damping_per_ps * fit.record_ps < LINE_GAMMA_T:
        sinusoid = line_fit(x, dt_ps, fit.omega_per_ps)
        if line != "always" and sinusoid["residual_near"] >= LINE_RESIDUAL \
                and fit.damping_per_ps * fit.record_ps < NOT_LINE_MIN_GAMMA_T:
            # not a line, yet narrower than a damped mode that fails the line test can be:
            # a local minimum on a spike of the periodogram; fit again with gamma above it
            fit = _fit_periodogram(I, j, n, dt_ps, lam, omega_guess, NOT_LINE_MIN_GAMMA_T / (n * dt_ps), G=G)
            fit.band_per_ps = (float(band_per_ps[0]), float(band_per_ps[1]))
        elif line == "always" or sinusoid["residual_near"] < LINE_RESIDUAL:
            return _as_line(fit, sinusoid, errors, I, j)
    if errors == "hessian":
        (fit.omega_err_per_ps, fit.damping_err_per_ps, fit.Q_err, fit.omega0_err_per_ps,
         fit.mean_variance_err) = _hessian_errors(fit, I, j)
    elif errors != "none":
        raise ValueError(f"errors: 'hessian' or 'none', got {errors!r}")
    return fit


def _as_line(fit: OscillatorFit, sinusoid: dict, errors: str, I, j) -> OscillatorFit:
    """The fit as a line: line_fit's frequency and error; the damping's error from the
    Whittle fit's Hessian."""
    fit.line = sinusoid
    fit.omega_per_ps = sinusoid["omega_per_ps"]
    if errors != "none":
        fit.omega_err_per_ps = sinusoid["omega_err_per_ps"]
        _, fit.damping_err_per_ps, _, _, fit.mean_variance_err = _hessian_errors(fit, I, j)
    return fit


def _expected_and_derivatives(n: int, dt_ps: float, omega: float, gamma: float) -> np.ndarray:
    """(3, n//2+1): expected_periodogram and its derivatives in log omega and log gamma."""
    k = np.arange(n)
    tau = k * dt_ps
    w = 1.0 - k / n
    e = np.exp(-gamma * tau)
    c, s = np.cos(omega * tau), np.sin(omega * tau)
    C = e * (c + (gamma / omega) * s)
    dC_dw = e * (-tau * s - (gamma / omega ** 2) * s + (gamma / omega) * tau * c)
    dC_dg = -tau * C + e * s / omega
    A = np.fft.rfft(np.stack([w * C, w * omega * dC_dw, w * gamma * dC_dg]), axis=1).real
    return 2.0 * A - np.array([C[0], 0.0, 0.0])[:, None]


class _Whittle:
    """Negative log-likelihood of the periodograms I (M, J) on the band's bins j, with its
    gradient, in p = (log omega, log gamma, log a_1..a_M, log b_1..b_M[, log c_1..c_M]):
    a_s the variance, b_s the floor and c_s the background's amplitude of series s (the
    background G (J,) when given: module doc)."""

    def __init__(self, I, j, n, dt, G=None):
        self.I, self.j, self.n, self.dt, self.G = I, j, n, dt, G
        self.M = I.shape[0]

    def unpack(self, p):
        M = self.M
        a, b = np.exp(p[2:2 + M]), np.exp(p[2 + M:2 + 2 * M])
        c = np.exp(p[2 + 2 * M:]) if self.G is not None else None
        return a, b, c

    def __call__(self, p):
        M, I = self.M, self.I
        F = _expected_and_derivatives(self.n, self.dt, math.exp(p[0]), math.exp(p[1]))[:, self.j]
        a, b, c = self.unpack(p)
        E = a[:, None] * F[0][None, :] + b[:, None]
        if c is not None:
            E = E + c[:, None] * self.G[None, :]
        E = np.maximum(E, 1e-300)
        r = 1.0 / E - I / E ** 2            # d nll / d E
        g = np.empty(len(p))
        g[0] = np.sum(r * a[:, None] * F[1][None, :])
        g[1] = np.sum(r * a[:, None] * F[2][None, :])
        g[2:2 + M] = a * np.sum(r * F[0][None, :], axis=1)
        g[2 + M:2 + 2 * M] = b * np.sum(r, axis=1)
        if c is not None:
            g[2 + 2 * M:] = c * np.sum(r * self.G[None, :], axis=1)
        return float(np.sum(np.log(E) + I / E)), g

    def start(self, omega, gamma):
        """p with each series' variance and floor (and background) matched to its mean
        power on the band."""
        f = expected_periodogram(self.n, self.dt, omega, gamma)[self.j]
        Ibar = np.maximum(self.I.mean(axis=1), 1e-300)
        p = [[math.log(omega), math.log(gamma)], np.log(0.9 * Ibar / max(f.mean(), 1e-300)), np.log(0.1 * Ibar)]
        if self.G is not None:
            # the background's share: the series' power where the oscillator is weakest
            k = int(np.argmin(f))
            p[2] = np.log(0.05 * Ibar)
            p.append(np.log(np.maximum(0.5 * self.I[:, k], 1e-300 + 0.05 * Ibar) / max(self.G[k], 1e-300)))
        return np.concatenate(p)

    def params(self, fit: "OscillatorFit") -> np.ndarray:
        p = [[math.log(fit.omega_per_ps), math.log(fit.damping_per_ps)], np.log(fit.variance), np.log(fit.floor)]
        if self.G is not None and fit.background_amplitude is not None:
            p.append(np.log(fit.background_amplitude))
        return np.concatenate(p)


def _fit_periodogram(I, j, n, dt, lam, omega_guess, gamma_min_per_ps=0.0, G=None) -> OscillatorFit:
    lo_w, hi_w = lam[j[0]], lam[j[-1]]
    if omega_guess is None:
        omega_guess = lam[j[np.argmax(I.sum(axis=0))]]
    omega_guess = float(np.clip(omega_guess, lo_w, hi_w))
    W = _Whittle(I, j, n, dt, G)
    # start from the best of a grid of frequencies around the guess (the periodogram's peak
    # is a noisy guess) and damping ratios (the likelihood is flat in gamma once the peak
    # is narrower than the record resolves)
    omegas = [w for w in omega_guess * np.exp(np.linspace(-0.25, 0.25, 11)) if lo_w <= w <= hi_w] or [omega_guess]
    starts = [W.start(w, w * r) for w in omegas for r in (0.5, 0.15, 0.04, 0.01, 1e-3, 1e-5)]
    if gamma_min_per_ps > 0:
        starts = [p for p in starts if p[1] >= math.log(gamma_min_per_ps)] or \
            [W.start(omega_guess, 2 * gamma_min_per_ps)]
    p0 = min(starts, key=lambda p: W(p)[0])
    lw = (math.log(max(lo_w, lam[1]) * 0.5), math.log(min(hi_w * 1.5, lam[-1])))
    lg_min = max(lw[0] + math.log(GAMMA_OVER_OMEGA_MIN), math.log(gamma_min_per_ps) if gamma_min_per_ps > 0 else -1e300)
    bounds = [lw, (lg_min, lw[1] + math.log(GAMMA_OVER_OMEGA_MAX))] \
        + [(-300.0, 300.0)] * (len(p0) - 2)    # E^2 stays finite
    res = minimize(W, p0, jac=True, method="L-BFGS-B", bounds=bounds,
                   options={"maxiter": 1000, "ftol": 1e-12, "gtol": 1e-7})
    p = res.x
    a, b, c = W.unpack(p)
    return OscillatorFit(math.exp(p[0]), math.exp(p[1]), a, b, (lo_w, hi_w), float(res.fun), n, dt,
                         background=G, background_amplitude=c)


def simulate(rng, n_series: int, n: int, dt_ps: float, omega: float, gamma: float,
             variance=1.0, floor=0.0) -> np.ndarray:
    """n_series stationary records (n_series, n) of the model: the oscillator sampled exactly
    (its discrete-time transition, any gamma >= 0) plus white noise of variance `floor`.
    variance and floor: scalars or one per series."""
    variance = np.broadcast_to(np.asarray(variance, float), (n_series,))
    floor = np.broadcast_to(np.asarray(floor, float), (n_series,))
    x = oscillator_series(rng, n_series, n, dt_ps, omega, gamma) * np.sqrt(variance)[:, None]
    return x + rng.standard_normal((n_series, n)) * np.sqrt(floor)[:, None]


def oscillator_series(rng, n_series: int, n: int, dt_ps: float, omega: float, gamma: float) -> np.ndarray:
    """Unit-variance stationary records (n_series, n) of the damped oscillator (module doc),
    exact in time at any gamma >= 0: the state y = (x, x') advances by F = exp(A dt) plus an
    innovation z of covariance S - F S F^T (S the stationary covariance), from a stationary
    start. By Cayley-Hamilton (F^2 = tr F F - det F), x alone obeys the ARMA(2,1) recursion
        x_t = tr F x_{t-1} - det F x_{t-2} + [z_t - (tr F - F) z_{t-1}]_x,
    which lfilter runs for t >= 2."""
    from scipy.signal import lfilter
    w0sq = omega * omega + gamma * gamma
    A = np.array([[0.0, 1.0], [-w0sq, -2 * gamma]])
    e, c, s = math.exp(-gamma * dt_ps), math.cos(omega * dt_ps), math.sin(omega * dt_ps)
    F = e * (c * np.eye(2) + (s / omega) * (A + gamma * np.eye(2)))   # exp(A dt), underdamped
    S = np.diag([1.0, w0sq])
    Qn = S - F @ S @ F.T
    wq, vq = np.linalg.eigh(0.5 * (Qn + Qn.T))
    z = rng.standard_normal((n_series, n, 2)) @ (vq * np.sqrt(np.clip(wq, 0.0, None))).T
    y = rng.standard_normal((n_series, 2)) * np.sqrt([1.0, w0sq])     # y_{-1}, stationary
    x = np.empty((n_series, n))
    for t in range(min(n, 2)):
        y = y @ F.T + z[:, t]
        x[:, t] = y[:, 0]
    if n > 2:
        tr, det = float(np.trace(F)), float(np.linalg.det(F))
        G = tr * np.eye(2) - F
        drive = z[:, 2:, 0] - (z[:, 1:-1] @ G.T)[..., 0]
        # direct form II transposed state that continues from x_1, x_0 (scipy.signal.lfiltic)
        zi = np.stack([tr * x[:, 1] - det * x[:, 0], -det * x[:, 1]], axis=1)
        x[:, 2:] = lfilter([1.0], [1.0, -tr, det], drive, axis=1, zi=zi)[0]
    return x


def _hessian_errors(fit: OscillatorFit, I, j):
    """Observed-information errors of omega, gamma, Q, omega0 and of the oscillator's variance
    averaged over the series (mean_s a_s: the mode's own static variance, without the floor
    and the background; d mean = sum_s a_s d log a_s / M; never below its sampling error,
    variance_sampling_err): the inverse Hessian of the
    negative log-likelihood (central differences of its analytic gradient) at the fit, all
    parameters free. At a line (gamma at its lower bound, where the likelihood is flat in
    gamma) gamma is held and the errors of gamma and Q are NaN (omega0's is omega's).
    With omega0^2 = omega^2 + gamma^2 and Q = omega0 / (2 gamma),
    d log omega0 = (omega^2 d log omega + gamma^2 d log gamma) / omega0^2 and
    d log Q = d log omega0 - d log gamma, through the covariance of omega and gamma."""
    W = _Whittle(I, j, fit.n_samples, fit.dt_ps, fit.background)
    p = W.params(fit)
    h = 1e-4
    H = np.empty((len(p), len(p)))
    for i in range(len(p)):
        d = np.zeros(len(p))
        d[i] = h
        H[i] = (W(p + d)[1] - W(p - d)[1]) / (2 * h)
    H = 0.5 * (H + H.T)
    at_line = fit.damping_per_ps <= GAMMA_OVER_OMEGA_MIN * fit.omega_per_ps * 1.01
    keep = [i for i in range(len(p)) if not (at_line and i == 1)]
    cov = np.linalg.pinv(H[np.ix_(keep, keep)])
    err_w = fit.omega_per_ps * math.sqrt(max(cov[0, 0], 0.0))
    a = np.asarray(fit.variance, float)
    i_a = [keep.index(2 + s) for s in range(len(a))]
    va = a / len(a)
    err_a = max(math.sqrt(max(float(va @ cov[np.ix_(i_a, i_a)] @ va), 0.0)), variance_sampling_err(fit))
    if at_line:
        return err_w, float("nan"), float("nan"), err_w, err_a
    err_g = fit.damping_per_ps * math.sqrt(max(cov[1, 1], 0.0))
    w2, g2 = fit.omega_per_ps ** 2, fit.damping_per_ps ** 2
    v0 = np.array([w2, g2]) / (w2 + g2)
    vQ = v0 - np.array([0.0, 1.0])
    err_Q = fit.Q * math.sqrt(max(float(vQ @ cov[:2, :2] @ vQ), 0.0))
    err_w0 = fit.omega0_per_ps * math.sqrt(max(float(v0 @ cov[:2, :2] @ v0), 0.0))
    return err_w, err_g, err_Q, err_w0, err_a


def line_fit(x: np.ndarray, dt_ps: float, omega_guess: float) -> dict:
    """A line (a mode that keeps its phase over the whole record): the frequency of the
    sinusoid, shared by the rows of x (M, N), that fits them best by least squares, each
    row with its own amplitude, phase and mean (the maximum-likelihood frequency of a
    sinusoid in noise). For a line, the Whittle fit's frequency is pulled by the
    interference of the +omega and -omega images of a record of few periods (a few % at 3
    periods, by the phase); least squares has no such term.

    Whether the record is a line: residual_near, the power the sinusoid leaves within 3
    bins of it over the power there. A damped mode wanders in amplitude and phase, and one
    sinusoid leaves about gamma T / 3 of its power; a line leaves the floor's.

    Error: the Cramer-Rao bound of the model (each row a cos + b sin + c, omega shared) in
    white noise of the residual's periodogram level S beside the line (2 to 8 bins away,
    both sides): the exact finite-record Fisher information, omega's part after the
    nuisance (a, b, c) of each row are profiled (Schur complement), summed over rows. Far
    from omega = 0 it is Kay's 24 S / (A^2 N (N^2 - 1)) [rad^2 per sample^2] (Fundamentals
    of Statistical Signal Processing I, Ex. 3.14); at a few periods it is not."""
    from scipy.optimize import minimize_scalar
    x = np.atleast_2d(np.asarray(x, float))
    M, n = x.shape
    t = np.arange(n) - (n - 1) / 2.0

    def coef(w):
        B = np.stack([np.cos(w * t), np.sin(w * t), np.ones(n)], axis=1)
        c, *_ = np.linalg.lstsq(B, x.T, rcond=None)
        return B, c

    def rss(w):
        B, c = coef(w)
        return float(np.sum((x.T - B @ c) ** 2))

    w0 = omega_guess * dt_ps                      # rad per sample
    half = 2 * np.pi / n                          # one Fourier bin
    grid = w0 + np.linspace(-half, half, 41)
    grid = grid[grid > 0]
    wg = grid[int(np.argmin([rss(w) for w in grid]))]
    res = minimize_scalar(rss, bounds=(max(wg - half / 20, 1e-12), wg + half / 20), method="bounded",
                          options={"xatol": 1e-13})
    w = float(res.x)
    B, c = coef(w)
    r = x.T - B @ c
    A2 = c[0] ** 2 + c[1] ** 2
    P = periodogram(r.T)
    jw = w * n / (2 * np.pi)
    near = np.abs(np.arange(P.shape[1]) - jw)
    side = (near >= 2) & (near <= 8) & (np.arange(P.shape[1]) > 0)
    S = P[:, side].mean(axis=1) if side.any() else P[:, 1:].mean(axis=1)
    info = 0.0
    for (a, b), s_level in zip(c[:2].T, S):
        d_w = t * (-a * B[:, 1] + b * B[:, 0])          # d(model)/d(omega) [per rad/sample]
        J = np.column_stack([B, d_w])
        F = J.T @ J / max(s_level, 1e-300)
        info += F[3, 3] - F[3, :3] @ np.linalg.solve(F[:3, :3], F[:3, 3])
    close = (near <= 3) & (np.arange(P.shape[1]) > 0)
    data_near = float(periodogram(x)[:, close].sum())
    return {"omega_per_ps": w / dt_ps, "omega_err_per_ps": float(1 / np.sqrt(info)) / dt_ps,
            "residual_near": float(P[:, close].sum()) / max(data_near, 1e-300),
            "amplitude": [float(a) for a in np.sqrt(A2)], "residual_level": [float(v) for v in S]}
