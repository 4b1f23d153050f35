"""Scene builders for the paper's rod runs.

`scene(...)` returns a scene as a nested dict with the structure of the TOML scene
files (docs/scenes.md), to be run by `mdbridge.rod.run.run_scene` (the one way the
Python side runs the rod; it returns a `mdbridge.rod.run.RodRun`).
"""
from __future__ import annotations


def straight_rod(L: float, N: int, Gamma03: float = 1.0, Omega03: float = 0.0) -> dict:
    return {"length": float(L), "points": int(N), "Gamma0": [0.0, 0.0, float(Gamma03)],
            "Omega0": [0.0, 0.0, float(Omega03)]}


def scene(rod: dict, initial: dict | None, t_end: float, frames: int,
          fields=("internal", "energy", "energy_parts"), rtol: float = 1e-10, space: str = "spectral",
          material: dict | None = None, checks: dict | None = None) -> dict:
    """initial=None: the initial fields are given to run_scene as arrays (initial=...)."""
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
