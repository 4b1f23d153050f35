"""`dnarod helical-params`: 3DNA-exact base-pair step parameters of a DNA
duplex in a structure or along a trajectory (mdbridge.geometry)."""
from __future__ import annotations

import sys
import warnings

from dna_models.errors import InputError


NAME = "helical-params"
HELP = "base-pair step parameters (shift, slide, rise, tilt, roll, twist) of a DNA duplex"
DESCRIPTION = """\
Base-pair step parameters of a DNA duplex, as 3DNA v2.3 defines them
(Olson et al. 2001 standard frame, CEHS step parameters), one CSV row per
step and trajectory frame:

    frame,step,shift,slide,rise,tilt,roll,twist

(Angstrom and degrees; step k joins base pairs k and k+1, numbered from 1
along strand I; frame counts from 0). Reads anything MDAnalysis reads: PDB
(all models), GRO, TPR + XTC/TRR. Base pairs are found automatically for a
duplex (two antiparallel complementary strands, or a hairpin); give them with
--pairs for anything else.

A `dnarod build-md` folder (or a file in it: conf.gro, md.tpr, ...) is read with
the base pairs its build.json records (the builder's: pair k joins residues k and
2n + 1 - k), so that a frayed or strained pair does not stop the pairing; --pairs
overrides them.

examples:
  dnarod helical-params 355d.pdb
  dnarod helical-params md158 --periodic            (md158/conf.gro, pairs from md158/build.json)
  dnarod helical-params topol.tpr traj.xtc --csv steps.csv --periodic
  dnarod helical-params sample_md0.pdb --pairs bpfile.dat
"""


def add_arguments(p):
    from dnarod import validate
    p.add_argument("structure", metavar="STRUCTURE",
                   help="PDB, GRO, TPR, ... (topology and/or coordinates), or a build-md folder")
    p.add_argument("trajectory", metavar="TRAJECTORY", nargs="?", help="optional XTC/TRR/DCD/... trajectory")
    p.add_argument("--csv", metavar="OUT", help="write the table to OUT instead of standard output")
    p.add_argument("--pairs", metavar="FILE",
                   help="base pairs: a 3DNA bpfile (find_pair output; nucleotides numbered 1, 2, ... "
                        "in file order) or lines 'resid_I resid_II'")
    p.add_argument("--periodic", action="store_true",
                   help="ligated periodic duplex: add the closing step from the last pair to the first")
    p.add_argument("--no-pbc", action="store_true",
                   help="ignore the periodic box (by default pair and step vectors are minimum images)")
    p.add_argument("--box", type=validate.finite(above=0), nargs=3, metavar=("LX", "LY", "LZ"),
                   help="the orthorhombic periodic box in A, for a file that does not carry it "
                        "(a PDB without CRYST1); replaces the file's box in every frame")
    p.add_argument("--start", type=int, default=None, help="first trajectory frame (0-based)")
    p.add_argument("--stop", type=int, default=None, help="stop before this frame")
    p.add_argument("--step", type=validate.integer(min=1), default=None, help="take every STEP-th frame")


def run(args):
    import numpy as np
    from mdbridge.geometry.structure import BasePairFrames, read_pairs_file

    from mdbridge.geometry.structure import load_universe
    from dnarod import validate
    if args.pairs:
        validate.input_file(args.pairs, "--pairs", "text")
    if args.csv:
        validate.output_file(args.csv, "--csv")
    structure, build_pairs = _build_md_folder(args.structure)
    u = load_universe(structure, *([args.trajectory] if args.trajectory else []))
    if args.box is not None:
        from MDAnalysis.transformations.boxdimensions import set_dimensions
        if args.no_pbc or min(args.box) <= 0:
            raise InputError(f"--box {' '.join(f'{x:g}' for x in args.box)}: three edges > 0 A, "
                             "and not with --no-pbc")
        u.trajectory.add_transformations(set_dimensions([*args.box, 90.0, 90.0, 90.0]))
    pairs, numbering = (None, "resid")
    if args.pairs:
        pairs, numbering = read_pairs_file(args.pairs)
    elif build_pairs is not None:
        pairs, numbering = build_pairs, "serial"
    bpf = BasePairFrames(u, pairs=pairs, pair_numbering=numbering, pbc=not args.no_pbc)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # "Reader has no dt information" for PDB models
        bpf.run(args.start, args.stop, args.step)
    P = bpf.step_parameters(periodic=args.periodic)
    T, n_steps, _ = P.shape
    frames = np.repeat(bpf.results.frame, n_steps)
    step = np.tile(np.arange(1, n_steps + 1), T)
    out = open(args.csv, "w") if args.csv else sys.stdout
    try:
        out.write("frame,step,shift,slide,rise,tilt,roll,twist\n")
        rows = P.reshape(-1, 6)
        for f, k, r in zip(frames, step, rows):
            out.write(f"{f},{k}," + ",".join(f"{x:.4f}" for x in r) + "\n")
    finally:
        if args.csv:
            out.close()
    return 0


def _build_md_folder(structure):
    """(structure file, pairs or None): a build-md folder means its conf.gro, and a file
    in such a folder comes with the pairs its build.json records, as 1-based nucleotide
    serial numbers (the build's residues are strand I 1..n, then strand II n+1..2n, in
    file order; a TPR numbers each strand's residues from 1 again)."""
    import json
    from pathlib import Path
    from mdbridge.md.builder.duplex import base_pairs
    path = Path(structure)
    folder = path if path.is_dir() else path.parent
    build = folder / "build.json"
    if path.is_dir():
        if not build.is_file():
            raise InputError(f"{path}: a folder, and not a `dnarod build-md` one (no build.json): give a "
                             "structure file")
        path = folder / "conf.gro"
    if not build.is_file():
        return path, None
    try:
        n_bp = int(json.loads(build.read_text())["n_bp"])
    except (ValueError, KeyError, TypeError) as e:
        raise InputError(f"{build}: not a build-md record ({type(e).__name__}: {e}); give --pairs") from None
    print(f"helical-params: base pairs from {build} ({n_bp} bp; --pairs overrides)", file=sys.stderr)
    return path, base_pairs(n_bp)
