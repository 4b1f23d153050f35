"""The paper's 158-bp scene with its MD's own random sequence under Olson 1998,
next to the paper's uniform rod: rod runs of 600 ps at A_v = 1 A/ps
and the standing-mode phase speed fitted by the comparison's analysis
(mdbridge.analysis.WaveAnalysis + the standing-mode fit, exactly as `dnarod
compare` does for a rod: workflows/steps/analyse.py, analyse_rod).

The MD's sequence: `dnarod build-md` draws random_sequence(158, seed) and the
workflow's MD uses --seed 1 (workflows/config/*.yaml, md.build_args), so
`dnarod dna-rod --random 158 --seed 1` is the same DNA. A third run, the
sequence rod's closed rest state without the kick, measures how much the rest
state itself moves in the solver (its statics residual is the discretisation
error: docs/scenes.md), i.e. the floor under the kicked run's mode amplitude.

  nice -n 15 python bench/sequence_rod.py [--out DIR] [--ps 600]
Writes DIR/sequence_rod.json (default bench/results).
"""
import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]


def rodsim():
    import os
    return str(Path(os.environ.get("DNAROD_BUILD", ROOT / "build")) / "bin" / "rodsim")


def analyse(h5, n_bp, in_plane):
    from mdbridge.analysis import BasePairTrajectory, WaveAnalysis
    from dnarod.steps import matched
    traj = BasePairTrajectory.from_rod_h5(h5, n_bp)
    a = WaveAnalysis(traj, in_plane=in_plane, offset=True, n_boot=0).run()
    sm = matched.mode_fit(a)
    r = a.results
    return {"standing_mode_speed_A_per_ps": sm.get("speed_A_per_ps"),
            "standing_mode_speed_err_A_per_ps": sm.get("speed_err_A_per_ps"),
            "standing_mode": {k: v for k, v in sm.items() if np.isscalar(v) or isinstance(v, str)},
            "travelling_wave_speed_A_per_ps": r.wave["speed_A_per_ps"],
            "max_mode_amplitude_A": float(np.max(np.abs(r.mode_amplitude))),
            "length_A": float(r.length_A)}


def run(cmd, log):
    import resource

    def child_cpu():
        r = resource.getrusage(resource.RUSAGE_CHILDREN)
        return r.ru_utime + r.ru_stime
    t0, c0 = time.time(), child_cpu()
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode:
        sys.exit(f"{' '.join(map(str, cmd))} failed:\n{p.stderr}")
    log.append({"cmd": " ".join(map(str, cmd)), "wall_s": round(time.time() - t0, 1),
                "cpu_s": round(child_cpu() - c0, 1),
                "stderr_tail": p.stderr.strip().splitlines()[-1:] if p.stderr else []})
    return p


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", type=Path, default=Path(__file__).parent / "results")
    ap.add_argument("--work", type=Path, default=Path("/tmp/dnarod-sequence-rod"))
    ap.add_argument("--ps", type=float, default=600.0)
    ap.add_argument("--points-per-bp", type=int, default=1,
                    help="grid points per base pair of the sequence rod (dna-rod --points-per-bp); "
                         "results go to sequence_rod.json (1) or sequence_rod_ppbM.json")
    a = ap.parse_args()
    log, out = [], {}
    import shutil
    from dna_models.units import Units
    dnarod = shutil.which("dnarod") or sys.exit("dnarod not on PATH")
    a.work = a.work / f"ppb{a.points_per_bp}"
    a.work.mkdir(parents=True, exist_ok=True)
    kicked, rest = a.work / "olson1998_kicked", a.work / "olson1998_rest"
    run([dnarod, "dna-rod", "--random", "158", "--seed", "1", "--params", "olson1998",
         "--kick", "1.0", "--t-end-ps", str(a.ps), "--points-per-bp", str(a.points_per_bp), "-o", str(kicked)], log)
    # the same rest state without the kick (velocities zeroed in a copy of the initial file)
    import h5py
    shutil.copytree(kicked, rest, dirs_exist_ok=True)
    with h5py.File(rest / "rest.h5", "a") as f:
        f["fields/gamma"][...] = 0.0
        f["fields/omega"][...] = 0.0
    for name, d in (("olson1998_kicked", kicked), ("olson1998_rest", rest)):
        run([rodsim(), "run", str(d / "scene.toml"), "-o", str(d / "rod.h5")], log)
        info = json.loads((d / "rest.json").read_text())
        ax = np.array(info["axis0"])
        e = np.array([1.0, 0.0, 0.0]) - ax[0] * ax       # the kick's direction (dna-rod --kick)
        out[name] = dict(analyse(d / "rod.h5", 158, (e / np.linalg.norm(e)).tolist()),
                         sequence=info["sequence"], tension_pN=info["tension_pN"],
                         torque_pN_nm=info["torque_pN_nm"], statics_residual=info["statics_residual"])
    scene = ROOT / "workflows" / "scenes" / "dna158.toml"
    h5 = a.work / "paper158.h5"
    run([rodsim(), "run", str(scene), "-o", str(h5), "--set", f"output.t_end={Units.paper().time_to_rod(a.ps)!r}"], log)
    out["paper_uniform"] = analyse(h5, 158, [0.0, 0.0, 1.0])
    out["commands"] = log
    a.out.mkdir(parents=True, exist_ok=True)
    name = "sequence_rod.json" if a.points_per_bp == 1 else f"sequence_rod_ppb{a.points_per_bp}.json"
    (a.out / name).write_text(json.dumps(out, indent=1, default=float))
    for k in ("olson1998_kicked", "olson1998_rest", "paper_uniform"):
        v = out[k]
        print(f"{k}: standing-mode speed {v['standing_mode_speed_A_per_ps']} +- "
              f"{v['standing_mode_speed_err_A_per_ps']} A/ps, max mode amplitude {v['max_mode_amplitude_A']:.3g} A")


if __name__ == "__main__":
    main()
