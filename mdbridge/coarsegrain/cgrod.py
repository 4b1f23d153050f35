"""The uniform coarse-grained rod: the duplex's long-wavelength material from a
coarse-graining, mapped onto the rod by mdbridge.rod.material.steps_to_rod, with its bootstrap
replicas, its own effective constants and its small-amplitude (Eq 39) prediction
(docs/coarse-graining.md, "The rod's K" and "The loop").

Material. The rod's per-step stiffness F (6 x 6, kT units) is the long-wavelength stiffness
K(q -> 0) of the step parameters (qstiffness.py: compliances in series, couplings between
steps included), its mean step p the sequence-averaged mean; the exact map of steps_to_rod
at h (the paper's rise, dna_models.units) gives its shape strains_from_steps(p, h) (Gamma0*,
Omega0*) and stiffness rod_stiffness(F, p, T, h) (K*). rho* and I* are the mean base pair's
mass and inertia over h (steps_to_rod's convention: the full inertia tensor about the
base-pair origin).

Coarse-graining length m (a diagnostic). The m-step segments' compliance average F_m =
(mean covariance)^-1 enters as the per-step equivalent F = m F_m: for independent steps the
m-step covariance is m times the per-step one (to first order; the twist between steps only
turns the bends, and the sum of isotropic bends does not care), so m F_m = F_1 there, and
on correlated steps m F_m tends to K(q -> 0) as m grows. It is not mapped as one
constant-strain piece of length m h: an m-step segment of a chain is not one (its bends sit
in body frames turned by the twist), and that map makes the bend stiffness low by about
sinc^2 of half the segment's twist (-22 % at m = 3). Caveat: the m-step shift and slide also
carry the bends' lever arms, so the shear block of m F_m is soft for m > 1 (-15 % at m = 3
on tests/python/test_coarsegrain_loop.py's ensemble).

Errors. The coarse-graining's moving-block bootstrap replicates (same frames for every step)
of p and F are written next to params.json (`write_replicas`, DIR/replicas.h5); each
replicate gives a material, and the spread of any prediction over those materials is its
bootstrap error. The extrapolation to q -> 0 and the opening rule add to it where they are
significant (`systematic_materials`). rho is exact (masses) and I is averaged over 50 frames,
so both are held at their central values.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from dna_models.errors import InputError
from dna_models.units import BOLTZMANN, Units

from mdbridge.stats import spread

REPLICAS_FORMAT = "dnarod-cg-replicas/2"


def write_replicas(path, cg, extras: dict | None = None) -> Path:
    """DIR/replicas.h5: the rod's K(q -> 0) (group `rod`: mean, stiffness and their bootstrap
    replicates; the same with the order-2 extrapolation and with the opening rule's steps
    left out, when there are such); per m the sequence-averaged mean and the compliance
    average and their replicates; the base pairs' masses and inertia; temperature and
    bootstrap settings."""
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
        lw, b1 = r["long_wavelength"], r["by_m"][1]
        g = f.create_group("rod")
        g.attrs["definition"] = "K(q -> 0) of the step parameters' compliance spectrum (qstiffness.py)"
        g["mean"] = b1["mean_avg"]
        g["mean_boot"] = b1["mean_avg_boot"]
        g["stiffness"] = lw["K_q0"]
        g["stiffness_boot"] = lw["K_q0_boot"]
        if lw["K_q0_order2"] is not None:
            g["stiffness_order2"] = lw["K_q0_order2"]
        if r["rule"] is not None:
            g["stiffness_rule"] = r["rule"]["K_q0"]
        for m, b in r["by_m"].items():
            g = f.create_group(f"m{m}")
            g["mean"] = b["mean_avg"]
            g["stiffness"] = b["K_series"]
            g["mean_boot"] = b["mean_avg_boot"]
            g["stiffness_boot"] = b["K_series_boot"]
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
        if "rod" not in f:
            raise InputError(f"{p}: group 'rod' missing")
        out["rod"] = {n: np.asarray(f["rod"][n]) for n in f["rod"]}
        for n in ("mass_amu", "inertia_amu_A2"):
            if n not in f:
                raise InputError(f"{p}: dataset '{n}' missing (the coarse-graining had no atoms)")
            out[n] = np.asarray(f[n])
    return out


def uniform_material(mean, F, temperature_K: float, mass_amu: float, inertia_amu_A2, m: int = 1,
                     units: Units | None = None) -> dict:
    """K* (6, 6), I* (3, 3), rho*, Gamma0*, Omega0* of the uniform rod whose every step has
    the mean step parameters `mean` (A, deg) and the per-step stiffness F (kT units), by the
    exact map of mdbridge.rod.material.steps_to_rod at h = the paper's rise. m = 0 marks
    the rod's K(q -> 0); for m >= 1, F is the per-step equivalent m F_m of the m-step
    compliance average F_m (`materials`)."""
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
    """The transverse constants of a material as an isotropic rod sees them. The helical
    twist turns the body axes many times over a long wave, so a lab-frame bend puts the
    two body directions in series: their compliances average,
    1 / D1 = ((K^-1)_44 + (K^-1)_55) / 2, the same for shear with (K^-1)_11, (K^-1)_22
    (mdbridge/rod/linear.py's rod does exactly this: tests/python/test_rod_linear.py,
    test_fast_twist_averages_the_bend_compliances). The compliances are the full K's,
    so the couplings (twist-bend, shear-bend) soften them as they soften the rod. The
    inertia, a kinetic term of a rigid cross-section, averages as it is."""
    K, I = np.asarray(mat["K_star"]), np.asarray(mat["I_star"])
    c = np.diagonal(np.linalg.inv(K))
    return {"C1": 2.0 / (c[0] + c[1]), "D1": 2.0 / (c[3] + c[4]),
            "I1": 0.5 * (I[0, 0] + I[1, 1]), "rho": float(mat["rho_star"])}


def rod_constants(K_star, temperature_K: float, units: Units | None = None) -> dict:
    """The rod's own effective constants at temperature_K, from its K* (..., 6, 6) alone,
    with the definitions of the m-step constants (continuum.py): bend persistence D1 / kT
    (isotropic_view's compliance average), torsional modulus 1 / (K^-1)_66, and from the
    (Gamma3, Omega3) block of K^-1 inverted: stretch modulus, twist-stretch coupling and
    twist stiffness at fixed extension. Values in nm, pN nm^2, pN, pN nm."""
    u = units or Units.paper()
    K_SI = np.asarray(u.stiffness_to_SI(np.asarray(K_star, float)))          # N, J, J m
    c = np.linalg.inv(K_SI)
    kT_J = BOLTZMANN * float(temperature_K)
    D = 2.0 / (c[..., 3, 3] + c[..., 4, 4])
    blk = np.linalg.inv(c[..., [2, 5], :][..., :, [2, 5]])
    return {"bend_persistence_length": D / kT_J * 1e9, "torsional_modulus": 1e30 / c[..., 5, 5],
            "stretch_modulus": blk[..., 0, 0] * 1e12, "twist_stretch_coupling": blk[..., 0, 1] * 1e21,
            "twist_stiffness_at_fixed_extension": blk[..., 1, 1] * 1e30}


ROD_CONSTANT_UNITS = {"bend_persistence_length": "nm", "torsional_modulus": "pN nm^2", "stretch_modulus": "pN",
                      "twist_stretch_coupling": "pN nm", "twist_stiffness_at_fixed_extension": "pN nm^2"}


def eq39_speed(mat: dict, length_fiducial: float, Gamma03: float = 1.0, units: Units | None = None) -> float:
    """Small-amplitude bend-branch lab speed [A/ps] of the fundamental (Eq 39) of a material,
    through its isotropic view (couplings left out: the rod runs include them)."""
    from mdbridge.analysis.dispersion import lab_speed_material_A_per_ps
    v = isotropic_view(mat)
    return lab_speed_material_A_per_ps(length_fiducial, v["C1"], v["D1"], v["I1"], v["rho"], Gamma03,
                                       "minus", 1, units)


def _stiffness_of(reps: dict, m: int | None):
    """(F, F replicates, m tag) of the rod (m None: K(q -> 0)) or of the m-step compliance average."""
    if m is None:
        r = reps["rod"]
        return r["stiffness"], r["stiffness_boot"], 0
    if m not in reps["by_m"]:
        raise InputError(f"coarse-graining length m = {m} is not in the replicas file "
                         f"(lengths there: {sorted(reps['by_m'])}); coarse-grain with -m {m}")
    b = reps["by_m"][m]
    return m * b["stiffness"], m * b["stiffness_boot"], m


def with_stiffness(reps: dict, F, mean=None, m: int = 0, units: Units | None = None) -> dict:
    """uniform_material of read_replicas' dict with the per-step stiffness F: its mean shape
    (or MEAN), the pairs' mean mass and inertia and its temperature."""
    return uniform_material(reps["by_m"][1]["mean"] if mean is None else mean, F, float(reps["temperature_K"]),
                            float(np.mean(reps["mass_amu"])), np.mean(reps["inertia_amu_A2"], axis=0), m, units)


def materials(reps: dict, m: int | None = None, n_replicas: int | None = None, units: Units | None = None):
    """(central material, [replicate materials]) from read_replicas' dict: the rod's
    K(q -> 0) (m None), or the m-step compliance average as per-step equivalent."""
    F, Fb, tag = _stiffness_of(reps, m)
    b1 = reps["by_m"][1]
    central = with_stiffness(reps, F, m=tag, units=units)
    n = len(b1["mean_boot"]) if n_replicas is None else min(int(n_replicas), len(b1["mean_boot"]))
    out: list[dict | None] = []
    for i in range(n):       # replicate i: the same resampled frames for every quantity (estimator.py)
        try:
            out.append(with_stiffness(reps, Fb[i], b1["mean_boot"][i], tag, units))
        except InputError:       # a replicate whose stiffness is not positive definite
            out.append(None)
    return central, out


def systematic_materials(reps: dict, units: Units | None = None) -> dict:
    """{"extrapolation": material, "rule": material} of the rod's K(q -> 0) extrapolated at
    order 2 and with the opening rule's steps left out, where the replicas file has them:
    their differences from the central material are its systematic errors."""
    r, b1 = reps["rod"], reps["by_m"][1]
    args = (float(reps["temperature_K"]), float(np.mean(reps["mass_amu"])),
            np.mean(reps["inertia_amu_A2"], axis=0), 0, units)
    out = {}
    for key, name in (("extrapolation", "stiffness_order2"), ("rule", "stiffness_rule")):
        if name in r:
            try:
                out[key] = uniform_material(b1["mean"], r[name], *args)
            except InputError:
                pass
    return out


def eq39_prediction(reps: dict, m: int | None, length_fiducial: float, Gamma03: float = 1.0,
                    units: Units | None = None) -> dict:
    """Eq 39 with the coarse-grained material and its error: the spread (half the central
    68 % interval) of Eq 39 over every bootstrap replicate's material; for the rod's
    K(q -> 0) (m None) also the shift of Eq 39 under the order-2 extrapolation (where it
    exceeds its bootstrap spread) and under the opening rule (where it exceeds the bootstrap
    error), in quadrature."""
    central, boot = materials(reps, m, None, units)
    c = eq39_speed(central, length_fiducial, Gamma03, units)
    vals = np.array([eq39_speed(b, length_fiducial, Gamma03, units) for b in boot if b is not None])
    err_boot = float(spread(vals)) if len(vals) > 1 else float("nan")
    parts = {"bootstrap": err_boot}
    if m is None:
        for key, mat in systematic_materials(reps, units).items():
            d = abs(eq39_speed(mat, length_fiducial, Gamma03, units) - c)
            parts[key] = d if d > err_boot else 0.0
    return {"speed_A_per_ps": c, "speed_err_A_per_ps": float(np.sqrt(sum(v * v for v in parts.values()))),
            "speed_err_parts_A_per_ps": parts, "replicates": int(len(vals)),
            "isotropic_view": isotropic_view(central),
            "error_method": "spread of Eq 39 over the coarse-graining's bootstrap replicate materials; "
                            "for K(q -> 0) the order-2 extrapolation's and the opening rule's shifts "
                            "added in quadrature where they exceed it"}


def as_json(mat: dict) -> dict:
    return {k: (np.asarray(v).tolist() if isinstance(v, np.ndarray) else v) for k, v in mat.items()}
