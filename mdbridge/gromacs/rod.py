"""The rod side of an MD build: run the scene through rodcore for the MD's length.

The same run gives (a) the rod's state at t = 0 (base-pair frames and the
rigid-body velocities of the cross-sections) and (b) the rod's own prediction
of how far the centerline will wander across the helix axis during the MD,
which sizes the box (box.py)."""
from __future__ import annotations

import copy
import math
import tomllib
from pathlib import Path

from dna_models.errors import DnarodError, InputError
from dna_models.units import Units

ROD_FRAMES = 101   # output frames of the sizing run: enough to catch the largest excursion


def load_scene(path: Path) -> dict:
    path = Path(path)
    try:
        with open(path, "rb") as f:
            return tomllib.load(f)
    except FileNotFoundError:
        raise InputError(f"{path}: scene file not found") from None
    except tomllib.TOMLDecodeError as e:
        raise InputError(f"{path}: not valid TOML ({e})") from None


def scene_bp_turns(scene: dict, path) -> tuple[int, int]:
    """Base pairs and helical turns of a DNA scene ([initial] kind = "dna_planar")."""
    ini = scene.get("initial", {})
    if ini.get("kind") != "dna_planar":
        raise InputError(f"{path}: [initial] kind = {ini.get('kind')!r}; build-md needs a DNA "
                         "scene (kind = \"dna_planar\" with bp and turns), e.g. "
                         "workflows/scenes/dna158.toml")
    bp, turns = ini.get("bp", 158), ini.get("turns", 15)
    if not (isinstance(bp, (int, float)) and bp == int(bp) and bp >= 4):
        raise InputError(f"{path}: [initial] bp = {bp!r}: need an integer >= 4")
    if not (isinstance(turns, (int, float)) and turns == int(turns) and turns >= 1):
        raise InputError(f"{path}: [initial] turns = {turns!r}: need an integer >= 1 (the "
                         "ligated helix must close on itself: twist = 360 turns / bp)")
    return int(bp), int(turns)


def md_scene(scene: dict, *, md_ps: float, bp: int | None = None, turns: int | None = None,
             units: Units | None = None) -> dict:
    """A copy of SCENE that runs for the MD length and writes what the build needs."""
    u = units or Units.paper()
    s = copy.deepcopy(scene)
    ini = s.setdefault("initial", {})
    if bp is not None:
        ini["bp"] = int(bp)
    if turns is not None:
        ini["turns"] = int(turns)
    n_bp = int(ini.get("bp", 158))
    rod = s.setdefault("rod", {})
    # base pair i must be grid point i N / n_bp (dna_planar's default N is n_bp)
    if "points" in rod and int(rod["points"]) % n_bp:
        rod["points"] = n_bp * math.ceil(int(rod["points"]) / n_bp)
    out = s.setdefault("output", {})
    out.update({"t_end": u.time_to_rod(md_ps) if md_ps > 0 else 0.0,
                "frames": ROD_FRAMES if md_ps > 0 else 1,
                "fields": ["internal", "centerline", "directors"]})
    return s


def run_rod(scene: dict, source: str) -> dict:
    """rodcore.run(scene) -> dict with time, s, fields/..., centerline, directors."""
    try:
        import rodcore  # the pybind11 module in build/python
    except ImportError as e:
        raise DnarodError(f"the rodcore Python module is not importable ({e}); build it with "
                          "`bash scripts/build.sh` and run through build/bin/dnarod (or put "
                          "build/python on PYTHONPATH)") from None
    try:
        return rodcore.run(scene)
    except (ValueError, RuntimeError) as e:
        raise DnarodError(f"{source}: rod run for the MD build failed: {e}") from None
