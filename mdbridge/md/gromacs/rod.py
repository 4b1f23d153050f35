"""The rod side of an MD build: the rod run that sizes the box and gives t = 0.

The same run gives (a) the rod's state at t = 0 (`RodInitial`: base-pair frames and
the rigid-body velocities of the cross-sections, sampled by mdbridge.rod.frames) and (b) the rod's own prediction
of how far the centerline will wander across the helix axis during the MD,
which sizes the box (box.py). `dnarod build-md` takes that run either from a
rod output file the workflow already made (`--rod ROD.h5`: `rod_for_md`) or runs
the scene for the MD's length (`md_scene`, through mdbridge.rod.run.run_scene)."""
from __future__ import annotations

import copy
import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from dna_models.errors import InputError
from dna_models.units import Units
from mdbridge.rod.frames import period_vector
from mdbridge.rod.run import RodRun
from mdbridge.rod.scene import _beside, scene_bp_turns, set_output

from .defaults import MD_PS

ROD_FRAMES = 101   # output frames of the sizing run: enough to catch the largest excursion
DEFAULT_MD_PS = MD_PS   # the paper's MD length (Sec 6.1), when no rod run is given (defaults.py)


def md_length_ps(run: RodRun | None, *, dt_ps: float, units: Units | None = None) -> float:
    """build-md's MD length when none is asked for: the whole rod run it is given, in whole
    MD steps of DT_PS that stay inside it (a scene's t_end of 637.2 tau is 599.97 ps, not
    600), or DEFAULT_MD_PS when build-md runs the rod itself."""
    if run is None:
        return DEFAULT_MD_PS
    u = units or Units.paper()
    run.require("time")
    assert run.time is not None
    covered_ps = float(u.time_to_ps(run.time[-1] - run.time[0]))
    return math.floor(covered_ps / dt_ps * (1 + 1e-12)) * dt_ps


@dataclass
class RodInitial:
    """The rod at t = 0 sampled at the base pairs s_i = i L / n_bp, in A, ps, rad."""
    origins_A: np.ndarray        # (n, 3) r(s_i)
    R: np.ndarray                # (n, 3, 3) columns d1, d2, d3 (= bp x, y, z axes)
    gamma_lab_A_ps: np.ndarray   # (n, 3)
    omega_lab_rad_ps: np.ndarray  # (n, 3)
    closure_length_A: float      # |r(s + L) - r(s)|

    @property
    def n_bp(self) -> int:
        return len(self.origins_A)


def rod_initial_from_run(run, n_bp: int, units: Units | None = None, frame: int = 0):
    """RodInitial (at output frame FRAME, default t = 0) and the centerline over the whole
    run in A (T, N, 3), from a rod run. Base pair i sits on grid point i N / n_bp, so no
    interpolation is involved; the sampling is mdbridge.rod.frames' (RodRun.trajectory,
    RodRun.bp_lab_velocities)."""
    u = units or Units.paper()
    run.require("fields/gamma", "fields/omega")
    traj = run.trajectory(n_bp, u)
    g, w = run.bp_lab_velocities(n_bp, frame=frame)
    rod = RodInitial(origins_A=traj.origins[frame], R=traj.R[frame],
                     gamma_lab_A_ps=u.velocity_to_A_per_ps(g),
                     omega_lab_rad_ps=u.angular_velocity_to_rad_per_ps(w),
                     closure_length_A=float(np.linalg.norm(traj.period[frame])))
    return rod, u.length_to_A(np.asarray(run.centerline, float))


def md_scene(scene: dict, *, md_ps: float, bp: int | None = None, turns: int | None = None,
             units: Units | None = None, source="scene", n_bp: int | None = None) -> dict:
    """A copy of SCENE that runs for the MD length and writes what the build needs.
    n_bp: the base pairs of a sequence-dependent scene (scene_sequence); otherwise they
    come from the dna_planar kind (bp, turns override it)."""
    u = units or Units.paper()
    s = copy.deepcopy(scene)
    if n_bp is None:
        ini = s.setdefault("initial", {})
        if bp is not None:
            ini["bp"] = int(bp)
        if turns is not None:
            ini["turns"] = int(turns)
        n_bp, _ = scene_bp_turns(s, source)
    rod = s.setdefault("rod", {})
    # base pair i must be grid point i N / n_bp (dna_planar's default N is n_bp)
    if "points" in rod and int(rod["points"]) % n_bp:
        rod["points"] = n_bp * math.ceil(int(rod["points"]) / n_bp)
    return set_output(s, t_end=u.time_to_rod(md_ps) if md_ps > 0 else 0.0,
                      frames=ROD_FRAMES if md_ps > 0 else 1, fields=["internal", "centerline", "directors"])


def rod_for_md(run: RodRun, *, md_ps: float, scene: dict, units: Units | None = None) -> RodRun:
    """The frames of an existing rod run that cover the MD (0 <= t <= md_ps), checked to
    be a run of SCENE (resolved, mdbridge.rod.scene.resolve_scene: every [rod], [material]
    and [initial] value the file records must be the scene's) that starts at t = 0 and
    lasts at least as long as the MD."""
    u = units or Units.paper()
    run.require("time", "s", "fields/gamma", "fields/omega", "fields/Gamma", "centerline", "directors")
    differ = []
    for section in ("rod", "material", "initial"):
        for key, want in scene.get(section, {}).items():
            got = run.attrs.get(f"{section}.{key}")
            if got is None or isinstance(want, str) or isinstance(got, str):
                if got is not None and str(got) != str(want):
                    differ.append(f"{section}.{key} = {got!r} (scene: {want!r})")
                continue
            if np.shape(got) != np.shape(want) or not np.allclose(got, want, rtol=1e-12, atol=0):
                differ.append(f"{section}.{key} = {np.round(got, 6).tolist()} "
                              f"(scene: {np.round(want, 6).tolist()})")
    if differ:
        raise InputError(f"{run.source}: not a run of this scene: " + "; ".join(differ))
    assert run.time is not None  # RodRun.read: a rod output file always has time
    if float(run.time[0]) != 0.0:
        raise InputError(f"{run.source}: the first frame is at t = {u.time_to_ps(run.time[0]):g} ps; "
                         "build-md needs the rod's state at t = 0")
    covered_ps = float(u.time_to_ps(run.time[-1]))
    if covered_ps < md_ps * (1 - 1e-9):
        why = "" if run.complete else " (the run stopped early: see its rodsim.log)"
        raise InputError(f"{run.source}: the rod run covers {covered_ps:g} ps, the MD {md_ps:g} ps"
                         f"{why}; the box is sized from the rod over the whole MD: run the rod at "
                         "least as long (workflow: rod.run_ps >= md.run_ps), or give a smaller --ps")
    return run.until(u.time_to_rod(md_ps))


# -- sequence-dependent scenes (`dnarod dna-rod`) ----------------------------------
def scene_sequence(scene: dict, scene_path) -> str | None:
    """The DNA of a sequence-dependent scene: the `sequence` attribute of its
    `[material] material_file` (written by `dnarod dna-rod`, docs/scenes.md). None for
    a scene without a material file (the paper's uniform dna_planar scenes)."""
    from dna_models.sequence import validate
    mf = scene.get("material", {}).get("material_file")
    if mf is None:
        return None
    path = _beside(scene_path, mf)
    import h5py
    try:
        with h5py.File(path, "r") as f:
            seq = f.attrs.get("sequence")
    except OSError as e:
        raise InputError(f"{scene_path}: [material] material_file = {mf!r}: cannot read {path} ({e})") from None
    if seq is None:
        raise InputError(f"{path}: no 'sequence' attribute: build-md builds the DNA a material file records "
                         "(`dnarod dna-rod` writes it); a material file without one has no DNA to build")
    return validate(seq.decode() if isinstance(seq, bytes) else str(seq), f"{path}: attribute 'sequence'")


def lab_rotation_to_axis(run: RodRun, axis: int = 1) -> np.ndarray:
    """The rotation Q (3, 3) that turns the rod's period vector at t = 0 (P = int_0^L
    d_k Gamma_k ds, the end-to-end vector of one period) onto the lab axis `axis`
    (GROMACS boxes here are orthorhombic, so the helix must run along x, y or z). A
    dna-rod scene starts with the frame at s = 0 equal to the lab frame, and its
    helix axis is wherever the sequence's closed shape puts it. The smallest rotation."""
    run.require("s", "directors", "fields/Gamma")
    s = np.asarray(run.s, float)   # present: require() raised otherwise
    assert run.directors is not None
    P = period_vector(run.directors[0], run.fields["Gamma"][0], float(s[1] - s[0]))
    a = P / np.linalg.norm(P)
    e = np.zeros(3)
    e[axis] = 1.0
    v, c = np.cross(a, e), float(a @ e)
    if np.linalg.norm(v) < 1e-15:
        if c > 0:
            return np.eye(3)
        # antiparallel: a half turn about any axis normal to e
        n = np.eye(3)[(axis + 1) % 3]
        return 2 * np.outer(n, n) - np.eye(3)
    V = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
    return np.eye(3) + V + V @ V / (1 + c)


def rotate_rod(rod, centerline_A, Q):
    """RodInitial and centerline (T, N, 3) seen in the lab rotated by Q (a rigid rotation
    of the whole rod run: positions, frames and velocities)."""
    return (dataclasses.replace(rod, origins_A=rod.origins_A @ Q.T, R=np.einsum("ij,njk->nik", Q, rod.R),
                                gamma_lab_A_ps=rod.gamma_lab_A_ps @ Q.T, omega_lab_rad_ps=rod.omega_lab_rad_ps @ Q.T),
            centerline_A @ Q.T)
