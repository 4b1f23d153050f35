"""The coarse-graining estimator: equilibrium step-parameter ensemble -> per-step
mean shape and 6x6 stiffness, m-step stiffness, continuum constants, each with its
error (docs/coarse-graining.md).

Order of work, each piece in its own module:
 1. equilibration stretch discarded (equilibration.py), minimum length checked
    against the autocorrelation times (mdbridge/stats.py);
 2. m-step composition of the steps (composition.py), windows containing an excluded
    step dropped;
 3. per window: mean, covariance, K = kT cov^-1 with the finite-sample correction
    (stiffness.py); the sequence's compliance average (mean covariance)^-1; continuum
    constants (continuum.py);
 4. the rod's K: the long-wavelength stiffness K(q -> 0) of the step parameters' compliance
    spectrum along the sequence (qstiffness.py), with every step the analysis defines, and
    again without the steps of opened base pairs (the opening rule's sensitivity);
 5. errors: moving-block bootstrap over frames of the whole of 2-4 (mdbridge/stats.py);
 6. checks: first half against second half, estimate against frames used;
 7. optional rest-shape correction of a pre-stressed (box-constrained) duplex
    (prestress.py).
Stiffness is in units of kT (the caller knows T); continuum constants in SI-like
units at the given temperature.
"""
from __future__ import annotations

import math

import numpy as np

from dna_models.errors import InputError

from mdbridge.geometry.analysis_base import AnalysisBase
from mdbridge.stats import integrated_time
from mdbridge.stats import block_length, block_starts, block_sums, replicate_moments, spread, weighted_moments
from .composition import compose
from .continuum import TWIST, contour_constants, physical_constants
from .ensemble import StepEnsemble
from .equilibration import equilibration_start
from .qstiffness import combined_error, fit_mode_time, long_wavelength
from .stiffness import bias_factor, mahalanobis_time

MIN_EFFECTIVE = 50   # independent frames required: the error of a stiffness element is then
                     # ~ sqrt(2 / N_eff) = 20 % and the bias correction below 20 %
P = 6


def longest_run(excluded: np.ndarray, closed: bool) -> int:
    """Longest stretch of consecutive usable steps (wrapping when closed)."""
    ok = ~np.asarray(excluded, dtype=bool)
    if ok.all():
        return len(ok)
    seq = np.concatenate([ok, ok]) if closed else ok
    best = run = 0
    for v in seq:
        run = run + 1 if v else 0
        best = max(best, run)
    return min(best, len(ok))


M_GRID = (1, 2, 3, 4, 5, 6, 7, 8, 10, 12, 15, 20, 25, 30, 40)


def default_m_values(n_steps: int, closed: bool, m_max: int | None = None, excluded=None) -> list[int]:
    """m on M_GRID up to m_max (and m_max itself), m_max = min(20, n_steps // 4) for a
    closed duplex (the box constraint suppresses long-wavelength fluctuations; keep m
    well below n_bp) and min(20, n_steps) for a linear one, and at most the longest
    stretch of usable steps."""
    cap = max(1, n_steps // 4) if closed else n_steps
    if excluded is not None:
        cap = min(cap, max(1, longest_run(excluded, closed)))
    m_max = min(20, cap) if m_max is None else m_max
    if m_max > cap:
        raise InputError(f"maximum coarse-graining length {m_max}: at most {cap} for this "
                         f"{'closed duplex (n_bp / 4)' if closed else 'duplex'} of {n_steps} steps "
                         "(and the longest stretch of steps without an opened base pair)")
    return sorted({m for m in M_GRID if m <= m_max} | {m_max})


def unwrap_twist(qm: np.ndarray, q1_windows_twist_sum: np.ndarray) -> np.ndarray:
    """Put an m-step's twist on the branch of the sum of its steps' twists (CEHS gives
    (-180, 180]; ten B-DNA steps twist by ~340 deg). Moving the twist by 360 k turns the
    mid-step frame by 180 k about z, so for odd k shift, slide, tilt and roll change
    sign: the parameters are then those of the mid-frame half-way along the true twist."""
    k = np.round((q1_windows_twist_sum - qm[..., TWIST]) / 360.0)
    out = qm.copy()
    out[..., TWIST] += 360.0 * k
    odd = (np.abs(k) % 2) == 1
    out[..., [0, 1, 3, 4]] = np.where(odd[..., None], -out[..., [0, 1, 3, 4]], out[..., [0, 1, 3, 4]])
    return out


def composite_series(q: np.ndarray, m_values, closed: bool, excluded: np.ndarray):
    """{m: (q_m (T, n_w, 6), first steps (n_w,))} of the windows free of excluded steps."""
    comp = compose(q, m_values, closed)
    csum = np.concatenate([q[..., TWIST], q[..., TWIST]], axis=1) if closed else q[..., TWIST]
    cexc = np.concatenate([excluded, excluded]) if closed else excluded
    out = {}
    for m, qm in comp.items():
        starts = np.arange(qm.shape[1])
        idx = starts[:, None] + np.arange(m)[None, :]
        tw_sum = csum[:, idx].sum(axis=-1)
        qm = unwrap_twist(qm, tw_sum)
        ok = ~cexc[idx].any(axis=1)
        if not ok.any():
            raise InputError(f"no window of {m} consecutive steps is free of excluded steps")
        out[m] = (qm[:, ok], starts[ok])
    return out


def _constants_of(mean, cov, T_K, n_eff, contour_A, sums=None):
    """Continuum constants of the pooled windows: window-averaged mean and covariance,
    segment length = the mean contour length (sum of the steps' mean rises); with
    sums = (mean (..., n_w, 2), cov (..., n_w, 2, 2)) of the windows' summed rise and
    twist, the contour constants too."""
    out = physical_constants(mean.mean(axis=-2), cov.mean(axis=-3), T_K, n_eff,
                             length_A=float(np.mean(contour_A)))
    if sums is not None:
        out.update(contour_constants(sums[0].mean(axis=-2), sums[1].mean(axis=-3), T_K, n_eff))
    return out


def _inv(c):
    """Inverse of each matrix of c (..., p, p); NaN for a singular one (a bootstrap replicate
    that kept too few frames of a window under the open-pair mask)."""
    c = np.asarray(c, dtype=float)
    try:
        return np.linalg.inv(c)
    except np.linalg.LinAlgError:
        flat = c.reshape((-1,) + c.shape[-2:])
        out = np.full_like(flat, np.nan)
        for k, m in enumerate(flat):
            if np.all(np.isfinite(m)) and np.linalg.matrix_rank(m) == m.shape[0]:
                out[k] = np.linalg.inv(m)
        return out.reshape(c.shape)


def _K_of(c, n):
    """Stiffness of each covariance c (..., 6, 6), bias-corrected for n samples."""
    K = _inv(c) * bias_factor(n, P)[..., :, None, None]
    return 0.5 * (K + np.swapaxes(K, -1, -2))


def _K_series(c, n):
    """The windows' compliance average: (mean covariance)^-1, bias-corrected with the
    pooled degrees of freedom (windows in series add compliances, not stiffnesses)."""
    K = _inv(c.mean(axis=-3)) * np.asarray(bias_factor(n, P))[..., None, None]
    return 0.5 * (K + np.swapaxes(K, -1, -2))


# a window closed in fewer than this fraction of the frames is left out, as an excluded
# step's are (its few closed frames would not hold a 6 x 6 covariance)
MIN_CLOSED_FRACTION = 0.5


def closed_filled(q: np.ndarray, open_frames: np.ndarray) -> np.ndarray:
    """q (T, n, 6) with each open (frame, step) set to that step's mean over its closed
    frames (the step's overall mean where it is never closed)."""
    if not open_frames.any():
        return q
    w = (~open_frames)[..., None].astype(float)
    n_closed = w.sum(axis=0)
    mean = np.where(n_closed > 0, (w * q).sum(axis=0) / np.maximum(n_closed, 1.0), q.mean(axis=0))
    return np.where(open_frames[..., None], mean[None], q)


def window_closed(open_frames: np.ndarray, starts: np.ndarray, m: int) -> np.ndarray:
    """(T, n_w): True where none of the m steps from each start is open in that frame
    (steps wrap around a closed duplex)."""
    n = open_frames.shape[1]
    idx = (starts[:, None] + np.arange(m)[None, :]) % n
    return ~open_frames[:, idx].any(axis=-1)


def closed_windows(qm: np.ndarray, starts: np.ndarray, open_frames: np.ndarray, m: int, source: str):
    """(qm, starts, keep) of the m-step windows closed in at least MIN_CLOSED_FRACTION of the
    frames; keep (T, n_w): the frames each keeps."""
    keep = window_closed(open_frames, starts, m)
    enough = keep.mean(axis=0) >= MIN_CLOSED_FRACTION
    if not enough.any():
        raise InputError(f"{source}: m = {m}: every window touches an open pair in more than "
                         f"{100 * (1 - MIN_CLOSED_FRACTION):g} % of the frames")
    return qm[:, enough], starts[enough], keep[:, enough]


def window_sums(q: np.ndarray, starts: np.ndarray, m: int) -> np.ndarray:
    """(T, n_w, 2): sum of rise and of twist over the m steps of each window
    (wrapping for a closed duplex: starts + m may pass n_steps)."""
    x = q[..., [2, TWIST]]
    x = np.concatenate([x, x], axis=1)
    C = np.concatenate([np.zeros_like(x[:, :1]), np.cumsum(x, axis=1)], axis=1)
    return C[:, starts + m] - C[:, starts]


class CoarseGrain(AnalysisBase):
    """Estimate shape, stiffness and continuum constants of a StepEnsemble.

        cg = CoarseGrain(ensemble, temperature_K=300.0).run()    # or .run(start, stop, step)
        cg.results["by_m"][1]["K"]      # (n_steps, 6, 6) kT/A^2, kT/(A deg), kT/deg^2

    An analysis of the one loop (mdbridge/geometry/analysis_base.py) that works on the
    whole trajectory at once (`_whole_trajectory`): its per-frame work is the step
    parameters, already in the ensemble, and everything it estimates (equilibration
    start, autocorrelation times, covariances, the block bootstrap) needs all the
    selected frames together.

    block: bootstrap block length in frames (None: from the autocorrelation; 1 treats
    frames as independent). discard: frames to drop at the start (None: the rule in
    equilibration.py). min_effective: independent frames required. progress, if given:
    progress("lengths analysed", done, total, "lengths") over the m values.
    """

    def __init__(self, ensemble: StepEnsemble, temperature_K: float, m_values=None,
                 m_rod: int | None = None, n_boot: int = 200, seed: int = 0, block: int | None = None,
                 discard: int | None = None, min_effective: float = MIN_EFFECTIVE,
                 convergence_points: int = 8, progress=None):
        super().__init__(ensemble)
        self.ens = ensemble
        self.progress = progress
        self.T_K = float(temperature_K)
        self.m_values = list(m_values) if m_values is not None else default_m_values(
            ensemble.n_steps, ensemble.closed, excluded=ensemble.excluded)
        self.m_values = sorted(set(self.m_values) | {1})       # per-step results always
        self.m_rod = int(m_rod) if m_rod is not None else max(self.m_values)
        if self.m_rod not in self.m_values:
            self.m_values = sorted(set(self.m_values) | {self.m_rod})
            default_m_values(ensemble.n_steps, ensemble.closed, max(self.m_values))
        self.n_boot = int(n_boot)
        self.rng = np.random.default_rng(seed)
        self.block = block
        self.discard = discard
        self.min_effective = float(min_effective)
        self.convergence_points = convergence_points

    _whole_trajectory = True

    def _conclude(self):
        ens = self.ens
        use = ~ens.excluded
        if not use.any():
            raise InputError(f"{ens.source}: every step is excluded (base pairs opened)")
        q_all = ens.q[self.frames]
        open_all = ens.open_frames[self.frames]
        # the open (step, frame)s carry no rod physics: where a whole-trajectory statistic
        # needs every frame (equilibration, correlation times, the q -> 0 modes) they stand
        # at their step's mean over its closed frames; the local estimates leave them out
        q_all = closed_filled(q_all, open_all)
        # 1. equilibration: sequence-averaged parameters of the usable steps
        if self.discard is None:
            t0, _ = equilibration_start(q_all[:, use].mean(axis=1))
            rule = "Chodera 2016: start maximising N_eff of the sequence-averaged step parameters"
        else:
            t0, rule = int(self.discard), "given"
        q = q_all[t0:]
        open_ = open_all[t0:]
        T = q.shape[0]
        if T < 10:
            raise InputError(f"{ens.source}: {T} frames after discarding {t0}; need far more "
                             f"(at least {math.ceil(2 * self.min_effective)}): give the trajectory "
                             "after the structure (e.g. md.tpr md.xtc), or a longer one")
        series = composite_series(q, self.m_values, ens.closed, ens.excluded)
        m_top = max(self.m_values)
        tau_steps = integrated_time(q[:, use])                     # (n_use, 6)
        tau_top = integrated_time(series[m_top][0])
        # slowest parameter, each parameter's tau the median over steps (a max over all
        # steps would pick up the ~30 % noise of single tau estimates)
        tau_max = float(max(np.median(tau_steps, axis=0).max(), np.median(tau_top, axis=0).max()))
        n_eff = T / (2.0 * tau_max)
        if n_eff < self.min_effective:
            need = math.ceil(2.0 * tau_max * self.min_effective) + t0
            raise InputError(
                f"{ens.source}: too few frames: {T} frames after discarding {t0} equilibration "
                f"frames are worth {n_eff:.1f} independent samples (slowest autocorrelation time "
                f"{tau_max:.1f} frames); at least {self.min_effective:g} are needed, i.e. about "
                f"{need} frames in total at this frame spacing")
        # the blocks also span the slowest mode of the q -> 0 fit (qstiffness.py)
        tau_modes = fit_mode_time(q, use, ens.closed)
        b = self.block if self.block is not None else block_length(max(tau_max, tau_modes), T)
        starts_boot = block_starts(T, b, self.n_boot, self.rng)
        half = T // 2
        W_half = np.zeros((2, T))
        W_half[0, :half] = 1.0
        W_half[1, half:] = 1.0
        n_conv = np.unique(np.linspace(min(T, max(2 * P + 10, T // self.convergence_points)), T,
                                       self.convergence_points).astype(int))
        W_conv = (np.arange(T)[None, :] < n_conv[:, None]).astype(float)

        by_m = {}
        for k, m in enumerate(self.m_values):
            if self.progress is not None:
                self.progress("lengths analysed", k, len(self.m_values), "lengths")
            qm, starts, keep = closed_windows(*series[m], open_, m, ens.source)
            by_m[m] = self._estimate(m, qm, starts, (starts_boot, b), W_half, W_conv, n_conv,
                                      q[:, :, 2].mean(axis=0), window_sums(q, starts, m), keep)
        lw = long_wavelength(q, use, ens.closed, (starts_boot, b), W_half)
        keep_rule = use & ~ens.opened
        by_rule = None
        if ens.opened[use].any() and keep_rule.sum() >= 2:
            by_rule = long_wavelength(q, keep_rule, ens.closed, (starts_boot, b))
        lw["K_q0_err"], lw["rule_spread"] = combined_error(lw, by_rule)
        res = {"discarded_frames": t0, "equilibration_rule": rule, "frames_used": T,
               "frames_total": self.n_frames, "tau_int_max_frames": tau_max,
               "tau_int_steps": tau_steps, "effective_samples": n_eff, "block_length": b,
               "tau_int_fit_modes_frames": tau_modes, "effective_samples_fit_modes": T / (2.0 * tau_modes),
               "n_boot": self.n_boot, "by_m": by_m, "m_rod": self.m_rod,
               "long_wavelength": lw, "rule": by_rule, "opened_steps": np.flatnonzero(ens.opened & use),
               "temperature_K": self.T_K, "used_steps": np.flatnonzero(use),
               "excluded_steps": np.flatnonzero(ens.excluded), "convergence_frames": n_conv,
               "open_step_frames": float(open_[:, use].mean()),
               "dt_ps": float(np.median(np.diff(self.times_ps))) if self.n_frames > 1 else 0.0}
        if self.progress is not None:
            self.progress("lengths analysed", len(self.m_values), len(self.m_values), "lengths")
        self.results.update(res)

    def _estimate(self, m, qm, starts, boot, W_half, W_conv, n_conv, rise, sums, keep):
        """One window length m. keep (T, n_w): the frames in which each window's steps are all
        closed; every moment of a window is over those frames only."""
        T = qm.shape[0]
        n = len(rise)
        contour = rise[(starts[:, None] + np.arange(m)[None, :]) % n].sum(axis=1)   # (n_w,) A
        T_w = keep.sum(axis=0)                                      # (n_w,) frames kept
        w = keep[..., None].astype(float)
        mean = (w * qm).sum(axis=0) / T_w[:, None]
        d = w * (qm - mean)
        cov = np.einsum("twi,twj->wij", d, d) / (T_w - 1)[:, None, None]
        tau2 = mahalanobis_time(qm, mean, cov, keep)                # (n_w,)
        n2 = T_w / (2.0 * tau2)
        if np.any(n2 <= P + 2):
            w = int(np.argmin(n2))
            need = math.ceil((P + 3) * 2.0 * tau2[w] * 2.0)
            raise InputError(
                f"{self.ens.source}: m = {m}, window from step {starts[w] + 1}: its {T} frames are worth "
                f"{n2[w]:.1f} independent samples of the 6x6 covariance (autocorrelation time of its "
                f"second moments {tau2[w]:.1f} frames); inverting it needs more than {P + 2}: use a "
                f"longer trajectory (about {need} frames), or smaller m (--m-max)")
        Kinv = np.linalg.inv(cov)

        K = 0.5 * (Kinv + np.swapaxes(Kinv, -1, -2)) * bias_factor(n2, P)[:, None, None]
        # the pooled covariance averages n_w windows, of which ~n_w / m do not overlap:
        # its degrees of freedom for the bias correction are ~N_eff max(1, n_w / m)
        n_pool = float(np.median(n2)) * max(1.0, len(starts) / m)
        sums_mean = (w * sums).sum(axis=0) / T_w[:, None]
        ds = w * (sums - sums_mean)
        sums_full = (sums_mean, np.einsum("twi,twj->wij", ds, ds) / (T_w - 1)[:, None, None])
        phys = _constants_of(mean, cov, self.T_K, n_pool, contour, sums_full)

        bm, bc = replicate_moments(qm, *boot, mask=keep)             # (B, n_w, 6), (B, n_w, 6, 6)
        bK = _K_of(bc, n2[None, :])
        bphys = _constants_of(bm, bc, self.T_K, n_pool, contour, replicate_moments(sums, *boot, mask=keep))
        # tangent correlation <cos Gamma> of the segments (static + dynamic bending); a window
        # left out of a frame stands at its mean over the frames kept
        cos_w = np.cos(np.radians(np.hypot(qm[..., 3], qm[..., 4])))                # (T, n_w)
        cos_w = np.where(keep, cos_w, (keep * cos_w).sum(axis=0) / T_w)
        cosG = cos_w.mean(axis=1)                                                   # (T,)
        L_nm = float(np.mean(contour)) / 10.0
        phys["bend_persistence_length_tangent"] = -L_nm / np.log(cosG.mean())
        bphys["bend_persistence_length_tangent"] = -L_nm / np.log(block_sums(cosG[:, None], *boot)[:, 0] / T)
        out = {"m": m, "first_step": starts,
               "mean": mean, "mean_err": spread(bm),
               "cov": cov, "K": K, "K_err": spread(bK), "tau2": tau2, "n_eff2": n2,
               "K_series": _K_series(cov, n_pool), "K_series_err": spread(_K_series(bc, n_pool)),
               "mean_avg": mean.mean(axis=0), "mean_avg_err": spread(bm.mean(axis=1)),
               # the replicates themselves: the m-step materials' errors are the spread of
               # rods built from them (cgrod.py)
               "K_series_boot": _K_series(bc, n_pool), "mean_avg_boot": bm.mean(axis=1),
               "physical": {k: float(v) for k, v in phys.items()},
               "physical_err": {k: float(spread(v)) for k, v in bphys.items()},
               "physical_boot": bphys, "n_eff_pooled": n_pool}
        out.update(self._subsets(qm, sums, keep, W_half, W_conv, n_conv, n2, n_pool, contour))
        return out

    def _subsets(self, qm, sums, keep, W_half, W_conv, n_conv, n2, n_pool, contour) -> dict:
        """The estimate on the record's two halves and on its first n frames (convergence)."""
        T = qm.shape[0]
        hm, hc = weighted_moments(qm, W_half, mask=keep)
        ok = np.all(n2[None, :] / 2.0 > P + 2)
        hK = _K_series(hc, n_pool / 2.0) if ok and n_pool / 2.0 > P + 2 else np.full_like(hc[:, 0], np.nan)
        hphys = (_constants_of(hm, hc, self.T_K, n_pool / 2.0, contour, weighted_moments(sums, W_half, mask=keep))
                 if n_pool / 2 > 4 else None)
        cm, cc = weighted_moments(qm, W_conv, mask=keep)
        okc = np.all(n2[None, :] * (n_conv[:, None] / T) > P + 2, axis=1)
        n_c = n_pool * n_conv / T
        cK = np.full_like(cc[:, 0], np.nan)
        okc &= n_c > P + 2
        if okc.any():
            cK[okc] = _K_series(cc[okc], n_c[okc])
        cphys = _constants_of(cm, cc, self.T_K, n_c if np.all(n_c > 4) else None, contour,
                              weighted_moments(sums, W_conv, mask=keep))
        return {"halves": {"K_series": hK, "mean_avg": hm.mean(axis=1),
                           "physical": None if hphys is None else {k: v for k, v in hphys.items()}},
                "convergence": {"frames": n_conv, "K_series": cK, "mean_avg": cm.mean(axis=1), "physical": cphys}}
