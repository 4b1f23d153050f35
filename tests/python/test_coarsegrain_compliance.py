"""The rod's K is the duplex's long-wavelength stiffness: compliances in series, couplings
between steps included (mdbridge/coarsegrain/qstiffness.py).

Truths, each independent of the estimator:
* steps in series: the compliance of n independent steps adds, so the uniform rod with their
  long-wavelength response has K = (mean_j F_j^-1)^-1 (Olson et al. 1998's dimer tables,
  tests/data/olson1998/); the arithmetic mean of the F_j is the control that must fail;
* nearest-neighbour coupling: a periodic Gaussian chain with energy
  sum_j x_j.A.x_j / 2 + x_j.B.x_{j+1} has the exact compliance spectrum
  S(q) = (A + B e^{iq} + B^T e^{-iq})^-1, so K(q -> 0) = A + B + B^T, while the per-step
  compliance average (mean over q of S)^-1 differs (the control);
* a fixed box: a ring whose sum of rises is held exactly has, for n independent steps, the
  per-step rise covariance (n - 1) / n of the free one; leaving out q = 0 removes that bias;
* the isotropic view against the linearised rod (mdbridge/rod/linear.py, rodcore's own RHS):
  a fast-twisting anisotropic rod's lowest bend mode is Eq 39 with compliance-averaged bend
  and shear; stiffness averaging (the control) misses it;
* the rod's own constants of the paper's material are the paper's (Sec 2.1 at 300 K).
"""
import math

import numpy as np
import pytest
from scipy import linalg

from cg_truth import UPPER, allowed_beyond_3sigma, olson_tables, per_step, z_scores
from mdbridge.coarsegrain import CoarseGrain, StepEnsemble
from mdbridge.coarsegrain.synthetic import ar1_steps

T_K = 300.0


def _diag(K):
    return np.diagonal(np.asarray(K), axis1=-2, axis2=-1)


@pytest.fixture(scope="module")
def olson_ring():
    """A closed 64-step ring of a random sequence with Olson 1998's dimer means and force
    constants, independent steps, 4000 frames (phi = 0.3)."""
    rng = np.random.default_rng(7)
    seq = "".join(rng.choice(list("ACGT"), 64))
    mean, F = per_step(seq, closed=True)
    q = ar1_steps(mean, F, 4000, 0.3, rng)
    cg = CoarseGrain(StepEnsemble(q, seq, closed=True), T_K, m_values=[1], n_boot=150, seed=3, discard=0).run()
    return cg.results, F


def test_olson_sequence_rod_is_the_series_stiffness(olson_ring):
    """K(q -> 0) and the per-step compliance average return the steps in series (21 upper
    elements each, z-scores within the binomial 3-sigma bound; every diagonal |z| < 3.5)."""
    r, F = olson_ring
    lw = r["long_wavelength"]
    series = np.linalg.inv(np.linalg.inv(F).mean(axis=0))
    for K, err in ((lw["K_q0"], lw["K_q0_err"]), (lw["K_avg_compliance"], lw["K_avg_compliance_err"])):
        z = z_scores(K[UPPER], err[UPPER], series[UPPER])
        assert np.sum(np.abs(z) > 3) <= allowed_beyond_3sigma(21), z
        assert np.all(np.abs(_diag(z_scores(K, err, series))) < 3.5)
    # the stated errors resolve the difference between the two averages
    arith = F.mean(axis=0)
    assert np.all(_diag(lw["K_q0_err"]) < 0.05 * _diag(series))
    assert np.all(_diag(arith) / _diag(series) > 1.15), _diag(arith) / _diag(series)


def test_control_arithmetic_mean_of_stiffness_fails(olson_ring):
    """Must fail the test above: the arithmetic mean of Olson's per-step stiffness is 1.2-1.6x
    the series stiffness, many stated errors away on every diagonal element."""
    r, F = olson_ring
    lw = r["long_wavelength"]
    z = _diag(z_scores(lw["K_q0"], lw["K_q0_err"], F.mean(axis=0)))
    assert np.all(np.abs(z) > 5), z
    z = _diag(z_scores(lw["K_avg_compliance"], lw["K_avg_compliance_err"], F.mean(axis=0)))
    assert np.all(np.abs(z) > 5), z


# -- nearest-neighbour coupling ------------------------------------------------------
N_NN = 64
BETA = np.array([-0.15, -0.1, -0.15, -0.1, -0.15, 0.2])   # per eigen-direction of A; |beta| < 1/2


def _coupled_chain():
    """A (6, 6) per-step block, B (6, 6) coupling, and the exact K(q -> 0) and spectrum."""
    _, F = olson_tables()
    A = F["GC"]
    Ah = linalg.sqrtm(A).real
    B = Ah @ np.diag(BETA) @ Ah
    return A, B


def _coupled_ensemble(A, B, n_frames, phi, rng):
    """(T, N_NN, 6) deviations of the periodic chain with precision blocks A (diagonal) and
    B (j, j + 1), an AR(1) series in time."""
    n6 = 6 * N_NN
    H = np.zeros((n6, n6))
    for j in range(N_NN):
        a, b = 6 * j, 6 * ((j + 1) % N_NN)
        H[a:a + 6, a:a + 6] = A
        H[a:a + 6, b:b + 6] = B
        H[b:b + 6, a:a + 6] = B.T
    L = np.linalg.cholesky(np.linalg.inv(H))
    e = rng.standard_normal((n_frames, n6)) @ L.T
    x = np.empty_like(e)
    x[0] = e[0]
    a = math.sqrt(1 - phi * phi)
    for t in range(1, n_frames):
        x[t] = phi * x[t - 1] + a * e[t]
    return x.reshape(n_frames, N_NN, 6)


@pytest.fixture(scope="module")
def coupled():
    A, B = _coupled_chain()
    mean, _ = olson_tables()
    rng = np.random.default_rng(11)
    q = mean["GC"] + _coupled_ensemble(A, B, 4000, 0.3, rng)
    cg = CoarseGrain(StepEnsemble(q, "GC" * (N_NN // 2), closed=True), T_K, m_values=[1], n_boot=150, seed=5,
                     discard=0).run()
    lw = cg.results["long_wavelength"]
    # exact spectrum and its per-step compliance average over the same (usable) modes
    qk = 2 * np.pi * np.arange(N_NN // 2 + 1) / N_NN
    S = np.linalg.inv(A[None] + B[None] * np.exp(1j * qk)[:, None, None] + B.T[None] * np.exp(-1j * qk)[:, None, None])
    w = np.where(lw["usable"], np.where((qk > 0) & (qk < np.pi), 2.0, 1.0), 0.0)
    K_avg_true = np.linalg.inv(np.einsum("k,kij->ij", w / w.sum(), S.real))
    return lw, A + B + B.T, K_avg_true


def test_coupled_chain_long_wavelength_stiffness(coupled):
    """K(q -> 0) returns A + B + B^T, the stiffness of the longest waves (21 upper elements,
    binomial 3-sigma bound; diagonal |z| < 3.5); the per-step compliance average returns its
    own exact value (mean of the exact spectrum over the usable modes)."""
    lw, K0_true, K_avg_true = coupled
    z = z_scores(lw["K_q0"][UPPER], lw["K_q0_err"][UPPER], K0_true[UPPER])
    assert np.sum(np.abs(z) > 3) <= allowed_beyond_3sigma(21), z
    assert np.all(np.abs(_diag(z_scores(lw["K_q0"], lw["K_q0_err"], K0_true))) < 3.5)
    za = _diag(z_scores(lw["K_avg_compliance"], lw["K_avg_compliance_err"], K_avg_true))
    assert np.all(np.abs(za) < 3.5), za


def test_control_compliance_average_misses_the_coupling(coupled):
    """Must fail the test above: the per-step compliance average is not the long-wavelength
    stiffness of a coupled chain (0.75-1.3x it here): many stated errors away on every
    diagonal element but shift's, and K(q -> 0) is far from the compliance average's value."""
    lw, K0_true, K_avg_true = coupled
    ratio = _diag(K_avg_true) / _diag(K0_true)
    assert np.all(np.abs(ratio - 1) > 0.1), ratio
    z = _diag(z_scores(lw["K_avg_compliance"], lw["K_avg_compliance_err"], K0_true))
    assert np.sum(np.abs(z) > 5) >= 5, z
    z = _diag(z_scores(lw["K_q0"], lw["K_q0_err"], K_avg_true))
    assert np.sum(np.abs(z) > 3) >= 4, z


# -- the fixed box -----------------------------------------------------------------
def test_fixed_box_leaves_the_long_wavelength_stiffness_unbiased():
    """A 21-step ring of independent Olson steps whose sum of rises is held exactly (the
    conditional Gaussian of the free ring): its per-step rise covariance is (n - 1) / n of
    the free one, so the inverse of the plain mean per-step covariance is 5 % stiff in rise
    (the control, measured here to fail by > 3 errors), and not 1.5x. K(q -> 0) and the
    compliance average, which leave q = 0 out, return the free ring's series stiffness."""
    rng = np.random.default_rng(21)
    seq = "ACGTTGCAAGCTTCGAGCATG"
    n = len(seq)
    mean, F = per_step(seq, closed=True)
    x = ar1_steps(np.zeros_like(mean), F, 5000, 0.0, rng).reshape(5000, 6 * n)
    Sigma = linalg.block_diag(*np.linalg.inv(F))
    c = np.zeros(6 * n)
    c[2::6] = 1.0                                                 # the sum of the rises
    P = np.eye(6 * n) - np.outer(Sigma @ c, c) / (c @ Sigma @ c)
    q = mean + (x @ P.T).reshape(5000, n, 6)
    assert np.abs(q[..., 2].sum(axis=1) - mean[:, 2].sum()).max() < 1e-9
    cg = CoarseGrain(StepEnsemble(q, seq, closed=True), T_K, m_values=[1], n_boot=150, seed=2, discard=0).run()
    lw = cg.results["long_wavelength"]
    series = np.linalg.inv(np.linalg.inv(F).mean(axis=0))
    for K, err in ((lw["K_q0"], lw["K_q0_err"]), (lw["K_avg_compliance"], lw["K_avg_compliance_err"])):
        assert np.all(np.abs(_diag(z_scores(K, err, series))) < 3.5)
    d = q - q.mean(axis=0)
    naive = np.linalg.inv(np.einsum("tni,tnj->ij", d, d) / (len(q) - 1) / n)
    assert naive[2, 2] / series[2, 2] == pytest.approx(n / (n - 1), abs=0.015)
    assert (naive[2, 2] - series[2, 2]) / lw["K_avg_compliance_err"][2, 2] > 3


# -- the isotropic view and the rod's constants ------------------------------------
def test_isotropic_view_is_the_fast_twisting_rods_bend_mode():
    """A 158-bp rod, 15 turns, bend stiffness 0.9 and 1.5, shear 0.7 and 1.3, a twist-bend
    coupling: Eq 39 through isotropic_view (compliances averaged) equals the lowest bend mode
    of the linearised rod (rodcore's RHS) within 0.3 %; the stiffness average (the control)
    is off by more than 1 %."""
    from dna_models.units import Units
    from mdbridge.analysis.dispersion import lab_speed_material_A_per_ps
    from mdbridge.coarsegrain.cgrod import eq39_speed, isotropic_view
    from mdbridge.rod.linear import LinearRod, UniformMaterial, dispersion
    u = Units.paper()
    L = 158 * u.length_to_rod(u.rise_A)
    K = np.diag([0.7, 1.3, 1.19, 0.9, 1.5, 2.02])
    K[4, 5] = K[5, 4] = 0.3
    mat = {"K_star": K, "I_star": np.diag([1.0, 1.0, 2.0]), "rho_star": 1.0}
    rod = UniformMaterial(K=K, I=np.diag([1.0, 1.0, 2.0]), rho=1.0, Gamma0=np.array([0.0, 0.0, 1.0]),
                          Omega0=np.array([0.0, 0.0, 2 * np.pi * 15 / L]))
    w = dispersion(LinearRod(rod, L, 158).modes(1), "bend")[1]["omega"]
    c_rod = u.velocity_to_A_per_ps(w / (2 * np.pi / L))
    assert eq39_speed(mat, L) == pytest.approx(c_rod, rel=3e-3)
    v = isotropic_view(mat)
    Kinv = np.linalg.inv(K)
    assert v["D1"] == pytest.approx(2 / (Kinv[3, 3] + Kinv[4, 4]), rel=1e-12)
    stiff = lab_speed_material_A_per_ps(L, 0.5 * (K[0, 0] + K[1, 1]), 0.5 * (K[3, 3] + K[4, 4]), 1.0, 1.0)
    assert abs(stiff / c_rod - 1) > 1e-2


def test_rod_constants_of_the_paper_material_are_the_papers():
    """The paper's rod at 300 K: bend persistence D / kT = 66.4 nm, torsional modulus
    D3 = 1.67 D = 459 pN nm^2, stretch modulus C3 = 1.19 C = 1080.5 pN (Sec 2.1 quotes
    1087 pN, which the solver's C3* = 1.19 rounds), no twist-stretch coupling."""
    from dna_models.units import Units
    from mdbridge.coarsegrain.cgrod import rod_constants
    u = Units.paper()
    c = rod_constants(np.diag([*u.C_star, *u.D_star]), 300.0, u)
    assert c["bend_persistence_length"] == pytest.approx(66.4, abs=0.1)
    assert c["torsional_modulus"] == pytest.approx(459, abs=1)
    assert c["stretch_modulus"] == pytest.approx(1080.5, abs=0.5)
    assert c["twist_stretch_coupling"] == 0.0
