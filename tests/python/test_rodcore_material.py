"""The general rod material (docs/numerics.md, "General
material"): a full symmetric positive-definite 6 x 6 K, a non-diagonal I and a
density rho, uniform or per grid point.

Independent truths, all written out here in numpy from the balance laws
(n, m) = K e, rho (gamma_t + omega x gamma) = n_s + Omega x n,
I omega_t + omega x I omega = m_s + Omega x m + Gamma x n and the two
compatibility equations -- never from the solver's output:
  * A_k, the 12 x 12 linearisation about the straight twisted rest state on a
    Fourier mode, with FD4's modified wavenumber for FD4;
  * a numpy RHS of the per-point material;
  * the energy 1/2 int rho|gamma|^2 + omega.I omega + e.K e ds.
"""
import math
import re

import h5py
import numpy as np
import pytest
from scipy.linalg import expm

import rodcore  # the installed module: a missing one fails (scripts/build.sh installs it)

L = 2 * math.pi
G0 = np.array([0.0, 0.0, 1.0])
O0 = np.array([0.0, 0.0, 1.0])  # straight, twisted


def full_K():
    """Every coupling non-zero, SPD (paper's diagonal plus a positive part)."""
    rng = np.random.default_rng(13)
    B = rng.normal(size=(6, 6))
    K = np.diag([1.0, 1.0, 1.19, 1.21, 1.21, 2.02]) + 0.04 * (B @ B.T) + 0.02
    assert np.all(K != 0) and np.all(np.linalg.eigvalsh(K) > 0)
    return K


I_FULL = np.array([[1.0, 0.1, 0.05], [0.1, 1.2, 0.08], [0.05, 0.08, 2.0]])
RHO = 1.3


def cross_matrix(v):
    return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


def A_k(k, K, I, rho, Gamma0=G0, Omega0=O0):
    """Linearisation about gamma = omega = 0, Gamma = Gamma0, Omega = Omega0
    (uniform), on a mode whose s-derivative is i k: A_k = A0 + i k A1."""
    Iinv = np.linalg.inv(I)
    Xo, Xg = cross_matrix(Omega0), cross_matrix(Gamma0)
    Kn, Km = K[:3], K[3:]
    A0 = np.zeros((12, 12))
    A1 = np.zeros((12, 12))
    A1[0:3, 6:12] = Kn / rho                       # n_s / rho
    A0[0:3, 6:12] = Xo @ Kn / rho                  # Omega0 x n / rho
    A1[3:6, 6:12] = Iinv @ Km                      # I^-1 m_s
    A0[3:6, 6:12] = Iinv @ (Xo @ Km + Xg @ Kn)     # I^-1 (Omega0 x m + Gamma0 x n)
    A1[6:9, 0:3] = np.eye(3)                       # gamma_s
    A0[6:9, 0:3] = Xo                              # Omega0 x gamma
    A0[6:9, 3:6] = Xg                              # - omega x Gamma0
    A1[9:12, 3:6] = np.eye(3)                      # omega_s
    A0[9:12, 3:6] = Xo                             # - omega x Omega0
    return A0 + 1j * k * A1


def k_eff(j, N, space):
    """Effective wavenumber of mode j on N points: exact for spectral, FD4's
    modified wavenumber (8 sin kh - sin 2kh) / 6h."""
    k, h = 2 * math.pi * j / L, L / N
    return k if space == "spectral" else (8 * math.sin(k * h) - math.sin(2 * k * h)) / (6 * h)


def rest(N, Gamma0=G0, Omega0=O0):
    y = np.zeros((12, N))
    y[6:9] = np.broadcast_to(np.asarray(Gamma0).reshape(3, -1), (3, N))
    y[9:12] = np.broadcast_to(np.asarray(Omega0).reshape(3, -1), (3, N))
    return y


def as_state(y):
    return {name: np.ascontiguousarray(y[3 * f:3 * f + 3].T)
            for f, name in enumerate(("gamma", "omega", "Gamma", "Omega"))}


def from_state(d):
    return np.concatenate([np.asarray(d[n]).T for n in ("gamma", "omega", "Gamma", "Omega")])


def scene(N, space, K=None, I=None, rho=None, material_file=None, rod_extra=None, **solver):
    sc = {"rod": {"length": L, "points": N, "Gamma0": list(G0), "Omega0": list(O0)},
          "material": {},
          "solver": {"space": space, "time": "dop853", "rtol": 1e-13, "atol": 1e-13, **solver},
          "output": {"t_end": 1.0, "frames": 2}}
    if rod_extra is not None:
        sc["rod"] = {"length": L, "points": N, **rod_extra}
    if K is not None:
        sc["material"]["K"] = np.asarray(K)
    if I is not None:
        sc["material"]["I"] = np.asarray(I)
    if rho is not None:
        sc["material"]["rho"] = rho
    if material_file is not None:
        sc["material"] = {"material_file": str(material_file)}
    return sc


def mode_field(v, j, N):
    """Re(v e^{i k s}) on the grid, v a complex 12-vector."""
    s = np.arange(N) * L / N
    return np.real(np.outer(v, np.exp(1j * 2 * math.pi * j / L * s)))


@pytest.mark.parametrize("space", ["spectral", "fd4"])
def test_rhs_jacobian_at_rest_is_A_k(space):
    """Central differences of the C++ RHS (exact: the RHS is quadratic) on
    cos and sin of mode j reproduce Re/Im of A_k; with FD4 only with FD4's
    modified wavenumber (control: the exact k misses by far more)."""
    N, K = 24, full_K()
    sc = scene(N, space, K=K, I=I_FULL, rho=RHO)
    y0 = rest(N)
    sim = rodcore.Simulation(sc)
    f0 = from_state(sim.rhs(as_state(y0)))
    assert np.max(np.abs(f0)) == 0.0  # the rest state is an equilibrium, exactly
    eps = 1e-4
    worst, worst_exact_k = 0.0, 0.0
    for j in (1, 3, 5):
        A = A_k(k_eff(j, N, space), K, I_FULL, RHO)
        A_exact = A_k(2 * math.pi * j / L, K, I_FULL, RHO)
        for c in range(12):
            for phase in (1.0, -1j):  # cos and sin modes
                v = np.zeros(12, complex)
                v[c] = phase
                d = mode_field(v, j, N)
                fp = from_state(sim.rhs(as_state(y0 + eps * d)))
                fm = from_state(sim.rhs(as_state(y0 - eps * d)))
                J = (fp - fm) / (2 * eps)
                worst = max(worst, np.max(np.abs(J - mode_field(A @ v, j, N))))
                worst_exact_k = max(worst_exact_k, np.max(np.abs(J - mode_field(A_exact @ v, j, N))))
    assert worst < 1e-9, worst
    if space == "fd4":
        assert worst_exact_k > 1e-3, worst_exact_k  # the modified wavenumber matters
    else:
        assert worst_exact_k < 1e-9


@pytest.mark.parametrize("space", ["spectral", "fd4"])
def test_linear_dynamics_follows_exp_A_k(space):
    """A single-mode state of amplitude a follows exp(A_k t) y0 up to t = 3
    (about 3 periods of the fastest branch); the discrepancy is the nonlinear
    part, so it doubles when a doubles (a = 1e-4, 2e-4), for k = 1, 2, 3."""
    N, K, T = 32, full_K(), 3.0
    rng = np.random.default_rng(7)
    for j in (1, 2, 3):
        v = rng.normal(size=12) + 1j * rng.normal(size=12)
        v /= np.max(np.abs(v))
        A = A_k(k_eff(j, N, space), K, I_FULL, RHO)
        errs = []
        for a in (1e-4, 2e-4):
            y0 = rest(N) + a * mode_field(v, j, N)
            sc = scene(N, space, K=K, I=I_FULL, rho=RHO)
            sc["output"] = {"t_end": T, "frames": 4}
            sc["solver"]["reduce"] = "off"
            out = rodcore.run(sc, initial=as_state(y0))
            err = 0.0
            for it, t in enumerate(out["time"]):
                y = from_state({k: out["fields"][k][it] for k in out["fields"]})
                pred = rest(N) + a * mode_field(expm(A * t) @ v, j, N)
                err = max(err, np.max(np.abs(y - pred)) / a)
            errs.append(err)
        ratio = errs[1] / errs[0]
        assert errs[0] < 1e-3, (j, errs)
        assert 1.8 < ratio < 2.2, (j, errs, ratio)


def test_rk4_limit_is_the_spectral_radius_of_A_k(rodsim, tmp_path):
    """The RK4 stability check of a coupled uniform material uses the exact
    spectral radius: numpy's max |eig A_k| over the same k samples."""
    N, K = 16, full_K()
    kmax = (N // 2 - 1) * 2 * math.pi / L  # spectral: the Nyquist mode is zeroed
    radius = max(np.max(np.abs(np.linalg.eigvals(A_k(kmax * m / 256, K, I_FULL, RHO)))) for m in range(257))
    sc = scene(N, "spectral", K=K, I=I_FULL, rho=RHO, time="rk4", dt=10.0)
    with pytest.raises(rodcore.NumericalError) as e:
        rodcore.run(sc)
    got = float(re.search(r"spectral radius ([0-9.e+-]+)", str(e.value)).group(1))
    assert abs(got - radius) < 1e-5 * radius, (got, radius)
    # Just below the limit runs; a diagonal-material estimate would differ.
    sc["solver"]["dt"] = 2.8 / radius * 0.999
    sc["output"]["t_end"] = 0.1
    rodcore.run(sc)


# ---- per-point material ---------------------------------------------------

def per_point_material(N):
    """Smooth s-dependent K, I, rho and intrinsic shape, SPD at every point."""
    s = np.arange(N) * L / N
    K0, rng = full_K(), np.random.default_rng(3)
    P = rng.normal(size=(6, 6))
    P = 0.05 * (P + P.T)
    K = K0[None] + np.sin(s)[:, None, None] * P[None] + 0.1 * np.cos(2 * s)[:, None, None] * np.eye(6)
    Q = np.array([[0.0, 0.05, 0.02], [0.05, 0.0, -0.03], [0.02, -0.03, 0.0]])
    I = I_FULL[None] + np.cos(s)[:, None, None] * Q[None]
    rho = 1.0 + 0.2 * np.sin(s + 0.3)
    Gamma0 = np.stack([0.05 * np.sin(s), 0.03 * np.cos(2 * s), 1.0 + 0.05 * np.cos(s)], axis=1)
    Omega0 = np.stack([0.1 * np.cos(s), -0.05 * np.sin(s), 1.0 + 0.1 * np.sin(2 * s)], axis=1)
    for i in range(N):
        assert np.all(np.linalg.eigvalsh(K[i]) > 0) and np.all(np.linalg.eigvalsh(I[i]) > 0)
    return K, I, rho, Gamma0, Omega0


def write_material(path, K, I, rho, Gamma0=None, Omega0=None, fmt="dnarod-material/1"):
    with h5py.File(path, "w") as f:
        f.attrs["format"] = fmt
        f["K"], f["I"], f["rho"] = K, I, rho
        if Gamma0 is not None:
            f["Gamma0"], f["Omega0"] = Gamma0, Omega0
    return path


def d_ds(f, space):
    """numpy derivative along the last axis, periodic grid of length L."""
    N = f.shape[-1]
    h = L / N
    if space == "fd4":
        r = lambda k: np.roll(f, -k, axis=-1)  # noqa: E731  f(s + k h)
        return (r(-2) - 8 * r(-1) + 8 * r(1) - r(2)) / (12 * h)
    F = np.fft.rfft(f, axis=-1)
    k = 2 * math.pi * np.arange(F.shape[-1]) / L
    dF = 1j * k * F
    if N % 2 == 0:
        dF[..., -1] = 0.0
    return np.fft.irfft(dF, n=N, axis=-1)


def numpy_rhs(y, K, I, rho, Gamma0, Omega0, space):
    """The balance laws with the derivative on n and m (per-point material)."""
    g, w, Gm, Om = y[0:3], y[3:6], y[6:9], y[9:12]
    e = np.concatenate([Gm - Gamma0.T, Om - Omega0.T])
    nm = np.einsum("irc,ci->ri", K, e)
    n, m = nm[:3], nm[3:]
    Iw = np.einsum("irc,ci->ri", I, w)
    cr = lambda a, b: np.cross(a.T, b.T).T  # noqa: E731
    tau = d_ds(m, space) + cr(Om, m) + cr(Gm, n) - cr(w, Iw)
    return np.concatenate([
        (d_ds(n, space) + cr(Om, n)) / rho - cr(w, g),
        np.linalg.solve(I, tau.T[..., None])[..., 0].T,
        d_ds(g, space) + cr(Om, g) - cr(w, Gm),
        d_ds(w, space) - cr(w, Om)])


def energy(y, K, I, rho, Gamma0, Omega0, couplings=True):
    N = y.shape[1]
    g, w = y[0:3], y[3:6]
    e = np.concatenate([y[6:9] - Gamma0.T, y[9:12] - Omega0.T])
    Kd = K if couplings else K * np.eye(6)[None]
    dens = rho * np.sum(g * g, axis=0) + np.einsum("ri,irc,ci->i", w, I, w) + np.einsum("ri,irc,ci->i", e, Kd, e)
    return 0.5 * L / N * np.sum(dens)


@pytest.mark.parametrize("space", ["spectral", "fd4"])
def test_numpy_rhs_of_per_point_material_agrees(tmp_path, space):
    N = 20
    K, I, rho, Gamma0, Omega0 = per_point_material(N)
    path = write_material(tmp_path / "mat.h5", K, I, rho, Gamma0, Omega0)
    sc = scene(N, space, material_file=path, rod_extra={})
    rng = np.random.default_rng(11)
    for _ in range(3):
        y = rest(N, Gamma0.T, Omega0.T) + 0.3 * rng.normal(size=(12, N))
        ref = numpy_rhs(y, K, I, rho, Gamma0, Omega0, space)
        got = from_state(rodcore.Simulation(sc).rhs(as_state(y)))
        assert np.max(np.abs(got - ref)) < 1e-12 * np.max(np.abs(ref)), np.max(np.abs(got - ref))


def smooth_state(N, Gamma0, Omega0, amp=0.05):
    s = np.arange(N) * L / N
    rng = np.random.default_rng(5)
    y = rest(N, Gamma0.T, Omega0.T)
    for j in (1, 2, 3):
        y += amp / j * (np.outer(rng.normal(size=12), np.cos(j * s)) + np.outer(rng.normal(size=12), np.sin(j * s)))
    return y


@pytest.mark.parametrize("space", ["spectral", "fd4"])
@pytest.mark.parametrize("kind", ["coupled", "per_point"])
def test_energy_conserved_with_couplings(tmp_path, space, kind):
    """DOP853 at rtol = atol = 1e-13 to t = 5: the energy, computed in numpy
    with the coupling terms and the full I, stays to 1e-10 relative; rodcore's
    energy and energy_parts agree with it. Control: without the off-diagonal
    terms of K the sum is not conserved."""
    N = 32
    if kind == "coupled":
        K1, I1 = full_K(), I_FULL
        K, I, rho = np.repeat(K1[None], N, 0), np.repeat(I1[None], N, 0), np.full(N, RHO)
        Gamma0, Omega0 = np.tile(G0, (N, 1)), np.tile(O0, (N, 1))
        sc = scene(N, space, K=K1, I=I1, rho=RHO)
    else:
        K, I, rho, Gamma0, Omega0 = per_point_material(N)
        sc = scene(N, space, material_file=write_material(tmp_path / "m.h5", K, I, rho, Gamma0, Omega0),
                   rod_extra={})
    sc["output"] = {"t_end": 5.0, "frames": 6, "fields": ["internal", "energy", "energy_parts"]}
    out = rodcore.run(sc, initial=as_state(smooth_state(N, Gamma0, Omega0)))
    ys = [from_state({k: out["fields"][k][it] for k in out["fields"]}) for it in range(len(out["time"]))]
    E = np.array([energy(y, K, I, rho, Gamma0, Omega0) for y in ys])
    assert np.max(np.abs(E - E[0])) / E[0] < 1e-10, np.max(np.abs(E - E[0])) / E[0]
    np.testing.assert_allclose(out["energy"], E, rtol=1e-13)
    parts = out["energy_parts"]
    assert "coupling" in parts
    np.testing.assert_allclose(sum(parts.values()), E, rtol=1e-13)
    E_diag = np.array([energy(y, K, I, rho, Gamma0, Omega0, couplings=False) for y in ys])
    assert np.max(np.abs(E_diag - E_diag[0])) / E_diag[0] > 1e-6


def test_diagonal_K_is_the_paper_material():
    """K = diag(C, D) given as a matrix is the same scene as C, D (the fast
    diagonal kernel), so every existing result holds for it."""
    N = 16
    C, D = [1.0, 1.0, 1.19], [1.21, 1.21, 2.0207]
    a = scene(N, "spectral")
    a["material"] = {"C": C, "D": D, "I": [1.0, 1.0, 2.0]}
    b = scene(N, "spectral", K=np.diag(C + D), I=np.diag([1.0, 1.0, 2.0]))
    y = smooth_state(N, np.tile(G0, (N, 1)), np.tile(O0, (N, 1)), amp=0.2)
    fa, fb = rodcore.Simulation(a).rhs(as_state(y)), rodcore.Simulation(b).rhs(as_state(y))
    for k in fa:
        assert np.array_equal(fa[k], fb[k])
    assert rodcore.resolve(a) == rodcore.resolve(b)


# ---- reduced planar system -------------------------------------------------

def planar_run(K, reduce):
    """Untwisted rod, omega2-polarised planar initial state (gamma1, gamma3,
    omega2, Gamma1, Gamma3, Omega2 only)."""
    N = 32
    s = np.arange(N) * L / N
    y = rest(N, [0, 0, 1.0], [0, 0, 0])
    for r, amp in ((0, 0.1), (2, 0.03), (4, 0.05), (6, 0.08), (8, 0.02), (10, 0.06)):
        y[r] += amp * np.sin(2 * s + r)
    sc = scene(N, "spectral", K=K, I=[[1.0, 0, 0], [0, 1.0, 0.0], [0, 0, 2.0]], reduce=reduce)
    sc["rod"]["Omega0"] = [0.0, 0.0, 0.0]
    sc["output"] = {"t_end": 2.0, "frames": 3}
    return rodcore.run(sc, initial=as_state(y))


def test_reduction_only_where_the_material_keeps_the_subspace():
    base = np.diag([1.0, 1.0, 1.19, 1.21, 1.21, 2.02])
    # Couples kept strains only to kept ones (shear1-bend2, shear1-stretch)
    # and zero ones to zero ones (tilt-twist): the omega2 plane stays invariant.
    keeps = base.copy()
    for (r, c, v) in ((0, 4, 0.2), (0, 2, 0.1), (3, 5, 0.15), (1, 3, 0.1)):
        keeps[r, c] = keeps[c, r] = v
    # Twist-stretch coupling (DNA overwinds when pulled): Gamma3 drives Omega3.
    breaks = base.copy()
    breaks[2, 5] = breaks[5, 2] = 0.2
    ok, ok_full = planar_run(keeps, "auto"), planar_run(keeps, "off")
    assert ok["summary"]["reduced"], ok["summary"]["reduce_note"]
    for k in ok["fields"]:
        np.testing.assert_allclose(ok["fields"][k], ok_full["fields"][k], rtol=0, atol=1e-11)
    assert np.all(ok_full["fields"]["Omega"][:, :, 2] == 0.0)  # the full system stays planar too
    no = planar_run(breaks, "auto")
    assert not no["summary"]["reduced"]
    assert "K[2][5]" in no["summary"]["reduce_note"], no["summary"]["reduce_note"]
    # ... and refusing was necessary: the full system leaves the plane.
    assert np.max(np.abs(no["fields"]["Omega"][-1, :, 2])) > 1e-4


# ---- bad input ---------------------------------------------------------------

def bad(sc, *needles):
    with pytest.raises(rodcore.InputError) as e:
        rodcore.resolve(sc)
    msg = str(e.value)
    for n in needles:
        assert n in msg, msg
    return msg


def test_bad_material_input_is_named(tmp_path):
    N, K = 16, full_K()
    asym = K.copy()
    asym[0, 3] += 0.1
    bad(scene(N, "spectral", K=asym), "material.K", "not symmetric", "[0][3]", "symmetric positive-definite 6 x 6")
    neg = K.copy()
    neg[2, 2] = -1.0
    bad(scene(N, "spectral", K=neg), "material.K", "not positive definite", "smallest eigenvalue")
    bad(scene(N, "spectral", K=K[:5]), "material.K", "6 x 6")
    bad(scene(N, "spectral", K=K[:, :5]), "material.K[0]", "6 numbers")
    nan = K.copy()
    nan[1, 4] = nan[4, 1] = np.nan
    bad(scene(N, "spectral", K=nan), "material.K[1][4]", "nan")
    bad(scene(N, "spectral", I=[[1.0, 2.0, 0], [2.0, 1.0, 0], [0, 0, 1.0]]), "material.I", "not positive definite",
        "3 x 3")
    bad(scene(N, "spectral", rho=-1.0), "material.rho", "> 0")
    both = scene(N, "spectral", K=K)
    both["material"]["C"] = [1.0, 1.0, 1.0]
    bad(both, "material.C", "not both")
    # Material file: wrong N, a non-SPD point, a missing format, a shape given twice.
    Kp, Ip, rho, G, O = per_point_material(N)
    p = write_material(tmp_path / "short.h5", Kp[:-1], Ip[:-1], rho[:-1])
    bad(scene(N, "spectral", material_file=p, rod_extra={}), "material.material_file", "short.h5", "'K'",
        "15 x 6 x 6", "expected 16 x 6 x 6")
    Kb = Kp.copy()
    Kb[7] = -Kb[7]
    p = write_material(tmp_path / "neg.h5", Kb, Ip, rho)
    bad(scene(N, "spectral", material_file=p, rod_extra={}), "dataset 'K' at point 7", "not positive definite")
    Ib = Ip.copy()
    Ib[3, 0, 1] += 0.5
    p = write_material(tmp_path / "asym.h5", Kp, Ib, rho)
    bad(scene(N, "spectral", material_file=p, rod_extra={}), "dataset 'I' at point 3", "not symmetric")
    p = write_material(tmp_path / "fmt.h5", Kp, Ip, rho, fmt="something")
    bad(scene(N, "spectral", material_file=p, rod_extra={}), "attribute 'format'", "dnarod-material/1")
    p = write_material(tmp_path / "shape.h5", Kp, Ip, rho, G, O)
    bad(scene(N, "spectral", material_file=p), "rod.Gamma0", "not both")
    with_k = scene(N, "spectral", material_file=p, rod_extra={})
    with_k["material"]["rho"] = 1.0
    bad(with_k, "material.rho", "not both")


def test_bad_K_in_a_scene_file_names_file_and_line(rodsim, tmp_path):
    import subprocess
    f = tmp_path / "s.toml"
    f.write_text("[rod]\nlength = 6.28\npoints = 16\n[material]\n"
                 "K = [[1,0,0,0,0,0],[0,1,0,0,0,0],[0,0,1,0,0,0],[0,0,0,1,0,0],[0,0,0,0,1,0],[0,0,0.5,0,0,1]]\n")
    r = subprocess.run([str(rodsim), "run", str(f), "-o", str(tmp_path / "o.h5")], capture_output=True, text=True)
    assert r.returncode == 2
    assert f"{f}:5: material.K: not symmetric: [2][5] = 0 but [5][2] = 0.5" in r.stderr, r.stderr
