"""The overdamped rod (solver.time = "brownian", rodcore/src/rodcore/brownian.hpp), against truths
built here from the linearised equations (numpy), not from the stepper:

* equipartition per Fourier mode at a step where every mode has lambda dt = 3-160: the
  whitened strain modes of a uniform straight rod have variance 1 (kT K^-1 / h per point) within
  1 % at every wavenumber the dynamics reaches (all but k = 0 and fd4's null at N / 2, which
  the dynamics conserves); control: the plain implicit Euler noise (the stepper's test switch)
  leaves the stiff modes far too cold. The lag-1 autocorrelation of every mode is >= 0 (an
  L-stable step never flips a stiff mode);
* relaxation at kT = 0: an imposed bending mode decays per step by 1 / (1 + lambda dt), lambda
  the slow eigenvalue of the linearised per-k block Z^-1 D(k)^H K D(k) (shear included, fd4's
  symbol), i.e. tau_num = dt / ln(1 + dt / tau), monotonically; control: the no-shear rate
  B k^4 / zeta_perp is refused.
"""
import math
import re

import numpy as np
import pytest
import rodcore

from dna_models.units import Units

UNITS = Units.paper()
K_DNA = np.diag(np.r_[1.0, 1.0, 1.19, UNITS.D_star])


def cross(v):
    return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


def frictions(scene_text):
    pair = r"\[([0-9.e+-]+), ([0-9.e+-]+)\]"
    zt = re.search(r"\[along, across\] = " + pair, scene_text).groups()
    zr = re.search(r"\[about the axis, across\] = " + pair, scene_text).groups()
    return (np.array([float(zt[1]), float(zt[1]), float(zt[0])]),
            np.array([float(zr[1]), float(zr[1]), float(zr[0])]))


def fd4_symbol(k, h):
    """i d(k): the fd4 derivative of e^{iks} on the grid."""
    return 1j * (8 * math.sin(k * h) - math.sin(2 * k * h)) / (6 * h)


def q_block(k, h, K, Zt, Zr):
    """d/dt of the strain mode q e^{iks} of the overdamped rod linearised about the straight
    untwisted rest state (Gamma0 = e3): -D Z^-1 D^H K with D = [[ik, [e3]x], [0, ik]]
    (compatibility: dGamma = dgamma' + e3 x dtheta, dOmega = dtheta'), D^H its adjoint."""
    ik = fd4_symbol(k, h)
    D = np.zeros((6, 6), complex)
    D[:3, :3] = ik * np.eye(3)
    D[:3, 3:] = cross([0, 0, 1.0])
    D[3:, 3:] = ik * np.eye(3)
    Zi = np.diag(1 / np.r_[Zt, Zr])
    return -D @ Zi @ D.conj().T @ K


def scene(N, L, kT, dt, t_end, frames, exact_noise=True, sample=True):
    return {"rod": {"length": L, "points": N, "Gamma0": [0, 0, 1.0], "Omega0": [0, 0, 0.0]},
            "material": {"K": K_DNA.tolist()},
            "thermal": {"kT": kT, "seed": 5, "sample_initial": sample, "keep_closure": False,
                        "friction_translational": "water", "friction_rotational": "water"},
            "solver": {"time": "brownian", "dt": dt, "exact_noise": exact_noise},
            "output": {"t_end": t_end, "frames": frames, "fields": ["internal"]}}


def whitened_modes(out, N, L, kT):
    """(T, N, 6) complex: U e_k (h / kT)^1/2 / N^1/2 for K = U^T U, e the strain deviation."""
    f = out["fields"]
    e = np.concatenate([f["Gamma"] - [0, 0, 1.0], f["Omega"]], axis=-1)
    U = np.linalg.cholesky(K_DNA).T
    white = e @ U.T * math.sqrt(L / N / kT)
    return np.fft.fft(white, axis=1) / math.sqrt(N)


def test_every_mode_has_the_boltzmann_variance_and_implicit_euler_noise_does_not():
    N, L, kT = 12, 12.0, 1e-10  # tiny kT: the linearised rod
    dt, steps = 100.0, 20000  # 94 ps
    out = rodcore.run(scene(N, L, kT, dt, dt * steps, steps + 1))
    Zt, Zr = frictions(out["scene"])
    rates = [-np.linalg.eigvals(q_block(2 * math.pi * n / L, L / N, K_DNA, Zt, Zr)).real
             for n in range(1, N // 2)]
    assert min(min(r) for r in rates) * dt > 2 and max(max(r) for r in rates) * dt > 100
    m = whitened_modes(out, N, L, kT)
    for n in range(1, N // 2):  # k = 0 and fd4's null at N / 2 are conserved
        var = (np.abs(m[:, n]) ** 2).mean(0)  # 6 components, each 1
        assert abs(var.mean() - 1) < 0.01, (n, var)
        for c in range(6):
            x = m[:, n, c]
            lag1 = (x[1:] * x[:-1].conj()).real.mean() / (np.abs(x) ** 2).mean()
            assert lag1 > -4 / math.sqrt(len(x)), (n, c, lag1)
    # control: the implicit Euler noise, from the same exact start, cools the stiff modes
    cold = whitened_modes(rodcore.run(scene(N, L, kT, dt, dt * 400, 401, exact_noise=False)), N, L, kT)
    assert all(abs((np.abs(cold[200:, n]) ** 2).mean() - 1) > 0.2 for n in range(1, N // 2))


@pytest.mark.parametrize("n", [2, 3])
def test_an_imposed_bend_relaxes_at_the_slow_eigenvalue_not_the_no_shear_rate(n):
    N, L = 32, 60.0  # 30 nm; n = 2, 3: wavelengths of 15 and 10 nm
    h = L / N
    k = 2 * math.pi * n / L
    text = rodcore.resolve(scene(N, L, 1e-9, 1.0, 1.0, 2))
    Zt, Zr = frictions(text)
    B = q_block(k, h, K_DNA, Zt, Zr)
    sub = B[np.ix_([0, 4], [0, 4])]  # shear Gamma1 and bend Omega2 of one plane
    lam = np.sort(-np.linalg.eigvals(sub).real)[0]
    tau = 1 / lam
    dt = tau / 60  # tau >= 50 dt
    s = np.arange(N) * h
    A = 1e-7
    init = {"gamma": np.zeros((N, 3)), "omega": np.zeros((N, 3)),
            "Gamma": np.tile([0, 0, 1.0], (N, 1)), "Omega": np.zeros((N, 3))}
    init["Omega"][:, 1] = A * np.cos(k * s)
    steps = 240
    sc = scene(N, L, 0.0, dt, dt * steps, steps + 1, sample=False)
    out = rodcore.run(sc, initial=init)
    amp = out["fields"]["Omega"][:, :, 1] @ np.cos(k * s) * 2 / N
    assert np.all(np.diff(amp) < 0) and np.all(amp > 0)  # monotone, never flips
    ratio = amp[61:] / amp[60:-1]  # after the shear transient
    tau_num = -dt / np.log(ratio.mean())
    expected = dt / math.log(1 + dt / tau)
    assert abs(tau_num / expected - 1) < 0.03, (tau_num, expected)
    no_shear = Zt[0] / (K_DNA[3, 3] * k ** 4)
    assert abs(tau_num / (dt / math.log(1 + dt / no_shear)) - 1) > 0.03
