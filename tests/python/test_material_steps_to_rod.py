"""The exact step -> rod map, its stiffness Jacobian, the unit factors and the
grid interpolation, each against an independent truth."""
import numpy as np
import pytest
from scipy.linalg import expm

from dna_models.sequence import random_sequence
from dna_models.units import BOLTZMANN, Units
from mdbridge.geometry import step_parameters
from mdbridge.rod.material.parameter_sets import olson1998_steps, paper_steps
from mdbridge.rod.material.steps_to_rod import (grid_material, rod_material, rod_stiffness, steps_from_strains,
                                            strains_from_steps)

U = Units.paper()
H_A = 3.38


def _twist_matrix(Gamma, Omega, h):
    """4x4 se(3) element of a rod piece with constant strains, for scipy's expm."""
    X = np.zeros((4, 4))
    w = Omega * h
    X[:3, :3] = [[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]]
    X[:3, 3] = Gamma * h
    return X


def test_round_trip_through_independent_exponential():
    """step params -> (Gamma, Omega) -> frames by scipy's matrix exponential of the
    constant-strain piece (not the code's own exp) -> 3DNA analysis -> step params."""
    sm = olson1998_steps(random_sequence(158, seed=5))
    rng = np.random.default_rng(1)
    p = sm.step_params + rng.normal(0, 1, sm.step_params.shape) * [0.5, 0.5, 0.2, 5, 5, 5]  # also far from rest
    G, O = strains_from_steps(p, H_A)
    h = U.length_to_rod(H_A)
    back = np.empty_like(p)
    for i in range(len(p)):
        T = expm(_twist_matrix(G[i], O[i], h))
        back[i] = step_parameters(np.eye(3), np.zeros(3), T[:3, :3], T[:3, 3] * U.ell_A)
    assert np.max(np.abs(back - p)) < 1e-10
    assert np.max(np.abs(steps_from_strains(G, O, H_A) - p)) < 1e-10


def test_not_the_omega_times_rise_approximation():
    """Control: (tilt, roll, twist)/h and (shift, slide, rise)/h are not the strains
    (at 34 deg of twist the mid-step frame and the rotation vector differ)."""
    p = np.array([0.3, -0.5, 3.3, -1.7, 4.5, 31.9])
    G, O = strains_from_steps(p, H_A)
    h = U.length_to_rod(H_A)
    naive_O = np.radians(p[3:]) / h
    naive_G = p[:3] / U.ell_A / h
    assert np.max(np.abs(O - naive_O)) > 1e-3 * np.linalg.norm(O)
    assert np.max(np.abs(G - naive_G)) > 1e-3 * np.linalg.norm(G)


def test_stiffness_by_energy_finite_differences():
    """E_step(p(x)) [kT] of the exact nonlinear map equals the rod's h/2 dx^T K dx
    [rod energy] / kT* to second order: the mismatch / E falls linearly with the amplitude."""
    sm = olson1998_steps("ACGTTAGC", closed=True)
    K = rod_stiffness(sm.stiffness, sm.step_params, sm.temperature_K, H_A)
    G0, O0 = strains_from_steps(sm.step_params, H_A)
    x0 = np.concatenate([G0, O0], axis=1)
    kT = BOLTZMANN * sm.temperature_K / (U.C * U.ell_m)
    h = U.length_to_rod(H_A)
    rng = np.random.default_rng(3)
    for i in range(len(x0)):
        y = rng.normal(size=6) * [0.05, 0.05, 0.02, 0.05, 0.05, 0.05]
        errs = []
        for eps in (1e-2, 5e-3, 2.5e-3):
            x = x0[i] + eps * y
            dp = steps_from_strains(x[:3], x[3:], H_A) - sm.step_params[i]
            E_step = 0.5 * dp @ sm.stiffness[i] @ dp              # kT
            E_rod = 0.5 * h * (eps * y) @ K[i] @ (eps * y) / kT    # kT
            errs.append(abs(E_step - E_rod) / E_rod)
        assert errs[0] < 0.05
        assert errs[1] / errs[0] == pytest.approx(0.5, abs=0.1) or errs[1] < 1e-9
        assert errs[2] / errs[1] == pytest.approx(0.5, abs=0.1) or errs[2] < 1e-9


def test_paper_set_is_the_default_material():
    sm = paper_steps(random_sequence(30, seed=2))
    rm = rod_material(sm)
    Kd = np.diag(list(U.C_star) + list(U.D_star))
    assert np.max(np.abs(rm.K - Kd)) < 1e-9
    assert np.allclose(rm.Gamma0, [0, 0, 1], atol=1e-13)
    assert np.allclose(rm.Omega0, [0, 0, 2 * np.pi / (158 / 15) / U.length_to_rod(3.38)], atol=1e-12)
    assert np.allclose(rm.rho, 1.0, rtol=1e-13) and np.allclose(rm.I, np.diag([1.0, 1, 2]), atol=1e-13)


def test_unit_factors_by_equipartition():
    """Independent check of kT, deg -> rad and per step -> per length: for a
    diagonal twist-only step stiffness F_tw [kT/deg^2], the rod's twist modulus K66
    gives <dOmega3^2> h = kT*/K66 ... i.e. K66 = F_tw (180/pi)^2 kT / (h C l^2) in SI."""
    sm = paper_steps("ACGTACGTAC")
    F = np.diag([10.0, 10, 30, 0.1, 0.06, 0.062])
    p = sm.step_params[0]
    K = rod_stiffness(F, p, 298.0, H_A)
    kT = BOLTZMANN * 298.0
    h = H_A * 1e-10
    D3_SI = 0.062 * (180 / np.pi) ** 2 * kT * h          # J m, a rod piece of length h
    C3_SI = 30.0 * kT / 1e-20 * h                        # N
    assert K[5, 5] == pytest.approx(D3_SI / (U.C * U.ell_m**2), rel=1e-6)
    assert K[2, 2] == pytest.approx(C3_SI / U.C, rel=2e-2)   # J(rise) includes a small twist coupling
    # the twist-rise block is exact because the step is straight (no bend): rise = h Gamma3
    assert np.linalg.inv(K)[2, 2] == pytest.approx(U.C / C3_SI, rel=1e-6)


def test_grid_values_at_their_points_and_errors():
    rm = rod_material(olson1998_steps(random_sequence(12, seed=4)))
    g = grid_material(rm, 24, "trig")              # even m: step midpoints are grid points
    assert np.allclose(g["K"][1::2], rm.K, atol=1e-10)
    assert np.allclose(g["Omega0"][1::2], rm.Omega0, atol=1e-12)
    assert np.allclose(g["rho"][0::2], rm.rho, atol=1e-12)
    for interp in ("trig", "smooth", "step"):
        gg = grid_material(rm, 36, interp)
        assert np.linalg.eigvalsh(gg["K"])[:, 0].min() > 0
    gs = grid_material(rm, 24, "step")
    assert np.allclose(gs["K"][1::2], rm.K) and np.allclose(gs["K"][2], 0.5 * (rm.K[0] + rm.K[1]))
    from dna_models.errors import InputError
    with pytest.raises(InputError, match="multiple of n_bp = 12"):
        grid_material(rm, 30)
    with pytest.raises(InputError, match="allowed trig, smooth, step"):
        grid_material(rm, 24, "linear")


def derivative(f, L, space):
    """d/ds of periodic grid data f (N,) as the solver's operators are defined
    (docs/numerics.md, "Spatial derivative operators"): Fourier with the Nyquist mode
    zeroed, or the 4th-order central difference."""
    N = f.shape[0]
    if space == "spectral":
        k = np.fft.rfftfreq(N, d=L / N) * 2 * np.pi
        if N % 2 == 0:
            k[-1] = 0.0
        return np.fft.irfft(1j * k * np.fft.rfft(f), n=N)
    h = L / N
    return (-np.roll(f, -2) + 8 * np.roll(f, -1) - 8 * np.roll(f, 1) + np.roll(f, 2)) / (12 * h)


def _operator_errors(interp, space, ms, n=16):
    """max |D f - f'| / max|f'| for f = K33(s) cos(2 pi s / L), on N = m n points, with
    f' from the spectral derivative on a 64 n grid of the same (N-independent) field."""
    rm = rod_material(olson1998_steps(random_sequence(n, seed=9)))
    L = rm.length
    gf = grid_material(rm, 64 * n, interp)
    ff = gf["K"][:, 2, 2] * np.cos(2 * np.pi * gf["s"] / L)
    dref = derivative(ff, L, "spectral")
    out = []
    for m in ms:
        g = grid_material(rm, m * n, interp)
        f = g["K"][:, 2, 2] * np.cos(2 * np.pi * g["s"] / L)
        d = derivative(f, L, space)
        out.append(np.max(np.abs(d - dref[:: 64 // m])) / np.max(np.abs(dref)))
    return np.array(out)


def test_convergence_of_the_operators_on_the_interpolated_material(capsys):
    ms = [2, 4, 8, 16]
    e = {(i, s): _operator_errors(i, s, ms) for i in ("trig", "smooth", "step") for s in ("spectral", "fd4")}
    with capsys.disabled():
        print("\n  interp/space   " + "  ".join(f"m={m:<7d}" for m in ms))
        for k, v in e.items():
            print(f"  {k[0]:7s}{k[1]:9s}" + "  ".join(f"{x:9.2e}" for x in v))
    # analytic fields: spectral converges exponentially, FD4 at 4th order
    assert e[("trig", "spectral")][-1] < 1e-9 and e[("smooth", "spectral")][-1] < 1e-9
    for i in ("trig", "smooth"):
        order = np.log2(e[(i, "fd4")][-2] / e[(i, "fd4")][-1])
        assert 3.5 < order < 4.6, (i, order)
    # piecewise constant: the derivative of a jump does not converge (Gibbs / O(1) at jumps)
    assert e[("step", "spectral")][-1] > 0.1 and e[("step", "fd4")][-1] > 0.1


@pytest.mark.parametrize("n, m", [(21, 1), (20, 2)])
def test_exact_shape_reproduces_the_steps(n, m):
    """shape = "exact": integrate dR/ds = R [Omega0]x, dr/ds = R Gamma0 along the
    trigonometric interpolant of the grid values (scipy's ODE solver, independent of
    the composition code) and analyse the base-pair frames with 3DNA: the Olson
    steps to 2e-3 deg / 3e-4 A; the interpolated shape misses them by ~1 deg (control)."""
    from scipy.integrate import solve_ivp
    from mdbridge.geometry import step_parameters_along
    from mdbridge.rod.frames import trig_interpolate
    sm = olson1998_steps(random_sequence(n, seed=1))
    rm = rod_material(sm)
    L, N = rm.length, n * m
    errs = {}
    for shape in ("exact", "interpolated"):
        g = grid_material(rm, N, shape=shape)
        x = np.concatenate([g["Gamma0"], g["Omega0"]], axis=1)

        def f(s, y):
            R = y[:9].reshape(3, 3)
            G, O = np.split(trig_interpolate(x, 0.0, L / N, [s])[0], 2)
            W = np.array([[0, -O[2], O[1]], [O[2], 0, -O[0]], [-O[1], O[0], 0]])
            return np.concatenate([(R @ W).ravel(), R @ G])

        sol = solve_ivp(f, (0, L), np.concatenate([np.eye(3).ravel(), np.zeros(3)]), method="DOP853",
                        rtol=1e-11, atol=1e-12, t_eval=np.arange(n + 1) * rm.h)
        R = sol.y[:9].T.reshape(-1, 3, 3)
        o = sol.y[9:].T * U.ell_A
        errs[shape] = np.abs(step_parameters_along(R, o) - sm.step_params).max(axis=0)
    assert np.all(errs["exact"][:3] < 3e-4) and np.all(errs["exact"][3:] < 2e-3)
    assert errs["interpolated"][5] > 0.3
