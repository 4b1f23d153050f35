"""Dispersion relation of the paper (Eqs 25-27, 39, Fig 5) against independent truths:
the defining polynomial, the asymptotic limits stated in Secs 3.1 and 4.1, and the
amplitudes of the exact (Eq 24) and asymptotic (Eqs 40-43) fields that the solver builds."""
import numpy as np
import pytest

from dnarod.paper import theory
from mdbridge.rod.run import run_scene
from mdbridge.rod.scene import new_scene, straight_rod

D1 = 1.21


@pytest.mark.parametrize("D1v,G", [(1.21, 1.0), (2.5, 0.7), (0.6, 1.3)])
def test_both_branches_solve_eq25(D1v, G):
    kappa = np.concatenate([np.logspace(-3, 3, 61), -np.logspace(-2, 2, 9)])
    for b in ("plus", "minus"):
        w = theory.omega(kappa, b, D1v, G)
        scale = np.maximum(w, np.abs(kappa)) ** 4 + G ** 4
        assert np.all(np.abs(theory.dispersion_residual(w, kappa, D1v, G)) / scale < 1e-12)
    assert np.all(theory.omega(kappa, "minus", D1v, G) < theory.omega(kappa, "plus", D1v, G))


def test_long_wave_limits_sec41():
    # omega_+ -> Gamma03 + kappa^2 (D1 + 1) / 2 Gamma03, omega_- -> kappa^2 sqrt(D1) / Gamma03,
    # the next terms are O(kappa^4): halving kappa divides the absolute error by ~16
    for b in ("plus", "minus"):
        k = np.array([0.04, 0.02, 0.01])
        err = np.abs(theory.omega(k, b) - theory.limit_small_kappa(k, b))
        assert np.all(err < 2 * k ** 4)
        assert np.allclose(err[:-1] / err[1:], 16.0, rtol=0.05)


def test_short_wave_limits():
    # k -> infinity: omega_+ ~ sqrt(D1) k (bend), omega_- ~ k (shear), relative error O(1/k^2)
    for b in ("plus", "minus"):
        k = np.array([100.0, 200.0, 400.0])
        err = np.abs(theory.omega(k, b) / theory.limit_large_kappa(k, b) - 1)
        assert err[-1] < 1e-4
        assert np.allclose(err[:-1] / err[1:], 4.0, rtol=0.05)


def test_parabolic_branches_near_k_equal_Omega03():
    # Sec 3.1: kappa_m = k - Omega03 -> 0 gives omega_-^m ~ kappa_m^2 sqrt(D1)/Gamma03 and
    # omega_+^m ~ Gamma03 + kappa_m^2 (D1 + 1)/(2 Gamma03); Gamma03 = 1.3 to catch a missing factor
    O3, G = 1.0, 1.3
    d = np.array([2e-2, 1e-2, 5e-3])
    _, km = theory.modified_wavenumbers(O3 + d, O3)
    wm = theory.omega(km, "minus", D1, G)
    wp = theory.omega(km, "plus", D1, G)
    rel = np.abs(wm / (km ** 2 * np.sqrt(D1) / G) - 1)   # O(kappa_m^2)
    assert rel[0] < 1e-3 and np.allclose(rel[:-1] / rel[1:], 4.0, rtol=0.02)
    assert np.allclose(wp, G + km ** 2 * (D1 + 1) / (2 * G), rtol=1e-6)
    assert theory.omega(0.0, "minus", D1, G) == 0.0
    assert theory.omega(0.0, "plus", D1, G) == pytest.approx(G, rel=1e-15)


def test_python_and_cpp_formulas_agree():
    # The Python entry points (branch names, vectorisation) must hand the C++ formula
    # the right sign: mdbridge.analysis.dispersion.omega_pm and theory.omega.
    import rodcore
    from mdbridge.analysis import dispersion as mod
    k = np.linspace(-5, 5, 41)
    for b, sign in (("plus", 1), ("minus", -1)):
        cpp = np.array([rodcore.analytic.dispersion(float(q), D1, 1.0, sign) for q in k])
        py = np.asarray([float(np.asarray(mod.omega_pm(np.array([q]), D1, 1.0, b)).ravel()[0]) for q in k])
        assert np.allclose(cpp, py, rtol=1e-14, atol=1e-15)
        assert np.allclose(cpp, theory.omega(k, b, D1, 1.0), rtol=1e-14, atol=1e-15)


@pytest.mark.parametrize("kappa_branch", ["p", "m"])
@pytest.mark.parametrize("branch", ["plus", "minus"])
def test_eq27_from_the_eq24_fields(kappa_branch, branch):
    """Eq (27) against Gamma_perp^2 / (D1 Omega_perp^2) of the exact fields built by the
    solver's twisted_wave kind, and against the solver's shear / bend energy parts."""
    k, O3, G = 2.0, 1.0, 1.0
    run = run_scene(new_scene(straight_rod(np.pi, 32, G, O3),
                          {"kind": "twisted_wave", "mode": 1, "A": 0.3, "kappa": kappa_branch, "branch": branch},
                          t_end=1e-3, frames=2))
    Gp = run.fields["Gamma"][0][:, :2]
    Op = run.fields["Omega"][0][:, :2]
    measured = np.sum(Gp ** 2) / (D1 * np.sum(Op ** 2))
    kappa = k + O3 if kappa_branch == "p" else k - O3
    w = theory.omega(kappa, branch)
    assert measured == pytest.approx(float(theory.energy_ratio(w, kappa)), rel=1e-10)
    parts = run.energy_parts
    assert parts["shear"][0] / parts["bend"][0] == pytest.approx(measured, rel=1e-10)


@pytest.mark.parametrize("branch", ["plus", "minus"])
@pytest.mark.parametrize("k", [0.5, 2.0, 8.0])
def test_fig5_ratio_from_the_eq40_43_fields(branch, k):
    run = run_scene(new_scene(straight_rod(2 * np.pi / k, 32),
                          {"kind": "untwisted_wave", "mode": 1, "epsilon": 0.01, "branch": branch},
                          t_end=1e-3, frames=2))
    G1 = run.fields["Gamma"][0][:, 0]
    O2 = run.fields["Omega"][0][:, 1]
    measured = np.sqrt(np.sum(G1 ** 2) / np.sum(O2 ** 2))
    w = theory.omega(k, branch)
    assert measured == pytest.approx(float(theory.shear_bend_amplitude_ratio(w, k)), rel=1e-10)
    # the same statement as Eq 27 at Omega03 = 0
    assert measured ** 2 / D1 == pytest.approx(float(theory.energy_ratio(w, k)), rel=1e-10)
