#!/usr/bin/python3
"""The shipped 10.5-kbp ring (workflows/scenes/dna10k_water.toml) started from rest
(thermal.sample_initial = false) at the scene's own dt: how fast its elastic energy reaches
equipartition. The potential energy per frame (elastic plus contact, the `energy` dataset of a
`brownian` run) less the rest energy (frame 0), over (6 N - 6) kT / 2 (the six closure constraints
removed); its mean over --window-ns and the frame-to-frame scatter.

    /usr/bin/python3 bench/kilobase_equipartition.py [--ns 100] [--frame-ns 5] [--window-ns 50 100]
        [--out bench/results/kilobase_equipartition.json]
"""
from __future__ import annotations

import argparse
import resource
import sys
import tomllib
from pathlib import Path

import numpy as np
import rodcore

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
sys.path.insert(0, str(HERE))
from dna_models.units import Units  # noqa: E402
from kilobase_ring import SCENE  # noqa: E402
from mdbridge.jsonio import write_json  # noqa: E402


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--ns", type=float, default=100.0)
    ap.add_argument("--frame-ns", type=float, default=5.0)
    ap.add_argument("--window-ns", type=float, nargs=2, default=[50.0, 100.0])
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--out", type=Path, default=None)
    a = ap.parse_args(argv)
    u = Units.paper()
    with open(SCENE, "rb") as f:
        sc = tomllib.load(f)
    dt = sc["solver"]["dt"]
    step_ns = dt * u.tau_ps / 1000
    steps = int(round(a.ns / step_ns))
    frames = int(round(a.ns / a.frame_ns)) + 1
    t0 = resource.getrusage(resource.RUSAGE_SELF).ru_utime
    out = rodcore.run(str(SCENE), set=["thermal.sample_initial=false", f"output.t_end={steps * dt!r}",
                                       f"output.frames={frames}", f"thermal.seed={a.seed}"])
    cpu = resource.getrusage(resource.RUSAGE_SELF).ru_utime - t0
    N = sc["rod"]["points"]
    kT = u.kT_to_rod(sc["thermal"]["temperature_K"])
    E = np.asarray(out["energy"], float)
    t_ns = np.asarray(out["time"]) * u.tau_ps / 1000
    ratio = (E - E[0]) / ((6 * N - 6) * kT / 2)
    w = (t_ns >= a.window_ns[0]) & (t_ns <= a.window_ns[1])
    res = {"scene": str(SCENE.relative_to(HERE.parent)), "seed": a.seed, "dt_ps": step_ns * 1000, "points": N,
           "rest_energy_kT": float(E[0] / kT), "time_ns": t_ns.tolist(), "energy_over_equipartition": ratio.tolist(),
           "window_ns": a.window_ns, "mean_in_window": float(ratio[w].mean()),
           "frame_scatter_in_window": float(ratio[w].std(ddof=1)), "cpu_s": cpu,
           "command": "bench/kilobase_equipartition.py " + " ".join(argv if argv is not None else sys.argv[1:])}
    print(f"energy / equipartition over {a.window_ns} ns: {res['mean_in_window']:.4f} (frames scatter "
          f"{res['frame_scatter_in_window']:.4f}); per frame {np.round(ratio, 3).tolist()}; {cpu:.0f} CPU s")
    if a.out:
        write_json(a.out, res)
    return 0


if __name__ == "__main__":
    sys.exit(main())
