"""The Boltzmann sample of the thermal rod ([thermal], docs/thermal.md), checked by its own
statistics against sampling theory, each with a control that must fail:

* the strain covariance is kT K^-1 / h for a coupled K and for a per-point sequence material
  (Wishart likelihood-ratio statistic below the chi-square_21 99.9 % quantile);
* equipartition per class of degree of freedom (translation, rotation, strain);
* twist in a periodic rod: windows of length l have Var(Tw_l) = l (1 - l/L) kT / (4 pi^2 C_eff),
  C_eff = 1 / (K^-1)_66 (closure fixes the total twist);
* DNA units: the paper's rod at 300 K has bend persistence D / kT = 66.4 nm, from the
  per-point bend variance of the 158-bp rod and from the tangent correlation of a ring 20
  persistence lengths long;
* the conservative right-hand side has zero divergence (Liouville), so exp(-E / kT) in
  (gamma, omega, Gamma, Omega) is invariant under the flow.

Samples are made by rodcore.Simulation (the sample is in its state at t = 0) with fixed seeds.
"""
import math

import h5py
import numpy as np
import pytest
import rodcore

from dna_models.units import Units

CHI2_21_999 = 46.80  # 99.9 % quantile of chi-square with 21 degrees of freedom
UNITS = Units.paper()


def coupled_K():
    K = np.diag([1.0, 1.1, 1.19, 1.21, 1.3, 2.02])
    K[2, 5] = K[5, 2] = -0.6   # twist-stretch
    K[0, 4] = K[4, 0] = 0.2    # shear-bend
    K[3, 4] = K[4, 3] = 0.15   # bend-bend
    return K


I_COUPLED = np.array([[1.0, 0.45, 0.0], [0.45, 1.2, 0.0], [0.0, 0.0, 2.0]])
OMEGA03 = 1.1


def straight(N, L, kT, seed, material=None):
    return {"rod": {"length": L, "points": N, "Gamma0": [0, 0, 1.0], "Omega0": [0, 0, OMEGA03]},
            "material": material or {"K": coupled_K(), "I": I_COUPLED, "rho": 1.3},
            "thermal": {"kT": kT, "seed": seed}, "output": {"t_end": 1.0}}


def samples(scene_of, seeds):
    """The sampled states (dicts of (N, 3) arrays) of a scene for each seed."""
    return [rodcore.Simulation(scene_of(s)).state for s in seeds]


def strains(states):
    """(n, 6) strain deviations e = (Gamma - Gamma0, Omega - Omega0) of a straight rod."""
    return np.concatenate([np.hstack([s["Gamma"] - [0, 0, 1.0], s["Omega"] - [0, 0, OMEGA03]])
                           for s in states])


def wishart(samples_, Sigma):
    """n [tr(A) - ln det A - p], A = Sigma^-1 S: chi-square with p (p + 1) / 2 degrees of
    freedom for n zero-mean Gaussian samples of covariance Sigma."""
    n, p = samples_.shape
    A = np.linalg.solve(Sigma, samples_.T @ samples_ / n)
    return n * (np.trace(A) - np.log(np.linalg.det(A)) - p)


def test_strain_covariance_coupled_K():
    N, L, kT = 256, 40.0, 1e-3
    e = strains(samples(lambda s: straight(N, L, kT, s), range(1, 31)))
    Sigma = kT / (L / N) * np.linalg.inv(coupled_K())
    assert wishart(e, Sigma) < CHI2_21_999
    # control: the couplings of K are seen (K's diagonal alone is refused)
    assert wishart(e, kT / (L / N) * np.diag(1 / np.diag(coupled_K()))) > 10 * CHI2_21_999


def test_strain_covariance_per_point_sequence_material(tmp_path):
    """A sequence-dependent material: four coupled K (and I, rho) cycling along the rod;
    each point whitened by its own K: the pooled whitened strains are N(0, kT/h 1)."""
    N, L, kT = 256, 40.0, 1e-3
    rng = np.random.default_rng(3)
    Ks = []
    for _ in range(4):
        A = rng.normal(scale=0.5, size=(6, 6))
        Ks.append(coupled_K() + A @ A.T)
    K = np.array([Ks[i % 4] for i in range(N)])
    Ip = np.array([I_COUPLED * (1 + 0.2 * (i % 3)) for i in range(N)])
    rho = np.array([1.0 + 0.3 * (i % 5) for i in range(N)])
    path = tmp_path / "material.h5"
    with h5py.File(path, "w") as f:
        f.attrs["format"] = "dnarod-material/1"
        f["K"], f["I"], f["rho"] = K, Ip, rho
    e = strains(samples(lambda s: straight(N, L, kT, s, {"material_file": str(path)}), range(1, 31)))
    e = e.reshape(30, N, 6)
    U = np.linalg.cholesky(K).transpose(0, 2, 1)          # K_i = U_i^T U_i
    white = np.einsum("iab,sib->sia", U, e).reshape(-1, 6)  # U_i e_i ~ N(0, kT / h)
    assert wishart(white, kT / (L / N) * np.eye(6)) < CHI2_21_999
    # control: whitened with the mean K (a uniform rod) the same strains are refused
    U_mean = np.linalg.cholesky(K.mean(0)).T
    assert wishart((e @ U_mean.T).reshape(-1, 6), kT / (L / N) * np.eye(6)) > 10 * CHI2_21_999


def test_equipartition_per_class():
    """Each class of degree of freedom holds kT / 2 per degree: the translational and rotational
    kinetic energies and the strain energy, averaged over points and samples. The sample's
    constraints (4 momenta, 6 closure directions) remove at most 4 / (3 N) of a class."""
    N, L, kT, rho, M = 256, 40.0, 1e-3, 1.3, 30
    states = samples(lambda s: straight(N, L, kT, s), range(1, M + 1))
    h = L / N
    g = np.concatenate([s["gamma"] for s in states])
    w = np.concatenate([s["omega"] for s in states])
    e = strains(states)
    per_class = {
        "translational": (rho * h * (g ** 2).sum(1) / kT, 3),
        "rotational": (h * np.einsum("ni,ij,nj->n", w, I_COUPLED, w) / kT, 3),
        "strain": (h * np.einsum("ni,ij,nj->n", e, coupled_K(), e) / kT, 6),
    }
    for name, (x, dof) in per_class.items():
        sd = math.sqrt(2.0 / (dof * len(x)))             # mean of chi-square_dof / dof
        assert abs(x.mean() / dof - 1) < 4 * sd + 4 / (3 * N), name
    # the kinetic temperature the run reports (2 KE / 6 N) is kT (6N - 4) / 6N
    kin = [rodcore.Simulation(straight(N, L, kT, s)).kinetic_kT for s in range(1, M + 1)]
    assert abs(np.mean(kin) / (kT * (1 - 4 / (6 * N))) - 1) < 4 * math.sqrt(2 / (6 * N * M))
    # control: with I's diagonal only (13 % off), the rotational class fails the same check
    xd = h * np.einsum("ni,ij,nj->n", w, np.diag(np.diag(I_COUPLED)), w) / kT
    assert abs(xd.mean() / 3 - 1) > 4 * math.sqrt(2.0 / (3 * len(xd))) + 4 / (3 * N)


def test_twist_windows_in_a_periodic_rod():
    """Closure fixes the total twist of a periodic rod, so a window of length l has
    Var(Tw_l) = l (1 - l/L) kT (K^-1)_66 / (4 pi^2), Tw in turns. The twist-stretch
    coupling makes C_eff = 1 / (K^-1)_66 17 % softer than K_66 (the control)."""
    N, L, kT, M = 512, 80.0, 1e-3, 300
    h = L / N
    Kinv66 = np.linalg.inv(coupled_K())[5, 5]
    twist = [s["Omega"][:, 2] - OMEGA03 for s in samples(lambda seed: straight(N, L, kT, seed), range(1, M + 1))]
    for n_w in (16, N // 2):
        l = n_w * h
        per_sample = []
        for t in twist:
            d3 = np.concatenate([t, t])
            tw = h * (np.cumsum(d3)[n_w:n_w + N] - np.cumsum(d3)[:N]) / (2 * np.pi)  # every window
            per_sample.append(np.mean(tw ** 2))
        per_sample = np.array(per_sample)
        mean, se = per_sample.mean(), per_sample.std(ddof=1) / math.sqrt(M)
        expected = l * (1 - l / L) * kT * Kinv66 / (4 * np.pi ** 2)
        assert abs(mean - expected) < 4 * se, (n_w, mean, expected, se)
        if n_w == 16:  # control: C = K_66 is refused (short windows: 32 per sample, se 1.5 %)
            assert abs(mean - l * (1 - l / L) * kT / coupled_K()[5, 5] / (4 * np.pi ** 2)) > 4 * se
        else:          # control: without the closure factor (1 - l/L) = 1/2
            assert abs(mean - l * kT * Kinv66 / (4 * np.pi ** 2)) > 4 * se


def dna_rod(bp, temperature_K, seed):
    return {"initial": {"kind": "dna_planar", "bp": bp, "turns": round(bp / 10.5), "A_v_A_per_ps": 0.0},
            "thermal": {"temperature_K": temperature_K, "seed": seed}, "output": {"t_end": 1.0}}


def test_dna_bend_persistence_from_the_per_point_bend_variance():
    """The 158-bp rod at 300 K: Var(Omega_1,2) = kT / (D h) per point, so D / kT =
    1 / (h Var) in rod lengths; the paper's Sec 2.1 constants give 66.4 nm."""
    M, T = 200, 300.0
    states = samples(lambda s: dna_rod(158, T, s), range(1, M + 1))
    h = 158 * UNITS.rise_A / UNITS.ell_A / 158
    bend = np.concatenate([s["Omega"][:, :2].ravel() for s in states])
    var, n = np.mean(bend ** 2), bend.size
    lp_nm = 1 / (h * var) * UNITS.ell_A / 10
    lp_err = lp_nm * math.sqrt(2 / n)
    paper_nm = UNITS.D / (1.380649e-23 * T) * 1e9    # D / kT from D = 2.75e-28 J m
    assert paper_nm == pytest.approx(66.4, abs=0.05)
    # the rod's D* = 1.21 (the paper's printed ratio; 1.2115 from its constants): 0.13 % lower
    assert abs(lp_nm - paper_nm) < 4 * lp_err + 0.0015 * paper_nm
    assert abs(lp_nm - paper_nm * T / 310) > 4 * lp_err  # control: 310 K is refused


def jacobian_diagonal(f, y, eps=1e-6):
    """d f_k / d y_k by central differences (error of order eps^2, ~1e-12 here)."""
    out = np.empty(y.size)
    for k in range(y.size):
        yp, ym = y.copy(), y.copy()
        yp[k] += eps
        ym[k] -= eps
        out[k] = (f(yp)[k] - f(ym)[k]) / (2 * eps)
    return out


def test_conservative_rhs_has_zero_divergence():
    """Liouville: the divergence of the semi-discrete RHS in (gamma, omega, Gamma, Omega) is
    zero at every point (docs/thermal.md), for a coupled K, a coupled I and rho != 1, at a
    thermal state. Single diagonal entries are not: omega x I omega gives I^-1 [I omega]_x -
    I^-1 [omega]_x I, whose trace vanishes (symmetric times antisymmetric) but whose diagonal
    entries vanish only for a diagonal I -- the test sees both."""
    N = 24
    sim = rodcore.Simulation(straight(N, 6.0, 1e-2, 5))
    y = np.concatenate([sim.state[k].T.ravel() for k in ("gamma", "omega", "Gamma", "Omega")])
    diag = jacobian_diagonal(sim.rhs, y).reshape(12, N)
    assert np.max(np.abs(diag.sum(0))) < 1e-8          # per-point divergence
    assert np.max(np.abs(diag[3:5])) > 1e-3             # the coupled I's entries are not zero
    # control: a friction of 1e-6 on gamma (divergence -3e-6 per point) is seen
    zeta = 1e-6
    damped = jacobian_diagonal(lambda v: sim.rhs(v) - zeta * np.r_[v[:3 * N], np.zeros(9 * N)], y)
    assert np.allclose(damped.reshape(12, N).sum(0), -3 * zeta, atol=1e-8)


def test_dna_bend_persistence_from_the_tangent_correlation_of_a_ring():
    """A stress-free, intrinsically circular ring (exact for the sampler) of the paper's DNA
    material at 300 K, 40 persistence lengths long, 4096 points (1.9 bp each): t = r'/|r'|
    from the directors and Gamma. The linear theory (the frame's mean propagator
    exp(M s), M = [Omega0]_x - diag(q + q3, q + q3, 2 q) / 2, q = 1/lp, q3 = kT/D3) times the
    mean shear tilt of the tangent, A = <Gamma3 / |Gamma|>^2 (1 - 2 kT/(h C) to first order),
    fitted for lp over s < lp/2; error by jackknife over 60 independent rings."""
    from scipy.linalg import expm
    from scipy.optimize import minimize_scalar
    kT = UNITS.kT_to_rod(300.0)
    D = UNITS.D_star
    lp = D[0] / kT
    L, N = 40 * lp, 4096
    h, k0 = L / N, 2 * np.pi / L
    K = int(lp / 2 / h)
    corr, tilt = [], []
    for seed in range(1, 61):
        sim = rodcore.Simulation({"rod": {"length": L, "points": N, "Gamma0": [0, 0, 1.0], "Omega0": [0, k0, 0]},
                                  "thermal": {"temperature_K": 300.0, "seed": seed},
                                  "output": {"t_end": 1.0, "fields": ["directors"]}})
        frame = {}
        sim.add_observer(lambda f: frame.setdefault("d", f["directors"]))
        sim.step_to(0.0)
        G = sim.state["Gamma"]
        t = np.einsum("iak,ik->ia", frame["d"], G) / np.linalg.norm(G, axis=1)[:, None]
        F = np.fft.rfft(t, axis=0)
        corr.append(np.fft.irfft((F * F.conj()).sum(1), n=N)[1:K + 1] / N)  # <t(s_i).t(s_i + s)>
        tilt.append(np.mean(G[:, 2] / np.linalg.norm(G, axis=1)))
    corr, tilt = np.array(corr), np.array(tilt)
    s = np.arange(1, K + 1) * h

    def model(lp_, q3=kT / D[2]):
        M = np.array([[0, 0, k0], [0, 0, 0], [-k0, 0, 0]]) - 0.5 * np.diag([1 / lp_ + q3, 1 / lp_ + q3, 2 / lp_])
        return np.array([expm(M * x)[2, 2] for x in s])

    def fit(c, A):
        return minimize_scalar(lambda x: np.sum((A * model(x) - c) ** 2), bounds=(0.5 * lp, 2 * lp),
                               method="bounded", options={"xatol": 1e-3}).x

    M = len(corr)
    est = fit(corr.mean(0), tilt.mean() ** 2)
    jack = [fit(np.delete(corr, j, 0).mean(0), np.delete(tilt, j).mean() ** 2) for j in range(M)]
    err = math.sqrt((M - 1) * np.var(jack))
    to_nm = UNITS.ell_A / 10
    assert abs(est - lp) < 4 * err, (est * to_nm, err * to_nm, lp * to_nm)
    assert abs(est * to_nm - 66.4) < 4 * err * to_nm + 0.1
    assert tilt.mean() ** 2 == pytest.approx(1 - 2 * kT / h, abs=2e-4)  # C1 = C2 = 1
    assert abs(est - lp * 300 / 330) > 4 * err  # control: 330 K is refused
