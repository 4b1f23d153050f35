"""The temperature kT is taken at: given, or the trajectory's own kinetic temperature.

Kinetic temperature from velocities (TRR, or anything MDAnalysis reads with
velocities): T = <sum m v^2> / (3 N k_B) over the atoms that are neither water nor
hydrogen. Water (SETTLE) and bonds to hydrogen are constrained in the usual
GROMACS setup and a trajectory does not say which, so counting 3 N degrees of
freedom over all atoms would understate T by up to a third. The atoms kept carry
3 k_B T each by equipartition except for a heavy atom X bound to a constrained H:
its share is (3 m_X + 2 m_H) / (m_X + m_H) k_B T, 2.6 % low for C-H; reported as a
bound, not corrected (the fraction of such atoms is reported too).
An .edr energy file gives the thermostat's temperature through `gmx energy`
(mdbridge/md/gromacs/energy.py, the one reader).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from dna_models.errors import ExternalToolError, InputError
from mdbridge.geometry.analysis_base import AnalysisBase, UniverseFrames
from mdbridge.md.gromacs.energy import energy_series
from mdbridge.md.gromacs.velocities import kinetic_temperature as _kinetic

_WATER = {"SOL", "WAT", "HOH", "TIP3", "TIP3P", "SPC", "TIP4", "TIP4P", "T3P", "SPCE"}


MAX_FRAMES = 100   # evenly spaced frames: N atoms x 100 frames pin T to ~0.1 % for a solvated duplex


class KineticTemperature(AnalysisBase):
    """Kinetic temperature of the atoms ATOMS in each selected frame (3 k_B T per atom), an
    analysis of the one loop (mdbridge/geometry/analysis_base.py): results.temperature_K
    (T,), NaN where a frame has no velocities, and results.has_velocities (T,)."""

    def __init__(self, universe, atoms):
        super().__init__(UniverseFrames(universe))
        self.universe, self.atoms = universe, atoms

    def _prepare(self):
        self.results.temperature_K = np.full(self.n_frames, np.nan)
        self.results.has_velocities = np.zeros(self.n_frames, dtype=bool)

    def _single_frame(self):
        if not self.universe.trajectory.ts.has_velocities:
            return
        sel, k = self.atoms, self._frame_index
        self.results.has_velocities[k] = True
        self.results.temperature_K[k] = _kinetic(sel.masses, sel.velocities / 10.0,   # A/ps -> nm/ps
                                                 n_dof=3 * len(sel))


def kinetic_temperature(universe, start=None, stop=None, step=None, max_frames=MAX_FRAMES):
    """(T_K, T_std_K per frame, n_atoms, note) or None when the trajectory has no velocities.
    At most max_frames evenly spaced frames of start:stop:step are read."""
    try:
        universe.trajectory[0].velocities  # noqa: B018
    except Exception:  # noqa: BLE001 - MDAnalysis raises NoDataError
        return None
    atoms = universe.atoms
    keep = np.array([(r not in _WATER) for r in atoms.resnames])
    try:
        el = np.array([str(e).strip().upper() for e in atoms.elements])
    except Exception:  # noqa: BLE001 - no elements: guess from names
        el = np.array([str(n).strip()[:1].upper() for n in atoms.names])
    keep &= el != "H"
    sel = atoms[keep]
    if len(sel) == 0:
        return None
    frames = np.arange(universe.trajectory.n_frames)[start:stop:step]
    frames = frames[np.unique(np.linspace(0, len(frames) - 1, min(len(frames), max_frames)).astype(int))]
    per_frame = KineticTemperature(universe, sel).run(frames=frames).results
    if not per_frame.has_velocities.all():
        return None
    vals = per_frame.temperature_K
    return float(vals.mean()), float(vals.std()), int(len(sel)), (
        f"velocities of non-water, non-hydrogen atoms in {len(vals)} frames, 3 k_B T per atom "
        "(<= 2.6 % low for atoms bound to constrained hydrogens)")


def edr_temperature(edr_path, gmx: str = "gmx", begin_ps=None):
    """Mean 'Temperature' of a GROMACS .edr (mdbridge/md/gromacs/energy.py, `gmx energy`)."""
    edr = Path(edr_path)
    if not edr.is_file():
        raise InputError(f"{edr}: energy file not found")
    try:
        e = energy_series(edr.resolve(), gmx, ("Temperature",), begin_ps=begin_ps)
    except FileNotFoundError:
        raise InputError(f"{edr}: reading an .edr needs GROMACS ('{gmx}' not found); "
                         "give --temperature instead") from None
    except ExternalToolError as err:
        raise InputError(f"{edr}: gmx energy failed to extract 'Temperature': {str(err)[-400:]}") from None
    T = e.get("Temperature", np.zeros(0))
    if not len(T):
        raise InputError(f"{edr}: no 'Temperature' term")
    return float(T.mean()), float(T.std())


def parse_temperature(value) -> float:
    try:
        t = float(value)
    except (TypeError, ValueError):
        raise InputError(f"--temperature {value!r}: need a number in K") from None
    if not (t > 0 and np.isfinite(t)):
        raise InputError(f"--temperature {value!r}: must be a positive temperature in K")
    return t
