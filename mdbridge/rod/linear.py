"""The linearised rod: the normal modes of a uniform rod about its uniform state under an
axial tension, read off rodcore's own right-hand side.

Why from the RHS: the physics exists once (rodcore/src/rhs.cpp). For a uniform material
(any symmetric 6x6 K, 3x3 I, rho) and a uniform state (constant Gamma, Omega; a straight
twisted rod, or the helix that a uniform intrinsic tilt/roll makes) the linearised
equations have constant coefficients in the body frame, so every body-frame Fourier mode
v e^{iks} is carried into itself: the linear operator is one 12 x 12 matrix A(k) per k.
The RHS is quadratic in the fields (linear constitutive law, cross products), so a central
difference of it is its exact derivative up to round-off, and the operator on the grid is
circulant: A(k) is the discrete Fourier transform of the response to one perturbed point
(12 Jacobian-vector products in all).

Laboratory wavenumbers. The rest state turns its body frame about the Darboux axis
e = Omega / |Omega| at |Omega| per unit arclength (R0(s) = exp(s [Omega]x)). A transverse
body field with circular components c+ = v_a + i v_b and c- = v_a - i v_b (a, b an
orthonormal pair perpendicular to e) that goes as e^{iks} is, in the laboratory, the sum of
waves of wavenumber k + |Omega| (weight |c+|^2) and |Omega| - k (weight |c-|^2). Components
along e (twist, stretch) keep their wavenumber. A periodic (ligated) rod has an integer
number of turns, |Omega| L = 2 pi turns, so lab wavenumbers are 2 pi n / L with integer n:
the mode number the MD's analysis uses (mdbridge/analysis/modes.py).

Tension. The state about which we linearise is the uniform equilibrium with axial force
n = T e and total rotation held at the ligated value (|Omega| L = 2 pi turns): in a
ligated duplex the linking number fixes the twist and the box length sets the tension,
which the MD measures (mdbridge/md/gromacs/tension.py).

Everything here is in the rod's dimensionless units (paper Sec 2.2; dna_models/units.py
converts). docs/dispersion.md states the method and its checks.
"""
from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np
from scipy.optimize import least_squares

from dna_models.errors import InputError, NumericalError

KINDS = ("bend", "shear", "stretch", "twist")


@dataclass(frozen=True)
class UniformMaterial:
    """A uniform rod material in rod units: K (6, 6) on (Gamma - Gamma0, Omega - Omega0),
    I (3, 3), rho, and the intrinsic (rest) strains Gamma0, Omega0."""
    K: np.ndarray
    I: np.ndarray
    rho: float
    Gamma0: np.ndarray
    Omega0: np.ndarray

    @classmethod
    def paper(cls, Omega03: float = 0.0) -> "UniformMaterial":
        """The paper's DNA rod (Sec 2.1-2.2, the solver's default material), straight,
        with intrinsic twist Omega03."""
        from dna_models.units import Units
        u = Units.paper()
        return cls(K=np.diag([*u.C_star, *u.D_star]), I=np.diag(u.I_star), rho=1.0,
                   Gamma0=np.array([0.0, 0.0, 1.0]), Omega0=np.array([0.0, 0.0, Omega03]))

    @classmethod
    def from_dict(cls, mat: dict) -> "UniformMaterial":
        """From the coarse-graining's material dict (K_star, I_star, rho_star, Gamma0_star,
        Omega0_star: mdbridge/coarsegrain/cgrod.py)."""
        return cls(K=np.asarray(mat["K_star"], float), I=np.asarray(mat["I_star"], float),
                   rho=float(mat["rho_star"]), Gamma0=np.asarray(mat["Gamma0_star"], float),
                   Omega0=np.asarray(mat["Omega0_star"], float))

    def scene(self, length: float, points: int) -> dict:
        return {"rod": {"length": float(length), "points": int(points),
                        "Gamma0": [float(x) for x in self.Gamma0],
                        "Omega0": [float(x) for x in self.Omega0]},
                "material": {"K": np.asarray(self.K, float), "I": np.asarray(self.I, float),
                             "rho": float(self.rho)},
                "initial": {"kind": "rest"}, "output": {"t_end": 1.0, "frames": 2},
                # spectral d/ds: exact on every resolved Fourier mode, so A(k) is the
                # continuum operator for |k| < pi N / L ("auto" picks fd4 for a state at
                # rest, whose fields have no smooth content to measure)
                "solver": {"space": "spectral"}}


@dataclass(frozen=True)
class Mode:
    """One normal mode: kind (bend, shear, stretch, twist: the block holding most of its
    kinetic energy), lab mode number n >= 0, angular frequency omega (1/tau), the body
    wavenumber k it came from, its circular handedness about the axis (+1/-1; 0 for axial
    modes), and purity (the fraction of its kinetic energy in its kind's block)."""
    kind: str
    n: int
    omega: float
    k: float
    handedness: int
    purity: float

    def as_dict(self) -> dict:
        return asdict(self)


def _unit(v) -> np.ndarray:
    v = np.asarray(v, float)
    return v / np.linalg.norm(v)


def _axis_basis(Omega: np.ndarray) -> np.ndarray:
    """Rows a, b, e: e along the Darboux axis (d3 when the rod is untwisted and straight),
    a and b completing a right-handed orthonormal frame (a x b = e)."""
    e = _unit(Omega) if np.linalg.norm(Omega) > 1e-14 else np.array([0.0, 0.0, 1.0])
    t = np.array([1.0, 0.0, 0.0]) if abs(e[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    a = _unit(t - e * (t @ e))
    return np.array([a, np.cross(e, a), e])


def uniform_state(mat: UniformMaterial, tension: float, twist_per_length: float | None = None):
    """(Gamma, Omega) of the uniform equilibrium with axial force `tension` along the
    Darboux axis and |Omega| = twist_per_length (default: the rest state's |Omega0|).

    A uniform state is in balance when Omega x n = 0 and Omega x m + Gamma x n = 0 (the
    RHS of a uniform state at rest: no s-derivatives); with n = T e, e = Omega/|Omega|,
    that is 2 + 2 conditions, and n.e = T, |Omega| = given make six for six unknowns."""
    K = np.asarray(mat.K, float)
    q0 = np.concatenate([mat.Gamma0, mat.Omega0])
    w = float(np.linalg.norm(mat.Omega0) if twist_per_length is None else twist_per_length)

    def residual(q):
        G, O = q[:3], q[3:]
        nm = K @ (q - q0)
        n, m = nm[:3], nm[3:]
        e = _unit(O) if np.linalg.norm(O) > 1e-14 else np.array([0.0, 0.0, 1.0])
        return np.concatenate([np.cross(O, n), np.cross(O, m) + np.cross(G, n),
                               [n @ e - tension, np.linalg.norm(O) - w]])

    start = q0 + np.linalg.solve(K, np.array([0.0, 0.0, tension, 0.0, 0.0, 0.0]))
    if np.linalg.norm(start[3:]) > 1e-14:
        start[3:] *= w / np.linalg.norm(start[3:])
    sol = least_squares(residual, start, xtol=1e-15, ftol=1e-15, gtol=1e-15)
    if np.abs(residual(sol.x)).max() > 1e-10 * max(1.0, abs(tension)):
        raise NumericalError(f"no uniform equilibrium at tension {tension:g} (rod units): "
                             f"balance residual {np.abs(residual(sol.x)).max():.2e}")
    return sol.x[:3].copy(), sol.x[3:].copy()


class LinearRod:
    """The linear operator of a uniform rod of fiducial length L on N points about its
    uniform equilibrium at a tension (rod units), through rodcore's RHS."""

    def __init__(self, mat: UniformMaterial, length: float, points: int, tension: float = 0.0,
                 turns: float | None = None):
        import rodcore  # type: ignore  # the compiled module (mdbridge/rod/run.py installs the check)
        if points < 4:
            raise InputError(f"points = {points}: need at least 4")
        self.mat, self.L, self.N = mat, float(length), int(points)
        twist = None if turns is None else 2.0 * np.pi * float(turns) / self.L
        self.Gamma, self.Omega = uniform_state(mat, tension, twist)
        self.tension = float(tension)
        sim = rodcore.Simulation(mat.scene(self.L, self.N))
        self._rhs = sim.rhs
        N = self.N
        y0 = np.zeros((12, N))
        y0[6:9] = self.Gamma[:, None]
        y0[9:12] = self.Omega[:, None]
        self.y0 = y0
        f0 = self._rhs(y0.ravel())
        scale = max(1.0, float(np.abs(K_times(mat, self.Gamma, self.Omega)).max()))
        if np.abs(f0).max() > 1e-9 * scale:
            raise NumericalError(f"the uniform state is not at rest in rodcore: |rhs| = {np.abs(f0).max():.2e}")
        # The response to one perturbed point, per component: columns of the circulant operator.
        h = 1e-3
        self._G = np.empty((12, 12, N))        # [j (perturbed), i (response), point]
        for j in range(12):
            v = np.zeros((12, N))
            v[j, 0] = 1.0
            fp = self._rhs((y0 + h * v).ravel())
            fm = self._rhs((y0 - h * v).ravel())
            self._G[j] = ((fp - fm) / (2 * h)).reshape(12, N)
        self._Ghat = np.fft.fft(self._G, axis=-1)  # [j, i, m]: A(k_m)[i, j]
        self.basis = _axis_basis(self.Omega)

    def k(self, m: int) -> float:
        return 2.0 * np.pi * m / self.L

    def operator(self, m: int) -> np.ndarray:
        """A(k_m), k_m = 2 pi m / L: d/dt (v e^{i k s}) = (A v) e^{i k s}."""
        return self._Ghat[:, :, m % self.N].T.copy()

    def jacobian(self) -> np.ndarray:
        """The whole 12 N x 12 N linear operator (for checks on small N)."""
        N = self.N
        J = np.zeros((12 * N, 12 * N))
        for j in range(12):
            for p in range(N):
                col = np.roll(self._G[j], p, axis=-1)      # perturbation at point p
                J[:, j * N + p] = col.ravel()
        return J

    def _classify(self, v: np.ndarray, m: int) -> tuple[str, int, int, float]:
        B = self.basis
        gam, om = B @ v[0:3], B @ v[3:6]
        Ib = B @ np.asarray(self.mat.I, float) @ B.T
        ke = {"bend": self.mat.rho * (abs(gam[0]) ** 2 + abs(gam[1]) ** 2),
              "stretch": self.mat.rho * abs(gam[2]) ** 2,
              "shear": float(np.real(np.conj(om[:2]) @ Ib[:2, :2] @ om[:2])),
              "twist": Ib[2, 2] * abs(om[2]) ** 2}
        total = sum(ke.values())
        kind = max(ke, key=lambda x: ke[x])
        k = self.k(m if m <= self.N // 2 else m - self.N)
        w = float(np.linalg.norm(self.Omega))
        if kind in ("stretch", "twist"):
            q, hand = k, 0
        else:
            x = gam if kind == "bend" else om
            cp, cm = x[0] + 1j * x[1], x[0] - 1j * x[1]
            q, hand = (k + w, 1) if abs(cp) >= abs(cm) else (w - k, -1)
        n = int(round(abs(q) * self.L / (2.0 * np.pi)))
        return kind, n, hand, float(ke[kind] / total) if total > 0 else 0.0

    def modes(self, n_max: int | None = None, body_indices=None) -> list[Mode]:
        """Every normal mode with omega > 0 whose lab mode number is <= n_max, from every body
        wavenumber index m (or only those of body_indices: `lab_bend_indices` gives the ones
        that hold given lab bend modes)."""
        out = []
        for m in (range(self.N) if body_indices is None else sorted({int(i) % self.N for i in body_indices})):
            w, V = np.linalg.eig(self.operator(m))
            growth = np.abs(w.real).max()
            if growth > 1e-8 * max(1.0, np.abs(w.imag).max()):
                raise NumericalError(f"the linear rod is not conservative at k index {m}: "
                                     f"max |Re lambda| = {growth:.2e}")
            for lam, v in zip(w, V.T):
                if lam.imag <= 1e-12:
                    continue
                kind, n, hand, purity = self._classify(v, m)
                if n_max is None or n <= n_max:
                    k = self.k(m if m <= self.N // 2 else m - self.N)
                    out.append(Mode(kind, n, float(lam.imag), float(k), hand, purity))
        return sorted(out, key=lambda x: (x.kind, x.n, x.omega))

    def damped_modes(self, friction_translational, friction_rotational, n_max: int | None = None) -> list[dict]:
        """The modes of the Langevin rod's mean motion (docs/thermal.md, "The Langevin rod"):
        A(k) with the body-frame frictions per length Z_t = diag(across, across, along) and
        Z_r = diag(across, across, about the axis) added, d gamma/dt -= Z_t gamma / rho,
        d omega/dt -= I^-1 Z_r omega. Each eigenvalue lambda = -damping + i omega (omega > 0)
        of lab mode number n <= n_max: {kind, n, omega, damping, handedness} in rod units.
        Both frictions are axisymmetric, so the rest state's turning frame carries them
        unchanged and the laboratory wavenumbers are those of the undamped modes."""
        (zt_along, zt_across), (zr_about, zr_across) = friction_translational, friction_rotational
        F = np.zeros((12, 12))
        F[0:3, 0:3] = -np.diag([zt_across, zt_across, zt_along]) / self.mat.rho
        F[3:6, 3:6] = -np.linalg.solve(np.asarray(self.mat.I, float), np.diag([zr_across, zr_across, zr_about]))
        out = []
        for m in range(self.N):
            w, V = np.linalg.eig(self.operator(m) + F)
            for lam, v in zip(w, V.T):
                if lam.imag <= 1e-12:
                    continue
                kind, n, hand, _ = self._classify(v, m)
                if n_max is None or n <= n_max:
                    out.append({"kind": kind, "n": n, "omega": float(lam.imag), "damping": float(-lam.real),
                                "handedness": hand})
        return sorted(out, key=lambda x: (x["kind"], x["n"], x["omega"]))


def lab_bend_indices(ns, turns: int, points: int) -> list[int]:
    """The body wavenumber indices m (mod points) whose transverse modes are lab mode n of a
    rod of `turns` helical turns: lab n = |m + turns| or |turns - m| (module doc)."""
    return sorted({(s * n + t * turns) % points for n in ns for s in (1, -1) for t in (1, -1)})


def K_times(mat: UniformMaterial, Gamma, Omega) -> np.ndarray:
    """(n, m) = K (q - q0) of a uniform state."""
    q = np.concatenate([Gamma, Omega]) - np.concatenate([mat.Gamma0, mat.Omega0])
    return np.asarray(mat.K, float) @ q


def dispersion(modes: list[Mode], kind: str) -> dict[int, dict]:
    """Per lab mode number n of `kind`: the lowest frequency over handedness and direction
    (the branch an MD mode of that n measures) and the spread between the handed modes
    (their splitting by the material's anisotropy)."""
    if kind not in KINDS:
        raise InputError(f"kind {kind!r}: one of {', '.join(KINDS)}")
    by_n: dict[int, list[float]] = {}
    for md in modes:
        if md.kind == kind:
            by_n.setdefault(md.n, []).append(md.omega)
    out = {}
    for n, ws in sorted(by_n.items()):
        ws = sorted(ws)
        # the lowest branch's members: within 20 % of the lowest (higher branches of the
        # same kind, e.g. bend-like modes above the shear gap, are far above it)
        low = [x for x in ws if x <= 1.2 * ws[0]]
        out[n] = {"omega": float(np.mean(low)), "omega_min": float(low[0]), "omega_max": float(low[-1]),
                  "count": len(low)}
    return out


def dna_dispersion(mat: UniformMaterial, n_bp: int, turns: int, tension_pN: float = 0.0,
                   n_max: int = 14, points_per_bp: int = 1, units=None) -> dict:
    """The predicted frequencies [rad/ps] of a ligated periodic DNA rod of n_bp base pairs and
    `turns` helical turns at axial tension `tension_pN`: per kind, {n: omega_per_ps, ...},
    with the spread between the handed bend modes. The fiducial length is n_bp rises
    (dna_models/units.py), the lab mode number n is the MD's (2 pi n / box length)."""
    from dna_models.units import Units
    u = units or Units.paper()
    if n_bp < 2 or turns < 0 or points_per_bp < 1:
        raise InputError(f"n_bp = {n_bp}, turns = {turns}, points_per_bp = {points_per_bp}: need "
                         "n_bp >= 2, turns >= 0, points_per_bp >= 1")
    L = n_bp * u.length_to_rod(u.rise_A)
    T = tension_pN * 1e-12 / u.C
    rod = LinearRod(mat, L, n_bp * points_per_bp, tension=T, turns=turns)
    modes = rod.modes(n_max)
    out: dict = {"tension_pN": float(tension_pN), "n_bp": int(n_bp), "turns": int(turns),
                 "Gamma": rod.Gamma.tolist(), "Omega": rod.Omega.tolist()}
    for kind in KINDS:
        d = dispersion(modes, kind)
        out[kind] = {int(n): {"omega_per_ps": u.angular_velocity_to_rad_per_ps(v["omega"]),
                              "omega_min_per_ps": u.angular_velocity_to_rad_per_ps(v["omega_min"]),
                              "omega_max_per_ps": u.angular_velocity_to_rad_per_ps(v["omega_max"])}
                     for n, v in d.items() if n >= 1}
    return out
