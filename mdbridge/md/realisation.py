"""One realisation of a duplex -- a rod output file or an MD folder -- recognised in one place.

`READERS` is the registry of the inputs the analyses take, each with the rule that
recognises it: a rod output file (HDF5, `rodsim run`; mdbridge/rod/run.py `is_hdf5`) and an
MD folder (mdbridge/md/folder.py, the one definition). `open_realisation(path)` opens a
path with the first reader that recognises it; `dnarod modes`, `dnarod topology` and
`dnarod coarse-grain` use it, so "a rod file or an MD folder" is decided here only.
It sits on the md floor because it imports both readers (rod and md); geometry's
BasePairTrajectory knows neither, and `read_rod_trajectory` is the rod file's reader for
`mdbridge.analysis.BasePairTrajectory.from_rod_h5`.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from dna_models.errors import InputError
from dna_models.units import Units
from mdbridge.geometry.trajectory import BasePairTrajectory
from mdbridge.rod.run import RodRun, is_hdf5

from .folder import MDFolder, is_md_folder, md_files, open_md_folder


@dataclass(frozen=True)
class Reader:
    kind: str                              # "rod" or "md"
    recognises: Callable[[Path], bool]
    what: str                              # for messages


READERS: tuple[Reader, ...] = (
    Reader("rod", is_hdf5, "a rod output file (HDF5, `rodsim run`)"),
    Reader("md", is_md_folder, "an MD folder (`dnarod build-md`)"),
)


@dataclass
class Realisation:
    """One opened input: a rod run (`run`, headers and datasets read) or an MD folder
    (its files checked; `md_folder()` opens the run with build.json's pairs)."""
    path: Path
    kind: str
    run: RodRun | None = None

    def md_files(self) -> list[Path]:
        """md.tpr + md.xtc, else conf.gro (mdbridge/md/folder.py)."""
        return md_files(self.path)

    def md_folder(self) -> MDFolder:
        """The MD run with build.json (mdbridge/md/folder.py open_md_folder)."""
        return open_md_folder(self.path)


def kind_of(path) -> str | None:
    """The kind of the first reader that recognises PATH, None when none does."""
    p = Path(path)
    return next((r.kind for r in READERS if r.recognises(p)), None)


def open_realisation(path) -> Realisation:
    """PATH opened by its reader: a rod file read (RodRun), an MD folder checked for its
    files; an InputError naming the path and the inputs allowed otherwise."""
    p = Path(path)
    if not p.exists():
        raise InputError(f"{p}: no such file or folder (give rod HDF5 files and MD folders)")
    kind = kind_of(p)
    if kind is None:
        raise InputError(f"{p}: not " + " or ".join(r.what for r in READERS))
    if kind == "rod":
        return Realisation(p, kind, RodRun.read(p))
    md_files(p)
    return Realisation(p, kind)


def read_rod_trajectory(path, n_bp: int, units: Units | None = None) -> BasePairTrajectory:
    """A rodsim output file (docs/contracts.md: time, s, fields/Gamma, centerline,
    directors) as the BasePairTrajectory of its n_bp base pairs (RodRun.trajectory)."""
    return RodRun.read(path).trajectory(n_bp, units)
