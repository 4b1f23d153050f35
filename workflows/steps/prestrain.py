"""A rod held in the MD's box at the MD's own rest length.

The MD box fixes the lab length of the duplex at n x rise (the scene's rise, 3.38 A). If
the duplex's zero-tension length L0 (from the MD's axis-only pressure-coupled
equilibration) differs, the MD in the box is pre-strained by Gamma03 = n rise / L0. The
rod gets the same state: fiducial length L0 / l (so its rest length is the MD's), intrinsic
Gamma0 = [0, 0, 1], and a straight initial state stretched to Gamma3 = Gamma03, i.e. lab
length n rise, the box's; its axial force is n3 = C3 (Gamma03 - 1). The `dna_planar` kind
cannot express this (it fixes Gamma3 = Gamma0 = 1), so the initial state is written as an
initial-condition file (`kind = "file"`, docs/scenes.md) with the same velocity and shape
fields as `dna_planar` (rodcore/src/initial_conditions.cpp) at the new length. The file
kind's anchor is the identity frame (d1 = X, d2 = Y, d3 = Z at s = 0), so the helix runs
along lab Z and the kick is along lab X: written to SCENE.json as in_plane.

The mass per length enters as an exact rescaling of time (rho and I scale together for the
same cross-section): omega(rho_MD) = omega(rho_rod) sqrt(rho_rod / rho_MD), reported by the
comparison, not run.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from dna_models.errors import InputError
from dna_models.units import Units
from mdbridge.jsonio import write_json


def gamma03_from_rest_length(n_bp: int, rise_box_A: float, rest_length_A: float) -> float:
    if not rest_length_A > 0:
        raise InputError(f"MD zero-tension length must be > 0 A, got {rest_length_A!r}")
    return n_bp * rise_box_A / rest_length_A


def prestrain_prediction(n_bp, rise_box_A, Gamma03, turns, D1, C3, units: Units | None = None) -> dict:
    """Small-amplitude bend-branch frequency and lab speed of the fundamental of the
    pre-strained rod (dispersion.omega_pm_tension), and the axial force."""
    from mdbridge.analysis.dispersion import omega_pm_tension
    u = units or Units.paper()
    L_fid = n_bp * rise_box_A / (u.ell_A * Gamma03)
    kappa = 2 * math.pi / L_fid
    n3 = C3 * (Gamma03 - 1.0)
    w = float(omega_pm_tension(kappa, D1, Gamma03, n3, "minus"))
    return {"Gamma03": Gamma03, "n3": n3, "tension_pN": n3 * u.C * 1e12,
            "fiducial_length": L_fid, "Gamma03_used_in_dispersion": Gamma03,
            "omega_per_ps": u.angular_velocity_to_rad_per_ps(w),
            "bend_branch_speed_A_per_ps": u.velocity_to_A_per_ps(Gamma03 * w / kappa),
            "D1": D1, "C3": C3, "note": "Eq 39 with the axial force (mdbridge/analysis/dispersion.py)"}


def make_prestrain_scene(base_path, out_path, Gamma03: float, A_v: float, run_ps: float,
                         every_ps: float, units: Units | None = None) -> dict:
    """Write OUT.toml (kind = "file"), OUT.ic.h5 and OUT.json (in_plane, the prediction)."""
    from mdbridge.rod.material.gridfile import write_initial_file
    from mdbridge.rod.scene import load_scene, scale_atol, scene_bp_turns, set_output, write_scene
    u = units or Units.paper()
    sc = load_scene(base_path)
    ini = sc.get("initial", {})
    if ini.get("kind") != "dna_planar":
        raise InputError(f"{base_path}: initial.kind = {ini.get('kind')!r}; the pre-strained rod is "
                         "built from a \"dna_planar\" scene")
    if not (0.5 < Gamma03 < 2.0):
        raise InputError(f"Gamma03 = {Gamma03!r} (box / MD rest length) outside (0.5, 2)")
    n, turns = scene_bp_turns(sc, base_path)
    rise = float(ini.get("rise_A", u.rise_A))
    A = float(ini.get("A_A", 0.0)) / u.ell_A
    Av = float(A_v) / u.velocity_A_per_ps
    L = n * rise / (u.ell_A * Gamma03)
    O3 = 2 * math.pi * turns / L
    q = 2 * math.pi / L
    s = np.arange(n) * L / n
    c, sn = np.cos(O3 * s), np.sin(O3 * s)
    drz = -A * q * np.sin(q * s)
    vz = Av * np.sin(q * s)
    z = np.zeros(n)
    fields = {"gamma": np.stack([c * vz, -sn * vz, z], 1), "omega": np.zeros((n, 3)),
              "Gamma": np.stack([c * drz, -sn * drz, np.full(n, Gamma03)], 1),
              "Omega": np.stack([z, z, np.full(n, O3)], 1)}
    out = Path(out_path)
    out.parent.mkdir(parents=True, exist_ok=True)
    ic = out.with_suffix(".ic.h5")
    write_initial_file(ic, s, fields["Gamma"], fields["Omega"], gamma=fields["gamma"], omega=fields["omega"])
    mat = sc.get("material", {})
    D1 = float(mat.get("D", u.D_star)[0])
    C3 = float(mat.get("C", u.C_star)[2])
    new = {k: v for k, v in sc.items() if k not in ("initial", "rod", "output")}
    new["initial"] = {"kind": "file", "path": str(ic.resolve())}
    new["rod"] = {"length": L, "points": n, "Gamma0": [0.0, 0.0, 1.0], "Omega0": [0.0, 0.0, O3]}
    if 0 < abs(A_v) < 1:   # as dnarod.steps.analyse.make_scene
        scale_atol(new, abs(A_v), str(base_path))
    set_output(new, t_end=float(u.time_to_rod(run_ps)), frames=int(round(run_ps / every_ps)) + 1,
               fields=["internal", "centerline", "directors"])
    write_scene(out, new, f"made by dnarod compare from {base_path}: pre-strained rod, Gamma03 = "
                          f"{Gamma03!r} (box / MD rest length), A_v = {A_v} A/ps, {run_ps} ps")
    pred = prestrain_prediction(n, rise, Gamma03, turns, D1, C3, u)
    meta = {"in_plane": [1.0, 0.0, 0.0], "n_bp": n, "A_v_A_per_ps": float(A_v), "A_A": float(ini.get("A_A", 0.0)),
            "Gamma03": Gamma03, "box_rise_A": rise, "rest_length_A": n * rise / Gamma03,
            "dispersion": {"fiducial_length": L, "D1": D1, "Gamma03": Gamma03,
                           "bend_branch_speed_A_per_ps": pred["bend_branch_speed_A_per_ps"],
                           "with_tension": pred}}
    write_json(out.with_suffix(".json"), meta)
    return meta
