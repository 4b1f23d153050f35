"""`dnarod coarse-grain`: an equilibrium all-atom DNA trajectory -> the rod's material
(mean shape, 6x6 step stiffness, m-step continuum stiffness, physical constants,
mass and inertia), each number with its error (mdbridge.coarsegrain)."""
from __future__ import annotations

import math
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
                   help="topology/coordinates (TPR, PDB, GRO, ...), or a rod output file (rodsim run of a "
                        "DNA scene, HDF5: the whole input)")
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


def headline(params: dict) -> str:
    """The rod's constants, the ones docs/coarse-graining.md defines as the rod's (the
    long-wavelength stiffness K(q -> 0)): the headline; the table below labels the others."""
    rod = params["rod"]["constants"]
    cells = [f"{k.replace('_', ' ')} {rod[k]['value']:.4g} +- {rod[k]['err']:.2g} {rod[k]['unit']}"
             for k in ("bend_persistence_length", "torsional_modulus", "stretch_modulus")]
    return ("the rod (K(q -> 0), docs/coarse-graining.md): " + ", ".join(cells)
            + "\n  beside it, not the rod's: the per-step compliance average (the control) and m-step segments' "
              "constants (their own definitions, which grow with m)")


def run(args):
    from mdbridge.coarsegrain.reader import is_hdf5
    from mdbridge.coarsegrain.temperature import parse_temperature
    from mdbridge.geometry.structure import load_universe, read_pairs_file

    # every file and number checked before the trajectory is read
    if args.temperature is not None:
        parse_temperature(args.temperature)
    if Path(args.structure).is_dir():
        raise InputError(f"{args.structure}: a folder; give the structure and trajectory files in it "
                         f"(e.g. {Path(args.structure) / 'md.tpr'} {Path(args.structure) / 'md.xtc'})")
    if args.pairs:
        validate.input_file(args.pairs, "--pairs", "text")
    if args.edr and Path(args.edr).exists():   # a missing one: the energy reader's message
        validate.input_file(args.edr, "--edr")
    validate.output_folder(args.output)
    if is_hdf5(args.structure):
        if args.trajectories:
            raise InputError(f"{args.structure}: a rod output file is the whole input; give no trajectory "
                             f"({' '.join(args.trajectories)})")
        from dnarod.progress import Stages
        with Stages("coarse-grain") as stages:
            return _coarse_grain(args, None, args.structure, None, "resid", True, stages)
    u = load_universe(args.structure, *args.trajectories)
    source = " + ".join([args.structure] + list(args.trajectories))
    pairs, numbering = (None, "resid")
    if args.pairs:
        pairs, numbering = read_pairs_file(args.pairs)
    closed = {"auto": None, "yes": True, "no": False}[args.closed]
    from dnarod.progress import Stages
    with Stages("coarse-grain") as stages:
        return _coarse_grain(args, u, source, pairs, numbering, closed, stages)


def _coarse_grain(args, u, source, pairs, numbering, closed, stages):
    """coarse-grain's steps; STAGES (dnarod.progress.Stages) shows the frames read, the
    base-pair check and the coarse-graining lengths analysed."""
    from mdbridge.coarsegrain.cgrod import write_replicas
    from mdbridge.coarsegrain.estimator import MIN_EFFECTIVE, CoarseGrain, default_m_values
    from mdbridge.coarsegrain.figure import convergence_figure, length_figure, q_stiffness_figure
    from mdbridge.coarsegrain.params import build_params, write_params
    from mdbridge.coarsegrain.reader import read_ensemble
    from mdbridge.coarsegrain.stepmaterial import write_material_files
    from mdbridge.coarsegrain.temperature import edr_temperature, kinetic_temperature, parse_temperature

    from mdbridge.coarsegrain.reader import read_rod_ensemble
    out = Path(args.output)
    if u is None:
        ens, extras = read_rod_ensemble(args.structure, args.start, args.stop, args.step)
    else:
        ens, extras = read_ensemble(u, pairs, numbering, closed, args.start, args.stop, args.step,
                                    args.max_open_fraction, source, progress=stages)
    stages.close()
    extras["max_open_fraction"] = args.max_open_fraction

    caveats = []
    if args.temperature is not None:
        T_K, T_src = parse_temperature(args.temperature), "given"
    elif u is None:
        if extras.get("temperature_K") is None:
            raise InputError(f"{source}: the rod file has no attribute 'temperature_K' (a scene with "
                             "[thermal] temperature_K writes it): give --temperature K")
        T_K, T_src = float(extras["temperature_K"]), "rod file (attribute temperature_K)"
    elif args.edr:
        T_K, sd = edr_temperature(args.edr)
        T_src = f"edr ({args.edr}: mean of gmx energy 'Temperature', s.d. {sd:.1f} K)"
    else:
        kin = kinetic_temperature(u, args.start, args.stop, args.step)
        if kin is None:
            raise InputError(f"{source}: no velocities in the trajectory, so no kinetic temperature: "
                             "give --temperature K (or --edr FILE)")
        T_K, sd, n_at, note = kin
        T_src = "kinetic"
        caveats.append(f"kinetic temperature {T_K:.1f} K (s.d. {sd:.1f} K over frames) from {n_at} atoms: {note}")

    m_values = default_m_values(ens.n_steps, ens.closed, args.m_max, ens.excluded)
    m_rod = args.length if args.length is not None else max(m_values)
    if m_rod < 1 or m_rod > max(m_values):
        raise InputError(f"--length {m_rod}: allowed 1..{max(m_values)} (raise --m-max; "
                         f"{'n_bp / 4 for a closed duplex' if ens.closed else 'at most the number of steps'})")
    min_eff = MIN_EFFECTIVE if args.min_effective is None else args.min_effective
    if min_eff < MIN_EFFECTIVE:
        caveats.append(f"--min-effective {min_eff:g} is below the default {MIN_EFFECTIVE}: few independent "
                       f"frames, stiffness errors ~ sqrt(2 / N_eff) = {100 * math.sqrt(2 / max(min_eff, 1)):.0f} % "
                       "or more, and the bias correction is large")
    if extras["opened_pairs"].size:
        caveats.append("opened base pairs (1-based, opening rule): "
                       + ", ".join(str(i + 1) for i in extras["opened_pairs"])
                       + "; their steps are used, and left out only for the rule's sensitivity")
    if ens.closed and args.tension is None and args.torque is None:
        caveats.append("closed duplex: the means are the box's pre-stressed shape (no --tension/--torque given)")
    if "mass_inertia" not in extras:
        caveats.append("the rod file carries no uniform rho and I (a material file): no mass and inertia")
    elif not extras["mass_inertia"]["hydrogens"]:
        caveats.append("the topology has no hydrogens: masses and inertia are those of the heavy atoms only")
    cg = CoarseGrain(ens, T_K, m_values=m_values, m_rod=m_rod, n_boot=args.bootstrap, seed=args.seed,
                     discard=args.discard, min_effective=min_eff, progress=stages).run()
    stages.close()
    n_modes = cg.results["effective_samples_fit_modes"]
    if n_modes < min_eff:
        caveats.append(f"the slowest mode of the q -> 0 fit (autocorrelation time "
                       f"{cg.results['tau_int_fit_modes_frames']:.0f} frames) has {n_modes:.0f} independent samples, "
                       f"fewer than {min_eff:g}: the bootstrap's blocks are capped at T / 8, so the rod's K's error "
                       "may be understated; a longer run settles it")
    params = build_params(cg, T_src, extras, args.tension, args.torque, min_eff, caveats)
    out.mkdir(parents=True, exist_ok=True)
    write_params(out / "params.json", params)
    params["convergence"]["figure"] = "convergence.png"
    convergence_figure(out / "convergence.png", params)
    length_figure(out / "by_length.png", params)
    params["by_length_figure"] = "by_length.png"
    q_stiffness_figure(out / "q_stiffness.png", params)
    params["q_stiffness"]["figure"] = "q_stiffness.png"
    params["files"] = write_material_files(out, cg, extras, source)
    write_replicas(out / "replicas.h5", cg, extras)
    params["files"]["replicas_file"] = "replicas.h5"
    write_params(out / "params.json", params)
    print(f"{ens.n_steps} steps ({len(cg.results['opened_steps'])} touch a pair the opening rule counts as opened), "
          f"{cg.results['frames_used']} frames used after discarding {cg.results['discarded_frames']}, "
          f"N_eff = {cg.results['effective_samples']:.0f}, T = {T_K:.1f} K ({T_src.split(' ')[0]})")
    print(headline(params))
    print(constants_table(params))
    for c in caveats:
        print(f"  caveat: {c}")
    extra = [f for f in (params["files"].get("steps_file"), params["files"].get("material_file"), "replicas.h5") if f]
    print(f"wrote {out / 'params.json'}, {out / 'q_stiffness.png'}, {out / 'convergence.png'}, {out / 'by_length.png'}"
          + "".join(f", {out / f}" for f in extra))
    return 0
