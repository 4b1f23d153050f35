"""Files for rodsim: the grid material file (`format = "dnarod-material/1"`),
the t = 0 state as an initial-condition file (also of workflows/steps/prestrain.py), and
the scene that uses both (made with the scene editor, mdbridge/rod/scene.py).

Material file (per grid point, dimensionless): K (N, 6, 6) on (Gamma1..3,
Omega1..3), I (N, 3, 3), rho (N), Gamma0 (N, 3), Omega0 (N, 3); read by rodsim
through `[material] material_file = "..."` (docs/scenes.md)."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from dna_models.units import Units
from mdbridge.rod.scene import new_scene

MATERIAL_FORMAT = "dnarod-material/1"


def write_grid_material(path, g: dict, source: str = "", attrs: dict | None = None) -> Path:
    import h5py
    path = Path(path)
    with h5py.File(path, "w") as f:
        f.attrs["format"] = MATERIAL_FORMAT
        f.attrs["source"] = source
        for k, v in (attrs or {}).items():
            f.attrs[k] = v
        for name in ("K", "I", "rho", "Gamma0", "Omega0"):
            f[name] = np.ascontiguousarray(g[name], dtype=float)
    return path


def write_initial_file(path, s, Gamma, Omega, gamma=None, omega=None) -> Path:
    """`initial.kind = "file"` state: s (N), fields/gamma, omega, Gamma, Omega (N, 3)."""
    import h5py
    path = Path(path)
    z = np.zeros_like(np.asarray(Gamma, dtype=float))
    with h5py.File(path, "w") as f:
        f["s"] = np.asarray(s, dtype=float)
        for name, v in (("gamma", gamma), ("omega", omega), ("Gamma", Gamma), ("Omega", Omega)):
            f[f"fields/{name}"] = z if v is None else np.asarray(v, dtype=float)
    return path


def grid_scene(length, points, material_file, initial_file, space="spectral", t_end_ps=600.0,
               frames=None, units: Units | None = None) -> dict:
    """A scene (mdbridge.rod.scene) running the grid material from the given initial
    state for t_end_ps (600 ps, the paper's MD) with `frames` output frames (default one
    per ps); write it with mdbridge.rod.scene.write_scene."""
    u = units or Units.paper()
    frames = int(t_end_ps) + 1 if frames is None else frames
    return new_scene({"length": float(length), "points": int(points)}, {"kind": "file", "path": str(initial_file)},
                     t_end=u.time_to_rod(t_end_ps), frames=frames, space=space,
                     fields=("internal", "energy", "centerline", "directors"),
                     material={"material_file": str(material_file)})
