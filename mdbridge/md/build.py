"""An MD build of a rod scene: what `dnarod build-md` does, in its stages.

`build_md(BuildRequest(scene=..., output=...))` writes the GROMACS inputs of the
periodic, ligated all-atom duplex that starts in the rod scene's shape with the rod's
velocities (paper Sec 6.2; docs/md.md):

1. the DNA: the sequence of a sequence-dependent scene's material file, else the given
   or a random one (`_dna`);
2. the rod run over the MD's length, or the frames of one already made (`_rod_run`;
   gromacs/rod.py; without a length asked for, the MD is as long as that run);
3. the rod at t = 0 on its base pairs, turned so that its helix axis lies on a lab axis,
   the box sized from the rod's own excursion, the duplex built on the rod's frames with
   its backbone closed and its O3'-P links checked (`_place`; gromacs/box.py, builder/);
4. the GROMACS inputs (gromacs/inputs.py build_inputs).

Every default is gromacs/defaults.py's. The command (workflows/commands/build_md.py)
only parses its arguments into a BuildRequest and prints the summary
(gromacs/build_summary.py).
"""
from __future__ import annotations

import secrets
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from dna_models.errors import InputError
from dna_models.sequence import random_sequence, validate
from dna_models.units import ANGSTROM_PER_NM, Units
from mdbridge.rod.run import RodRun, run_scene
from mdbridge.rod.scene import load_scene, resolve_scene, scene_bp_turns, with_absolute_paths

from .builder import build_duplex
from .builder.backbone import check_structure_links
from .gromacs import defaults
from .gromacs.box import plan_box
from .gromacs.equilibrate import check_protocol
from .gromacs.gmx import find_gmx
from .gromacs.inputs import build_inputs
from .gromacs.mdp import MdSettings
from .gromacs.pair_hold import PairHold
from .gromacs.solvent import Solvent, check_medium, solvent_of
from .gromacs.rod import (lab_rotation_to_axis, md_length_ps, md_scene, rod_for_md, rod_initial_from_run,
                          rotate_rod, scene_sequence)


@dataclass
class BuildRequest:
    """Every choice of an MD build (the options of `dnarod build-md`), with its default.
    None: dt_ps from the constraints (defaults.default_dt_ps), protocol from the
    temperature (defaults.default_protocol), seed drawn (and recorded), sequence random,
    bp and turns the scene's, rod: the rod is run, ps: the whole --rod run in whole time
    steps (gromacs/rod.py md_length_ps), defaults.MD_PS when the rod is run."""
    scene: str | Path
    output: str | Path
    temperature_K: float = defaults.TEMPERATURE_K
    seed: int | None = None
    sequence: str | None = None
    bp: int | None = None
    turns: int | None = None
    rod: str | Path | None = None
    ps: float | None = None
    forcefield: str = defaults.FORCEFIELD
    electrostatics: str = defaults.ELECTROSTATICS
    dt_ps: float | None = None
    constraints: str = defaults.CONSTRAINTS
    cutoffs: str = defaults.COMMAND_CUTOFFS
    lincs_order: int = defaults.LINCS_ORDER
    lincs_iter: int = defaults.LINCS_ITER
    thermostat: bool = False
    tau_t_ps: float = defaults.TAU_T_PS
    protocol: str | None = None
    equilibrate_ps: float = defaults.EQUILIBRATE_PS
    axial_pressure: bool = False
    hold_pairs: bool = False
    minimize: bool = False
    margin_A: float = defaults.MARGIN_A
    gmx: str | None = None
    threads: int = defaults.BUILD_THREADS
    solvent: str = defaults.SOLVENT
    salt_mM: float = defaults.SALT_MM
    axial_tension_pN: float | None = None

    def medium(self) -> Solvent | None:
        """The solvent (None: vacuum) with the choices that go with it, checked (before any work)."""
        solvent = solvent_of(self.solvent, self.salt_mM, self.forcefield)
        check_medium(solvent, axial_tension_pN=self.axial_tension_pN, thermostat=self.thermostat,
                     axial_pressure=self.axial_pressure)
        return solvent

    def dt(self) -> float:
        return self.dt_ps if self.dt_ps is not None else defaults.default_dt_ps(self.constraints)

    def settings(self, md_ps: float) -> MdSettings:
        """The md.mdp settings of an MD of md_ps, checked (before any work starts)."""
        dt = self.dt()
        if self.constraints == "none" and dt > defaults.DT_PS + 1e-12:
            raise InputError(f"--dt {dt}: without constraints the X-H bonds (period ~10 fs) need "
                             f"dt <= {defaults.DT_PS} ps; use --constraints h-bonds for "
                             f"{defaults.DT_CONSTRAINED_PS}")
        if not self.tau_t_ps > 0:
            raise InputError(f"--tau-t-ps {self.tau_t_ps}: must be > 0 ps")
        return MdSettings(dt_ps=dt, constraints=self.constraints, thermostat=self.thermostat,
                          tau_t_ps=self.tau_t_ps, cutoffs=self.cutoffs, lincs_order=self.lincs_order,
                          lincs_iter=self.lincs_iter, temperature_K=self.temperature_K,
                          nsteps=int(round(md_ps / dt)), solvated=self.medium() is not None,
                          axial_tension_pN=self.axial_tension_pN)


@dataclass
class _Dna:
    sequence: str
    bp: int
    turns: int | None
    n_bp_scene: int | None      # a sequence-dependent scene's base pairs, else None
    source: str                 # build.json sequence_source


def _say(text: str) -> None:
    print(f"build-md: {text}", file=sys.stderr)


def build_md(req: BuildRequest, stages=None, md_rate=None, say=_say) -> tuple[dict, np.ndarray]:
    """Build the MD of REQ; returns build.json's content and the O3'-P links of the duplex
    as built (builder/backbone.py check_structure_links). STAGES, if given, is called as
    stages(stage, done, total, unit[, rate=]) while the rod run, the minimisation and the
    equilibration run, and has close() (workflows/progress.py Stages); MD_RATE is the rate
    shown for the MD stages. SAY reports each step (default: stderr)."""
    solvent = req.medium()
    gmx = find_gmx(req.gmx)
    if req.ps is not None and req.ps < 0:
        raise InputError(f"--ps {req.ps}: must be >= 0")
    if req.rod and (req.bp is not None or req.turns is not None):
        raise InputError("--rod: the rod run fixes the base pairs and turns; drop --bp/--turns "
                         "(or run the rod again without --rod)")
    req.settings(0.0)   # the choices checked before the rod file is read
    protocol = req.protocol or defaults.default_protocol(req.temperature_K)
    check_protocol(protocol, temperature_K=req.temperature_K, equilibrate_ps=req.equilibrate_ps,
                   axial_pressure=req.axial_pressure)
    u = Units.paper()
    rod_given = RodRun.read(req.rod) if req.rod else None
    md_ps = req.ps if req.ps is not None else md_length_ps(rod_given, dt_ps=req.dt(), units=u)
    settings = req.settings(md_ps)
    seed = req.seed if req.seed is not None else secrets.randbelow(2**31)
    scene, dna = _dna(req, load_scene(req.scene), seed, say)
    run = _rod_run(req, rod_given, md_ps, scene, dna, u, stages, say)
    rod, box, structure = _place(req, run, md_ps, dna, settings, u, in_water=solvent is not None)
    built_links = check_structure_links(structure, where=f"{req.scene}: the duplex on the rod's t = 0 frames")
    say(f"box {np.round(box.box_A, 2).tolist()} A; pdb2gmx, junction check, velocities, grompp ...")
    progress = None if stages is None else (lambda stage, done, total, unit: stages(
        stage, round(done, 6), total, unit, rate=md_rate if unit == "ps" else None,
        time_left=stage != "minimisation"))   # the minimisation stops when converged
    info = build_inputs(Path(req.output), structure, rod, box, sequence=dna.sequence,
                        forcefield=req.forcefield, electrostatics=req.electrostatics,
                        temperature_K=req.temperature_K, seed=seed, settings=settings,
                        minimize=req.minimize, gmx=gmx, threads=req.threads,
                        protocol=protocol, equilibrate_ps=req.equilibrate_ps,
                        axial_pressure=req.axial_pressure, progress=progress,
                        hold_pairs=PairHold() if req.hold_pairs else None, solvent=solvent,
                        meta={"scene": str(Path(req.scene).resolve()), "turns": dna.turns,
                              "rod_run": str(Path(req.rod).resolve()) if req.rod else "run by build-md",
                              "twist_deg": None if dna.turns is None else 360.0 * dna.turns / dna.bp,
                              "md_length_ps": md_ps, "sequence_source": dna.source})
    if stages is not None:
        stages.close()
    return info, built_links


def _dna(req: BuildRequest, scene: dict, seed: int, say) -> tuple[dict, _Dna]:
    """Stage 1: the sequence. A sequence-dependent scene (`dnarod dna-rod`) carries its DNA:
    build THAT sequence (and return the scene with absolute file paths, so that it runs from
    here); a dna_planar scene takes the given sequence or a random one of its length."""
    scene_seq = scene_sequence(scene, req.scene)
    if scene_seq is not None:
        if req.bp is not None or req.turns is not None:
            raise InputError(f"{req.scene}: a sequence-dependent scene fixes its base pairs and shape "
                             "(its material file's sequence); drop --bp/--turns")
        if req.sequence and validate(req.sequence, "--sequence") != scene_seq:
            raise InputError(f"--sequence differs from the sequence of {req.scene} ({len(scene_seq)} bp, "
                             f"{scene_seq[:12]}...): the MD must be the rod's DNA; drop --sequence")
        say(f"{len(scene_seq)} bp, the sequence of the scene's material file, seed {seed}")
        return (with_absolute_paths(scene, req.scene),
                _Dna(scene_seq, len(scene_seq), None, len(scene_seq), "the scene's material file"))
    bp, turns = scene_bp_turns(md_scene(scene, md_ps=0, bp=req.bp, turns=req.turns, source=req.scene),
                               req.scene)
    if req.sequence:
        seq = validate(req.sequence, "--sequence")
        if len(seq) != bp:
            raise InputError(f"--sequence has {len(seq)} bases, the scene has {bp} base pairs")
    else:
        seq = random_sequence(bp, seed=seed)
    say(f"{bp} bp, {turns} turns (twist {360.0 * turns / bp:.4f} deg), seed {seed}")
    return scene, _Dna(seq, bp, turns, None, "given" if req.sequence else f"random, seed {seed}")


def _rod_run(req: BuildRequest, rod_given: RodRun | None, md_ps: float, scene: dict, dna: _Dna, u: Units,
             stages, say) -> RodRun:
    """Stage 2: the rod over the MD's length -- the frames of the given run of the same
    scene (--rod), or the scene run now."""
    if rod_given is not None:
        say(f"the rod run {req.rod} (box sizing) ...")
        return rod_for_md(rod_given, md_ps=md_ps, scene=resolve_scene(Path(req.scene), req.scene), units=u)
    say("running the rod for the MD length (box sizing) ...")
    progress = None if stages is None else (lambda t, t_end: stages(
        "rod run", round(float(u.time_to_ps(t)), 3), round(float(u.time_to_ps(t_end)), 3), "ps"))
    run = run_scene(md_scene(scene, md_ps=md_ps, bp=req.bp, turns=req.turns, units=u,
                             source=req.scene, n_bp=dna.n_bp_scene), source=req.scene, progress=progress)
    if stages is not None:
        stages.close()
    return run


def _place(req: BuildRequest, run: RodRun, md_ps: float, dna: _Dna, settings: MdSettings, u: Units,
           in_water: bool = False):
    """Stage 3: the rod at t = 0 on its base pairs (a sequence-dependent scene's closed shape
    turned so that its helix axis is lab Y: the box is orthorhombic; in water every scene's
    helix axis is turned onto lab Z, the axis that semi-isotropic pressure coupling keeps
    apart), the box sized from the rod's excursion over the run, and the duplex built on the
    rod's frames (its backbone closed: builder/backbone.py)."""
    rod, centerline = rod_initial_from_run(run, dna.bp, u)
    if in_water:
        rod, centerline = rotate_rod(rod, centerline, lab_rotation_to_axis(run, axis=2))
    elif dna.n_bp_scene is not None:
        rod, centerline = rotate_rod(rod, centerline, lab_rotation_to_axis(run, axis=1))
    box = plan_box(centerline, rod.origins_A, rod.closure_length_A, rod_run_ps=md_ps,
                   cutoff_A=settings.cutoff_nm * ANGSTROM_PER_NM, margin_A=req.margin_A)
    periodic = np.zeros(3)
    periodic[box.axis] = rod.closure_length_A
    return rod, box, build_duplex(dna.sequence, rod.origins_A, rod.R, periodic_box=periodic, close_backbone=True)
