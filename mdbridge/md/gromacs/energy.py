"""The one reader of GROMACS energy files: `gmx energy` on an .edr, and the .xvg it writes.

Every energy series of the toolkit (drift in checks.json, the equilibration's stationarity,
the axial tension, the thermostat's temperature for coarse-graining) comes through here.
MDAnalysis's EDR reader needs pyedr, which Debian does not ship.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from .gmx import run_gmx


def read_xvg(path: Path) -> tuple[list[str], np.ndarray]:
    legends, rows = [], []
    for ln in Path(path).read_text().splitlines():
        if ln.startswith("@ s") and "legend" in ln:
            legends.append(ln.split('"')[1])
        elif ln and ln[0] not in "#@":
            rows.append([float(t) for t in ln.split()])
    return legends, np.array(rows)


def read_energies(directory: Path, gmx: str, edr: str = "md.edr") -> dict:
    """Time series of md.edr (via `gmx energy`): {"time": ..., "Potential": ..., ...}."""
    d = Path(directory)
    run_gmx(gmx, ["energy", "-f", edr, "-o", "energy.xvg"], d,
            stdin="Potential\nKinetic-En.\nTotal-Energy\nConserved-En.\nTemperature\n"
                  "Pres-XX\nPres-YY\nPres-ZZ\nBox-X\nBox-Y\nBox-Z\n\n",
            log_name="gmx_energy.log")
    names, data = read_xvg(d / "energy.xvg")
    out = {n: data[:, k + 1] for k, n in enumerate(names)}
    out["time"] = data[:, 0]
    return out
