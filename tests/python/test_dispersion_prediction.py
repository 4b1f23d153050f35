"""The rod's predicted mode spectrum and the T/B fit (mdbridge/analysis/dispersion_prediction.py)
against things known independently of them: Eq 26 and the twist and stretch wave speeds of
the paper rod, the linear rod of mdbridge/rod/linear.py for a coupled anisotropic material,
the string-beam in its limit (inextensible, unshearable, no rotary inertia), Timoshenko's
static compliance, masses dropping out of a static variance, the z-scores of fits to
synthetic noisy frequencies (sampling theory), and the kinetic inertia of an axial mode
written in SI from the continuum rod's equipartition, with controls that must fail. ~40 s."""
import math

import numpy as np
import pytest

from dna_models.errors import InputError
from dna_models.units import BOLTZMANN, Units
from mdbridge.analysis.dispersion_prediction import (Duplex, axial_inertia, axial_inertia_table, bend_frequencies,
                                                     bend_stiffness_pN_nm2, bend_variances_A2, compare,
                                                     fit_tension_bend, frequencies, paper_material, predict,
                                                     scaled_bend)
from mdbridge.rod.linear import UniformMaterial, dna_dispersion
from mdbridge.stats import spread

U = Units.paper()
DUPLEX = Duplex(158, 15, 300.0)
L_M = 158 * U.rise_A * 1e-10
KT = BOLTZMANN * 300.0


def coupled_material() -> UniformMaterial:
    """A coarse-grained-like material: anisotropic bend, twist-stretch and shear couplings,
    a full inertia, 616 Da/bp-like density, the duplex's intrinsic twist."""
    rng = np.random.default_rng(7)
    M = rng.normal(size=(6, 6)) * 0.08
    K = np.diag([0.9, 1.1, 1.3, 0.85, 1.05, 1.7]) + M @ M.T
    I = np.array([[0.9, 0.03, 0.0], [0.03, 1.1, 0.01], [0.0, 0.01, 1.9]])
    O3 = 2 * np.pi * 15 / DUPLEX.fiducial_length(U)
    return UniformMaterial(K=K, I=I, rho=0.94, Gamma0=np.array([0.0, 0.0, 0.99]), Omega0=np.array([0.0, 0.0, O3]))


def eq26(n):
    import rodcore
    q = 2 * np.pi * n / DUPLEX.fiducial_length(U)
    return U.angular_velocity_to_rad_per_ps(rodcore.analytic.dispersion(q, U.D_star[0], 1.0, -1))


def test_paper_rod_at_zero_tension_is_eq26_and_the_wave_speeds():
    p = predict(paper_material(DUPLEX), DUPLEX, 0.0)
    got = {(m["kind"], m["n"]): m["omega_per_ps"] for m in p["modes"]}
    assert len(got) == 3 * 14
    for n in range(1, 15):
        q = 2 * np.pi * n / DUPLEX.fiducial_length(U)
        assert got["bend", n] == pytest.approx(eq26(n), rel=1e-9)
        assert got["twist", n] == pytest.approx(U.angular_velocity_to_rad_per_ps(
            math.sqrt(U.D_star[2] / U.I_star[2]) * q), rel=1e-9)
        assert got["stretch", n] == pytest.approx(U.angular_velocity_to_rad_per_ps(math.sqrt(U.C_star[2]) * q),
                                                  rel=1e-9)
    assert all(m["omega_err_per_ps"] == 0 for m in p["modes"])


def test_prediction_of_a_coupled_material_is_the_linear_rod_with_its_errors():
    """Central values are linear.py's dna_dispersion; the material error is the spread over
    the replicas' dna_dispersion; the tension error is half the difference at T +- dT, and at
    n = 1 it is the string-beam's d ln omega / dT = 1 / (2 (T + B k^2)) to the shear term."""
    mat = coupled_material()
    reps = [scaled_bend(mat, b) for b in (0.9, 0.95, 1.0, 1.05, 1.1, 0.97, 1.02)]
    p = predict(mat, DUPLEX, 5.0, 0.3, reps + [None])
    assert p["replicas_used"] == 7
    ref = dna_dispersion(mat, 158, 15, 5.0)
    hi, lo = dna_dispersion(mat, 158, 15, 5.3), dna_dispersion(mat, 158, 15, 4.7)
    rep = [dna_dispersion(r, 158, 15, 5.0) for r in reps]
    for m in p["modes"]:
        k, n = m["kind"], m["n"]
        assert m["omega_per_ps"] == pytest.approx(ref[k][n]["omega_per_ps"], rel=1e-12)
        assert m["omega_err_tension_per_ps"] == pytest.approx(
            0.5 * abs(hi[k][n]["omega_per_ps"] - lo[k][n]["omega_per_ps"]), rel=1e-9, abs=1e-15)
        e_mat = spread(np.array([r[k][n]["omega_per_ps"] for r in rep]))
        assert m["omega_err_material_per_ps"] == pytest.approx(e_mat, rel=1e-9, abs=1e-15)
        assert m["omega_err_per_ps"] == pytest.approx(math.hypot(e_mat, m["omega_err_tension_per_ps"]), rel=1e-12)
    # the subset evaluation of the fit is the full one
    ns = [1, 2, 3, 4, 9, 14]
    assert np.allclose(bend_frequencies(mat, DUPLEX, 5.0, ns), [ref["bend"][n]["omega_per_ps"] for n in ns],
                       rtol=1e-12)
    # n = 1 moves by the string-beam's rate (the paper rod: ~6 % per pN at 5 pN)
    pp = predict(paper_material(DUPLEX), DUPLEX, 5.0, 0.01)
    b1 = next(m for m in pp["modes"] if (m["kind"], m["n"]) == ("bend", 1))
    k = 2 * np.pi / (L_M * 1e9)
    rate = 1 / (2 * (5.0 + bend_stiffness_pN_nm2(paper_material(DUPLEX)) * k ** 2))
    assert b1["omega_err_tension_per_ps"] / b1["omega_per_ps"] / 0.01 == pytest.approx(rate, rel=0.02)
    assert 0.05 < rate < 0.07
    # control: the same material at zero tension is far off (the tension enters)
    p0 = frequencies(mat, DUPLEX, 0.0, 3)
    assert abs(p0["bend"][1][0] / ref["bend"][1]["omega_per_ps"] - 1) > 0.2


def _string_beam_limit(mat):
    """Inextensible, unshearable, no rotary inertia: the material's shear and stretch x 1e4,
    I x 1e-4 (the string-beam's assumptions)."""
    K = np.array(mat.K, float)
    for i in (0, 1, 2):
        K[i, i] *= 1e4
    return UniformMaterial(K=K, I=np.asarray(mat.I) * 1e-4, rho=mat.rho, Gamma0=mat.Gamma0, Omega0=mat.Omega0)


@pytest.mark.parametrize("T", [0.0, 5.0, 20.0])
def test_string_beam_limit_frequencies_and_variances(T):
    """mu omega^2 = B k^4 + T k^2 and <|c_n|^2> = 4 kT / ((B k^4 + T k^2) L) in the limit the
    formula assumes; the paper rod (shear, extension, inertia) departs from both (control)."""
    paper = paper_material(DUPLEX)
    mat = _string_beam_limit(paper)
    ns = [1, 2, 4, 8, 12]
    B = bend_stiffness_pN_nm2(paper) * 1e-30
    mu = U.rho * paper.rho
    k = 2 * np.pi * np.array(ns) / L_M
    stiff = B * k ** 4 + T * 1e-12 * k ** 2
    w = bend_frequencies(mat, DUPLEX, T, ns) * 1e12
    v = bend_variances_A2(mat, DUPLEX, T, ns) * 1e-20
    assert np.allclose(w, np.sqrt(stiff / mu), rtol=1e-4)
    assert np.allclose(v, 4 * KT / (stiff * L_M), rtol=1e-4)
    wp = bend_frequencies(paper, DUPLEX, T, ns) * 1e12
    assert abs(wp[-1] / np.sqrt(stiff[-1] / mu) - 1) > 0.1


def test_static_variance_is_timoshenko_and_does_not_see_the_masses():
    """At zero tension a shearable beam's compliances add: <|c_n|^2> = (4 kT / L)(1 / (B k^4)
    + 1 / (C k^2)) exactly; the static variance depends on the potential only, so scaling rho
    and I changes the frequencies and not the variances."""
    paper = paper_material(DUPLEX)
    ns = [1, 2, 4, 8, 12]
    B = bend_stiffness_pN_nm2(paper) * 1e-30
    C = U.stiffness_to_SI(paper.K)[0, 0]
    k = 2 * np.pi * np.array(ns) / L_M
    v = bend_variances_A2(paper, DUPLEX, 0.0, ns) * 1e-20
    assert np.allclose(v, 4 * KT / L_M * (1 / (B * k ** 4) + 1 / (C * k ** 2)), rtol=1e-10)
    assert abs(v[-1] / (4 * KT / (L_M * B * k[-1] ** 4)) - 1) > 0.1      # Euler-Bernoulli misses it
    mat = coupled_material()
    heavy = UniformMaterial(K=mat.K, I=np.asarray(mat.I) * 0.3, rho=mat.rho * 2.5, Gamma0=mat.Gamma0,
                            Omega0=mat.Omega0)
    assert np.allclose(bend_variances_A2(heavy, DUPLEX, 5.0, ns), bend_variances_A2(mat, DUPLEX, 5.0, ns),
                       rtol=1e-10)
    assert not np.allclose(bend_frequencies(heavy, DUPLEX, 5.0, ns), bend_frequencies(mat, DUPLEX, 5.0, ns),
                           rtol=0.1)


# stated relative errors of the lowest bend frequencies of a 4-ns record (docs/modes.md's
# calibration: periods 1100, 375, 187, 111 ps)
NS = [1, 2, 3, 4]
REL = np.array([0.06, 0.035, 0.02, 0.01])


def _euler_bernoulli_fit(w, err, rho):
    """The string-beam formula's T and B by weighted linear least squares of
    mu omega^2 / k^2 = T + B k^2 (the control: no shear, no rotary inertia)."""
    k = 2 * np.pi * np.array(NS) / L_M
    mu = U.rho * rho
    y = mu * (w * 1e12) ** 2 / k ** 2 * 1e12           # pN
    ey = 2 * y * err / w
    A = np.stack([np.ones(len(NS)), k ** 2 * 1e-18], axis=1) / ey[:, None]
    x = np.linalg.lstsq(A, y / ey, rcond=None)[0]
    cov = np.linalg.inv(A.T @ A)
    return x, np.sqrt(np.diag(cov))


def test_fit_recovers_T_and_B_with_calibrated_errors():
    """Frequencies of the coupled material's rod at T = 5 pN, B scaled by 0.7, with Gaussian
    noise at the stated errors, 40 realisations: the fit with the template's other constants
    gives z = (fit - truth) / error ~ N(0, 1) for T and B. Controls that must fail: the
    Euler-Bernoulli formula on the same data (B biased by several errors), and the fit
    told errors half the real ones (z scatter ~2)."""
    template = coupled_material()
    truth = scaled_bend(template, 0.7)
    T_true, B_true = 5.0, bend_stiffness_pN_nm2(truth)
    w_true = bend_frequencies(truth, DUPLEX, T_true, NS)
    rng = np.random.default_rng(11)
    z, z_eb, z_half = [], [], []
    for _ in range(40):
        err = REL * w_true
        w = w_true + err * rng.standard_normal(len(NS))
        f = fit_tension_bend(NS, w, err, template, DUPLEX)
        z.append(((f["tension_pN"] - T_true) / f["tension_err_pN"], (f["B_pN_nm2"] - B_true) / f["B_err_pN_nm2"]))
        x, e = _euler_bernoulli_fit(w, err, template.rho)
        z_eb.append((x[1] - B_true) / e[1])
        if len(z_half) < 5:
            h = fit_tension_bend(NS, w, err / 2, template, DUPLEX)
            z_half.append((h["B_pN_nm2"] - B_true) / h["B_err_pN_nm2"])
    z = np.array(z)
    # 40 samples: the mean of N(0, 1) within 3 / sqrt(40) = 0.47, its sd within ~+-0.35
    assert np.all(np.abs(z.mean(axis=0)) < 0.47), z.mean(axis=0)
    assert np.all((0.7 < z.std(axis=0)) & (z.std(axis=0) < 1.35)), z.std(axis=0)
    assert abs(np.mean(z_eb)) > 2.0, np.mean(z_eb)
    # the same estimates, errors halved: z doubles (checked on 5, then it is arithmetic)
    assert np.allclose(z_half, 2 * z[:5, 1], rtol=1e-3)
    assert np.std(2 * z[:, 1]) > 1.5, np.std(2 * z[:, 1])


def test_variance_fit_returns_the_material_and_refuses_one_mode():
    template = coupled_material()
    truth = scaled_bend(template, 1.3)
    v = bend_variances_A2(truth, DUPLEX, 3.0, NS)
    f = fit_tension_bend(NS, v, 0.05 * v, template, DUPLEX, observable="variance")
    assert f["tension_pN"] == pytest.approx(3.0, abs=1e-6)
    assert f["B_pN_nm2"] == pytest.approx(bend_stiffness_pN_nm2(truth), rel=1e-7)
    assert f["chi2"] < 1e-12 and f["dof"] == 2
    with pytest.raises(InputError, match="at least 2 bend modes"):
        fit_tension_bend([2], v[:1], v[:1], template, DUPLEX)


def test_compare_rows_and_z():
    p = predict(paper_material(DUPLEX), DUPLEX, 5.0, 0.5)
    b3 = next(m for m in p["modes"] if (m["kind"], m["n"]) == ("bend", 3))
    md = [{"kind": "bend", "n": 3, "k_per_A": 0.035, "omega_per_ps": b3["omega_per_ps"] * 1.1,
           "omega_err_per_ps": 0.001, "damping_per_ps": 0.0, "damping_err_per_ps": 0.0001, "reason": None},
          {"kind": "bend", "n": 1, "k_per_A": 0.012, "omega_per_ps": None, "omega_err_per_ps": None,
           "reason": "fewer than 3 periods"}]
    rows = compare(md, {"paper_rod": p})
    z = (b3["omega_per_ps"] * 0.1) / math.hypot(0.001, b3["omega_err_per_ps"])
    assert rows[0]["z_paper_rod"] == pytest.approx(z, rel=1e-12)
    assert rows[1]["z_paper_rod"] is None and rows[1]["md_reason"] == "fewer than 3 periods"
    assert rows[1]["paper_rod_omega_per_ps"] is not None
    # a damped mode is compared by its undamped frequency sqrt(omega^2 + gamma^2)
    md[0].update(damping_per_ps=0.5 * md[0]["omega_per_ps"], damping_err_per_ps=0.002)
    r = compare(md[:1], {"paper_rod": p})[0]
    assert r["md_omega0_per_ps"] == pytest.approx(md[0]["omega_per_ps"] * math.sqrt(1.25), rel=1e-12)
    assert r["md_omega0_err_per_ps"] == pytest.approx(math.hypot(0.001, 0.5 * 0.002) / math.sqrt(1.25), rel=1e-12)


@pytest.mark.parametrize("kind,n", [("twist", 1), ("twist", 6), ("stretch", 3), ("stretch", 14)])
def test_axial_inertia_of_an_equipartitioned_mode_is_the_rods(kind, n):
    """A twist (stretch) mode of the paper's continuum rod, written in SI: the node field
    a_n (twist angle, axial displacement) holds <|a_n|^2> = 4 kT / (S k^2 L) (S = D3 or C3:
    potential equipartition), oscillates at omega0 = sqrt(S / I) k (I = I3 or rho) with a
    damping gamma, and the step field the modes see is (e^{ikh} - 1) a_n (/ h for Omega3).
    The inertia comes back as the paper's in rod units (2, 1); the damped frequency in its
    place (the control) does not."""
    L = 158 * U.rise_A * 1e-10
    h, k = L / 158, 2 * np.pi * n / L
    S, I = ((U.D * U.D_ratios[2], U.I * U.I_ratios[2]) if kind == "twist" else (U.C * U.C_ratios[2], U.rho))
    w0 = math.sqrt(S / I) * k * 1e-12                        # rad/ps
    gamma = 0.4 * w0
    step = 2 * math.sin(k * h / 2) / (h if kind == "twist" else 1.0)
    var = step ** 2 * 4 * KT / (S * k ** 2 * L) * (1e-20 if kind == "twist" else 1e20)   # rad^2/A^2, A^2
    entry = {"kind": kind, "n": n, "omega_per_ps": math.sqrt(w0 ** 2 - gamma ** 2), "omega_err_per_ps": 0.01 * w0,
             "damping_per_ps": gamma, "damping_err_per_ps": 0.0, "oscillator_variance": var,
             "oscillator_variance_err": 0.05 * var}
    value, err = axial_inertia(entry, 158, L * 1e10, 300.0)
    truth = U.I_ratios[2] if kind == "twist" else 1.0      # rod units: I / U.I, rho / U.rho
    assert value == pytest.approx(truth, rel=1e-9)
    # the error: twice omega0's relative error (0.01 omega / omega0) and the variance's, in quadrature
    assert err / value == pytest.approx(math.hypot(2 * 0.01 * entry["omega_per_ps"] / w0, 0.05), rel=1e-9)
    control = dict(entry, damping_per_ps=0.0)               # the damped frequency taken as omega0
    assert axial_inertia(control, 158, L * 1e10, 300.0)[0] / truth == pytest.approx(1 / (1 - 0.16), rel=1e-9)


def test_axial_inertia_refuses_bend_and_passes_over_refused_modes():
    with pytest.raises(InputError, match="bend"):
        axial_inertia({"kind": "bend", "n": 1}, 158, 534.0, 300.0)
    assert axial_inertia({"kind": "twist", "n": 1, "omega_per_ps": None}, 158, 534.0, 300.0) == (None, None)
    # the table pools the modes by weight and counts their chi^2 about the mean
    mat = paper_material(DUPLEX)
    e = {"kind": "twist", "omega_per_ps": 0.1, "omega_err_per_ps": 0.0, "damping_per_ps": 0.0,
         "oscillator_variance_err": 0.0}
    modes = [dict(e, n=1, oscillator_variance=1e-5, oscillator_variance_err=1e-6),
             dict(e, n=1, oscillator_variance=2e-5, oscillator_variance_err=1e-6)]
    t = axial_inertia_table(modes, 158, 534.0, 300.0, {"paper_rod": mat})
    (a, ea), (b, eb) = (axial_inertia(m, 158, 534.0, 300.0) for m in modes)
    w = np.array([ea, eb]) ** -2.0
    pooled = t["twist"]["pooled"]
    assert pooled["I3_rod_units"] == pytest.approx((w[0] * a + w[1] * b) / w.sum(), rel=1e-12)
    assert pooled["chi2"] == pytest.approx((a - b) ** 2 / (ea ** 2 + eb ** 2), rel=1e-9)
    assert t["twist"]["modes"][0]["over_paper_rod"] == pytest.approx(a / 2.0, rel=1e-12)
    assert t["stretch"] == {"modes": [], "pooled": None}
