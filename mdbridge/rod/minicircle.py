"""A supercoiled minicircle as a rod: a DNA ring at a chosen linking-number difference,
relaxed in the Langevin rod, with its Lk, Tw and Wr (docs/topology.md, "A supercoiled
minicircle"; the command is `dnarod minicircle`).

1. The material: the DNA's per-step shape and stiffness (mdbridge.rod.material, as
   `dnarod dna-rod` makes it) on a grid of points_per_bp points per base pair.
2. The ring (mdbridge.rod.material.ring): Lk = round(Lk0) + Delta Lk with Lk0 = N / (bp per
   turn of the relaxed rod); the planar circle of Lk turns, closed exactly. A small lab
   velocity out of the ring's plane, A sin(4 pi s / L) e_x (the ring lies in the lab y-z
   plane), seeds the out-of-plane buckling of an overtwisted ring, which a perfect circle at
   kT = 0 would leave only through round-off; velocities leave the closure untouched.
3. The relaxation: the scene's Langevin rod ([thermal]) at temperature_K with a friction
   (default: every velocity damped at twice the slowest bending frequency of the ring, so
   the ring settles in a few of its periods; "water" is DNA's real drag, under which a
   336-bp ring takes microseconds), and self-contact when [contact] is asked for.
4. The checks of the run (`relaxation_topology`): every frame a ring, Lk constant and equal to
   the ring's. A rod without self-contact passes through itself once an overtwisted ring has
   buckled far enough (Lk jumps by 2): that is an error naming the frame, not a result.
5. Relaxed or not (`relaxation_test`): the ring is called relaxed only when its energy and
   its writhe have stopped changing by the stated test of mdbridge.stats `stationarity`:
   for each, the mean over the last quarter of the run differs from the mean over the third
   quarter by less than twice the standard error of that difference (each quarter's from
   the means of its longest blocks that leave RELAXED_BLOCKS of them) or by less than a
   floor (RELAXED_FLOOR_KT, RELAXED_FLOOR_WR).
   Otherwise the command says "not relaxed" with those numbers; the atoms are still built
   on the last frame.
"""
from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from dna_models.errors import InputError, NumericalError
from dna_models.units import Units
from mdbridge.stats import sem_longest_blocks, stationarity

from .material.ring import RingState, grid_frames, relaxed_turns, ring_state
from .run import RodRun
from .scene import new_scene
from .topology import WRITHE_POINTS, is_closed, rod_topology

SEED_KICK_A_PER_PS = 0.01       # out-of-plane seed velocity amplitude (module docstring, step 2)
RELAX_PS = 5000.0               # default relaxation: about 20 / omega_2 of a 336-bp ring
FRAMES = 101
# The relaxation test (module docstring, step 5): a change of the mean energy between the
# run's third and last quarter below this (kT at 300 K) is too small to matter, and a run at
# kT = 0 has no fluctuation to compare a change with.
RELAXED_FLOOR_KT = 0.1
RELAXED_FLOOR_WR = 0.01         # turns: a slowly buckling ring changes its writhe at an almost flat energy
RELAXED_BLOCKS = 4
RELAXED_MIN_FRAMES = 4 * RELAXED_BLOCKS + 1   # a quarter of the frames holds RELAXED_BLOCKS blocks
DT_PER_POINT_SPACING = 0.2      # Langevin step at kT = 0 (tau per 1 point/bp): RK4-stable on DNA
DT_THERMAL = 0.1                # at kT > 0: every class within 1 % (docs/thermal.md, "Error in dt")


@dataclass
class RelaxationChoice:
    """How the ring is relaxed: [thermal] and [contact] of the scene."""
    temperature_K: float = 0.0
    friction: str | float = "critical"    # "critical", "water" or a damping rate [1/ps]
    relax_ps: float = RELAX_PS
    frames: int = FRAMES
    seed: int = 1
    seed_kick_A_per_ps: float = SEED_KICK_A_PER_PS
    contact_diameter_nm: float | None = None   # [contact] diameter_nm; None: no self-contact

    def check(self) -> None:
        if not self.temperature_K >= 0:
            raise InputError(f"--temperature-K {self.temperature_K}: must be >= 0")
        if not self.relax_ps >= 0:
            raise InputError(f"--relax-ps {self.relax_ps}: must be >= 0")
        if self.frames < 3:
            raise InputError(f"--frames {self.frames}: must be >= 3")
        if isinstance(self.friction, str):
            if self.friction not in ("critical", "water"):
                raise InputError(f"--friction {self.friction!r}: allowed 'critical', 'water' or a rate > 0 [1/ps]")
        elif not self.friction > 0:
            raise InputError(f"--friction {self.friction}: a damping rate must be > 0 [1/ps]")
        if self.contact_diameter_nm is not None and not self.contact_diameter_nm > 0:
            raise InputError(f"--contact-diameter-nm {self.contact_diameter_nm}: must be > 0")


def slowest_bend_rate(g, L) -> float:
    """omega_2 = sqrt(B / rho) k^2 at k = 4 pi / L (rod units): the n = 2 bending mode of a
    ring of length L, the slowest (n = 1 is a rigid motion); B the bend stiffness in series
    (mean compliance of K's two bending entries), rho the mean density. An estimate: it
    leaves out the ring's own curvature and the twist coupling."""
    C = np.linalg.inv(np.asarray(g["K"], float))
    B = 1.0 / np.mean(0.5 * (C[:, 3, 3] + C[:, 4, 4]))
    return float(math.sqrt(B / np.mean(g["rho"])) * (4.0 * math.pi / L) ** 2)


def friction_keys(choice: RelaxationChoice, g, L, u: Units) -> dict:
    """[thermal] friction keys: "water", or the same damping rate F for every velocity
    (translational friction per length F rho, rotational F I_33 about the axis and F I_11
    across, with the grid's mean rho and I)."""
    if choice.friction == "water":
        return {"friction_translational": "water", "friction_rotational": "water"}
    F = 2.0 * slowest_bend_rate(g, L) if choice.friction == "critical" else float(choice.friction) * u.tau_ps
    I = np.mean(np.asarray(g["I"], float), axis=0)
    return {"friction_translational": float(F * np.mean(g["rho"])),
            "friction_rotational": [float(F * I[2, 2]), float(F * 0.5 * (I[0, 0] + I[1, 1]))]}


def seed_velocity(ring: RingState, L, amplitude_rod):
    """gamma (N, 3) of the lab velocity A sin(4 pi s / L) e_x (module docstring, step 2)."""
    x = np.concatenate([ring.Gamma, ring.Omega], axis=1)
    R, _ = grid_frames(x, L)
    s = np.arange(len(x)) * L / len(x)
    v = amplitude_rod * np.sin(4.0 * np.pi * s / L)[:, None] * np.array([1.0, 0.0, 0.0])
    return np.einsum("jki,jk->ji", R, v)


def relaxation_scene(choice: RelaxationChoice, g, L, material_file, initial_file, u: Units) -> dict:
    """The scene: the grid material from the ring, the Langevin rod of `choice`, output
    fields for the topology and the all-atom build."""
    N = g["K"].shape[0]
    n_bp = round(L / u.length_to_rod(u.rise_A))
    dt_max = DT_THERMAL if choice.temperature_K > 0 else DT_PER_POINT_SPACING * n_bp / N
    # --relax-ps 0: two steps, three frames (frame 0 is the ring itself)
    frames = choice.frames if choice.relax_ps > 0 else 3
    interval = u.time_to_rod(choice.relax_ps) / (frames - 1) if choice.relax_ps > 0 else dt_max
    sc = new_scene({"length": float(L), "points": int(N)}, {"kind": "file", "path": str(initial_file)},
                   t_end=interval * (frames - 1), frames=frames, space="spectral",
                   fields=("internal", "energy", "centerline", "directors"),
                   material={"material_file": str(material_file)})
    sc["solver"] = {"space": "spectral", "time": "langevin", "dt": interval / math.ceil(interval / dt_max - 1e-9)}
    sc["thermal"] = {"temperature_K": float(choice.temperature_K), "seed": int(choice.seed),
                     # the ring is pre-stressed: the linearised sample would not keep it closed
                     # (docs/thermal.md, "Pre-stressed states are not sampled exactly")
                     "sample_initial": False, **friction_keys(choice, g, L, u)}
    if choice.contact_diameter_nm is not None:
        sc["contact"] = {"diameter_nm": float(choice.contact_diameter_nm)}
    return sc


@dataclass
class MinicircleRod:
    """The minicircle rod before its run: Lk0, Lk and the ring's t = 0 numbers."""
    n_bp: int
    points: int
    L: float
    Lk0: float
    Lk: int
    ring: RingState
    scene: dict

    def as_dict(self) -> dict:
        r = asdict(self.ring)
        for k in ("Gamma", "Omega"):
            r.pop(k)
        return {"n_bp": self.n_bp, "points": self.points, "length": self.L, "Lk0": self.Lk0,
                "bp_per_turn_relaxed": self.n_bp / self.Lk0, "Lk": self.Lk, "delta_Lk": self.Lk - self.Lk0,
                "ring_t0": r}


def make_minicircle(g, L, n_bp: int, delta_Lk: int, choice: RelaxationChoice, out: Path,
                    u: Units | None = None) -> MinicircleRod:
    """Writes OUT/ring.h5 (the t = 0 state) and returns the rod with its scene (to be
    written beside OUT/material.h5, which the caller writes)."""
    from .material.gridfile import write_initial_file
    u = u or Units.paper()
    choice.check()
    Lk0 = relaxed_turns(g, L)
    Lk = int(round(Lk0)) + int(delta_Lk)
    if Lk < 1:
        raise InputError(f"--delta-lk {delta_Lk}: Lk = round(Lk0) + Delta Lk = {Lk}; a right-handed ring "
                         f"of {n_bp} bp (Lk0 = {Lk0:.3f}) needs Lk >= 1")
    ring = ring_state(g, L, Lk)
    gamma = seed_velocity(ring, L, u.velocity_to_rod(choice.seed_kick_A_per_ps))
    write_initial_file(out / "ring.h5", g["s"], ring.Gamma, ring.Omega, gamma=gamma)
    scene = relaxation_scene(choice, g, L, "material.h5", "ring.h5", u)
    return MinicircleRod(n_bp=n_bp, points=int(g["K"].shape[0]), L=float(L), Lk0=Lk0, Lk=Lk, ring=ring,
                         scene=scene)


def relaxation_topology(run: RodRun, Lk: int, contact: bool, writhe_points: int = WRITHE_POINTS) -> dict:
    """Lk, Tw, Wr per frame of the relaxation, and its checks: every frame a ring and Lk
    always the ring's. Returns the topology (mdbridge.rod.topology) with `failure` (None,
    or the message of the first failed check) so that the caller writes it before raising."""
    run.require("time", "centerline", "directors")
    u = run.units()
    x = np.asarray(run.centerline, float)
    time = np.asarray(run.time, float)
    t_ps = np.asarray(u.time_to_ps(time))
    open_frames = [f for f in range(len(x)) if not is_closed(x[f])]
    if open_frames:
        f = open_frames[0]
        gap = u.length_to_A(float(np.linalg.norm(x[f, -1] - x[f, 0])))
        keep = run.until(float(time[f - 1])) if f >= 3 else None
        top = rod_topology(keep, writhe_points) if keep is not None else {}
        top["failure"] = (f"the ring opened at frame {f} (t = {t_ps[f]:.1f} ps; last-to-first gap {gap:.1f} A): "
                          "the semi-discrete rod keeps its closure only to its discretisation error "
                          "(docs/thermal.md, 'Closure in a run'); use more --points-per-bp, a lower "
                          "--temperature-K or a shorter --relax-ps")
        return top
    top = rod_topology(run, writhe_points)
    Lks = np.asarray(top["Lk"], int)
    top["failure"] = None
    if np.any(Lks != Lk):
        f = int(np.flatnonzero(Lks != Lk)[0])
        top["failure"] = (f"Lk changed from {Lk} to {Lks[f]} at frame {f} (t = {t_ps[f]:.1f} ps, Wr "
                          f"{top['Wr'][f - 1]:.3f} -> {top['Wr'][f]:.3f}): the rod passed through itself"
                          + ("" if contact else
                             "; relax with self-contact (--contact-diameter-nm), or a shorter --relax-ps"))
    return top


def check_relaxation(top: dict) -> None:
    if top.get("failure"):
        raise NumericalError(top["failure"])


def relaxation_test(run: RodRun, top: dict, reference_K: float, u: Units | None = None) -> dict:
    """Step 5 of the module docstring on the run's energy, in kT at reference_K (the command:
    300 K), and on its writhe (top: `relaxation_topology`'s): relaxed (True, False, or None
    when the run has fewer than RELAXED_MIN_FRAMES frames), the numbers of both, and the
    rule in words."""
    u = u or run.units()
    rule = (f"relaxed: for the energy and for Wr alike, the mean over the run's last quarter differs from the "
            f"mean over its third quarter by less than 2 standard errors of the difference (blocks: the longest "
            f"leaving {RELAXED_BLOCKS} per quarter) or by less than a floor ({RELAXED_FLOOR_KT:g} kT at "
            f"{reference_K:g} K; {RELAXED_FLOOR_WR:g} turns)")
    n = 0 if run.energy is None else len(run.energy)
    if n < RELAXED_MIN_FRAMES or len(top.get("Wr", [])) != n:
        return {"relaxed": None, "rule": rule,
                "reason": f"{n} frames with an energy and a writhe; the test needs at least {RELAXED_MIN_FRAMES}"}
    t = np.asarray(u.time_to_ps(np.asarray(run.time, float)))
    E = np.asarray(run.energy, float) / u.kT_to_rod(reference_K)
    Wr = np.asarray(top["Wr"], float)

    def test(y, floor):
        r = stationarity(t, y, sem=lambda _, yq: sem_longest_blocks(yq, RELAXED_BLOCKS), floor=floor)
        return {"first": float(y[0]), "last": float(y[-1]), "mean_last_half": r["mean_second_half"],
                "change_last_vs_third_quarter": r["change_between_quarters"],
                "standard_error_of_change": r["standard_error_of_change"], "floor": floor,
                "stationary": r["stationary"]}
    e, w = test(E, RELAXED_FLOOR_KT), test(Wr, RELAXED_FLOOR_WR)
    return {"relaxed": e["stationary"] and w["stationary"], "rule": rule, "energy_kT": e, "Wr": w}


def relaxation_words(test: dict, relax_ps: float) -> str:
    """The relaxation test's verdict with its numbers, for the command's output."""
    if test["relaxed"] is None:
        return f"not called relaxed: the relaxation was not tested ({test['reason']})"

    def numbers(name, r, unit):
        return (f"{name} {r['first']:.4g} -> {r['last']:.4g}{unit}, mean of the last quarter - third quarter "
                f"{r['change_last_vs_third_quarter']:+.2g}{unit} (2 standard errors "
                f"{2 * r['standard_error_of_change']:.2g}, floor {r['floor']:g})")
    words = (f"over {relax_ps:g} ps: " + numbers("energy", test["energy_kT"], " kT") + "; "
             + numbers("Wr", test["Wr"], ""))
    if test["relaxed"]:
        return f"relaxed by the stated test (docs/topology.md): {words}"
    still = " and ".join(k for k, key in (("the energy", "energy_kT"), ("Wr", "Wr")) if not test[key]["stationary"])
    return f"NOT relaxed ({still} still changing) {words}; relax longer (--relax-ps)"
