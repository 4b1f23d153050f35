"""dt convergence of the overdamped rod's step (solver.time = "brownian", rodcore/src/rodcore/brownian.hpp),
against truths from the linearised equations (numpy) and a control that must fail: the explicit
Euler-Maruyama step of the same rod at the same dt, written here on rodcore's own right-hand side
(Simulation.rhs: the force at zero velocity, and the compatibility rows at velocity dx).

* The stationary variance of every mode is exact at any dt by the step's design (A C A^T = C + Sigma):
  at a dt where the explicit step is still stable (lambda_max dt = 1.6) the stiff modes of the straight
  rod have their Boltzmann variance (test_thermal_brownian.py checks it at lambda dt up to 160); the
  plain implicit Euler noise is too cold by 1 / (1 + lambda dt / 2) and the explicit Euler-Maruyama
  step too hot by 1 / (1 - lambda dt / 2).
* The relaxation time of an imposed mode (kT = 0) converges at first order, as the L-stable linearly
  implicit step claims: tau_num = dt / ln(1 + dt / tau) = tau (1 + dt / (2 tau) + O(dt^2)), from above,
  monotonically; bend n = 2 and twist n = 1 of a 30-nm rod, dt = tau / 4 .. tau / 64; within 2 % of tau
  from dt = tau / 25. The explicit step at the same dt diverges (bend: its stiff shear modes have
  lambda dt = 10-40) or relaxes too fast, tau_num = dt / -ln(1 - dt / tau) (twist).
"""
import math

import numpy as np
import pytest
import rodcore

from test_thermal_brownian import K_DNA, frictions, q_block, scene, whitened_modes


def explicit_euler_maruyama(sc, dt, steps, kT, initial=None, seed=11):
    """The explicit Euler-Maruyama step of the overdamped rod of scene SC (from INITIAL, a dict of
    (N, 3) arrays, if given): per point and length, Z dx = F(q) dt + (2 kT dt Z / h)^1/2 eta,
    q += D(q) dx; F = (rho f_gamma, I f_omega) from the RHS at zero velocity (the paper's rho = 1,
    I = diag(1, 1, 2)), D(q) dx the RHS's compatibility rows at velocity dx. Returns the strain rows
    (steps + 1, 6, N), cut short where they diverge."""
    sim = rodcore.Simulation(sc) if initial is None else rodcore.Simulation(sc, initial=initial)
    Zt, Zr = frictions(sim.scene)
    Z = np.r_[Zt, Zr][:, None]
    N = sc["rod"]["points"]
    h = sc["rod"]["length"] / N
    inertia = np.array([1.0, 1.0, 1.0, 1.0, 1.0, 2.0])[:, None]
    y = np.asarray(sim.y, float).reshape(12, N).copy()
    rng = np.random.default_rng(seed)
    out = [y[6:].copy()]
    for _ in range(steps):
        y[:6] = 0.0
        F = inertia * np.asarray(sim.rhs(y.ravel())).reshape(12, N)[:6]
        y[:6] = dt * F / Z + math.sqrt(2 * kT * dt / h) * rng.standard_normal((6, N)) / np.sqrt(Z)
        y[6:] += np.asarray(sim.rhs(y.ravel())).reshape(12, N)[6:]
        out.append(y[6:].copy())
        if not np.all(np.isfinite(y)) or np.abs(y[6:] - out[0]).max() > 1.0:
            break
    return np.array(out)


def variance_and_error(m, n, blocks=20):
    """Mean over the 6 whitened components of |mode n|^2, and its standard error from block means."""
    x = (np.abs(m[:, n]) ** 2).mean(axis=1)
    b = x[: len(x) // blocks * blocks].reshape(blocks, -1).mean(axis=1)
    return x.mean(), b.std(ddof=1) / math.sqrt(blocks)


def test_stiff_modes_keep_their_variance_where_implicit_euler_and_euler_maruyama_do_not():
    N, L, kT = 12, 12.0, 1e-10   # the rod of test_thermal_brownian.py: tiny kT, the linearised rod
    Zt, Zr = frictions(rodcore.resolve(scene(N, L, kT, 1.0, 1.0, 2)))
    lam = {n: np.sort(-np.linalg.eigvals(q_block(2 * math.pi * n / L, L / N, K_DNA, Zt, Zr)).real)
           for n in range(1, N // 2)}
    dt = 1.6 / max(v.max() for v in lam.values())    # the explicit step stable (lambda_max dt < 2)
    stiff = [n for n in lam if lam[n].min() * dt > 0.1]    # every component of the mode lambda dt > 0.1
    assert len(stiff) >= 3
    steps = 20000
    exact = whitened_modes(rodcore.run(scene(N, L, kT, dt, dt * steps, steps + 1)), N, L, kT)
    for n in stiff:
        v, se = variance_and_error(exact[200:], n)
        assert abs(v - 1) < max(4 * se, 0.01), (n, v, se)
    # controls from the same exact start: implicit Euler noise cools, explicit Euler-Maruyama heats
    ie = whitened_modes(rodcore.run(scene(N, L, kT, dt, dt * steps, steps + 1, exact_noise=False)), N, L, kT)
    hot_steps = 4000
    em_strains = explicit_euler_maruyama(scene(N, L, kT, dt, dt, 2), dt, hot_steps, kT)
    em = whitened_modes({"fields": {"Gamma": np.swapaxes(em_strains[:, :3], 1, 2),
                                    "Omega": np.swapaxes(em_strains[:, 3:], 1, 2)}}, N, L, kT)
    for n in stiff:
        v_ie, se_ie = variance_and_error(ie[200:], n)
        v_em, se_em = variance_and_error(em[200:], n)
        assert v_ie < 1 - max(4 * se_ie, 0.01), (n, v_ie, se_ie)
        assert v_em > 1 + max(4 * se_em, 0.01), (n, v_em, se_em)


def relaxation_time(mode, dt_per_tau, explicit=False):
    """(tau_num, tau, amplitudes): the slow relaxation time of an imposed mode of a 30-nm straight rod
    at kT = 0 ("bend": Omega2 ~ cos 2 k1 s, its slow eigenvalue with shear; "twist": Omega3 ~ cos k1 s),
    measured over t = tau / 2 .. 3 tau / 2, at dt = tau * dt_per_tau."""
    N, L = 32, 60.0
    h = L / N
    n, comp = (2, 4) if mode == "bend" else (1, 5)
    k = 2 * math.pi * n / L
    Zt, Zr = frictions(rodcore.resolve(scene(N, L, 1e-9, 1.0, 1.0, 2)))
    B = q_block(k, h, K_DNA, Zt, Zr)
    if mode == "bend":
        lam = np.sort(-np.linalg.eigvals(B[np.ix_([0, 4], [0, 4])]).real)[0]   # shear Gamma1, bend Omega2
    else:
        lam = -B[5, 5].real                                                    # twist: C k^2 / Z_r (fd4)
    tau = 1 / lam
    dt = tau * dt_per_tau
    steps = int(round(1.5 / dt_per_tau))
    s = np.arange(N) * h
    init = {"gamma": np.zeros((N, 3)), "omega": np.zeros((N, 3)),
            "Gamma": np.tile([0, 0, 1.0], (N, 1)), "Omega": np.zeros((N, 3))}
    init["Omega"][:, comp - 3] = 1e-7 * np.cos(k * s)
    sc = scene(N, L, 0.0, dt, dt * steps, steps + 1, sample=False)
    if explicit:
        field = explicit_euler_maruyama(sc, dt, steps, 0.0, initial=init)[:, comp]
    else:
        field = rodcore.run(sc, initial=init)["fields"]["Omega"][:, :, comp - 3]
    amp = field @ np.cos(k * s) * 2 / N
    i0 = int(round(0.5 / dt_per_tau))
    t = np.arange(len(amp)) * dt
    if len(amp) <= i0 + 2 or not np.all(np.isfinite(amp)) or np.any(amp[i0:] <= 0):
        return math.nan, tau, amp
    slope = np.polyfit(t[i0:], np.log(amp[i0:]), 1)[0]
    return -1 / slope, tau, amp


@pytest.mark.parametrize("mode", ["bend", "twist"])
def test_relaxation_time_converges_at_first_order_from_above(mode):
    fractions = [1 / 4, 1 / 8, 1 / 16, 1 / 32, 1 / 64]
    err = []
    for f in fractions:
        tau_num, tau, amp = relaxation_time(mode, f)
        assert np.all(np.diff(amp) < 0) and np.all(amp > 0)          # monotone: L-stable, no flip
        assert abs(tau_num / (f * tau / math.log(1 + f)) - 1) < 0.005, (f, tau_num, tau)
        err.append(tau_num / tau - 1)
    err = np.array(err)
    assert np.all(err > 0)                                           # from above: implicit is slow
    order = np.log2(err[:-1] / err[1:])
    assert np.all(np.abs(order - 1) < 0.1), order                    # first order
    assert np.all(np.abs(err / (np.array(fractions) / 2) - 1) < 0.1), err   # error dt / (2 tau)
    # within 2 % of tau from dt = tau / 25 (tau / 32 here), not at tau / 16
    assert err[3] < 0.02 < err[2]
    # control: the explicit step at the same dt fails the same check: the bend's stiff shear (lambda dt
    # 10-40) makes it diverge; the twist, alone in its block, relaxes too fast, dt / -ln(1 - dt / tau)
    for f in (1 / 4, 1 / 16):
        tau_ex, _, amp_ex = relaxation_time(mode, f, explicit=True)
        assert not abs(tau_ex / (f * tau / math.log(1 + f)) - 1) < 0.005, (f, tau_ex, tau)
        if mode == "twist":
            assert abs(tau_ex / (f * tau / -math.log(1 - f)) - 1) < 0.005, (f, tau_ex, tau)
        else:
            assert math.isnan(tau_ex) and np.any(amp_ex <= 0), (f, amp_ex[:5])   # flips and grows
