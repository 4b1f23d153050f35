"""The mode table of `dnarod modes`: static variance, frequency and damping of every mode,
pooled over quadratures, transverse directions and realisations, with refusals
(docs/modes.md).

`ModeSeries` is one realisation's reduced result: the complex mode amplitudes against time
(mdbridge/analysis/modes.py) and, for MD, the open base-pair fraction. It is what
DIR/mode_series.npz holds (float32), so a run can be re-analysed without its trajectory.

`mode_table` fits each mode (mdbridge/analysis/spectrum.py) and refuses, with the reason,
a mode that
  * holds fewer than MIN_PERIODS periods in the record,
  * has no peak: the fit runs to its overdamped bound (gamma = omega), out of the band of
    the periodogram's peak, or its peak stands less than MIN_PEAK_TO_FLOOR above the floor,
  * has no resolved peak: the data at the fitted peak stand no higher above the level below
    it than noise reaches (unresolved_peak): a fit on an overdamped mode's flat spectrum,
  * is not stationary: the frequencies fitted to the two halves of the record differ by more
    than STATIONARY_Z of their combined error (tested when each half holds MIN_PERIODS).
    A line (an undamped mode, taken as a sinusoid: spectrum.line_fit) is not: its halves'
    errors are the noise's alone, while the frequency of an undamped mode of a real rod
    wanders (the other modes modulate it through the rod's nonlinearity: the cold thermal
    rod's halves differ by ~1e-5 of the frequency, tests/python/test_modes_cold_rod.py).
    With one record a slow drift of a line's frequency cannot be told from such a wander,
    so the halves' scatter |omega_1 - omega_2| / 2 (the error of the mean of two) enters a
    line's error in quadrature instead of refusing it.
  * holds no signal: its rms amplitude is below ROUND_OFF of the field's own scale (the
    rise for bend and stretch, the mean twist density for twist): a deterministic run (a
    kicked rod) leaves the modes it does not excite at round-off, where a fit means nothing.
A refused mode keeps its entry with null frequency and damping (and null variance when it
is not stationary: the static variance of a drifting record means nothing), and its regime
(regime_of): overdamped, with the relaxation time of its series
(mdbridge/analysis/relaxation.py), or unresolved.

Errors. The frequency's and damping's are the fit's (observed information; calibrated on
synthetic oscillators by bench/mode_spectrum_calibration.py). With two or more
realisations each is also fitted alone, and the pooled error is multiplied by the Birge
ratio sqrt(chi^2 / (R - 1)) of their scatter about the pooled value when that exceeds 1: the
between-seed scatter enters whenever it is larger than the fit's own error explains.

Two static variances. `variance` is <|c_n - <c_n>|^2> of the record: everything the mode's
amplitude does. `oscillator_variance` is the part that is the fitted oscillator's own (the
variance of its autocovariance, C(0), per real series, averaged over the series, times 2 for
Re and Im), without the white floor and the common background: for a mode that is a linear
rod's normal mode it is that mode's equipartition variance; its error is the observed
information's, like the frequency's. In the 158-bp MD the two differ by up to 10x at the
higher bend modes: slow, localised motion of a few base pairs that is not the rod's
(docs/dispersion.md, "The statics").
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass, field

import numpy as np

from dna_models.errors import InputError
from mdbridge.analysis.modes import AMPLITUDE_UNIT, KINDS, VARIANCE_UNIT
from mdbridge.analysis.spectrum import (band_indices, expected_periodogram, fit_oscillator, frequencies_per_ps,
                                        line_fit, periodogram, GAMMA_OVER_OMEGA_MAX, LINE_RESIDUAL,
                                        NOT_LINE_MIN_GAMMA_T)
from mdbridge.analysis.relaxation import relaxation_time
from mdbridge.stats import block_sem

MIN_PERIODS = 3.0
MIN_PEAK_TO_FLOOR = 2.0     # the oscillator's peak over what lies beneath it (floor + common background)
STATIONARY_Z = 3.0
ROUND_OFF = 1e-8           # rms amplitude / the field's own scale below which a mode holds no signal
BAND_OVER_PEAK = 3.0       # the fit's band: peak / 3 .. 3 x peak (_band)
MIN_MODES_FOR_BACKGROUND = 5   # a common background needs this many modes of a kind (common_background)
SMOOTH_FRACTION = 0.1      # log_smooth: +-10 % in frequency
BACKGROUND_QUANTILE = 0.25  # common_background: the lowest quarter of the modes at each frequency
SPIKE_FALSE = 0.01         # noise_peak: the chance that noise alone passes on a band
OFF_BRANCH_MIN = 2         # off_branch: lower modes above a mode's frequency that refuse it
NPZ_FORMAT = 1


@dataclass
class ModeSeries:
    """One realisation: times_ps (T,), n (n_max,), bend (T, n_max, 2), twist and stretch
    (T, n_max) complex amplitudes (modes.py), length_A, n_bp, helical_repeat, source,
    input kind ("rod", "md"), open_fraction (T,) or None, meta (JSON-able)."""
    times_ps: np.ndarray
    n: np.ndarray
    bend: np.ndarray
    twist: np.ndarray
    stretch: np.ndarray
    length_A: float
    n_bp: int
    helical_repeat: int
    source: str
    kind: str
    open_fraction: np.ndarray | None = None
    meta: dict = field(default_factory=dict)

    @classmethod
    def from_analysis(cls, results, kind: str, open_fraction=None, meta=None) -> "ModeSeries":
        r = results
        return cls(np.asarray(r.times_ps, float), np.asarray(r.n), r.bend, r.twist, r.stretch,
                   float(r.length_A), int(r.n_bp), int(r.helical_repeat), str(r.source), kind,
                   None if open_fraction is None else np.asarray(open_fraction, float), dict(meta or {}))

    @property
    def dt_ps(self) -> float:
        return float(np.median(np.diff(self.times_ps)))

    @property
    def k_per_A(self) -> np.ndarray:
        return 2 * np.pi * self.n / self.length_A

    def after(self, discard_ps: float, until_ps: float | None = None) -> "ModeSeries":
        """The frames from times_ps[0] + discard_ps on, up to times_ps[0] + until_ps if given
        (one window of every realisation: seeds compared at the same age)."""
        t = self.times_ps - self.times_ps[0]
        keep = t >= discard_ps - 1e-9
        if until_ps is not None:
            keep &= t <= until_ps + 1e-9
        return ModeSeries(self.times_ps[keep], self.n, self.bend[keep], self.twist[keep],
                          self.stretch[keep], self.length_A, self.n_bp, self.helical_repeat,
                          self.source, self.kind,
                          None if self.open_fraction is None else self.open_fraction[keep], dict(self.meta))

    def amplitudes(self, kind: str, i_mode: int) -> np.ndarray:
        """(T, directions) complex amplitudes of mode index i_mode (n = i_mode + 1)."""
        a = getattr(self, kind)[:, i_mode]
        return a if a.ndim == 2 else a[:, None]

    def real_series(self, kind: str, i_mode: int) -> np.ndarray:
        """The real series of one mode (M, T), each with its mean removed: Re and Im of each
        direction's c_n (the two quadratures)."""
        a = self.amplitudes(kind, i_mode)
        x = np.concatenate([a.real.T, a.imag.T], axis=0)
        return x - x.mean(axis=1, keepdims=True)


def save_npz(path, series: list[ModeSeries], extra: dict | None = None) -> None:
    """DIR/mode_series.npz: every realisation's amplitudes as float32 (real, imag last)."""
    arrays = {}
    heads = []
    for i, s in enumerate(series):
        p = f"r{i}_"
        arrays[p + "times_ps"] = s.times_ps
        for kind in KINDS:
            a = getattr(s, kind)
            arrays[p + kind] = np.stack([a.real, a.imag], axis=-1).astype(np.float32)
        if s.open_fraction is not None:
            arrays[p + "open_fraction"] = s.open_fraction.astype(np.float32)
        heads.append({"n": [int(v) for v in s.n], "length_A": s.length_A, "n_bp": s.n_bp,
                      "helical_repeat": s.helical_repeat, "source": s.source, "kind": s.kind,
                      "meta": s.meta})
    header = {"format": NPZ_FORMAT, "what": "dnarod modes: mode amplitudes c_n(t) per realisation "
              "(docs/analysis.md, 'Mode spectra')", "realisations": heads, **(extra or {})}
    arrays["header"] = np.array(json.dumps(header))
    np.savez_compressed(path, **arrays)


def load_npz(path) -> list[ModeSeries]:
    """The realisations of a mode_series.npz (save_npz); InputError naming the file otherwise."""
    try:
        z = np.load(path, allow_pickle=False)
        header = json.loads(str(z["header"]))
    except (OSError, ValueError, KeyError) as e:
        raise InputError(f"{path}: not a mode_series.npz written by `dnarod modes` ({e})") from None
    if header.get("format") != NPZ_FORMAT:
        raise InputError(f"{path}: mode_series.npz format {header.get('format')!r}; this dnarod reads "
                         f"format {NPZ_FORMAT}")
    out = []
    for i, h in enumerate(header["realisations"]):
        p = f"r{i}_"
        c = {k: z[p + k][..., 0].astype(float) + 1j * z[p + k][..., 1].astype(float) for k in KINDS}
        of = z[p + "open_fraction"].astype(float) if p + "open_fraction" in z.files else None
        out.append(ModeSeries(z[p + "times_ps"], np.asarray(h["n"]), c["bend"], c["twist"], c["stretch"],
                              float(h["length_A"]), int(h["n_bp"]), int(h["helical_repeat"]),
                              f"{path}[{i}] ({h['source']})", h["kind"], of, dict(h.get("meta") or {})))
    return out


# -- the table -----------------------------------------------------------------------------
def _common_length(series: list[ModeSeries]) -> int:
    return min(len(s.times_ps) for s in series)


def pooled_series(series, kind, i_mode, n_frames, part=slice(None)):
    x = np.concatenate([s.real_series(kind, i_mode)[:, :n_frames] for s in series], axis=0)
    x = x[:, part]
    return x - x.mean(axis=1, keepdims=True)


def _smoothing_window(n_bins: int, fraction: float = SMOOTH_FRACTION):
    """The bins lo_j .. hi_j - 1 that log_smooth averages at each j."""
    j = np.arange(n_bins)
    h = np.maximum(1, (fraction * j).astype(int))
    return np.maximum(1, j - h), np.minimum(n_bins, j + h + 1)


def log_smooth(p: np.ndarray, fraction: float = SMOOTH_FRACTION) -> np.ndarray:
    """The running mean of p over bins j (1 - fraction) .. j (1 + fraction) (at least one
    bin each side): a constant resolution in log-frequency, where peaks of a given Q are
    equally wide."""
    p = np.asarray(p, float)
    c = np.concatenate([[0.0], np.cumsum(p)])
    lo, hi = _smoothing_window(len(p), fraction)
    out = (c[hi] - c[lo]) / np.maximum(hi - lo, 1)
    out[0] = p[0]
    return out


def common_background(mean_periodograms, n_series: int,
                      quantile: float = BACKGROUND_QUANTILE) -> tuple[np.ndarray, np.ndarray] | None:
    """The part of a kind's spectra that is the same at every n, (B (J,), alpha (n_modes,)):
    mode n's background is alpha_n B. mean_periodograms (n_modes, J): each mode's
    periodogram averaged over its n_series pooled series. None with fewer than
    MIN_MODES_FOR_BACKGROUND modes.

    A mode's own peak moves with n (it is dispersive); what does not move, the slow red noise
    of pairs opening and the broad band of the base-pair steps' own vibration, is found in
    every n. At each frequency the modes whose peak is not there sit lowest, so B is the
    lower BACKGROUND_QUANTILE of the log-smoothed spectra over n (each scaled by alpha_n),
    divided by the same quantile of the sampling distribution of a background-only mode
    there (the mean of m_j bins of n_series periodograms: Gamma of shape m_j n_series and
    mean 1), which makes it the background's mean at every j, however few bins are
    smoothed. alpha_n is the median over frequency of mode n's spectrum over B (alternated
    to a fixed point): it ignores a peak held by a minority of the bins. A peak that stands
    at the same frequency in most n is background, and no mode's dispersive peak. Modes
    broad enough to overlap (Q ~ 1.5 with omega ~ n) cover up to half of the n at one
    frequency, which a median would take for background."""
    from scipy.stats import gamma
    P = np.array([log_smooth(p) for p in np.asarray(mean_periodograms, float)])
    if P.shape[0] < MIN_MODES_FOR_BACKGROUND:
        return None
    P = np.maximum(P, 1e-300)
    lo, hi = _smoothing_window(P.shape[1])
    dof = np.maximum(hi - lo, 1) * n_series
    unbias = gamma.ppf(quantile, dof, scale=1.0 / dof)
    inner = slice(1, P.shape[1] - 1)           # no mean, no Nyquist bin
    alpha = np.ones(P.shape[0])
    for _ in range(20):
        B = np.quantile(P / alpha[:, None], quantile, axis=0) / unbias
        new = np.median(P[:, inner] / B[None, inner], axis=1)
        new /= np.exp(np.mean(np.log(new)))     # B carries the scale
        if np.allclose(new, alpha, rtol=1e-6):
            break
        alpha = new
    return B, alpha


def _band(x, dt, background=None):
    """The fit's band (peak / BAND_OVER_PEAK, BAND_OVER_PEAK x peak) and the peak [rad/ps],
    at frequencies of at least MIN_PERIODS periods in the record.

    With the mode's background (common_background), the peak is where the pooled
    periodogram (log-smoothed) stands most significantly above it: the dispersive peak,
    whatever red noise or local band lies above it in power. The excess X_j = I_j / G_j - 1
    is scored in units of its own sampling error, X_j sqrt(m_j M): the mean of m_j bins of
    M series' periodograms, each exponential about its mean, scatters by 1 / sqrt(m_j M)
    of it. (The bare ratio would pick the few-bin noise of the lowest frequencies.)
    Without one (a single mode, fewer than
    MIN_MODES_FOR_BACKGROUND of a kind), the maximum of lambda I(lambda), the pooled
    periodogram smoothed over three bins, per unit log-frequency: an oscillator's
    lambda S(lambda) peaks near omega0 at any Q >~ 1, while a red spectrum is flattened."""
    p = periodogram(x).mean(axis=0)
    lam = frequencies_per_ps(x.shape[1], dt)
    lo = int(np.ceil(MIN_PERIODS))                # Fourier bin j holds j periods of the record
    if len(lam) < lo + 4:
        raise ValueError(f"a record of {x.shape[1]} frames is too short for a spectrum")
    if background is None:
        score = np.convolve(p, np.ones(3) / 3, mode="same") * lam
    else:
        lo_w, hi_w = _smoothing_window(len(p))
        score = (log_smooth(p) / np.maximum(np.asarray(background, float), 1e-300) - 1.0) \
            * np.sqrt((hi_w - lo_w) * x.shape[0])
    j = lo + int(np.argmax(score[lo:-1]))
    peak = float(lam[j])
    return (peak / BAND_OVER_PEAK, min(BAND_OVER_PEAK * peak, lam[-1])), peak


def line_near(x, dt, peak) -> float | None:
    """The frequency of the line near `peak` [rad/ps], or None when there is none: the
    pooled periodogram's highest bin within a factor 1 +- 2 SMOOTH_FRACTION of the peak, and
    the sinusoid there (spectrum.line_fit) if it leaves less than LINE_RESIDUAL of the power
    near it. _band finds a line only to within its smoothing window (log_smooth spreads the
    line's one bin over +-SMOOTH_FRACTION of frequency, and the score peaks where the
    background is lowest under that plateau), while the sinusoid is sought within a bin of
    its start."""
    top = highest_bin_near(x, dt, peak)
    if top is None:
        return None
    sinusoid = line_fit(x, dt, top)
    return sinusoid["omega_per_ps"] if sinusoid["residual_near"] < LINE_RESIDUAL else None


def highest_bin_near(x, dt, peak) -> float | None:
    """The frequency [rad/ps] of the pooled periodogram's highest bin within a factor
    1 +- 2 SMOOTH_FRACTION of `peak` (no mean, no Nyquist bin), or None when there is none."""
    p = periodogram(x).mean(axis=0)
    lam = frequencies_per_ps(x.shape[1], dt)
    near = np.flatnonzero((lam >= peak / (1 + 2 * SMOOTH_FRACTION)) & (lam <= peak * (1 + 2 * SMOOTH_FRACTION)))
    near = near[(near > 0) & (near < len(lam) - 1)]
    return float(lam[near[np.argmax(p[near])]]) if len(near) else None


def fit_mode(x, dt, errors="hessian", line="auto", background=None):
    """(OscillatorFit, None) or (None, the reason there is none) for the pooled real series
    x (M, T) of one mode: the band from the periodogram's peak, the fit on it, with the
    mode's background (common_background) when given.

    A fit narrower than the smoothing window (gamma < SMOOTH_FRACTION omega) that is not a
    line is tried again from the highest bin near the peak (highest_bin_near), and the start
    of lower negative log-likelihood is kept: _band places a narrow peak only to within that
    window (line_near), and the likelihood of a nearly undamped mode whose frequency wanders
    (the 300-K rod's twist n = 7, 13) has local minima a few bins apart, where a start 8 %
    off ended 1-2 % off the mode's own peak. A broader peak is placed by the smoothing."""
    try:
        band, peak = _band(x, dt, background)
        if line == "auto":
            w = line_near(x, dt, peak)
            if w is not None:
                lam = frequencies_per_ps(x.shape[1], dt)
                band, peak = (w / BAND_OVER_PEAK, min(BAND_OVER_PEAK * w, lam[-1])), w
        fit = fit_oscillator(x, dt, band, omega_guess=peak, errors=errors, line=line, background=background)
        if fit.line is None and fit.damping_per_ps < SMOOTH_FRACTION * fit.omega_per_ps:
            top = highest_bin_near(x, dt, peak)
            if top is not None and top != peak:
                other = fit_oscillator(x, dt, band, omega_guess=top, errors=errors, line=line, background=background)
                if other.nll < fit.nll:
                    fit = other
        return fit, None
    except ValueError as e:
        return None, f"no peak ({e})"


def backgrounds(xs, oscillators=None, skip=None) -> list:
    """Each mode's background alpha_n B (common_background) from the pooled series xs of
    every mode of one kind, or None for each when there are too few modes. skip: modes that
    hold no signal (round-off: a kicked rod's unexcited modes), left out of B and given
    None, since their spectra say nothing of what the others share. oscillators:
    None (the first estimate: the lower quartile over n of the spectra themselves), or each
    mode's fitted oscillator (or None), whose expected power is taken off its spectrum
    first (the second estimate: the median over n of what is not the modes)."""
    use = [i for i in range(len(xs)) if skip is None or not skip[i]]
    P = {i: periodogram(xs[i]).mean(axis=0) for i in use}
    if oscillators is None:
        cb = common_background([P[i] for i in use], xs[0].shape[0])
    else:
        for i in use:
            f = oscillators[i]
            if f is not None:
                own = np.mean(f.variance) * expected_periodogram(f.n_samples, f.dt_ps, f.omega_per_ps,
                                                                 f.damping_per_ps)
                P[i] = np.maximum(P[i] - own, 0.0)
        cb = common_background([P[i] for i in use], xs[0].shape[0], quantile=0.5)
    out: list = [None] * len(xs)
    if cb is not None:
        B, alpha = cb
        for i, a in zip(use, alpha):
            out[i] = a * B
    return out


def resolved_background(second, first, n_series: int):
    """The second background estimate (backgrounds with oscillators), never below its
    resolution: the first estimate's level times the relative sampling error of a
    log-smoothed periodogram, 1 / sqrt(m_j M) (m_j bins of M series). The second estimate is a
    median of spectra less their oscillators, each clipped at zero; where a mode's power is
    all its own oscillator (every mode of a rod in NVE: nothing else moves it), the
    periodogram, exponential about that mean, falls below it in 63 % of the bins, and the
    median over n is exactly zero. A background of zero is not a measurement of one: it
    would make any power in those bins infinitely significant to _band's peak search (the
    300-K rod's stretch n = 5, 7, 8 were fitted there, about 6x below their own peaks, and
    accepted; tests/python/test_modes_background.py). None stays None."""
    if second is None:
        return None
    lo, hi = _smoothing_window(len(second))
    return np.maximum(second, first / np.sqrt((hi - lo) * n_series))


def fit_kind(xs, dt, errors="hessian", line="auto", skip=None, wanted=None) -> list:
    """(OscillatorFit, None) or (None, reason) for each mode of one kind, from the pooled
    series xs of every mode: each mode's oscillator over the common background
    (common_background), estimated twice: first from the spectra themselves (their lower
    quartile over n), then from the spectra less the oscillators that first fit found (their
    median over n). The second estimate is what the modes have in common once their own
    peaks, however broad (a mode of Q ~ 1.5 has a plateau below its peak reaching every
    lower n), are taken off, known only to within its resolution (resolved_background).
    skip: modes never fitted (no signal); wanted: the modes whose final fit is returned (the
    others are (None, "not wanted"), yet enter the background)."""
    skip = skip if skip is not None else [False] * len(xs)
    wanted = wanted if wanted is not None else [True] * len(xs)
    bg = backgrounds(xs, skip=skip)
    if any(b is not None for b in bg):
        first = [None if sk else fit_mode(x, dt, "none", line, background=b)[0] for x, b, sk in zip(xs, bg, skip)]
        # A line (an undamped mode) keeps the first background and is left out of the second:
        # its periodogram is not its expected power (its sidelobes fall by its phase), so
        # what would be left of it after the subtraction would stand in the others' background.
        is_line = [f is not None and f.line is not None for f in first]
        # only a mode that is not refused is taken off: a fit on noise would carve a hole
        second = backgrounds(xs, [f if f is not None and refusal(f, x.shape[1] * dt) is None else None
                                  for f, x in zip(first, xs)], [sk or ln for sk, ln in zip(skip, is_line)])
        bg = [b1 if ln else resolved_background(b2, b1, xs[0].shape[0]) for b1, b2, ln in zip(bg, second, is_line)]
    return [fit_mode(x, dt, errors, line, background=b) if w and not sk else (None, "not wanted")
            for x, b, sk, w in zip(xs, bg, skip, wanted)]


def noise_peak(fit) -> float:
    """The highest bin that noise alone reaches on the fit's band, over its mean: the
    1 - SPIKE_FALSE / J quantile of the mean of M exponentials (the periodogram bins of the
    fit's M series; J bins on the band), Gamma of shape M and mean 1. A fit at the narrowest
    width allowed (NOT_LINE_MIN_GAMMA_T) whose peak stands no higher above what lies
    beneath it has found one high bin of noise, not a mode."""
    from scipy.stats import gamma
    M = len(fit.variance)
    J = max(len(band_indices(fit.n_samples, fit.dt_ps, fit.band_per_ps)), 1)
    return float(gamma.ppf(1.0 - SPIKE_FALSE / J, M, scale=1.0 / M))


def refusal(fit, record_ps):
    if fit is None:
        return "no peak"
    w, g = fit.omega_per_ps, fit.damping_per_ps
    periods = w * record_ps / (2 * np.pi)
    if periods < MIN_PERIODS:
        return f"fewer than {MIN_PERIODS:g} periods in the record ({periods:.2f})"
    if g >= 0.99 * GAMMA_OVER_OMEGA_MAX * w:
        return "no peak (the fit runs to its overdamped bound)"
    if fit.line is None and g * record_ps <= 1.01 * NOT_LINE_MIN_GAMMA_T and fit.peak_to_floor() < noise_peak(fit) - 1:
        return ("no peak (a spike of the periodogram: narrower than the record resolves, not a line, and no "
                "higher than noise alone reaches on the band)")
    lo, hi = fit.band_per_ps
    if not (lo < w < hi):
        return "no peak (the fitted frequency is outside the band of the periodogram's peak)"
    ratio = fit.peak_to_floor()
    if ratio < MIN_PEAK_TO_FLOOR:
        under = "floor + common background" if fit.background is not None else "floor"
        return f"no peak (peak / {under} {ratio:.2g} < {MIN_PEAK_TO_FLOOR:g})"
    return None


def peak_excess(fit, x) -> tuple[float | None, float, float]:
    """(r, threshold, lambda_p) of the resolved-peak test (unresolved_peak): r, the pooled
    periodogram of the series x (M, N) summed over the peak's bins over what a flat spectrum at
    the level below the peak would put there; threshold, what noise alone exceeds with chance
    SPIKE_FALSE anywhere on the band; lambda_p [rad/ps], the fitted oscillator's power maximum.
    r is None when the band holds no frequency below the peak."""
    from scipy.stats import gamma
    j = band_indices(fit.n_samples, fit.dt_ps, fit.band_per_ps)
    lam = frequencies_per_ps(fit.n_samples, fit.dt_ps)[j]
    I = periodogram(x)[:, j]
    b = np.asarray(fit.floor, float)[:, None] * np.ones((1, len(j)))
    if fit.background is not None and fit.background_amplitude is not None:
        b = b + np.asarray(fit.background_amplitude, float)[:, None] * np.asarray(fit.background, float)[None, :]
    w, g = fit.omega_per_ps, fit.damping_per_ps
    lam_p = math.sqrt(max(w * w - g * g, 0.0))
    # the peak's half-width: its damping, and at least the resolution at which _band places a
    # peak (log_smooth's +-SMOOTH_FRACTION): a narrow mode whose frequency wanders spreads its
    # power over that much, and a spike of noise one bin wide is diluted in it
    h = max(g, SMOOTH_FRACTION * lam_p)
    at = np.flatnonzero(np.abs(lam - lam_p) <= h)
    if len(at) == 0:
        at = np.array([int(np.argmin(np.abs(lam - lam_p)))])
    below = np.flatnonzero(lam < min(lam[at[0]], lam_p - h) - 1e-12)
    if len(below) == 0:
        return None, math.nan, lam_p
    net = I[:, below] - b[:, below]
    # the level below the peak, taken high by one standard error (each bin exponential about
    # its mean): a level known from a few bins does not make a peak
    q = float(net.mean()) + float(np.sqrt(np.sum(I[:, below] ** 2)) / I[:, below].size)
    flat = float(np.sum(b[:, at] + max(q, 0.0)))
    r = float(np.sum(I[:, at])) / max(flat, 1e-300)
    n = I[:, at].size
    places = max(1, len(j) // len(at))
    return r, float(gamma.ppf(1.0 - SPIKE_FALSE / places, n, scale=1.0 / n)), lam_p


def unresolved_peak(fit, x) -> str | None:
    """Why the fitted oscillator's peak is not one of the data (None when it is): a peak is a
    maximum, so the power of the pooled series x (M, N) at the fit's peak must stand above the
    power below it, on the fit's band.

    The peak: the bins within the fitted damping gamma of the oscillator's power maximum
    lambda_p = (omega^2 - gamma^2)^1/2 (at least the nearest bin); below it: the band's bins
    under lambda_p - gamma. The hypothesis of no peak: the spectrum at the peak's bins is no
    higher than below it, i.e. the fitted floor and common background there plus the net
    power (less floor and background) of the bins below, taken at its mean plus one standard
    error. Under it the summed periodogram of the n = M x bins at the peak, over its expected
    value, is Gamma-distributed (shape n, mean 1); the peak is resolved when it exceeds the
    quantile 1 - SPIKE_FALSE / P of that distribution, P the number of places on the band the
    peak could have been (band bins / peak bins): the fit chose its place, so the highest
    place that noise reaches is the bar (as noise_peak). A damped harmonic mode's spectrum has
    a maximum above zero frequency only when Gamma^2 < 2 omega0^2 (Q > 1/sqrt 2), and it
    stands out only when the record resolves the rise below it: an overdamped mode (Gamma > 2
    omega0), flat up to omega0^2 / Gamma, has none, and a fit placed on it (on a few low bins
    of noise, a spike, or the shape of a background the other modes set) is refused here
    (docs/modes.md, "Overdamped modes"). A line passes by its own test (spectrum.line_fit)."""
    if fit is None:
        return "no peak"
    if fit.line is not None:
        return None
    r, bar, lam_p = peak_excess(fit, x)
    if r is None:
        return (f"no resolved peak (the fitted peak at {lam_p:.3g} rad/ps has no frequencies below it on the "
                "band: the record does not show its rise)")
    if r < bar:
        return (f"no resolved peak (the power at the fitted peak, {lam_p:.3g} rad/ps, is {r:.3g} x what a "
                f"spectrum flat from below it gives there; noise alone reaches {bar:.3g} x)")
    return None


def _variance(series, kind, i_mode, n_frames):
    """<|c_n - <c_n>|^2> per direction, averaged over directions and realisations, with the
    error of that mean (blocking, per realisation)."""
    means, sems = [], []
    for s in series:
        a = s.amplitudes(kind, i_mode)[:n_frames]
        d2 = np.abs(a - a.mean(axis=0)) ** 2
        y = d2.mean(axis=1)
        b = block_sem(y)
        means.append(float(y.mean()))
        sems.append(float(b["sem"]))
    v = float(np.mean(means))
    err = float(np.sqrt(np.sum(np.square(sems)))) / len(sems)   # NaN: a record too short to block
    if len(means) >= 2:
        err = max(err, float(np.std(means, ddof=1) / math.sqrt(len(means))))
    return v, err


def _num(v):
    return None if v is None or not np.isfinite(v) else float(v)


def _check_pooled(series: list[ModeSeries]) -> None:
    """InputError unless every realisation has one frame interval, and all are of one duplex."""
    s0 = series[0]
    for s in series:
        d = np.diff(s.times_ps)
        # (1 %: MD times are float32, good to ~1e-7 of t)
        if d.size and (d.min() <= 0 or d.max() - d.min() > 1e-2 * np.median(d)):
            raise InputError(f"{s.source}: frames at uneven times ({d.min():g} to {d.max():g} ps apart); the "
                             "spectra need one frame interval")
    for s in series[1:]:
        if (s.n_bp, s.helical_repeat, len(s.n)) != (s0.n_bp, s0.helical_repeat, len(s0.n)):
            raise InputError(f"{s.source}: {s.n_bp} bp, {s.helical_repeat} turns, {len(s.n)} modes; "
                             f"{s0.source} has {s0.n_bp}, {s0.helical_repeat}, {len(s0.n)}: realisations "
                             "pooled in one table must be of the same duplex")
        if abs(s.dt_ps - s0.dt_ps) > 1e-6 * s0.dt_ps:
            raise InputError(f"{s.source}: frames every {s.dt_ps:g} ps, {s0.source} every {s0.dt_ps:g} ps: "
                             "pooled realisations need one frame interval")


def _entry(kind: str, n, length_A: float, n_series: int, var, fit, reason, record_ps: float) -> dict:
    """One mode's entry before the halves' and the seeds' checks."""
    var_i, var_err = var
    e = {"kind": kind, "n": int(n), "k_per_A": 2 * np.pi * int(n) / length_A,
         "omega_per_ps": None, "omega_err_per_ps": None, "omega0_per_ps": None, "omega0_err_per_ps": None,
         "damping_per_ps": None, "damping_err_per_ps": None, "Q": None, "Q_err": None,
         "variance": var_i, "variance_err": _num(var_err), "variance_unit": VARIANCE_UNIT[kind],
         "oscillator_variance": None, "oscillator_variance_err": None, "periods_in_record": None,
         "reason": reason, "n_series": n_series, "record_ps": record_ps}
    if fit is not None:
        e["periods_in_record"] = fit.omega_per_ps * record_ps / (2 * np.pi)
        e["peak_to_background"] = fit.peak_to_floor()
        e["common_background"] = fit.background is not None
        e["band_per_ps"] = list(fit.band_per_ps)
        e["fit"] = _fit_record(fit)
    return e


def _measured(e: dict, fit, half_fits, half_ps: float, seed_fits, record_ps: float) -> None:
    """A measured mode's numbers into E, then the halves' check (a line's scatter enters
    its error; another mode whose halves differ is refused) and the seeds' Birge ratio."""
    e.update(_numbers(fit))
    e["halves"] = _halves(half_fits, half_ps)
    z_halves = e["halves"].get("z")
    if z_halves is not None and z_halves > STATIONARY_Z and fit.line is not None:
        # a line's frequency wanders (module doc): the halves' scatter enters its error
        w1, w2 = e["halves"]["omega_per_ps"]
        e["halves"]["scatter_per_ps"] = abs(w1 - w2) / 2
        for k in ("omega_err_per_ps", "omega0_err_per_ps"):
            if e[k] is not None:
                e[k] = math.hypot(e[k], e["halves"]["scatter_per_ps"])
    elif z_halves is not None and z_halves > STATIONARY_Z:
        e["reason"] = (f"not stationary: the halves' frequencies differ by "
                       f"{e['halves']['z']:.1f} of their combined error (> {STATIONARY_Z:g})")
        e.update({k: None for k in ("omega_per_ps", "omega_err_per_ps", "omega0_per_ps",
                                    "omega0_err_per_ps", "damping_per_ps", "damping_err_per_ps",
                                    "Q", "Q_err", "variance", "variance_err",
                                    "oscillator_variance", "oscillator_variance_err")})
    elif seed_fits is not None:
        e["seeds"] = _seeds(seed_fits, record_ps, fit)
        for k in ("omega_err_per_ps", "omega0_err_per_ps", "damping_err_per_ps", "Q_err"):
            if e[k] is not None:
                e[k] *= e["seeds"]["birge_ratio_applied"]


def _kind_entries(series: list[ModeSeries], kind: str, n_frames: int, length_A: float, errors: str) -> list:
    """The entries of one kind (bend, twist, stretch), every mode n of the duplex."""
    s0 = series[0]
    dt = s0.dt_ps
    record_ps = n_frames * dt
    h = length_A / s0.n_bp
    scale = {"bend": h, "stretch": h, "twist": 2 * np.pi * s0.helical_repeat / length_A}[kind]
    h2 = n_frames // 2
    modes = range(len(s0.n))
    xs = [pooled_series(series, kind, i, n_frames) for i in modes]
    var = [_variance(series, kind, i, n_frames) for i in modes]
    no_signal = [math.sqrt(v) < ROUND_OFF * scale for v, _ in var]
    fits = fit_kind(xs, dt, errors, skip=no_signal)
    reasons = off_branch(fits, [why or refusal(f, record_ps) or unresolved_peak(f, x) for (f, why), x in zip(fits, xs)])
    passed = [r is None for r in reasons]
    halves = [fit_kind([pooled_series(series, kind, i, n_frames, part) for i in modes], dt, errors,
                       skip=no_signal, wanted=passed)
              for part in (slice(0, h2), slice(h2, 2 * h2))] if any(passed) else None
    seeds = [fit_kind([pooled_series([s], kind, i, n_frames) for i in modes], dt, errors,
                      skip=no_signal, wanted=passed)
             for s in series] if len(series) >= 2 and any(passed) else None
    entries = []
    for i, n in enumerate(s0.n):
        if no_signal[i]:
            fit, reason = None, (f"no signal (rms amplitude {math.sqrt(var[i][0]):.2g} {AMPLITUDE_UNIT[kind]}, "
                                 f"below {ROUND_OFF:g} of the field's scale: round-off)")
        else:
            fit, reason = fits[i][0], reasons[i]
        e = _entry(kind, n, length_A, int(xs[i].shape[0]), var[i], fit, reason, record_ps)
        if reason is None:
            _measured(e, fit, [hf[i] for hf in halves], h2 * dt,
                      None if seeds is None else [f[i] for f in seeds], record_ps)
        e.update(regime_of(e, xs[i], dt, no_signal[i]))
        entries.append(e)
    return entries


def regime_of(e: dict, x, dt: float, no_signal: bool) -> dict:
    """The mode's regime and, when it has no frequency, its relaxation time (docs/modes.md,
    "Overdamped modes"):
      oscillating  a frequency (every refusal above passed, the peak resolved: unresolved_peak);
      overdamped   no frequency, and the integrated autocorrelation time of its pooled series
                   x (M, N) resolved (mdbridge/analysis/relaxation.py): Gamma / omega0^2,
                   zeta / k of the mode;
      unresolved   neither: no signal, not stationary, or a relaxation time the record does
                   not resolve (`relaxation.reason` says why)."""
    out: dict = {"regime": "oscillating", "relaxation_time_ps": None, "relaxation_time_err_ps": None}
    if e["reason"] is None:
        return out
    out["regime"] = "unresolved"
    if no_signal or e["reason"].startswith("not stationary"):
        return out
    r = relaxation_time(x, dt)
    out["relaxation"] = {k: r[k] for k in ("tau_ps", "tau_err_ps", "window_ps", "relaxations_in_record",
                                           "rho_min", "blocks", "reason")}
    if r["resolved"]:
        out.update(regime="overdamped", relaxation_time_ps=r["tau_ps"], relaxation_time_err_ps=r["tau_err_ps"])
    return out


def mode_table(series: list[ModeSeries], errors: str = "hessian") -> dict:
    """The entries of modes.json["modes"] (module doc) for realisations of one duplex."""
    _check_pooled(series)
    s0 = series[0]
    dt = s0.dt_ps
    n_frames = _common_length(series)
    record_ps = n_frames * dt
    length_A = float(np.mean([s.length_A for s in series]))
    entries = [e for kind in KINDS for e in _kind_entries(series, kind, n_frames, length_A, errors)]
    return {"modes": entries, "drift": {kind: common_drift([e for e in entries if e["kind"] == kind])
                                        for kind in KINDS},
            "record_ps": record_ps, "dt_ps": dt, "n_frames": n_frames,
            "length_A": length_A, "n_bp": s0.n_bp, "helical_repeat": s0.helical_repeat,
            "realisations": [{"source": s.source, "kind": s.kind, "n_frames": len(s.times_ps),
                              "t_start_ps": float(s.times_ps[0]), "t_end_ps": float(s.times_ps[-1]),
                              **({"open_fraction": open_fraction_check(s)} if s.open_fraction is not None
                                 else {})} for s in series]}


def _numbers(fit) -> dict:
    w, g = fit.omega_per_ps, fit.damping_per_ps
    g_err = _num(fit.damping_err_per_ps)
    # A line is undamped over the record: one sinusoid leaves under LINE_RESIDUAL of the
    # power near it, and a damped mode leaves ~gamma T / 3 (spectrum.line_fit)
    undamped = fit.line is not None or g_err is None or g < 2 * g_err
    out = {"omega_per_ps": w, "omega_err_per_ps": _num(fit.omega_err_per_ps), "omega0_per_ps": fit.omega0_per_ps,
           "omega0_err_per_ps": _num(fit.omega0_err_per_ps),
           "damping_per_ps": g, "damping_err_per_ps": g_err, "Q": None if undamped else fit.Q,
           "Q_err": None if undamped else _num(fit.Q_err), "undamped": bool(undamped),
           # <|c_n|^2> of one component that is the oscillator's own (module doc): the fitted
           # variance of each real series (Re, Im) averaged over series, times 2; none for a
           # line, whose periodogram is not an oscillator's expected power
           "oscillator_variance": None if undamped else 2 * float(np.mean(fit.variance)),
           "oscillator_variance_err": None if undamped else _num(2 * fit.mean_variance_err)}
    if undamped:
        # damping consistent with zero: Q has only a lower bound
        g_max = 3 * LINE_RESIDUAL / fit.record_ps if fit.line is not None else g + 2 * (g_err or 0.0)
        out["Q_lower_bound"] = fit.omega0_per_ps / (2 * g_max) if g_max > 0 else None
    return out


def _fit_record(fit) -> dict:
    out = {"omega_per_ps": fit.omega_per_ps, "damping_per_ps": fit.damping_per_ps,
           "variance": [float(v) for v in fit.variance], "floor": [float(v) for v in fit.floor],
           "nll": fit.nll, "n_samples": fit.n_samples, "dt_ps": fit.dt_ps}
    if fit.background is not None and fit.background_amplitude is not None:
        # the summed series' common background on the band's bins (spectrum.band_indices)
        out["background"] = [float(v) for v in float(np.sum(fit.background_amplitude)) * fit.background]
    return out


def _halves(half_fits, half_ps) -> dict:
    """The frequencies of the first and the second half of the record (each fitted with the
    common background of its own half: fit_kind), and their z."""
    out: dict = {"omega_per_ps": [], "omega_err_per_ps": [], "z": None, "reason": None}
    for fit, why in half_fits:
        why = why or refusal(fit, half_ps)
        if why:
            out["reason"] = f"a half cannot be fitted: {why}"
            return out
        out["omega_per_ps"].append(fit.omega_per_ps)
        out["omega_err_per_ps"].append(_num(fit.omega_err_per_ps))
    e = out["omega_err_per_ps"]
    if None not in e:
        w = out["omega_per_ps"]
        out["z"] = abs(w[0] - w[1]) / math.hypot(e[0], e[1])
    return out


def off_branch(fits, reasons) -> list:
    """The reasons, with a mode that is off its kind's branch refused: a mode's peak is the
    dispersive one, and modes n = 1 .. helical repeat - 1 of a rod of 158 steps lie far below
    the end of the acoustic branch, where omega rises with n for any rod (no material
    enters). A mode whose frequency lies below those of OFF_BRANCH_MIN lower modes that are
    not refused, each by more than STATIONARY_Z combined errors, sits on something else
    (red noise, another kind's mode reaching this series). Two are needed, so that one
    lower mode on a wrong peak cannot veto the modes above it."""
    out = list(reasons)
    for i, (fit, _) in enumerate(fits):
        if out[i] is not None:
            continue
        above = [m for m in range(i) if out[m] is None and fits[m][0].omega_per_ps - fit.omega_per_ps
                 > STATIONARY_Z * math.hypot(_err(fits[m][0]), _err(fit))]
        if len(above) >= OFF_BRANCH_MIN:
            out[i] = (f"off the branch: its frequency lies below those of modes n = "
                      f"{', '.join(str(m + 1) for m in above)} of its kind (a dispersive mode's rises with n)")
    # the branch rises from its first mode on: a mode at or above a higher one is refused (on
    # the acoustic branch omega_(n+1) / omega_n >= (n+1) / n, far beyond the errors). The lower
    # n is the one refused: its few periods in the record make it the one that locks onto a
    # wrong peak (the main job's stretch n = 1 at 0.33 rad/ps above its n = 2 at 0.29; 0.10
    # in a 5-ns record)
    for i, (fit, _) in enumerate(fits):
        if out[i] is not None:
            continue
        below = [m for m in range(i + 1, len(fits)) if out[m] is None
                 and fit.omega_per_ps >= fits[m][0].omega_per_ps]
        if below:
            out[i] = (f"off the branch: its frequency lies above that of mode n = {below[0] + 1} of its kind "
                      "(a branch rises with n from its first mode on)")
    return out


def _err(fit) -> float:
    e = fit.omega_err_per_ps
    return float(e) if e is not None and np.isfinite(e) else 0.0


def common_drift(entries) -> dict:
    """Whether a kind's frequencies move together between the halves of the record: each
    mode's relative shift d = (omega_2 - omega_1) / mean and its error, their weighted mean
    and its z, and how many are positive. A stationary record gives shifts of random sign
    (z of the mean ~ N(0, 1)); an error model too small for the halves inflates each |d| /
    error but not their common sign; a record that drifts (a tension that changes as pairs
    open) shifts every mode one way. The mean's error is multiplied by the Birge ratio
    sqrt(chi^2 / (N - 1)) of the shifts about it when that exceeds 1, so that errors too
    small for the halves (which inflate the scatter) do not pass for a drift. `drifts` is
    true when |z| > STATIONARY_Z."""
    d, e = [], []
    for m in entries:
        h = m.get("halves") or {}
        w, we = h.get("omega_per_ps") or [], h.get("omega_err_per_ps") or []
        if len(w) == 2 and None not in we:
            mean = 0.5 * (w[0] + w[1])
            d.append((w[1] - w[0]) / mean)
            e.append(math.hypot(we[0], we[1]) / mean)
    out: dict = {"modes": len(d), "relative_shift": None, "relative_shift_err": None, "z": None,
                 "positive": int(sum(v > 0 for v in d)), "drifts": None}
    if d:
        wt = 1.0 / np.square(e)
        mean = float(np.sum(wt * np.array(d)) / np.sum(wt))
        chi2 = float(np.sum(wt * (np.array(d) - mean) ** 2))
        birge = math.sqrt(chi2 / (len(d) - 1)) if len(d) >= 2 else 1.0
        err = float(1.0 / math.sqrt(np.sum(wt))) * max(1.0, birge)
        out.update(relative_shift=mean, relative_shift_err=err, z=mean / err, chi2_about_mean=chi2,
                   birge_ratio=birge, drifts=bool(abs(mean / err) > STATIONARY_Z))
    return out


def _seeds(seed_fits, record_ps, pooled) -> dict:
    """Each realisation fitted alone (fit_kind on its own modes); the Birge ratio of their
    scatter about the pooled fit."""
    w, e = [], []
    for fit, why in seed_fits:
        if why or refusal(fit, record_ps) or not np.isfinite(fit.omega_err_per_ps):
            continue
        w.append(fit.omega_per_ps)
        e.append(fit.omega_err_per_ps)
    out: dict = {"omega_per_ps": w, "omega_err_per_ps": e, "birge_ratio": None, "birge_ratio_applied": 1.0}
    if len(w) >= 2:
        chi2 = float(np.sum(((np.array(w) - pooled.omega_per_ps) / np.array(e)) ** 2))
        b = math.sqrt(chi2 / (len(w) - 1))
        out["birge_ratio"] = b
        out["birge_ratio_applied"] = max(1.0, b)
        out["scatter_per_ps"] = float(np.std(w, ddof=1) / math.sqrt(len(w)))
    return out


def open_fraction_check(s: ModeSeries) -> dict:
    """The fraction of open base pairs against time (thinned), its mean in each half of the
    record, and their difference in units of its blocking error (a duplex that keeps
    opening is not stationary; `stationary` is false beyond STATIONARY_Z)."""
    f = s.open_fraction
    if f is None:
        raise ValueError(f"{s.source}: no open base-pair fraction (an MD realisation has one)")
    h = len(f) // 2
    a, b = block_sem(f[:h]), block_sem(f[h:2 * h])
    se = math.hypot(a["sem"], b["sem"]) if np.isfinite(a["sem"]) and np.isfinite(b["sem"]) else float("nan")
    z = abs(a["mean"] - b["mean"]) / se if se > 0 else (0.0 if a["mean"] == b["mean"] else float("inf"))
    step = max(1, len(f) // 200)       # the curve, at most ~200 points (the npz has every frame)
    return {"mean": float(np.mean(f)), "halves": [float(a["mean"]), float(b["mean"])],
            "times_ps": [float(v) for v in s.times_ps[::step]], "fraction": [float(v) for v in f[::step]],
            "z": _num(z), "stationary": bool(np.isfinite(z) and z <= STATIONARY_Z) if np.isfinite(se) else None}
