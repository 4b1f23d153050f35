"""params.json: every number of a coarse-graining, with its unit and error, in the
layout docs/coarse-graining.md lists key by key."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from mdbridge.geometry.steps import STEP_NAMES

from dna_models.units import Units

from mdbridge.stats import spread

from .cgrod import ROD_CONSTANT_UNITS, rod_constants
from .constants import kT_pN_nm, paper_rho_I
from .continuum import UNITS
from .mass import rod_densities
from .prestress import rest_shape
from .qstiffness import VIEW_UNITS, view

FORMAT = "dnarod-cg-params/2"
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
        "tau_int_fit_modes_frames": r["tau_int_fit_modes_frames"],
        "effective_samples_fit_modes": r["effective_samples_fit_modes"],
        "min_effective_samples": min_effective,
        "bootstrap": {"method": "moving block", "block_length_frames": r["block_length"],
                      "replicates": r["n_boot"]},
        "order": list(STEP_NAMES), "units": UNITS_TEXT,
        "steps": _steps(ens, r, rest, stressed),
        "average": _average(r, rest),
        "long_wavelength": _long_wavelength(r),
        "q_stiffness": _q_stiffness(r, b1["mean_avg"][2]),
        "by_length": [{"m": m, "n_windows": int(len(bl["first_step"])),
                       "mean": _l(bl["mean_avg"]), "mean_err": _l(bl["mean_avg_err"]),
                       "rest_mean": rest(bl["mean_avg"], bl["cov"].mean(axis=0)),
                       "stiffness": _l(bl["K_series"]), "stiffness_err": _l(bl["K_series_err"]),
                       "stiffness_definition": "compliance average of the m-step windows, "
                                               "(mean covariance)^-1",
                       "physical": _phys(bl["physical"], bl["physical_err"])}
                      for m, bl in sorted(r["by_m"].items())],
        "physical": _phys(bm["physical"], bm["physical_err"]),
        "physical_m": m_rod,
        "physical_note": "continuum constants of m-step segments at m = physical_m "
                         "(docs/coarse-graining.md); by_length has every m",
        "rod": _rod_section(r),
        "excluded": {"steps": [int(k) + 1 for k in r["excluded_steps"]],
                     "note": "steps not used at all (none unless the caller excluded them: every step "
                             "the analysis defines is used)"},
        "opening_rule": {"rule": "a base pair whose N1-N3 distance exceeds 3.5 A (mdbridge.md.integrity) "
                                 "in more than max_open_fraction of the frames counts as opened; the "
                                 "sensitivity leaves out every step touching it",
                         "steps": [int(k) + 1 for k in r["opened_steps"]],
                         # the local estimates leave each step out where it touches an open
                         # pair, frame by frame (estimator.py): the fraction left out
                         "open_step_frames": r.get("open_step_frames", 0.0)},
        "halves": _halves(bm),
        "box_constraint": _box_constraint(ens.closed, tension_pN, torque_pN_nm, stressed,
                                          r["long_wavelength"]),
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
        d = {"step": k + 1, "dimer": ens.dimer(k), "excluded": bool(ens.excluded[k]),
             "opened": bool(ens.opened[k])}
        if k in row:
            j = row[k]
            d.update(mean=_l(b1["mean"][j]), mean_err=_l(b1["mean_err"][j]),
                     stiffness=_l(b1["K"][j]), stiffness_err=_l(b1["K_err"][j]),
                     tau_int_frames=_l(tau[k]))
            if stressed:
                d["rest_mean"] = rest(b1["mean"][j], b1["cov"][j])
        steps.append(d)
    return steps


def _average(r, rest) -> dict:
    """The rod's per-step stiffness K(q -> 0) and its error parts; the per-step compliance
    average beside it."""
    lw, b1 = r["long_wavelength"], r["by_m"][1]
    rule = r["rule"]
    return {"mean": _l(b1["mean_avg"]), "mean_err": _l(b1["mean_avg_err"]),
            "rest_mean": rest(b1["mean_avg"], b1["cov"].mean(axis=0)),
            "stiffness": _l(lw["K_q0"]), "stiffness_err": _l(lw["K_q0_err"]),
            "stiffness_err_parts": {"bootstrap": _l(lw["K_q0_boot_err"]),
                                    "extrapolation": _l(lw["extrapolation_err"]),
                                    "opening_rule": _l(lw["rule_spread"])},
            "definition": "K(q -> 0): the long-wavelength stiffness of the step parameters' compliance "
                          "spectrum, per step, kT units (the K the rod is built from; "
                          "docs/coarse-graining.md, \"The rod's K\")",
            "compliance_average": {"stiffness": _l(lw["K_avg_compliance"]),
                                   "stiffness_err": _l(lw["K_avg_compliance_err"]),
                                   "definition": "inverse of the mean per-step covariance, the "
                                                 "closure's modes taken out (equal to K(q -> 0) for "
                                                 "independent steps)"},
            "opening_rule": None if rule is None else {
                "stiffness": _l(rule["K_q0"]), "compliance_average": _l(rule["K_avg_compliance"]),
                "steps_left_out": [int(k) + 1 for k in r["opened_steps"]]},
            "over": f"{lw['n_kept']} of {lw['n_steps']} steps"}


def _long_wavelength(r) -> dict:
    lw = r["long_wavelength"]
    d = {"helical_turns": lw["helical_turns"], "fit_modes": [int(k) for k in lw["fit_modes"]],
         "fit_order": lw["fit_order"], "fit_q_max_rad_per_step": lw["fit_q_max_rad"],
         "fit": "Re S(q) = a0 + a1 4 sin^2(q/2) by least squares over fit_modes; S(0) = a0",
         "fit_weights": _l(lw["fit_weights"]),
         "stiffness_order2": _l(lw["K_q0_order2"]),
         "degrees_of_freedom": {"q0": float(lw["dof_q0"]), "compliance_average": float(lw["dof_avg"])},
         "modes_left_out": "k = 0 and k = helical_turns (the closure's)" if lw["closed"] else "none"}
    if "halves" in lw:
        h = lw["halves"]["K_q0"]
        e = 2.0 * np.diagonal(lw["K_q0_boot_err"])
        d["halves"] = {"first_diag": _l(np.diagonal(h[0])), "second_diag": _l(np.diagonal(h[1])),
                       "z_diag": _l((np.diagonal(h[0]) - np.diagonal(h[1])) / e)}
    return d


def _q_stiffness(r, rise_A) -> dict:
    """Bend, twist and stretch stiffness against q, with bootstrap errors, and at q -> 0."""
    lw = r["long_wavelength"]
    kT = kT_pN_nm(r["temperature_K"])
    v, vb = view(lw["S"], rise_A, kT), view(lw["S_boot"], rise_A, kT)
    v0, v0b = view(np.linalg.inv(lw["K_q0"]), rise_A, kT), view(np.linalg.inv(lw["K_q0_boot"]), rise_A, kT)
    va = view(np.linalg.inv(lw["K_avg_compliance"]), rise_A, kT)
    q = lw["q_rad_per_step"]
    out = {"k": [int(k) for k in lw["k"]], "q_rad_per_step": _l(q), "q_per_nm": _l(q / (rise_A / 10.0)),
           "usable": [bool(u) for u in lw["usable"]], "fit_modes": [int(k) for k in lw["fit_modes"]],
           "definition": "per mode, the compliances of the spectrum S(q) as constants of a segment of one "
                         "mean rise: bend 2 h / (S_tilt + S_roll), twist kT h / S_twist, stretch "
                         "kT h [(S_rise,twist)^-1]_rise; at_q0 the same of K(q -> 0)^-1"}
    for k, unit in VIEW_UNITS.items():
        out[k] = {"value": _l(v[k]), "err": _l(spread(vb[k])), "unit": unit,
                  "at_q0": float(v0[k]), "at_q0_err": float(spread(v0b[k])),
                  "compliance_average": float(va[k])}
    return out


def _rod_section(r) -> dict:
    """The uniform rod the loop builds (cgrod.py): K(q -> 0) at the sequence-averaged mean
    step through mdbridge.rod.material.steps_to_rod at the paper's rise, and its own
    effective constants, with bootstrap errors; the same constants of the compliance average."""
    from mdbridge.rod.material.steps_to_rod import rod_stiffness, strains_from_steps
    u = Units.paper()
    lw, b1 = r["long_wavelength"], r["by_m"][1]
    T_K = r["temperature_K"]
    mean = b1["mean_avg"]
    K = rod_stiffness(lw["K_q0"], mean, T_K, u.rise_A, u)
    Kb = rod_stiffness(lw["K_q0_boot"], b1["mean_avg_boot"], T_K, u.rise_A, u)
    Ka = rod_stiffness(lw["K_avg_compliance"], mean, T_K, u.rise_A, u)
    Kab = rod_stiffness(lw["K_avg_compliance_boot"], b1["mean_avg_boot"], T_K, u.rise_A, u)
    G0, O0 = strains_from_steps(mean, u.rise_A, u)
    c, cb = rod_constants(K, T_K, u), rod_constants(Kb, T_K, u)
    ca, cab = rod_constants(Ka, T_K, u), rod_constants(Kab, T_K, u)
    return {"definition": "the uniform coarse-grained rod: K(q -> 0) (average.stiffness) at the mean step "
                          "(average.mean), mapped by mdbridge.rod.material.steps_to_rod at h = the "
                          "paper's rise", "h_A": u.rise_A,
            "K_star": _l(K), "K_star_err": _l(spread(Kb)), "K_SI": _l(u.stiffness_to_SI(K)),
            "K_SI_units": "N (Gamma-Gamma), J (Gamma-Omega), J m (Omega-Omega)",
            "order": ["Gamma1", "Gamma2", "Gamma3", "Omega1", "Omega2", "Omega3"],
            "Gamma0_star": _l(G0), "Omega0_star": _l(O0),
            "constants": {k: {"value": float(c[k]), "err": float(spread(cb[k])), "unit": unit}
                          for k, unit in ROD_CONSTANT_UNITS.items()},
            "constants_compliance_average": {k: {"value": float(ca[k]), "err": float(spread(cab[k])),
                                                 "unit": unit} for k, unit in ROD_CONSTANT_UNITS.items()},
            "constants_note": "the rod's own effective constants at temperature_K from its K* alone "
                              "(mdbridge.coarsegrain.cgrod.rod_constants); errors bootstrap only",
            "units": "paper's (dna_models.units): force C, length l = sqrt(I/rho)"}


def _box_constraint(closed, tension_pN, torque_pN_nm, stressed, lw) -> dict:
    return {"closed": closed,
            "modes_left_out": (f"k = 0 (total twist and length) and k = {lw['helical_turns']} (the "
                               "laboratory-frame bend closure) of the spectrum" if closed else None),
            "tension_pN": tension_pN, "torque_pN_nm": torque_pN_nm,
            "corrected": stressed,
            "correction": "rest mean q0 = <q> - <dq dq^T> f / kT, f = (0, 0, F, 0, 0, tau) "
                          "(mdbridge.coarsegrain.prestress)",
            "note": (("mean shape is the box's pre-stressed state; give --tension/--torque "
                      "to correct it" if not stressed else "rest_mean keys are corrected")
                     if closed else "linear duplex: no box constraint")}


def _add_extras(out: dict, extras: dict, rise_A, excluded) -> None:
    """The opened pairs, and the mass and inertia (and so the rod's rho* and I*)."""
    out["opening_rule"]["opened_pairs"] = [int(i) + 1 for i in extras.get("opened_pairs", [])]
    out["opening_rule"]["open_fraction"] = _l(extras.get("open_fraction"))
    out["opening_rule"]["max_open_fraction"] = extras.get("max_open_fraction")
    if "mass_inertia" in extras:
        mi = extras["mass_inertia"]
        out["mass_inertia"] = _mass_section(mi, rise_A, excluded, rod_rho_I=None)
        # the loop's convention (cgrod.uniform_material): mean mass and full inertia tensor over h
        u = Units.paper()
        out["rod"]["rho_star"] = float(u.mass_amu_per_length_A_to_rod(float(np.mean(mi["mass"])), u.rise_A))
        I = np.asarray(u.inertia_amu_A2_per_length_A_to_rod(np.mean(np.asarray(mi["inertia"], float), axis=0),
                                                           u.rise_A))
        out["rod"]["I_star"] = _l(0.5 * (I + I.T))


def _halves(bm):
    h = bm["halves"]
    d = {"first": {"mean": _l(h["mean_avg"][0]), "stiffness_diag": _l(np.diagonal(h["K_series"][0]))},
         "second": {"mean": _l(h["mean_avg"][1]), "stiffness_diag": _l(np.diagonal(h["K_series"][1]))}}
    # each half has ~sqrt(2) times the full-run error; their difference 2 times
    e_mean = 2.0 * bm["mean_avg_err"]
    e_K = 2.0 * np.diagonal(bm["K_series_err"])
    d["z_mean"] = _l((h["mean_avg"][0] - h["mean_avg"][1]) / e_mean)
    d["z_stiffness_diag"] = _l((np.diagonal(h["K_series"][0]) - np.diagonal(h["K_series"][1])) / e_K)
    if h["physical"] is not None:
        d["physical"] = {k: {"first": float(v[0]), "second": float(v[1]),
                             "z": float((v[0] - v[1]) / (2.0 * bm["physical_err"][k]))}
                         for k, v in h["physical"].items() if bm["physical_err"].get(k, 0.0) > 0}
    d["note"] = "z = (first - second) / (2 x full-run error); |z| > 3 says the run is not stationary"
    return d


def _convergence(bm):
    c = bm["convergence"]
    return {"m": bm["m"], "frames": [int(x) for x in c["frames"]],
            "stiffness_diag": _l(np.diagonal(c["K_series"], axis1=-2, axis2=-1)),
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
