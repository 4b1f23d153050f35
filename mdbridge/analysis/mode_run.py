"""The mode-spectra pipeline: realisations in, DIR/modes.json, mode_series.npz and figures out.

`mode_spectra(paths, output)` is what `dnarod modes` runs (workflows/commands/modes.py
parses, calls this and prints): each PATH is one realisation of one duplex -- a rod output
file or an MD folder (mdbridge/md/realisation.py), or a mode_series.npz an earlier run
wrote -- opened first (headers only) so that bad input fails before any work; then the mode
amplitudes of each (mdbridge/analysis/modes.py), the table of mode_spectra.py, the files.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from dna_models.errors import InputError
from mdbridge.analysis.results import ModeTable
from mdbridge.jsonio import write_json
from mdbridge.md.realisation import kind_of, open_realisation


class ModeInput:
    """One PATH, opened (cheap: headers only) so that bad input fails before any work."""

    def __init__(self, path: str):
        self.path = path
        p = Path(path)
        if p.is_file() and p.suffix == ".npz":
            from mdbridge.analysis.mode_spectra import load_npz
            self.kind = "npz"
            self.series = load_npz(p)
            self.times_ps = self.series[0].times_ps
        elif kind_of(p) is not None:
            real = open_realisation(p)
            self.kind = real.kind
            if real.kind == "md":
                self.folder = real.md_folder()
                self.times_ps = self.folder.times_ps
            else:
                self._rod(real.run)
        else:
            raise InputError(f"{path}: not a rod output file (HDF5), an MD folder (with build.json) or a "
                             "mode_series.npz; those are the inputs of `dnarod modes`")
        if len(self.times_ps) < 3:
            raise InputError(f"{path}: {len(self.times_ps)} frames; the mode spectra need a trajectory")

    def _rod(self, run) -> None:
        self.run = run
        self.run.require("time", "s", "centerline", "directors", "fields/Gamma")
        if "initial.bp" not in self.run.attrs:
            raise InputError(f"{self.path}: a rod file without initial.bp: not a DNA scene, so its base "
                             "pairs are unknown (a DNA scene's kind, e.g. dna_planar, records them)")
        self.n_bp = int(self.run.attrs["initial.bp"])
        self.units = self.run.units()
        self.times_ps = self.units.time_to_ps(np.asarray(self.run.time, float))

    @property
    def record_ps(self) -> float:
        return float(self.times_ps[-1] - self.times_ps[0])

    def check_window(self, discard_ps: float, until_ps: float | None) -> None:
        """InputError when the window [discard_ps, until_ps] does not fit this record."""
        span = f"({self.record_ps:g} ps, {self.times_ps[0]:g} to {self.times_ps[-1]:g} ps)"
        if until_ps is not None and until_ps > self.record_ps + 1e-6:
            raise InputError(f"{self.path}: --until-ps {until_ps:g} is beyond its record {span}")
        if discard_ps >= self.record_ps:
            raise InputError(f"{self.path}: --discard-ps {discard_ps:g} is not shorter than its record {span}")

    def mode_series(self, progress) -> list:
        """The realisation(s) of this input as ModeSeries; progress(stage, done, total, unit)."""
        from mdbridge.analysis.mode_spectra import ModeSeries
        from mdbridge.analysis.modes import ModeAnalysis
        if self.kind == "npz":
            return self.series
        name = Path(self.path).name
        if self.kind == "rod":
            traj = self.run.trajectory(self.n_bp, self.units)
            meta = {"n_bp_from": "the file's initial.bp", "tau_ps": self.units.tau_ps, "ell_A": self.units.ell_A}
            open_fraction = None
        else:
            traj = self.folder.trajectory(progress=lambda d, t: progress(f"{name}: base-pair frames", d, t, "frames"))
            _, open_fraction = self.folder.open_fraction(
                progress=lambda d, t: progress(f"{name}: open base pairs", d, t, "frames"))
            meta = {"n_bp_from": "build.json", "sequence": self.folder.build.get("sequence"),
                    "seed": self.folder.build.get("seed")}
        a = ModeAnalysis(traj).run(progress=lambda d, t: progress(f"{name}: mode amplitudes", d, t, "frames"))
        return [ModeSeries.from_analysis(a.results, self.kind, open_fraction, meta)]


def _quiet(stage, done, total, unit=""):
    pass


def mode_spectra(paths, output, discard_ps: float = 0.0, until_ps: float | None = None,
                 progress=None) -> ModeTable:
    """The mode table of the realisations PATHS (each from discard_ps to until_ps after its
    start), written to OUTPUT/modes.json with mode_series.npz, spectra.png and
    dispersion.png; returns the table (typed: mdbridge/analysis/results.py). progress: as
    dnarod.progress.Stages (called with (stage, done, total, unit); its close() ends the
    reading stages)."""
    from mdbridge.analysis.mode_figures import dispersion_figure, spectra_figure
    from mdbridge.analysis.mode_spectra import mode_table, save_npz
    if not (math.isfinite(discard_ps) and discard_ps >= 0):
        raise InputError(f"--discard-ps {discard_ps}: a time >= 0 in ps")
    if until_ps is not None and not (math.isfinite(until_ps) and until_ps > discard_ps):
        raise InputError(f"--until-ps {until_ps:g}: a time in ps after --discard-ps ({discard_ps:g})")
    inputs = [ModeInput(str(p)) for p in paths]
    for inp in inputs:
        inp.check_window(discard_ps, until_ps)
    out = Path(output)
    out.mkdir(parents=True, exist_ok=True)
    series = [s for inp in inputs for s in inp.mode_series(progress or _quiet)]
    if hasattr(progress, "close"):
        progress.close()
    save_npz(out / "mode_series.npz", series)
    used = [s.after(discard_ps, until_ps) for s in series]
    table = mode_table(used)
    until = "" if until_ps is None else f" --until-ps {until_ps:g}"
    table.update(command="dnarod modes " + " ".join(map(str, paths)) + f" --discard-ps {discard_ps:g}{until} -o {out}",
                 inputs=[{"path": i.path, "kind": i.kind} for i in inputs], discard_ps=discard_ps,
                 until_ps=until_ps)
    write_json(out / "modes.json", table)
    spectra_figure(used, table, out / "spectra.png")
    dispersion_figure(table, out / "dispersion.png")
    return ModeTable.from_json(table)
