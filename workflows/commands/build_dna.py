"""`dnarod build-dna`: an all-atom DNA duplex (PDB, CHARMM27 names, heavy atoms)
from step parameters, an ideal helix, or a rod scene's t = 0 state."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from dna_models import bdna
from dna_models.errors import InputError
from dnarod import validate
from dnarod.commands._options import add_output

NAME = "build-dna"
HELP = "build an all-atom DNA duplex (PDB) from step parameters, an ideal helix or a rod scene"
DESCRIPTION = """\
Build an all-atom double-stranded DNA the way 3DNA's `rebuild` does: each
nucleotide is a rigid B-DNA template (3DNA's BDNA set, CHARMM27 atom names)
placed on its base-pair frame. Writes a PDB (strand I = chain A, strand II =
chain B, both 5'->3') and prints a chemistry report: the worst O3'-P link per
strand and the closest non-bonded heavy-atom pair. Hydrogens are left to
`gmx pdb2gmx -ignh` unless --hydrogens.

Sources of the base-pair frames (choose one):
  --params STEPS.csv   header step,shift,slide,rise,tilt,roll,twist (A, deg), one row
                       per step (n_bp - 1 rows; with --box also n_bp rows, the last
                       being the closing step, which is then only checked); the
                       `dnarod helical-params` CSV (frame,step,...) works too (--frame)
  --params FILE.par    3DNA's bp_step.par (sequence and base-pair parameters included)
  --ideal              uniform helix, --rise and --twist (default B-DNA 3.38 A, 36 deg)
  --scene SCENE.toml   the rod's t = 0 state (rodcore), base pair i on the rod's
                       frame at s_i = i L / n_bp

Examples:
  dnarod build-dna --ideal --sequence CGCGAATTCGCG -o ideal.pdb
  dnarod build-dna --ideal --sequence $(python3 -c "print('ACGT'*5)") --twist 36 --periodic -o ring.pdb
  dnarod build-dna --params steps.csv --sequence CGCGAATTCGCG -o bent.pdb
  dnarod build-dna --params 355d_bp_step.par -o 355d_rebuilt.pdb
  dnarod build-dna --scene workflows/scenes/dna21.toml --sequence ... -o rod_t0.pdb
"""


def add_arguments(p):
    src = p.add_mutually_exclusive_group(required=True)
    src.add_argument("--params", metavar="FILE", help="step parameters: CSV or 3DNA .par")
    src.add_argument("--ideal", action="store_true", help="uniform helix (--rise, --twist)")
    src.add_argument("--scene", metavar="SCENE.toml", help="rod scene: frames of its t = 0 state")
    p.add_argument("--sequence", metavar="SEQ",
                   help="strand I, 5'->3' (A/C/G/T); optional with a .par file (taken from it)")
    p.add_argument("--seed", type=int, default=None,
                   help="with --scene and no --sequence: random sequence with this seed")
    p.add_argument("--rise", type=validate.finite(above=0), default=bdna.RISE_A, help="--ideal rise, A (3.38)")
    p.add_argument("--twist", type=validate.finite(), default=bdna.TWIST_DEG, help="--ideal twist, deg (36)")
    p.add_argument("--frame", type=validate.integer(min=0), default=None, help="frame to use from a multi-frame CSV")
    per = p.add_mutually_exclusive_group()
    per.add_argument("--box", type=validate.finite(above=0), metavar="L",
                     help="periodic: box length along z in A; the strands close through it")
    per.add_argument("--periodic", action="store_true",
                     help="periodic with the natural box: n_bp x rise (--ideal), the rod "
                          "length (--scene)")
    p.add_argument("--no-bp-params", action="store_true",
                   help="ignore the base-pair parameters of a .par file (bases coplanar)")
    p.add_argument("--hydrogens", action="store_true",
                   help="add CHARMM27 hydrogens from templates (default: heavy atoms only)")
    add_output(p, metavar="OUT.pdb", help="PDB file to write")


def _sequence(args, n_needed=None, default=None):
    from dna_models.sequence import validate
    seq = args.sequence or default
    if seq is None:
        raise InputError("--sequence is required with --params CSV and --ideal")
    seq = validate(seq, "--sequence")
    if n_needed is not None and len(seq) != n_needed:
        raise InputError(f"--sequence has {len(seq)} bases but the frames need {n_needed} "
                         "base pairs")
    return seq


def _from_params(args):
    from mdbridge.geometry.steps import frames_from_steps
    from mdbridge.md.builder.params import read_3dna_par, read_steps_csv
    path = Path(args.params)
    bp_params = None
    if path.suffix.lower() == ".par":
        par = read_3dna_par(path)
        seq = _sequence(args, len(par.sequence), default=par.sequence)
        steps = par.steps
        if not args.no_bp_params and np.any(par.base_pair_params != 0):
            bp_params = par.base_pair_params
    else:
        steps = read_steps_csv(path, args.frame)
        seq = _sequence(args)
        n = len(seq)
        if args.box is not None and len(steps) == n:
            steps = steps[:-1]  # the closing step: the junction check reports it
        if len(steps) != n - 1:
            raise InputError(f"{path}: {len(steps)} steps for a {n}-bp sequence; need {n - 1}"
                             + (f" (or {n} with --box)" if args.box is None else ""))
    R, o = frames_from_steps(steps)
    box = args.box
    if args.periodic:
        raise InputError("--periodic needs --ideal or --scene; with --params give --box L")
    return seq, o, R, box, bp_params


def _from_ideal(args):
    from mdbridge.md.builder.frames import ideal_frames
    seq = _sequence(args)
    R, o = ideal_frames(len(seq), args.rise, args.twist)
    box = len(seq) * args.rise if args.periodic else args.box
    return seq, o, R, box, None


def _from_scene(args):
    from mdbridge.md.builder.scene import frames_from_scene
    frames = frames_from_scene(args.scene)
    n = len(frames.origins)
    if args.sequence:
        seq = _sequence(args, n)
    else:
        from dna_models.sequence import random_sequence
        seed = 0 if args.seed is None else args.seed
        seq = random_sequence(n, seed=seed)
        print(f"build-dna: random sequence (seed {seed}): {seq}")
    box = frames.box if args.periodic else args.box
    return seq, frames.origins, frames.R, box, None


def run(args):
    from mdbridge.md.builder import build_duplex, check_chemistry, write_pdb
    if args.params:
        validate.input_file(args.params, "--params", "3DNA .par" if args.params.lower().endswith(".par") else "CSV")
    if args.scene:
        validate.input_file(args.scene, "--scene", "TOML")
    validate.output_file(args.output)
    if args.params:
        seq, o, R, box, bp_params = _from_params(args)
    elif args.ideal:
        seq, o, R, box, bp_params = _from_ideal(args)
    else:
        seq, o, R, box, bp_params = _from_scene(args)
    s = build_duplex(seq, o, R, periodic_box=box, hydrogens=args.hydrogens,
                     base_pair_params=bp_params)
    report = check_chemistry(s)
    out = Path(args.output)
    write_pdb(out, s, remarks=[f"dnarod build-dna: {len(seq)} bp, sequence {seq}",
                               "periodic box " + (f"{np.round(s.box, 3).tolist()} A"
                                                  if s.box is not None else "none")])
    print(f"build-dna: wrote {out} ({s.n_atoms} atoms, {len(seq)} bp"
          + (f", periodic box {np.round(s.box, 3).tolist()} A" if s.box is not None else "")
          + ")")
    print(report)
    return 0
