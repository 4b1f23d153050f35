"""An MD folder: the one definition, and the folder read as the analyses need it.

An MD folder is a directory that `dnarod build-md` wrote (build.json, conf.gro, topol.top,
...) and `dnarod run-md` may have run (md.tpr, md.xtc). Its structure is md.tpr + md.xtc
once run, else the built conf.gro (`md_files`); an analysis of the run itself (modes, the
comparison) opens it with `open_md_folder`: the universe of md.tpr + md.xtc, build.json,
and the base-pair trajectory of the pairs as built (mdbridge/md/builder/duplex.py
base_pairs), never paired by distance: in a long vacuum run some pairs are open in
whichever frame a search would look at.
"""
from __future__ import annotations

import json
import warnings
from dataclasses import dataclass
from pathlib import Path

from dna_models.errors import InputError
from mdbridge.geometry.trajectory import BasePairTrajectory
from mdbridge.md.builder.duplex import base_pairs


@dataclass
class MDFolder:
    path: Path
    build: dict
    universe: object

    @property
    def n_bp(self) -> int:
        return int(self.build["n_bp"])

    @property
    def pairs(self) -> list[tuple[int, int]]:
        return base_pairs(self.n_bp)

    def trajectory(self, start=None, stop=None, step=None, progress=None) -> BasePairTrajectory:
        """The base-pair frames of the pairs as built (module doc); progress as
        BasePairTrajectory.from_universe's."""
        return BasePairTrajectory.from_universe(self.universe, pairs=self.pairs, start=start, stop=stop,
                                                step=step, progress=progress)

    def open_fraction(self, start=None, stop=None, step=None, progress=None):
        """(times_ps, fraction of the built pairs open in each frame): N1-N3 beyond the
        intact cut-off of mdbridge/md/integrity.py."""
        from mdbridge.md.integrity import bp_intact_fraction
        by_resid = {int(r.resid): r for r in self.universe.residues}
        pairs = [(by_resid[a], by_resid[b]) for a, b in self.pairs]
        t, intact, _ = bp_intact_fraction(self.universe, pairs, start, stop, step, progress=progress)
        return t, 1.0 - intact

    @property
    def times_ps(self):
        """The frame times, from the trajectory's header (no frame read)."""
        import numpy as np
        tr = self.universe.trajectory
        return float(tr[0].time) + np.arange(tr.n_frames) * float(tr.dt)


def is_md_folder(path) -> bool:
    """An MD folder is a directory (module doc); what it must hold, md_files and
    open_md_folder say, naming what is missing."""
    return Path(path).is_dir()


def md_sequence(folder, option: str = "MD folder") -> str:
    """Strand I's sequence (5'->3') of an MD folder, from its build.json; an InputError
    naming OPTION, the folder and what is missing otherwise."""
    from dna_models.sequence import validate
    bj = Path(folder) / "build.json"
    if not bj.is_file():
        raise InputError(f"{option} {folder}: no build.json there (a folder written by `dnarod build-md`)")
    try:
        d = json.loads(bj.read_text())
    except ValueError as e:
        raise InputError(f"{bj}: not JSON ({e})") from None
    if "sequence" not in d:
        raise InputError(f"{bj}: key 'sequence' missing")
    return validate(d["sequence"], f"{bj}: sequence")


def md_files(folder) -> list[Path]:
    """md.tpr + md.xtc, else conf.gro, of an MD folder; an InputError naming what is
    missing otherwise."""
    d = Path(folder)
    if not d.is_dir():
        raise InputError(f"{d}: not a folder (give a rod HDF5 file or an MD folder of `dnarod build-md`)")
    if (d / "md.tpr").is_file() and (d / "md.xtc").is_file():
        return [d / "md.tpr", d / "md.xtc"]
    if (d / "conf.gro").is_file():
        return [d / "conf.gro"]
    raise InputError(f"{d}: no md.tpr + md.xtc and no conf.gro (an MD folder of `dnarod build-md`, "
                     "run or not by `dnarod run-md`)")


def open_md_folder(path) -> MDFolder:
    """The folder's md.tpr + md.xtc universe and build.json; InputError naming what is
    missing (a folder `dnarod build-md` did not write, or that `run-md` has not finished)."""
    import MDAnalysis as mda
    d = Path(path)
    if not (d / "build.json").is_file():
        raise InputError(f"{d}: not an MD folder (no build.json; `dnarod build-md SCENE -o {d}` writes one)")
    for f in ("md.tpr", "md.xtc"):
        if not (d / f).is_file():
            raise InputError(f"{d / f}: missing; run `dnarod run-md {d}` first (a run still going "
                             "writes md.part.xtc, renamed md.xtc when it finishes)")
    try:
        build = json.loads((d / "build.json").read_text())
        n_bp = int(build["n_bp"])
    except (ValueError, KeyError, TypeError) as e:
        raise InputError(f"{d / 'build.json'}: no base-pair count n_bp ({e})") from None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        u = mda.Universe(str(d / "md.tpr"), str(d / "md.xtc"))
    if len(u.residues) != 2 * n_bp:
        raise InputError(f"{d}: md.tpr has {len(u.residues)} residues, build.json's duplex {2 * n_bp}")
    return MDFolder(d, build, u)
