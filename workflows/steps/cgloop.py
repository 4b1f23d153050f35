"""The coarse-graining loop of `dnarod compare`: the rod predicts the MD.

    python -m dnarod.steps.cgloop coarse-grain MD_DIR OUT_DIR [--m M] [--temperature K]
        [--min-effective N] [--max-open-fraction F] [--discard N] [--m-max M]
    python -m dnarod.steps.cgloop rod SCENE.toml CG_DIR MD_DIR OUT_DIR --rodsim RODSIM [--m M]
        [--replicas R] [--n-boot B] [--sequence-dependent]   (no --m: the rod's K(q -> 0))

`coarse-grain` runs `dnarod coarse-grain` on the unkicked equilibrium MD (A_v = 0) of one
seed and writes OUT_DIR/cg.json: ok, or the estimator's refusal (e.g. too few frames for
its minimum) as the reason, so the comparison still reports everything else.

`rod` builds the uniform coarse-grained rod (mdbridge.coarsegrain.cgrod: the long-wavelength
stiffness K(q -> 0) at the mean step through mdbridge.rod.material.steps_to_rod; with --m the
m-step compliance average instead), runs it with
the headline scene (same kick, length, output and in-plane direction as the paper-constant
rod: only [material] differs), fits its standing mode with the same WaveAnalysis, and
does the same for R bootstrap-replicate materials: the predicted speed's error is their
spread (half the central 68 % interval), combined with the central run's own fit error.
It also writes Eq 39 with the coarse-grained material (error over all replicates). With
--sequence-dependent, the per-step material (`dnarod dna-rod --params CG_DIR/steps.h5`,
closed pre-stressed rest state) runs once more, without an error estimate. Writes
OUT_DIR/analysis.json (+ .npz of the central run); keys: docs/coarse-graining.md.
"""
from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np

from dna_models.errors import DnarodError, InputError
from mdbridge.jsonio import write_json
from mdbridge.rod.scene import write_scene

from dnarod.steps.analyse import run_step


def coarse_grain_md(md_dir, out_dir, m=None, temperature=None, min_effective=None, max_open_fraction=0.05,
                    discard=None, m_max=None) -> dict:
    """The coarse-graining (mdbridge.coarsegrain.pipeline) of MD_DIR/md.tpr + MD_DIR/md.xtc into
    OUT_DIR, as `dnarod coarse-grain`, with T from md.edr unless given; OUT_DIR/cg.json records
    success or the refusal, and the equivalent command."""
    from mdbridge.coarsegrain.pipeline import CoarseGrainRequest, coarse_grain
    from dnarod.progress import Stages
    md, out = Path(md_dir), Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    # The pairs as built (mdbridge/md/builder/duplex.py), not found by distance: in a long
    # vacuum run some pairs are open in the frame the search would look at.
    from mdbridge.md.builder.duplex import base_pairs
    if not (md / "build.json").is_file():
        raise InputError(f"{md / 'build.json'}: missing; coarse-graining needs a `dnarod build-md` folder")
    n_bp = int(json.loads((md / "build.json").read_text())["n_bp"])
    pairs_file = out / "pairs.dat"
    pairs_file.write_text("".join(f"{a} {b}\n" for a, b in base_pairs(n_bp)))
    edr = str(md / "md.edr") if temperature is None and (md / "md.edr").is_file() else None
    req = CoarseGrainRequest(
        structure=str(md / "md.tpr"), trajectories=[str(md / "md.xtc")], output=str(out),
        pairs_file=str(pairs_file), max_open_fraction=float(max_open_fraction),
        temperature=None if temperature is None else float(temperature), edr=edr,
        length=None if m is None else int(m), min_effective=None if min_effective is None else float(min_effective),
        discard=None if discard is None else int(discard), m_max=None if m_max is None else int(m_max))
    rec: dict = {"md_dir": str(md), "command": _command_line(req)}
    try:
        with Stages("coarse-grain") as stages:
            coarse_grain(req, progress=stages)
        rec.update(ok=True, reason=None)
    except DnarodError as e:
        rec.update(ok=False, reason=str(e))
        print(f"coarse-graining refused: {e}", file=sys.stderr)
    write_json(out / "cg.json", rec)
    return rec


def _command_line(req) -> str:
    """The `dnarod coarse-grain` command that does what REQ does (for cg.json)."""
    words = ["dnarod", "coarse-grain", req.structure, *req.trajectories, "-o", req.output,
             "--pairs", req.pairs_file, "--max-open-fraction", repr(req.max_open_fraction)]
    for option, value in (("--temperature", req.temperature), ("--edr", req.edr), ("-m", req.length),
                          ("--min-effective", req.min_effective), ("--discard", req.discard),
                          ("--m-max", req.m_max)):
        if value is not None:
            words += [option, repr(value) if isinstance(value, float) else str(value)]
    return " ".join(words)


def _material_scene(scene: dict, mat: dict) -> dict:
    """The headline scene with the coarse-grained material in place of the paper's."""
    sc = json.loads(json.dumps(scene))
    sc["material"] = {"K": np.asarray(mat["K_star"]).tolist(), "I": np.asarray(mat["I_star"]).tolist(),
                      "rho": float(mat["rho_star"])}
    return sc


def _run_rodsim(rodsim, scene_path: Path, h5: Path):
    """rodsim run; exit 3 (a numerical stop, frames kept) is analysed like the workflow's rod runs."""
    p = subprocess.run([str(rodsim), "run", str(scene_path), "-o", str(h5)], capture_output=True, text=True)
    (h5.parent / "rodsim.log").write_text(p.stdout + p.stderr)
    if p.returncode not in (0, 3):
        raise InputError(f"{scene_path}: rodsim failed (exit {p.returncode}): {(p.stderr or p.stdout).strip()[:400]}")


def _mode_speed(scene_path: Path, h5: Path, scene: dict) -> dict:
    """The standing-mode fit of one replicate run (no files kept)."""
    from mdbridge.analysis import BasePairTrajectory, WaveAnalysis
    from mdbridge.rod.run import RodRun
    from mdbridge.rod.scene import scene_n_bp
    from dnarod.steps import matched
    run = RodRun.read(h5)
    traj = BasePairTrajectory.from_rod(run, scene_n_bp(scene, scene_path))
    a = WaveAnalysis(traj, in_plane=matched.scene_in_plane(scene, scene_path), offset=True, n_boot=10).run()
    f = matched.mode_fit(a)
    return {"speed_A_per_ps": float(f.get("speed_A_per_ps", float("nan"))), "complete": bool(run.complete),
            "planarity": float(a.results.planarity["planarity"]), "reason": f.get("reason")}


def refused(out_dir: Path, reason: str, extra: dict | None = None) -> dict:
    s = {"kind": "cg_rod", "speed_A_per_ps": float("nan"), "speed_err_A_per_ps": float("nan"),
         "reason": reason, "dispersion": None, "planarity": float("nan")}
    s.update(extra or {})
    write_json(out_dir / "analysis.json", s)
    return s


def cg_rod(scene_path, cg_dir, md_dir, out_dir, rodsim, m=None, n_replicas=20, n_boot=200,
           sequence_dependent=False) -> dict:
    from mdbridge.stats import spread
    from mdbridge.coarsegrain.cgrod import as_json, eq39_prediction, materials, read_replicas
    from mdbridge.rod.scene import load_scene
    from dnarod.steps.analyse import analyse_rod, rod_dispersion
    scene_path, cg_dir, out = Path(scene_path), Path(cg_dir), Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    rec = json.loads((cg_dir / "cg.json").read_text())
    if not rec.get("ok"):
        return refused(out, f"coarse-graining refused: {rec.get('reason')}", {"cg": rec})
    params = json.loads((cg_dir / "params.json").read_text())
    scene = load_scene(scene_path)
    reps = read_replicas(cg_dir / "replicas.h5")
    try:
        central, boot = materials(reps, m, n_replicas)
    except InputError as e:
        return refused(out, str(e), {"cg": rec})
    disp = rod_dispersion(scene)
    eq39 = eq39_prediction(reps, m, disp["fiducial_length"], 1.0)
    A_v = scene["initial"].get("A_v_A_per_ps")
    sc = out / "central" / "scene.toml"
    what = "K(q -> 0)" if m is None else f"m = {m}"
    write_scene(sc, _material_scene(scene, central),
                f"dnarod compare: the uniform coarse-grained rod ({what}) of {cg_dir}, kicked like {scene_path}")
    _run_rodsim(rodsim, sc, out / "central" / "rod.h5")
    c = analyse_rod(sc, out / "central" / "rod.h5", out / "analysis_central", n_boot)
    reps_out = _replicate_runs(boot, scene, cg_dir, out, rodsim)
    v = np.array([r["speed_A_per_ps"] for r in reps_out], float)
    ok = np.isfinite(v)
    err_cg = float(spread(v[ok])) if ok.sum() > 1 else float("nan")
    err_fit = float(c.get("wave_speed_err_A_per_ps") or float("nan"))
    speed = c.get("wave_speed_A_per_ps")
    # the material's systematic parts (order-2 extrapolation, opening rule), carried over from
    # Eq 39 as relative errors: the rod runs are linear in them at the kicks compared
    parts = eq39["speed_err_parts_A_per_ps"]
    rel_sys = math.hypot(parts.get("extrapolation", 0.0), parts.get("rule", 0.0)) / eq39["speed_A_per_ps"]
    err_sys = rel_sys * float(speed) if speed is not None and math.isfinite(float(speed)) else float("nan")
    err_stat = math.hypot(err_cg, err_fit) if math.isfinite(err_fit) else err_cg
    s = {"kind": "cg_rod", "A_v_A_per_ps": A_v, "m": m, "seed_md_dir": str(md_dir),
         "material_definition": ("K(q -> 0), the long-wavelength stiffness of the step parameters" if m is None
                                 else f"the {m}-step compliance average as per-step equivalent"),
         "speed_A_per_ps": speed,
         "speed_err_A_per_ps": math.hypot(err_stat, err_sys) if math.isfinite(err_sys) else err_stat,
         "speed_err_cg_A_per_ps": err_cg, "speed_err_fit_A_per_ps": err_fit,
         "speed_err_systematic_A_per_ps": err_sys,
         "quantity": c.get("wave_quantity"), "reason": (c.get("standing_mode") or {}).get("reason"),
         "error_method": f"spread (half the central 68 % interval) of the standing-mode speed over "
                         f"{int(ok.sum())} rod runs with bootstrap-replicate materials of the "
                         "coarse-graining (same frames resampled for every step), combined in quadrature "
                         "with the central run's fit error and the material's systematic parts (Eq 39's "
                         "relative shift under the order-2 extrapolation and the opening rule)",
         "replicates": reps_out, "replicates_used": int(ok.sum()),
         "planarity": c.get("planarity"), "mode_amplitude_A": (c.get("standing_mode") or {}).get("mode_amplitude_A"),
         "complete": c.get("complete"), "dispersion": eq39, "paper_dispersion": disp,
         "material": as_json(central),
         "shape_in_run": "the box's (the headline scene's straight twisted rod, Gamma0 = (0, 0, 1), "
                         "Omega0 = (0, 0, 2 pi turns / L)); the coarse-grained mean shape is material."
                         "Gamma0_star / Omega0_star, not imposed",
         "cg": _cg_summary(cg_dir, params)}
    if sequence_dependent:
        s["sequence_dependent"] = _sequence_dependent(cg_dir, md_dir, out, rodsim, scene, n_boot)
    write_json(out / "analysis.json", s)
    return s


def _replicate_runs(boot, scene, cg_dir, out, rodsim) -> list:
    """The standing-mode speed of the rod of each bootstrap-replicate material (a replicate
    whose stiffness is not positive definite is recorded with its reason)."""
    from mdbridge.rod.scene import load_scene
    reps_out = []
    for i, b in enumerate(boot):
        if b is None:
            reps_out.append({"replicate": i, "speed_A_per_ps": float("nan"),
                             "reason": "replicate stiffness not positive definite"})
            continue
        d = out / f"replicate{i:03d}"
        sp = d / "scene.toml"
        write_scene(sp, _material_scene(scene, b), f"bootstrap replicate {i} of {cg_dir}")
        _run_rodsim(rodsim, sp, d / "rod.h5")
        r = _mode_speed(sp, d / "rod.h5", load_scene(sp))
        r["replicate"] = i
        reps_out.append(r)
        (d / "rod.h5").unlink()          # the number is kept; 20 full records are not needed
    return reps_out


def _cg_summary(cg_dir: Path, params: dict) -> dict:
    """The coarse-graining's numbers analysis.json repeats (from CG_DIR/params.json)."""
    return {"params": str(cg_dir / "params.json"), "temperature_K": params.get("temperature_K"),
            "temperature_source": params.get("temperature_source"),
            "frames_used": params.get("frames_used"), "effective_samples": params.get("effective_samples"),
            "excluded_steps": params.get("excluded", {}).get("steps"), "caveats": params.get("caveats"),
            "opening_rule_steps": params.get("opening_rule", {}).get("steps"),
            "rod_constants": params.get("rod", {}).get("constants"),
            "physical_m": params.get("physical_m"),
            "physical": {k: params.get("physical", {}).get(k) for k in (
                "bend_persistence_length", "stretch_modulus", "torsional_modulus", "twist_stretch_coupling")},
            "rho": params.get("mass_inertia", {}).get("rho")}


def _sequence_dependent(cg_dir, md_dir, out, rodsim, scene, n_boot) -> dict:
    """The per-step coarse-grained rod (closed pre-stressed rest state, as `dnarod dna-rod`
    makes it: mdbridge.rod.material.dna_rod), kicked like the headline scene; one run, no
    error estimate (each replicate would need its own closed rest state)."""
    from dna_models.units import Units
    from mdbridge.md.folder import md_sequence
    from mdbridge.rod.material.dna_rod import DnaRodRequest, dna_rod
    from dnarod.steps.analyse import analyse_rod, rod_dispersion
    u = Units.paper()
    ini, o = scene["initial"], scene["output"]
    t_ps = u.time_to_ps(float(o["t_end"]))
    d = out / "sequence_dependent"
    steps = cg_dir / "steps.h5"
    if not steps.is_file():
        return {"speed_A_per_ps": float("nan"), "reason": f"{steps} missing"}
    try:
        info = dna_rod(DnaRodRequest(sequence=md_sequence(md_dir, "--sequence-from-md"), output=str(d),
                                     params=str(steps), kick=float(ini.get("A_v_A_per_ps", 0.0)), t_end_ps=t_ps),
                       log=lambda text: print(text, file=sys.stderr))
        a = np.asarray(info["axis0"], float)
        e = np.array([1.0, 0.0, 0.0]) - a[0] * a           # dna-rod's kick direction
        meta = {"in_plane": (e / np.linalg.norm(e)).tolist(), "n_bp": info["n_bp"],
                "A_v_A_per_ps": ini.get("A_v_A_per_ps"), "A_A": 0.0,
                "box_rise_A": u.length_to_A(info["box_length"]) / info["n_bp"],
                "dispersion": rod_dispersion(scene)}
        write_json(d / "scene.json", meta)
        _run_rodsim(rodsim, d / "scene.toml", d / "rod.h5")
        r = analyse_rod(d / "scene.toml", d / "rod.h5", d / "analysis", n_boot)
    except DnarodError as e:
        return {"speed_A_per_ps": float("nan"), "reason": str(e)}
    return {"speed_A_per_ps": r.get("wave_speed_A_per_ps"), "speed_fit_err_A_per_ps": r.get("wave_speed_err_A_per_ps"),
            "speed_err_A_per_ps": None, "reason": (r.get("standing_mode") or {}).get("reason"),
            "planarity": r.get("planarity"), "rest_tension_pN": info.get("tension_pN"),
            "rest_torque_pN_nm": info.get("torque_pN_nm"),
            "note": "per-step material from steps.h5 (excluded steps carry the average); no error estimate"}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m dnarod.steps.cgloop", description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="step", required=True)
    p = sub.add_parser("coarse-grain")
    p.add_argument("md_dir")
    p.add_argument("out_dir")
    p.add_argument("--m", type=int, default=None)
    p.add_argument("--temperature", type=float, default=None)
    p.add_argument("--min-effective", type=float, default=None)
    p.add_argument("--max-open-fraction", type=float, default=0.05)
    p.add_argument("--discard", type=int, default=None)
    p.add_argument("--m-max", type=int, default=None)
    p = sub.add_parser("rod")
    p.add_argument("scene")
    p.add_argument("cg_dir")
    p.add_argument("md_dir")
    p.add_argument("out_dir")
    p.add_argument("--rodsim", required=True)
    p.add_argument("--m", type=int, default=None)
    p.add_argument("--replicas", type=int, default=20)
    p.add_argument("--n-boot", type=int, default=200)
    p.add_argument("--sequence-dependent", action="store_true")
    a = ap.parse_args(argv)

    def step():
        if a.step == "coarse-grain":
            coarse_grain_md(a.md_dir, a.out_dir, a.m, a.temperature, a.min_effective, a.max_open_fraction, a.discard,
                            a.m_max)
        else:
            cg_rod(a.scene, a.cg_dir, a.md_dir, a.out_dir, a.rodsim, a.m, a.replicas, a.n_boot,
                   a.sequence_dependent)
    return run_step(f"cg {a.step}", step)


if __name__ == "__main__":
    sys.exit(main())
