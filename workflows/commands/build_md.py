"""`dnarod build-md`: GROMACS inputs of a periodic, ligated all-atom duplex that
starts in the rod scene's shape with the rod's velocities (paper Sec 6.2)."""
from __future__ import annotations

from pathlib import Path

from dna_models.errors import InputError

NAME = "build-md"
HELP = "GROMACS inputs (conf.gro with velocities, topol.top, md.mdp) of the periodic duplex of a rod scene"
DESCRIPTION = """\
Build the all-atom counterpart of a DNA rod scene, as in the paper (Sec 6.2):
a periodic duplex whose two strands are each covalently closed across the
periodic boundary (ligated), in the rod's t = 0 shape, with initial
velocities = thermal (Maxwell-Boltzmann, --temperature, --seed) + for every
atom of base pair i the rigid-body velocity of the rod's cross-section at
s_i = i L / n_bp. Vacuum, cut-off electrostatics and vdW at 1.0 nm, NVE.

Steps: the rod runs through rodcore for the MD length (--ps) to predict how
far the duplex moves across its axis (this sizes the box), or, with --rod, the
frames of a rod run already made are used (the workflow passes its own rod.h5,
so the rod of a comparison runs once); the builder places
the nucleotides on the rod's base-pair frames; pdb2gmx closes both strands
into rings and dnarod checks, term by term, that each junction carries
exactly the bonded terms of an interior step; velocities are assigned; grompp
checks the result.

Writes DIR/conf.gro (coordinates, velocities, box), topol.top (+ per-strand
.itp), md.mdp, em.mdp, build.json (every choice, the sequence and seed, the
scales, the box and why, the junction report, the t = 0 frame check).
Run it with `dnarod run-md DIR`. See docs/md.md.

A sequence-dependent scene (`dnarod dna-rod`: [material] material_file with the
sequence, [initial] the closed rest state) builds the duplex of THAT sequence on
the rod's base-pair frames, its helix axis (the period vector) turned onto lab Y.

Examples:
  dnarod build-md workflows/scenes/dna158.toml -o md158
  dnarod dna-rod --random 21 --seed 1 --params olson1998 -o rod21 && dnarod build-md rod21/scene.toml -o md21s
  dnarod build-md workflows/scenes/dna21.toml -o md21 --temperature 0 --ps 5
  dnarod build-md workflows/scenes/dna158.toml -o md158n --electrostatics neutral-phosphates --minimize
"""


def add_arguments(p):
    from mdbridge.md.gromacs.charges import ELECTROSTATICS
    from mdbridge.md.gromacs.mdp import CUTOFFS
    from mdbridge.md.gromacs.topology import FORCEFIELDS
    p.add_argument("scene", metavar="SCENE.toml", help="rod scene: [initial] kind = \"dna_planar\" (uniform "
                   "paper DNA), or a sequence-dependent scene of `dnarod dna-rod` (its DNA is built)")
    p.add_argument("-o", "--output", required=True, metavar="DIR", help="directory to write")
    p.add_argument("--temperature", type=float, default=300.0, metavar="K",
                   help="thermal part of the initial velocities, K (300; 0 = rod motion only)")
    p.add_argument("--seed", type=int, default=None,
                   help="seed of the random sequence and the thermal velocities (default: drawn "
                        "and recorded in build.json)")
    p.add_argument("--sequence", metavar="SEQ", help="strand I 5'->3' (default: random, --seed)")
    p.add_argument("--bp", type=int, default=None, help="override the scene's number of base pairs")
    p.add_argument("--turns", type=int, default=None,
                   help="override the scene's helical turns (twist = 360 turns / bp)")
    p.add_argument("--rod", metavar="ROD.h5", default=None,
                   help="use this rod output of the same scene (rodsim run SCENE.toml -o ROD.h5, "
                        "with internal, centerline and directors, at least --ps long) instead of "
                        "running the rod again")
    p.add_argument("--ps", type=float, default=600.0,
                   help="MD length the box is sized for (rod run of the same length), ps (600)")
    p.add_argument("--forcefield", choices=FORCEFIELDS, default="charmm27")
    p.add_argument("--electrostatics", choices=ELECTROSTATICS, default="paper",
                   help="paper: full charges (default); neutral-phosphates: +0.5 e on O1P/O2P, "
                        "every nucleotide neutral (docs/md.md: measured effect and its cost)")
    p.add_argument("--dt", type=float, default=None,
                   help="time step, ps (0.001 without constraints; 0.002 with --constraints h-bonds)")
    p.add_argument("--constraints", choices=("none", "h-bonds"), default="none")
    p.add_argument("--cutoffs", choices=CUTOFFS, default="smooth",
                   help="smooth (default): reaction-field eps_rf = 0 and vdW force-switch 0.8-1.0 nm, "
                        "potential and force zero at the 1.0-nm cut-off (energy-conserving); paper: "
                        "plain cut-offs, force jumps at 1.0 nm (docs/md.md, energy conservation)")
    p.add_argument("--lincs-order", type=int, default=4, help="LINCS expansion order (4)")
    p.add_argument("--lincs-iter", type=int, default=1, help="LINCS iterations (1)")
    p.add_argument("--thermostat", action="store_true",
                   help="v-rescale at --temperature instead of NVE (the paper is NVE)")
    p.add_argument("--tau-t-ps", type=float, default=1.0, metavar="PS",
                   help="coupling time of --thermostat, ps (1.0; a global stochastic thermostat "
                        "with tau-t of ~1-2 ps leaves the duplex's mode dynamics unchanged)")
    p.add_argument("--protocol", choices=("equilibrated", "paper"), default=None,
                   help="equilibrated (default when --temperature > 0): a v-rescale stage at "
                        "--temperature of --equilibrate-ps before the rod's velocities are added; "
                        "paper: no equilibration, as in the paper (default at 0 K)")
    p.add_argument("--equilibrate-ps", type=float, default=20.0, metavar="PS",
                   help="length of the equilibration stage, ps (20; build.json records whether "
                        "temperature and potential energy were stationary)")
    p.add_argument("--axial-pressure", action="store_true",
                   help="equilibrate with pressure coupling along the helix axis only (ref 0 bar): "
                        "the box length becomes the duplex's zero-tension length (build.json)")
    p.add_argument("--minimize", action="store_true",
                   help="restrained steepest descent (base heavy atoms held) before velocities")
    p.add_argument("--margin", type=float, default=10.0,
                   help="extra box margin across the axis, A (10)")
    p.add_argument("--gmx", metavar="PATH",
                   help="gmx: a path, or a name (gmx_d) looked up in the project's build, then PATH "
                        "(default: $DNAROD_GMX, else the project's build, else PATH)")
    p.add_argument("--threads", type=int, default=2, help="threads for the minimisation (2)")


def run(args):
    import warnings
    # MDAnalysis 2.4 (Debian) imports the deprecated xdrlib: noise for a user
    warnings.filterwarnings("ignore", message="'xdrlib' is deprecated")
    from dnarod.progress import Stages, md_rate

    with Stages("build-md") as stages:
        return _build(args, stages, md_rate)


def _build(args, stages, md_rate):
    """build-md's steps; STAGES (dnarod.progress.Stages) shows the rod run, the
    minimisation and the equilibration while they run."""
    import secrets
    import sys

    import numpy as np

    from dna_models.sequence import random_sequence, validate
    from dna_models.units import ANGSTROM_PER_NM, Units
    from mdbridge.md.builder import build_duplex
    from mdbridge.md.gromacs.box import plan_box
    from mdbridge.md.gromacs.gmx import find_gmx
    from mdbridge.md.gromacs.inputs import build_inputs
    from mdbridge.md.gromacs.mdp import MdSettings
    from mdbridge.md.gromacs.rod import (lab_rotation_to_axis, md_scene, rod_for_md, rod_initial_from_run,
                                        rotate_rod, scene_sequence)
    from mdbridge.rod.run import RodRun, run_scene
    from mdbridge.rod.scene import load_scene, resolve_scene, scene_bp_turns, with_absolute_paths

    gmx = find_gmx(args.gmx)
    if args.ps < 0:
        raise InputError(f"--ps {args.ps}: must be >= 0")
    if args.rod and (args.bp is not None or args.turns is not None):
        raise InputError("--rod: the rod run fixes the base pairs and turns; drop --bp/--turns "
                         "(or run the rod again without --rod)")
    dt = args.dt if args.dt is not None else (0.002 if args.constraints == "h-bonds" else 0.001)
    if args.constraints == "none" and dt > 0.001 + 1e-12:
        raise InputError(f"--dt {dt}: without constraints the X-H bonds (period ~10 fs) need "
                         "dt <= 0.001 ps; use --constraints h-bonds for 0.002")
    if not args.tau_t_ps > 0:
        raise InputError(f"--tau-t-ps {args.tau_t_ps}: must be > 0 ps")
    settings = MdSettings(dt_ps=dt, constraints=args.constraints, thermostat=args.thermostat,
                          tau_t_ps=args.tau_t_ps,
                          cutoffs=args.cutoffs, lincs_order=args.lincs_order,
                          lincs_iter=args.lincs_iter,
                          temperature_K=args.temperature, nsteps=int(round(args.ps / dt)))
    protocol = args.protocol or ("equilibrated" if args.temperature > 0 else "paper")
    u = Units.paper()
    scene = load_scene(args.scene)
    seed = args.seed if args.seed is not None else secrets.randbelow(2**31)
    # a sequence-dependent scene (`dnarod dna-rod`) carries its DNA: build THAT sequence
    scene_seq = scene_sequence(scene, args.scene)
    n_bp_scene = None
    if scene_seq is not None:
        if args.bp is not None or args.turns is not None:
            raise InputError(f"{args.scene}: a sequence-dependent scene fixes its base pairs and shape "
                             "(its material file's sequence); drop --bp/--turns")
        if args.sequence and validate(args.sequence, "--sequence") != scene_seq:
            raise InputError(f"--sequence differs from the sequence of {args.scene} ({len(scene_seq)} bp, "
                             f"{scene_seq[:12]}...): the MD must be the rod's DNA; drop --sequence")
        scene = with_absolute_paths(scene, args.scene)
        seq, bp, turns, n_bp_scene = scene_seq, len(scene_seq), None, len(scene_seq)
        print(f"build-md: {bp} bp, the sequence of the scene's material file, seed {seed}", file=sys.stderr)
    else:
        bp, turns = scene_bp_turns(md_scene(scene, md_ps=0, bp=args.bp, turns=args.turns,
                                            source=args.scene), args.scene)
        if args.sequence:
            seq = validate(args.sequence, "--sequence")
            if len(seq) != bp:
                raise InputError(f"--sequence has {len(seq)} bases, the scene has {bp} base pairs")
        else:
            seq = random_sequence(bp, seed=seed)
        print(f"build-md: {bp} bp, {turns} turns (twist {360.0 * turns / bp:.4f} deg), seed {seed}",
              file=sys.stderr)
    if args.rod:
        print(f"build-md: the rod run {args.rod} (box sizing) ...", file=sys.stderr)
        run = rod_for_md(RodRun.read(args.rod), md_ps=args.ps,
                         scene=resolve_scene(Path(args.scene), args.scene), units=u)
    else:
        print("build-md: running the rod for the MD length (box sizing) ...", file=sys.stderr)
        run = run_scene(md_scene(scene, md_ps=args.ps, bp=args.bp, turns=args.turns, units=u,
                                 source=args.scene, n_bp=n_bp_scene), source=args.scene,
                        progress=lambda t, t_end: stages("rod run", round(float(u.time_to_ps(t)), 3),
                                                         round(float(u.time_to_ps(t_end)), 3), "ps"))
        stages.close()
    rod, centerline = rod_initial_from_run(run, bp, u)
    if scene_seq is not None:     # the closed shape's helix axis onto lab Y (orthorhombic box)
        rod, centerline = rotate_rod(rod, centerline, lab_rotation_to_axis(run, axis=1))
    box = plan_box(centerline, rod.origins_A, rod.closure_length_A, rod_run_ps=args.ps,
                   cutoff_A=settings.cutoff_nm * ANGSTROM_PER_NM, margin_A=args.margin)
    periodic = np.zeros(3)
    periodic[box.axis] = rod.closure_length_A
    structure = build_duplex(seq, rod.origins_A, rod.R, periodic_box=periodic)
    print(f"build-md: box {np.round(box.box_A, 2).tolist()} A; pdb2gmx, junction check, "
          "velocities, grompp ...", file=sys.stderr)
    info = build_inputs(Path(args.output), structure, rod, box, sequence=seq,
                        forcefield=args.forcefield, electrostatics=args.electrostatics,
                        temperature_K=args.temperature, seed=seed, settings=settings,
                        minimize=args.minimize, gmx=gmx, threads=args.threads,
                        protocol=protocol, equilibrate_ps=args.equilibrate_ps,
                        axial_pressure=args.axial_pressure,
                        progress=lambda stage, done, total, unit: stages(
                            stage, round(done, 6), total, unit, rate=md_rate if unit == "ps" else None),
                        meta={"scene": str(Path(args.scene).resolve()), "turns": turns,
                              "rod_run": str(Path(args.rod).resolve()) if args.rod else "run by build-md",
                              "twist_deg": None if turns is None else 360.0 * turns / bp,
                              "md_length_ps": args.ps,
                              "sequence_source": ("the scene's material file" if scene_seq is not None
                                                  else "given" if args.sequence else f"random, seed {seed}")})
    stages.close()
    links = ", ".join(f"{s}: {v['junction']:.3f} A" for s, v in info["junction_O3P_t0_A"].items())
    n_terms = sum(r["junction_total"] for r in info["junctions"])
    fr = info["frames_t0_vs_rod"]
    print(f"build-md: {info['n_atoms']} atoms, charge {info['total_charge_e']:+g} e; junction "
          f"O3'-P {links}; {n_terms} junction terms verified; frames vs rod "
          f"{fr['max_origin_A']:.3f} A / {fr['max_angle_deg']:.2f} deg", file=sys.stderr)
    if info.get("minimization"):
        m = info["minimization"]
        print(f"build-md: minimisation {'converged' if m.get('converged') else 'NOT converged'}; "
              f"base-pair frames moved {m['frames_moved']['max_origin_A']:.3f} A / "
              f"{m['frames_moved']['max_angle_deg']:.2f} deg", file=sys.stderr)
    if info.get("equilibration"):
        q = info["equilibration"]
        zt = q.get("axial_pressure")
        print(f"build-md: equilibrated {q['ps']:g} ps at {args.temperature:g} K: T "
              f"{q['temperature_K']['mean_second_half']:.1f} K, stationary: {q['stationary']}"
              + (f"; zero-tension length {zt['zero_tension_length_nm']:.3f} +- "
                 f"{zt['zero_tension_length_se_nm']:.3f} nm (built {zt['box_length_start_nm']:.3f})"
                 if zt else ""), file=sys.stderr)
    print(f"build-md: wrote {args.output}/ (conf.gro, topol.top, md.mdp, em.mdp, build.json)")
    return 0
