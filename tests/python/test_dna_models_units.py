"""dna_models.units against the numbers printed in the paper (Sec 2.1-2.2):
tau = 9.4e-13 s, l = 5.0e-10 m, C* = diag(1, 1, 1.19), D* = 1.21 diag(1, 1, 1.67),
I* = diag(1, 1, 2), D rho / (I C) = 1.21."""
import math

import pytest

from dna_models.units import Units


@pytest.fixture(scope="module")
def u():
    return Units.paper()


def test_time_scale_is_094_ps(u):
    assert u.tau_ps == pytest.approx(0.94, abs=0.005)       # printed with 2 digits


def test_length_scale_is_5_angstrom(u):
    assert u.ell_A == pytest.approx(5.0, abs=0.05)


def test_dimensionless_matrices(u):
    assert u.C_star == pytest.approx((1.0, 1.0, 1.19))
    assert u.I_star == pytest.approx((1.0, 1.0, 2.0))
    assert u.D_star == pytest.approx((1.21, 1.21, 1.21 * 1.67))


def test_bend_shear_ratio_from_constants(u):
    # D rho / (I C) from Sec 2.1's constants, printed as 1.21
    assert u.bend_shear_ratio_from_constants == pytest.approx(1.21, abs=0.005)


def test_stretch_modulus_1087_pN(u):
    # C3 = 1.19 C is the stretch modulus quoted in Sec 2.1 (1087 pN)
    assert 1.19 * u.C / 1e-12 == pytest.approx(1087, rel=0.01)


def test_conversions_round_trip_and_scale(u):
    assert u.length_to_A(u.length_to_rod(3.38)) == pytest.approx(3.38, rel=1e-15)
    assert u.time_to_ps(1.0) == pytest.approx(u.tau_ps)
    # Omega* = l Omega: one B-DNA turn per 10.5 bp
    twist_rad_per_A = 2 * math.pi / (10.5 * 3.38)
    assert u.curvature_to_rod(twist_rad_per_A) == pytest.approx(twist_rad_per_A * u.ell_A)
    assert u.velocity_to_A_per_ps(1.0) == pytest.approx(u.ell_A / u.tau_ps)
