"""Wave speed from the space-time Fourier content of u(s, t).

Estimator 1 (the reported value): nonlinear least squares on the k = 2 pi / L mode.
With c(t) = (2/n) sum_i u(s_i, t) exp(-i k s_i) the complex amplitude of that mode,

    u = a_+ cos(k s - w t + p_+) + a_- cos(k s + w t + p_-)
    <=>  c(t) = A_+ exp(-i w t) + A_- exp(+i w t) (+ B),   A_pm = a_pm exp(i p_pm),

which is exactly the least-squares fit of the travelling-wave model to u(s, t) restricted
to that mode (Parseval); B, the static deformation of the mode, is fitted with `offset`.
The model is linear in A_pm for a given w, so w is found by variable projection: a global
scan of the residual over w (from a quarter period in the record up to the Nyquist
frequency, steps of 1/16 of the peak width), then a golden-section refinement between the
scan's neighbours of its minimum. The same estimator runs on many records at once
(`fit_frequencies`), which is what makes the parametric bootstrap below affordable.

Error of w (`fit_with_replicates`):
* the noise of c(t) is an Ornstein-Uhlenbeck process estimated by restricted maximum
  likelihood from the residual, with what the fit absorbs accounted for
  (mdbridge/analysis/mode_noise.py);
* the linearised error (`omega_err_cov_per_ps`): the least-squares covariance with that
  noise covariance (the sandwich (J^T J)^-1 J^T Sigma J (J^T J)^-1);
* the stated error (`omega_err_bootstrap_per_ps`, = `omega_err_per_ps` when n_boot >= 2):
  a parametric bootstrap -- records drawn from the fitted model plus the fitted noise
  process, fitted by this same estimator -- the RMS of the refitted w about the fitted w.
  It includes the estimator's bias and the nonlinear regime (noise as large as the mode,
  records under a period), where the linearised error is several times too small; it is
  right by construction when the noise model is (docs/analysis.md gives the grid on which
  that was measured). Only the replicates that stay on the fitted peak (within its first
  zero, 2 pi / span) enter; the fraction that finds another is reported;
* detection: the same estimator on records of the fitted noise alone gives the height of
  the highest peak the noise makes (`line_power`, its DETECTION_QUANTILE), against which
  mode_error.refusal judges the record's own peak.
Speed = w / k; forward if |A_+| > |A_-|; "standing" when |A_+| - |A_-| is within
STANDING_SIGMA of its (linearised) standard error.

Estimator 2 (the cross-check): the phase velocity of c(t). For a predominantly travelling
wave, arg c(t) = p - w t, so the unwrapped phase falls linearly and the crest of the
mode moves at w / k (crest tracking of the k-mode). When |c(t)| is strongly modulated
(a standing or mixed wave), the forward and backward parts are first separated by their
sign of frequency (FFT in time) and the phase of the stronger one is used.
Neither estimator looks at the other's result.
"""
from __future__ import annotations

import math

import numpy as np

from dna_models.errors import InputError
from mdbridge.analysis.mode_noise import draw_ou, fit_ou_noise, ou_apply

MIN_PERIODS = 0.25       # below: no fit (a frequency cannot be told from a slow drift)
STANDING_SIGMA = 2.0     # |A_+| - |A_-| within this many standard errors -> standing
STANDING_REL = 0.05      # ... or within 5 % of |A_+| + |A_-| (|c| then dips to 5 % of its peak)
DETECTION_QUANTILE = 0.99  # a line must exceed this quantile of the noise alone's highest peak
SCAN_BUDGET = 1_000_000     # frequencies x records of one scan (fit_frequencies)
GOLDEN_STEPS = 36        # golden-section steps: the bracket (1/8 of the peak width) shrinks by 3e-8


def mode_amplitude(u: np.ndarray, mode: int = 1) -> np.ndarray:
    """c(t) of Fourier mode `mode` of u (T, n) sampled at s_i = i L / n (see module doc)."""
    u = np.asarray(u, float)
    return 2.0 / u.shape[1] * np.fft.fft(u, axis=1)[:, mode]


def basis(tc: np.ndarray, w, offset: bool) -> np.ndarray:
    """The model's columns e^{-iwt}, e^{+iwt} (and 1): (T, m) for one w, (R, T, m) for R."""
    w = np.asarray(w, float)
    e = np.exp(-1j * w[..., None] * tc) if w.ndim else np.exp(-1j * w * tc)
    cols = [e, np.conj(e)] + ([np.ones_like(e)] if offset else [])
    return np.stack(cols, axis=-1)


def _gram(s1, s2, n, offset):
    """Gram matrices (..., m, m) of the basis from s1 = sum e^{iwt}, s2 = sum e^{2iwt} (...)."""
    m = 3 if offset else 2
    G = np.zeros(s1.shape + (m, m), complex)
    G[..., 0, 0] = G[..., 1, 1] = n
    G[..., 0, 1] = s2
    G[..., 1, 0] = np.conj(s2)
    if offset:
        G[..., 2, 2] = n
        G[..., 0, 2] = G[..., 2, 1] = s1
        G[..., 2, 0] = G[..., 1, 2] = np.conj(s1)
    # where the basis degenerates (w at the Nyquist frequency, where e^{-iwt} = e^{iwt}
    # on the samples) a tiny ridge keeps the solve finite; the residual there is large
    return G + 1e-12 * n * np.eye(m)


def _explained(G, b):
    """b^H G^-1 b (...,): the part of |c|^2 the projection explains."""
    x = np.linalg.solve(G, b[..., None])[..., 0]
    return np.einsum("...i,...i->...", np.conj(b), x).real


def _grid_sums(tc, C, grid, h=1):
    """S(w) = sum_t e^{i h w t} x(t) at every w of `grid` (G,) for each row x of C (R, T):
    (G, R).

    On uniform times the grid steps are 1/16 of 2 pi / span, so S is a zero-padded FFT of
    length ~16 T (O(T log T) per record instead of O(T^2)); otherwise a matrix product."""
    n = len(tc)
    dt = np.diff(tc)
    dw = grid[1] - grid[0] if len(grid) > 1 else 0.0
    N = int(round(2 * np.pi / (dw * dt[0]))) if dw > 0 else 0
    if len(grid) > 1 and np.allclose(dt, dt[0], rtol=1e-9) and np.isclose(dw * dt[0] * N, 2 * np.pi) \
            and N >= n and h * (len(grid) - 1) < N:
        x = C * np.exp(1j * h * grid[0] * dt[0] * np.arange(n))[None, :]
        S = N * np.fft.ifft(x, N, axis=1)[:, :h * len(grid):h]
        return (S * np.exp(1j * h * grid[None, :] * tc[0])).T     # tc[0] = -(the centre)
    out = np.empty((len(grid), len(C)), complex)
    for a in range(0, len(grid), 512):
        out[a:a + 512] = np.exp(1j * h * grid[a:a + 512, None] * tc[None, :]) @ C.T
    return out


def _rss_scan(tc, C, grid, offset):
    """Residual sum of squares (G, R) of the projected fit of each record C (R, T) at every
    w of `grid` (G,), through the normal equations: the Gram matrix of the basis depends on
    w only (its columns have modulus 1: sums of e^{iwt} and e^{2iwt}), the right-hand side
    is sum e^{+-iwt} c (and sum c)."""
    ones = np.ones((1, len(tc)))
    s1 = _grid_sums(tc, ones, grid)[:, 0]
    s2 = _grid_sums(tc, ones, grid, h=2)[:, 0]
    Ginv = np.linalg.inv(_gram(s1, s2, len(tc), offset))               # one per w, for all records
    b = [_grid_sums(tc, C, grid), np.conj(_grid_sums(tc, np.conj(C), grid))]
    if offset:
        b.append(np.broadcast_to(C.sum(axis=1), (len(grid), len(C))))
    bb = np.stack(b, axis=-1)
    explained = np.einsum("gri,gij,grj->gr", np.conj(bb), Ginv, bb, optimize=True).real
    return np.sum(np.abs(C) ** 2, axis=1)[None, :] - explained


def _rss_at(tc, C, w, offset):
    """Residual sum of squares (R,) of each record C (R, T) at its own w (R,)."""
    ep = np.exp(1j * w[:, None] * tc[None, :])
    G = _gram(ep.sum(axis=1), (ep ** 2).sum(axis=1), len(tc), offset)
    b = [np.sum(ep * C, axis=1), np.sum(np.conj(ep) * C, axis=1)] + ([C.sum(axis=1)] if offset else [])
    return np.sum(np.abs(C) ** 2, axis=1) - _explained(G, np.stack(b, axis=-1))


def amplitudes(tc, C, w, offset):
    """Least-squares A (R, m) and residuals (R, T) of each record C (R, T) at its w (R,)."""
    E = basis(tc, w, offset)
    G = np.einsum("rti,rtj->rij", np.conj(E), E)
    b = np.einsum("rti,rt->ri", np.conj(E), C)
    A = np.linalg.solve(G + 1e-12 * len(tc) * np.eye(E.shape[-1]), b[..., None])[..., 0]
    return A, C - np.einsum("rti,ri->rt", E, A)


def frequency_grid(times_ps) -> np.ndarray:
    """The scan's w: a quarter period in the record up to Nyquist, steps pi / (8 span)."""
    t = np.asarray(times_ps, float)
    span = t[-1] - t[0]
    dt = np.median(np.diff(t))
    return np.arange(np.pi / (2 * span), np.pi / dt, np.pi / (8 * span))


def fitted(times_ps, w) -> np.ndarray:
    """Which frequencies w are a fit, not a drift: above a quarter period in the record and
    off the scan's lowest step (a minimum at the bound is a slow drift, not an oscillation)."""
    grid = frequency_grid(times_ps)
    return np.asarray(w) > grid[0] + 0.5 * (grid[1] - grid[0])


def line_power(times_ps, C, w, offset: bool) -> np.ndarray:
    """The fraction (R,) of each record's variance (about its mean with `offset`) that the
    fitted oscillation at its w explains: the height of the peak the scan found."""
    t = np.asarray(times_ps, float)
    C = np.atleast_2d(np.asarray(C, complex))
    total = np.sum(np.abs(C - (C.mean(axis=1, keepdims=True) if offset else 0.0)) ** 2, axis=1)
    return 1.0 - _rss_at(t - t.mean(), C, np.asarray(w, float), offset) / total


def fit_frequencies(times_ps, C, offset: bool) -> tuple[np.ndarray, np.ndarray]:
    """Estimator 1 on each record C (R, T): w (R,) [rad/ps] and A (R, m), times centred (the
    centring decorrelates the frequency from the phase)."""
    t = np.asarray(times_ps, float)
    C = np.atleast_2d(np.asarray(C, complex))
    grid = frequency_grid(t)
    tc = t - t.mean()
    # the scan holds (frequencies x records) numbers: records in chunks keep it to
    # SCAN_BUDGET (~100 MB) whatever the record length (a 5-ns record of 0.5-ps frames has
    # ~80000 frequencies)
    chunk = max(1, SCAN_BUDGET // len(grid))
    j = np.concatenate([np.argmin(_rss_scan(tc, C[a:a + chunk], grid, offset), axis=0)
                        for a in range(0, len(C), chunk)])
    lo, hi = grid[np.maximum(j - 1, 0)], grid[np.minimum(j + 1, len(grid) - 1)]
    g = (math.sqrt(5.0) - 1.0) / 2.0
    x1, x2 = hi - g * (hi - lo), lo + g * (hi - lo)
    f1, f2 = _rss_at(tc, C, x1, offset), _rss_at(tc, C, x2, offset)
    for _ in range(GOLDEN_STEPS):
        left = f1 < f2                      # the minimum is in [lo, x2]
        hi = np.where(left, x2, hi)
        lo = np.where(left, lo, x1)
        xn = np.where(left, hi - g * (hi - lo), lo + g * (hi - lo))
        fn = _rss_at(tc, C, xn, offset)
        x2, f2, x1, f1 = (np.where(left, x1, xn), np.where(left, f1, fn),
                          np.where(left, xn, x2), np.where(left, fn, f2))
    w = np.where(f1 < f2, x1, x2)
    A, _ = amplitudes(tc, C, w, offset)
    return w, A


def jacobian(tc, w: float, A: np.ndarray) -> np.ndarray:
    """Complex columns (T, p) of d(model)/d(w, Re A_+, Im A_+, Re A_-, Im A_- [, Re B, Im B])."""
    E = basis(tc, w, len(A) == 3)
    cols = [-1j * tc * A[0] * E[:, 0] + 1j * tc * A[1] * E[:, 1]]
    for j in range(len(A)):
        cols += [E[:, j], 1j * E[:, j]]
    return np.stack(cols, axis=1)


def linear_covariance(times_ps, J: np.ndarray, rms_A: float, tau_ps: float) -> np.ndarray:
    """Covariance of the real parameters of a least-squares fit with complex columns J (T, p)
    under OU noise (mode_noise.py): (J^T J)^-1 J^T Sigma J (J^T J)^-1, real and imaginary
    parts independent."""
    H = np.linalg.pinv(J.real.T @ J.real + J.imag.T @ J.imag)
    M = J.real.T @ ou_apply(times_ps, tau_ps, J.real) + J.imag.T @ ou_apply(times_ps, tau_ps, J.imag)
    return rms_A ** 2 * H @ M @ H


def _refused(method, w, span, periods):
    nan = float("nan")
    return {"method": method, "speed_A_per_ps": nan, "speed_err_A_per_ps": nan, "omega_per_ps": nan,
            "omega_at_bound_per_ps": w, "periods_in_record": periods,
            "reason": f"the record ({span:.3g} ps) holds about a quarter period of the wave or less "
                      f"({periods:.2f} fitted): a drift, not an oscillation; run longer"}


def _noise_at(t, c, w, A, offset):
    """The fitted model at (w, A) and the REML noise of its residual (mode_noise.py)."""
    tc = t - t.mean()
    model = basis(tc, w, offset) @ A
    return model, fit_ou_noise(t, c - model, jacobian(tc, w, A))


def fit_with_replicates(times_ps, c, k_per_A, offset=False, n_boot=200, seed=0):
    """Estimator 1 with its error (module doc). Returns the result dict and the bootstrap
    records (n_boot, T) (None when there is no fit), so that a caller can run other fits on
    the same replicates (mode_error.py: the sub-record term)."""
    t = np.asarray(times_ps, float)
    c = np.asarray(c, complex)
    if len(t) < 8:
        raise InputError(f"wave-speed fit needs at least 8 frames, got {len(t)}")
    method = ("LS fit of forward+backward k-mode" + (" + static offset" if offset else "")
              + " (variable projection); error: parametric bootstrap with REML Ornstein-Uhlenbeck noise")
    tc = t - t.mean()
    span = float(t[-1] - t[0])
    w_arr, A_arr = fit_frequencies(t, c[None], offset)
    w, A = float(w_arr[0]), A_arr[0]
    periods = w * span / (2 * np.pi)
    if not fitted(t, w):
        return _refused(method, w, span, periods), None
    model, noise = _noise_at(t, c, w, A, offset)
    r = c - model
    J = jacobian(tc, w, A)
    cov = linear_covariance(t, J, noise["noise_rms_A"], noise["noise_tau_ps"])
    w_err_cov = float(math.sqrt(max(cov[0, 0], 0.0)))
    # |A_+| - |A_-| and its standard error (gradient wrt Re, Im of A_+ and A_-)
    g = np.zeros(J.shape[1])
    for j, sign in ((0, 1.0), (1, -1.0)):
        a = abs(A[j])
        if a > 0:
            g[1 + 2 * j], g[2 + 2 * j] = sign * A[j].real / a, sign * A[j].imag / a
    d_amp = float(abs(A[0]) - abs(A[1]))
    d_amp_err = float(math.sqrt(max(g @ cov @ g, 0.0)))
    standing = abs(d_amp) <= max(STANDING_SIGMA * d_amp_err, STANDING_REL * (abs(A[0]) + abs(A[1])))
    replicates = None
    w_err_boot, other, power_null_q = float("nan"), float("nan"), float("nan")
    if n_boot >= 2:
        rng = np.random.default_rng(seed)
        replicates = model[None, :] + draw_ou(rng, t, noise["noise_rms_A"], noise["noise_tau_ps"], n_boot)
        wb, _ = fit_frequencies(t, replicates, offset)
        # of the replicates that give a number (a drift at the scan's bound gives none, as in a
        # real run), those on the fitted peak -- within its first zero, 2 pi / span -- make the
        # error; the others found another peak and are counted, not averaged
        ok = fitted(t, wb)
        on = ok & (np.abs(wb - w) <= 2 * np.pi / span)
        other = float(1.0 - np.sum(on) / max(np.sum(ok), 1))
        w_err_boot = float(np.sqrt(np.mean((wb[on] - w) ** 2))) if np.sum(on) >= 2 else float("inf")
        # detection: what the noise alone (with the offset) gives this estimator as a mode
        null = basis(tc, w, offset)[:, 2:] @ A[2:] + draw_ou(rng, t, noise["noise_rms_A"],
                                                              noise["noise_tau_ps"], n_boot)
        wn, _ = fit_frequencies(t, null, offset)
        power_null = line_power(t, null, wn, offset)[fitted(t, wn)]
        power_null_q = float(np.quantile(power_null, DETECTION_QUANTILE)) if len(power_null) else 0.0
    w_err = w_err_boot if n_boot >= 2 else w_err_cov
    c_var = float(np.vdot(c - c.mean(), c - c.mean()).real)
    A_f, A_b = abs(A[0]), abs(A[1])
    out = {
        "method": method,
        "omega_per_ps": w, "omega_err_per_ps": w_err,
        "omega_err_cov_per_ps": w_err_cov, "omega_err_bootstrap_per_ps": w_err_boot,
        "n_boot": n_boot, "bootstrap_other_peak_fraction": other,
        "line_power": float(line_power(t, c, [w], offset)[0]), "noise_only_line_power": power_null_q,
        "speed_A_per_ps": w / k_per_A, "speed_err_A_per_ps": w_err / k_per_A,
        "amplitude_forward_A": float(A_f), "amplitude_backward_A": float(A_b),
        "amplitude_difference_A": d_amp, "amplitude_difference_err_A": d_amp_err,
        "wave_kind": "standing" if standing else "travelling",
        "direction": "forward" if A_f >= A_b else "backward",
        "r2": 1.0 - float(np.vdot(r, r).real) / c_var if c_var > 0 else float("nan"),
        "periods_in_record": periods, **noise,
    }
    if offset:
        out["offset_A"] = float(abs(A[2]))
    return out, replicates


def fit_wave_speed(times_ps, c, k_per_A, offset=False, n_boot=200, seed=0) -> dict:
    """Estimator 1 and its error (module doc); speed NaN with a reason when the record holds
    less than a quarter period."""
    return fit_with_replicates(times_ps, c, k_per_A, offset, n_boot, seed)[0]


def _slope(t, y):
    X = np.column_stack([np.ones_like(t), t - t.mean()])
    coef, res, *_ = np.linalg.lstsq(X, y, rcond=None)
    r = y - X @ coef
    se = np.sqrt(np.sum(r ** 2) / max(len(t) - 2, 1) / np.sum((t - t.mean()) ** 2))
    return float(coef[1]), float(se)


def phase_velocity(times_ps, c, k_per_A) -> dict:
    """Estimator 2: phase velocity (crest tracking) of the k-mode amplitude c(t)."""
    t = np.asarray(times_ps, float)
    c = np.asarray(c, complex)
    mag = np.abs(c)
    modulation = float((mag.max() - mag.min()) / (mag.max() + mag.min())) if mag.max() > 0 else 1.0
    if modulation < 0.3:
        how, z, sel = "phase of c(t)", c, slice(None)
    else:
        dts = np.diff(t)
        if not np.allclose(dts, dts[0], rtol=1e-6):
            return {"method": "phase velocity", "speed_A_per_ps": float("nan"),
                    "reason": "standing/mixed wave on non-uniform times: cannot split by frequency"}
        C = np.fft.fft(c)
        nu = np.fft.fftfreq(len(t), 1.0)
        fwd, bwd = np.where(nu < 0, C, 0), np.where(nu > 0, C, 0)
        pf, pb = np.sum(np.abs(fwd) ** 2), np.sum(np.abs(bwd) ** 2)
        how = "phase of the stronger frequency-signed part of c(t)"
        z = np.fft.ifft(fwd if pf >= pb else bwd)
        n = len(t)
        sel = slice(n // 10, n - n // 10)  # drop the FFT's edge effects
    phase = np.unwrap(np.angle(z[sel]))
    slope, se = _slope(t[sel], phase)
    periods = abs(slope) * (t[-1] - t[0]) / (2 * np.pi)
    out = {"method": f"phase velocity ({how})", "modulation": modulation,
           "omega_per_ps": abs(slope), "speed_A_per_ps": abs(slope) / k_per_A,
           "speed_err_A_per_ps": se / k_per_A, "periods_in_record": periods,
           "direction": "forward" if slope < 0 else "backward", "reliable": True}
    if modulation >= 0.3 and periods < 1.5:
        # the frequency split of a standing wave needs a few periods in the record
        out["reliable"] = False
        out["reason"] = f"standing/mixed wave with only {periods:.2f} periods in the record"
    return out
