#!/usr/bin/python3
"""The closure of a thermal run (docs/thermal.md, "Closure in a run"): where its drift comes
from (--part source), what keeping it costs (--part cost), and how far the box wanders
between projections (--part wander).

1. source.
The continuum rod keeps its holonomy H = g(0)^-1 g(L) up to conjugation by the frame at
s = 0: H^-1 dH/dt = eta(0) - H^-1 eta(0) H, with eta(0) = (omega, gamma)(0) as a twist. The
semi-discrete rod does not. This script asks whether a better reconstruction of H from the
grid strains would keep it: for the paper's 158-bp rod, at rest-kicked (0 K, smooth) and
from its thermal sample at 30 K and 300 K, it takes the right-hand side of rodcore (spectral
and fd4) and differentiates H along it for four quadratures of the product integral:

- magnus-fourier: the strains interpolated by their Fourier series, 16 fourth-order Magnus
  substeps per grid interval (the continuum H of the band-limited fields);
- midpoint-interp: one exponential per interval of the Fourier-interpolated midpoint strain;
- trapezoid: one exponential per interval of the mean of its end points;
- left: exp(h xi_i), the left point (what a chain of rigid base pairs would be).

Printed per case: |defect| = |H^-1 dH/dt - (continuum value)| and |H^-1 dH/dt| (rotation
[rad per time unit], translation [length per time unit]). If a quadrature made the defect
vanish, the drift would be the reconstruction's; it does not for any of them.

2. cost: CPU seconds of 50 time units of the 158-bp rod at 300 K (Langevin, dt = 0.05)
   without the projection, every 0.5 time units (the default), every 0.1 and every step; 3 rounds
   taken in turn, ratios per round.

3. wander: the same rod over 50 time units with a frame every step: the largest change of
   the period vector |r(L) - r(0) - (its value at t = 0)| / L and of the holonomy angle, over
   all frames, for the projection every 0.5, every 0.1 and every step, and without it.

4. interval: does the box's breathing between projections change what the run measures?
   The same rod over 3200 time units (a frame every 2, the first 200 dropped), projected every
   0.5 (the default) and every step, SEEDS independent seeds each: the slack tension on the
   box (the force of the constraint per frame, as tests/python/test_thermal_closure.py
   measures it) and the effective frequencies of the lab bending modes n = 2, 4, 8,
   w_n^2 = <|da_n/dt|^2> / <|a_n|^2> with a_n the Fourier amplitude of the centerline's
   displacement across the box axis (for a harmonic mode in equilibrium this is its
   frequency, whatever the friction). Errors from the scatter over the seeds. Each run holds
   the scene's box (`box_over_L` per run checks it); the two runs of a seed share their
   noise, so the comparison is paired by seed.

    /usr/bin/python3 bench/thermal_closure.py [--part source|cost|wander|interval|all]
        [--out bench/results/thermal_closure.json]

Needs the Python module rodcore on PYTHONPATH (build/python) and scipy; parts 1-3 about two
minutes, part 4 about five CPU minutes.
"""
from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np
import rodcore
from scipy.linalg import expm

from dna_models.units import Units
from mdbridge.jsonio import write_json

HERE = Path(__file__).resolve().parent

U = Units.paper()
N = 158
L = N * U.rise_A / U.ell_A
SCHEMES = ("magnus-fourier", "midpoint-interp", "trapezoid", "left")


def hat(xi: np.ndarray) -> np.ndarray:
    """xi = (Omega, Gamma) -> the 4 x 4 matrix of se(3)."""
    W, V = xi[:3], xi[3:]
    M = np.zeros((4, 4))
    M[:3, :3] = [[0, -W[2], W[1]], [W[2], 0, -W[0]], [-W[1], W[0], 0]]
    M[:3, 3] = V
    return M


def vee(M: np.ndarray) -> np.ndarray:
    return np.array([M[2, 1], M[0, 2], M[1, 0], M[0, 3], M[1, 3], M[2, 3]])


def fourier_at(f: np.ndarray, shift: float) -> np.ndarray:
    """Grid values f (N, k) -> their Fourier interpolant at s_i + shift (Nyquist mode kept real)."""
    F = np.fft.rfft(f, axis=0)
    k = 2 * np.pi * np.arange(F.shape[0]) / L
    phase = np.exp(1j * k * shift)
    if N % 2 == 0:
        phase[-1] = math.cos(k[-1] * shift)
    return np.fft.irfft(F * phase[:, None], n=N, axis=0)


def holonomy(xi: np.ndarray, scheme: str, m: int = 16) -> np.ndarray:
    h = L / N
    g = np.eye(4)
    if scheme == "magnus-fourier":
        c = (0.5 - math.sqrt(3) / 6, 0.5 + math.sqrt(3) / 6)
        at = [[fourier_at(xi, (sub + ca) * h / m) for ca in c] for sub in range(m)]
        hs = h / m
        for i in range(N):
            for sub in range(m):
                A1, A2 = hat(at[sub][0][i]), hat(at[sub][1][i])
                g = g @ expm(hs / 2 * (A1 + A2) + math.sqrt(3) / 12 * hs ** 2 * (A1 @ A2 - A2 @ A1))
    elif scheme == "midpoint-interp":
        mid = fourier_at(xi, h / 2)
        for i in range(N):
            g = g @ expm(h * hat(mid[i]))
    elif scheme == "trapezoid":
        for i in range(N):
            g = g @ expm(h * hat(0.5 * (xi[i] + xi[(i + 1) % N])))
    else:
        for i in range(N):
            g = g @ expm(h * hat(xi[i]))
    return g


def defect_rate(sim, scheme: str, eps: float = 1e-6) -> tuple[np.ndarray, np.ndarray]:
    st = sim.state
    y = np.concatenate([st[k].T.ravel() for k in ("gamma", "omega", "Gamma", "Omega")])
    f = np.asarray(sim.rhs(y)).reshape(12, N)
    Y = y.reshape(12, N)
    xi, dxi = np.hstack([Y[9:12].T, Y[6:9].T]), np.hstack([f[9:12].T, f[6:9].T])
    eta0 = np.r_[Y[3:6, 0], Y[0:3, 0]]
    H = holonomy(xi, scheme)
    dH = (holonomy(xi + eps * dxi, scheme) - holonomy(xi - eps * dxi, scheme)) / (2 * eps)
    Hi = np.linalg.inv(H)
    rate = vee(Hi @ dH)
    return rate - vee(hat(eta0) - Hi @ hat(eta0) @ H), rate


def scene(T: float, space: str) -> dict:
    if T == 0:
        return {"initial": {"kind": "dna_planar", "bp": N, "turns": 15, "A_v_A_per_ps": 2.0},
                "solver": {"space": space}, "output": {"t_end": 1.0}}
    return {"initial": {"kind": "dna_planar", "bp": N, "turns": 15, "A_v_A_per_ps": 0.0},
            "thermal": {"temperature_K": T, "seed": 3}, "solver": {"space": space, "dt": 0.04},
            "output": {"t_end": 1.0}}


def source_study() -> dict:
    rows = []
    for T in (0.0, 30.0, 300.0):
        for space in ("spectral", "fd4"):
            sim = rodcore.Simulation(scene(T, space))
            for scheme in SCHEMES:
                d, rate = defect_rate(sim, scheme)
                row = {"temperature_K": T, "space": space, "scheme": scheme,
                       "defect_rotation": float(np.linalg.norm(d[:3])),
                       "defect_translation": float(np.linalg.norm(d[3:])),
                       "rate_rotation": float(np.linalg.norm(rate[:3])),
                       "rate_translation": float(np.linalg.norm(rate[3:]))}
                rows.append(row)
                print(f"T = {T:5g} K {space:8s} {scheme:16s} defect rot {row['defect_rotation']:.2e} "
                      f"trans {row['defect_translation']:.2e} (|H^-1 dH/dt| rot {row['rate_rotation']:.2e} "
                      f"trans {row['rate_translation']:.2e})", flush=True)
    return {"rows": rows}


def dna300(keep: bool, interval: float, t_end: float, frames: int) -> dict:
    return {"initial": {"kind": "dna_planar", "bp": N, "turns": 15, "A_v_A_per_ps": 0.0},
            "thermal": {"temperature_K": 300.0, "seed": 3, "friction_translational": 0.02,
                        "friction_rotational": "water", "keep_closure": keep, "closure_interval": interval},
            "solver": {"dt": 0.05, "space": "spectral"},
            "output": {"t_end": t_end, "frames": frames, "fields": ["centerline"]}}


CASES = {"none": (False, 0.5), "every 0.5": (True, 0.5), "every 0.1": (True, 0.1), "every step": (True, 0.0)}


def cost_study(rounds: int = 3) -> dict:
    seconds: dict = {name: [] for name in CASES}
    for _ in range(rounds):
        for name, (keep, interval) in CASES.items():
            sim = rodcore.Simulation(dna300(keep, interval, 50.0, 2))
            t0 = time.process_time()
            sim.run()
            seconds[name].append(time.process_time() - t0)
    ratios = {name: [a / b for a, b in zip(seconds[name], seconds["none"])] for name in CASES}
    print("CPU seconds per 50 time units:", {k: [round(x, 3) for x in v] for k, v in seconds.items()},
          "ratio to none:", {k: round(float(np.median(v)), 2) for k, v in ratios.items()}, flush=True)
    return {"seconds": seconds, "ratio_median": {k: float(np.median(v)) for k, v in ratios.items()}}


def wander_study() -> dict:
    out = {}
    for name, (keep, interval) in CASES.items():
        sim = rodcore.Simulation(dna300(keep, interval, 50.0, 1001))
        box, angle = [], []
        sim.add_observer(lambda f: (box.append(np.asarray(f["end_to_end"]).copy()), angle.append(f["end_rotation"])))
        sim.run()
        B, A = np.array(box), np.array(angle)
        out[name] = {"period_vector": float(np.linalg.norm(B - B[0], axis=1).max() / L),
                     "holonomy_angle_rad": float(np.abs(A - A[0]).max())}
        print(f"{name:10s}: largest |period vector change| / L {out[name]['period_vector']:.2e}, "
              f"holonomy angle {out[name]['holonomy_angle_rad']:.2e} rad (frames every step, 50 time units)",
              flush=True)
    return out


SEEDS = (3, 4, 5, 6, 7, 8)
MODES = (2, 4, 8)
FORCE_PN = U.C * 1e12


def box_observables(interval: float, seed: int, t_end: float = 3200.0, frame: float = 2.0,
                    skip: int = 100) -> dict:
    """Mean box tension [pN] and effective bending-mode frequencies [rad per time unit] of one run."""
    sc = dna300(True, interval, t_end, int(round(t_end / frame)) + 1)
    sc["thermal"]["seed"] = seed
    sc["output"]["fields"] = ["internal", "centerline", "directors"]
    C3 = U.C_star[2]
    phase = np.exp(-2j * np.pi * np.outer(MODES, np.arange(N)) / N)        # (modes, N)
    F, a2, v2, box = [], [], [], []

    def observe(f):
        if f["index"] == skip:   # the first frame used (a sample drawn off the box is back by then)
            box.append(float(np.linalg.norm(f["end_to_end"])) / L)
        if f["index"] < skip:
            return
        e = np.asarray(f["end_to_end"])
        e = e / np.linalg.norm(e)
        R = f["directors"]
        F.append(C3 * (f["fields"]["Gamma"][:, 2].mean() - 1.0) / (R[:, :, 2] @ e).mean())
        across = np.eye(3) - np.outer(e, e)
        u = f["centerline"] @ across                                        # (N, 3)
        v = np.einsum("nij,nj->ni", R, f["fields"]["gamma"]) @ across       # lab velocity across
        a2.append(np.sum(np.abs(phase @ u) ** 2, axis=1))
        v2.append(np.sum(np.abs(phase @ v) ** 2, axis=1))

    sim = rodcore.Simulation(sc)
    sim.add_observer(observe)
    sim.run()
    w = np.sqrt(np.mean(v2, axis=0) / np.mean(a2, axis=0))
    return {"tension_pN": float(np.mean(F) * FORCE_PN), "omega": [float(x) for x in w], "box_over_L": box[0]}


def interval_study() -> dict:
    out: dict = {"seeds": list(SEEDS), "modes": list(MODES), "t_end": 3200.0, "frame": 2.0,
                 "skipped_frames": 100}
    for name, interval in (("every 0.5", 0.5), ("every step", 0.0)):
        runs = [box_observables(interval, seed) for seed in SEEDS]
        F = np.array([r["tension_pN"] for r in runs])
        W = np.array([r["omega"] for r in runs])
        se = math.sqrt(len(SEEDS))
        out[name] = {"tension_pN": float(F.mean()), "tension_err_pN": float(F.std(ddof=1) / se),
                     "omega": W.mean(axis=0).tolist(), "omega_err": (W.std(ddof=1, axis=0) / se).tolist(),
                     "runs": runs}
        print(f"{name:10s}: tension {F.mean():.2f} +- {F.std(ddof=1) / se:.2f} pN; omega_n (n = {MODES}) "
              + ", ".join(f"{m:.5f} +- {s:.5f}" for m, s in zip(W.mean(axis=0), W.std(ddof=1, axis=0) / se)),
              flush=True)
    # the box a run keeps is that of its initial sample, which is the scene's only when the
    # sampler's nonlinear closure converged (summary.thermal_note); the tension of the runs
    # that hold the scene's box, for comparison with theory
    held = [i for i, r in enumerate(out["every step"]["runs"]) if abs(r["box_over_L"] - 1.0) < 1e-6]
    F = np.array([out["every step"]["runs"][i]["tension_pN"] for i in held])
    out["scene_box_seeds"] = [SEEDS[i] for i in held]
    out["scene_box_tension_pN"] = float(F.mean())
    out["scene_box_tension_err_pN"] = float(F.std(ddof=1) / math.sqrt(len(F)))
    print(f"runs that hold the scene's box (seeds {out['scene_box_seeds']}): tension "
          f"{F.mean():.2f} +- {F.std(ddof=1) / math.sqrt(len(F)):.2f} pN; boxes / L of all runs: "
          + ", ".join(f"{r['box_over_L']:.4f}" for r in out["every step"]["runs"]), flush=True)
    # the two runs of a seed share their noise, so they are paired: the error of the difference
    # is the scatter of the per-seed differences (independent realisations of it)
    a, b = out["every 0.5"]["runs"], out["every step"]["runs"]
    dF = np.array([x["tension_pN"] - y["tension_pN"] for x, y in zip(a, b)])
    dW = np.array([np.array(x["omega"]) / np.array(y["omega"]) - 1.0 for x, y in zip(a, b)])
    se = math.sqrt(len(SEEDS))
    out["difference"] = {"tension_pN": float(dF.mean()), "tension_err_pN": float(dF.std(ddof=1) / se),
                         "omega_relative": dW.mean(axis=0).tolist(),
                         "omega_relative_err": (dW.std(ddof=1, axis=0) / se).tolist(),
                         "note": "0.5 minus every step, paired by seed; errors from the scatter of the pairs"}
    print(f"0.5 - every step (paired): tension {dF.mean():+.3f} +- {dF.std(ddof=1) / se:.3f} pN; "
          "omega_n / omega_n(every step) - 1: "
          + ", ".join(f"{m:+.5f} +- {e:.5f}" for m, e in zip(dW.mean(axis=0), dW.std(ddof=1, axis=0) / se)),
          flush=True)
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--part", choices=["source", "cost", "wander", "interval", "all"], default="all")
    ap.add_argument("--out", type=Path, default=HERE / "results" / "thermal_closure.json")
    args = ap.parse_args(argv)
    result = json.loads(args.out.read_text()) if args.out.is_file() else {}
    for part, study in (("source", source_study), ("cost", cost_study), ("wander", wander_study),
                         ("interval", interval_study)):
        if args.part in (part, "all"):
            result[part] = study()
    result["rod"] = "the paper's 158-bp rod, 15 turns, 158 points"
    result["command"] = "/usr/bin/python3 bench/thermal_closure.py"
    write_json(args.out, result)
    return 0


if __name__ == "__main__":
    sys.exit(main())
