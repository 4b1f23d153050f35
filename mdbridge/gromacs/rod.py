"""The rod side of an MD build: the rod run that sizes the box and gives t = 0.

The same run gives (a) the rod's state at t = 0 (base-pair frames and the
rigid-body velocities of the cross-sections) and (b) the rod's own prediction
of how far the centerline will wander across the helix axis during the MD,
which sizes the box (box.py). `dnarod build-md` takes that run either from a
rod output file the workflow already made (`--rod ROD.h5`: `rod_for_md`) or runs
the scene for the MD's length (`md_scene`, through mdbridge.rodrun.run_scene)."""
from __future__ import annotations

import copy
import math

import numpy as np

from dna_models.errors import InputError
from dna_models.units import Units
from mdbridge.rodrun import RodRun, scene_bp_turns

ROD_FRAMES = 101   # output frames of the sizing run: enough to catch the largest excursion


def md_scene(scene: dict, *, md_ps: float, bp: int | None = None, turns: int | None = None,
             units: Units | None = None, source="scene") -> dict:
    """A copy of SCENE that runs for the MD length and writes what the build needs."""
    u = units or Units.paper()
    s = copy.deepcopy(scene)
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
    out = s.setdefault("output", {})
    out.update({"t_end": u.time_to_rod(md_ps) if md_ps > 0 else 0.0,
                "frames": ROD_FRAMES if md_ps > 0 else 1,
                "fields": ["internal", "centerline", "directors"]})
    return s


def rod_for_md(run: RodRun, *, md_ps: float, scene: dict, units: Units | None = None) -> RodRun:
    """The frames of an existing rod run that cover the MD (0 <= t <= md_ps), checked to
    be a run of SCENE (resolved, mdbridge.rodrun.resolve_scene: every [rod], [material]
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
