"""Wave speed from the space-time Fourier content of u(s, t).

Estimator 1 (the reported value): nonlinear least squares on the k = 2 pi / L mode.
With c(t) = (2/n) sum_i u(s_i, t) exp(-i k s_i) the complex amplitude of that mode,

    u = a_+ cos(k s - w t + p_+) + a_- cos(k s + w t + p_-)
    <=>  c(t) = A_+ exp(-i w t) + A_- exp(+i w t),   A_pm = a_pm exp(i p_pm),

which is exactly the least-squares fit of the travelling-wave model to u(s, t) restricted
to that mode (Parseval). The model is linear in A_pm for a given w, so w is found by
variable projection: a global scan of the residual over w (from a quarter period in the
record up to the Nyquist frequency), a bounded 1-D refinement, then a full Levenberg-
Marquardt step on (w, A_+, A_-) whose Jacobian gives the covariance. Uncertainty: the
larger of the covariance standard error and a moving-block residual bootstrap (block
length from the residual autocorrelation, so correlated thermal noise in MD is not
treated as white). Speed = w / k; forward if |A_+| > |A_-|.

Estimator 2 (the cross-check): the phase velocity of c(t). For a predominantly travelling
wave, arg c(t) = p - w t, so the unwrapped phase falls linearly and the crest of the
mode moves at w / k (crest tracking of the k-mode). When |c(t)| is strongly modulated
(a standing or mixed wave), the forward and backward parts are first separated by their
sign of frequency (FFT in time) and the phase of the stronger one is used.
Neither estimator looks at the other's result.
"""
from __future__ import annotations

import numpy as np
from scipy.optimize import least_squares, minimize_scalar

from dna_models.errors import InputError
from mdbridge.stats import circular_block_indices, e_folding_lag


def mode_amplitude(u: np.ndarray, mode: int = 1) -> np.ndarray:
    """c(t) of Fourier mode `mode` of u (T, n) sampled at s_i = i L / n (see module doc)."""
    u = np.asarray(u, float)
    return 2.0 / u.shape[1] * np.fft.fft(u, axis=1)[:, mode]


def _basis(t, w, offset):
    cols = [np.exp(-1j * w * t), np.exp(1j * w * t)]
    if offset:
        cols.append(np.ones_like(t, dtype=complex))
    return np.stack(cols, axis=1)


def _project(t, c, w, offset):
    E = _basis(t, w, offset)
    A = np.linalg.lstsq(E, c, rcond=None)[0]
    r = c - E @ A
    return A, r, float(np.vdot(r, r).real)


def _rss_scan(t, c, grid, offset, chunk=1024):
    """Residual sum of squares of the projected fit at every w of `grid`, vectorised
    through the normal equations (the basis functions have modulus 1, so the Gram
    matrix needs only sums of exp(+-i w t) and exp(2 i w t))."""
    out = np.empty(len(grid))
    cc = float(np.vdot(c, c).real)
    n = len(t)
    for a in range(0, len(grid), chunk):
        w = grid[a:a + chunk, None]
        ep = np.exp(1j * w * t[None, :])          # conj(f1) = e^{iwt}, f2 = e^{iwt}
        m = 3 if offset else 2
        G = np.zeros((len(w), m, m), complex)
        G[:, 0, 0] = G[:, 1, 1] = n
        G[:, 0, 1] = np.sum(ep ** 2, axis=1)      # sum conj(f1) f2
        G[:, 1, 0] = np.conj(G[:, 0, 1])
        b = np.zeros((len(w), m), complex)
        b[:, 0] = ep @ c
        b[:, 1] = np.conj(ep) @ c
        if offset:
            G[:, 2, 2] = n
            G[:, 0, 2] = np.sum(ep, axis=1)
            G[:, 2, 0] = np.conj(G[:, 0, 2])
            G[:, 1, 2] = np.conj(G[:, 0, 2])
            G[:, 2, 1] = G[:, 0, 2]
            b[:, 2] = np.sum(c)
        # where the basis degenerates (w at the Nyquist frequency, where e^{-iwt} = e^{iwt}
        # on the samples) a tiny ridge keeps the solve finite; the residual there is large
        G += 1e-12 * n * np.eye(m)
        x = np.linalg.solve(G, b[..., None])[..., 0]
        out[a:a + chunk] = cc - np.einsum("gi,gi->g", np.conj(b), x).real
    return out


def fit_wave_speed(times_ps, c, k_per_A, offset=False, n_boot=200, seed=0) -> dict:
    """Estimator 1: nonlinear LS of c(t) = A_+ e^{-iwt} + A_- e^{iwt} (+ B if offset)."""
    t = np.asarray(times_ps, float)
    c = np.asarray(c, complex)
    if len(t) < 8:
        raise InputError(f"wave-speed fit needs at least 8 frames, got {len(t)}")
    tc = t - t.mean()  # centred time: decorrelates frequency from phase
    span = t[-1] - t[0]
    dt = np.median(np.diff(t))
    w_min, w_max = np.pi / (2 * span), np.pi / dt
    dw = np.pi / (8 * span)
    grid = np.arange(w_min, w_max, dw)
    rss = _rss_scan(tc, c, grid, offset)
    j = int(np.argmin(rss))
    lo, hi = grid[max(j - 1, 0)], grid[min(j + 1, len(grid) - 1)]
    w1 = minimize_scalar(lambda w: _project(tc, c, w, offset)[2], bounds=(lo, hi), method="bounded",
                         options={"xatol": 1e-12 * w_max}).x
    A1, _, _ = _project(tc, c, w1, offset)

    def resid(p):
        w, A = p[0], p[1::2] + 1j * p[2::2]
        r = c - _basis(tc, w, offset) @ A
        return np.concatenate([r.real, r.imag])

    p0 = np.concatenate([[w1], np.column_stack([A1.real, A1.imag]).ravel()])
    sol = least_squares(resid, p0, method="lm", xtol=1e-14, ftol=1e-14)
    w = float(sol.x[0])
    A = sol.x[1::2] + 1j * sol.x[2::2]
    r = c - _basis(tc, w, offset) @ A
    dof = max(2 * len(t) - len(p0), 1)
    s2 = float(np.sum(sol.fun ** 2)) / dof
    try:
        cov = np.linalg.inv(sol.jac.T @ sol.jac) * s2
        w_err_cov = float(np.sqrt(max(cov[0, 0], 0.0)))
    except np.linalg.LinAlgError:
        w_err_cov = np.inf

    # moving-block residual bootstrap (circular blocks)
    rng = np.random.default_rng(seed)
    b = e_folding_lag(r)
    fitted = c - r
    n = len(t)
    half = max(3 * dw, 10 * w_err_cov if np.isfinite(w_err_cov) else 3 * dw)
    boot = []
    for _ in range(n_boot):
        idx = circular_block_indices(n, b, rng)
        cb = fitted + r[idx]
        local = np.linspace(max(w - half, w_min / 2), w + half, 41)
        rl = _rss_scan(tc, cb, local, offset)
        j = int(np.argmin(rl))
        wb = minimize_scalar(lambda x: _rss_scan(tc, cb, np.array([x]), offset)[0],
                             bounds=(local[max(j - 1, 0)], local[min(j + 1, 40)]), method="bounded",
                             options={"xatol": 1e-10 * w_max}).x
        boot.append(wb)
    w_err_boot = float(np.std(boot, ddof=1)) if n_boot > 1 else 0.0
    w_err = max(w_err_cov, w_err_boot)
    A_f, A_b = abs(A[0]), abs(A[1])
    c_var = float(np.vdot(c - c.mean(), c - c.mean()).real)
    periods = float(w * span / (2 * np.pi))
    if periods < 0.25:
        # a record this short cannot tell a frequency from a slow drift: no speed, say why
        nan = float("nan")
        return {"method": "NLS fit of forward+backward k-mode (variable projection + LM)",
                "speed_A_per_ps": nan, "speed_err_A_per_ps": nan, "omega_per_ps": nan,
                "omega_at_bound_per_ps": w, "periods_in_record": periods,
                "reason": f"the record ({span:.3g} ps) holds less than a quarter period of the wave; "
                          "run longer"}
    return {
        "method": "NLS fit of forward+backward k-mode (variable projection + LM)",
        "omega_per_ps": w, "omega_err_per_ps": w_err,
        "omega_err_cov_per_ps": w_err_cov, "omega_err_bootstrap_per_ps": w_err_boot,
        "bootstrap_block": b, "n_boot": n_boot,
        "speed_A_per_ps": w / k_per_A, "speed_err_A_per_ps": w_err / k_per_A,
        "amplitude_forward_A": float(A_f), "amplitude_backward_A": float(A_b),
        "direction": "forward" if A_f >= A_b else "backward",
        "r2": 1.0 - float(np.vdot(r, r).real) / c_var if c_var > 0 else float("nan"),
        "periods_in_record": float(w * span / (2 * np.pi)),
    }


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
