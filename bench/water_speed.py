"""ns/day and atom counts of the solvated periodic duplex (build-md --solvent) on this machine.

    python bench/water_speed.py [--systems 21 158] [--steps 5000] [--threads 2]
                                [--work /tmp/water_speed] [--gmx GMX ...] [--out bench/results]

For each system (21: workflows/scenes/dna21.toml, 2 turns; 158: workflows/scenes/dna158.toml),
`dnarod build-md SCENE --solvent tip3p --salt-mM 150` in the production setting of a tension
run (h-bond constraints, 2 fs, smooth vdW, PME, v-rescale at 300 K, semi-isotropic C-rescale
at 0 pN), the box sized across the axis as every build-md sizes it (the rod's excursion over
--ps; 600 ps for 158 bp, the paper's run: the box of the kicked wave, ~5 x 17 nm across),
with build-md's restrained minimisation of the solvated system (--minimize: the rigid build's
DNA has H contacts at ~1.2 A; 10 steps of minimisation left the 158-bp system to crash with
LINCS warnings at MD step 0, measured); then --steps of MD from conf.gro with
`mdrun -resethway` (the timing counts the second half only: no start-up cost). Records per
system: atoms (DNA, water, ions), the box, ns/day, the wall and CPU time of the build (with
the minimisation) and of the MD, and the 1-ns cost in core-hours; writes
OUT/water_speed.json (one object per system).

The numbers are those of the machine as it is: other jobs on the cores slow it down
(`uptime` is recorded next to them). With --steps of a few, the script is only checked.
"""
from __future__ import annotations

import argparse
import json
import os
import re
import resource
import subprocess
import sys
import time
from pathlib import Path

from mdbridge.md.gromacs.run import ns_per_day

REPO = Path(__file__).resolve().parents[1]
SCENES = {21: REPO / "workflows/scenes/dna21.toml", 158: REPO / "workflows/scenes/dna158.toml"}
BOX_PS = {21: None, 158: 600.0}          # --ps of the build: the MD length the box is sized for
BUILD = ["--solvent", "tip3p", "--salt-mM", "150", "--minimize", "--constraints", "h-bonds", "--dt", "0.002",
         "--cutoffs", "smooth", "--temperature", "300", "--protocol", "paper", "--thermostat",
         "--axial-tension-pN", "0", "--seed", "1"]


def cpu_s() -> float:
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def timed(cmd: list[str], cwd: Path | None = None, stdin: str | None = None) -> dict:
    w0, c0 = time.time(), cpu_s()
    subprocess.run(cmd, cwd=cwd, check=True, input=stdin, text=True,
                   stdout=subprocess.DEVNULL if cwd else None)
    return {"wall_s": round(time.time() - w0, 1), "cpu_s": round(cpu_s() - c0, 1)}


def set_key(mdp: str, key: str, value) -> str:
    out = [f"{key:<24s}= {value}" if ln.split("=")[0].strip() == key else ln for ln in mdp.splitlines()]
    return "\n".join(out) + "\n"


def atoms(build: dict) -> dict:
    w = build["solvent"]
    return {"total": w["n_atoms"], "dna": build["n_atoms"], "water_molecules": w["n_water"],
            "cations": w["ions"]["n_cation"], "anions": w["ions"]["n_anion"],
            "box_nm": [round(x, 3) for x in build["box_nm"]]}


def one(n_bp: int, a, work: Path) -> list[dict]:
    """Build the system once (with the first --gmx), then time --steps of MD with each --gmx."""
    d = work / f"dna{n_bp}"
    base: dict = {"system": f"{n_bp} bp", "scene": str(SCENES[n_bp].relative_to(REPO))}
    if not (d / "build.json").is_file():
        ps = ["--ps", str(BOX_PS[n_bp])] if BOX_PS[n_bp] else []
        base["build"] = timed([sys.executable, "-m", "dnarod.cli", "build-md", str(SCENES[n_bp]), "-o", str(d),
                               *BUILD, *ps, "--gmx", a.gmx[0], "--threads", str(a.threads)])
    build = json.loads((d / "build.json").read_text())
    base["atoms"] = atoms(build)
    base["minimization"] = build.get("minimization")
    md = set_key((d / "md.mdp").read_text(), "nsteps", a.steps)
    (d / "speed_md.mdp").write_text(md)
    rows = []
    for gmx in a.gmx:
        timed([gmx, "grompp", "-f", "speed_md.mdp", "-c", "conf.gro", "-p", "topol.top", "-o", "speed_md.tpr",
               "-po", "speed_md_out.mdp"], d)
        run = timed([gmx, "mdrun", "-deffnm", "speed_md", "-nt", str(a.threads), "-resethway", "-noconfout"], d)
        log = (d / "speed_md.log").read_text()
        simd = re.search(r"SIMD instructions(?: selected at compile time)?:\s*(\S+)", log)
        ns_day = ns_per_day(log)
        rows.append({**base, "gmx": gmx, "simd": simd.group(1) if simd else None,
                     "md": {"steps": a.steps, "dt_ps": 0.002, "threads": a.threads, **run, "ns_per_day": ns_day,
                            "core_hours_per_ns": None if not ns_day else round(24.0 * a.threads / ns_day, 2)},
                     "uptime": os.getloadavg()})
    return rows


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--systems", type=int, nargs="+", default=[21, 158], choices=sorted(SCENES))
    ap.add_argument("--steps", type=int, default=5000, help="MD steps timed (the second half counts)")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--work", type=Path, default=Path("/tmp/water_speed"))
    ap.add_argument("--gmx", nargs="+", default=["gmx"], help="one or more gmx to time side by side")
    ap.add_argument("--out", type=Path, default=REPO / "bench" / "results")
    a = ap.parse_args()
    a.work.mkdir(parents=True, exist_ok=True)
    rows = [r for n in a.systems for r in one(n, a, a.work)]
    for r in rows:
        print(json.dumps(r))
    if a.steps >= 1000:            # a check of a few steps measures nothing: not recorded
        a.out.mkdir(parents=True, exist_ok=True)
        (a.out / "water_speed.json").write_text(json.dumps(rows, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
