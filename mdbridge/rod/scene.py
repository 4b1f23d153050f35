"""The rod scene as a dict: the one scene editor of the Python side.

A scene is the nested dict of a scene TOML file (docs/scenes.md): read one
(`load_scene`), ask rodcore for every default it fills (`resolve_scene`, and
`scene_bp_turns` for a DNA scene's base pairs and turns: Python keeps no copy of the
solver's defaults), make one (`new_scene`, `straight_rod`), edit one (`set_output`,
`scale_atol`, `with_absolute_paths`) and write one (`write_scene`: the one TOML writer,
with a comment header saying who made the file). Running a scene is
mdbridge/rod/run.py (`run_scene`); this module only shapes its input.
"""
from __future__ import annotations

import copy
import json
import math
import tomllib
from pathlib import Path

from dna_models.errors import DnarodError, InputError

from mdbridge.geometry.compiled import rodcore_module


# -- read ----------------------------------------------------------------------
def resolve_scene(scene, source="scene") -> dict:
    """SCENE with every key rodcore fills by default (rodcore.resolve), as a dict. With
    rodcore.kinds (scene_bp_turns) this is how Python learns a default of the solver
    (material, grid, kind parameters): from the solver, never from a copy."""
    try:
        text = rodcore_module().resolve(str(scene) if isinstance(scene, Path) else scene)
    except ValueError as e:
        raise InputError(f"{source}: {e}") from None
    return tomllib.loads(text)


def load_scene(path) -> dict:
    """A scene file as a dict; InputError naming the file when it is missing or not TOML."""
    path = Path(path)
    try:
        with open(path, "rb") as f:
            return tomllib.load(f)
    except FileNotFoundError:
        raise InputError(f"{path}: scene file not found") from None
    except OSError as e:
        raise InputError(f"{path}: cannot read the scene ({e.strerror})") from None
    except tomllib.TOMLDecodeError as e:
        raise InputError(f"{path}: not valid TOML ({e})") from None
    except UnicodeDecodeError:
        raise InputError(f"{path}: not a TOML file (its bytes are binary)") from None


def _kind_default(kind: str, key: str) -> float:
    for k in rodcore_module().kinds():
        if k["name"] == kind:
            for p in k["numbers"]:
                if p["name"] == key:
                    return float(p["default"])
    raise DnarodError(f"rodcore has no default for initial.{key} of kind {kind!r}")


def _whole(scene: dict, key: str, minimum: int, source, why: str = "") -> int:
    ini = scene.get("initial", {})
    v = ini[key] if key in ini else _kind_default("dna_planar", key)
    if isinstance(v, bool) or not (isinstance(v, (int, float)) and v == int(v) and v >= minimum):
        raise InputError(f"{source}: [initial] {key} = {v!r}: need an integer >= {minimum}{why}")
    return int(v)


def scene_bp_turns(scene: dict, source="scene") -> tuple[int, int]:
    """Base pairs and helical turns of a DNA scene ([initial] kind = "dna_planar")."""
    kind = scene.get("initial", {}).get("kind")
    if kind != "dna_planar":
        raise InputError(f"{source}: [initial] kind = {kind!r}: the number of base pairs is known "
                         "only for a DNA scene (kind = \"dna_planar\" with bp and turns), e.g. "
                         "workflows/scenes/dna158.toml")
    return (_whole(scene, "bp", 4, source),
            _whole(scene, "turns", 1, source, " (the ligated helix must close on itself: "
                   "twist = 360 turns / bp)"))


def scene_n_bp(scene: dict, source="scene") -> int:
    """Base pairs of a DNA scene (see scene_bp_turns)."""
    return scene_bp_turns(scene, source)[0]


# -- make ------------------------------------------------------------------------
def straight_rod(L: float, N: int, Gamma03: float = 1.0, Omega03: float = 0.0) -> dict:
    """A [rod] section: a straight rod of length L on N points, intrinsic Gamma3 and Omega3."""
    return {"length": float(L), "points": int(N), "Gamma0": [0.0, 0.0, float(Gamma03)],
            "Omega0": [0.0, 0.0, float(Omega03)]}


def new_scene(rod: dict, initial: dict | None, t_end: float, frames: int,
              fields=("internal", "energy", "energy_parts"), rtol: float = 1e-10, space: str = "spectral",
              material: dict | None = None, checks: dict | None = None) -> dict:
    """A scene integrated by dop853 at rtol = atol (solver time t_end, `frames` output
    frames). initial=None: the initial fields are given to run_scene as arrays (initial=...)."""
    sc = {"rod": rod}
    if material:
        sc["material"] = material
    if initial is not None:
        sc["initial"] = initial
    sc["solver"] = {"space": space, "time": "dop853", "rtol": rtol, "atol": rtol}
    sc["output"] = {"t_end": float(t_end), "frames": int(frames), "fields": list(fields)}
    if checks:
        sc["checks"] = checks
    return sc


# -- edit --------------------------------------------------------------------------
def set_output(scene: dict, *, t_end: float, frames: int, fields) -> dict:
    """SCENE's [output] t_end (solver time), frames and fields set in place (its other
    output keys kept); returns SCENE."""
    scene.setdefault("output", {}).update(t_end=t_end, frames=frames, fields=list(fields))
    return scene


def scale_atol(scene: dict, factor: float, source="scene") -> dict:
    """SCENE's solver.atol multiplied by FACTOR in place (rodcore's default when the scene
    has none); returns SCENE. A kick of amplitude A_v < 1 A/ps scales the fields, not an
    absolute tolerance: atol x A_v keeps the relative accuracy of A_v = 1 A/ps."""
    sol = scene.get("solver", {})
    atol = sol["atol"] if "atol" in sol else resolve_scene(scene, source)["solver"]["atol"]
    scene.setdefault("solver", {})["atol"] = float(atol) * factor
    return scene


def _beside(scene_path, p) -> Path:
    q = Path(p)
    return q if q.is_absolute() else Path(scene_path).resolve().parent / q


def with_absolute_paths(scene: dict, scene_path) -> dict:
    """A copy of SCENE whose file paths (material_file, initial.path, rod.intrinsic_file)
    are absolute, so the dict runs from any folder as the file does from its own."""
    s = copy.deepcopy(scene)
    for section, key in (("material", "material_file"), ("initial", "path"), ("rod", "intrinsic_file")):
        if key in s.get(section, {}):
            s[section][key] = str(_beside(scene_path, s[section][key]))
    return s


# -- write -------------------------------------------------------------------------
def _toml_value(v, where: str) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        return repr(v) if math.isfinite(v) else ("nan" if v != v else ("inf" if v > 0 else "-inf"))
    if isinstance(v, str):
        return json.dumps(v)   # a TOML basic string
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x, where) for x in v) + "]"
    if hasattr(v, "tolist"):   # a numpy scalar or array
        return _toml_value(v.tolist(), where)
    raise InputError(f"{where} = {v!r}: a scene value is a number, a string, a boolean or a list of them")


def scene_toml(scene: dict, comment: str = "") -> str:
    """SCENE as TOML text: one [section] per table, `key = value`, a blank line between
    sections; COMMENT (any lines) as `# ` lines on top."""
    parts = []
    for section, table in scene.items():
        if not isinstance(table, dict):
            raise InputError(f"scene key {section!r}: a scene has only [section] tables (docs/scenes.md)")
        lines = [f"[{section}]"] + [f"{k} = {_toml_value(v, f'{section}.{k}')}" for k, v in table.items()]
        parts.append("\n".join(lines) + "\n")
    head = "".join(f"# {line}\n" for line in comment.splitlines())
    return head + "\n".join(parts)


def write_scene(path, scene: dict, comment: str = "") -> Path:
    """Write SCENE to PATH (folders made) as scene_toml(SCENE, COMMENT)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(scene_toml(scene, comment))
    return path
