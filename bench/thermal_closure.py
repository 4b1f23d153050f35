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

    /usr/bin/python3 bench/thermal_closure.py [--part source|cost|wander|all] [--out bench/results/thermal_closure.json]

Needs the Python module rodcore on PYTHONPATH (build/python) and scipy; about two minutes.
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

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
from dna_models.units import Units  # noqa: E402
from mdbridge.jsonio import write_json  # noqa: E402

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


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--part", choices=["source", "cost", "wander", "all"], default="all")
    ap.add_argument("--out", type=Path, default=HERE / "results" / "thermal_closure.json")
    args = ap.parse_args(argv)
    result = json.loads(args.out.read_text()) if args.out.is_file() else {}
    for part, study in (("source", source_study), ("cost", cost_study), ("wander", wander_study)):
        if args.part in (part, "all"):
            result[part] = study()
    result["rod"] = "the paper's 158-bp rod, 15 turns, 158 points"
    result["command"] = "/usr/bin/python3 bench/thermal_closure.py"
    write_json(args.out, result)
    return 0


if __name__ == "__main__":
    sys.exit(main())
