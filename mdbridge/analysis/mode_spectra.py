"""The mode table of `dnarod modes`: static variance, frequency and damping of every mode,
pooled over quadratures, transverse directions and realisations, with refusals
(docs/analysis.md, "Mode spectra").

`ModeSeries` is one realisation's reduced result: the complex mode amplitudes against time
(mdbridge/analysis/modes.py) and, for MD, the open base-pair fraction. It is what
DIR/mode_series.npz holds (float32), so a run can be re-analysed without its trajectory.

`mode_table` fits each mode (mdbridge/analysis/spectrum.py) and refuses, with the reason,
a mode that
  * holds fewer than MIN_PERIODS periods in the record,
  * has no peak: the fit runs to its overdamped bound (gamma = omega), out of the band of
    the periodogram's peak, or its peak stands less than MIN_PEAK_TO_FLOOR above the floor,
  * is not stationary: the frequencies fitted to the two halves of the record differ by more
    than STATIONARY_Z of their combined error (tested when each half holds MIN_PERIODS).
  * holds no signal: its rms amplitude is below ROUND_OFF of the field's own scale (the
    rise for bend and stretch, the mean twist density for twist): a deterministic run (a
    kicked rod) leaves the modes it does not excite at round-off, where a fit means nothing.
A refused mode keeps its entry with null frequency and damping (and null variance when it
is not stationary: the static variance of a drifting record means nothing).

Errors. The frequency's and damping's are the fit's (observed information; calibrated on
synthetic oscillators by bench/mode_spectrum_calibration.py). With two or more
realisations each is also fitted alone, and the pooled error is multiplied by the Birge
ratio sqrt(chi^2 / (R - 1)) of their scatter about the pooled value when that exceeds 1: the
between-seed scatter enters whenever it is larger than the fit's own error explains.
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass, field

import numpy as np

from dna_models.errors import InputError
from mdbridge.analysis.modes import AMPLITUDE_UNIT, KINDS, VARIANCE_UNIT
from mdbridge.analysis.spectrum import (fit_oscillator, frequencies_per_ps, periodogram,
                                        GAMMA_OVER_OMEGA_MAX)
from mdbridge.stats import block_sem

MIN_PERIODS = 3.0
MIN_PEAK_TO_FLOOR = 3.0
STATIONARY_Z = 3.0
ROUND_OFF = 1e-8           # rms amplitude / the field's own scale below which a mode holds no signal
BAND_OVER_PEAK = 3.0       # the fit's band: peak / 3 .. 3 x peak (_band)
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

    def after(self, discard_ps: float) -> "ModeSeries":
        """The frames from times_ps[0] + discard_ps on."""
        keep = self.times_ps >= self.times_ps[0] + discard_ps - 1e-9
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


def _band(x, dt):
    """The fit's band (peak / BAND_OVER_PEAK, BAND_OVER_PEAK x peak) and the peak [rad/ps].
    The peak is the maximum of lambda I(lambda), the pooled periodogram smoothed over three
    bins, per unit log-frequency, at frequencies of at least MIN_PERIODS periods in the
    record: an oscillator's lambda S(lambda) peaks near omega0 at any Q >~ 1, while the
    slow, red part of an MD's spectrum (pairs opening, the duplex's drift), which
    dominates I itself at the lowest frequencies, is flattened; the band then leaves it out
    (the floor is white, and cannot describe it)."""
    p = periodogram(x).mean(axis=0)
    lam = frequencies_per_ps(x.shape[1], dt)
    sm = np.convolve(p, np.ones(3) / 3, mode="same") * lam
    lo = int(np.ceil(MIN_PERIODS))                # Fourier bin j holds j periods of the record
    if len(lam) < lo + 4:
        raise ValueError(f"a record of {x.shape[1]} frames is too short for a spectrum")
    j = lo + int(np.argmax(sm[lo:-1]))
    peak = float(lam[j])
    return (peak / BAND_OVER_PEAK, min(BAND_OVER_PEAK * peak, lam[-1])), peak


def fit_mode(x, dt, errors="hessian", line="auto"):
    """(OscillatorFit, None) or (None, the reason there is none) for the pooled real series
    x (M, T) of one mode: the band from the periodogram's peak, the fit on it."""
    try:
        band, peak = _band(x, dt)
        return fit_oscillator(x, dt, band, omega_guess=peak, errors=errors, line=line), None
    except ValueError as e:
        return None, f"no peak ({e})"


def refusal(fit, record_ps):
    if fit is None:
        return "no peak"
    w, g = fit.omega_per_ps, fit.damping_per_ps
    periods = w * record_ps / (2 * np.pi)
    if periods < MIN_PERIODS:
        return f"fewer than {MIN_PERIODS:g} periods in the record ({periods:.2f})"
    if g >= 0.99 * GAMMA_OVER_OMEGA_MAX * w:
        return "no peak (the fit runs to its overdamped bound)"
    lo, hi = fit.band_per_ps
    if not (lo < w < hi):
        return "no peak (the fitted frequency is outside the band of the periodogram's peak)"
    ratio = fit.peak_to_floor()
    if ratio < MIN_PEAK_TO_FLOOR:
        return f"no peak (peak / floor {ratio:.2g} < {MIN_PEAK_TO_FLOOR:g})"
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


def mode_table(series: list[ModeSeries], errors: str = "hessian") -> dict:
    """The entries of modes.json["modes"] (module doc) for realisations of one duplex."""
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
    dt = s0.dt_ps
    n_frames = _common_length(series)
    record_ps = n_frames * dt
    length_A = float(np.mean([s.length_A for s in series]))
    entries = []
    h = length_A / s0.n_bp
    scale = {"bend": h, "stretch": h, "twist": 2 * np.pi * s0.helical_repeat / length_A}
    for kind in KINDS:
        for i, n in enumerate(s0.n):
            x = pooled_series(series, kind, i, n_frames)
            var, var_err = _variance(series, kind, i, n_frames)
            if math.sqrt(var) < ROUND_OFF * scale[kind]:
                fit, reason = None, (f"no signal (rms amplitude {math.sqrt(var):.2g} {AMPLITUDE_UNIT[kind]}, "
                                     f"below {ROUND_OFF:g} of the field's scale: round-off)")
            else:
                fit, why = fit_mode(x, dt, errors)
                reason = why or refusal(fit, record_ps)
            e = {"kind": kind, "n": int(n), "k_per_A": 2 * np.pi * int(n) / length_A,
                 "omega_per_ps": None, "omega_err_per_ps": None, "omega0_per_ps": None,
                 "damping_per_ps": None, "damping_err_per_ps": None, "Q": None,
                 "variance": var, "variance_err": _num(var_err), "variance_unit": VARIANCE_UNIT[kind],
                 "periods_in_record": None, "reason": reason, "n_series": int(x.shape[0]),
                 "record_ps": record_ps}
            if fit is not None:
                e["periods_in_record"] = fit.omega_per_ps * record_ps / (2 * np.pi)
                e["band_per_ps"] = list(fit.band_per_ps)
                e["fit"] = _fit_record(fit)
            if reason is None:
                e.update(_numbers(fit))
                e["halves"] = _halves(series, kind, i, n_frames, dt, errors)
                if e["halves"].get("z") is not None and e["halves"]["z"] > STATIONARY_Z:
                    e["reason"] = (f"not stationary: the halves' frequencies differ by "
                                   f"{e['halves']['z']:.1f} of their combined error (> {STATIONARY_Z:g})")
                    e.update({k: None for k in ("omega_per_ps", "omega_err_per_ps", "omega0_per_ps",
                                                "damping_per_ps", "damping_err_per_ps", "Q", "variance",
                                                "variance_err")})
                elif len(series) >= 2:
                    e["seeds"] = _seeds(series, kind, i, n_frames, dt, errors, fit)
                    for k in ("omega_err_per_ps", "damping_err_per_ps"):
                        if e[k] is not None:
                            e[k] *= e["seeds"]["birge_ratio_applied"]
            entries.append(e)
    return {"modes": entries, "record_ps": record_ps, "dt_ps": dt, "n_frames": n_frames,
            "length_A": length_A, "n_bp": s0.n_bp, "helical_repeat": s0.helical_repeat,
            "realisations": [{"source": s.source, "kind": s.kind, "n_frames": len(s.times_ps),
                              "t_start_ps": float(s.times_ps[0]), "t_end_ps": float(s.times_ps[-1]),
                              **({"open_fraction": open_fraction_check(s)} if s.open_fraction is not None
                                 else {})} for s in series]}


def _numbers(fit) -> dict:
    w, g = fit.omega_per_ps, fit.damping_per_ps
    g_err = _num(fit.damping_err_per_ps)
    undamped = g_err is None or g < 2 * g_err
    out = {"omega_per_ps": w, "omega_err_per_ps": _num(fit.omega_err_per_ps), "omega0_per_ps": fit.omega0_per_ps,
           "damping_per_ps": g, "damping_err_per_ps": g_err, "Q": None if undamped else fit.Q,
           "undamped": bool(undamped)}
    if undamped:
        # damping consistent with zero: Q has only a lower bound
        out["Q_lower_bound"] = fit.omega0_per_ps / (2 * (g + 2 * (g_err or 0.0))) if g + 2 * (g_err or 0) > 0 \
            else None
    return out


def _fit_record(fit) -> dict:
    return {"omega_per_ps": fit.omega_per_ps, "damping_per_ps": fit.damping_per_ps,
            "variance": [float(v) for v in fit.variance], "floor": [float(v) for v in fit.floor],
            "nll": fit.nll, "n_samples": fit.n_samples, "dt_ps": fit.dt_ps}


def _halves(series, kind, i, n_frames, dt, errors) -> dict:
    """The frequencies of the first and the second half of the record, and their z."""
    h = n_frames // 2
    out: dict = {"omega_per_ps": [], "omega_err_per_ps": [], "z": None, "reason": None}
    for part in (slice(0, h), slice(h, 2 * h)):
        x = pooled_series(series, kind, i, n_frames, part)
        fit, why = fit_mode(x, dt, errors)
        why = why or refusal(fit, h * dt)
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


def _seeds(series, kind, i, n_frames, dt, errors, pooled) -> dict:
    """Each realisation fitted alone; the Birge ratio of their scatter about the pooled fit."""
    w, e = [], []
    for s in series:
        fit, why = fit_mode(pooled_series([s], kind, i, n_frames), dt, errors)
        if why or refusal(fit, n_frames * dt) or not np.isfinite(fit.omega_err_per_ps):
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
