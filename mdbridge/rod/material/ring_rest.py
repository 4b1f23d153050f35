"""The closed ring's rest state: the least energy of a DNA ring at the linking number of the
relaxed ring (`dnarod dna-rod --ring`; docs/dna-rod.md, "A closed ring").

A sequence's intrinsic shape is not a circle: closed, the ring is pre-stressed, and its rest
state is the minimum of the energy E = sum_i h e_i.K_i e_i / 2 over the closed states, holonomy
g(0)^-1 g(L) = identity, at Lk = round(Lk0), Lk0 = (1/2 pi) int Omega0_3 ds the turns of the
relaxed rod (ring.py's relaxed_turns); a local minimum, the one reached from the planar circle.

**1. The solver descends.** The overdamped rod at kT = 0 (solver.time = "brownian",
rodcore/src/rodcore/brownian.hpp) takes the step (Z + dt H) dx = dt F, H = D^T K D: at large dt a
damped Gauss-Newton step on the energy, with the run's closure projection keeping the holonomy
(docs/thermal.md, "Closure in a Brownian run"). From the planar circle of Lk turns, closed by
ring.py's least-energy Newton steps, it runs in chunks of `CHUNK` steps, dt raised x`GROW` after a
chunk that lowered the energy and cut /`SHRINK` after one that raised it, folded the rod or changed
its Lk (Levenberg-Marquardt's damping, Z / dt; without [contact], whose explicit force a huge step
cannot take: the Lk check stands for it, and the result must have no contact energy), until the
energy stays put. This is the global part: a 10.5-kbp ring moves far from the circle (13 kT ->
0.2 kT).

**2. The least-energy closed state.** The descent stops at the fd4 rod's own rest (F = 0 with the
projection), which is not the minimum of E over the closed states: fd4's compatibility and the
holonomy of the strains' interpolant differ on a sequence's rough fields (at 10.5 kbp the minimum is
35 % lower). The minimum solves h K_i e_i = B_i^T lambda (the closure's constant force and moment,
lambda, seen in each frame: the continuum statics), iterated as x <- x0 + W^-1 C^T lambda(x)
(least_energy_closed). Its fd4 statics residual is then the grid's: as large as the difference
between fd4's and the spectral d/ds's residual at the same state (discretisation_floor).

**Closure to round-off, in the solver's own frames.** Every state is moved onto the identity
holonomy of rodsim's sweep (composition.magnus_holonomy) by Newton steps of least energy,
dx = -W^-1 C^T (C W^-1 C^T)^-1 c, W = K h, C ring.py's Jacobian on its midpoint cells.
"""
from __future__ import annotations

import copy
import resource
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from dna_models.errors import InputError, NumericalError
from mdbridge.geometry.compiled import rodcore_module
from mdbridge.geometry.rotations import rotation_log
from mdbridge.geometry.topology import ribbon_topology

from .composition import magnus_holonomy
from .ring import relaxed_turns, ring_defect, ring_state

CHUNK = 10                 # steps per trial run
DT_START = 1e5             # time units (~94 ns): every mode of a kilobase ring shorter than ~1 um relaxed
DT_MAX = 1e14              # beyond the slowest elastic mode of any ring the solver can hold
GROW, SHRINK = 3.0, 10.0
DT_MIN = 1e-2              # a chunk rejected down to this step: the energy sits on the closure floor
DT_CONVERGED = 1e8         # ~0.1 s: beyond the ring's slowest bending mode at 10.5 kbp (ms)
ENERGY_TOL = 1e-10
MAX_CHUNKS = 400
ANDERSON = 6               # depth of the least-energy iteration's acceleration
POLISH_ITERATIONS = 80


@dataclass
class RingRest:
    Gamma: np.ndarray           # (N, 3)
    Omega: np.ndarray           # (N, 3)
    Lk0: float                  # turns of the relaxed rod (its principal twist, coarse.py)
    Lk: int                     # of the ring, as rodsim measures it (centreline framed by d1)
    Tw: float
    Wr: float                   # exact (Klenin-Langowski, stride 1)
    energy: float               # the scene's potential energy (elastic + contact), rod units
    energy_start: float         # elastic, of the closed planar circle it started from
    contact_energy: float       # at the rest state (0: no pair within the cut-off)
    residual: float             # rms |(F, tau)| per length of the statics, rod units
    residual_start: float
    residual_floor: float       # rms |F_fd4 - F_spectral| at the rest state (discretisation_floor)
    closure_rotation_rad: float     # |log R(L)| in the solver's sweep
    closure_translation: float      # |r(L)|, rod units
    chunks: int
    steps: int
    dt_last: float
    energy_descent: float       # where the overdamped descent stopped (the fd4 rod's own rest)
    residual_descent: float
    polish_iterations: int
    cpu_s: float
    trace: list = field(default_factory=list)   # (dt, energy) per accepted chunk


def _cpu() -> float:
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def _state(x) -> dict:
    z = np.zeros((x.shape[0], 3))
    return {"gamma": z, "omega": z.copy(), "Gamma": np.ascontiguousarray(x[:, :3]),
            "Omega": np.ascontiguousarray(x[:, 3:])}


def _closure(x, L):
    R, r = magnus_holonomy(x, L)
    return np.concatenate([rotation_log(R), r])


def close_in_solver_frames(x, g, L, tol=1e-13, maxiter=12, B=None):
    """x (N, 6) moved onto the identity holonomy of rodsim's sweep by least-energy Newton steps
    (module docstring), the Jacobian from ring.py's midpoint cells, taken again only when a step
    did not shrink the defect tenfold (chord steps near the ring)."""
    N = x.shape[0]
    Winv = np.linalg.inv(np.asarray(g["K"], float) * (L / N))
    scale = np.array([L / (2 * np.pi)] * 3 + [1.0] * 3)
    x = np.asarray(x, float).copy()
    size = np.inf
    WCt = S = None
    for _ in range(maxiter):
        c = _closure(x, L)
        new = float(np.linalg.norm(c * scale))
        if new < tol * L:
            return x
        if WCt is None or new > 0.1 * size:
            _, C = ring_defect(x, L, B=B)
            WCt = np.einsum("jab,kjb->jak", Winv, C.reshape(6, N, 6)).reshape(6 * N, 6)
            S = C @ WCt
        size = new
        x = x - (WCt @ np.linalg.solve(S, c)).reshape(N, 6)
    if float(np.linalg.norm(_closure(x, L) * scale)) >= 1e3 * tol * L:
        raise NumericalError(f"ring rest: the ring did not close in the solver's frames (defect {_closure(x, L)})")
    return x


def least_energy_closed(x, g, L, log=None, tol=1e-12, maxiter=POLISH_ITERATIONS, B=None):
    """The minimum of E = sum_i h e_i.K_i e_i / 2 over the closed states near x (N, 6): the
    sequential-quadratic step x <- x0 + W^-1 C^T lambda (x0 the intrinsic strains, W = K h, C the
    holonomy's Jacobian at x, lambda the closure's multipliers: the constant force and moment the
    closure exerts), closed in the solver's frames, and Anderson-accelerated (depth ANDERSON) since
    the closure's curvature makes the plain step contract slowly. Stops when a step moves the
    strains by less than tol of their rest values. Returns (x, iterations)."""
    from mdbridge.rod.material.composition import cell_matrix
    from .ring import REFINE
    N = x.shape[0]
    B = cell_matrix(N, L, REFINE) if B is None else B
    x0 = np.concatenate([np.asarray(g["Gamma0"], float), np.asarray(g["Omega0"], float)], axis=1)
    Winv = np.linalg.inv(np.asarray(g["K"], float) * (L / N))
    scale = float(np.abs(x0).max())

    def step(y):
        c = _closure(y, L)
        _, C = ring_defect(y, L, B=B)
        WCt = np.einsum("jab,kjb->jak", Winv, C.reshape(6, N, 6)).reshape(6 * N, 6)
        lam = np.linalg.solve(C @ WCt, C @ (y - x0).ravel() - c)
        return close_in_solver_frames(x0 + (WCt @ lam).reshape(N, 6), g, L, B=B)

    X, F = [], []
    y = np.asarray(x, float)
    for it in range(1, maxiter + 1):
        gy = step(y)
        f = (gy - y).ravel()
        move = float(np.abs(f).max())
        if log:
            log(f"ring rest: least-energy step {it}: moves the strains by {move:.2e}")
        if move < tol * scale:
            return gy, it
        X.append(y.ravel())
        F.append(f)
        X, F = X[-ANDERSON - 1:], F[-ANDERSON - 1:]
        if len(F) > 1:
            dF = np.diff(np.array(F), axis=0).T
            dX = np.diff(np.array(X), axis=0).T
            gamma = np.linalg.lstsq(dF, f, rcond=None)[0]
            y = (y.ravel() + f - (dX + dF) @ gamma).reshape(N, 6)
        else:
            y = gy
    raise NumericalError(f"ring rest: the least-energy closed state did not converge in {maxiter} steps "
                         f"(last move {move:.3g})")


def _minimiser_scene(scene: dict, dt: float, steps: int, contact: bool = True) -> dict:
    """SCENE (a dict with [rod], [material], optional [contact]) as the kT = 0 overdamped rod
    (without its contact for contact=False)."""
    keep = ("rod", "material", "contact") if contact else ("rod", "material")
    s = {k: copy.deepcopy(v) for k, v in scene.items() if k in keep}
    s["thermal"] = {"temperature_K": 0.0, "friction_translational": "water", "friction_rotational": "water",
                    "sample_initial": False}
    s["solver"] = {"time": "brownian", "dt": float(dt)}
    s["output"] = {"t_end": float(dt) * steps, "frames": 2, "fields": ["internal", "energy"]}
    return s


def statics_force(scene: dict, x, contact: bool = True, space: str | None = None) -> tuple[float, np.ndarray]:
    """(the potential energy, the statics residual (N, 6): force rho dgamma/dt and torque I domega/dt
    per length) of strains x (N, 6) in SCENE: rodcore's own energy and right-hand side at zero
    velocity, with the scene's d/ds (fd4 for "brownian") or SPACE."""
    import h5py
    rc = rodcore_module()
    s = _minimiser_scene(scene, 1.0, 1, contact)
    if space:       # the inertial rod's right-hand side at zero velocity: the same statics, any d/ds
        s = {k: v for k, v in s.items() if k not in ("thermal", "solver")}
        s["solver"] = {"space": space}
    sim = rc.Simulation(s, initial=_state(x))
    f = sim.rhs(_state(x))
    with h5py.File(scene["material"]["material_file"], "r") as m:
        rho, I = m["rho"][()], m["I"][()]
    return float(sim.energy()), np.concatenate([rho[:, None] * f["gamma"], np.einsum("jab,jb->ja", I, f["omega"])],
                                               axis=1)


def _rms(F) -> float:
    return float(np.sqrt(np.mean(np.sum(np.asarray(F) ** 2, axis=1))))


def statics(scene: dict, x, contact: bool = True) -> tuple[float, float]:
    """(the potential energy, the rms statics residual per length) of strains x (N, 6) in SCENE."""
    E, F = statics_force(scene, x, contact)
    return E, _rms(F)


def discretisation_floor(scene: dict, x) -> float:
    """The rms difference of the statics residual under the scene's fd4 and the spectral d/ds at
    strains x: what the grid leaves undecided. A residual of this size is the discretisation's."""
    return _rms(statics_force(scene, x, space="fd4")[1] - statics_force(scene, x, space="spectral")[1])


def descend(scene: dict, x, Lk: int, log=None):
    """The kT = 0 overdamped descent of strains x (N, 6) in SCENE (module docstring). Returns
    (x, chunks, steps, dt, trace)."""
    rc = rodcore_module()
    dt, chunks, steps = DT_START, 0, 0
    trace: list[tuple[float, float]] = []
    E = statics(scene, x, contact=False)[0]
    while chunks < MAX_CHUNKS:
        chunks += 1
        try:
            out = rc.run(_minimiser_scene(scene, dt, CHUNK, contact=False), initial=_state(x))
            En = float(out["energy"][-1])
            ok = En <= E + 1e-12 * abs(E) and out["topology"]["Lk"][-1] == Lk
            what = f"energy {En:.12g}, Lk {out['topology']['Lk'][-1]:g}"
        except (FloatingPointError, ValueError) as e:      # the rod folded: too large a step
            ok, what = False, str(e)[:80]
        if log:
            log(f"ring rest: dt {dt:.1e}: {what}")
        if not ok:
            dt /= SHRINK
            if dt < DT_MIN:
                return x, chunks, steps, dt, trace
            continue
        steps += CHUNK
        x = np.concatenate([out["fields"]["Gamma"][-1], out["fields"]["Omega"][-1]], axis=1)
        trace.append((dt, En))
        if abs(E - En) < ENERGY_TOL * abs(En):
            return x, chunks, steps, dt, trace
        E = En
        dt = min(dt * GROW, DT_MAX)
    raise NumericalError(f"ring rest: not converged after {MAX_CHUNKS} chunks of {CHUNK} steps (dt {dt:.3g}, "
                         f"energy {E:.12g})")


def ring_topology(scene: dict, x) -> dict:
    """Lk, Tw (rodsim's measure) and the exact Wr of the ring x in SCENE, on the solver's frames."""
    rc = rodcore_module()
    s = _minimiser_scene(scene, 1e-6, 1)
    s["output"]["fields"] = ["internal", "centerline", "directors"]
    frames: list = []
    sim = rc.Simulation(s, initial=_state(x))
    sim.add_observer(lambda fr: frames.append(fr))
    sim.step_to(0.0)
    fr = frames[0]
    return ribbon_topology(np.asarray(fr["centerline"]), np.asarray(fr["directors"])[:, :, 0], None, 1)


def ring_rest_state(g, L, scene: dict, log=None) -> RingRest:
    """The rest state of the ring of grid material g (steps_to_rod.grid_material) of length L in
    SCENE (a dict whose [material] material_file holds g, with optional [contact]); module
    docstring."""
    if not Path(scene["material"]["material_file"]).is_file():
        raise InputError(f"ring rest: {scene['material']['material_file']}: the material file must be written first")
    t0 = _cpu()
    Lk0 = relaxed_turns(g, L)
    Lk = int(round(Lk0))
    x = close_in_solver_frames(_planar(g, L, Lk), g, L)
    E0, res0 = statics(scene, x, contact=False)
    x, chunks, steps, dt, trace = descend(scene, x, Lk, log)
    x = close_in_solver_frames(x, g, L)
    E_descent, res_descent = statics(scene, x)
    x, polish = least_energy_closed(x, g, L, log)
    E, res = statics(scene, x)
    contact = E - statics(scene, x, contact=False)[0]
    floor = discretisation_floor(scene, x)
    top = ring_topology(scene, x)
    if top["Lk"] != Lk:
        raise NumericalError(f"ring rest: the ring links {top['Lk']} times, not {Lk} (it passed through itself "
                             "on the way down: give it [contact])")
    c = _closure(x, L)
    return RingRest(Gamma=x[:, :3].copy(), Omega=x[:, 3:].copy(), Lk0=Lk0, Lk=Lk, Tw=top["Tw"], Wr=top["Wr"],
                    energy=E, energy_start=E0, contact_energy=contact, residual=res, residual_start=res0,
                    residual_floor=floor,
                    closure_rotation_rad=float(np.linalg.norm(c[:3])), closure_translation=float(np.linalg.norm(c[3:])),
                    chunks=chunks, steps=steps, dt_last=dt, energy_descent=E_descent, residual_descent=res_descent,
                    polish_iterations=polish, cpu_s=_cpu() - t0, trace=trace)


def _planar(g, L, Lk):
    r = ring_state(g, L, Lk)
    return np.concatenate([r.Gamma, r.Omega], axis=1)
