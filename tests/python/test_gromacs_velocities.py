"""Initial velocities for the MD (mdbridge.md.gromacs.velocities), without GROMACS.

Independent truths: the Maxwell-Boltzmann law (each m-weighted component is a
standard normal), the equipartition temperature, rigid-body kinematics
(distances between atoms of one base pair do not change to first order, the
velocity at the cross-section's centre is gamma), and a finite rigid motion
differenced in time."""
import numpy as np
import pytest
from scipy import stats
from scipy.spatial.transform import Rotation

from mdbridge.md.gromacs.velocities import (KB_KJ_MOL_K, base_pair_of_residue, kinetic_temperature,
                                         rigid_body_velocities, thermal_velocities)


def test_boltzmann_constant_is_codata_in_gromacs_units():
    # R = N_A k_B = 8.314462618 J/(mol K) (CODATA 2018) -> kJ/(mol K)
    assert KB_KJ_MOL_K == pytest.approx(8.314462618e-3, rel=1e-10)


@pytest.mark.parametrize("T", [300.0, 10.0])
def test_thermal_velocities_exact_temperature_zero_momentum_maxwell(T):
    rng = np.random.default_rng(5)
    m = rng.choice([1.008, 12.011, 14.007, 15.999, 30.974], size=6000)
    v = thermal_velocities(m, T, seed=42)
    n = len(m)
    ke = 0.5 * np.sum(m[:, None] * v ** 2)
    assert 2 * ke / ((3 * n - 3) * 8.314462618e-3) == pytest.approx(T, rel=1e-9)
    assert np.abs((m[:, None] * v).sum(axis=0)).max() < 1e-9
    # Maxwell-Boltzmann: v sqrt(m / kT) is N(0, 1) in every component
    z = (v * np.sqrt(m / (KB_KJ_MOL_K * T))[:, None]).ravel()
    assert stats.kstest(z, "norm").pvalue > 1e-3
    # the seed is the whole story
    assert np.array_equal(v, thermal_velocities(m, T, seed=42))
    assert not np.array_equal(v, thermal_velocities(m, T, seed=43))


def test_zero_kelvin_gives_zero():
    assert not thermal_velocities(np.ones(10), 0.0, seed=1).any()


def test_kinetic_temperature_of_known_state():
    # two argon-like atoms, 1 nm/ps each along x: KE = 2 * 0.5 * 40 * 1 = 40 kJ/mol
    m = np.array([40.0, 40.0])
    v = np.array([[1.0, 0, 0], [-1.0, 0, 0]])
    assert kinetic_temperature(m, v, n_dof=3) == pytest.approx(2 * 40.0 / (3 * 8.314462618e-3))


def test_rigid_body_velocity_is_a_rigid_motion():
    rng = np.random.default_rng(0)
    n_bp = 5
    origins = rng.normal(size=(n_bp, 3)) * 10
    gamma = rng.normal(size=(n_bp, 3))           # A/ps
    omega = rng.normal(size=(n_bp, 3)) * 0.1     # rad/ps
    bp = np.repeat(np.arange(n_bp), 40)
    x = origins[bp] + rng.normal(size=(len(bp), 3)) * 5
    v = rigid_body_velocities(x, bp, origins, gamma, omega) * 10.0   # back to A/ps
    # d/dt |x_a - x_b|^2 = 2 (x_a - x_b).(v_a - v_b) = 0 within a base pair
    for i in range(n_bp):
        xa, va = x[bp == i], v[bp == i]
        dx = xa[:, None] - xa[None]
        dv = va[:, None] - va[None]
        assert np.abs((dx * dv).sum(-1)).max() < 1e-10
    # an atom at the origin of its cross-section moves with gamma
    v0 = rigid_body_velocities(origins, np.arange(n_bp), origins, gamma, omega) * 10.0
    assert np.allclose(v0, gamma, atol=1e-14)
    # finite rigid motion x(t) = r + g t + exp(t [w]x) (x - r), central difference at t = 0
    h = 1e-5
    for i in range(n_bp):
        sel = bp == i

        def at(t):
            Rt = Rotation.from_rotvec(omega[i] * t).as_matrix()
            return origins[i] + gamma[i] * t + (x[sel] - origins[i]) @ Rt.T
        fd = (at(h) - at(-h)) / (2 * h)
        assert np.allclose(v[sel], fd, atol=1e-6)


def test_units_angstrom_per_ps_to_nm_per_ps():
    v = rigid_body_velocities(np.zeros((1, 3)), [0], np.zeros((1, 3)), [[1.0, 2.0, 3.0]], [[0, 0, 0]])
    assert np.allclose(v, [[0.1, 0.2, 0.3]])


def test_residue_to_base_pair_follows_3dna_numbering():
    # n = 4: strand I 1..4 -> pairs 0..3; strand II 5..8 runs 5'->3' from pair 3 down to pair 0
    assert base_pair_of_residue([1, 2, 3, 4, 5, 6, 7, 8], 4).tolist() == [0, 1, 2, 3, 3, 2, 1, 0]
    with pytest.raises(ValueError, match="residue number 9"):
        base_pair_of_residue([9], 4)
