"""The rod's effective bend stiffness that reproduces a measured (MD) wave speed.

At the paper's amplitudes the rod's wave speed is far above the small-amplitude bend
speed of Eq (39) (0.34 A/ps for 158 bp): a closed, periodic rod cannot lengthen its
period, so a transverse displacement stretches it, and that tension adds a string-like
restoring force (speed^2 ~ c_bend^2 + C3 (k a)^2 / 4 in the paper's units). So the
modulus is fitted with the full nonlinear rod at the same amplitude, not with Eq (39):
the scene is run through mdbridge.rod.run.run_scene with D1 = D2 = f D1*, D3 = f D3* and the same
analysis (WaveAnalysis) measures the speed; f is found by Brent's method on log f.
`dispersion.bend_modulus_for_speed` gives the small-amplitude (Eq 39) answer for
comparison.
"""
from __future__ import annotations

import math

from scipy.optimize import brentq

from dna_models.units import Units, persistence_length_nm
from mdbridge.geometry.trajectory import BasePairTrajectory
from mdbridge.analysis.wave_analysis import WaveAnalysis


def _material(which: str, scale: float, u: Units) -> str:
    if which == "bend":      # D1 = D2 (bend) and D3 (twist) scaled together
        D = [d * scale for d in u.D_star]
        return f"material.D=[{D[0]!r}, {D[1]!r}, {D[2]!r}]"
    if which == "stretch":   # C3 (stretch) only
        C = list(u.C_star)
        C[2] *= scale
        return f"material.C=[{C[0]!r}, {C[1]!r}, {C[2]!r}]"
    raise ValueError(f"which must be 'bend' or 'stretch', got {which!r}")


def rod_speed(scene, n_bp: int, scale: float, which: str = "bend", units: Units | None = None) -> float:
    """Wave speed [A/ps] of the scene's rod with one modulus scaled by `scale`."""
    from mdbridge.rod.run import run_scene
    u = units or Units.paper()
    run = run_scene(scene, source=str(scene),
                    set=[_material(which, scale, u), 'output.fields=["internal", "centerline", "directors"]'])
    traj = BasePairTrajectory.from_rod(run, n_bp, u)
    # in_plane: the dna_planar scene kicks along lab Z (docs/scenes.md)
    return float(WaveAnalysis(traj, in_plane=[0.0, 0.0, 1.0], n_boot=0).run().results.wave["speed_A_per_ps"])


def fit_modulus(scene, n_bp: int, target_speed_A_per_ps: float, which: str = "bend",
                bracket=(0.05, 50.0), rtol: float = 1e-3, units: Units | None = None) -> dict:
    """Scale f of the paper's bend stiffness D or stretch modulus C3 (Sec 2.1) for which the
    rod's speed equals the target. Bend: D_eff = f D in J m and as a persistence length
    D_eff / kT (300 K); stretch: f C3 in pN."""
    u = units or Units.paper()
    evals = []
    cache = {}

    def g(logf):
        if logf not in cache:
            v = rod_speed(scene, n_bp, math.exp(logf), which, u)
            evals.append((math.exp(logf), v))
            cache[logf] = v
        return cache[logf] - target_speed_A_per_ps

    lo, hi = math.log(bracket[0]), math.log(bracket[1])
    try:
        glo, ghi = g(lo), g(hi)
    except FloatingPointError as e:  # the rod folded at an end of the bracket
        return {"scale": float("nan"), "which": which, "reason": f"rod run failed in the bracket: {e}",
                "evaluations": evals}
    if glo * ghi > 0:
        return {"scale": float("nan"), "which": which, "evaluations": evals,
                "reason": f"target {target_speed_A_per_ps:.3g} A/ps outside the rod's speeds "
                          f"{evals[0][1]:.3g}..{evals[1][1]:.3g} A/ps for {which} modulus x {bracket}"}
    logf = brentq(g, lo, hi, xtol=rtol, rtol=rtol)
    f = math.exp(logf)
    out = {"scale": f, "which": which, "target_speed_A_per_ps": target_speed_A_per_ps,
           "evaluations": [(float(a), float(b)) for a, b in evals],
           "method": "nonlinear rod (rodcore.run) at the scene's amplitude, Brent on log(scale)"}
    if which == "bend":
        out.update(D_J_m=f * u.D, paper_D_J_m=u.D,
                   persistence_length_nm_300K=persistence_length_nm(f * u.D, 300.0))
    else:
        out.update(stretch_modulus_pN=f * u.C_star[2] * u.C * 1e12,
                   paper_stretch_modulus_pN=u.C_star[2] * u.C * 1e12)
    return out
