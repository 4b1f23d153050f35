"""The rod's prediction of a closed duplex's mode spectrum, and the MD's tension and bend
stiffness read back from its own modes (docs/dispersion.md).

Prediction, no fitted parameter. A uniform rod material (the coarse-grained one, or the
paper's) held at the MD's measured axial tension has, by the linear Cosserat dynamics of
rodcore's own right-hand side (mdbridge/rod/linear.py), one frequency per kind (bend, twist,
stretch) and lab mode number n. Its error has two parts, added in quadrature:
  * the material's: the spread (mdbridge.stats.spread) of the frequency over the
    coarse-graining's bootstrap replicate materials;
  * the tension's: half the difference of the frequencies at T + dT and T - dT (the lowest
    bend mode of the 158-bp duplex moves ~6 % per pN).

The MD's T and B. The lowest bend modes of a string-beam obey mu omega^2 / k^2 = T + B k^2.
The rod adds shear compliance and rotary inertia (at n = 10 of 158 bp the shear term
B k^2 / C is ~30 %), so the fit here is not of that formula but of the linear rod itself:
the frequencies of a template material (the coarse-grained one: its mass, inertia, shear
and stretch blocks) whose bend block is scaled by b, at tension T, are fitted to the
measured ones by weighted least squares (Gauss-Newton with central differences, damped
when a step would not lower chi^2). B is the
compliance average of the scaled material's bend stiffness, 1 / B = [(K^-1)_44 + (K^-1)_55] / 2
(what a rod that turns many times over a wavelength feels: mdbridge/rod/linear.py's tests).

The static variances give a second, independent B and T: for one transverse direction of
u(s) = sum_n Re(c_n e^{i k_n s}), equipartition of the translational momenta gives
<|dc_n/dt|^2> = 4 kT / M exactly (M the duplex's mass), and each normal mode j that moves
lab mode n holds the share w_j of that velocity variance, so
    <|c_n|^2> = (4 kT / M) sum_j w_j / omega_j^2,
which is 4 kT / ((B k^4 + T k^2) L) for an Euler-Bernoulli string-beam and carries the same
shear and inertia corrections as the frequencies otherwise (it depends on the potential
energy only: tests/python/test_dispersion_prediction.py checks that masses drop out).

Everything in DNA units at the interface (pN, rad/ps, A^2, K); rod units inside.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from dna_models.errors import InputError, NumericalError
from dna_models.units import Units, persistence_length_nm
from mdbridge.rod.linear import LinearRod, UniformMaterial, dispersion, lab_bend_indices
from mdbridge.stats import spread

KINDS = ("bend", "twist", "stretch")
TENSION_STEP_PN = 0.05        # central-difference step of the fit in T
BEND_SCALE_STEP = 1e-3        # and in ln b
LN_BEND_SCALE_MAX = math.log(1e3)   # the fit's range of b: template's B / 1000 .. x 1000


@dataclass(frozen=True)
class Duplex:
    """The closed duplex a prediction is for: base pairs, helical turns, and the MD's
    temperature (kT of the static variances, the persistence length)."""
    n_bp: int
    turns: int
    temperature_K: float = 300.0

    def fiducial_length(self, u: Units) -> float:
        return self.n_bp * u.length_to_rod(u.rise_A)


def paper_material(duplex: Duplex, units: Units | None = None) -> UniformMaterial:
    """The paper's rod (Sec 2.1-2.2) with the duplex's intrinsic twist (unstressed at rest)."""
    u = units or Units.paper()
    return UniformMaterial.paper(2 * np.pi * duplex.turns / duplex.fiducial_length(u))


def scaled_bend(mat: UniformMaterial, b: float) -> UniformMaterial:
    """The material with its bend block scaled by b: K' = S K S, S = diag(1, 1, 1, sqrt b,
    sqrt b, 1), so every bend compliance (K'^-1)_44, _55, _45 is that of K over b and the
    couplings keep their correlation coefficients."""
    if not b > 0:
        raise InputError(f"bend scale {b}: must be > 0")
    s = np.array([1.0, 1.0, 1.0, math.sqrt(b), math.sqrt(b), 1.0])
    return UniformMaterial(K=np.asarray(mat.K, float) * s[:, None] * s[None, :], I=mat.I, rho=mat.rho,
                           Gamma0=mat.Gamma0, Omega0=mat.Omega0)


def bend_stiffness_pN_nm2(mat: UniformMaterial, units: Units | None = None) -> float:
    """The compliance-averaged bend stiffness B = 2 / [(K^-1)_44 + (K^-1)_55] [pN nm^2]."""
    u = units or Units.paper()
    C = np.linalg.inv(u.stiffness_to_SI(np.asarray(mat.K, float)))
    return 2.0 / (C[3, 3] + C[4, 4]) * 1e12 * 1e18


def persistence_nm(B_pN_nm2: float, temperature_K: float) -> float:
    return persistence_length_nm(B_pN_nm2 * 1e-30, temperature_K)


def box_twist(mat: UniformMaterial, duplex: Duplex, units: Units | None = None) -> UniformMaterial:
    """The material with its intrinsic twist-curvature vector Omega0 scaled to the ligated
    duplex's |Omega| = 2 pi turns / L: the same rest shape, torque-free in the box (a
    coarse-grained mean step from a biased selection of steps can carry a twist that the
    ligation then holds as a torque, which softens the bend modes)."""
    u = units or Units.paper()
    O0 = np.asarray(mat.Omega0, float)
    w = 2 * np.pi * duplex.turns / duplex.fiducial_length(u)
    return UniformMaterial(K=mat.K, I=mat.I, rho=mat.rho, Gamma0=mat.Gamma0, Omega0=O0 * w / np.linalg.norm(O0))


def rest_state(mat: UniformMaterial, duplex: Duplex, tension_pN: float, units: Units | None = None) -> dict:
    """The uniform state the modes are about: Gamma, Omega (rod units), and the axial force
    and torque along the Darboux axis [pN, pN nm] (the torque is what the ligation holds
    when the material's intrinsic twist differs from the box's)."""
    from mdbridge.rod.linear import K_times, uniform_state
    u = units or Units.paper()
    G, O = uniform_state(mat, tension_pN * 1e-12 / u.C, 2 * np.pi * duplex.turns / duplex.fiducial_length(u))
    nm = K_times(mat, G, O)
    e = O / np.linalg.norm(O)
    return {"Gamma": G.tolist(), "Omega": O.tolist(), "force_pN": float(nm[:3] @ e) * u.C * 1e12,
            "torque_pN_nm": float(nm[3:] @ e) * u.C * u.ell_m * 1e21,
            "intrinsic_twist_over_box": float(np.linalg.norm(mat.Omega0) / np.linalg.norm(O))}


def _rod(mat: UniformMaterial, duplex: Duplex, tension_pN: float, u: Units, n_max: int | None = None) -> LinearRod:
    """The linear rod of n_bp points (the rod runs' grid), or, given the highest lab mode
    n_max, of the fewest points that resolve every body wavenumber it needs (|m| <= turns +
    n_max): spectral d/ds makes A(k) the continuum operator at any resolved k, so both give
    the same frequencies to round-off (tests/python/test_dispersion_prediction.py)."""
    N = duplex.n_bp if n_max is None else min(duplex.n_bp, 2 * (duplex.turns + n_max) + 2)
    return LinearRod(mat, duplex.fiducial_length(u), N, tension=tension_pN * 1e-12 / u.C, turns=duplex.turns)


def frequencies(mat: UniformMaterial, duplex: Duplex, tension_pN: float, n_max: int = 14,
                units: Units | None = None) -> dict:
    """{kind: {n: (omega, omega_min, omega_max) [rad/ps]}} for n = 1..n_max of the rod of `mat`
    at `tension_pN` (mdbridge/rod/linear.py: dispersion; min and max are the handed bend
    modes' splitting by the material's anisotropy)."""
    u = units or Units.paper()
    rod = _rod(mat, duplex, tension_pN, u)
    modes = rod.modes(n_max)
    w = u.angular_velocity_to_rad_per_ps
    return {kind: {n: (w(v["omega"]), w(v["omega_min"]), w(v["omega_max"]))
                   for n, v in dispersion(modes, kind).items() if 1 <= n <= n_max} for kind in KINDS}


def bend_frequencies(mat: UniformMaterial, duplex: Duplex, tension_pN: float, ns,
                     units: Units | None = None) -> np.ndarray:
    """The bend frequencies [rad/ps] of lab modes `ns` only (the body wavenumbers that hold
    them: linear.lab_bend_indices), as `frequencies` gives them."""
    u = units or Units.paper()
    rod = _rod(mat, duplex, tension_pN, u, max(ns))
    modes = rod.modes(max(ns), lab_bend_indices(ns, duplex.turns, rod.N))
    d = dispersion(modes, "bend")
    return np.array([u.angular_velocity_to_rad_per_ps(d[n]["omega"]) for n in ns])


def bend_variances_A2(mat: UniformMaterial, duplex: Duplex, tension_pN: float, ns,
                      units: Units | None = None) -> np.ndarray:
    """<|c_n|^2> [A^2] of one transverse direction of the axis, lab modes `ns`, in thermal
    equilibrium at duplex.temperature_K (module doc; M = the rod's own mass rho L).

    Each eigenvector v (omega > 0) of A(k) at a body index m that holds lab mode n moves it
    through the circular part of its translational velocity that lands on n (c+ = v_a + i v_b
    on |m + turns|, c- = v_a - i v_b on |turns - m|: mdbridge/rod/linear.py's module doc); its
    share of the velocity variance is |c|^2 over its kinetic energy rho |gamma|^2 + omega.I.omega
    (every normal mode holds kT)."""
    u = units or Units.paper()
    rod = _rod(mat, duplex, tension_pN, u, max(ns))
    B = rod.basis
    I = np.asarray(mat.I, float)
    num = {int(n): 0.0 for n in ns}
    den = {int(n): 0.0 for n in ns}
    for m in lab_bend_indices(ns, duplex.turns, rod.N):
        ms = m if m <= rod.N // 2 else m - rod.N
        lam, V = np.linalg.eig(rod.operator(m))
        for w, v in zip(lam.imag, V.T):
            if w <= 1e-12:
                continue
            g = B @ v[0:3]
            ke = mat.rho * float(np.vdot(v[0:3], v[0:3]).real) + float(np.vdot(v[3:6], I @ v[3:6]).real)
            for n_lab, c in ((abs(ms + duplex.turns), g[0] + 1j * g[1]), (abs(duplex.turns - ms), g[0] - 1j * g[1])):
                if n_lab in num:
                    share = abs(c) ** 2 / ke
                    num[n_lab] += share / w ** 2
                    den[n_lab] += share
    kT = u.kT_to_rod(duplex.temperature_K)
    M = float(mat.rho) * duplex.fiducial_length(u)
    return np.array([4 * kT / M * num[int(n)] / den[int(n)] for n in ns]) * u.ell_A ** 2


# -- the inertia of the axial modes, from kinetic equipartition ---------------------------
AXIAL_INERTIA = {"twist": "I3", "stretch": "rho"}


def axial_inertia(entry: dict, n_bp: int, length_A: float, temperature_K: float,
                  units: Units | None = None) -> tuple:
    """(value, error) [rod units] of the inertia per length that a measured twist or stretch
    mode (an entry of modes.json["modes"]) implies, I3 for twist and rho for stretch; (None,
    None) when the mode has no fitted oscillator.

    Equipartition of the kinetic energy, with no stiffness in it. A step field sampled on
    base pair i at s_i = i h (h = L / n_bp) is a difference of a node field: twist_i =
    phi_{i+1} - phi_i (Omega3 = twist_i / h), rise_i = h + z_{i+1} - z_i. Its mode c_n
    (mdbridge/analysis/modes.py) is (e^{i k h} - 1) times the node field's a_n, so
    |c_n|^2 = (2 sin(k h / 2))^2 |a_n|^2 exactly (h^-2 more for Omega3). The node field's
    kinetic energy, sum_i (1/2) I3 h phidot_i^2, is (I3 L / 4) |adot_n|^2 for the two real
    degrees of freedom of a_n, so <|adot_n|^2> = 4 kT / (I3 L) (rho for z). The fitted
    oscillator of undamped frequency omega0 (md_natural_frequency: a Langevin or thermostat
    friction does not change it) has <|cdot|^2> = omega0^2 <|c|^2>_osc, hence
        I3  = 4 kT (2 sin(k h / 2) / h)^2 / (L omega0^2 <|c_n|^2>_osc)
        rho = 4 kT (2 sin(k h / 2))^2 / (L omega0^2 <|c_n|^2>_osc).
    <|c_n|^2>_osc is the oscillator's own variance (modes.json oscillator_variance), not the
    record's: a slow motion that does not oscillate holds variance but not the mode's
    velocity. Relative error: that of the variance and twice that of omega0, in quadrature.
    Checked on Langevin rods of known I3 and rho (bench/mode_spectrum_calibration.py
    --thermal-rod, docs/analysis.md "Calibration")."""
    kind = entry["kind"]
    if kind not in AXIAL_INERTIA:
        raise InputError(f"axial_inertia: mode kind {kind!r}; allowed: {sorted(AXIAL_INERTIA)}")
    w0, e0 = md_natural_frequency(entry)
    v, ev = entry.get("oscillator_variance"), entry.get("oscillator_variance_err")
    if w0 is None or not v:
        return None, None
    u = units or Units.paper()
    L = u.length_to_rod(length_A)
    h = L / n_bp
    k = 2 * np.pi * int(entry["n"]) / L
    w0_rod = w0 * u.tau_ps
    # the variance in rod units: rad^2/A^2 -> rad^2/ell^2, A^2 -> ell^2
    v_rod = v * u.ell_A ** 2 if kind == "twist" else v / u.ell_A ** 2
    q = 2 * math.sin(k * h / 2) / (h if kind == "twist" else 1.0)
    value = 4 * u.kT_to_rod(temperature_K) * q ** 2 / (L * w0_rod ** 2 * v_rod)
    rel = math.hypot(2 * (e0 or 0.0) / w0, (ev or 0.0) / v)
    return value, value * rel


def axial_inertia_table(modes: list, n_bp: int, length_A: float, temperature_K: float,
                        references: dict, units: Units | None = None) -> dict:
    """Every measured twist and stretch mode's kinetic inertia (axial_inertia) over each
    reference material's (name -> UniformMaterial: its I33, rho), and per kind the weighted
    mean over the modes with its standard error and the chi^2 of the modes about it (a
    chi^2 / dof well above 1 says the modes do not share one inertia), each over the
    references too."""
    out = {}
    for kind, name in AXIAL_INERTIA.items():
        ref_value = {ref: float(np.asarray(mat.I)[2, 2]) if kind == "twist" else float(mat.rho)
                     for ref, mat in references.items()}

        def over_references(v, err):
            return {key: x for ref, r in ref_value.items()
                    for key, x in ((f"over_{ref}", v / r), (f"over_{ref}_err", err / r))}
        rows = []
        for e in modes:
            if e["kind"] != kind:
                continue
            v, err = axial_inertia(e, n_bp, length_A, temperature_K, units)
            if v is not None:
                rows.append({"n": int(e["n"]), f"{name}_rod_units": v, f"{name}_err_rod_units": err,
                             **over_references(v, err)})
        pooled = None
        if len(rows) >= 2:
            x = np.array([r[f"{name}_rod_units"] for r in rows])
            w = np.array([r[f"{name}_err_rod_units"] for r in rows]) ** -2.0
            mean, err = float((w * x).sum() / w.sum()), float(w.sum() ** -0.5)
            pooled = {f"{name}_rod_units": mean, f"{name}_err_rod_units": err, **over_references(mean, err),
                      "chi2": float((w * (x - mean) ** 2).sum()), "dof": len(rows) - 1}
        out[kind] = {"modes": rows, "pooled": pooled}
    return out


# -- the prediction ------------------------------------------------------------------------
def predict(mat: UniformMaterial, duplex: Duplex, tension_pN: float, tension_err_pN: float = 0.0,
            replicas=(), n_max: int = 14, units: Units | None = None) -> dict:
    """Every mode's predicted frequency with its error (module doc): {"tension_pN",
    "tension_err_pN", "replicas_used", "replicas_unstable", "state" (rest_state), "modes":
    [{kind, n, omega_per_ps, omega_err_per_ps, omega_err_material_per_ps,
    omega_err_tension_per_ps, omega_min_per_ps, omega_max_per_ps}]}. replicas:
    UniformMaterials (None entries, refused replicas, are skipped; a replica whose rod is
    unstable at this tension is counted in replicas_unstable)."""
    if not (math.isfinite(tension_pN) and math.isfinite(tension_err_pN) and tension_err_pN >= 0):
        raise InputError(f"tension {tension_pN} +- {tension_err_pN} pN: need finite numbers, error >= 0")
    try:
        central = frequencies(mat, duplex, tension_pN, n_max, units)
        side = [frequencies(mat, duplex, tension_pN + s * tension_err_pN, n_max, units)
                for s in (1, -1)] if tension_err_pN > 0 else None
    except NumericalError as e:
        raise NumericalError(f"the straight rod is unstable between {tension_pN - tension_err_pN:.3g} and "
                             f"{tension_pN + tension_err_pN:.3g} pN (it buckles under a compression beyond Euler's "
                             f"load, or a torque beyond Greenhill's): {e}") from None
    reps, unstable = [], 0
    for r in replicas:
        if r is None:
            continue
        try:
            reps.append(frequencies(r, duplex, tension_pN, n_max, units))
        except NumericalError:      # a replicate whose rod buckles at this tension
            unstable += 1
    modes = []
    for kind in KINDS:
        for n in range(1, n_max + 1):
            if n not in central[kind]:
                continue
            w, w_lo, w_hi = central[kind][n]
            e_T = 0.5 * abs(side[0][kind][n][0] - side[1][kind][n][0]) if side else 0.0
            vals = np.array([r[kind][n][0] for r in reps if n in r[kind]])
            e_mat = float(spread(vals)) if len(vals) > 1 else 0.0
            modes.append({"kind": kind, "n": n, "omega_per_ps": w, "omega_err_per_ps": math.hypot(e_T, e_mat),
                          "omega_err_material_per_ps": e_mat if len(vals) > 1 else None,
                          "omega_err_tension_per_ps": e_T, "omega_min_per_ps": w_lo, "omega_max_per_ps": w_hi})
    return {"tension_pN": tension_pN, "tension_err_pN": tension_err_pN, "replicas_used": len(reps),
            "replicas_unstable": unstable, "n_bp": duplex.n_bp, "turns": duplex.turns,
            "state": rest_state(mat, duplex, tension_pN, units), "modes": modes}


def md_natural_frequency(entry: dict) -> tuple:
    """(omega0, its error) [rad/ps] of a measured mode (an entry of modes.json["modes"]): the
    undamped frequency sqrt(omega^2 + gamma^2) of the fitted damped oscillator, the one a rod
    without friction has; its error from those of omega and gamma (None when refused)."""
    w, g = entry.get("omega_per_ps"), entry.get("damping_per_ps")
    if w is None:
        return None, None
    g = g or 0.0
    w0 = math.hypot(w, g)
    ew, eg = entry.get("omega_err_per_ps"), entry.get("damping_err_per_ps")
    if ew is None:
        return w0, None
    return w0, math.hypot(w / w0 * ew, g / w0 * (eg or 0.0))


def z_score(a, ea, b, eb):
    """(a - b) / sqrt(ea^2 + eb^2), None when a number or both errors are missing."""
    if a is None or b is None:
        return None
    e = math.hypot(ea or 0.0, eb or 0.0)
    return (a - b) / e if e > 0 else None


def compare(md_modes: list, predictions: dict) -> list:
    """One row per MD mode (modes.json["modes"]): the MD's undamped frequency omega0 and its
    error (md_natural_frequency; None with the MD's reason when refused), each prediction's
    (name -> predict() output) omega and error, and z = (MD - rod) / sqrt(err_MD^2 + err_rod^2)."""
    pred = {name: {(m["kind"], m["n"]): m for m in p["modes"]} for name, p in predictions.items()}
    rows = []
    for e in md_modes:
        key = (e["kind"], int(e["n"]))
        w0, e0 = md_natural_frequency(e)
        row = {"kind": e["kind"], "n": int(e["n"]), "k_per_A": e.get("k_per_A"),
               "md_omega0_per_ps": w0, "md_omega0_err_per_ps": e0, "md_reason": e.get("reason")}
        for name, p in pred.items():
            r = p.get(key)
            row[f"{name}_omega_per_ps"] = r["omega_per_ps"] if r else None
            row[f"{name}_omega_err_per_ps"] = r["omega_err_per_ps"] if r else None
            row[f"z_{name}"] = z_score(w0, e0, row[f"{name}_omega_per_ps"], row[f"{name}_omega_err_per_ps"]) \
                if r else None
        rows.append(row)
    return rows


# -- T and B from the MD's own modes -------------------------------------------------------
def _least_squares(model, y, err, x0, steps, max_iter: int = 40):
    """Weighted least squares of model(x) to y +- err: Gauss-Newton steps with central-difference
    Jacobians of `steps`, damped (Levenberg-Marquardt) whenever a step would raise chi^2;
    (x, covariance, chi2). NumericalError when it does not converge or the data do not fix x
    (a singular normal matrix), or the model fails on the way (e.g. a buckled rod)."""
    y, err = np.asarray(y, float), np.asarray(err, float)

    def chi2_at(x):
        r = (y - model(x)) / err
        return float(r @ r), r

    def jac(x):
        J = np.empty((len(y), len(x)))
        for i, h in enumerate(steps):
            d = np.zeros(len(x))
            d[i] = h
            J[:, i] = (model(x + d) - model(x - d)) / (2 * h)
        return J / err[:, None]

    x = np.array(x0, float)
    chi2, r = chi2_at(x)
    lam = 0.0
    for _ in range(max_iter):
        J = jac(x)
        A, g = J.T @ J, J.T @ r
        while True:
            try:
                dx = np.linalg.solve(A + lam * np.diag(np.diag(A)), g)
            except np.linalg.LinAlgError:
                raise NumericalError(f"the data do not fix the parameters (singular normal matrix at {x})") from None
            try:
                new, r_new = chi2_at(x + dx)
            except NumericalError as e:
                new, r_new, why = math.inf, r, e
            if new <= chi2 or lam > 1e8:
                break
            lam = max(1e-3, 10 * lam)
        if new > chi2:
            raise NumericalError(f"the fit is stuck at {x} (chi2 {chi2:.3g}): no step lowers it"
                                 + (f" ({why})" if new == math.inf else ""))
        x, chi2, r, lam = x + dx, new, r_new, lam / 10 if lam > 1e-3 else 0.0
        if np.all(np.abs(dx) < 1e-6 * np.maximum(1.0, np.abs(x))):
            break
    else:
        raise NumericalError(f"the fit did not converge in {max_iter} iterations (last step {dx})")
    J = jac(x)
    try:
        cov = np.linalg.inv(J.T @ J)
    except np.linalg.LinAlgError:
        raise NumericalError(f"the data do not fix the parameters (singular normal matrix at {x})") from None
    return x, cov, chi2


def fit_tension_bend(ns, values, errors, template: UniformMaterial, duplex: Duplex, observable: str = "omega",
                     tension0_pN: float = 5.0, units: Units | None = None) -> dict:
    """T [pN] and B [pN nm^2] of the rod that reproduces the measured bend `values` +- `errors`
    of lab modes `ns`: frequencies [rad/ps] (observable "omega") or static variances [A^2]
    ("variance"), with the template's every other constant (module doc).
    Returns T, B, their errors and correlation, the persistence length, chi2 and dof."""
    u = units or Units.paper()
    ns = [int(n) for n in ns]
    if len(ns) < 2:
        raise InputError(f"fitting T and B needs at least 2 bend modes; got {len(ns)} ({ns})")
    if observable not in ("omega", "variance"):
        raise InputError(f"observable {observable!r}: 'omega' or 'variance'")
    B0 = bend_stiffness_pN_nm2(template, u)

    def model(x):
        if abs(x[1]) > LN_BEND_SCALE_MAX:
            raise NumericalError(f"B runs to {math.exp(x[1]):.3g} x the template's (the fit's range: 1/1000 to "
                                 "1000 x): the measured values are not those of a bending rod")
        mat = scaled_bend(template, math.exp(x[1]))
        if observable == "omega":
            return bend_frequencies(mat, duplex, x[0], ns, u)
        return bend_variances_A2(mat, duplex, x[0], ns, u)

    x, cov, chi2 = _least_squares(model, values, errors, [tension0_pN, 0.0], [TENSION_STEP_PN, BEND_SCALE_STEP])
    T, b = float(x[0]), math.exp(x[1])
    B = B0 * b
    T_err, lnb_err = math.sqrt(cov[0, 0]), math.sqrt(cov[1, 1])
    dof = len(ns) - 2
    return {"observable": observable, "n": ns, "tension_pN": T, "tension_err_pN": T_err,
            "B_pN_nm2": B, "B_err_pN_nm2": B * lnb_err,
            "persistence_length_nm": persistence_nm(B, duplex.temperature_K),
            "persistence_length_err_nm": persistence_nm(B, duplex.temperature_K) * lnb_err,
            "correlation_T_B": float(cov[0, 1] / (T_err * lnb_err)), "chi2": chi2, "dof": dof,
            "bend_scale_of_template": b, "template_B_pN_nm2": B0,
            "model": [float(v) for v in model(x)]}
