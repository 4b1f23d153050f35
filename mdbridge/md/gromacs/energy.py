"""The one reader of GROMACS energy files: `gmx energy` on an .edr, and the .xvg it writes.

Every energy series of the toolkit (drift in checks.json, the equilibration's stationarity,
the axial tension, the thermostat's temperature for coarse-graining) comes through here.
MDAnalysis's EDR reader needs pyedr, which Debian does not ship.
"""
from __future__ import annotations

import tempfile
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


# the terms every run directory's energy.xvg holds (checks.json, equilibration, tension)
RUN_TERMS = ("Potential", "Kinetic-En.", "Total-Energy", "Conserved-En.", "Temperature",
             "Pres-XX", "Pres-YY", "Pres-ZZ", "Box-X", "Box-Y", "Box-Z",
             "Restraint-Pot.")   # the last only in a --hold-pairs run (pair_hold.py)


def energy_series(edr, gmx: str, terms=RUN_TERMS, *, cwd: Path | None = None,
                  begin_ps: float | None = None) -> dict:
    """Time series of TERMS of the energy file EDR (via `gmx energy`): {"time": ...,
    legend: series, ...}, the legends as gmx writes them ("Kinetic En." for "Kinetic-En.").
    In CWD (energy.xvg and gmx_energy.log stay there), else in a temporary folder. A term
    the file lacks is left out by gmx; ExternalToolError when gmx fails."""
    args = ["energy", "-f", str(edr), "-o", "energy.xvg"]
    if begin_ps is not None:
        args += ["-b", str(begin_ps)]
    stdin = "".join(f"{k}\n" for k in terms) + "\n"
    with tempfile.TemporaryDirectory(prefix="dnarod-energy-") as tmp:
        d = Path(cwd) if cwd is not None else Path(tmp)
        run_gmx(gmx, args, d, stdin=stdin, log_name="gmx_energy.log", timeout_s=None if cwd else 120)
        names, data = read_xvg(d / "energy.xvg")
    out = {n: data[:, k + 1] for k, n in enumerate(names)} if len(data) else {}
    out["time"] = data[:, 0] if len(data) else np.zeros(0)
    return out


def read_energies(directory: Path, gmx: str, edr: str = "md.edr") -> dict:
    """Time series of DIRECTORY/EDR (a run's md.edr or eq.edr): {"time": ..., "Potential":
    ..., ...}; energy.xvg is left in DIRECTORY."""
    return energy_series(edr, gmx, cwd=Path(directory))
