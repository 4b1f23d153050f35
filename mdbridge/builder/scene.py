"""Base-pair frames of a rod scene's t = 0 state, for the builder.

The rod is run through the `rodcore` Python module (build/python/) for a
tiny time with three output frames (the trajectory class below wants at
least three) and centerline, directors and internal fields asked for; frame
0 is the initial state itself. Base pair i takes the rod's frame at
s_i = i L / n_bp (d1, d2, d3 = x, y, z) and r(s_i) in A as its origin
(mdbridge.rodframes), through
mdbridge.analysis.BasePairTrajectory.from_rod_arrays (the path
build-md uses too), which also gives the period vector P = r(s + L) - r(s):
the box along which the strands close.
"""
from __future__ import annotations

import copy
import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from dna_models.errors import InputError

DEFAULT_BP = 158  # dna_planar's default (initial_conditions.cpp)


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


def n_bp_of_scene(scene: dict, path) -> int:
    ini = scene.get("initial", {})
    if ini.get("kind") == "dna_planar":
        return int(ini.get("bp", DEFAULT_BP))
    raise InputError(f"{path}: initial.kind = {ini.get('kind')!r}: the number of base pairs is "
                     "known only for kind = \"dna_planar\" (initial.bp)")


def frames_from_rod_output(out: dict, n_bp: int, source="rod") -> RodFrames:
    """RodFrames at the first output time from rodcore.run's result dict
    (at least 3 output frames)."""
    from mdbridge.analysis.trajectory import BasePairTrajectory
    missing = [k for k in ("time", "s", "centerline", "directors") if k not in out]
    if missing or "Gamma" not in out.get("fields", {}):
        raise InputError(f"{source}: rod output lacks {missing or ['fields/Gamma']}")
    traj = BasePairTrajectory.from_rod_arrays(out["time"], out["s"], out["centerline"],
                                              out["directors"], out["fields"]["Gamma"],
                                              n_bp, source=source)
    return RodFrames(origins=np.asarray(traj.origins[0]), R=np.asarray(traj.R[0]),
                     period=np.asarray(traj.period[0]))


def frames_from_scene(path) -> RodFrames:
    path = Path(path)
    try:
        scene = tomllib.loads(path.read_text())
    except OSError as e:
        raise InputError(f"{path}: cannot read scene ({e.strerror})") from e
    except tomllib.TOMLDecodeError as e:
        raise InputError(f"{path}: not valid TOML ({e})") from e
    n_bp = n_bp_of_scene(scene, path)
    try:
        import rodcore
    except ImportError:
        rodcore = None
    # the source folder rodcore/ imports as an empty namespace package when
    # the compiled module is not on the path
    if not hasattr(rodcore, "run"):
        raise InputError("the rodcore Python module is not built or not on the path: run "
                         "scripts/build.sh (it goes to build/python/) or use build/bin/dnarod")
    run_scene = copy.deepcopy(scene)
    out_cfg = run_scene.setdefault("output", {})
    out_cfg.update(t_end=1e-6, frames=3, fields=["internal", "centerline", "directors"])
    # initial.path (kind = "file") is relative to the scene file
    ini = run_scene.get("initial", {})
    if "path" in ini and not Path(ini["path"]).is_absolute():
        ini["path"] = str((path.parent / ini["path"]).resolve())
    try:
        out = rodcore.run(run_scene)
    except (ValueError, RuntimeError) as e:
        raise InputError(f"{path}: {e}") from e
    return frames_from_rod_output(out, n_bp, source=str(path))
