"""params.json: every number of a coarse-graining, with its unit and error, in the
layout docs/coarse-graining.md lists key by key."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from mdbridge.geometry.steps import STEP_NAMES

from .constants import paper_rho_I
from .continuum import UNITS
from .mass import rod_densities
from .prestress import rest_shape
from .segment import segment_rod_material

FORMAT = "dnarod-cg-params/1"
UNITS_TEXT = "A, deg; stiffness kT/A^2, kT/(A deg), kT/deg^2"
REFERENCE_POINT = ("base-pair frame origin (3DNA: mid-point of the two base origins; the rod's "
                   "centreline point r(s_i)), axes = base-pair x (d1, major groove), y (d2), z (d3)")


def _l(a):
    return None if a is None else np.asarray(a, dtype=float).tolist()


def _phys(values: dict, errs: dict | None):
    return {k: {"value": float(v), "err": None if errs is None else float(errs[k]), "unit": UNITS[k]}
            for k, v in values.items()}


def build_params(cg, temperature_source: str, extras: dict | None = None,
                 tension_pN: float | None = None, torque_pN_nm: float | None = None,
                 min_effective: float | None = None, caveats=()) -> dict:
    """The params.json dictionary of a finished CoarseGrain `cg`."""
    ens, r = cg.ens, cg.results
    T_K = r["temperature_K"]
    b1 = r["by_m"][1]
    stressed = tension_pN is not None or torque_pN_nm is not None
    F = tension_pN or 0.0
    tq = torque_pN_nm or 0.0

    def rest(mean, cov):
        return _l(rest_shape(mean, cov, F, tq, T_K)) if stressed else None

    m_rod = r["m_rod"]
    bm = r["by_m"][m_rod]
    out = {
        "format": FORMAT,
        "source": ens.source, "sequence": ens.sequence, "closed": ens.closed,
        "temperature_K": T_K, "temperature_source": temperature_source,
        "frames_used": r["frames_used"], "frames_total": r["frames_total"],
        "discarded_frames": r["discarded_frames"], "equilibration_rule": r["equilibration_rule"],
        "frame_spacing_ps": r["dt_ps"],
        "tau_int_max_frames": r["tau_int_max_frames"], "effective_samples": r["effective_samples"],
        "min_effective_samples": min_effective,
        "bootstrap": {"method": "moving block", "block_length_frames": r["block_length"],
                      "replicates": r["n_boot"]},
        "order": list(STEP_NAMES), "units": UNITS_TEXT,
        "steps": _steps(ens, r, rest, stressed),
        "average": {"mean": _l(b1["mean_avg"]), "mean_err": _l(b1["mean_avg_err"]),
                    "rest_mean": rest(b1["mean_avg"], b1["cov"].mean(axis=0)),
                    "stiffness": _l(b1["K_avg"]), "stiffness_err": _l(b1["K_avg_err"]),
                    "over": f"{len(b1['first_step'])} steps not excluded"},
        "by_length": [{"m": m, "n_windows": int(len(bl["first_step"])),
                       "mean": _l(bl["mean_avg"]), "mean_err": _l(bl["mean_avg_err"]),
                       "rest_mean": rest(bl["mean_avg"], bl["cov"].mean(axis=0)),
                       "stiffness": _l(bl["K_avg"]), "stiffness_err": _l(bl["K_avg_err"]),
                       "physical": _phys(bl["physical"], bl["physical_err"])}
                      for m, bl in sorted(r["by_m"].items())],
        "physical": _phys(bm["physical"], bm["physical_err"]),
        "physical_m": m_rod,
        "physical_note": "continuum constants of m-step segments at m = physical_m "
                         "(docs/coarse-graining.md); by_length has every m",
        "rod": _rod_section(bm, m_rod, T_K, F, tq, stressed),
        "excluded": {"rule": "a base pair whose N1-N3 distance exceeds 3.5 A (mdbridge.analysis."
                             "integrity) opens; every step touching it is excluded",
                     "steps": [int(k) + 1 for k in r["excluded_steps"]]},
        "halves": _halves(bm),
        "box_constraint": _box_constraint(ens.closed, tension_pN, torque_pN_nm, stressed),
        "convergence": _convergence(bm),
        "caveats": list(caveats),
    }
    if extras:
        _add_extras(out, extras, b1["mean_avg"][2], ens.excluded)
    return out


def _steps(ens, r, rest, stressed) -> list:
    """One row per step: its dimer, whether it is excluded, and (not excluded) its mean,
    stiffness and their errors at m = 1."""
    b1 = r["by_m"][1]
    row = {int(k): j for j, k in enumerate(b1["first_step"])}
    tau = dict(zip(r["used_steps"].tolist(), r["tau_int_steps"]))
    steps = []
    for k in range(ens.n_steps):
        d = {"step": k + 1, "dimer": ens.dimer(k), "excluded": bool(ens.excluded[k])}
        if k in row:
            j = row[k]
            d.update(mean=_l(b1["mean"][j]), mean_err=_l(b1["mean_err"][j]),
                     stiffness=_l(b1["K"][j]), stiffness_err=_l(b1["K_err"][j]),
                     tau_int_frames=_l(tau[k]))
            if stressed:
                d["rest_mean"] = rest(b1["mean"][j], b1["cov"][j])
        steps.append(d)
    return steps


def _rod_section(bm, m_rod, T_K, F, tq, stressed) -> dict:
    """The uniform rod of the m_rod-step segments (segment.py), at their rest mean when the
    box pre-stresses them."""
    mean_rod = bm["mean_avg"] if not stressed else rest_shape(bm["mean_avg"], bm["cov"].mean(axis=0), F, tq, T_K)
    rod = segment_rod_material(mean_rod, bm["cov"].mean(axis=0), T_K, bm["n_eff_pooled"])
    return {"m": m_rod, "segment_length_A": rod["segment_length_A"],
            "K_star": _l(rod["K_star"]), "K_SI": _l(rod["K_SI"]),
            "K_SI_units": "N (Gamma-Gamma), J (Gamma-Omega), J m (Omega-Omega)",
            "order": ["Gamma1", "Gamma2", "Gamma3", "Omega1", "Omega2", "Omega3"],
            "Gamma0_star": _l(rod["Gamma0_star"]), "Omega0_star": _l(rod["Omega0_star"]),
            "units": "paper's (dna_models.units): force C, length l = sqrt(I/rho)"}


def _box_constraint(closed, tension_pN, torque_pN_nm, stressed) -> dict:
    return {"closed": closed, "tension_pN": tension_pN, "torque_pN_nm": torque_pN_nm,
            "corrected": stressed,
            "correction": "rest mean q0 = <q> - <dq dq^T> f / kT, f = (0, 0, F, 0, 0, tau) "
                          "(mdbridge.coarsegrain.prestress)",
            "note": (("mean shape is the box's pre-stressed state; give --tension/--torque "
                      "to correct it" if not stressed else "rest_mean keys are corrected")
                     if closed else "linear duplex: no box constraint")}


def _add_extras(out: dict, extras: dict, rise_A, excluded) -> None:
    """The opened pairs, and the mass and inertia (and so the rod's rho* and I*)."""
    out["excluded"]["opened_pairs"] = [int(i) + 1 for i in extras.get("opened_pairs", [])]
    out["excluded"]["open_fraction"] = _l(extras.get("open_fraction"))
    out["excluded"]["max_open_fraction"] = extras.get("max_open_fraction")
    if "mass_inertia" in extras:
        out["mass_inertia"] = _mass_section(extras["mass_inertia"], rise_A, excluded, rod_rho_I=None)
        rho_p, I_p = paper_rho_I()
        mi = out["mass_inertia"]
        out["rod"]["rho_star"] = mi["rho"]["value"] / rho_p
        out["rod"]["I_star"] = _l(np.asarray(mi["I"]["value"]) / I_p)


def _halves(bm):
    h = bm["halves"]
    d = {"first": {"mean": _l(h["mean_avg"][0]), "stiffness_diag": _l(np.diagonal(h["K_avg"][0]))},
         "second": {"mean": _l(h["mean_avg"][1]), "stiffness_diag": _l(np.diagonal(h["K_avg"][1]))}}
    # each half has ~sqrt(2) times the full-run error; their difference 2 times
    e_mean = 2.0 * bm["mean_avg_err"]
    e_K = 2.0 * np.diagonal(bm["K_avg_err"])
    d["z_mean"] = _l((h["mean_avg"][0] - h["mean_avg"][1]) / e_mean)
    d["z_stiffness_diag"] = _l((np.diagonal(h["K_avg"][0]) - np.diagonal(h["K_avg"][1])) / e_K)
    if h["physical"] is not None:
        d["physical"] = {k: {"first": float(v[0]), "second": float(v[1]),
                             "z": float((v[0] - v[1]) / (2.0 * bm["physical_err"][k]))}
                         for k, v in h["physical"].items() if bm["physical_err"].get(k, 0.0) > 0}
    d["note"] = "z = (first - second) / (2 x full-run error); |z| > 3 says the run is not stationary"
    return d


def _convergence(bm):
    c = bm["convergence"]
    return {"m": bm["m"], "frames": [int(x) for x in c["frames"]],
            "stiffness_diag": _l(np.diagonal(c["K_avg"], axis1=-2, axis2=-1)),
            "physical": {k: _l(v) for k, v in c["physical"].items()}}


def _mass_section(mi, rise_A, excluded, rod_rho_I=None):
    mass = np.asarray(mi["mass"])
    sl = np.asarray(mi["slice_inertia"])
    rho, I = rod_densities(mass.mean(), sl.mean(axis=0), rise_A)
    rho_e = rho * (mass.std(ddof=1) / np.sqrt(len(mass)) / mass.mean()) if len(mass) > 1 else 0.0
    _, Ie = rod_densities(mass.mean(), np.sqrt((np.asarray(mi["slice_inertia_err"]) ** 2).mean(axis=0)
                                               / len(mass)), rise_A)
    rho_p, I_p = paper_rho_I()
    _, I_full = rod_densities(mass.mean(), np.asarray(mi["inertia"]).mean(axis=0), rise_A)
    return {"reference_point": REFERENCE_POINT,
            "I_full": {"value": _l(I_full), "unit": "kg m",
                       "convention": "full 3-d tensor of a base pair / mean rise (what the per-step file "
                                     "stores, divided by the rise); includes the base pair's extent along z"},
            "hydrogens_in_topology": mi["hydrogens"], "frames_averaged": mi["frames"],
            "mass_amu": _l(mass), "inertia_amu_A2": _l(mi["inertia"]),
            "inertia_convention": "full tensor sum m (|r|^2 1 - r r^T) about the reference point",
            "rho": {"value": rho, "err": rho_e, "unit": "kg/m", "paper": rho_p, "ratio": rho / rho_p,
                    "note": "mean base-pair mass / mean rise; err: sequence scatter of the mean"},
            "I": {"value": _l(I), "err": _l(Ie), "unit": "kg m", "paper_I1": I_p,
                  "ratio_diag": _l(np.diagonal(I) / I_p),
                  "ratio_bend_mean": float((I[0, 0] + I[1, 1]) / 2 / I_p),
                  "note": "one base pair is long along y (I11 > I22); along a helical turn the two "
                          "bend directions average, so compare (I11 + I22) / 2 with the paper's I",
                  "convention": "thin slice (cross-section) per unit length: I11 = sum m y^2, "
                                "I22 = sum m x^2, I33 = sum m (x^2 + y^2), / mean rise; paper I* = (1, 1, 2)"}}


def write_params(path, params: dict) -> Path:
    """Strict JSON (mdbridge.jsonio: a non-finite number becomes null)."""
    from mdbridge.jsonio import dumps
    p = Path(path)
    p.write_text(dumps(params) + "\n")
    return p
