"""`dnarod coarse-grain`: an equilibrium all-atom DNA trajectory -> the rod's material
(mean shape, 6x6 step stiffness, m-step continuum stiffness, physical constants,
mass and inertia), each number with its error (mdbridge.coarsegrain)."""
from __future__ import annotations

from pathlib import Path

from dna_models.errors import InputError
from dnarod import validate
from dnarod.commands._options import add_output

NAME = "coarse-grain"
HELP = "coarse-grain an all-atom DNA trajectory into the rod's stiffness, shape, rho and I"
DESCRIPTION = """\
Coarse-grain an equilibrium MD trajectory of a DNA duplex into the elastic rod:

  * per step (3DNA step parameters q = shift, slide, rise [A], tilt, roll, twist
    [deg]): mean shape and stiffness K = kT <dq dq^T>^-1 (kT/A^2, kT/(A deg),
    kT/deg^2), finite-sample bias of the inverse covariance corrected;
  * the rod's K: the long-wavelength stiffness K(q -> 0) of the step parameters'
    compliance spectrum along the sequence (steps in series, couplings between steps
    included), the per-step compliance average beside it, the stiffness against q
    (DIR/q_stiffness.png), and the rod's own effective constants;
  * m-step segments (m consecutive steps composed into one rigid-body step) for
    m = 1..M: stiffness against length, and the continuum constants (bend and
    torsional persistence length, torsional and stretch modulus, twist-stretch
    coupling) at m = --length;
  * mass and inertia per base pair about the base-pair origin, the rod's rho and I
    next to the paper's.

Errors: moving-block bootstrap with the block length from the autocorrelation
times. The equilibration stretch is discarded (Chodera's rule), the remaining
frames must be worth --min-effective independent samples, the two halves are
compared. Every step is used; the opening rule (a base pair with N1-N3 > 3.5 A in
more than --max-open-fraction of the frames) is a sensitivity: the rod's K without
those steps is reported beside it, and its spread enters the error where it exceeds
the bootstrap's. Writes DIR/params.json, DIR/convergence.png, DIR/by_length.png,
DIR/q_stiffness.png,
DIR/replicas.h5 (the bootstrap replicates of the sequence-averaged mean and
stiffness at every m, for the coarse-grained rod's error) and
(with the per-step file module mdbridge.rod.material) DIR/steps.h5 and, for a
closed duplex, the rod's DIR/material.h5 (docs/coarse-graining.md).

T is the trajectory's kinetic temperature (velocities, e.g. a TRR), or the .edr's
(--edr), or --temperature (which wins); params.json says which.

A rod output file (`rodsim run` of a DNA scene at a temperature, e.g. a Langevin rod) goes
through the same estimator: its base pairs at s_i = i L / n_bp, closed, T from the file.

examples:
  dnarod coarse-grain md.tpr md.trr -o cg
  dnarod coarse-grain rod_thermal.h5 -o cg_rod
  dnarod coarse-grain md.tpr part1.xtc part2.xtc --temperature 300 -m 10 -o cg
  dnarod coarse-grain sample_md0.pdb --pairs bpfile.dat --temperature 300 --min-effective 8 -o cg
"""


def add_arguments(p):
    p.add_argument("structure", metavar="STRUCTURE",
                   help="topology/coordinates (TPR, PDB, GRO, ...), a rod output file (rodsim run of a "
                        "DNA scene, HDF5: the whole input), or, with steps.npz files as the trajectories, the "
                        "run's input folder (docs/intact.md)")
    p.add_argument("trajectories", metavar="TRAJECTORY", nargs="*", help="trajectories, concatenated in order")
    add_output(p, metavar="DIR", help="output directory")
    p.add_argument("--temperature", metavar="K", help="temperature in K (default: kinetic, from velocities)")
    p.add_argument("--edr", metavar="FILE", help="GROMACS energy file: take T from it (gmx energy)")
    p.add_argument("-m", "--length", type=validate.integer(min=1), metavar="M",
                   help="coarse-graining length (steps) for the rod's K and the headline constants "
                        "(default: the largest m)")
    p.add_argument("--m-max", type=validate.integer(min=1), metavar="M",
                   help="largest m (default min(20, n_steps); n_bp / 4 for a closed duplex)")
    p.add_argument("--pairs", metavar="FILE", help="base pairs: 3DNA bpfile or lines 'resid_I resid_II'")
    p.add_argument("--closed", choices=("auto", "yes", "no"), default="auto",
                   help="periodic ligated duplex (closing step included); auto: strand I's ends bonded "
                        "across the box")
    p.add_argument("--tension", type=validate.finite(), metavar="PN",
                   help="measured mean tension (pN) of the box-held duplex: rest shape corrected")
    p.add_argument("--torque", type=validate.finite(), metavar="PN_NM",
                   help="measured mean torque (pN nm, positive overwinds): rest shape corrected")
    p.add_argument("--discard", type=validate.integer(min=0), metavar="N",
                   help="frames to discard as equilibration (default: Chodera's rule)")
    p.add_argument("--min-effective", type=validate.finite(above=0), default=None, metavar="N",
                   help="independent frames required (default 50)")
    p.add_argument("--max-open-fraction", type=validate.finite(min=0, below=1), default=0.05, metavar="F",
                   help="opening rule of the sensitivity: a base pair counts as opened if N1-N3 > 3.5 A "
                        "in more than this fraction of frames (default 0.05; 0: in any frame)")
    p.add_argument("--bootstrap", type=validate.integer(min=1), default=200, metavar="N",
                   help="bootstrap replicates (200)")
    p.add_argument("--seed", type=int, default=0, help="bootstrap random seed")
    p.add_argument("--start", type=int, default=None, help="first trajectory frame (0-based)")
    p.add_argument("--stop", type=int, default=None, help="stop before this frame")
    p.add_argument("--step", type=validate.integer(min=1), default=None, help="take every STEP-th frame")
    p.add_argument("--leave-out-open-frames", action="store_true",
                   help="each step's local estimates without the frames where it touches an open pair "
                        "(N1-N3 > 3.5 A; docs/intact.md)")
    p.add_argument("--window-ps", type=float, nargs="+", metavar="W",
                   help="compliance by timescale: windows (ps) for K(W); the first is params.json's "
                        "\"unrelaxed\" (default 50 ps; docs/coarse-graining.md, \"Compliance by timescale\"); "
                        "the whole-record estimate is then written with a caveat when short of --min-effective")


def constants_table(params: dict) -> str:
    """The rod's own constants (K(q -> 0)), those of the per-step compliance average and the
    m-step segments' physical constants, side by side, each with its error."""
    rod, ca, ph = params["rod"]["constants"], params["rod"]["constants_compliance_average"], params["physical"]
    m = params["physical_m"]
    rows = [f"  {'':30s} {'the rod: K(q->0)':>20s} {'compliance average':>20s} {f'{m}-step segments':>20s}"]
    for k in ("bend_persistence_length", "torsional_modulus", "stretch_modulus", "twist_stretch_coupling"):
        cells = [f"{d[k]['value']:.4g} +- {d[k]['err']:.2g}" for d in (rod, ca, ph)]
        name = f"{k.replace('_', ' ')} [{rod[k]['unit']}]"
        rows.append(f"  {name:30s} " + " ".join(f"{c:>20s}" for c in cells))
    return "\n".join(rows)


def unrelaxed_line(params: dict) -> str:
    """The unrelaxed stiffness against the whole record's, or why there is none."""
    import numpy as np
    if params.get("unrelaxed"):
        un, rel = params["unrelaxed"], params["compliance_by_window"]["stiffness"][-1]
        ratio = np.diagonal(np.asarray(un["stiffness"])) / np.diagonal(np.asarray(rel))
        return (f"  unrelaxed K(W = {un['window_ps']:g} ps) / whole-record K, diagonal (shift ... twist): "
                + " ".join(f"{r:.3g}" for r in ratio))
    return f"  no unrelaxed stiffness: {params.get('unrelaxed_reason')}"


def request(args):
    """The CoarseGrainRequest of the parsed options."""
    from mdbridge.coarsegrain.pipeline import CoarseGrainRequest
    return CoarseGrainRequest(
        structure=args.structure, output=args.output, trajectories=list(args.trajectories),
        temperature=args.temperature, edr=args.edr, length=args.length, m_max=args.m_max,
        pairs_file=args.pairs, closed=args.closed, tension=args.tension, torque=args.torque,
        discard=args.discard, min_effective=args.min_effective, max_open_fraction=args.max_open_fraction,
        bootstrap=args.bootstrap, seed=args.seed, start=args.start, stop=args.stop, step=args.step,
        window_ps=args.window_ps, leave_out_open_frames=args.leave_out_open_frames)


def headline(params: dict) -> str:
    """The rod's constants, the ones docs/coarse-graining.md defines as the rod's (the
    long-wavelength stiffness K(q -> 0)): the headline; the table below labels the others."""
    rod = params["rod"]["constants"]
    cells = [f"{k.replace('_', ' ')} {rod[k]['value']:.4g} +- {rod[k]['err']:.2g} {rod[k]['unit']}"
             for k in ("bend_persistence_length", "torsional_modulus", "stretch_modulus")]
    return ("the rod (K(q -> 0), docs/coarse-graining.md): " + ", ".join(cells)
            + "\n  beside it, not the rod's: the per-step compliance average (the control) and m-step segments' "
              "constants (their own definitions, which grow with m)")


def _check_inputs(args) -> None:
    """Every file and number checked before the trajectory is read."""
    from mdbridge.coarsegrain.temperature import parse_temperature
    if args.temperature is not None:
        parse_temperature(args.temperature)
    from mdbridge.coarsegrain.reader import is_steps_file
    steps = bool(args.trajectories) and all(is_steps_file(t) for t in args.trajectories)
    if Path(args.structure).is_dir() and not steps:
        raise InputError(f"{args.structure}: a folder; give the structure and trajectory files in it "
                         f"(e.g. {Path(args.structure) / 'md.tpr'} {Path(args.structure) / 'md.xtc'})")
    if args.pairs:
        validate.input_file(args.pairs, "--pairs", "text")
    if args.edr and Path(args.edr).exists():   # a missing one: the energy reader's message
        validate.input_file(args.edr, "--edr")
    validate.output_folder(args.output, command="coarse-grain")


def run(args):
    from mdbridge.coarsegrain.pipeline import coarse_grain
    from dnarod.progress import Stages
    _check_inputs(args)
    with Stages("coarse-grain") as stages:
        r = coarse_grain(request(args), progress=stages)
    res = r.results
    print(f"{r.n_steps} steps ({len(res['opened_steps'])} touch a pair the opening rule counts as opened), "
          f"{res['frames_used']} frames used after discarding {res['discarded_frames']}, "
          f"N_eff = {res['effective_samples']:.0f}, T = {r.T_K:.1f} K ({r.T_source.split(' ')[0]})")
    if args.leave_out_open_frames:
        of = r.params["opening_rule"].get("open_step_frames", 0.0)
        print(f"  {100 * of:.1f} % of the (step, frame)s touch an open pair (N1-N3 > 3.5 A): left out of the "
              "local estimates frame by frame")
    print(headline(r.params))
    print(constants_table(r.params))
    print(unrelaxed_line(r.params))
    for c in r.caveats:
        print(f"  caveat: {c}")
    print("wrote " + ", ".join(str(f) for f in r.written))
    return 0
