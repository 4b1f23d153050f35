"""The coarse-grained rod's prediction with each mode's own storage stiffness
(mdbridge/analysis/unrelaxed_prediction.py; docs/coarse-graining.md, "Compliance by timescale").

Known answer: one step's fast elastic fluctuations (AR(1), 1 ps, compliance J_fast: Olson
1998's GA dimer) plus slow smooth episodes (Gaussian kernel of 200 ps, J_slow = 2 J_fast),
40 ns at 1 ps (mdbridge/coarsegrain/synthetic.py). Its J*(omega) is known in closed form, so
each mode's self-consistent frequency is too: omega* = f(Re J*(omega*)^-1), f the 158-bp
linear rod of that stiffness at 30 pN. The estimate returns omega* within 2 % for twist
n = 3 and bend n = 8 (periods of ~30-40 ps, the slow part gone) and bend n = 3 (~150 ps, part
of it left), in a few iterations. Control (must fail): the relaxed rod, K = (J_fast + J_slow)^-1,
misses the first two by more than 20 % and bend n = 3, whose frequency the tension holds up,
by more than 5 %.
"""
import numpy as np
import pytest

from cg_truth import per_step
from mdbridge.analysis.dispersion_prediction import Duplex, frequencies
from mdbridge.analysis.unrelaxed_prediction import unrelaxed_mode
from mdbridge.coarsegrain.cgrod import uniform_material
from mdbridge.coarsegrain.synthetic import fast_slow_steps
from mdbridge.rod.linear import UniformMaterial

T_K, TENSION_PN, SIGMA_PS, TAU_FAST_PS = 300.0, 30.0, 200.0, 1.0
MASS_AMU, INERTIA_AMU_A2 = 618.0, np.diag([25000.0, 25000.0, 50000.0])
DUPLEX = Duplex(158, 15, T_K)


def _J_star(omega, J_fast, J_slow):
    """The synthetic ensemble's J*(omega) in closed form (tests/python/test_coarsegrain_timescale.py)."""
    u = np.linspace(0.0, 12.0 * SIGMA_PS, 200001)
    f = np.exp(-u ** 2 / (4.0 * SIGMA_PS ** 2) - 1j * omega * u)
    slow_hat = np.sum(0.5 * (f[1:] + f[:-1])) * (u[1] - u[0])
    return J_fast / (1.0 + 1j * omega * TAU_FAST_PS) + J_slow * (1.0 - 1j * omega * slow_hat)


@pytest.fixture(scope="module")
def ensemble():
    mean, F = per_step("GA")
    J_fast = np.linalg.inv(F[0])
    q = fast_slow_steps(mean, J_fast, 2 * J_fast, 40000, 1.0, TAU_FAST_PS, SIGMA_PS, np.random.default_rng(4))
    return mean[0], J_fast, q


def _rod(mean):
    def material_of(F):
        return UniformMaterial.from_dict(uniform_material(mean, F, T_K, MASS_AMU, INERTIA_AMU_A2, m=0))

    def frequency_of(kind, n):
        return lambda mat: frequencies(mat, DUPLEX, TENSION_PN, n_max=n)[kind][n][0]
    return material_of, frequency_of


@pytest.mark.parametrize("kind,n,control", [("twist", 3, 0.2), ("bend", 8, 0.2), ("bend", 3, 0.05)])
def test_self_consistent_frequency_of_the_known_answer(ensemble, kind, n, control):
    mean, J_fast, q = ensemble
    material_of, frequency_of = _rod(mean)
    f = frequency_of(kind, n)
    relaxed = f(material_of(np.linalg.inv(3 * J_fast)))
    truth = relaxed
    for _ in range(30):                      # the fixed point with the closed-form J*
        truth = f(material_of(np.linalg.inv(_J_star(truth, J_fast, 2 * J_fast)).real))
    r = unrelaxed_mode(kind, n, q, np.ones(1, bool), False, 1.0, material_of, f, relaxed, n_boot=20)
    assert r["converged"] and r["iterations"] <= 6, r["omega_path_per_ps"]
    assert r["omega_per_ps"] == pytest.approx(truth, rel=0.02), (r["omega_path_per_ps"], truth)
    assert abs(relaxed / truth - 1) > control                                # the control
