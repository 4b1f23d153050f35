"""Steps of `dnarod compare` (called from workflows/Snakefile, one process each).

    python -m dnarod.steps scene   BASE.toml OUT.toml --A-v 1 --run-ps 600 --every-ps 1
    python -m dnarod.steps rod     SCENE.toml ROD.h5 OUT_PREFIX [--n-boot 200]
    python -m dnarod.steps md      SCENE.toml MD_DIR OUT_PREFIX [--n-boot 200]
    python -m dnarod.steps modulus SCENE.toml OUT.json MD_ANALYSIS.json...
    python -m dnarod.steps prestrain-scene BASE.toml OUT.toml --A-v 1 --rest-length-A L0 \
        --run-ps 600 --every-ps 1

`rod` and `md` run the same `mdbridge.analysis.WaveAnalysis` and write OUT_PREFIX.json
(scalars) and OUT_PREFIX.npz (u(s, t), axis, planarity and integrity over time).
"""
from __future__ import annotations

import argparse
import json
import math
import sys
from pathlib import Path

import numpy as np

from dna_models.errors import DnarodError, InputError
from dna_models.units import Units
from mdbridge.jsonio import write_json
from mdbridge.rod.run import RodRun
from mdbridge.rod.scene import load_scene, scale_atol, scene_n_bp, set_output, write_scene


def make_scene(base_path, out_path, A_v: float, run_ps: float, every_ps: float) -> dict:
    """The base scene with initial.A_v_A_per_ps = A_v and output for the analysis."""
    sc = load_scene(base_path)
    ini = sc.setdefault("initial", {})
    if ini.get("kind") != "dna_planar":
        raise InputError(f"{base_path}: initial.kind = {ini.get('kind')!r}; the comparison needs "
                         "\"dna_planar\" (the paper's Sec 6 scene)")
    ini["A_v_A_per_ps"] = float(A_v)
    if 0 < abs(A_v) < 1:   # (and so the scene's energy-drift check holds as at 1 A/ps)
        scale_atol(sc, abs(A_v), str(base_path))
    set_output(sc, t_end=float(Units.paper().time_to_rod(run_ps)), frames=int(round(run_ps / every_ps)) + 1,
               fields=["internal", "centerline", "directors"])
    write_scene(out_path, sc, f"made by dnarod compare from {base_path}, A_v = {A_v} A/ps, {run_ps} ps")
    return sc


def _write(prefix, analysis, summary: dict, extra_arrays: dict):
    r = analysis.results
    p = r.planarity
    np.savez_compressed(f"{prefix}.npz", times_ps=r.times_ps, x_A=r.x_A, u_in=r.u_in, u_out=r.u_out,
                        axis=r.axis, in_rms_A=p["in_rms_A"], out_rms_A=p["out_rms_A"],
                        ratio=p["ratio"], angle_deg=p["angle_deg"], e_in=r.e_in, e_out=r.e_out,
                        e_axis=r.e_axis, **extra_arrays)
    write_json(f"{prefix}.json", summary)


def rod_dispersion(scene: dict) -> dict:
    """Small-amplitude prediction for the scene's fundamental (Eq 39 at kappa = 2 pi / L)."""
    from mdbridge.analysis.dispersion import lab_speed_A_per_ps
    u = Units.paper()
    ini = scene.get("initial", {})
    n_bp = scene_n_bp(scene, "the comparison's scene")
    L = n_bp * float(ini.get("rise_A", u.rise_A)) / u.ell_A
    D1 = float(scene.get("material", {}).get("D", u.D_star)[0])
    return {"fiducial_length": L, "D1": D1, "Gamma03": 1.0,
            "bend_branch_speed_A_per_ps": lab_speed_A_per_ps(L, D1, 1.0, "minus", 1, u),
            "shear_branch_speed_A_per_ps": lab_speed_A_per_ps(L, D1, 1.0, "plus", 1, u)}


def _report_mode_fit(s: dict):
    """The run's reported speed is the standing-mode fit's (offset fitted, three-part error,
    refused with the reason on too short a standing record: mdbridge/analysis/mode_error.py);
    the travelling-wave fit of WaveAnalysis stays under wave_fit."""
    sm = s["standing_mode"]
    s["wave_speed_A_per_ps"] = sm.get("speed_A_per_ps")
    s["wave_speed_err_A_per_ps"] = sm.get("speed_err_A_per_ps")
    s["wave_quantity"] = sm.get("quantity")
    if sm.get("reason"):
        s["wave_fit"] = dict(s["wave_fit"], reason=sm["reason"])


def analyse_rod(scene_path, h5_path, prefix, n_boot=200):
    from mdbridge.analysis import BasePairTrajectory, WaveAnalysis
    scene = load_scene(scene_path)
    from dnarod.steps import matched
    run = RodRun.read(h5_path)
    side = Path(scene_path).with_suffix(".json")  # a pre-strained rod's record (prestrain.py)
    meta = json.loads(side.read_text()) if side.is_file() else {}
    traj = BasePairTrajectory.from_rod(run, int(meta["n_bp"]) if "n_bp" in meta
                                       else scene_n_bp(scene, scene_path))
    e_in = matched.scene_in_plane(scene, scene_path)
    a = WaveAnalysis(traj, in_plane=e_in, offset=True, n_boot=n_boot).run()
    s = a.summary()
    s.update(kind="rod", A_v_A_per_ps=scene["initial"].get("A_v_A_per_ps", meta.get("A_v_A_per_ps")),
             A_A=scene["initial"].get("A_A", meta.get("A_A", 0.0)),
             dispersion=meta.get("dispersion") or rod_dispersion(scene),
             complete=run.complete, standing_mode=matched.mode_fit(a),
             plane=matched.plane_report(a, e_in),
             matched=matched.rod_matched(traj, run, scene if not meta else
                                         dict(scene, initial={"rise_A": meta["box_rise_A"]})))
    if meta:
        s["prestrain"] = meta
    _report_mode_fit(s)
    if not s["complete"]:
        log = Path(h5_path).with_name("rodsim.log")
        s["stopped"] = log.read_text().strip().splitlines()[0] if log.is_file() else "run incomplete"
    _write(prefix, a, s, {})
    return s


def analyse_md(scene_path, md_dir, prefix, n_boot=200):
    from mdbridge.analysis import WaveAnalysis
    from mdbridge.md.folder import open_md_folder
    from mdbridge.md.integrity import bp_intact_fraction
    md_dir = Path(md_dir)
    scene = load_scene(scene_path)
    folder = open_md_folder(md_dir)
    u = folder.universe
    n_bp = scene_n_bp(scene, scene_path)
    if folder.n_bp != n_bp:
        raise InputError(f"{md_dir}: the MD duplex has {folder.n_bp} base pairs, the scene {n_bp}")
    traj = folder.trajectory()
    from dnarod.steps import matched
    e_in = matched.scene_in_plane(scene, scene_path)
    a = WaveAnalysis(traj, in_plane=e_in, offset=True, n_boot=n_boot).run()
    t_int, intact, _ = bp_intact_fraction(u, traj.meta["pairs"])
    s = a.summary()
    s.update(standing_mode=matched.mode_fit(a), plane=matched.plane_report(a, e_in),
             matched=matched.md_matched(traj, u, md_dir, scene))
    _report_mode_fit(s)
    s.update(kind="md", A_v_A_per_ps=scene["initial"].get("A_v_A_per_ps"),
             bp_intact_fraction_final=float(intact[-1]), bp_intact_fraction_min=float(intact.min()),
             bp_intact_fraction_mean=float(intact.mean()))
    checks = md_dir / "checks.json"
    if checks.is_file():
        c = json.loads(checks.read_text())
        s["gromacs_checks"] = {k: c.get(k) for k in ("junction_ok", "energy", "side_image",
                                                     "protocol", "equilibration") if k in c}
        e = c.get("energy", {})
        # the one drift definition (mdbridge/md/gromacs/checks.py fit_drift), next to the speed
        s["energy_drift_kJ_mol_per_ns_per_atom"] = e.get("drift_kJ_mol_per_ns_per_atom")
        s["energy_drift_within_target"] = e.get("drift_within_target")
        s["protocol"] = c.get("protocol", "paper")
        if "side_image" in s["gromacs_checks"] and isinstance(s["gromacs_checks"]["side_image"], dict):
            s["gromacs_checks"]["side_image"].pop("per_frame_A", None)
        wc = c.get("watson_crick", {})
        if "final_fraction_intact" in wc:  # H5's independent count, same criterion
            s["bp_intact_fraction_final_checks"] = wc["final_fraction_intact"]
    build = md_dir / "build.json"
    if build.is_file():
        b = json.loads(build.read_text())
        vel = b.get("velocities")
        s["seed"] = b.get("seed", vel.get("seed") if isinstance(vel, dict) else None)
    _write(prefix, a, s, {"intact_times_ps": t_int, "intact_fraction": intact})
    return s


def fit_moduli(scene_path, md_jsons, out_json, which=("bend", "stretch")):
    """Rod modulus (bend D, stretch C3) that reproduces the mean MD wave speed of md_jsons."""
    from mdbridge.analysis.modulus import fit_modulus
    scene = load_scene(scene_path)
    speeds = [json.loads(Path(p).read_text()).get("wave_speed_A_per_ps") for p in md_jsons]
    speeds = [v for v in speeds if v is not None and math.isfinite(v)]
    res = {"md_wave_speed_A_per_ps": float(np.mean(speeds)) if speeds else None, "fits": {}}
    if speeds:
        for w in which:
            res["fits"][w] = fit_modulus(str(Path(scene_path).resolve()), scene_n_bp(scene, scene_path),
                                         float(np.mean(speeds)), which=w)
    Path(out_json).parent.mkdir(parents=True, exist_ok=True)
    write_json(out_json, res)
    return res


def run_step(label: str, step) -> int:
    """Run one workflow step (a callable) as a command: 0 when it succeeds, 2 with the
    error on stderr when it raises a DnarodError (bad input, a refused fit), so the
    Snakemake log names what failed and why; any other exception is a bug and propagates."""
    try:
        step()
    except DnarodError as e:
        print(f"dnarod compare ({label}): error: {e}", file=sys.stderr)
        return 2
    return 0


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m dnarod.steps", description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="step", required=True)
    for name in ("scene", "prestrain-scene"):
        p = sub.add_parser(name)
        p.add_argument("base")
        p.add_argument("out")
        p.add_argument("--A-v", type=float, required=True)
        p.add_argument("--run-ps", type=float, required=True)
        p.add_argument("--every-ps", type=float, required=True)
        if name == "prestrain-scene":
            p.add_argument("--rest-length-A", type=float, required=True,
                           help="the MD duplex's zero-tension length [A]")
    for name in ("rod", "md"):
        p = sub.add_parser(name)
        p.add_argument("scene")
        p.add_argument("input")
        p.add_argument("prefix")
        p.add_argument("--n-boot", type=int, default=200)
    p = sub.add_parser("modulus")
    p.add_argument("scene")
    p.add_argument("out")
    p.add_argument("md_json", nargs="+")
    a = ap.parse_args(argv)

    def step():
        if a.step == "scene":
            make_scene(a.base, a.out, a.A_v, a.run_ps, a.every_ps)
        elif a.step == "prestrain-scene":
            from dnarod.steps.prestrain import gamma03_from_rest_length, make_prestrain_scene
            sc = load_scene(a.base)
            ini = sc.get("initial", {})
            G = gamma03_from_rest_length(scene_n_bp(sc, a.base), float(ini.get("rise_A", Units.paper().rise_A)),
                                         a.rest_length_A)
            make_prestrain_scene(a.base, a.out, G, a.A_v, a.run_ps, a.every_ps)
        elif a.step == "modulus":
            fit_moduli(a.scene, a.md_json, a.out)
        elif a.step == "rod":
            analyse_rod(a.scene, a.input, a.prefix, a.n_boot)
        else:
            analyse_md(a.scene, a.input, a.prefix, a.n_boot)
    return run_step(a.step, step)


if __name__ == "__main__":
    sys.exit(main())
