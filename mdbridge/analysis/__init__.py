"""Comparison analysis of rod and MD trajectories: one analysis, two inputs.

Both the rod (an HDF5 output of rodsim) and an all-atom MD trajectory become a
`BasePairTrajectory` (base-pair origins and frames over time, plus the period
vector of the closed, periodic duplex). `WaveAnalysis` then runs the same code
on either: helical axis (one-turn window), transverse displacement u(s, t),
wave speed (two estimators), planarity. See docs/analysis.md.
"""
# BasePairTrajectory lives on the ground floor (mdbridge.geometry); it is re-exported here,
# where users have always imported it. Importing the rod layer lets from_rod_h5 read rod files.
import mdbridge.rod  # noqa: F401
from mdbridge.geometry.trajectory import BasePairTrajectory
from mdbridge.analysis.axis import helical_axis, one_turn_weights, mean_twist
from mdbridge.analysis.wavespeed import fit_wave_speed, phase_velocity, mode_amplitude
from mdbridge.analysis.planarity import planarity
from mdbridge.analysis.superpose import kabsch_rmsd
from mdbridge.analysis.wave_analysis import WaveAnalysis

__all__ = ["BasePairTrajectory", "helical_axis", "one_turn_weights", "mean_twist",
           "fit_wave_speed", "phase_velocity", "mode_amplitude", "planarity",
           "kabsch_rmsd", "WaveAnalysis"]
