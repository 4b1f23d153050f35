"""`dnarod rod-to-atoms`: a rod trajectory as molecules for VMD, PyMOL, MDAnalysis."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from dna_models.errors import InputError
from dnarod import validate
from dnarod.commands._options import add_output
from mdbridge.jsonio import write_json

NAME = "rod-to-atoms"
HELP = "write a rod run as an all-atom trajectory (like an MD build) or as a coarse bead model"
DESCRIPTION = """\
Back-map every frame of a rod run (rodsim HDF5 with centerline and directors) to
molecules a viewer reads (docs/viewing.md).

  --like MDDIR  all-atom: each rod frame rebuilt by the builder's rule on the rod's
                base-pair frames, in the atoms, order and names of the MD build in
                MDDIR (its conf.gro / topol.top), so MDDIR's structure file loads both
                the rod's and the MD's trajectories and overlays them frame by frame.
                Writes OUT (.xtc, .trr or .dcd), OUT's first frame as .gro and .pdb, and
                OUT.chemistry.json: per frame the O3'-P link lengths (min/max) and the
                closest non-bonded heavy-atom contact, since rigid nucleotides on
                strained frames stretch the backbone.
  --coarse      one pseudo-atom per base pair on the centreline (C) plus the tip of
                its d1 director (D1), bonded by CONECT records: a light view of the rod
                and its twist. OUT is a multi-model .pdb. With --like MDDIR too, in the
                MD's coordinates (and box).

Examples:
  dnarod rod-to-atoms out/rod/Av1/rod.h5 --like out/md/Av1_seed1 -o rod_atoms.xtc
  vmd out/md/Av1_seed1/conf.gro rod_atoms.xtc out/md/Av1_seed1/md.xtc   (see docs/viewing.md)
  dnarod rod-to-atoms out/rod/Av1/rod.h5 --coarse --bp 158 -o rod_coarse.pdb
"""


def add_arguments(p):
    p.add_argument("rod", help="rod run (rodsim HDF5 with centerline and directors)")
    p.add_argument("--like", metavar="MDDIR", help="MD build directory (dnarod build-md) whose atoms and "
                                                  "coordinates to use (with --coarse: only its coordinates)")
    p.add_argument("--coarse", action="store_true", help="coarse bead model instead of atoms")
    add_output(p, help="output trajectory (.xtc/.trr/.dcd with --like, .pdb with --coarse)")
    p.add_argument("--bp", type=validate.integer(min=2),
                   help="base pairs the rod carries (default: from MDDIR/build.json or the "
                                          "rod file's scene)")
    p.add_argument("--every", type=validate.integer(min=1), default=1, help="write every n-th rod frame (default 1)")
    p.add_argument("--no-chemistry", action="store_true", help="skip the per-frame link/contact report")
    p.add_argument("--relax-steps", type=validate.integer(min=0), default=0,
                   help="with --like: a restrained steepest descent of this many steps per frame (base "
                        "atoms held, the MD build's em.mdp), for viewing; 0 = off (default)")
    p.add_argument("--gmx", help="gmx executable for --relax-steps (default: as dnarod run-md finds it)")


def _n_bp(args, rod_path: Path, build: dict | None) -> int:
    if args.bp:
        return args.bp
    if build is not None:
        return int(build["n_bp"])
    from mdbridge.rod.run import RodRun
    from mdbridge.rod.scene import scene_n_bp
    scene = RodRun.read(rod_path).attrs.get("scene")
    if scene is None:
        raise InputError(f"{rod_path}: the number of base pairs is not recorded; give --bp")
    import tomllib
    return scene_n_bp(tomllib.loads(scene), str(rod_path))


def run(args) -> int:
    from mdbridge.rod.run import RodRun
    rod = Path(args.rod)
    if not rod.exists():
        raise InputError(f"{rod}: no such rod run (rodsim HDF5)")
    validate.input_file(rod)
    if args.every < 1:
        raise InputError(f"--every {args.every}: must be at least 1")
    out = Path(args.output)
    if not (args.like or args.coarse):
        raise InputError("give --like MDDIR (all-atom, like that MD build) or --coarse (beads)")
    build = None
    if args.like:
        md = validate.input_folder(args.like, "--like", "an MD build folder of `dnarod build-md`")
        for f in ("build.json", "conf.gro", "topol.top"):
            if not (md / f).is_file():
                raise InputError(f"--like {md}: {f} missing (an MD build directory of `dnarod build-md`)")
        build = json.loads((md / "build.json").read_text())
    if args.coarse and out.suffix.lower() != ".pdb":
        raise InputError(f"-o {out}: --coarse writes a multi-model PDB; name it *.pdb")
    if not args.coarse and out.suffix.lower() not in (".xtc", ".trr", ".dcd"):
        raise InputError(f"-o {out}: allowed trajectory formats .xtc, .trr, .dcd")
    n_bp = _n_bp(args, rod, build)
    validate.output_file(out)
    run = RodRun.read(rod)
    R, o = run.bp_frames(n_bp)
    if build is not None:
        R, o = _in_build_frame(run, R, o, build)
    t = np.asarray(run.time, float) * float(run.attrs.get("tau_ps", 1.0))  # ps, as the MD's
    R, o, t = R[::args.every], o[::args.every], t[::args.every]
    if args.coarse:
        from mdbridge.md.backmap import write_coarse_pdb
        write_coarse_pdb(out, R, o, box=None if build is None else build["box"]["box_A"])
        print(f"rod-to-atoms: {len(t)} frames of {n_bp} beads (+ d1 tips) -> {out}")
        return 0
    from dnarod.progress import Stages
    with Stages("rod-to-atoms") as stages:
        return _atoms(args, md, build, out, R, o, t, stages)


def _in_build_frame(run, R, o, build):
    """The rod's base-pair frames where build-md put the duplex: build-md turns the rod's
    helix axis (its period vector at t = 0) onto the box axis (lab_rotation_to_axis, a
    no-op for a rod already along it) and moves the duplex into its box by
    build.json's box.shift_A. The same rigid motion puts the rod where the MD is, so the
    two overlay frame by frame, whatever axis the scene uses."""
    from mdbridge.md.gromacs.rod import lab_rotation_to_axis
    Q = lab_rotation_to_axis(run, axis=int(build["box"]["axis"]))
    R = np.einsum("ij,tnjk->tnik", Q, R)
    o = o @ Q.T + np.asarray(build["box"]["shift_A"], dtype=float)
    return R, o


# frames placed per call of AtomMap.place: progress granularity, and the memory of one
# vectorised call stays small
CHUNK = 25


def _atoms(args, md, build, out, R, o, t, stages) -> int:
    """The all-atom trajectory; STAGES (dnarod.progress.Stages) shows the frames
    back-mapped, relaxed (--relax-steps), written and checked (chemistry report)."""
    import MDAnalysis as mda
    from mdbridge.md.backmap import atom_map, overlay_problems, rms_to_build_A
    from mdbridge.md.gromacs.gmx import find_gmx, gmx_top_dir
    gmx = find_gmx(args.gmx)
    # topol.top #includes charmm27.ff/...: the force-field folder of the GROMACS install
    u = mda.Universe(str(md / "topol.top"), str(md / "conf.gro"), topology_format="ITP",
                     include_dir=str(gmx_top_dir(gmx)))
    amap = atom_map(u, build["sequence"])
    n = len(t)
    xyz = np.empty((n, u.atoms.n_atoms, 3), dtype=np.float32)
    for a in range(0, n, CHUNK):
        xyz[a:a + CHUNK] = amap.place(R[a:a + CHUNK], o[a:a + CHUNK])
        stages("frames back-mapped", min(n, a + CHUNK), n, "frames")
    rms_t0 = rms_to_build_A(u, xyz[0], md / "duplex_in.pdb")
    if args.relax_steps:
        from mdbridge.md.backmap import relax
        xyz = relax(md, u, xyz, steps=args.relax_steps, gmx=gmx,
                    workdir=out.with_name(out.stem + "_relax"),
                    progress=lambda k, total: stages("frames relaxed", k, total, "frames")
                    ).astype(np.float32)
    _write_frames(out, u, xyz, t, stages)
    msg = (f"rod-to-atoms: {len(t)} frames x {u.atoms.n_atoms} atoms -> {out} (+ {out.with_suffix('.gro').name})"
           f"; t = 0 vs the build {rms_t0:.3f} A rms")
    links = contact = None
    if not args.no_chemistry:
        links, contact, text = _chemistry(u, xyz, amap, t, out, stages, build.get("forcefield"))
        msg += text
    stages.close()
    print(msg)
    problems = overlay_problems(rms_t0, links, contact, t)
    if problems:
        hint = ("" if args.relax_steps or all("rms" in q for q in problems) else
                "; to look at it anyway, --relax-steps N relaxes each frame (for viewing only)")
        raise InputError(f"{out} (written, to look at) fails its checks: " + "; ".join(problems) + hint)
    return 0


def _write_frames(out, u, xyz, t, stages) -> None:
    """OUT (XTC or another MDAnalysis format) with every frame, and its first frame as .gro and .pdb."""
    import warnings

    import MDAnalysis as mda
    # XTC at 1e-4 nm (GROMACS's default is 1e-3 nm = 0.01 A, which alone tilts a fitted
    # base frame by up to ~0.2 deg): re-analysed frames then equal the rod's to 0.1 deg
    opts = {"precision": 4} if out.suffix.lower() == ".xtc" else {}
    with mda.Writer(str(out), n_atoms=u.atoms.n_atoms, **opts) as w:
        for k in range(len(t)):
            u.atoms.positions = xyz[k]
            u.trajectory.ts.time = float(t[k])
            w.write(u.atoms)
            stages("frames written", k + 1, len(t), "frames")
    u.atoms.positions = xyz[0]
    u.atoms.write(str(out.with_suffix(".gro")))
    with warnings.catch_warnings():  # MDAnalysis lists the PDB columns a .gro lacks
        warnings.simplefilter("ignore", UserWarning)
        u.atoms.write(str(out.with_suffix(".pdb")))


def _chemistry(u, xyz, amap, t, out, stages, forcefield_name):
    """(O3'-P link lengths, closest non-bonded contacts, the summary's text) of every frame,
    written to OUT.chemistry.json; the bond's equilibrium is the build's force field's."""
    from mdbridge.md.backmap import closest_nonbonded
    from mdbridge.md.builder.backbone import link_lengths
    from mdbridge.md.forcefields import forcefield
    from mdbridge.md.gromacs.defaults import FORCEFIELD
    ff = forcefield(forcefield_name or FORCEFIELD)
    links = link_lengths(xyz, amap.links, amap.box_A)
    contact = closest_nonbonded(u, xyz, progress=lambda k, total: stages("frames checked", k, total, "frames"))
    report = {"times_ps": t.tolist(), "O3P_min_A": links.min(1).tolist(), "O3P_max_A": links.max(1).tolist(),
              "closest_nonbonded_heavy_A": [float(c) if np.isfinite(c) else None for c in contact],
              "definitions": {"O3P": "O3'(i)-P(i+1) bond lengths along both strands, minimum image; "
                                     f"{ff.name} equilibrium {ff.o3_p.length_A:.2f} A",
                              "closest_nonbonded_heavy_A": "closest heavy-atom pair that is not 1-2 or 1-3 "
                                                           "bonded, within 4 A (null: none)"}}
    path = out.with_suffix(".chemistry.json")
    write_json(path, report)
    text = (f"; O3'-P {links.min():.2f}-{links.max():.2f} A, closest contact "
            f"{np.nanmin(np.where(np.isfinite(contact), contact, np.nan)):.2f} A ({path.name})")
    return links, contact, text
