"""The duplex in water held at a tension it is told (build-md --axial-tension-pN): the runs of
results/water21 (docs/md.md, "DNA in water: the 21-bp runs").

    python bench/water_tension.py [--tensions 0 30] [--ps 200] [--work /tmp/water_tension]
                                  [--threads 2] [--gmx gmx] [--results results/water21]

What runs (dna21.toml with A_v = 0, an equilibrium duplex; seed 4; per tension T):
1. `dnarod build-md --solvent tip3p --salt-mM 150 --minimize --thermostat --axial-tension-pN T`,
   h-bond constraints, 2 fs, smooth vdW, PME, v-rescale (tau-t 1 ps) at 300 K, semi-isotropic
   C-rescale (1 bar across, ref_p_z = 1 - 10 T / A_xy), the 20-ps equilibration stage;
2. --ps of MD, energies (pressure tensor, box) every 10 steps, frames every 0.2 ps.
Each stage is skipped when its build.json / md.done is in WORK, so the script continues (a
checkpoint of the same request resumes). Then `dnarod.steps.water` measures every finished run
in WORK into RESULTS: the tension against the set one (test 1), the length gained between the
lowest and the highest tension against the lower run's own stretch modulus (test 2), the pairs,
and the coarse-graining (workflows/steps/water.py says what each file holds).

Cost (measured in results/water21: 17,002 atoms, 6.5-7 ns/day on one core of Debian's SSE4.1
gmx, 10 ns/day on two): a 200-ps run is ~45 min of one core. Resolution: the tension's error
at 200 ps is above 3 pN (pressure fluctuations of ~150 bar over ~26 nm^2 are ~400 pN per frame),
and 30 pN adds ~0.2 nm to a 7-nm duplex whose length fluctuates by ~0.16 nm: both want ns.
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

from md_tension import scene_av0
from mdbridge.md.gromacs.run import _set_keys, run_md

REPO = Path(__file__).resolve().parents[1]
SEED = 4
BUILD = ["--solvent", "tip3p", "--salt-mM", "150", "--minimize", "--thermostat", "--constraints", "h-bonds",
         "--dt", "0.002", "--cutoffs", "smooth", "--temperature", "300", "--seed", str(SEED), "--ps", "1"]


def build(work: Path, T: float, a) -> Path:
    d = work / f"T{T:g}"
    if not (d / "build.json").is_file():
        subprocess.run([sys.executable, "-m", "dnarod.cli", "build-md", str(scene_av0(work)), "-o", str(d), *BUILD,
                        "--axial-tension-pN", str(T), "--gmx", a.gmx, "--threads", str(a.threads)], check=True)
    return d


def run(d: Path, a) -> dict:
    if (d / "md.done").is_file():
        return json.loads((d / "md.done").read_text())
    mdp = (d / "md.mdp").read_text()
    (d / "md.mdp").write_text(_set_keys(mdp, {"nstenergy": 10, "nstcalcenergy": 10, "nstxout-compressed": 100,
                                              "nstlog": 5000}))
    return run_md(d, ps=a.ps, gmx=a.gmx, threads=a.threads, checks=False, stream=None)


def main() -> int:
    from dnarod.steps.water import analyse
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--tensions", type=float, nargs="+", default=[0.0, 30.0])
    ap.add_argument("--ps", type=float, default=200.0)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--work", type=Path, default=Path("/tmp/water_tension"))
    ap.add_argument("--gmx", default="gmx")
    ap.add_argument("--results", type=Path, default=REPO / "results" / "water21")
    a = ap.parse_args()
    a.work.mkdir(parents=True, exist_ok=True)
    dirs = []
    for T in sorted(a.tensions):
        d = build(a.work, T, a)
        run(d, a)
        dirs.append(d)
    analyse(a.results, dirs, gmx=a.gmx)
    print((a.results / "summary.json").read_text())
    return 0


if __name__ == "__main__":
    sys.exit(main())
