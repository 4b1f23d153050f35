"""The sequence-dependent DNA rod, as a library call: per-step file, grid material, closed
pre-stressed rest state (kicked or not) and scene, written into one folder.

`dna_rod(DnaRodRequest(...))` is what `dnarod dna-rod` runs (workflows/commands/dna_rod.py
parses, calls this and prints) and what the comparison's loop runs for the per-step
coarse-grained rod (workflows/steps/cgloop.py). The files and rest.json's keys:
docs/scenes.md, "Sequence-dependent DNA".
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from dna_models.errors import InputError
from dna_models.units import Units
from mdbridge.jsonio import write_json


@dataclass
class DnaRodRequest:
    """The rod of SEQUENCE (validated) and how to make it; the fields are `dnarod dna-rod`'s options."""
    sequence: str
    output: str
    params: str = "olson1998"          # paper | olson1998 | a per-step file STEPS.h5
    mass: str = "paper"                # paper | atoms
    points_per_bp: int = 1
    bp_per_point: int = 1              # > 1: coarse segments of that many base pairs (coarse.py)
    interpolation: str = "trig"        # trig | smooth | step
    space: str = "spectral"            # spectral | fd4
    rest: str = "closed"               # closed | equilibrium
    shape: str = "interpolated"        # interpolated | exact
    box_A: float | None = None         # end-to-end length along the helix axis (default n_bp x rise)
    kick: float = 0.0                  # A_v, A/ps (0: at rest)
    t_end_ps: float = 600.0
    ring: bool = False                 # a closed ring in water (ring_rest.py) instead of the box-held rod
    contact_diameter_nm: float | None = None   # --ring: the scene's [contact] diameter (None: no contact)
    seed: int | None = None            # --ring: the scene's thermal.seed (and the sequence's, recorded)


def _kicked_gamma(rest, g, L: float, kick_A_per_ps: float, u: Units) -> np.ndarray:
    """Body-frame velocities of the paper's kick (Sec 6.1): lab velocity A_v sin(2 pi s / L) e_perp,
    e_perp = d1(0) made normal to the helix axis."""
    from mdbridge.rod.material.closed_rest import _frames_on_grid
    R = _frames_on_grid(np.concatenate([rest.Gamma, rest.Omega], axis=1), L, 16)
    a = rest.axis0
    e = np.array([1.0, 0.0, 0.0]) - a[0] * a
    e /= np.linalg.norm(e)
    v = u.velocity_to_rod(kick_A_per_ps) * np.sin(2 * np.pi * g["s"] / L)[:, None] * e[None, :]
    return np.einsum("jki,jk->ji", R, v)          # body frame: R^T v


def dna_rod(req: DnaRodRequest, log=None) -> dict:
    """Write REQ.output/steps.h5, material.h5, rest.h5, scene.toml and rest.json; returns
    rest.json's content. log(text), if given, hears the stages."""
    from mdbridge.rod.material.closed_rest import closed_rest_state, tension_torque_physical
    from mdbridge.rod.material.coarse import coarse_material
    from mdbridge.rod.material.gridfile import grid_scene, write_grid_material, write_initial_file
    from mdbridge.rod.material.parameter_sets import step_material
    from mdbridge.rod.material.stepfile import write_steps
    from mdbridge.rod.material.steps_to_rod import grid_material, rod_material
    from mdbridge.rod.scene import write_scene
    u = Units.paper()
    seq = req.sequence
    if req.points_per_bp < 1 or req.bp_per_point < 1:
        raise InputError(f"--points-per-bp {req.points_per_bp}, --bp-per-point {req.bp_per_point}: must be >= 1")
    if req.points_per_bp > 1 and req.bp_per_point > 1:
        raise InputError(f"--points-per-bp {req.points_per_bp} and --bp-per-point {req.bp_per_point}: give one")
    out = Path(req.output)
    out.mkdir(parents=True, exist_ok=True)
    sm = step_material(seq, req.params, closed=True, mass=req.mass)
    rm = rod_material(sm, units=u)
    rm, turns = coarse_material(rm, req.bp_per_point)
    N = req.points_per_bp * rm.n_bp
    g = grid_material(rm, N, req.interpolation, shape=req.shape)
    L = rm.length
    if req.ring:
        return _ring(req, sm, g, L, N, int(turns.sum()), rm.h_A, u, out, log)
    if req.box_A is not None:
        box = u.length_to_rod(req.box_A)
    elif req.params in ("paper", "olson1998"):
        box = L
    else:
        # a per-step file (e.g. `dnarod coarse-grain`'s) carries its own rise: the box is n_bp
        # of its mean rise, so that its rod closes without a hand-set --box-A (3.44 A against
        # the default 3.38 compresses a coarse-grained 21-bp rod until the shooting fails)
        box = u.length_to_rod(len(seq) * float(np.mean(sm.step_params[:, 2])))
    if log:
        log(f"dna-rod: {len(seq)} bp, {req.params}, N = {N}; closed rest state ...")
    rest = closed_rest_state(g, L, box_length=box, space=req.space, mode=req.rest)
    write_steps(out / "steps.h5", sm)
    write_grid_material(out / "material.h5", g, source=sm.source,
                        attrs={"sequence": seq, "interpolation": req.interpolation, "h_A": rm.h_A,
                               "bp_per_point": req.bp_per_point, "turns_dropped": int(turns.sum())})
    gamma = _kicked_gamma(rest, g, L, req.kick, u) if req.kick else None
    write_initial_file(out / "rest.h5", g["s"], rest.Gamma, rest.Omega, gamma=gamma)
    write_scene(out / "scene.toml", grid_scene(L, N, "material.h5", "rest.h5", space=req.space,
                                               t_end_ps=req.t_end_ps, units=u),
                comment=f"{len(seq)}-bp DNA, sequence {seq}\nparameters: {sm.source}\n"
                f"t = 0: the closed, pre-stressed rest state" + (f", kicked with A_v = {req.kick} A/ps"
                                                                    if req.kick else "")
                + "\nwritten by `dnarod dna-rod` (docs/scenes.md, 'Sequence-dependent DNA')")
    T_pN, M_pNnm = tension_torque_physical(rest, u)
    info = {"sequence": seq, "params": req.params, "source": sm.source, "n_bp": len(seq), "points": N,
            "bp_per_point": req.bp_per_point, "turns_dropped": int(turns.sum()),
            "length": L, "box_length": box, "h_A": rm.h_A, "interpolation": req.interpolation, "shape": req.shape,
            "space": req.space, "rest": req.rest, "tension": rest.tension, "torque": rest.torque, "tension_pN": T_pN,
            "torque_pN_nm": M_pNnm, "statics_residual": rest.statics_residual,
            "closure_rotation_rad": rest.closure_rotation_rad,
            "closure_length_error_A": u.length_to_A(rest.closure_length_error),
            "rest_iterations": rest.iterations, "elastic_energy": rest.energy,
            "elastic_energy_kT": rest.energy / u.kT_to_rod(sm.temperature_K),
            "axis0": rest.axis0.tolist(), "kick_A_per_ps": req.kick}
    write_json(out / "rest.json", info)
    return info


# The ring's scene (--ring): the overdamped rod in water at 300 K, 100-ps steps (docs/thermal.md,
# "The overdamped rod"), a frame per ns.
RING_TEMPERATURE_K = 300.0
RING_DT_PS = 100.0
RING_FRAME_PS = 1000.0


def ring_scene(L: float, N: int, t_end_ps: float, seed: int | None, contact_diameter_nm: float | None,
               units: Units, material_file="material.h5", initial_file="rest.h5") -> dict:
    """The scene of a closed DNA ring from its rest state (`dnarod dna-rod --ring`)."""
    frames = max(2, int(round(t_end_ps / RING_FRAME_PS)) + 1)
    sc = {"rod": {"length": float(L), "points": int(N)}, "material": {"material_file": str(material_file)},
          "initial": {"kind": "file", "path": str(initial_file)},
          "thermal": {"temperature_K": RING_TEMPERATURE_K, "seed": int(seed or 1),
                      "friction_translational": "water", "friction_rotational": "water"},
          "solver": {"time": "brownian", "dt": units.time_to_rod(RING_DT_PS)},
          "output": {"t_end": units.time_to_rod(t_end_ps), "frames": frames, "fields": ["internal", "energy"]}}
    if contact_diameter_nm is not None:
        sc["contact"] = {"diameter_nm": float(contact_diameter_nm)}
    return sc


def _ring(req: DnaRodRequest, sm, g, L: float, N: int, turns: int, h_A: float, u: Units, out: Path, log) -> dict:
    """--ring: material.h5, rest.h5 (ring_rest.py), scene.toml and rest.json of the closed ring."""
    from mdbridge.rod.material.gridfile import write_grid_material, write_initial_file
    from mdbridge.rod.material.ring_rest import ring_rest_state
    from mdbridge.rod.scene import write_scene
    seq = req.sequence
    write_grid_material(out / "material.h5", g, source=sm.source,
                        attrs={"sequence": seq, "interpolation": req.interpolation, "h_A": h_A,
                               "bp_per_point": req.bp_per_point, "turns_dropped": turns})
    scene = ring_scene(L, N, req.t_end_ps, req.seed, req.contact_diameter_nm, u)
    work = dict(scene, material={"material_file": str((out / "material.h5").resolve())})
    if log:
        log(f"dna-rod --ring: {len(seq)} bp, {req.params}, N = {N}; the closed ring's rest state ...")
    rest = ring_rest_state(g, L, work, log=log)
    write_initial_file(out / "rest.h5", g["s"], rest.Gamma, rest.Omega)
    write_scene(out / "scene.toml", scene,
                comment=f"{len(seq)}-bp DNA ring, {req.params} ({sm.source}), {req.bp_per_point} bp per point\n"
                f"t = 0: the closed ring's rest state (the energy minimum at Lk = {rest.Lk}), in water at "
                f"{RING_TEMPERATURE_K:g} K, overdamped\nwritten by `dnarod dna-rod --ring` (docs/dna-rod.md)")
    kT = u.kT_to_rod(RING_TEMPERATURE_K)
    info = {"sequence": seq, "params": req.params, "source": sm.source, "n_bp": len(seq), "points": N,
            "bp_per_point": req.bp_per_point, "turns_dropped": turns, "length": L, "interpolation": req.interpolation,
            "ring": True, "contact_diameter_nm": req.contact_diameter_nm,
            "Lk0": rest.Lk0, "Lk": rest.Lk, "Tw": rest.Tw, "Wr": rest.Wr, "Lk_DNA": rest.Lk + turns,
            "energy": rest.energy, "energy_kT": rest.energy / kT, "energy_start_kT": rest.energy_start / kT,
            "contact_energy_kT": rest.contact_energy / kT,
            "statics_residual": rest.residual, "statics_residual_start": rest.residual_start,
            "statics_residual_floor": rest.residual_floor,
            "closure_rotation_rad": rest.closure_rotation_rad,
            "closure_translation_A": u.length_to_A(rest.closure_translation),
            "rest_chunks": rest.chunks, "rest_steps": rest.steps, "rest_dt_last": rest.dt_last,
            "descent_energy_kT": rest.energy_descent / kT, "descent_statics_residual": rest.residual_descent,
            "least_energy_iterations": rest.polish_iterations,
            "rest_cpu_s": rest.cpu_s, "temperature_K": RING_TEMPERATURE_K}
    write_json(out / "rest.json", info)
    return info
