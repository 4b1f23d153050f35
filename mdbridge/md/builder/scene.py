"""Base-pair frames of a rod scene's t = 0 state, for the builder.

The rod is run through mdbridge.rod.run.run_scene for a
tiny time with three output frames (the trajectory class below wants at
least three) and centerline, directors and internal fields asked for; frame
0 is the initial state itself. Base pair i takes the rod's frame at
s_i = i L / n_bp (d1, d2, d3 = x, y, z) and r(s_i) in A as its origin
(mdbridge.rod.frames), through
mdbridge.analysis.BasePairTrajectory.from_rod (the path
build-md uses too), which also gives the period vector P = r(s + L) - r(s):
the box along which the strands close.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from dna_models.errors import InputError
from mdbridge.rod.run import RodRun, run_scene
from mdbridge.rod.scene import load_scene, scene_n_bp, set_output, with_absolute_paths


@dataclass(frozen=True)
class RodFrames:
    origins: np.ndarray   # (n_bp, 3) A
    R: np.ndarray         # (n_bp, 3, 3) columns d1, d2, d3
    period: np.ndarray    # (3,) A, r(s + L) - r(s)

    @property
    def box(self) -> np.ndarray:
        """Orthorhombic box for periodic_box: |P| along the lab axis P lies on."""
        P = self.period
        axis = int(np.argmax(np.abs(P)))
        off = np.delete(P, axis)
        if np.linalg.norm(off) > 1e-6 * np.linalg.norm(P):
            raise InputError(f"the rod's period vector {np.round(P, 4).tolist()} A is not along a "
                             "lab axis; an orthorhombic box cannot hold it (give --box along z for "
                             "a rod along z, or rotate the scene)")
        box = np.zeros(3)
        box[axis] = abs(P[axis])
        return box


def frames_from_rod_output(out, n_bp: int, source="rod") -> RodFrames:
    """RodFrames at the first output time of a rod run (a RodRun, or rodcore.run's
    result dict; at least 3 output frames)."""
    from mdbridge.geometry.trajectory import BasePairTrajectory
    run = out if isinstance(out, RodRun) else RodRun.from_result(out, source=source)
    traj = BasePairTrajectory.from_rod(run, n_bp)
    return RodFrames(origins=np.asarray(traj.origins[0]), R=np.asarray(traj.R[0]),
                     period=np.asarray(traj.period[0]))


def frames_from_scene(path) -> RodFrames:
    path = Path(path)
    scene = load_scene(path)
    n_bp = scene_n_bp(scene, path)
    # the scene's files (initial.path, material_file, ...) are relative to the scene file
    sc = set_output(with_absolute_paths(scene, path), t_end=1e-6, frames=3,
                    fields=["internal", "centerline", "directors"])
    return frames_from_rod_output(run_scene(sc, source=str(path)), n_bp, source=str(path))
