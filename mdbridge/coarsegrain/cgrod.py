"""The uniform coarse-grained rod: the sequence-averaged material of a coarse-graining,
mapped onto the rod by mdbridge.rod.material.steps_to_rod, with its bootstrap replicas and
its small-amplitude (Eq 39) prediction (docs/coarse-graining.md, "The loop").

Material. The sequence-averaged mean step p (6) and per-step stiffness F (6 x 6, kT units)
are those of every step of a uniform rod, and the exact map of steps_to_rod at h (the
paper's rise, dna_models.units) gives its shape strains_from_steps(p, h) (Gamma0*,
Omega0*) and stiffness rod_stiffness(F, p, T, h) (K*). rho* and I* are the mean base
pair's mass and inertia over h (steps_to_rod's convention: the full inertia tensor about
the base-pair origin).

Coarse-graining length m > 1. The m-step segments' stiffness F_m enters as the per-step
equivalent F = m F_m: for independent steps the m-step covariance is m times the
per-step one (to first order; the twist between steps only turns the bends, and the
sum of isotropic bends does not care), so m F_m = F_1 there, and on correlated steps
m F_m is the longer segments' stiffness (nearest-neighbour correlations included). It
is not mapped as one constant-strain piece of length m h: an m-step segment of a chain
is not one (its bends sit in body frames turned by the twist), and that map makes the
bend stiffness low by about sinc^2 of half the segment's twist (-22 % at m = 3; the
speed of tests/python/test_coarsegrain_loop.py's rod came out 10 % low). Caveat: the
m-step shift and slide also carry the bends' lever arms, so the shear block of m F_m is
soft for m > 1 (-15 % at m = 3 on the test's ensemble; felt by a 42-bp ring's bend
branch at the % level, negligible at 158 bp where D k^2 << C1).

Errors. The coarse-graining's moving-block bootstrap replicates (same frames for every
step) of p_m and F_m are written next to params.json (`write_replicas`, DIR/replicas.h5);
each replicate gives a material, and the spread of any prediction over those materials is
its error from the coarse-grained parameters. rho is exact (masses) and I is averaged over
50 frames, so both are held at their central values.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from dna_models.errors import InputError
from dna_models.units import Units

from mdbridge.stats import spread

REPLICAS_FORMAT = "dnarod-cg-replicas/1"


def write_replicas(path, cg, extras: dict | None = None) -> Path:
    """DIR/replicas.h5: per m the sequence-averaged mean and stiffness and their bootstrap
    replicates; the base pairs' masses and inertia; temperature and bootstrap settings."""
    import h5py
    r = cg.results
    p = Path(path)
    with h5py.File(p, "w") as f:
        f.attrs["format"] = REPLICAS_FORMAT
        f.attrs["temperature_K"] = r["temperature_K"]
        f.attrs["block_length_frames"] = r["block_length"]
        f.attrs["sequence"] = cg.ens.sequence
        f.attrs["closed"] = bool(cg.ens.closed)
        f.attrs["source"] = cg.ens.source
        f.attrs["units"] = "mean: A, deg; stiffness: kT/A^2, kT/(A deg), kT/deg^2 (shift slide rise tilt roll twist)"
        for m, b in r["by_m"].items():
            g = f.create_group(f"m{m}")
            g["mean"] = b["mean_avg"]
            g["stiffness"] = b["K_avg"]
            g["mean_boot"] = b["mean_avg_boot"]
            g["stiffness_boot"] = b["K_avg_boot"]
        if extras and "mass_inertia" in extras:
            f["mass_amu"] = np.asarray(extras["mass_inertia"]["mass"], float)
            f["inertia_amu_A2"] = np.asarray(extras["mass_inertia"]["inertia"], float)
    return p


def read_replicas(path) -> dict:
    """The contents of a replicas file as numpy arrays; {m: {...}} under "by_m"."""
    import h5py
    p = Path(path)
    if not p.is_file():
        raise InputError(f"{p}: missing (written by `dnarod coarse-grain`)")
    with h5py.File(p, "r") as f:
        if f.attrs.get("format") != REPLICAS_FORMAT:
            raise InputError(f"{p}: attribute 'format' is {f.attrs.get('format')!r}, expected {REPLICAS_FORMAT!r}")
        out = {k: (v.decode() if isinstance(v, bytes) else v) for k, v in f.attrs.items()}
        out["by_m"] = {int(k[1:]): {n: np.asarray(g[n]) for n in g} for k, g in f.items() if k.startswith("m")
                       and isinstance(g, h5py.Group)}
        for n in ("mass_amu", "inertia_amu_A2"):
            if n not in f:
                raise InputError(f"{p}: dataset '{n}' missing (the coarse-graining had no atoms)")
            out[n] = np.asarray(f[n])
    return out


def uniform_material(mean, F, temperature_K: float, mass_amu: float, inertia_amu_A2, m: int = 1,
                     units: Units | None = None) -> dict:
    """K* (6, 6), I* (3, 3), rho*, Gamma0*, Omega0* of the uniform rod whose every step has
    the mean step parameters `mean` (A, deg) and the per-step stiffness F (kT units), by the
    exact map of mdbridge.rod.material.steps_to_rod at h = the paper's rise. For m > 1, F is
    the per-step equivalent m F_m of the m-step stiffness F_m (`materials`)."""
    from mdbridge.rod.material.steps_to_rod import rod_stiffness, strains_from_steps
    u = units or Units.paper()
    mean = np.asarray(mean, float)
    G0, O0 = strains_from_steps(mean, u.rise_A, u)
    K = rod_stiffness(F, mean, temperature_K, u.rise_A, u)
    ev = np.linalg.eigvalsh(K)
    if ev[0] <= 0:
        raise InputError(f"coarse-grained rod stiffness at m = {m} is not positive definite "
                         f"(smallest eigenvalue {ev[0]:.3g})")
    rho = float(u.mass_amu_per_length_A_to_rod(float(mass_amu), u.rise_A))
    I = np.asarray(u.inertia_amu_A2_per_length_A_to_rod(np.asarray(inertia_amu_A2, float), u.rise_A))
    return {"m": int(m), "h_A": u.rise_A, "K_star": K, "I_star": 0.5 * (I + I.T), "rho_star": rho,
            "Gamma0_star": np.asarray(G0), "Omega0_star": np.asarray(O0)}


def isotropic_view(mat: dict) -> dict:
    """The transverse constants of a material as an isotropic rod sees them: shear, bend
    and inertia averaged over the two transverse directions (the helical twist turns
    the body axes many times over a long wave, so a lab-frame bend samples both)."""
    K, I = np.asarray(mat["K_star"]), np.asarray(mat["I_star"])
    return {"C1": 0.5 * (K[0, 0] + K[1, 1]), "D1": 0.5 * (K[3, 3] + K[4, 4]),
            "I1": 0.5 * (I[0, 0] + I[1, 1]), "rho": float(mat["rho_star"])}


def eq39_speed(mat: dict, length_fiducial: float, Gamma03: float = 1.0, units: Units | None = None) -> float:
    """Small-amplitude bend-branch lab speed [A/ps] of the fundamental (Eq 39) of a material,
    through its isotropic view (couplings left out: the rod runs include them)."""
    from mdbridge.analysis.dispersion import lab_speed_material_A_per_ps
    v = isotropic_view(mat)
    return lab_speed_material_A_per_ps(length_fiducial, v["C1"], v["D1"], v["I1"], v["rho"], Gamma03,
                                       "minus", 1, units)


def materials(reps: dict, m: int, n_replicas: int | None = None, units: Units | None = None):
    """(central material, [replicate materials]) at length m from read_replicas' dict."""
    if m not in reps["by_m"]:
        raise InputError(f"coarse-graining length m = {m} is not in the replicas file "
                         f"(lengths there: {sorted(reps['by_m'])}); coarse-grain with -m {m}")
    b, b1 = reps["by_m"][m], reps["by_m"][1]
    mass = float(np.mean(reps["mass_amu"]))
    inertia = np.mean(reps["inertia_amu_A2"], axis=0)
    T = float(reps["temperature_K"])
    central = uniform_material(b1["mean"], m * b["stiffness"], T, mass, inertia, m, units)
    n = len(b["mean_boot"]) if n_replicas is None else min(int(n_replicas), len(b["mean_boot"]))
    out: list[dict | None] = []
    for i in range(n):       # replicate i: the same resampled frames at every m (estimator.py)
        try:
            out.append(uniform_material(b1["mean_boot"][i], m * b["stiffness_boot"][i], T, mass, inertia, m,
                                        units))
        except InputError:       # a replicate whose stiffness is not positive definite
            out.append(None)
    return central, out


def eq39_prediction(reps: dict, m: int, length_fiducial: float, Gamma03: float = 1.0,
                    units: Units | None = None) -> dict:
    """Eq 39 with the coarse-grained material and its error: the spread (half the central
    68 % interval) of Eq 39 over every bootstrap replicate's material."""
    central, boot = materials(reps, m, None, units)
    vals = np.array([eq39_speed(b, length_fiducial, Gamma03, units) for b in boot if b is not None])
    return {"speed_A_per_ps": eq39_speed(central, length_fiducial, Gamma03, units),
            "speed_err_A_per_ps": float(spread(vals)) if len(vals) > 1 else float("nan"),
            "replicates": int(len(vals)), "isotropic_view": isotropic_view(central),
            "error_method": "spread of Eq 39 over the coarse-graining's bootstrap replicate materials"}


def as_json(mat: dict) -> dict:
    return {k: (np.asarray(v).tolist() if isinstance(v, np.ndarray) else v) for k, v in mat.items()}
