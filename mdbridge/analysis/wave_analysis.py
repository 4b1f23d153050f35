"""`WaveAnalysis`: the one comparison analysis, run identically on rod and MD.

An analysis of the one loop (mdbridge/geometry/analysis_base.py): `_prepare` (the
one-turn axis window), `_single_frame` (the helical axis of one frame), `_conclude`
(displacement field, wave speed by two estimators, planarity); all results in
`results`. Input is a `BasePairTrajectory`, built from a rod output file
(`BasePairTrajectory.from_rod_h5`) or from an MD universe
(`BasePairTrajectory.from_universe`) -- nothing below knows which.

Conventions: x_i = i |P| / n is the fiducial axial position of base pair i [A] (P the
period vector at t = 0); k = 2 pi / |P| the fundamental; speeds are laboratory speeds
along the axis in A/ps. u(s, t) is the displacement of the axis point of base pair i,
perpendicular to P, with the mean over s removed (rigid translation is not a wave), and
resolved on e_in (the plane of the initial disturbance, which contains the axis) and
e_out = e_axis x e_in.
"""
from __future__ import annotations

import numpy as np

from mdbridge.analysis.axis import helical_axis, mean_twist, one_turn_weights, window_response
from mdbridge.analysis.planarity import planarity
from mdbridge.geometry.analysis_base import AnalysisBase
from mdbridge.geometry.trajectory import BasePairTrajectory
from mdbridge.analysis.mode_error import refusal
from mdbridge.analysis.wavespeed import fit_wave_speed, mode_amplitude, phase_velocity


def transverse(axis: np.ndarray, e_axis: np.ndarray) -> np.ndarray:
    """Axis points (T, n, 3) -> displacement perpendicular to e_axis, mean over s removed."""
    d = axis - axis.mean(axis=1, keepdims=True)
    return d - np.einsum("tix,x->ti", d, e_axis)[..., None] * e_axis


def initial_plane_direction(u_perp: np.ndarray, times: np.ndarray, n_early: int = 5) -> np.ndarray:
    """In-plane direction of the initial disturbance: from the t = 0 displacement, or from the
    early velocity when the rod starts straight (A = 0, A_v != 0). A straight-line fit
    u(t) = u0 + v (t - t0) over the first frames separates the two; the larger of |u0| and
    |v| (t_K - t0) wins and its principal direction (SVD over base pairs) is e_in."""
    K = min(n_early, len(times))
    tt = times[:K] - times[0]
    X = np.column_stack([np.ones(K), tt])
    coef = np.linalg.lstsq(X, u_perp[:K].reshape(K, -1), rcond=None)[0]
    u0, v = coef[0].reshape(-1, 3), coef[1].reshape(-1, 3) * (tt[-1] if K > 1 else 0.0)
    field = u0 if np.linalg.norm(u0) >= np.linalg.norm(v) else v
    e_in = np.linalg.svd(field, full_matrices=False)[2][0]
    # The SVD's sign is arbitrary; fix it (largest lab component positive) so that rod
    # and MD of the same scene get the same e_in and their u_in can be compared by sign.
    return e_in if e_in[np.argmax(np.abs(e_in))] > 0 else -e_in


class WaveAnalysis(AnalysisBase):
    """The wave of a rod or MD trajectory: WaveAnalysis(traj).run(start, stop, step).results
    (docs/analysis.md lists the results)."""

    def __init__(self, traj: BasePairTrajectory, in_plane=None, offset: bool = True,
                 n_boot: int = 200, verbose: bool = False):
        """traj: the base-pair trajectory; in_plane: a lab vector in the plane of the initial
        disturbance (from the scene), or None to take it from the first frames; offset: fit the
        static k-mode deformation in the wave fit; n_boot: bootstrap replicates."""
        super().__init__(traj, verbose)
        self.in_plane = None if in_plane is None else np.asarray(in_plane, float)
        self.offset = offset
        self.n_boot = n_boot

    def _prepare(self):
        tr = self._trajectory
        t0 = self.frames[0]
        self._weights = one_turn_weights(mean_twist(tr.R[t0]), tr.n_bp)  # one window for all frames
        self._axis = np.empty((self.n_frames, tr.n_bp, 3))

    def _single_frame(self):
        tr, t = self._trajectory, self._frame
        self._axis[self._frame_index] = helical_axis(tr.origins[t], tr.R[t], tr.period[t], self._weights)[0]

    def _conclude(self):
        tr, res = self._trajectory, self.results
        times = self.times_ps
        P0 = tr.period[self.frames[0]]
        length = float(np.linalg.norm(P0))
        e_axis = P0 / length
        n = tr.n_bp
        k = 2 * np.pi / length
        u_perp = transverse(self._axis, e_axis)
        e_in = self.in_plane if self.in_plane is not None else initial_plane_direction(u_perp, times)
        e_in = e_in - np.dot(e_in, e_axis) * e_axis
        e_in /= np.linalg.norm(e_in)
        e_out = np.cross(e_axis, e_in)
        u_in = u_perp @ e_in
        u_out = u_perp @ e_out
        c = mode_amplitude(u_in)

        res.source = tr.source
        res.times_ps = times
        res.x_A = np.arange(n) * length / n
        res.length_A = length
        res.k_per_A = k
        res.axis = self._axis
        res.axis_weights = self._weights
        res.axis_window_bp = float(len(self._weights) - 2 + 2 * self._weights[0] / self._weights[1]) \
            if len(self._weights) > 1 else 1.0
        res.axis_window_response = window_response(self._weights, 2 * np.pi / n)
        res.e_axis, res.e_in, res.e_out = e_axis, e_in, e_out
        res.u_in, res.u_out = u_in, u_out
        res.mode_amplitude = c
        res.wave, res.wave_check = self._fit(times, c, k, length)
        res.planarity = planarity(u_in, u_out)

    def _fit(self, times, c, k, length):
        """Both estimators, or speed None with the reason when there is no wave to measure
        or the record is too short for one (mode_error.refusal: the workflow's rule)."""
        reason = None
        if np.max(np.abs(c)) < 1e-9 * length:
            reason = "no displacement in the k = 2 pi / L mode (rod at rest?)"
        elif len(times) < 8:
            reason = f"only {len(times)} frames; the wave-speed fit needs at least 8"
        else:
            wave = fit_wave_speed(times, c, k, offset=self.offset, n_boot=self.n_boot)
            reason = refusal(wave, float(times[-1] - times[0]))
        if reason:
            none = {"speed_A_per_ps": None, "speed_err_A_per_ps": None, "reason": reason}
            return dict(none), dict(none)
        return wave, phase_velocity(times, c, k)

    def summary(self) -> dict:
        """JSON-ready scalars of the results."""
        r = self.results
        return {"source": r.source, "n_frames": len(r.times_ps), "n_bp": len(r.x_A),
                "t_start_ps": float(r.times_ps[0]), "t_end_ps": float(r.times_ps[-1]),
                "length_A": r.length_A, "axis_window_bp": r.axis_window_bp,
                "axis_window_response": r.axis_window_response,
                "wave_speed_A_per_ps": r.wave["speed_A_per_ps"],
                "wave_speed_err_A_per_ps": r.wave["speed_err_A_per_ps"],
                "wave_fit": {k: v for k, v in r.wave.items()},
                "wave_speed_check_A_per_ps": r.wave_check.get("speed_A_per_ps"),
                "wave_check": dict(r.wave_check),
                "planarity": r.planarity["planarity"],
                "plane_angle_deg": r.planarity["plane_angle_deg"],
                "max_abs_plane_angle_deg": float(np.nanmax(np.abs(r.planarity["angle_deg"]))),
                "in_plane_amplitude_A": float(np.max(r.planarity["in_rms_A"]) * np.sqrt(2))}
