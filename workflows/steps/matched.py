"""The matched rod-vs-MD comparison of `dnarod compare`: per run the standing-mode
fit with its three-part error (mdbridge/analysis/mode_error.py), amplitude, strain and
tension (mdbridge/analysis/matched.py); across runs the regime labels, the rod's frequency
at the MD's amplitude, the baseline tension and the buckling check. Keys: docs/analysis.md,
"Matched comparison".
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from dna_models.errors import InputError
from dna_models.units import AMU, Units


def scene_in_plane(scene: dict, scene_path=None):
    """The plane of the initial disturbance fixed by the scene: lab Z for `dna_planar` (its
    velocity and displacement are along Z); for a scene written by `prestrain_scene` the
    direction stored next to it (SCENE.json, key in_plane); else None (then the analysis
    estimates it from the first frames and says so)."""
    ini = scene.get("initial", {})
    if ini.get("kind") == "dna_planar":
        return [0.0, 0.0, 1.0]
    if scene_path is not None:
        side = Path(scene_path).with_suffix(".json")
        if side.is_file():
            v = json.loads(side.read_text()).get("in_plane")
            if v is not None:
                return [float(x) for x in v]
    return None


def plane_report(analysis, scene_vec) -> dict:
    """Where the e_in came from and the angle between the measured plane and the scene's."""
    from mdbridge.analysis.wave_analysis import initial_plane_direction
    r = analysis.results
    out = {"in_plane_source": "scene" if scene_vec is not None else "first 5 frames (scene gives none)",
           "e_in": r.e_in.tolist(),
           "plane_angle_to_scene_deg": r.planarity["plane_angle_deg"] if scene_vec is not None else None}
    u_perp = r.u_in[..., None] * r.e_in + r.u_out[..., None] * r.e_out
    guess = initial_plane_direction(u_perp, r.times_ps)
    cosang = abs(float(np.dot(guess, r.e_in)))
    out["first_frames_guess_angle_to_e_in_deg"] = float(np.degrees(np.arccos(min(cosang, 1.0))))
    return out


def mode_fit(analysis) -> dict:
    from mdbridge.analysis.mode_error import standing_mode_fit
    r = analysis.results
    if np.max(np.abs(r.mode_amplitude)) < 1e-9 * r.length_A or len(r.times_ps) < 8:
        return {"speed_A_per_ps": float("nan"), "speed_err_A_per_ps": float("nan"),
                "reason": "no displacement in the fundamental or fewer than 8 frames"}
    return standing_mode_fit(r.times_ps, r.mode_amplitude, r.k_per_A)


def rod_matched(traj, run, scene: dict, units: Units | None = None) -> dict:
    """Strain (sum of rises, as for MD) and tension n3 = C3 (Gamma3 - 1) of a rod run
    (`run`: a mdbridge.rod.run.RodRun or the path of its file)."""
    from mdbridge.analysis.matched import axial_strain, rod_tension_pN, tension_summary
    from mdbridge.rod.run import RodRun
    u = units or Units.paper()
    if not isinstance(run, RodRun):
        run = RodRun.read(run)
    run.require("fields/Gamma")
    rise = float(scene.get("initial", {}).get("rise_A", u.rise_A))
    st = axial_strain(traj, rise)
    G3 = np.asarray(run.fields["Gamma"])[:, :, 2]
    # the resolved material the run was made with (a full K wins: rodsim then still records
    # the default C), else the scene's; couplings of a full K to Gamma3 are left out
    K = run.attrs.get("material.K")
    C = run.attrs.get("material.C")
    mat = scene.get("material", {})
    if K is not None and np.size(K) == 36:
        C3 = float(np.asarray(K, float).reshape(6, 6)[2, 2])
    elif "K" in mat:
        C3 = float(np.asarray(mat["K"], float)[2, 2])
    else:
        C3 = float(C[2]) if C is not None else float(mat.get("C", u.C_star)[2])
    F = rod_tension_pN(G3.mean(axis=1), u) * (C3 / u.C_star[2])
    out = {k: v for k, v in st.items() if k != "series"}
    out.update(tension_summary(F))
    out["tension_source"] = "n3 = C3 (Gamma3 - 1), C = %.4g N, C3* = %.4g" % (u.C, C3)
    out["Gamma3_mean"] = float(G3.mean())
    out["tension_max_pN"] = float(F.max())  # the rod's instantaneous peak (MD's is not measurable)
    out["mass_per_length_kg_per_m"] = u.rho
    return out


def md_pressure_axis(md_dir: Path, axis: int, gmx: str = "gmx"):
    """Times [ps] and the pressure-tensor component along box axis `axis` [bar] from
    md.edr by `gmx energy` (MDAnalysis's EDR reader needs pyedr, not in Debian)."""
    from mdbridge.md.gromacs.energy import read_xvg
    from mdbridge.md.gromacs.gmx import run_gmx
    name = "Pres-" + "XYZ"[axis] * 2
    if not (md_dir / "md.edr").is_file():
        raise InputError(f"{md_dir / 'md.edr'}: missing; the tension needs the energy file of `dnarod run-md`")
    run_gmx(gmx, ["energy", "-f", "md.edr", "-o", "pressure_axis.xvg"], md_dir, stdin=f"{name}\n\n",
            log_name="gmx_energy_pressure.log")
    names, data = read_xvg(md_dir / "pressure_axis.xvg")
    if data.ndim != 2 or data.shape[1] < 2:
        raise InputError(f"{md_dir / 'pressure_axis.xvg'}: no {name} column")
    return data[:, 0], data[:, 1]


def md_matched(traj, universe, md_dir: Path, scene: dict, units: Units | None = None) -> dict:
    """Strain (sum of rises), tension from <P_axis> x cross-section, mass per length."""
    import shutil
    from mdbridge.analysis.matched import axial_strain, box_axis_and_area, tension_summary
    from mdbridge.md.gromacs.tension import md_tension_pN
    u = units or Units.paper()
    rise = float(scene.get("initial", {}).get("rise_A", u.rise_A))
    st = axial_strain(traj, rise)
    out = {k: v for k, v in st.items() if k != "series"}
    universe.trajectory[0]
    dims = universe.dimensions
    ax, area = box_axis_and_area(traj.period[0], dims[:3])
    out["box_axis"] = "XYZ"[ax]
    out["cross_section_A2"] = area
    out["mass_per_length_kg_per_m"] = float(universe.atoms.total_mass() * AMU
                                            / (np.linalg.norm(traj.period[0]) * 1e-10))
    gmx = shutil.which("gmx")
    try:
        if gmx is None:
            raise InputError("gmx not on PATH")
        if (Path(md_dir) / "build.json").is_file() and \
                json.loads((Path(md_dir) / "build.json").read_text()).get("solvent"):
            # the vacuum formula below would read the water's pressure as a tension
            raise InputError("a run in water: its tension is mdbridge/md/gromacs/tension.py tension_series's")
        t, P = md_pressure_axis(Path(md_dir), ax, gmx)
        out.update(tension_summary(md_tension_pN(P, area)))
        out["tension_source"] = (f"F = -<P_{'xyz'[ax] * 2}> x A (box cross-section {area:.4g} A^2), "
                                 "from md.edr by gmx energy; F > 0 = tension")
        out["pressure_axis_bar_mean"] = float(np.mean(P))
    except Exception as e:  # the wave analysis stands without it; say why
        out["tension_pN"] = float("nan")
        out["tension_reason"] = f"not measured: {e}"
    return out


def interp_rod_curve(rows, amplitude_A: float) -> dict:
    """The rod's frequency at an amplitude, by linear interpolation in log(amplitude) of the
    sweep's (mode amplitude, omega) points; outside the sweep's range: NaN with the reason."""
    pts = sorted((r["mode_amplitude_A"], r["omega_per_ps"], r.get("omega_err_per_ps", 0.0))
                 for r in rows if r and math.isfinite(r.get("omega_per_ps", float("nan")))
                 and r.get("mode_amplitude_A", 0) > 0)
    if not math.isfinite(amplitude_A) or len(pts) < 2:
        return {"omega_per_ps": float("nan"), "reason": "fewer than 2 rod sweep points with a frequency"}
    a = np.array([p[0] for p in pts])
    w = np.array([p[1] for p in pts])
    if not a[0] <= amplitude_A <= a[-1]:
        return {"omega_per_ps": float("nan"),
                "reason": f"MD amplitude {amplitude_A:.3g} A outside the rod sweep's "
                          f"{a[0]:.3g}-{a[-1]:.3g} A"}
    la = np.log(a)
    j = int(np.clip(np.searchsorted(a, amplitude_A) - 1, 0, len(a) - 2))
    f = (math.log(amplitude_A) - la[j]) / (la[j + 1] - la[j])
    wi = (1 - f) * w[j] + f * w[j + 1]
    # interpolation error: linear-in-amplitude vs linear-in-log(amplitude) between the points
    f_lin = (amplitude_A - a[j]) / (a[j + 1] - a[j])
    wl = (1 - f_lin) * w[j] + f_lin * w[j + 1]
    return {"omega_per_ps": float(wi), "omega_interp_err_per_ps": float(abs(wi - wl)),
            "bracket_amplitudes_A": [float(a[j]), float(a[j + 1])]}
