#!/usr/bin/python3
"""A supercoiled kilobase ring in water (docs/topology.md, "Supercoiled kilobase rings"): the
overdamped rod (solver.time = "brownian") with self-contact, the paper's uniform DNA closed into
a ring of --bp base pairs at linking-number difference --delta-lk (sigma = delta-lk / (bp / 10.5)),
from the planar twisted circle at rest (its linearised sample would not do: the circle is unstable
to buckling at this twist), several seeds. Per run and frame:
Lk, Tw, Wr (rodsim's, docs/topology.md), the energy; per seed the strand-passage guard's note.
Reduced to <Wr> over the frames after --discard-ns, with its error from the blocked scatter
(blocks of --block-ns, pooled over the seeds: blocks longer than the writhe's autocorrelation
time, checked by the block-length scan printed with it).

    /usr/bin/python3 bench/supercoil_ring.py [--bp 1050] [--bp-per-point 3] [--delta-lk -6]
        [--dt-ps 100] [--ns 2000] [--seeds 1 2 3 4] [--out bench/results/supercoil_ring.json]

Needs the Python module rodcore on PYTHONPATH (build/python).
"""
from __future__ import annotations

import argparse
import resource
import sys
import tempfile
from pathlib import Path

import numpy as np
import rodcore

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
from dna_models.units import Units  # noqa: E402
from mdbridge.jsonio import write_json  # noqa: E402
from mdbridge.rod.material.gridfile import write_initial_file  # noqa: E402
from mdbridge.rod.scene import write_scene  # noqa: E402

RISE_A = 3.4
BP_PER_TURN = 10.5
DIAMETER_NM = 5.0   # 0.15 M NaCl (Rybenkov, Cozzarelli & Vologodskii, PNAS 90:5307, 1993)


def cpu_seconds() -> float:
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def twisted_circle(N: int, L: float, delta_lk: int):
    """The planar circle of an intrinsically straight, untwisted rod twisted by delta_lk turns:
    Omega = (kappa cos phi, -kappa sin phi, tau), phi = tau s, kappa = 2 pi / L, tau = 2 pi delta_lk / L
    (mdbridge/rod/material/ring.py with Omega0 = 0): closed exactly, Lk = Tw = delta_lk, Wr = 0."""
    s = np.arange(N) * L / N
    kappa, tau = 2 * np.pi / L, 2 * np.pi * delta_lk / L
    Omega = np.c_[kappa * np.cos(tau * s), -kappa * np.sin(tau * s), np.full(N, tau)]
    Gamma = np.c_[np.zeros(N), np.zeros(N), np.ones(N)]
    return s, Gamma, Omega


def scene(a, N: int, L: float, u: Units, initial: Path) -> dict:
    dt = a.dt_ps / u.tau_ps
    steps = int(round(a.ns * 1000 / a.dt_ps))
    frames = int(round(a.ns / a.frame_ns)) + 1
    if steps % (frames - 1):
        raise SystemExit(f"--ns {a.ns} is not a multiple of --frame-ns {a.frame_ns} in steps of {a.dt_ps} ps")
    return {"rod": {"length": L, "points": N, "Gamma0": [0.0, 0.0, 1.0], "Omega0": [0.0, 0.0, 0.0]},
            "initial": {"kind": "file", "path": str(initial)},
            # from rest: the linearised sample of the buckling-unstable twisted circle is no start
            "thermal": {"temperature_K": 300.0, "seed": 1, "friction_translational": "water",
                        "friction_rotational": "water", "sample_initial": False},
            "contact": {"diameter_nm": DIAMETER_NM, "barrier_kT": a.barrier_kT},
            "solver": {"time": "brownian", "dt": dt},
            "output": {"t_end": steps * dt, "frames": frames, "fields": ["energy"]}}


def blocked_mean(series: list[np.ndarray], block: int) -> tuple[float, float, int]:
    """Mean of the pooled block means and its standard error (blocks of `block` frames per series)."""
    means = [x[k * block:(k + 1) * block].mean() for x in series for k in range(len(x) // block)]
    m = np.asarray(means)
    return float(m.mean()), float(m.std(ddof=1) / np.sqrt(len(m))), len(m)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bp", type=int, default=1050)
    ap.add_argument("--bp-per-point", type=int, default=3)
    ap.add_argument("--delta-lk", type=int, default=-6)
    ap.add_argument("--dt-ps", type=float, default=100.0)
    ap.add_argument("--ns", type=float, default=2000.0)
    ap.add_argument("--frame-ns", type=float, default=1.0)
    ap.add_argument("--discard-ns", type=float, default=200.0)
    ap.add_argument("--block-ns", type=float, default=200.0)
    ap.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3, 4])
    ap.add_argument("--barrier-kT", type=float, default=100.0)
    ap.add_argument("--out", type=Path, default=None)
    a = ap.parse_args(argv)
    u = Units.paper()
    N = a.bp // a.bp_per_point
    L = a.bp * RISE_A / u.ell_A
    work = Path(tempfile.mkdtemp(prefix="supercoil_"))
    write_initial_file(work / "ring.h5", *twisted_circle(N, L, a.delta_lk))
    sc = scene(a, N, L, u, work / "ring.h5")
    write_scene(work / "scene.toml", sc, comment="bench/supercoil_ring.py")
    runs, Wr_series = [], []
    for seed in a.seeds:
        t0 = cpu_seconds()
        out = rodcore.run(str(work / "scene.toml"), set=[f"thermal.seed={seed}"])
        cpu = cpu_seconds() - t0
        top = out["topology"]
        Lk, Tw, Wr = (np.asarray(top[k], float) for k in ("Lk", "Tw", "Wr"))
        t_ns = np.asarray(out["time"]) * u.tau_ps / 1000
        keep = t_ns >= a.discard_ns
        Wr_series.append(Wr[keep])
        runs.append({"seed": seed, "cpu_s": cpu, "Lk": sorted(set(Lk.tolist())),
                     "max_Lk_minus_Tw_Wr": float(np.max(np.abs(Lk - Tw - Wr))),
                     "Wr_mean_after_discard": float(Wr[keep].mean()), "note": out["summary"]["thermal_note"],
                     "time_ns": t_ns.tolist(), "Wr": Wr.tolist(), "Tw": Tw.tolist()})
        print(f"seed {seed}: {cpu:.1f} CPU s, Lk {runs[-1]['Lk']}, <Wr> {runs[-1]['Wr_mean_after_discard']:.3f}, "
              f"max|Lk-Tw-Wr| {runs[-1]['max_Lk_minus_Tw_Wr']:.1e}", flush=True)
    block = int(round(a.block_ns / a.frame_ns))
    scan = {f"{b * a.frame_ns:g}": blocked_mean(Wr_series, b)[1] for b in (block // 4, block // 2, block)
            if b >= 1}
    Wr_mean, Wr_err, n_blocks = blocked_mean(Wr_series, block)
    res = {"bp": a.bp, "bp_per_point": a.bp_per_point, "points": N, "delta_Lk": a.delta_lk,
           "sigma": a.delta_lk / (a.bp / BP_PER_TURN), "contact_diameter_nm": DIAMETER_NM, "dt_ps": a.dt_ps,
           "ns_per_seed": a.ns, "discard_ns": a.discard_ns, "block_ns": a.block_ns, "Wr_mean": Wr_mean,
           "Wr_err": Wr_err, "blocks": n_blocks, "Wr_err_by_block_ns": scan,
           "Wr_over_delta_Lk": Wr_mean / a.delta_lk,
           "command": "bench/supercoil_ring.py " + " ".join(argv if argv is not None else sys.argv[1:]),
           "runs": runs}
    print(f"<Wr> = {Wr_mean:.3f} +- {Wr_err:.3f} ({n_blocks} blocks; error by block length {scan}); "
          f"Wr / delta Lk = {Wr_mean / a.delta_lk:.3f}")
    if a.out:
        write_json(a.out, res)
    return 0


if __name__ == "__main__":
    sys.exit(main())
