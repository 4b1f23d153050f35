"""Fourier-mode amplitudes of a closed periodic duplex, frame by frame: `ModeAnalysis`
(docs/modes.md, "The modes"). The same code for rod and MD: the input is a
`BasePairTrajectory`.

For each frame, with L = |P| the period's length, h = L / n the fiducial step and
s_i = i h, a field f_i along the duplex is written f(s) = sum_{n>=1} Re(c_n e^{i k_n s}),
k_n = 2 pi n / L, so c_n = (2 / n_bp) sum_i f_i e^{-i k_n s_i} (as
mdbridge/analysis/wavespeed.py's mode_amplitude). The fields:

  bend     the helical axis's displacement perpendicular to the period, resolved on two
           fixed laboratory directions e1, e2 (one complex c_n each) [A];
  twist    the twist density Omega3 = twist_i / h of each step, the closing step
           included (3DNA twist of consecutive frames, mdbridge.geometry.steps) [rad/A],
           each step's twist on the branch nearest the frame's mean twist: a broken step
           crossing 3DNA's +-180-degree cut between frames would otherwise enter every twist
           mode as a 360-degree spike;
  stretch  the rise of each step (3DNA rise) [A].

The axis. The one-turn window (mdbridge/analysis/axis.py) passes a bend mode n of the
158-bp, 15-turn duplex by 0.83, 0.59, 0.41 and 0.23 at n = 5, 8, 10, 12: no use for the
high modes. Here the axis point of base pair i is its origin minus the helical offset,
    a_i = o_i - d x_i - e y_i,
with x_i, y_i the base pair's own axes and (d, e) fitted to each frame by least squares
to the part of the origins the one-turn window removes (o_i - window(o)_i). A uniform
offset is thereby removed exactly and the axis keeps every mode n < the helical repeat
with response 1 (tests/python/test_analysis_modes.py plants a mode under a 1-A offset).
What remains is each base pair's own deviation from the mean offset, a noise that is
white along the duplex and fast in time: the floor of the spectral fit
(mdbridge/analysis/spectrum.py). At n = the helical repeat (the duplex's turns: 15 for 158
bp) every offset lands on the same mode; the modes stop below it.
"""
from __future__ import annotations

import numpy as np

from mdbridge.analysis.axis import helical_axis, mean_twist, one_turn_weights
from mdbridge.geometry.analysis_base import AnalysisBase
from mdbridge.geometry.steps import circular_mean_deg, step_parameters, unwrap_twist_deg

KINDS = ("bend", "twist", "stretch")
VARIANCE_UNIT = {"bend": "A^2", "twist": "rad^2/A^2", "stretch": "A^2"}
AMPLITUDE_UNIT = {"bend": "A", "twist": "rad/A", "stretch": "A"}


def helical_repeat(R: np.ndarray) -> int:
    """The duplex's number of helical turns (the mode where base-pair offsets land), from
    the mean twist of one frame's closed ring of frames R (n, 3, 3)."""
    return int(round(abs(mean_twist(R)) * len(R) / (2 * np.pi)))


def transverse_basis(e_axis: np.ndarray):
    """Two fixed laboratory unit vectors perpendicular to e_axis and to each other: e1 from
    the laboratory axis most nearly perpendicular to e_axis (the first of X, Y, Z among
    those within 1e-6: a box axis's round-off does not choose), e2 = e_axis x e1."""
    lab = np.eye(3)[np.argmin(np.abs(e_axis) + 1e-6 * np.arange(3))]
    e1 = lab - np.dot(lab, e_axis) * e_axis
    e1 /= np.linalg.norm(e1)
    return e1, np.cross(e_axis, e1)


def helical_offset(origins, R, period, weights) -> np.ndarray:
    """(d, e) [A]: the offset of the origins from the axis along the base pairs' own x and
    y axes, by least squares against what the one-turn window removes (module doc)."""
    r = (origins - helical_axis(origins, R, period, weights)[0]).ravel()
    B = np.stack([R[:, :, 0].ravel(), R[:, :, 1].ravel()], axis=1)
    return np.linalg.lstsq(B, r, rcond=None)[0]


def _fourier(f: np.ndarray, n_max: int) -> np.ndarray:
    """c_n, n = 1..n_max, of f (n_bp, ...) sampled at s_i = i L / n_bp (module doc)."""
    return 2.0 / f.shape[0] * np.fft.fft(f, axis=0)[1:n_max + 1]


def frame_modes(origins, R, period, n_max: int, e1, e2, weights, branch: bool = True):
    """One frame's mode amplitudes: bend (n_max, 2), twist (n_max,), stretch (n_max,) complex,
    and the helical offset (d, e). origins (n, 3) continuous along the strand, R (n, 3, 3),
    period (3,) with origin_{i+n} = origin_i + period. branch: each step's twist on the
    branch nearest the frame's circular-mean twist (geometry/steps.py unwrap_twist_deg), so
    that a broken step crossing 3DNA's +-180-degree cut is continuous in time; False keeps
    3DNA's branch."""
    n = len(origins)
    d, e = helical_offset(origins, R, period, weights)
    axis = origins - d * R[:, :, 0] - e * R[:, :, 1]
    u = np.stack([axis @ e1, axis @ e2], axis=1)
    o_next = np.roll(origins, -1, axis=0)
    o_next[-1] += period
    steps = step_parameters(R, origins, np.roll(R, -1, axis=0), o_next)
    h = np.linalg.norm(period) / n
    twist_deg = unwrap_twist_deg(steps[:, 5], circular_mean_deg(steps[:, 5])) if branch else steps[:, 5]
    twist_density = np.radians(twist_deg) / h
    rise = steps[:, 2]
    return (_fourier(u, n_max), _fourier(twist_density, n_max), _fourier(rise, n_max),
            np.array([d, e]))


class ModeAnalysis(AnalysisBase):
    """The mode amplitudes of every frame of a closed periodic duplex.

    trajectory: a BasePairTrajectory; n_max: the highest mode (default: one below the
    helical repeat). Results: times_ps (T,), n (n_max,), k_per_A, length_A, n_bp,
    helical_repeat, e_axis, e1, e2, bend (T, n_max, 2), twist (T, n_max), stretch
    (T, n_max) complex amplitudes, helical_offset_A (T, 2)."""

    def __init__(self, trajectory, n_max: int | None = None, verbose: bool = False):
        super().__init__(trajectory, verbose=verbose)
        self.n_max = n_max

    def _prepare(self):
        tr = self._trajectory
        f0 = self.frames[0]
        P0 = np.asarray(tr.period[f0], float)
        self._e_axis = P0 / np.linalg.norm(P0)
        self._e1, self._e2 = transverse_basis(self._e_axis)
        self._weights = one_turn_weights(mean_twist(tr.R[f0]), tr.n_bp)
        self._repeat = helical_repeat(tr.R[f0])
        n_max = self.n_max if self.n_max is not None else self._repeat - 1
        if n_max < 1 or n_max >= tr.n_bp // 2:
            from dna_models.errors import InputError
            raise InputError(f"{tr.source}: modes 1..{n_max} asked of {tr.n_bp} base pairs and "
                             f"{self._repeat} helical turns: allowed 1 <= n_max < n_bp / 2")
        self._n_max = n_max
        T = self.n_frames
        self._bend = np.empty((T, n_max, 2), complex)
        self._twist = np.empty((T, n_max), complex)
        self._stretch = np.empty((T, n_max), complex)
        self._offset = np.empty((T, 2))

    def _single_frame(self):
        tr, t, i = self._trajectory, self._frame, self._frame_index
        self._bend[i], self._twist[i], self._stretch[i], self._offset[i] = frame_modes(
            np.asarray(tr.origins[t], float), np.asarray(tr.R[t], float), np.asarray(tr.period[t], float),
            self._n_max, self._e1, self._e2, self._weights)

    def _conclude(self):
        tr, r = self._trajectory, self.results
        length = float(np.mean(np.linalg.norm(np.asarray(tr.period)[self.frames], axis=1)))
        n = np.arange(1, self._n_max + 1)
        r.source = tr.source
        r.times_ps = np.asarray(self.times_ps, float)
        r.n = n
        r.length_A = length
        r.k_per_A = 2 * np.pi * n / length
        r.n_bp = tr.n_bp
        r.helical_repeat = self._repeat
        r.e_axis, r.e1, r.e2 = self._e_axis, self._e1, self._e2
        r.bend, r.twist, r.stretch = self._bend, self._twist, self._stretch
        r.helical_offset_A = self._offset
