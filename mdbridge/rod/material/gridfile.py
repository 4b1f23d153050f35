"""Files for rodsim: the grid material file (`format = "dnarod-material/1"`),
the t = 0 state as an initial-condition file, and the scene that uses both.

Material file (per grid point, dimensionless): K (N, 6, 6) on (Gamma1..3,
Omega1..3), I (N, 3, 3), rho (N), Gamma0 (N, 3), Omega0 (N, 3); read by rodsim
through `[material] material_file = "..."` (docs/scenes.md)."""
from __future__ import annotations

from pathlib import Path

import numpy as np

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


def scene_text(length, points, material_file, initial_file, space="spectral", t_end=637.2, frames=601,
               comment=""):
    """A scene TOML running the grid material from the given initial state."""
    head = "".join(f"# {line}\n" for line in comment.splitlines())
    return f"""{head}[rod]
length = {float(length)!r}
points = {int(points)}

[material]
material_file = "{material_file}"

[initial]
kind = "file"
path = "{initial_file}"

[solver]
space = "{space}"
time = "dop853"
rtol = 1e-10
atol = 1e-10

[output]
t_end = {float(t_end)!r}
frames = {int(frames)}
fields = ["internal", "energy", "centerline", "directors"]
"""
