"""`dnarod minicircle`: a supercoiled DNA minicircle, rod and atoms (mdbridge.rod.minicircle,
mdbridge.md.ring; docs/topology.md, "A supercoiled minicircle")."""
from __future__ import annotations

import argparse
import secrets
import sys

from mdbridge.md.gromacs.defaults import TEMPERATURE_K

NAME = "minicircle"
HELP = "a DNA ring at a chosen linking number: closed rod, relaxation, writhe, all-atom ring"
DESCRIPTION = """\
A closed DNA ring of N base pairs at Lk = round(Lk0) + D, Lk0 = N / (bp per turn of
the relaxed rod), relaxed in the Langevin rod, with its linking number, twist and
writhe; then the all-atom ring on the relaxed rod's base pairs, minimised, with
GROMACS inputs.

Lk of a closed ring is an integer; Lk0 in general is not, so the linking-number
difference Lk - Lk0 is D + round(Lk0) - Lk0, within 0.5 of D (336 bp of Olson 1998
DNA: Lk0 = 31.8765, D = -2 gives Lk = 30 and Lk - Lk0 = -1.8765). The command
prints both; Lk - Lk0 = D exactly needs a ring whose Lk0 is an integer.

Writes into DIR:

  material.h5     the DNA's grid material (as `dnarod dna-rod`)
  ring.h5         the t = 0 state: the planar ring of Lk turns, closed, with a small
                  out-of-plane seed velocity (initial.kind = "file")
  scene.toml      the relaxation: [thermal] Langevin rod (--temperature-K, --friction),
                  [contact] with --contact-diameter-nm
  relax.h5        the rod run (rodsim's output)
  minicircle.json Lk0, Lk, D, Lk - Lk0; per frame time_ps, Lk, Tw, Wr (about the helical
                  axis, as the atoms': docs/topology.md) and Wr_centreline; the last
                  frame's Tw and Wr; the relaxation test; the all-atom ring's Lk, Tw, Wr
                  and closest atom pairs
  atoms/          conf.gro, topol.top, strand .itp files, md.mdp, em.mdp, build.json
                  (`dnarod run-md atoms` runs it; `dnarod topology atoms` reads it)

Relaxed: the ring is called relaxed only when its energy and its writhe have stopped
changing: for each, the mean over the run's last quarter within 2 standard errors
(or 0.1 kT, 0.01 turns) of the mean over its third quarter; otherwise the command
says "NOT relaxed" with the numbers (docs/topology.md).

Checks (each an error, exit 2, after minicircle.json is written): every frame of the
run is a ring, its Lk never changes (a rod without self-contact passes through itself
once an overtwisted ring has buckled far enough), the built strands (C1' and P
polygons, and conf.gro's C1') link as often as the rod, and no atoms of conf.gro clash
(non-bonded pairs closer than 1.5 A, heavy atoms closer than 2.2 A).

examples:
  dnarod minicircle --bp 336 --delta-lk -2 --random-seed 1 -o mc336
  dnarod minicircle --bp 80 --delta-lk 1 --params paper --relax-ps 500 -o mc80
  dnarod minicircle --sequence ACGT... --delta-lk 0 --no-atoms -o ring
"""


def add_arguments(p):
    from dnarod import validate
    from dnarod.commands._options import add_output
    p.add_argument("--bp", type=validate.integer(min=1), metavar="N",
                   help="base pairs (with --random-seed; implied by --sequence)")
    p.add_argument("--delta-lk", type=int, required=True, metavar="D",
                   help="turns added to the relaxed ring: Lk = round(Lk0) + D (an integer; Lk - Lk0 is "
                        "within 0.5 of D)")
    src = p.add_mutually_exclusive_group()
    src.add_argument("--sequence", metavar="SEQ", help="strand I, 5'->3' (A/C/G/T)")
    src.add_argument("--random-seed", type=int, metavar="S",
                     help="a random sequence of --bp bases from seed S (default: a drawn seed, recorded)")
    p.add_argument("--params", default="olson1998", metavar="SET",
                   help="paper | olson1998 | a per-step file STEPS.h5 (default olson1998; as dna-rod)")
    p.add_argument("--points-per-bp", type=validate.integer(min=1), default=None, metavar="M",
                   help="grid points per base pair (default 1 for paper, 2 otherwise: a sequence-dependent "
                        "ring on 1 point per bp opens in the run, docs/topology.md)")
    p.add_argument("--temperature-K", type=validate.finite(min=0), default=0.0, metavar="T",
                   help="temperature of the Langevin relaxation (default 0: friction only)")
    p.add_argument("--friction", default="critical", metavar="F",
                   help="critical (default: every velocity damped at twice the ring's slowest bending "
                        "frequency), water (DNA's drag: microseconds for 336 bp), or a rate [1/ps]")
    p.add_argument("--relax-ps", type=validate.finite(min=0), default=None, metavar="PS",
                   help="length of the relaxation (default 5000 ps; 0: no run, the atoms on the planar ring)")
    p.add_argument("--frames", type=validate.integer(min=1), default=None, metavar="K",
                   help="output frames of the run (101)")
    p.add_argument("--seed-kick", type=validate.finite(), default=None, metavar="A_PER_PS",
                   help="out-of-plane seed velocity amplitude (0.01 A/ps; 0: none)")
    p.add_argument("--contact-diameter-nm", type=validate.finite(above=0), default=None, metavar="D",
                   help="self-contact: [contact] diameter_nm = D in the scene, so the ring cannot pass "
                        "through itself (off by default; docs/topology.md, Self-contact)")
    p.add_argument("--no-atoms", action="store_true", help="the rod only, no all-atom ring")
    p.add_argument("--md-temperature-K", type=validate.finite(min=0), default=TEMPERATURE_K, metavar="T",
                   help=f"thermal velocities of the all-atom ring ({TEMPERATURE_K:g})")
    p.add_argument("--minimize", action=argparse.BooleanOptionalAction, default=True,
                   help="restrained minimisation of the all-atom ring (default; --no-minimize: none, and "
                        "clashing atoms are then an error)")
    p.add_argument("--gmx", default=None, metavar="PATH", help="the gmx executable (as build-md)")
    p.add_argument("--threads", type=validate.integer(min=1), default=1, metavar="N",
                   help="mdrun threads of the minimisation (1: a ring of a few thousand atoms)")
    add_output(p, metavar="DIR", help="output folder")


def _sequence(args) -> tuple[str, str]:
    from dna_models.errors import InputError
    from dna_models.sequence import random_sequence, validate
    if args.sequence:
        seq = validate(args.sequence, "--sequence")
        if args.bp is not None and args.bp != len(seq):
            raise InputError(f"--bp {args.bp}: --sequence has {len(seq)} bases")
        return seq, "given"
    if args.bp is None:
        raise InputError("--bp N is needed with a random sequence (or give --sequence)")
    seed = args.random_seed if args.random_seed is not None else secrets.randbelow(2**31)
    return random_sequence(args.bp, seed=seed), f"random, seed {seed}"


def _choice(args):
    from dna_models.errors import InputError
    from mdbridge.rod.minicircle import FRAMES, RELAX_PS, SEED_KICK_A_PER_PS, RelaxationChoice
    friction = args.friction
    if friction not in ("critical", "water"):
        try:
            friction = float(friction)
        except ValueError:
            raise InputError(f"--friction {args.friction!r}: allowed 'critical', 'water' or a rate > 0 "
                             "[1/ps]") from None
    c = RelaxationChoice(temperature_K=args.temperature_K, friction=friction,
                         relax_ps=RELAX_PS if args.relax_ps is None else args.relax_ps,
                         frames=FRAMES if args.frames is None else args.frames,
                         seed_kick_A_per_ps=SEED_KICK_A_PER_PS if args.seed_kick is None else args.seed_kick,
                         contact_diameter_nm=args.contact_diameter_nm)
    c.check()
    return c


def _checked(args):
    """(sequence, its source, RelaxationChoice, points per bp, gmx or None): every input
    checked before any work."""
    from dna_models.errors import InputError
    seq, seq_source = _sequence(args)
    if len(seq) < 10:
        raise InputError(f"{len(seq)} bp: a minicircle needs at least 10 base pairs")
    choice = _choice(args)
    ppb = args.points_per_bp if args.points_per_bp is not None else (1 if args.params == "paper" else 2)
    if ppb < 1:
        raise InputError(f"--points-per-bp {ppb}: must be >= 1")
    if args.threads < 1:
        raise InputError(f"--threads {args.threads}: must be >= 1")
    if args.md_temperature_K < 0:
        raise InputError(f"--md-temperature-K {args.md_temperature_K}: must be >= 0")
    gmx = None
    if not args.no_atoms:
        from mdbridge.md.gromacs.gmx import find_gmx
        gmx = find_gmx(args.gmx)
    return seq, seq_source, choice, ppb, gmx


def run(args):
    import numpy as np

    from dna_models.units import Units
    from mdbridge.jsonio import write_json
    from mdbridge.rod.material.gridfile import write_grid_material
    from mdbridge.rod.material.parameter_sets import step_material
    from mdbridge.rod.material.steps_to_rod import grid_material, rod_material
    from mdbridge.rod.minicircle import (check_relaxation, make_minicircle, relaxation_test, relaxation_topology,
                                         relaxation_words)
    from mdbridge.rod.run import run_scene
    from mdbridge.rod.scene import with_absolute_paths, write_scene

    u = Units.paper()
    seq, seq_source, choice, ppb, gmx = _checked(args)
    sm = step_material(seq, args.params, closed=True)

    from dnarod import validate
    out = validate.output_folder(args.output, command="minicircle")
    rm = rod_material(sm, units=u)
    g = grid_material(rm, ppb * rm.n_bp, "trig")
    print(f"minicircle: {rm.n_bp} bp ({seq_source}), {args.params}, {ppb} point(s) per bp; closing the ring ...",
          file=sys.stderr)
    mc = make_minicircle(g, rm.length, rm.n_bp, args.delta_lk, choice, out, u)
    write_grid_material(out / "material.h5", g, source=sm.source,
                        attrs={"sequence": seq, "interpolation": "trig", "h_A": rm.h_A})
    write_scene(out / "scene.toml", mc.scene,
                comment=f"{rm.n_bp}-bp minicircle, Lk = {mc.Lk} = round(Lk0) + ({args.delta_lk}), Lk0 = "
                        f"{mc.Lk0:.4f}, Lk - Lk0 = {mc.Lk - mc.Lk0:+.4f}, sequence {seq}\nparameters: {sm.source}\n"
                        "written by `dnarod minicircle` (docs/topology.md, 'A supercoiled minicircle')")
    print(f"minicircle: {_lk_words(mc, args.delta_lk)}; relaxing for {choice.relax_ps:g} ps ...", file=sys.stderr)
    run_ = run_scene(with_absolute_paths(mc.scene, out / "scene.toml"), source=str(out / "scene.toml"),
                     output=out / "relax.h5")
    top = relaxation_topology(run_, mc.Lk, contact=choice.contact_diameter_nm is not None)
    relaxed = relaxation_test(run_, top, TEMPERATURE_K, u) if choice.relax_ps > 0 and not top["failure"] else {
        "relaxed": None, "rule": None, "reason": "--relax-ps 0: no run" if choice.relax_ps == 0 else "failed run"}
    info = {"format": "dnarod-minicircle/1", "sequence": seq, "sequence_source": seq_source,
            "params": args.params, "source": sm.source, **mc.as_dict(), "delta_Lk_asked": args.delta_lk,
            "relaxation": {
                "temperature_K": choice.temperature_K, "friction": mc.scene["thermal"],
                "relax_ps": choice.relax_ps, "seed_kick_A_per_ps": choice.seed_kick_A_per_ps,
                "contact": mc.scene.get("contact"), "wall_seconds": run_.summary.get("wall_seconds"),
                **relaxed},
            "topology": top, "failure": top["failure"]}
    if top.get("Wr"):
        info.update(Tw_final=top["Tw"][-1], Wr_final=top["Wr"][-1], Wr_centreline_final=top["Wr_centreline"][-1],
                    energy_kT=(np.asarray(run_.energy, float) / u.kT_to_rod(TEMPERATURE_K)).tolist()
                    if run_.energy is not None else None)
    write_json(out / "minicircle.json", info)
    check_relaxation(top)
    print(f"minicircle: Lk {mc.Lk} in all {len(top['Lk'])} frames of the run; last frame Tw {top['Tw'][-1]:.4f}, "
          f"Wr {top['Wr'][-1]:.4f} (about the helical axis; Tw + Wr - Lk "
          f"{top['Tw'][-1] + top['Wr'][-1] - mc.Lk:+.1e})", file=sys.stderr)
    print("minicircle: " + (relaxation_words(relaxed, choice.relax_ps) if relaxed["rule"] else
                            "not relaxed: --relax-ps 0, no run"), file=sys.stderr)
    if not args.no_atoms:
        _atoms(args, run_, seq, out, mc.Lk, choice, gmx, info)
    print(f"wrote {out}/")
    return 0


def _lk_words(mc, D: int) -> str:
    """Lk, the D asked for and Lk - Lk0, each named (the command's description)."""
    words = (f"Lk0 = {mc.Lk0:.4f} ({mc.n_bp / mc.Lk0:.4f} bp per turn); Lk = round(Lk0) + D = {round(mc.Lk0)} "
             f"{'+' if D >= 0 else '-'} {abs(D)} = {mc.Lk} (D = {D} as asked); linking-number difference "
             f"Lk - Lk0 = {mc.Lk - mc.Lk0:+.4f}")
    if abs(mc.Lk - mc.Lk0 - D) < 5e-5:
        return words
    return words + f", not {D}: a closed ring's Lk is an integer and this Lk0 is not"


def _atoms(args, run_, seq, out, Lk, choice, gmx, info) -> None:
    """The all-atom ring of the relaxed rod's last frame (the planar ring's without a run),
    minimised unless --no-minimize, recorded in minicircle.json; a clash or a strand Lk
    other than the rod's is an error after minicircle.json is written."""
    from dna_models.errors import DnarodError
    from mdbridge.jsonio import write_json
    from mdbridge.md.ring import build_ring_md
    frame = -1 if choice.relax_ps > 0 else 0
    try:
        info["atoms"] = build_ring_md(run_, seq, out / "atoms", Lk=Lk, frame=frame,
                                      temperature_K=args.md_temperature_K, minimize=args.minimize, gmx=gmx,
                                      threads=args.threads, seed=choice.seed,
                                      meta={"minicircle": str(out / "minicircle.json")},
                                      say=lambda s: print(f"minicircle: {s}", file=sys.stderr))
    except DnarodError as e:
        info["failure"] = str(e)
        write_json(out / "minicircle.json", info)
        raise
    a = info["atoms"]
    t = a["conf_gro_topology"]
    rod_Wr = info["topology"]["Wr"][frame]
    print(f"minicircle: all-atom ring (atoms/conf.gro): Lk {a['strands_Lk_conf_gro']}, Tw {t['Tw']:.4f}, "
          f"Wr {t['Wr']:.4f} (the rod's frame: Wr {rod_Wr:.4f})", file=sys.stderr)
    write_json(out / "minicircle.json", info)
