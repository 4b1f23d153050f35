"""The rod layer: one rod run through rodcore and its HDF5 output (`run`), the scene as a
dict -- read, resolved, made, edited, written (`scene`) --, rod <-> base-pair frames
(`frames`), DNA as a rod material (`material/`). It imports only the ground floor
(mdbridge.geometry, mdbridge.stats, mdbridge.jsonio) and dna_models (docs/architecture.md).

    from mdbridge.rod import RodRun, run_scene
    traj = RodRun.read("rod.h5").trajectory(n_bp=158)     # a BasePairTrajectory
"""
from .run import RodRun, run_scene
from .scene import load_scene, scene_bp_turns, scene_n_bp, write_scene

__all__ = ["RodRun", "load_scene", "run_scene", "scene_bp_turns", "scene_n_bp", "write_scene"]
