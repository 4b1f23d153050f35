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

The rod's errors and the damping, on four independent realisations of each mode: the
bootstrap error of omega (each replica of J* through the same map) and the loss part's
gamma = Delta / (2 omega), both against the closed form's. Controls (must fail): an elastic
rod (gamma = 0), and errors a third as large.
"""
import numpy as np
import pytest

from cg_truth import per_step
from mdbridge.analysis.dispersion_prediction import Duplex, frequencies
from mdbridge.analysis.unrelaxed_prediction import unrelaxed_mode
from mdbridge.coarsegrain.damping import mode_decay_rate
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


MODES = [("twist", 3, 0.2), ("bend", 8, 0.2), ("bend", 3, 0.05)]
SEEDS = (4, 5, 6, 7)


def _ensemble(seed):
    mean, F = per_step("GA")
    J_fast = np.linalg.inv(F[0])
    q = fast_slow_steps(mean, J_fast, 2 * J_fast, 40000, 1.0, TAU_FAST_PS, SIGMA_PS, np.random.default_rng(seed))
    return mean[0], J_fast, q


@pytest.fixture(scope="module")
def ensembles():
    return {seed: _ensemble(seed) for seed in SEEDS}


def _truth(kind, n, mean, J_fast):
    """The relaxed rod's omega, and the closed form's self-consistent omega* and gamma*."""
    material_of, frequency_of = _rod(mean)
    f = frequency_of(kind, n)
    relaxed = f(material_of(np.linalg.inv(3 * J_fast)))
    w = relaxed
    for _ in range(30):                      # the fixed point with the closed-form J*
        w = f(material_of(np.linalg.inv(_J_star(w, J_fast, 2 * J_fast)).real))
    K = np.linalg.inv(_J_star(w, J_fast, 2 * J_fast))
    return relaxed, w, mode_decay_rate(K.real, K.imag, w, material_of, f)


@pytest.fixture(scope="module")
def runs(ensembles):
    """(kind, n) -> (relaxed, omega*, gamma*, [unrelaxed_mode of each seed])."""
    out = {}
    for kind, n, _ in MODES:
        mean, J_fast, _q = ensembles[SEEDS[0]]
        relaxed, w, g = _truth(kind, n, mean, J_fast)
        material_of, frequency_of = _rod(mean)
        rs = [unrelaxed_mode(kind, n, ensembles[s][2], np.ones(1, bool), False, 1.0, material_of,
                             frequency_of(kind, n), relaxed, n_boot=20) for s in SEEDS]
        out[(kind, n)] = (relaxed, w, g, rs)
    return out


def _rod(mean):
    def material_of(F):
        return UniformMaterial.from_dict(uniform_material(mean, F, T_K, MASS_AMU, INERTIA_AMU_A2, m=0))

    def frequency_of(kind, n):
        return lambda mat: frequencies(mat, DUPLEX, TENSION_PN, n_max=n)[kind][n][0]
    return material_of, frequency_of


@pytest.mark.parametrize("kind,n,control", MODES)
def test_self_consistent_frequency_of_the_known_answer(runs, kind, n, control):
    relaxed, truth, _g, rs = runs[(kind, n)]
    r = rs[0]
    assert r["converged"] and r["iterations"] <= 6, r["omega_path_per_ps"]
    assert r["omega_per_ps"] == pytest.approx(truth, rel=0.02), (r["omega_path_per_ps"], truth)
    assert abs(relaxed / truth - 1) > control                                # the control


def test_the_rod_s_errors_and_damping_cover_the_realisations(runs):
    z_w, z_g, bias_g, z_elastic = [], [], [], []
    for (kind, n), (_rel, w, g, rs) in runs.items():
        for r in rs:
            assert r["bootstrap"]["failed"] == 0, r["bootstrap"]
            z_w.append((r["omega_per_ps"] - w) / r["omega_err_per_ps"])
            z_g.append((r["gamma_per_ps"] - g) / r["gamma_err_per_ps"])
            z_elastic.append(g / r["gamma_err_per_ps"])
        bias_g.append(np.mean([r["gamma_per_ps"] for r in rs]) / g - 1)

    def rms(z):
        return float(np.sqrt(np.mean(np.square(z))))
    # omega's error covers the realisations; gamma's is biased and understated at bend n = 8
    # (docs/coarse-graining.md, "The damping": a gamma agrees within about 2.5 errors)
    assert 0.5 < rms(z_w) < 1.6, z_w
    assert rms(z_g) < 2.5 and max(np.abs(z_g)) < 7, z_g
    assert max(abs(b) for b in bias_g) < 0.2, bias_g
    # controls: errors a third as large leave the band; an elastic rod (gamma = 0) misses the damping
    assert rms(3 * np.array(z_w)) > 1.6
    assert min(z_elastic) > 2 and rms(z_elastic) > 5
