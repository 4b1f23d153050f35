"""The linearised rod (mdbridge/rod/linear.py) against things known independently of it:
the paper's closed-form dispersion (Eq 26, rodcore/src/analytic.cpp), the wave speeds of
twist and stretch, the whole Jacobian's eigenvalues, the compliance average of a fast-
twisting anisotropic rod, and the string's tension term."""
import numpy as np
import pytest

from dna_models.units import Units
from mdbridge.rod.linear import LinearRod, UniformMaterial, dispersion, dna_dispersion

U = Units.paper()
L158 = 158 * U.length_to_rod(U.rise_A)
OMEGA15 = 2 * np.pi * 15 / L158


def eq26(q):
    import rodcore
    return rodcore.analytic.dispersion(abs(q), U.D_star[0], 1.0, -1)


def test_paper_rod_gives_eq26_twist_and_stretch_waves():
    """The twisted paper rod (158 bp, 15 turns): bend = Eq 26's lower branch at the lab
    wavenumber, twist = sqrt(D3 / I3) q, stretch = sqrt(C3 / rho) q, for n = 1..8."""
    modes = LinearRod(UniformMaterial.paper(OMEGA15), L158, 158).modes(8)
    bend, twist, stretch = (dispersion(modes, k) for k in ("bend", "twist", "stretch"))
    for n in range(1, 9):
        q = 2 * np.pi * n / L158
        assert bend[n]["omega_min"] == pytest.approx(eq26(q), rel=1e-10)
        assert bend[n]["omega_max"] == pytest.approx(eq26(q), rel=1e-10)
        assert bend[n]["count"] == 4        # two handed modes, each travelling either way
        assert twist[n]["omega"] == pytest.approx(np.sqrt(U.D_star[2] / U.I_star[2]) * q, rel=1e-10)
        assert stretch[n]["omega"] == pytest.approx(np.sqrt(U.C_star[2]) * q, rel=1e-10)


def test_the_fourier_blocks_are_the_whole_operator():
    """For a general uniform material (coupled K, non-diagonal I, intrinsic tilt and roll,
    so the rest state is a helix) under tension, the 12 x 12 blocks A(k) hold every
    eigenvalue of the whole 12 N x 12 N Jacobian (the operator is circulant)."""
    rng = np.random.default_rng(3)
    M = rng.normal(size=(6, 6)) * 0.15
    K = np.diag([1.0, 1.3, 1.19, 1.1, 1.6, 2.0]) + M @ M.T
    I = np.array([[1.0, 0.05, 0.0], [0.05, 1.2, 0.02], [0.0, 0.02, 2.0]])
    mat = UniformMaterial(K=K, I=I, rho=0.95, Gamma0=np.array([0.02, -0.03, 1.0]),
                          Omega0=np.array([0.01, 0.04, 2 * np.pi * 3 / 20.0]))
    rod = LinearRod(mat, 20.0, 24, tension=0.02, turns=3)
    whole = np.linalg.eigvals(rod.jacobian())
    blocks = np.concatenate([np.linalg.eigvals(rod.operator(m)) for m in range(24)])
    assert np.abs(np.sort(whole.imag) - np.sort(blocks.imag)).max() < 1e-7   # zero modes: Jordan blocks
    assert np.abs(whole.real).max() < 1e-7      # conservative


def test_fast_twist_averages_the_bend_compliances():
    """A rod whose body frame turns 15 times over its length sees its two bend stiffnesses
    in series: its lowest bend mode is that of the harmonic mean 2 / (1/D1 + 1/D2), not of
    the arithmetic mean (control). The isotropic rod of the harmonic mean, same shear,
    carries the same Timoshenko correction."""
    D1, D2 = 0.9, 1.5
    harmonic, arithmetic = 2 / (1 / D1 + 1 / D2), 0.5 * (D1 + D2)

    def lowest(d1, d2):
        mat = UniformMaterial(K=np.diag([1.0, 1.0, 1.19, d1, d2, 2.02]), I=np.diag([1.0, 1.0, 2.0]),
                              rho=1.0, Gamma0=np.array([0.0, 0.0, 1.0]),
                              Omega0=np.array([0.0, 0.0, OMEGA15]))
        return dispersion(LinearRod(mat, L158, 158).modes(1), "bend")[1]["omega"]

    w = lowest(D1, D2)
    assert w == pytest.approx(lowest(harmonic, harmonic), rel=2e-3)
    assert abs(w / lowest(arithmetic, arithmetic) - 1) > 1e-2      # the control must fail


def planar_tension(q, T, G, C1=1.0, D=1.21, I=1.0, rho=1.0, string=True):
    """The lowest bend frequency of an untwisted isotropic rod stretched to Gamma3 = G by
    the axial force T, from the planar linear balance laws written out by hand
    (n1 = C1 Gamma1, n3 = T, m2 = D Omega2; fields e^{i(qs - wt)}):
        rho gamma1_t = n1_s + Omega2 n3,        I omega2_t = m2_s + Gamma3 n1 - Gamma1 n3,
        Gamma1_t = gamma1_s - omega2 Gamma3,    Omega2_t = omega2_s.
    string=False drops the Omega2 n3 term (the control)."""
    M = np.array([[0, 0, 1j * q * C1 / rho, (T if string else 0.0) / rho],
                  [0, 0, (G * C1 - T) / I, 1j * q * D / I],
                  [1j * q, -G, 0, 0],
                  [0, 1j * q, 0, 0]])
    return np.sort(np.abs(np.linalg.eigvals(M).imag))[0]


def test_tension_against_the_planar_balance_laws():
    """Under tension the lowest bend modes equal the hand-written planar linearisation
    (an independent derivation of the same continuum equations); the same without the
    tension's Omega x n term fails (control). The string-beam rule mu omega^2 = T q^2 + B q^4
    holds only to O(B q^2 / C): the tension couples to shear (Cosserat, not Euler-Bernoulli)."""
    mat = UniformMaterial.paper(0.0)
    for T in (1e-4, 5e-4):
        rod = LinearRod(mat, L158, 158, tension=T)
        G = rod.Gamma[2]
        assert G == pytest.approx(1 + T / U.C_star[2], rel=1e-12)
        wT = dispersion(rod.modes(3), "bend")
        for n in (1, 2, 3):
            q = 2 * np.pi * n / L158
            assert wT[n]["omega"] == pytest.approx(planar_tension(q, T, G), rel=1e-9)
            assert abs(wT[n]["omega"] / planar_tension(q, T, G, string=False) - 1) > 1e-3


def test_dna_units_periods_of_the_paper_rod():
    """In DNA units: the paper rod's fundamental at zero tension is Eq 26's 1560 ps, and
    tension shortens it (5 pN: about a third)."""
    d0 = dna_dispersion(UniformMaterial.paper(OMEGA15), 158, 15, 0.0, n_max=3)
    d5 = dna_dispersion(UniformMaterial.paper(OMEGA15), 158, 15, 5.0, n_max=3)
    q = 2 * np.pi / L158
    assert 2 * np.pi / d0["bend"][1]["omega_per_ps"] == pytest.approx(U.time_to_ps(2 * np.pi / eq26(q)),
                                                                     rel=1e-9)
    assert 0.6 < d5["bend"][1]["omega_per_ps"] ** -1 / d0["bend"][1]["omega_per_ps"] ** -1 < 0.7


def test_damped_modes_against_closed_forms_and_the_hand_built_block():
    """LinearRod.damped_modes (the Langevin rod's mean motion) against what is known apart
    from it: on the twisted paper rod, stretch and twist are damped oscillators whose
    eigenvalues are closed forms, lambda = -z / (2 m) + i sqrt(c q^2 / m - (z / 2m)^2) with
    (m, c, z) = (rho, C3, friction along) and (I3, D3, friction about the axis); on the untwisted rod,
    bend is the slow eigenvalue pair of the 12 x 12 block built by hand from the linearised
    equations in tests/python/test_thermal_langevin.py (both frictions, shear, rotary
    inertia). Control: that block without the rotational friction across misses bend's
    damping."""
    from test_thermal_langevin import linearised_block
    zt, zr = (0.032, 0.01), (0.079, 0.05)
    got = LinearRod(UniformMaterial.paper(OMEGA15), L158, 158, turns=15).damped_modes(zt, zr, 6)
    for n in range(1, 7):
        q = 2 * np.pi * n / L158
        for kind, m, c, z in (("stretch", 1.0, U.C_star[2], zt[0]), ("twist", U.I_star[2], U.D_star[2], zr[0])):
            g = z / (2 * m)
            ws = [(x["omega"], x["damping"]) for x in got if (x["kind"], x["n"]) == (kind, n)]
            assert len(ws) == 2, (kind, n, ws)
            for w, d in ws:
                assert w == pytest.approx(np.sqrt(c * q * q / m - g * g), rel=1e-9)
                assert d == pytest.approx(g, rel=1e-9)
    flat = LinearRod(UniformMaterial.paper(0.0), L158, 158).damped_modes(zt, zr, 6)
    K, I = np.diag([*U.C_star, *U.D_star]), np.diag(U.I_star)
    Zt, Zr = np.array([zt[1], zt[1], zt[0]]), np.array([zr[1], zr[1], zr[0]])
    for n in range(2, 7):               # n = 1 is overdamped at this friction
        q = 2 * np.pi * n / L158
        lam = np.linalg.eigvals(linearised_block(q, np.array([0, 0, 1.0]), K, I, 1.0, Zt, Zr))
        slow = min((x for x in lam if x.imag > 1e-12), key=lambda x: x.imag)
        ws = [(x["omega"], x["damping"]) for x in flat if (x["kind"], x["n"]) == ("bend", n)]
        assert len(ws) == 4, (n, ws)
        for w, d in ws:
            assert w == pytest.approx(slow.imag, rel=1e-8) and d == pytest.approx(-slow.real, rel=1e-8)
        lam0 = np.linalg.eigvals(linearised_block(q, np.array([0, 0, 1.0]), K, I, 1.0, Zt, Zr * [0, 0, 1]))
        slow0 = min((x for x in lam0 if x.imag > 1e-12), key=lambda x: x.imag)
        assert abs(-slow0.real / ws[0][1] - 1) > 1e-3, (n, slow0, ws[0])     # control
