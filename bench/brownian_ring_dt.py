#!/usr/bin/python3
"""dt convergence of the overdamped rod on a 1-kbp ring (docs/thermal.md, "The overdamped rod"):
each observable at dt and at dt / 16, side by side in one run.

* Imposed-mode relaxation (kT = 0, deterministic): the paper's uniform DNA as an intrinsically
  circular ring (a stress-free ring, as the shipped scene's material), 10 bp per point; a small
  out-of-plane bend Omega1 = eps cos(2 pi n s / L), n = 2 .. 10, or twist Omega3 = eps cos(2 pi s / L),
  is imposed and its amplitude (the projection of the strain deviation on that Fourier mode) read
  per frame; the relaxation time is the late-time slope of its logarithm.
* Mean-square displacement at 300 K of the grid points, in the frame of the ring's centre of mass
  removed, from --msd-lags ns, over --seeds exact-sample starts.

Reported: each observable's ratio at dt to that at dt / 16, and tau / dt for the modes (the first-
order error of the implicit step is about dt / (2 tau), docs/thermal.md).

    /usr/bin/python3 bench/brownian_ring_dt.py [--dt-ps 100] [--seeds 4] [--out bench/results/brownian_ring_dt.json]
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import rodcore

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
from dna_models.units import Units  # noqa: E402
from mdbridge.jsonio import write_json  # noqa: E402

BP, RISE_A, BP_PER_POINT = 1050, 3.4, 10
EPS = 1e-4


def scene(dt: float, t_end: float, frames: int, temperature_K: float, fields: list[str], initial=None) -> dict:
    u = Units.paper()
    N = BP // BP_PER_POINT
    L = BP * RISE_A / u.ell_A
    sc = {"rod": {"length": L, "points": N, "Gamma0": [0.0, 0.0, 1.0], "Omega0": [0.0, 2 * np.pi / L, 0.0]},
          "initial": {"kind": "rest"},
          "thermal": {"temperature_K": temperature_K, "seed": 1, "friction_translational": "water",
                      "friction_rotational": "water", "sample_initial": temperature_K > 0},
          "solver": {"time": "brownian", "dt": dt},
          "output": {"t_end": t_end, "frames": frames, "fields": fields}}
    return sc


def relaxation_time_ns(dt_ps: float, row: int, n: int, t_end_ns: float) -> float:
    """The late-time relaxation time of Omega_row's Fourier mode n imposed at rest, kT = 0."""
    u = Units.paper()
    dt = dt_ps / u.tau_ps
    steps = int(round(t_end_ns * 1000 / dt_ps))
    frames = 41
    steps -= steps % (frames - 1)
    sc = scene(dt, steps * dt, frames, 0.0, ["internal"])
    N = sc["rod"]["points"]
    L = sc["rod"]["length"]
    s = np.arange(N) * L / N
    mode = np.cos(2 * np.pi * n * s / L)
    Gamma = np.tile([0.0, 0.0, 1.0], (N, 1))
    Omega = np.tile([0.0, 2 * np.pi / L, 0.0], (N, 1))
    Omega[:, row] += EPS * mode
    z = np.zeros((N, 3))
    out = rodcore.run(sc, initial={"gamma": z, "omega": z, "Gamma": Gamma, "Omega": Omega})
    O = np.asarray(out["fields"]["Omega"])[:, row, :] if np.asarray(out["fields"]["Omega"]).shape[1] == 3 else \
        np.asarray(out["fields"]["Omega"])[:, :, row]
    A = np.abs((O - O[:, :].mean(axis=1, keepdims=True)) @ mode) * 2 / N
    t = np.asarray(out["time"]) * u.tau_ps / 1000
    late = (A > 1e-3 * A[0]) & (t >= t[-1] / 4)
    slope = np.polyfit(t[late], np.log(A[late]), 1)[0]
    return float(-1.0 / slope)


def superposed(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """y moved rigidly onto x (Kabsch): what is left of y - x is the ring's internal motion."""
    cx, cy = x.mean(0), y.mean(0)
    U, _, Vt = np.linalg.svd((y - cy).T @ (x - cx))
    R = Vt.T @ np.diag([1.0, 1.0, np.sign(np.linalg.det(Vt.T @ U.T))]) @ U.T
    return (y - cy) @ R.T + cx


def msd_nm2(dt_ps: float, lags_ns: list[float], seeds: list[int], t_end_ns: float) -> tuple[list, list]:
    """The grid points' mean-square displacement at each lag [nm^2]: with the centre of mass removed,
    and with the whole rigid motion removed (the later frame superposed on the earlier)."""
    u = Units.paper()
    dt = dt_ps / u.tau_ps
    frame_ns = min(lags_ns)
    steps = int(round(t_end_ns * 1000 / dt_ps))
    frames = int(round(t_end_ns / frame_ns)) + 1
    sc = scene(dt, steps * dt, frames, 300.0, ["centerline"])
    out_msd, internal = np.zeros(len(lags_ns)), np.zeros(len(lags_ns))
    for seed in seeds:
        sc["thermal"]["seed"] = seed
        x = np.asarray(rodcore.run(sc)["centerline"]) * u.ell_A / 10
        x = x - x.mean(axis=1, keepdims=True)                     # the centre of mass removed
        for k, lag in enumerate(lags_ns):
            m = int(round(lag / frame_ns))
            out_msd[k] += np.mean(np.sum((x[m:] - x[:-m]) ** 2, axis=-1)) / len(seeds)
            internal[k] += np.mean([np.sum((superposed(x[j], x[j + m]) - x[j]) ** 2, axis=-1).mean()
                                    for j in range(len(x) - m)]) / len(seeds)
    return out_msd.tolist(), internal.tolist()


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dt-ps", type=float, default=100.0)
    ap.add_argument("--seeds", type=int, default=4)
    ap.add_argument("--msd-ns", type=float, default=400.0)
    ap.add_argument("--msd-lags", type=float, nargs="+", default=[1.0, 3.0, 10.0, 30.0, 100.0])
    ap.add_argument("--modes", type=int, default=1, help="1: the imposed modes too; 0: the MSD only")
    ap.add_argument("--out", type=Path, default=None)
    a = ap.parse_args(argv)
    fine = a.dt_ps / 16
    res = {"bp": BP, "bp_per_point": BP_PER_POINT, "dt_ps": a.dt_ps, "fine_dt_ps": fine, "modes": [], "msd": {}}
    cases = [("bend", 0, n) for n in (2, 3, 5, 10)] + [("twist", 2, 1)] if a.modes else []
    for kind, row, n in cases:
        # long enough for the slow mode to decay (bend n: ~ L^4 / n^4; twist: fast)
        t_end = 20.0 if kind == "twist" else min(4000.0, 6000.0 / n ** 3)
        tau = relaxation_time_ns(a.dt_ps, row, n, t_end)
        tau_f = relaxation_time_ns(fine, row, n, t_end)
        res["modes"].append({"kind": kind, "n": n, "tau_ns": tau, "tau_fine_ns": tau_f, "ratio": tau / tau_f,
                             "tau_over_dt": tau_f * 1000 / a.dt_ps})
        print(f"{kind} n = {n}: tau {tau:.4g} ns at {a.dt_ps:g} ps, {tau_f:.4g} ns at {fine:g} ps: ratio "
              f"{tau / tau_f:.4f} (tau / dt = {tau_f * 1000 / a.dt_ps:.1f})", flush=True)
    seeds = list(range(1, a.seeds + 1))
    coarse, coarse_int = msd_nm2(a.dt_ps, a.msd_lags, seeds, a.msd_ns)
    fine_m, fine_int = msd_nm2(fine, a.msd_lags, seeds, a.msd_ns)
    res["msd"] = {"lags_ns": a.msd_lags, "seeds": a.seeds, "t_end_ns": a.msd_ns, "msd_nm2": coarse,
                  "msd_fine_nm2": fine_m, "ratio": (np.asarray(coarse) / np.asarray(fine_m)).tolist(),
                  "internal_nm2": coarse_int, "internal_fine_nm2": fine_int,
                  "internal_ratio": (np.asarray(coarse_int) / np.asarray(fine_int)).tolist()}
    print("MSD (centre of mass removed) ratio dt / (dt / 16) at lags", a.msd_lags, "ns:",
          np.round(res["msd"]["ratio"], 4).tolist(), "; rigid motion removed:",
          np.round(res["msd"]["internal_ratio"], 4).tolist(), "values", np.round(coarse_int, 2).tolist(),
          np.round(fine_int, 2).tolist())
    res["command"] = "bench/brownian_ring_dt.py " + " ".join(argv if argv is not None else sys.argv[1:])
    if a.out:
        write_json(a.out, res)
    return 0


if __name__ == "__main__":
    sys.exit(main())
