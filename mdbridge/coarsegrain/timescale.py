"""Compliance by timescale: what stiffness the duplex shows to motions of a given duration
(docs/coarse-graining.md, "Compliance by timescale").

A static coarse-graining inverts the covariance of the whole record: the relaxed stiffness,
every slow episode included. A wave of period P feels only the motions faster than about P.
Two views of the same equilibrium correlation functions, both in kT units (a compliance is
a covariance of step parameters; K = compliance^-1, as `average.stiffness`):

* The creep compliance J(u) = <(x(t + u) - x(t)) (x(t + u) - x(t))^T> / (2 kT)
  = C(0) - (C(u) + C(u)^T) / 2 (the mean-square displacement over 2 kT), rising from 0 to
  the relaxed compliance C(0).
* K(W): the covariance within windows of W = n frames, each about its own mean (divisor n),
  averaged over the record's n_w = T // n disjoint windows. Exactly (stationarity only),

      K(W)^-1 = C(0) - var(window mean) = (2 / n^2) sum_{k=1}^{n-1} (n - k) J(k dt)
              -> (2 / W^2) int_0^W (W - u) J(u) du,

  a triangle-weighted average of J over lags below W (`triangle_average`), not J(W): a
  process of correlation time tau keeps 1 - 2 tau / W of its compliance, a slow one of time
  tau_s >> W adds W / (3 tau_s) of its own (exponential), or (W / sigma)^2 / 24 (a smooth
  episode of correlation exp(-u^2 / 4 sigma^2)). Errors: moving-block bootstrap over the
  windows (blocks of consecutive windows spanning their own correlation); the record
  (W = T) by the moving-block bootstrap over frames. Per step and for the q -> 0 collective
  coordinates of qstiffness.py (the same fit modes and intercept weights, so K(W = record)
  is `average.stiffness`).
* The dynamic compliance, by fluctuation-dissipation (the response to a force is
  chi(t) = -dC/dt / kT for t > 0):

      J*(omega) = [C(0) - i omega C^(omega)] / kT,   C^(omega) = int_0^inf C(t) e^{-i omega t} dt,

  J* = J' - i J'' (storage, loss); a relaxation of compliance J and time tau gives the Debye
  J / (1 + i omega tau): the motions faster than 1 / omega count in full, the slower ones
  as J / (omega tau)^2. C^ is the trapezoid lag sum to a maximum lag with a cosine taper
  over its second half; J* is then the mean over t of the products g(t) x(t)^T with
  g(t) = x(t) - i omega sum_k h_k x(t + k), so its error is the same moving-block bootstrap
  over frames as the static estimator's.
"""
from __future__ import annotations

import math

import numpy as np

from dna_models.errors import InputError
from mdbridge.stats import block_length, block_starts, block_sums, integrated_time, spread

from .qstiffness import features, fit_modes, half_modes, helical_turns, intercept_weights, usable_modes

P = 6
TWIST = 5
MIN_WINDOWS = 8            # a bootstrap over windows needs at least this many
WINDOW_GRID_PS = (2.0, 5.0, 10.0, 20.0, 50.0, 100.0, 200.0, 500.0, 1000.0, 2000.0, 5000.0, 10000.0)
DEFAULT_WINDOW_PS = 50.0   # the unrelaxed stiffness when --window-ps is not given (docs)


def frame_time_ps(times_ps, source: str = "trajectory") -> float:
    """The frame spacing (ps) of times_ps (T,), which must be uniform to 1 %."""
    t = np.asarray(times_ps, dtype=float)
    if len(t) < 2:
        raise InputError(f"{source}: {len(t)} frame(s): compliance by timescale needs a time series")
    dt = np.diff(t)
    d = float(np.median(dt))
    if not d > 0 or np.max(np.abs(dt - d)) > 0.01 * d:
        raise InputError(f"{source}: the frame times are not evenly spaced (spacings {dt.min():g} to "
                         f"{dt.max():g} ps): compliance by timescale needs one frame spacing (allowed: "
                         "trajectories written at one interval, without gaps or overlaps)")
    return d


def triangle_average(J_lags: np.ndarray, n: int) -> np.ndarray:
    """(2 / n^2) sum_{k=1}^{n-1} (n - k) J[k]: the within-window compliance of windows of n
    frames from the creep compliance at lags 0.. (J_lags (>= n, ...), J[0] = 0)."""
    k = np.arange(1, n)
    w = 2.0 * (n - k) / float(n * n)
    return np.tensordot(w, np.asarray(J_lags)[1:n], axes=(0, 0))


def triangle_average_continuous(J_of_u, W: float, points: int = 4001) -> float:
    """(2 / W^2) int_0^W (W - u) J(u) du for a function J (Simpson on `points` nodes)."""
    from scipy.integrate import simpson
    u = np.linspace(0.0, W, points)
    return float(simpson(2.0 * (W - u) * J_of_u(u) / W ** 2, x=u))


# -- the coordinates: per step, and the q -> 0 collective ones ---------------------------
class Coordinates:
    """The real series whose within-window covariances give the compliances: the step
    parameters (T, n_steps, 6) of the kept steps, and the 12 real parts of the Fourier
    amplitudes of the q -> 0 fit modes (T, K, 12), with the intercept weights that turn
    their Re S(q_k) into S(0) (qstiffness.py). leave_out: a body-frame wavenumber k taken
    out of the fit and the intercept refitted (the rule's guard against a mode's own
    resonance in its stiffness, docs/coarse-graining.md, "Compliance by timescale")."""

    def __init__(self, q_steps: np.ndarray, keep: np.ndarray, closed: bool, leave_out: int | None = None):
        q = np.asarray(q_steps, dtype=float)
        self.T, n, _ = q.shape
        self.keep = np.asarray(keep, dtype=bool)
        self.n_kept = int(self.keep.sum())
        self.x_steps = q[:, self.keep]
        turns = helical_turns(q[:, :, TWIST].mean(axis=0)) if closed else None
        k_all = half_modes(n)
        fit = fit_modes(n, closed, turns)
        idx = np.flatnonzero(fit)
        if leave_out is not None:
            idx = idx[k_all[idx] != int(leave_out)]
        if len(idx) == 0:
            idx = np.flatnonzero(usable_modes(n, closed, turns) & (k_all != (leave_out if leave_out is not None
                                                                              else -1)))[:1]
        w = intercept_weights(2 * np.pi * k_all[idx] / n, 1)
        self.weights = np.ones(1) if w is None else w
        self.modes = k_all[idx]
        self.y = features(q, self.keep)[:, idx]                     # (T, K, 12)

    def q0_products(self, u: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Per frame, the q -> 0 compliance's products (T, 6, 6): sum_k w_k (u_a v_a^T + u_b v_b^T)
        / n_kept of two series of the fit modes' real parts (T, K, 12) (u may be complex); their
        mean over frames is q0_compliance of the covariance, without the K 12 x 12 blocks."""
        p = np.einsum("tki,tkj->tkij", u[..., :P], v[..., :P]) + np.einsum("tki,tkj->tkij", u[..., P:], v[..., P:])
        return np.einsum("k,tkij->tij", self.weights, p) / float(self.n_kept)

    def q0_compliance(self, cov12: np.ndarray) -> np.ndarray:
        """S(0) (..., 6, 6) from covariances (..., K, 12, 12) of the fit modes' real parts:
        the fit's intercept of Re S(q_k) = (cov_aa + cov_bb) / n_kept."""
        re = (cov12[..., :P, :P] + cov12[..., P:, P:]) / float(self.n_kept)
        S0 = np.tensordot(re, self.weights, axes=([-3], [0]))       # (..., 6, 6, ) after moving
        return 0.5 * (S0 + np.swapaxes(S0, -1, -2))


def _window_cov(x: np.ndarray, n: int) -> np.ndarray:
    """(n_w, ..., p, p) covariance of x (T, ..., p) within each of the T // n disjoint
    windows of n frames, about the window's own mean, divisor n."""
    n_w = x.shape[0] // n
    xw = x[:n_w * n].reshape((n_w, n) + x.shape[1:])
    d = xw - xw.mean(axis=1, keepdims=True)
    return np.einsum("wt...i,wt...j->w...ij", d, d) / float(n)


def _second_moment_time(x: np.ndarray, n: int) -> np.ndarray:
    """tau_2 (frames) of the standardised squared within-window deviations of x (T, ..., p),
    per series (...): the degrees of freedom of a within-window covariance."""
    n_w = x.shape[0] // n
    xw = x[:n_w * n].reshape((n_w, n) + x.shape[1:])
    d = (xw - xw.mean(axis=1, keepdims=True)).reshape((n_w * n,) + x.shape[1:])
    sd = d.std(axis=0)
    z = np.where(sd > 0, d / np.where(sd > 0, sd, 1.0), 0.0)
    return np.minimum(integrated_time((z * z).sum(axis=-1)), 0.5 * n)


def _boot_mean(series: np.ndarray, n_boot: int, rng: np.random.Generator, b: int) -> np.ndarray:
    """(n_boot, ...) moving-block bootstrap replicates of the mean of series (N, ...)."""
    N = series.shape[0]
    flat = series.reshape(N, -1)
    st = block_starts(N, b, n_boot, rng)
    return (block_sums(flat, st, b) / float(N)).reshape((n_boot,) + series.shape[1:])


def _inv(S):
    K = np.linalg.inv(S)
    return 0.5 * (K + np.swapaxes(K, -1, -2))


def window_compliance(coords: Coordinates, n: int, n_boot: int, rng: np.random.Generator) -> dict:
    """K(W) for windows of n frames: the within-window compliance per step (n_kept, 6, 6) and of
    the q -> 0 coordinates (6, 6), their stiffness, bootstrap errors over windows, and the
    effective samples of the pooled within-window covariance (N_eff, the 50-sample rule)."""
    T = coords.T
    n_w = T // n
    if n_w < MIN_WINDOWS:
        raise InputError(f"windows of {n} frames: the record's {T} frames hold {n_w}, fewer than "
                         f"{MIN_WINDOWS} (the bootstrap over windows needs them)")
    cs = _window_cov(coords.x_steps, n)                          # (n_w, n_kept, 6, 6)
    cq = coords.q0_compliance(_window_cov(coords.y, n))          # (n_w, 6, 6)
    # block length over windows: the windows' compliances are correlated by episodes longer
    # than a window
    tr = np.concatenate([np.trace(cq, axis1=-2, axis2=-1)[:, None],
                         np.diagonal(cq, axis1=-2, axis2=-1)], axis=1)
    b = block_length(float(np.max(integrated_time(tr))), n_w)
    bq = _boot_mean(cq, n_boot, rng, b)
    bs = _boot_mean(cs.mean(axis=1), n_boot, rng, b)            # the sequence-averaged per-step compliance
    tau_steps = float(np.median(_second_moment_time(coords.x_steps, n)))
    tau_q0 = float(np.max(_second_moment_time(coords.y, n)))
    n_eff = n_w * n / (2.0 * max(tau_steps, tau_q0))
    Sq = cq.mean(axis=0)
    Jq, Jq_err = creep_q0(coords, n, n_boot, rng)
    return {"frames": n, "windows": n_w, "block_windows": b, "creep_q0": Jq, "creep_q0_err": Jq_err,
            "compliance_q0": Sq, "compliance_q0_err": spread(bq),
            "stiffness_q0": _inv(Sq), "stiffness_q0_err": spread(_inv(bq)),
            "compliance_steps": cs.mean(axis=0), "compliance_step_average": cs.mean(axis=(0, 1)),
            "compliance_step_average_err": spread(bs),
            "tau2_frames": max(tau_steps, tau_q0), "effective_samples": n_eff}


def creep_q0(coords: Coordinates, lag: int, n_boot: int, rng: np.random.Generator):
    """J(lag dt) of the q -> 0 coordinates, (6, 6) kT units, and its moving-block bootstrap
    error over the frame pairs (blocks of 6 tau of the slowest fit-mode amplitude)."""
    d = coords.y[lag:] - coords.y[:-lag]
    prod = 0.5 * coords.q0_products(d, d)
    b = block_length(float(np.max(integrated_time(coords.y))), len(d))
    return _sym(prod.mean(axis=0)), spread(_sym(_boot_mean(prod, n_boot, rng, b)))


def _sym(S):
    return 0.5 * (S + np.swapaxes(S, -1, -2))


def record_compliance(coords: Coordinates, n_boot: int, rng: np.random.Generator) -> dict:
    """The whole record as one window (W = T, divisor T): the relaxed compliance, with the
    moving-block bootstrap over frames (blocks of 6 tau of the slowest fit-mode amplitude)."""
    T = coords.T
    d = coords.y - coords.y.mean(axis=0)
    prod = coords.q0_products(d, d)
    tau = float(np.max(integrated_time(coords.y)))
    b = block_length(tau, T)
    Sq = _sym(prod.mean(axis=0))
    bq = _sym(_boot_mean(prod, n_boot, rng, b))
    ds = coords.x_steps - coords.x_steps.mean(axis=0)
    cs = np.einsum("tsi,tsj->sij", ds, ds) / float(T)
    return {"frames": T, "windows": 1, "block_frames": b, "compliance_q0": Sq, "compliance_q0_err": spread(bq),
            "stiffness_q0": _inv(Sq), "stiffness_q0_err": spread(_inv(bq)),
            "compliance_steps": cs, "compliance_step_average": cs.mean(axis=0),
            "tau_frames": tau, "effective_samples": T / (2.0 * tau)}


def window_frames(window_ps: float, dt_ps: float, T: int, source: str = "trajectory") -> int:
    """Frames per window of window_ps: round(W / dt), at least 2 and leaving MIN_WINDOWS."""
    n = int(round(float(window_ps) / dt_ps))
    if not (math.isfinite(window_ps) and window_ps > 0) or n < 2:
        raise InputError(f"{source}: window {window_ps:g} ps: allowed at least two frames "
                         f"({2 * dt_ps:g} ps at this trajectory's frame spacing {dt_ps:g} ps)")
    if T // n < MIN_WINDOWS:
        raise InputError(f"{source}: window {window_ps:g} ps = {n} frames: the record's {T} frames "
                         f"({T * dt_ps:g} ps) hold {T // n} windows, fewer than {MIN_WINDOWS}: allowed up to "
                         f"{T // MIN_WINDOWS * dt_ps:g} ps")
    return n


def compliance_by_window(q_steps, keep, closed: bool, dt_ps: float, windows_ps=None, n_boot: int = 200,
                         seed: int = 0, source: str = "trajectory") -> dict:
    """K(W) for each W of windows_ps (default: WINDOW_GRID_PS up to the record / MIN_WINDOWS),
    then the record itself. Returns {"window_ps": [...], "entries": [window_compliance dicts],
    "record": record_compliance dict, "dt_ps": dt_ps}."""
    coords = Coordinates(q_steps, keep, closed)
    T = coords.T
    if windows_ps is None:
        windows_ps = [w for w in WINDOW_GRID_PS if w >= 2 * dt_ps and T // int(round(w / dt_ps)) >= MIN_WINDOWS]
    rng = np.random.default_rng(seed)
    W = sorted(float(w) for w in windows_ps)
    entries = [window_compliance(coords, window_frames(w, dt_ps, T, source), n_boot, rng) for w in W]
    return {"window_ps": W, "entries": entries, "record": record_compliance(coords, n_boot, rng),
            "dt_ps": dt_ps, "record_ps": T * dt_ps, "fit_modes": coords.modes}


# -- creep and dynamic compliance --------------------------------------------------------
def lag_covariance(x: np.ndarray, max_lag: int) -> np.ndarray:
    """C(k) = <x(t + k) x(t)^T> (k = 0..max_lag, ..., p, p) of the real series x (T, ..., p)
    about its mean, each lag averaged over its T - k pairs (FFT, zero-padded)."""
    x = np.asarray(x, dtype=float)
    T = x.shape[0]
    d = x - x.mean(axis=0)
    L = 1 << int(np.ceil(np.log2(2 * T)))
    f = np.fft.rfft(d, n=L, axis=0)
    c = np.fft.irfft(f[..., :, None] * np.conj(f[..., None, :]), n=L, axis=0)[:max_lag + 1]
    return c / (T - np.arange(max_lag + 1)).reshape((-1,) + (1,) * (c.ndim - 1))


def creep_compliance(x: np.ndarray, max_lag: int) -> np.ndarray:
    """J(k dt) = C(0) - (C(k) + C(k)^T) / 2 (kT units), k = 0..max_lag, of x (T, ..., p)."""
    C = lag_covariance(x, max_lag)
    return C[0][None] - 0.5 * (C + np.swapaxes(C, -1, -2))


def lag_kernel(dt_ps: float, omega_per_ps: float, max_lag: int) -> np.ndarray:
    """h_k (k = 0..max_lag) with C^(omega) = sum_k h_k C(k): trapezoid (h_0 halved), a cosine
    taper over the second half of the lags, e^{-i omega k dt} dt."""
    k = np.arange(max_lag + 1)
    w = np.ones(max_lag + 1)
    half = max_lag // 2
    if max_lag > 1:
        s = (k[half:] - half) / float(max(max_lag - half, 1))
        w[half:] = 0.5 * (1.0 + np.cos(np.pi * s))
    w[0] = 0.5
    return dt_ps * w * np.exp(-1j * omega_per_ps * dt_ps * k)


def _filtered(x: np.ndarray, h: np.ndarray, omega: float) -> np.ndarray:
    """g(t) = x(t) - i omega sum_k h_k x(t + k), t = 0..T - 1 - max_lag, for x (T, F)."""
    from scipy.signal import fftconvolve
    M = len(h) - 1
    y = fftconvolve(x, h[::-1][:, None], mode="valid", axes=0)
    return x[:x.shape[0] - M] - 1j * omega * y


def dynamic_compliance_products(x: np.ndarray, dt_ps: float, omega_per_ps: float, max_lag: int) -> np.ndarray:
    """(T - max_lag, F, F) complex products g(t) x(t)^T of x (T, F) about its mean, whose mean
    over t is J*(omega) (kT units) before symmetrisation."""
    d = np.asarray(x, dtype=float)
    d = d - d.mean(axis=0)
    g = _filtered(d, lag_kernel(dt_ps, omega_per_ps, max_lag), omega_per_ps)
    return g[:, :, None] * d[:len(g), None, :]


def dynamic_compliance(x: np.ndarray, dt_ps: float, omegas_per_ps, max_lag: int, n_boot: int = 200,
                       seed: int = 0, block: int | None = None) -> dict:
    """J*(omega) (n_omega, F, F) of the series x (T, F) (kT units: x's covariance is its
    compliance), symmetrised, with moving-block bootstrap errors of its real (storage) and
    imaginary (minus the loss) parts; K*(omega) = J*^-1 beside it."""
    x = np.asarray(x, dtype=float)
    T = x.shape[0]
    if not 1 <= max_lag < T // 2:
        raise InputError(f"maximum lag {max_lag} frames: allowed 1 to {T // 2 - 1} for {T} frames")
    b = block if block is not None else block_length(float(np.max(integrated_time(x))), T - max_lag)
    rng = np.random.default_rng(seed)
    Js, re_err, im_err = [], [], []
    for om in np.atleast_1d(omegas_per_ps):
        prod = dynamic_compliance_products(x, dt_ps, float(om), max_lag)
        prod = 0.5 * (prod + np.swapaxes(prod, -1, -2))
        J = prod.mean(axis=0)
        st = block_starts(len(prod), b, n_boot, rng)
        flat = np.concatenate([prod.real.reshape(len(prod), -1), prod.imag.reshape(len(prod), -1)], axis=1)
        bs = block_sums(flat, st, b) / float(len(prod))
        half = bs.shape[1] // 2
        Js.append(J)
        re_err.append(spread(bs[:, :half]).reshape(J.shape))
        im_err.append(spread(bs[:, half:]).reshape(J.shape))
    J = np.array(Js)
    return {"omega_per_ps": np.atleast_1d(np.asarray(omegas_per_ps, float)), "J": J,
            "J_storage_err": np.array(re_err), "J_loss_err": np.array(im_err),
            "K": np.linalg.inv(J), "block_frames": b, "max_lag_frames": max_lag}


def dynamic_compliance_q0(coords: Coordinates, dt_ps: float, omegas_per_ps, max_lag: int, n_boot: int = 200,
                          seed: int = 0) -> dict:
    """J*(omega) (6, 6) of the q -> 0 collective coordinates: the fit modes' 12 x 12 blocks
    through the intercept (Coordinates.q0_compliance), with bootstrap errors."""
    T, K, _ = coords.y.shape
    y = coords.y.reshape(T, K * 12)
    if not 1 <= max_lag < T // 2:
        raise InputError(f"maximum lag {max_lag} frames: allowed 1 to {T // 2 - 1} for {T} frames")
    b = block_length(float(np.max(integrated_time(coords.y))), T - max_lag)
    rng = np.random.default_rng(seed)
    out, re_err, im_err, boot = [], [], [], []
    d = y - y.mean(axis=0)
    for om in np.atleast_1d(omegas_per_ps):
        g = _filtered(d, lag_kernel(dt_ps, float(om), max_lag), float(om)).reshape(-1, K, 12)
        J = _sym(coords.q0_products(g, d[:len(g)].reshape(-1, K, 12)))   # (T', 6, 6) complex
        st = block_starts(len(J), b, n_boot, rng)
        flat = np.concatenate([J.real.reshape(len(J), -1), J.imag.reshape(len(J), -1)], axis=1)
        bs = block_sums(flat, st, b) / float(len(J))
        out.append(J.mean(axis=0))
        re_err.append(spread(bs[:, :36]).reshape(6, 6))
        im_err.append(spread(bs[:, 36:]).reshape(6, 6))
        boot.append((bs[:, :36] + 1j * bs[:, 36:]).reshape(-1, 6, 6))
    J = np.array(out)
    return {"omega_per_ps": np.atleast_1d(np.asarray(omegas_per_ps, float)), "J": J,
            "J_storage_err": np.array(re_err), "J_loss_err": np.array(im_err),
            "J_boot": np.array(boot),      # (omegas, n_boot, 6, 6): each block-bootstrap replica's J*
            "K": np.linalg.inv(J), "block_frames": b, "max_lag_frames": max_lag}


# -- params.json ---------------------------------------------------------------------------
def _l(a):
    return np.asarray(a, dtype=float).tolist()


def params_section(q_steps, keep, closed: bool, times_ps, window_ps=None, min_effective: float = 50.0,
                   n_boot: int = 200, seed: int = 0, source: str = "trajectory") -> dict:
    """params.json's "unrelaxed" and "compliance_by_window" (docs/coarse-graining.md, "Compliance
    by timescale"), per step, kT units, in the order and units of "average"."stiffness".
    window_ps: the W given (--window-ps; the first is the unrelaxed one); None: the default
    DEFAULT_WINDOW_PS, and a record too short for it gives "unrelaxed": null with the reason
    instead of an error. A W whose windows are worth fewer than min_effective samples is
    refused (InputError) when given, reported null with the reason by default."""
    given = window_ps is not None and len(window_ps) > 0
    W_unrel = float(window_ps[0]) if given else DEFAULT_WINDOW_PS
    try:
        dt = frame_time_ps(times_ps, source)
        T = np.asarray(q_steps).shape[0]
        grid = [w for w in WINDOW_GRID_PS if w >= 2 * dt and T // int(round(w / dt)) >= MIN_WINDOWS]
        W = sorted(set(grid) | ({float(w) for w in window_ps} if given else set()))
        if not given and (T // max(2, int(round(W_unrel / dt))) < MIN_WINDOWS or W_unrel < 2 * dt):
            raise InputError(f"{source}: the record ({T} frames of {dt:g} ps) is too short for the default "
                             f"window {W_unrel:g} ps ({MIN_WINDOWS} windows needed)")
        W = sorted(set(W) | {W_unrel})
        r = compliance_by_window(q_steps, keep, closed, dt, W, n_boot, seed, source)
    except (InputError, np.linalg.LinAlgError) as err:
        # by default the section must never cost the static coarse-graining its result
        if given and isinstance(err, InputError):
            raise
        if given:
            raise InputError(f"{source}: a window compliance is singular ({err}): allowed windows hold "
                             "fluctuations in all six step parameters (a longer --window-ps)") from err
        return {"unrelaxed": None, "unrelaxed_reason": str(err), "compliance_by_window": None}
    entries = dict(zip(r["window_ps"], r["entries"]))
    e = entries[W_unrel]
    unrelaxed: dict | None = None
    reason = None
    if e["effective_samples"] < min_effective:
        n = e["frames"]
        need = math.ceil(min_effective * 2.0 * e["tau2_frames"] / n) * n
        reason = (f"{source}: windows of {W_unrel:g} ps ({n} frames): the {e['windows']} windows are worth "
                  f"{e['effective_samples']:.1f} independent samples of the within-window covariance, fewer than "
                  f"{min_effective:g}; about {need} frames ({need * dt:g} ps) are needed")
        if given:
            raise InputError(reason)
    else:
        unrelaxed = {"window_ps": W_unrel, "window_frames": e["frames"], "windows": e["windows"],
                     "stiffness": _l(e["stiffness_q0"]), "stiffness_err": _l(e["stiffness_q0_err"]),
                     "compliance": _l(e["compliance_q0"]), "compliance_err": _l(e["compliance_q0_err"]),
                     "creep_stiffness": _l(_inv(e["creep_q0"])),
                     "effective_samples": e["effective_samples"],
                     "definition": "K(W): the inverse of the q -> 0 coordinates' covariance within disjoint "
                                   "windows of W (each about its own mean), per step, kT units; creep_stiffness "
                                   "is J(W)^-1, the mean-square displacement at lag W over 2 kT, inverted"}
    entries_all = [entries[w] for w in r["window_ps"]] + [r["record"]]
    rec_ps = r["record_ps"]
    out: dict = {"unrelaxed": unrelaxed,
           "compliance_by_window": {
               "window_ps": list(r["window_ps"]) + [rec_ps], "frame_spacing_ps": dt,
               "compliance": [_l(x["compliance_q0"]) for x in entries_all],
               "compliance_err": [_l(x["compliance_q0_err"]) for x in entries_all],
               "stiffness": [_l(x["stiffness_q0"]) for x in entries_all],
               "stiffness_err": [_l(x["stiffness_q0_err"]) for x in entries_all],
               "creep_compliance": [_l(x["creep_q0"]) for x in r["entries"]] + [None],
               "compliance_step_average": [_l(x["compliance_step_average"]) for x in entries_all],
               "windows": [int(x["windows"]) for x in entries_all],
               "effective_samples": [float(x["effective_samples"]) for x in entries_all],
               "fit_modes": [int(k) for k in r["fit_modes"]],
               "definition": "per W: the q -> 0 coordinates' covariance within disjoint windows of W, about "
                             "each window's mean, averaged over the windows (compliance per step, kT units); "
                             "= (2 / W^2) int_0^W (W - u) J(u) du of the creep compliance J; the last entry is "
                             "the whole record (relaxed). Errors: moving-block bootstrap over windows (the "
                             "record: over frames). docs/coarse-graining.md, \"Compliance by timescale\""}}
    if reason is not None:
        out["unrelaxed_reason"] = reason
    return out
