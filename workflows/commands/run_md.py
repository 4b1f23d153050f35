"""`dnarod run-md`: grompp + mdrun of a build-md directory, then checks.json."""
from __future__ import annotations

NAME = "run-md"
HELP = "run GROMACS (grompp + mdrun) in a build-md directory and write checks.json"
DESCRIPTION = """\
Run the MD of a directory written by `dnarod build-md`: gmx grompp (md.tpr)
and gmx mdrun with a progress line, leaving md.tpr, md.xtc, md.edr, md.log,
confout.gro, then DIR/checks.json (junction O3'-P lengths, NVE energy drift,
Watson-Crick pairs intact over time, t = 0 frames vs the rod, side-wall image
distance). md.done is written last: without it the run is unfinished.

Resumable: mdrun writes a checkpoint every --checkpoint-minutes (2) of wall
time; running the same command again after an interruption (kill, crash, wall
time limit) continues from it (mdrun -cpi -append), every frame written once.
--fresh starts from step 0 instead. Progress (ps done, ns/day, time left) is
shown on a terminal and written as a plain line every minute into a log.

gmx: --gmx, else $DNAROD_GMX, else the build of scripts/build_gromacs.sh if it
exists, else `gmx` on PATH (Debian's build is SSE4.1-only). A bare name such as
`--gmx gmx_d` is looked up in that build first, then on PATH; a path is used as given.

Examples:
  dnarod run-md md21 --ps 5
  dnarod run-md md158 --gmx /opt/gromacs/bin/gmx --threads 8
"""


def add_arguments(p):
    from dnarod import validate
    p.add_argument("directory", metavar="DIR", help="a build-md output directory")
    length = p.add_mutually_exclusive_group()
    length.add_argument("--ps", type=validate.finite(), help="MD length, ps (default: the build's --ps)")
    length.add_argument("--steps", type=validate.integer(min=1), help="MD length in steps")
    p.add_argument("--gmx", metavar="PATH",
                   help="gmx: a path, or a name (gmx_d) looked up in the project's build, then PATH "
                        "(default: $DNAROD_GMX, else the project's build, else PATH)")
    p.add_argument("--threads", type=validate.integer(min=1), default=None, help="mdrun -nt (default: mdrun decides)")
    p.add_argument("--output-ps", type=validate.finite(above=0), default=None,
                   help="interval of coordinates/energies, ps (default: md.mdp's, 1 ps)")
    p.add_argument("--no-checks", action="store_true", help="skip checks.json")
    p.add_argument("--checkpoint-minutes", type=validate.finite(above=0), default=None, metavar="MIN",
                   help="wall-clock minutes between mdrun checkpoints (2): at most this much "
                        "work is lost when the run is killed")
    p.add_argument("--fresh", action="store_true",
                   help="start from step 0 even if an interrupted run left a checkpoint")
    p.add_argument("--reprod", action="store_true",
                   help="mdrun -reprod: the same inputs, gmx and threads give the same bits")


def run(args):
    import json
    import sys

    from mdbridge.md.gromacs.defaults import CHECKPOINT_MIN
    from mdbridge.md.gromacs.run import run_md
    from dnarod import validate
    from dnarod.progress import Progress, md_rate
    validate.input_folder(args.directory, None, "a `dnarod build-md` folder")
    bar: list[Progress] = []

    def progress(done_ps, total_ps):
        if not bar:
            bar.append(Progress("run-md", total_ps, "ps", rate=md_rate))
        bar[0].update(round(done_ps, 6))

    try:
        rec = run_md(args.directory, ps=args.ps, steps=args.steps, gmx=args.gmx,
                     threads=args.threads, output_ps=args.output_ps, checks=not args.no_checks,
                     checkpoint_min=(CHECKPOINT_MIN if args.checkpoint_minutes is None
                                     else args.checkpoint_minutes),
                     reprod=args.reprod, fresh=args.fresh, progress=progress)
    finally:
        if bar:
            bar[0].close()
    print(f"run-md: {rec['steps']} steps ({rec['length_ps']:g} ps) in {rec['wall_s']:.1f} s"
          + (f", {rec['ns_per_day']:g} ns/day" if rec.get("ns_per_day") else ""), file=sys.stderr)
    if not args.no_checks:
        c = json.loads(open(f"{args.directory}/checks.json").read())
        e = c["energy"]
        print(f"run-md: junctions ok: {c['junction_ok']}; drift "
              f"{e.get('drift_kJ_mol_per_ns_per_atom', float('nan')):.3g} kJ/mol/ns/atom; "
              f"WC pairs intact at end {100 * c['watson_crick']['final_fraction_intact']:.0f} %; "
              f"min side-image distance {c['side_image']['min_distance_A']:.1f} A", file=sys.stderr)
    print(f"run-md: done: {args.directory}/md.done")
    return 0
