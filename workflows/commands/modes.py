"""`dnarod modes`: equilibrium mode spectra of a closed periodic duplex (rod or MD): per
Fourier mode of bend, twist and stretch, the static variance, the frequency and the damping
(mdbridge/analysis/modes.py, spectrum.py, mode_spectra.py; docs/analysis.md)."""
from __future__ import annotations

import sys

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
has no peak or its peak does not stand above the power below it, or when the two halves
of the record disagree (not stationary). Each mode's regime: oscillating (a frequency),
overdamped (no frequency; its relaxation time, the integral of its autocorrelation,
Gamma / omega0^2 = friction / stiffness, with an error from blocks) or unresolved.

Each PATH is one realisation (a seed), all of one duplex:
  a rod output file (rodsim run of a DNA scene: base pairs and units from the file),
  an MD folder written by `dnarod build-md` and `dnarod run-md` (md.tpr, md.xtc,
    build.json; its pairs as built),
  or a mode_series.npz an earlier `dnarod modes` wrote (its realisations).

Writes DIR/modes.json (docs/modes.md: the keys),
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


def run(args):
    from mdbridge.analysis.mode_run import mode_spectra
    from dnarod.progress import Stages

    from dnarod import validate
    out = validate.output_folder(args.output, command="modes")
    with Stages("modes") as stages:
        table = mode_spectra(args.paths, out, args.discard_ps, args.until_ps, progress=stages)
    _warn(table)
    for r in table.realisations:      # what an MD record's numbers come from: its open pairs
        of = r.get("open_fraction")
        if of:
            print(f"modes: {r['source']}: {100 * of['mean']:.1f} % of base pairs open (N1-N3 > 3.5 A) over the "
                  f"frames read")
    counts = ", ".join(f"{kind} {len(table.measured(kind))}" for kind in ("bend", "twist", "stretch"))
    slow = ", ".join(f"{kind} {len(table.overdamped(kind))}" for kind in ("bend", "twist", "stretch"))
    rest = len(table.modes) - len(table.measured()) - len(table.overdamped())
    print(f"modes: {len(table.measured())} of {len(table.modes)} modes oscillating, with a frequency ({counts}); "
          f"{len(table.overdamped())} overdamped, with a relaxation time instead ({slow}); {rest} unresolved; "
          f"wrote {out}/modes.json, mode_series.npz, spectra.png, dispersion.png")
    return 0


def _warn(table) -> None:
    """The table's (mdbridge.analysis.results.ModeTable) warnings on stderr: an open fraction
    or the frequencies drifting."""
    for r in table.realisations:
        of = r.get("open_fraction")
        if of and of["stationary"] is False:
            print(f"modes: warning: {r['source']}: the open base-pair fraction drifts ({of['halves'][0]:.3f} "
                  f"then {of['halves'][1]:.3f} in the two halves, z = {of['z']:.1f}): the record may not be "
                  "stationary (modes.json realisations[].open_fraction)", file=sys.stderr)
    for kind, d in table.drift.items():
        if d["drifts"]:
            print(f"modes: warning: the {kind} frequencies move together between the record's halves: "
                  f"{100 * d['relative_shift']:+.1f} +- {100 * d['relative_shift_err']:.1f} % (z = {d['z']:.1f}; "
                  f"{d['positive']} of {d['modes']} modes up): the record drifts (modes.json drift)", file=sys.stderr)
