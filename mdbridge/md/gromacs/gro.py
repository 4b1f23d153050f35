"""The .gro format (fixed columns; nm and nm/ps): read and write with velocities and box."""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from dna_models.errors import InputError


@dataclass
class Gro:
    title: str
    resid: np.ndarray      # (N,) int
    resname: list          # (N,) str
    name: list             # (N,) str
    x: np.ndarray          # (N, 3) nm
    v: np.ndarray | None   # (N, 3) nm/ps or None
    box: np.ndarray        # (3,) nm, rectangular

    @property
    def n_atoms(self) -> int:
        return len(self.name)


def read_gro(path: Path) -> Gro:
    path = Path(path)
    lines = path.read_text().splitlines()
    try:
        n = int(lines[1])
    except (IndexError, ValueError):
        raise InputError(f"{path}: not a .gro file (line 2 must be the atom count)")
    if len(lines) < n + 3:
        raise InputError(f"{path}: {n} atoms announced but only {len(lines) - 3} atom lines")
    resid = np.empty(n, dtype=int)
    resname, name = [], []
    x = np.empty((n, 3))
    v = np.empty((n, 3))
    has_v = True
    first = lines[2]
    # The decimal-point spacing of the first coordinate gives the field width (GROMACS rule).
    dot = first.index(".", 20)
    w = first.index(".", dot + 1) - dot
    for i, ln in enumerate(lines[2:2 + n]):
        resid[i] = int(ln[0:5])
        resname.append(ln[5:10].strip())
        name.append(ln[10:15].strip())
        x[i] = [float(ln[20 + k * w:20 + (k + 1) * w]) for k in range(3)]
        rest = ln[20 + 3 * w:]
        if has_v and len(rest.strip().split()) >= 3:
            v[i] = [float(t) for t in rest.split()[:3]]
        else:
            has_v = False
    box = np.array([float(t) for t in lines[2 + n].split()[:3]])
    return Gro(lines[0], resid, resname, name, x, v if has_v else None, box)


def write_gro(path: Path, gro: Gro) -> None:
    out = [gro.title, f"{gro.n_atoms:5d}"]
    for i in range(gro.n_atoms):
        s = (f"{gro.resid[i] % 100000:5d}{gro.resname[i]:<5.5s}{gro.name[i]:>5.5s}"
             f"{(i + 1) % 100000:5d}{gro.x[i, 0]:8.3f}{gro.x[i, 1]:8.3f}{gro.x[i, 2]:8.3f}")
        if gro.v is not None:
            s += f"{gro.v[i, 0]:8.4f}{gro.v[i, 1]:8.4f}{gro.v[i, 2]:8.4f}"
        out.append(s)
    out.append(f"{gro.box[0]:10.5f}{gro.box[1]:10.5f}{gro.box[2]:10.5f}")
    Path(path).write_text("\n".join(out) + "\n")
