"""3DNA-exact base-pair geometry: base frames, base-pair frames, step and
base-pair parameters, and their inverses (see docs/geometry.md); SE(3) steps (`se3`);
the trajectory of base-pair frames that rod and MD both become (`BasePairTrajectory`).

    from mdbridge.geometry import step_parameters, frames_from_steps, BasePairFrames
"""
from .steps import (STEP_NAMES, BP_NAMES, cehs, step_parameters, step_parameters_along,
                    step_transform, next_frame, frames_from_steps, flip_strand_II,
                    base_pair_parameters, base_pair_frames, base_frames_from_pair)
from .basefit import fit_frames
from .pbc import minimum_image
from .structure import BasePairFrames, read_pairs_file
from .trajectory import BasePairTrajectory

__all__ = ["STEP_NAMES", "BP_NAMES", "cehs", "step_parameters", "step_parameters_along",
           "step_transform", "next_frame", "frames_from_steps", "flip_strand_II",
           "base_pair_parameters", "base_pair_frames", "base_frames_from_pair",
           "fit_frames", "minimum_image", "BasePairFrames", "read_pairs_file", "BasePairTrajectory"]
