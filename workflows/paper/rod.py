"""Run a rod scene and get its output as numpy arrays.

`run_scene(scene)` takes a scene as a nested dict with the structure of the TOML
scene files (docs/scenes.md) and returns a `RodRun`. It uses the compiled Python
module `rodcore.run` when it is importable and otherwise writes the scene to a
temporary TOML file and runs `rodsim run` (so the paper checks work with either
build product). Both paths run the same C++ Simulation.
"""
from __future__ import annotations

import math
import os
import shutil
import subprocess
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from dna_models.errors import ExternalToolError, InputError

ROOT = Path(__file__).resolve().parents[2]


@dataclass
class RodRun:
    """Output of one run (solver units). fields[name] is (T, N, 3) for gamma, omega,
    Gamma, Omega; energy_parts[name] is (T,); centerline (T, N, 3); directors
    (T, N, 3, 3) with directors[t, i, :, k] = d_k (design.md)."""
    time: np.ndarray
    s: np.ndarray
    fields: dict
    energy: np.ndarray | None = None
    energy_parts: dict = field(default_factory=dict)
    centerline: np.ndarray | None = None
    directors: np.ndarray | None = None
    summary: dict = field(default_factory=dict)

    @property
    def L(self) -> float:
        return float(self.s[1] - self.s[0]) * len(self.s)


# -- scene dict -> TOML text ------------------------------------------------------------
def _toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, (float, np.floating)):
        v = float(v)
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, (list, tuple, np.ndarray)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    raise InputError(f"scene value {v!r} of type {type(v).__name__} cannot be written to TOML")


def scene_to_toml(scene: dict) -> str:
    lines = []
    for section, table in scene.items():
        if not isinstance(table, dict):
            raise InputError(f"scene section '{section}' must be a table (dict), got {table!r}")
        lines.append(f"[{section}]")
        lines += [f"{k} = {_toml_value(v)}" for k, v in table.items()]
        lines.append("")
    return "\n".join(lines)


# -- running ------------------------------------------------------------------------------
def rodsim_path() -> Path:
    """The rodsim executable: $DNAROD_BIN_DIR, $DNAROD_BUILD/bin, build/bin, or PATH."""
    cands = []
    if os.environ.get("DNAROD_BIN_DIR"):
        cands.append(Path(os.environ["DNAROD_BIN_DIR"]) / "rodsim")
    if os.environ.get("DNAROD_BUILD"):
        cands.append(Path(os.environ["DNAROD_BUILD"]) / "bin" / "rodsim")
    cands.append(ROOT / "build" / "bin" / "rodsim")
    for c in cands:
        if c.is_file() and os.access(c, os.X_OK):
            return c
    found = shutil.which("rodsim")
    if found:
        return Path(found)
    raise ExternalToolError("rodsim not found: build it (bash scripts/build.sh) or set DNAROD_BUILD "
                            f"/ DNAROD_BIN_DIR; looked in {', '.join(str(c) for c in cands)} and PATH")


def _module_run():
    try:
        import rodcore  # type: ignore
    except ImportError:
        return None
    return getattr(rodcore, "run", None)


def _from_mapping(d) -> RodRun:
    get = (lambda k: d[k] if k in d else None)
    fields = {k: np.asarray(v) for k, v in dict(get("fields") or {}).items()}
    parts = {k: np.asarray(v) for k, v in dict(get("energy_parts") or {}).items()}
    arr = (lambda k: None if get(k) is None else np.asarray(get(k)))
    summary = get("summary")
    return RodRun(np.asarray(d["time"]), np.asarray(d["s"]), fields, arr("energy"), parts,
                  arr("centerline"), arr("directors"), dict(summary) if summary is not None else {})


def read_h5(path) -> RodRun:
    import h5py
    with h5py.File(path, "r") as f:
        d = {"time": f["time"][:], "s": f["s"][:],
             "fields": {k: f["fields"][k][:] for k in f["fields"]} if "fields" in f else {},
             "energy_parts": {k: f["energy_parts"][k][:] for k in f["energy_parts"]}
             if "energy_parts" in f else {}}
        for k in ("energy", "centerline", "directors"):
            if k in f:
                d[k] = f[k][:]
        d["summary"] = {k[len("summary."):]: (v.decode() if isinstance(v, bytes) else v)
                        for k, v in f.attrs.items() if k.startswith("summary.")}
    return _from_mapping(d)


def write_initial_h5(path, s, fields: dict) -> None:
    """An `initial.kind = "file"` input (design.md): s (N) and fields/<name> (N x 3)."""
    import h5py
    with h5py.File(path, "w") as f:
        f["s"] = np.asarray(s, float)
        for name in ("gamma", "omega", "Gamma", "Omega"):
            f[f"fields/{name}"] = np.asarray(fields[name], float)


def run_scene(scene: dict, use_module: bool | None = None) -> RodRun:
    """Run `scene` (a dict shaped like the TOML) and return its output. use_module:
    None = the Python module if built, else rodsim; False = always rodsim."""
    run = _module_run() if use_module in (None, True) else None
    if run is not None and not _has_file_kind(scene):
        try:
            return _from_mapping(run(scene))
        except FloatingPointError as e:  # rodcore.NumericalError
            raise ExternalToolError(f"rodcore: numerical error: {e}") from None
        except ValueError as e:  # rodcore.InputError
            raise InputError(f"rodcore: {e}") from None
    with tempfile.TemporaryDirectory(prefix="dnarod-paper-") as tmp:
        toml = Path(tmp) / "scene.toml"
        toml.write_text(scene_to_toml(scene))
        out = Path(tmp) / "out.h5"
        proc = subprocess.run([str(rodsim_path()), "run", str(toml), "-o", str(out), "--quiet"],
                              capture_output=True, text=True)
        if proc.returncode != 0:
            raise ExternalToolError(f"rodsim failed (exit {proc.returncode}) on the scene\n"
                                    f"{toml.read_text()}\n{proc.stderr.strip()}")
        return read_h5(out)


def _has_file_kind(scene: dict) -> bool:
    # A file path is simplest to pass to rodsim; the module may take arrays instead.
    return scene.get("initial", {}).get("kind") == "file"


# -- scene builders for the paper's runs -------------------------------------------------
def straight_rod(L: float, N: int, Gamma03: float = 1.0, Omega03: float = 0.0) -> dict:
    return {"length": float(L), "points": int(N), "Gamma0": [0.0, 0.0, float(Gamma03)],
            "Omega0": [0.0, 0.0, float(Omega03)]}


def scene(rod: dict, initial: dict, t_end: float, frames: int, fields=("internal", "energy", "energy_parts"),
          rtol: float = 1e-10, space: str = "spectral", material: dict | None = None,
          checks: dict | None = None) -> dict:
    sc = {"rod": rod}
    if material:
        sc["material"] = material
    sc["initial"] = initial
    sc["solver"] = {"space": space, "time": "dop853", "rtol": rtol, "atol": rtol}
    sc["output"] = {"t_end": float(t_end), "frames": int(frames), "fields": list(fields)}
    if checks:
        sc["checks"] = checks
    return sc
