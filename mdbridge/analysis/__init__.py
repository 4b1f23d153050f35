"""Comparison analysis of rod and MD trajectories: one analysis, two inputs.

Both the rod (an HDF5 output of rodsim) and an all-atom MD trajectory become a
`BasePairTrajectory` (base-pair origins and frames over time, plus the period
vector of the closed, periodic duplex). `WaveAnalysis` then runs the same code
on either: helical axis (one-turn window), transverse displacement u(s, t),
wave speed (two estimators), planarity. See docs/analysis.md.
"""
from mdbridge.geometry import trajectory as _trajectory
from mdbridge.md.realisation import read_rod_trajectory
from mdbridge.analysis.axis import helical_axis, one_turn_weights, mean_twist
from mdbridge.analysis.wavespeed import fit_wave_speed, phase_velocity, mode_amplitude
from mdbridge.analysis.planarity import planarity
from mdbridge.analysis.superpose import kabsch_rmsd
from mdbridge.analysis.wave_analysis import WaveAnalysis


class BasePairTrajectory(_trajectory.BasePairTrajectory):
    """mdbridge.geometry's BasePairTrajectory, where users have always imported it, with the
    reader of rod output files, which geometry (below the rod layer) cannot import: the
    registry of inputs is mdbridge/md/realisation.py."""

    @classmethod
    def from_rod_h5(cls, path, n_bp: int, units=None) -> _trajectory.BasePairTrajectory:
        """A rodsim output file (docs/contracts.md: time, s, fields/Gamma, centerline,
        directors) as the trajectory of its n_bp base pairs at s_i = i L / n_bp."""
        return read_rod_trajectory(path, n_bp, units)


__all__ = ["BasePairTrajectory", "helical_axis", "one_turn_weights", "mean_twist",
           "fit_wave_speed", "phase_velocity", "mode_amplitude", "planarity",
           "kabsch_rmsd", "WaveAnalysis"]
