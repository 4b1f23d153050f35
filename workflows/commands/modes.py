"""`dnarod modes`: equilibrium mode spectra of a closed periodic duplex (rod or MD): per
Fourier mode of bend, twist and stretch, the static variance, the frequency and the damping
(mdbridge/analysis/modes.py, spectrum.py, mode_spectra.py; docs/analysis.md)."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from dna_models.errors import InputError

NAME = "modes"
HELP = "equilibrium mode spectra of a closed duplex: variance, frequency and damping of each Fourier mode"
DESCRIPTION = """\
The Fourier modes n = 1 .. (helical turns - 1) of a closed, periodic duplex, from an
equilibrium trajectory (by fluctuation-dissipation, their time correlations are the
duplex's small-kick response):

  bend     the helical axis's displacement perpendicular to the period, on two fixed
           laboratory directions, both quadratures [A];
  twist    the twist density of the steps [rad/A];
  stretch  the rise of the steps [A].

Per mode: the static variance <|c_n|^2> (one transverse direction for bend), and the
frequency omega and damping rate gamma (half the power peak's full width) of the damped
oscillator's exact discrete-time spectrum fitted by Whittle likelihood, pooled over
quadratures, directions and realisations, with calibrated errors. A mode is refused, with
the reason and null numbers, when the record holds fewer than 3 of its periods, when it
has no peak, or when the two halves of the record disagree (not stationary).

Each PATH is one realisation (a seed), all of one duplex:
  a rod output file (rodsim run of a DNA scene: base pairs and units from the file),
  an MD folder written by `dnarod build-md` and `dnarod run-md` (md.tpr, md.xtc,
    build.json; its pairs as built),
  or a mode_series.npz an earlier `dnarod modes` wrote (its realisations).

Writes DIR/modes.json (docs/analysis.md, "Mode spectra": the keys),
DIR/mode_series.npz (the amplitudes against time, float32, every frame: re-analyse with
`dnarod modes DIR/mode_series.npz`), DIR/spectra.png (each mode's power spectrum with its
fit) and DIR/dispersion.png (omega against k).

examples:
  dnarod modes runs/md/Av0_seed1 runs/md/Av0_seed2 --discard-ps 500 -o modes_md
  dnarod modes rod_thermal.h5 -o modes_rod
  dnarod modes modes_md/mode_series.npz --discard-ps 1000 -o modes_md_late
"""


def add_arguments(p):
    from dnarod import validate
    from dnarod.commands._options import add_output
    p.add_argument("paths", metavar="PATH", nargs="+",
                   help="rod output file, MD folder or mode_series.npz (one realisation each)")
    add_output(p, metavar="DIR", help="output directory")
    p.add_argument("--discard-ps", type=validate.finite(min=0), default=0.0, metavar="T",
                   help="discard the first T ps of each realisation (equilibration; default 0)")
    p.add_argument("--until-ps", type=validate.finite(above=0), default=None, metavar="T",
                   help="use each realisation only up to T ps from its start (one window for seeds "
                        "of different lengths; default: to its end)")


class _Input:
    """One PATH, opened (cheap: headers only) so that bad input fails before any work."""

    def __init__(self, path: str):
        self.path = path
        p = Path(path)
        from mdbridge.md.folder import is_md_folder, open_md_folder
        if is_md_folder(p):
            self.kind = "md"
            self.folder = open_md_folder(p)
            self.times_ps = self.folder.times_ps
        elif p.is_file() and p.suffix == ".npz":
            from mdbridge.analysis.mode_spectra import load_npz
            self.kind = "npz"
            self.series = load_npz(p)
            self.times_ps = self.series[0].times_ps
        elif p.is_file() and _is_hdf5(p):
            from mdbridge.rod.run import RodRun
            self.kind = "rod"
            self.run = RodRun.read(p)
            self.run.require("time", "s", "centerline", "directors", "fields/Gamma")
            if "initial.bp" not in self.run.attrs:
                raise InputError(f"{path}: a rod file without initial.bp: not a DNA scene, so its base "
                                 "pairs are unknown (a DNA scene's kind, e.g. dna_planar, records them)")
            self.n_bp = int(self.run.attrs["initial.bp"])
            self.units = self.run.units()
            self.times_ps = self.units.time_to_ps(np.asarray(self.run.time, float))
        else:
            raise InputError(f"{path}: not a rod output file (HDF5), an MD folder (with build.json) or a "
                             "mode_series.npz; those are the inputs of `dnarod modes`")
        if len(self.times_ps) < 3:
            raise InputError(f"{path}: {len(self.times_ps)} frames; the mode spectra need a trajectory")

    @property
    def record_ps(self) -> float:
        return float(self.times_ps[-1] - self.times_ps[0])

    def mode_series(self, stages) -> list:
        """The realisation(s) of this input as ModeSeries."""
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
            traj = self.folder.trajectory(progress=lambda d, t: stages(f"{name}: base-pair frames", d, t, "frames"))
            _, open_fraction = self.folder.open_fraction(
                progress=lambda d, t: stages(f"{name}: open base pairs", d, t, "frames"))
            meta = {"n_bp_from": "build.json", "sequence": self.folder.build.get("sequence"),
                    "seed": self.folder.build.get("seed")}
        a = ModeAnalysis(traj).run(progress=lambda d, t: stages(f"{name}: mode amplitudes", d, t, "frames"))
        return [ModeSeries.from_analysis(a.results, self.kind, open_fraction, meta)]


def _is_hdf5(p: Path) -> bool:
    with open(p, "rb") as f:
        return f.read(8) == b"\x89HDF\r\n\x1a\n"


def run(args):
    from mdbridge.analysis.mode_spectra import mode_table, save_npz
    from mdbridge.jsonio import write_json
    from dnarod.progress import Stages

    if not (math.isfinite(args.discard_ps) and args.discard_ps >= 0):
        raise InputError(f"--discard-ps {args.discard_ps}: a time >= 0 in ps")
    if args.until_ps is not None and not (math.isfinite(args.until_ps) and args.until_ps > args.discard_ps):
        raise InputError(f"--until-ps {args.until_ps:g}: a time in ps after --discard-ps ({args.discard_ps:g})")
    inputs = [_Input(p) for p in args.paths]
    for inp in inputs:
        if args.until_ps is not None and args.until_ps > inp.record_ps + 1e-6:
            raise InputError(f"{inp.path}: --until-ps {args.until_ps:g} is beyond its record "
                             f"({inp.record_ps:g} ps, {inp.times_ps[0]:g} to {inp.times_ps[-1]:g} ps)")
        if args.discard_ps >= inp.record_ps:
            raise InputError(f"{inp.path}: --discard-ps {args.discard_ps:g} is not shorter than its record "
                             f"({inp.record_ps:g} ps, {inp.times_ps[0]:g} to {inp.times_ps[-1]:g} ps)")
    from dnarod import validate
    out = validate.output_folder(args.output)
    with Stages("modes") as stages:
        series = [s for inp in inputs for s in inp.mode_series(stages)]
        stages.close()
        save_npz(out / "mode_series.npz", series)
        used = [s.after(args.discard_ps, args.until_ps) for s in series]
        table = mode_table(used)
    until = "" if args.until_ps is None else f" --until-ps {args.until_ps:g}"
    table.update(command="dnarod modes " + " ".join(args.paths) + f" --discard-ps {args.discard_ps:g}{until} -o {out}",
                 inputs=[{"path": i.path, "kind": i.kind} for i in inputs], discard_ps=args.discard_ps,
                 until_ps=args.until_ps)
    write_json(out / "modes.json", table)
    from mdbridge.analysis.mode_figures import dispersion_figure, spectra_figure
    spectra_figure(used, table, out / "spectra.png")
    dispersion_figure(table, out / "dispersion.png")
    import sys
    for r in table["realisations"]:
        of = r.get("open_fraction")
        if of and of["stationary"] is False:
            print(f"modes: warning: {r['source']}: the open base-pair fraction drifts ({of['halves'][0]:.3f} "
                  f"then {of['halves'][1]:.3f} in the two halves, z = {of['z']:.1f}): the record may not be "
                  "stationary (modes.json realisations[].open_fraction)", file=sys.stderr)
    for kind, d in table["drift"].items():
        if d["drifts"]:
            print(f"modes: warning: the {kind} frequencies move together between the record's halves: "
                  f"{100 * d['relative_shift']:+.1f} +- {100 * d['relative_shift_err']:.1f} % (z = {d['z']:.1f}; "
                  f"{d['positive']} of {d['modes']} modes up): the record drifts (modes.json drift)", file=sys.stderr)
    ok = [e for e in table["modes"] if e["reason"] is None]
    counts = ", ".join(f"{kind} {sum(1 for e in ok if e['kind'] == kind)}" for kind in ("bend", "twist", "stretch"))
    print(f"modes: {len(ok)} of {len(table['modes'])} modes measured ({counts}); "
          f"wrote {out}/modes.json, mode_series.npz, spectra.png, dispersion.png")
    return 0
