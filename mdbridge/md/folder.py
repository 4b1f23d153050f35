"""An MD folder written by `dnarod build-md` and `dnarod run-md`, read as the analyses need it:
the universe of md.tpr + md.xtc, build.json, and the base-pair trajectory of the pairs as
built (mdbridge/md/builder/duplex.py base_pairs), never paired by distance: in a long vacuum
run some pairs are open in whichever frame a search would look at.
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
    return Path(path).is_dir() and (Path(path) / "build.json").is_file()


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
