"""The damping a standard linear solid predicts (mdbridge/coarsegrain/damping.py), against a
synthetic process of known parameters.

Truth: the equilibrium fluctuation of an overdamped standard linear solid is x = x_u + x_r,
x_u the fast elastic part (AR(1) of correlation time 0.2 ps, compliance J_u) and x_r the
retarded one (an Ornstein-Uhlenbeck process of time tau, compliance J_r), so its creep
compliance is J_u (1 - e^{-t / 0.2 ps}) + J_r (1 - e^{-t / tau}) exactly at the frame times.
The fit above the fast time returns (J_u, J_r, tau) within errors from refitting eight
independent pieces of the record, and the damping constant of a mode of period 50 ps,
gamma = omega tan(delta), within its error. Controls: the elastic material (J_r = 0)
predicts no damping and must miss; the first-order gamma agrees with the exact root of
m omega^2 = K*(omega) to second order in the loss.
"""
import numpy as np
import pytest
from scipy.signal import lfilter

from mdbridge.coarsegrain.damping import fit_sls, mode_root, predicted_gamma, sls_dynamic
from mdbridge.coarsegrain.timescale import creep_compliance

DT = 0.1
J_U, J_R, TAU, TAU_FAST = 1.0, 0.6, 10.0, 0.2
OMEGA = 2 * np.pi / 50.0


def _ar1(n, tau, rng):
    phi = np.exp(-DT / tau)
    return lfilter([np.sqrt(1 - phi * phi)], [1.0, -phi], rng.standard_normal(n))


def _fit(x):
    J = creep_compliance(x[:, None], 600)[:, 0, 0]
    f = fit_sls(np.arange(len(J)) * DT, J, t_min_ps=2.0)
    return np.array([f["J_u"], f["J_r"], f["tau_ps"], float(predicted_gamma(OMEGA, f["J_u"], f["J_r"], f["tau_ps"]))])


def test_standard_linear_solid_fit_and_its_damping():
    rng = np.random.default_rng(4)
    T = 400000                                             # 40 ns at 0.1 ps, 4000 tau
    x = np.sqrt(J_U) * _ar1(T + 1000, TAU_FAST, rng)[1000:] + np.sqrt(J_R) * _ar1(T + 5000, TAU, rng)[5000:]
    est = _fit(x)
    pieces = np.array([_fit(p) for p in x.reshape(8, -1)])
    err = pieces.std(axis=0, ddof=1) / np.sqrt(8)
    gamma_true = float(predicted_gamma(OMEGA, J_U, J_R, TAU))
    truth = np.array([J_U, J_R, TAU, gamma_true])
    z = (est - truth) / err
    assert np.all(np.abs(z) < 3), (est, truth, err)
    assert np.all(err / truth < 0.1), err / truth
    # control: the elastic material of the same relaxed compliance predicts no damping
    assert abs(0.0 - est[3]) / err[3] > 5
    # the first-order damping against the exact complex root, mass tuned to the mode
    Js = sls_dynamic(OMEGA, J_U, J_R, TAU)
    m = (1.0 / Js).real / OMEGA ** 2
    w = mode_root(m, J_U, J_R, TAU, OMEGA)
    tan_delta = -Js.imag / Js.real
    assert abs(2 * w.imag / gamma_true - 1) < 2 * tan_delta, (2 * w.imag, gamma_true, tan_delta)
    assert abs(w.real / OMEGA - 1) < tan_delta ** 2


def test_a_rod_mode_s_decay_rate_is_half_the_damping_constant():
    # mode_decay_rate through a one-coordinate "rod" (w = sqrt(K / m)) on the same material:
    # the amplitude decay rate Im(omega) of the exact root, half of gamma = omega tan(delta)
    from mdbridge.coarsegrain.damping import mode_decay_rate
    K = 1.0 / sls_dynamic(OMEGA, J_U, J_R, TAU)
    m = K.real / OMEGA ** 2
    rate = mode_decay_rate(np.array([[K.real]]), np.array([[K.imag]]), OMEGA, lambda k: k,
                           lambda k: np.sqrt(k[0, 0] / m))
    assert rate == pytest.approx(float(predicted_gamma(OMEGA, J_U, J_R, TAU)) / 2, rel=1e-6)
    w = mode_root(m, J_U, J_R, TAU, OMEGA)
    tan_delta = K.imag / K.real
    assert abs(rate / w.imag - 1) < 2 * tan_delta
    # control: the damping constant itself (twice the rate) is not the decay rate
    assert abs(2 * rate / w.imag - 1) > 0.5
