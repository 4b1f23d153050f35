"""`dnarod dna-rod`: a sequence-dependent DNA rod for rodsim (material, closed rest state, scene)."""
from __future__ import annotations

import sys
from pathlib import Path

from dna_models.errors import InputError
from dnarod import validate
from dnarod.commands._options import add_output

NAME = "dna-rod"
HELP = "a sequence-dependent DNA rod: per-step file, grid material, closed pre-stressed rest state, scene"
DESCRIPTION = """\
Make the rod of a given DNA: its per-step shape and stiffness from a parameter
set, mapped exactly onto the rod (mdbridge.rod.material.steps_to_rod), put on a
grid of N = points-per-bp x n_bp points (or n_bp / bp-per-point coarse
segments), and its closed, pre-stressed
equilibrium (frame at L = frame at 0, end-to-end = the box length along the
helix axis), which is the t = 0 state of the scene. Writes into DIR:

  steps.h5      the per-step DNA file (format dnarod-steps/1)
  material.h5   the grid material (format dnarod-material/1: K, I, rho, Gamma0, Omega0)
  rest.h5       the closed rest state (initial.kind = "file"), with --kick the kicked state
  scene.toml    rodsim scene: [material] material_file = "material.h5", [initial] path = "rest.h5"
  rest.json     tension [pN], torque [pN nm], residuals, closure defect, parameters

Parameter sets: paper (uniform, Sec 2.1), olson1998 (Olson et al. 1998 PNAS
95:11163, Table 1), or a per-step file (e.g. from coarse-graining).

Examples:
  dnarod dna-rod --sequence CGCGAATTCGCGCGCGAATTC --params olson1998 -o rod21
  dnarod dna-rod --sequence-from-md md158 --params olson1998 --kick 1.0 -o rod158
  dnarod dna-rod --random 158 --seed 7 --params paper -o rod158p
  dnarod dna-rod --random 10500 --seed 1 --bp-per-point 10 --ring --contact-diameter-nm 11.6 -o ring10k

--ring: a closed ring instead (frame at L = frame at 0, end-to-end 0) at the
linking number of the relaxed ring, its rest state the energy minimum found by
the overdamped rod at kT = 0 (mdbridge.rod.material.ring_rest); the scene is
that rod in water at 300 K, 100-ps steps (docs/dna-rod.md, "A closed ring").
"""


def add_arguments(p):
    src = p.add_mutually_exclusive_group(required=True)
    src.add_argument("--sequence", metavar="SEQ", help="strand I, 5'->3' (A/C/G/T)")
    src.add_argument("--sequence-from-md", metavar="MDDIR", help="the sequence of a `dnarod build-md` folder "
                     "(its build.json)")
    src.add_argument("--random", type=validate.integer(min=1), metavar="N_BP",
                     help="a random sequence of N_BP bases (--seed)")
    p.add_argument("--seed", type=int, default=None, help="seed of --random (the build-md convention)")
    p.add_argument("--params", default="olson1998", metavar="SET",
                   help="paper | olson1998 | a per-step file STEPS.h5 (default olson1998)")
    p.add_argument("--mass", default="paper", choices=("paper", "atoms"),
                   help="mass and inertia per base pair: the paper's rho, I (Sec 2.1) or the all-atom "
                        "B-DNA templates (sequence-dependent, no counterions); not for a step file")
    p.add_argument("--points-per-bp", type=validate.integer(min=1), default=1, metavar="M",
                   help="grid points per base pair (1)")
    p.add_argument("--bp-per-point", type=validate.integer(min=1), default=1, metavar="M",
                   help="coarse segments: one grid point per M base pairs, the material composed by series "
                        "compliance along the intrinsic shape (docs/dna-rod.md, 'Coarse segments'; M divides "
                        "n_bp; 1)")
    p.add_argument("--interpolation", default="trig", choices=("trig", "smooth", "step"),
                   help="per-step values -> grid (docs/scenes.md; default trig)")
    p.add_argument("--space", default="spectral", choices=("spectral", "fd4"),
                   help="the solver's d/ds the rest state is an equilibrium of (spectral)")
    p.add_argument("--rest", default="closed", choices=("closed", "equilibrium"),
                   help="closed (default): closure to round-off, the solver's statics to the "
                        "discretisation error; equilibrium: then the nearest exact root of the statics "
                        "(stays at rest in rodsim), closed only approximately, and possibly the "
                        "unstressed shape (docs/scenes.md)")
    p.add_argument("--shape", default="interpolated", choices=("interpolated", "exact"),
                   help="intrinsic shape on the grid: interpolated per-step strains, or exact (the rod "
                        "read at its base pairs has the step parameters; even n_bp needs --points-per-bp >= 2)")
    p.add_argument("--box-A", type=validate.finite(above=0), default=None, metavar="B",
                   help="end-to-end length along the helix axis, A (default n_bp x 3.38 A, the MD box; "
                        "with a per-step file n_bp x its mean rise)")
    p.add_argument("--kick", type=validate.finite(), default=0.0, metavar="A_V",
                   help="transverse velocity amplitude, A/ps: lab velocity A_v sin(2 pi s / L) e_perp "
                        "(the paper's kick, Sec 6.1), e_perp = d1(0) made normal to the helix axis (0: at rest)")
    p.add_argument("--t-end-ps", type=validate.finite(above=0), default=None,
                   help="scene length, ps (600, the paper's MD; with --ring 10000)")
    p.add_argument("--ring", action="store_true",
                   help="a closed ring at the relaxed ring's linking number, from its rest state (the energy "
                        "minimum), overdamped in water at 300 K (docs/dna-rod.md, 'A closed ring')")
    p.add_argument("--contact-diameter-nm", type=validate.finite(above=0), default=None, metavar="D",
                   help="with --ring: the scene's self-contact diameter, nm (docs/topology.md, 'Self-contact'; "
                        "default: no [contact])")
    add_output(p, metavar="DIR", help="directory to write (steps.h5, material.h5, rest.h5, scene.toml, rest.json)")


def _sequence(args):
    from dna_models.sequence import random_sequence, validate
    from mdbridge.md.folder import md_sequence
    if args.sequence:
        return validate(args.sequence, "--sequence")
    if args.random is not None:
        return random_sequence(args.random, seed=args.seed)
    return md_sequence(args.sequence_from_md, "--sequence-from-md")


def run(args):
    if args.sequence_from_md:
        validate.input_folder(args.sequence_from_md, "--sequence-from-md", "a `dnarod build-md` folder")
    seq = _sequence(args)
    # the solver's fewest grid points (rodcore/src/scene/scene_reader.cpp: fd4 5, spectral 4)
    n_min = 5 if args.space == "fd4" else 4
    if args.points_per_bp * len(seq) < n_min:
        raise InputError(f"{len(seq)} bp x --points-per-bp {args.points_per_bp} = "
                         f"{args.points_per_bp * len(seq)} grid points; the {args.space} solver needs at least "
                         f"{n_min}: give more base pairs or --points-per-bp")
    if args.bp_per_point > 1 and (len(seq) % args.bp_per_point or len(seq) // args.bp_per_point < n_min):
        raise InputError(f"--bp-per-point {args.bp_per_point}: must divide the {len(seq)} bp into at least "
                         f"{n_min} segments (the {args.space} solver's fewest grid points)")
    if args.ring:
        for flag, given in (("--kick", args.kick), ("--box-A", args.box_A is not None),
                            ("--rest equilibrium", args.rest != "closed"),
                            ("--shape exact", args.shape != "interpolated"),
                            ("--points-per-bp", args.points_per_bp > 1)):
            if given:
                raise InputError(f"{flag}: not with --ring (a ring has no box; its rest state is the closed minimum "
                                 "on the coarse grid)")
    elif args.contact_diameter_nm is not None:
        raise InputError("--contact-diameter-nm: only with --ring")
    validate.output_folder(args.output, command="dna-rod")
    from mdbridge.rod.material.dna_rod import DnaRodRequest, dna_rod
    req = DnaRodRequest(
        sequence=seq, output=args.output, params=args.params, mass=args.mass,
        points_per_bp=args.points_per_bp, bp_per_point=args.bp_per_point, interpolation=args.interpolation,
        space=args.space, rest=args.rest, shape=args.shape, box_A=args.box_A, kick=args.kick,
        t_end_ps=args.t_end_ps or (10000.0 if args.ring else 600.0), ring=args.ring,
        contact_diameter_nm=args.contact_diameter_nm, seed=args.seed)
    info = dna_rod(req, log=lambda text: print(text, file=sys.stderr))
    if args.ring:
        print(f"dna-rod: ring rest state Lk = {info['Lk']} (DNA {info['Lk_DNA']}), energy {info['energy_kT']:.4f} kT "
              f"(closed circle {info['energy_start_kT']:.4f}), statics residual {info['statics_residual']:.2e} "
              f"(circle {info['statics_residual_start']:.2e}), closure {info['closure_rotation_rad']:.1e} rad / "
              f"{info['closure_translation_A']:.1e} A, {info['rest_cpu_s']:.0f} CPU s", file=sys.stderr)
        print(f"dna-rod: wrote {Path(args.output)}/ (material.h5, rest.h5, scene.toml, rest.json)")
        return 0
    print(f"dna-rod: rest state tension {info['tension_pN']:.2f} pN, torque {info['torque_pN_nm']:.3f} pN nm, "
          f"statics residual {info['statics_residual']:.2e}, closure {info['closure_rotation_rad']:.2e} rad / "
          f"{info['closure_length_error_A']:.2e} A", file=sys.stderr)
    print(f"dna-rod: wrote {Path(args.output)}/ (steps.h5, material.h5, rest.h5, scene.toml, rest.json)")
    return 0
