"""`dnarod build-md`: GROMACS inputs of a periodic, ligated all-atom duplex that
starts in the rod scene's shape with the rod's velocities (paper Sec 6.2)."""
from __future__ import annotations

from dnarod import validate
from dnarod.commands._options import add_output

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
so the rod of a comparison runs once; without --ps the MD is as long as that run); the builder places
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
  dnarod build-md workflows/scenes/dna21.toml -o md21w --solvent tip3p --salt-mM 150 --minimize
  dnarod build-md workflows/scenes/dna21.toml -o md21t --solvent tip3p --salt-mM 150 --minimize \
      --thermostat --axial-tension-pN 30
"""


def add_arguments(p):
    from mdbridge.md.gromacs import defaults as d
    from mdbridge.md.gromacs.charges import ELECTROSTATICS
    from mdbridge.md.gromacs.mdp import CUTOFFS
    from mdbridge.md.gromacs.solvent import SOLVENTS
    from mdbridge.md.gromacs.topology import FORCEFIELDS
    p.add_argument("scene", metavar="SCENE.toml", help="rod scene: [initial] kind = \"dna_planar\" (uniform "
                   "paper DNA), or a sequence-dependent scene of `dnarod dna-rod` (its DNA is built)")
    add_output(p, metavar="DIR", help="directory to write")
    p.add_argument("--temperature", type=validate.finite(min=0), default=d.TEMPERATURE_K, metavar="K",
                   help=f"thermal part of the initial velocities, K ({d.TEMPERATURE_K:g}; 0 = rod motion only)")
    p.add_argument("--seed", type=int, default=None,
                   help="seed of the random sequence and the thermal velocities (default: drawn "
                        "and recorded in build.json)")
    p.add_argument("--sequence", metavar="SEQ", help="strand I 5'->3' (default: random, --seed)")
    p.add_argument("--bp", type=validate.integer(min=1), default=None, help="override the scene's number of base pairs")
    p.add_argument("--turns", type=validate.integer(min=1), default=None,
                   help="override the scene's helical turns (twist = 360 turns / bp)")
    p.add_argument("--rod", metavar="ROD.h5", default=None,
                   help="use this rod output of the same scene (rodsim run SCENE.toml -o ROD.h5, "
                        "with internal, centerline and directors, at least --ps long) instead of "
                        "running the rod again")
    p.add_argument("--ps", type=validate.finite(min=0), default=None,
                   help="MD length the box is sized for and run-md runs by default, ps (default: "
                        f"the whole --rod run, in whole time steps; {d.MD_PS:g} when build-md runs the rod)")
    p.add_argument("--forcefield", choices=FORCEFIELDS, default=d.FORCEFIELD)
    p.add_argument("--electrostatics", choices=ELECTROSTATICS, default=d.ELECTROSTATICS,
                   help="paper: full charges (default); neutral-phosphates: +0.5 e on O1P/O2P, "
                        "every nucleotide neutral (docs/md.md: measured effect and its cost)")
    p.add_argument("--dt", type=validate.finite(above=0), default=None,
                   help=f"time step, ps ({d.DT_PS:g} without constraints; {d.DT_CONSTRAINED_PS:g} with "
                        "--constraints h-bonds)")
    p.add_argument("--constraints", choices=("none", "h-bonds"), default=d.CONSTRAINTS)
    p.add_argument("--cutoffs", choices=CUTOFFS, default=d.COMMAND_CUTOFFS,
                   help="smooth (default): reaction-field eps_rf = 0 and vdW force-switch 0.8-1.0 nm, "
                        "potential and force zero at the 1.0-nm cut-off (energy-conserving); paper: "
                        "plain cut-offs, force jumps at 1.0 nm (docs/md.md, energy conservation)")
    p.add_argument("--lincs-order", type=validate.integer(min=1), default=d.LINCS_ORDER,
                   help=f"LINCS expansion order ({d.LINCS_ORDER})")
    p.add_argument("--lincs-iter", type=validate.integer(min=1), default=d.LINCS_ITER, help=f"LINCS iterations ({d.LINCS_ITER})")
    p.add_argument("--thermostat", action="store_true",
                   help="v-rescale at --temperature instead of NVE (the paper is NVE)")
    p.add_argument("--tau-t-ps", type=validate.finite(above=0), default=d.TAU_T_PS, metavar="PS",
                   help=f"coupling time of --thermostat, ps ({d.TAU_T_PS:.1f}; a global stochastic thermostat "
                        "with tau-t of ~1-2 ps leaves the duplex's mode dynamics unchanged)")
    p.add_argument("--protocol", choices=("equilibrated", "paper"), default=None,
                   help="equilibrated (default when --temperature > 0): a v-rescale stage at "
                        "--temperature of --equilibrate-ps before the rod's velocities are added; "
                        "paper: no equilibration, as in the paper (default at 0 K)")
    p.add_argument("--equilibrate-ps", type=validate.finite(min=0), default=d.EQUILIBRATE_PS, metavar="PS",
                   help=f"length of the equilibration stage, ps ({d.EQUILIBRATE_PS:g}; build.json records "
                        "whether temperature and potential energy were stationary)")
    p.add_argument("--axial-pressure", action="store_true",
                   help="equilibrate with pressure coupling along the helix axis only (ref 0 bar): "
                        "the box length becomes the duplex's zero-tension length (build.json)")
    p.add_argument("--hold-pairs", action="store_true",
                   help="keep the Watson-Crick pairs closed: flat-bottomed restraints on their H-bond "
                        "distances, no force below 3.3 A, no exclusions added (docs/md.md: the intact "
                        "duplex); the full-charge run without it is the paper's setting")
    p.add_argument("--solvent", choices=SOLVENTS, default=d.SOLVENT,
                   help="vacuum (the paper's setting, default) or a water model of the force field: water "
                        "(gmx solvate), neutralising counterions and --salt-mM of salt (gmx genion, the force "
                        "field's ions), PME; the helix axis on the box's z (docs/md.md, DNA in water)")
    p.add_argument("--salt-mM", dest="salt_mM", type=validate.finite(min=0), default=d.SALT_MM, metavar="C",
                   help="salt (the force field's Na+/Cl-) on top of the counterions, mM of the water's volume "
                        f"({d.SALT_MM:g}; needs --solvent)")
    p.add_argument("--axial-tension-pN", dest="axial_tension_pN", type=validate.finite(), default=None,
                   metavar="T", help="hold the duplex at tension T (pN) in water: semi-isotropic C-rescale, 1 bar "
                   "across and ref_p_z = 1 - 10 T / A_xy[nm^2] bar (needs --solvent and --thermostat; default: "
                   "a fixed box)")
    p.add_argument("--minimize", action="store_true",
                   help="restrained steepest descent (base heavy atoms held) before velocities")
    p.add_argument("--margin", type=validate.finite(min=0), default=d.MARGIN_A,
                   help=f"extra box margin across the axis, A ({d.MARGIN_A:g})")
    p.add_argument("--gmx", metavar="PATH",
                   help="gmx: a path, or a name (gmx_d) looked up in the project's build, then PATH "
                        "(default: $DNAROD_GMX, else the project's build, else PATH)")
    p.add_argument("--threads", type=validate.integer(min=1), default=d.BUILD_THREADS,
                   help=f"threads for the minimisation ({d.BUILD_THREADS})")


def run(args):
    import os
    import sys

    from dnarod.progress import Stages, md_rate
    from dnarod.staging import written_on_success
    from mdbridge.md.gromacs.build_summary import summary_lines
    from mdbridge.md.build import BuildRequest, build_md

    if os.path.exists(args.scene):     # a missing one: the scene reader's message
        validate.input_file(args.scene, None, "TOML")
    if args.rod and os.path.exists(args.rod):
        validate.input_file(args.rod, "--rod")
    validate.output_folder(args.output, command="build-md")
    request = BuildRequest(
        scene=args.scene, output=args.output, temperature_K=args.temperature, seed=args.seed,
        sequence=args.sequence, bp=args.bp, turns=args.turns, rod=args.rod, ps=args.ps,
        forcefield=args.forcefield, electrostatics=args.electrostatics, dt_ps=args.dt,
        constraints=args.constraints, cutoffs=args.cutoffs, lincs_order=args.lincs_order,
        lincs_iter=args.lincs_iter, thermostat=args.thermostat, tau_t_ps=args.tau_t_ps,
        protocol=args.protocol, equilibrate_ps=args.equilibrate_ps, axial_pressure=args.axial_pressure,
        hold_pairs=args.hold_pairs, minimize=args.minimize, margin_A=args.margin, gmx=args.gmx, threads=args.threads,
        solvent=args.solvent, salt_mM=args.salt_mM, axial_tension_pN=args.axial_tension_pN)
    request.medium()    # the solvent's choices, before any work (exit 2)
    # built beside DIR and moved in on success: a failed rebuild leaves DIR's build intact
    with written_on_success(args.output, last="build.json", stale=("build.json", "md.done", "checks.json")) as tmp:
        request.output = str(tmp)
        with Stages("build-md") as stages:
            info, built_links = build_md(request, stages, md_rate)
    for line in summary_lines(info, built_links, args.temperature):
        print(f"build-md: {line}", file=sys.stderr)
    print(f"build-md: wrote {args.output}/ (conf.gro, topol.top, md.mdp, em.mdp, build.json)")
    return 0
