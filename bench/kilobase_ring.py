#!/usr/bin/python3
"""The shipped 10.5-kbp ring in water (workflows/scenes/dna10k_water.toml, solver.time = "brownian": an
Olson 1998 sequence on 10-bp segments, closed, from its rest state, with self-contact): what a run
costs, in its parts. From the exact-sample start (closed by continuation, docs/thermal.md,
"Thermal states") for `--ns` of simulated time at the scene's 100-ps step, 10 frames per 100 ns:

* the sample: the process CPU seconds of a run of one step with frames at 0 and 100 ps (the median
  of three, after a warm-up run), less a step, and the note's Newton steps and continuation stages;
* the run: CPU seconds per step, (run - one-step run) / (steps - 1), and per simulated ns (process
  CPU time, which a shared machine's load moves by 10-30 %: the median of --repeat runs),
  bp us per CPU second (10500 bp), and the full 1 us the scene is for, extrapolated;
* the frames: Lk, Tw, Wr per frame, with the number of Lk jumps (the scene's [contact] is there to
  keep the ring from passing through itself: the count says whether it does), and max |Lk - Tw - Wr|.

    /usr/bin/python3 bench/kilobase_ring.py [--ns 10] [--seed 1] [--repeat 3] [--out bench/results/kilobase_ring.json]

Needs the Python module rodcore on PYTHONPATH (build/python). A full-length run (--ns 1000) takes
about 1000 x the CPU seconds per ns printed by a short one.
"""
from __future__ import annotations

import argparse
import resource
import statistics
import tomllib
import sys
from pathlib import Path

import numpy as np
import rodcore

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))
from dna_models.units import Units  # noqa: E402
from mdbridge.jsonio import write_json  # noqa: E402

SCENE = HERE.parent / "workflows" / "scenes" / "dna10k_water.toml"
DT = tomllib.loads(SCENE.read_text())["solver"]["dt"]     # the scene's step, 100 ps
BP = 10500


def report(res: dict, out: Path | None) -> None:
    """Print a result's entries and write it to `out` (if given)."""
    for k, v in res.items():
        print(f"{k}: {v}")
    if out:
        write_json(out, res)


def cpu_seconds() -> float:
    r = resource.getrusage(resource.RUSAGE_SELF)
    return r.ru_utime + r.ru_stime


def run(seed: int, steps: int, frames: int) -> tuple[dict, float]:
    t0 = cpu_seconds()
    out = rodcore.run(str(SCENE), set=[f"thermal.seed={seed}", f"output.t_end={steps * DT!r}",
                                       f"output.frames={frames}"])
    return out, cpu_seconds() - t0


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--ns", type=float, default=10.0, help="simulated ns (a multiple of 10; default 10)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--repeat", type=int, default=3, help="runs of the full length, the median CPU quoted")
    ap.add_argument("--out", type=Path, default=None)
    a = ap.parse_args(argv)
    tau_ps = Units.paper().tau_ps
    step_ps = DT * tau_ps
    steps = int(round(a.ns * 1000 / step_ps))
    frames = max(2, int(round(a.ns / 10)) + 1)        # 10 frames per 100 ns
    if steps % (frames - 1):
        print(f"--ns {a.ns}: must be a multiple of 10 ns", file=sys.stderr)
        return 2
    run(a.seed, 1, 2)  # warm-up: the process's first run pays one-time costs (planning, loading)
    ones = [run(a.seed, 1, 2) for _ in range(3)]
    one, cpu_one = ones[0][0], statistics.median(c for _, c in ones)
    longs = [run(a.seed, steps, frames) for _ in range(a.repeat)]
    out, cpu = longs[0][0], statistics.median(c for _, c in longs)
    step_cpu = (cpu - cpu_one) / (steps - 1)
    sample_cpu = cpu_one - step_cpu
    ns = steps * step_ps / 1000
    per_ns = (cpu - sample_cpu) / ns
    top = out["topology"]
    Lk, Tw, Wr = (np.asarray(top[k]) for k in ("Lk", "Tw", "Wr"))
    res = {"scene": str(SCENE.relative_to(HERE.parent)), "seed": a.seed, "ns": ns, "steps": steps,
           "cpu_s_runs": [c for _, c in longs],
           "frames": frames, "sample_note": one["summary"]["thermal_note"].split(";")[0],
           "sample_cpu_s": sample_cpu, "cpu_s_per_step": step_cpu, "cpu_s_per_ns": per_ns,
           "bp_us_per_cpu_s": BP * 1e-3 / per_ns, "one_us_cpu_s": 1000 * per_ns,
           "Lk": Lk.tolist(), "Lk_jumps": int(np.count_nonzero(np.diff(Lk))),
           "max_Lk_minus_Tw_Wr": float(np.nanmax(np.abs(Lk - Tw - Wr)))}
    report(res, a.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
