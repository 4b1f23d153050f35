"""Speed of `dnarod coarse-grain` (the budget, docs/coarse-graining.md: a 600-frame
trajectory of the 158-bp duplex in <= 30 s on 2 cores).

Makes a synthetic 600-frame trajectory of the periodic, ligated 158-bp duplex
(15 turns) with the toolkit's builder: step parameters drawn as an AR(1) series
(phi = 0.5) around B-DNA with Olson-like fluctuations, heavy atoms, PDB + TRR with
velocities at 300 K (the kinetic-temperature path is timed too). Then times the
whole command (read + frames + integrity + mass/inertia + kinetic temperature +
estimator with 200 bootstrap replicates on the default m grid up to 20 + files), CPU
and wall, and writes bench/results/coarsegrain.json. The duplex is analysed as
linear (--closed no): independent random steps do not close a ring, so the closing
step would be meaningless; it would add one step of 158 to the cost.

    /usr/bin/python3 bench/coarsegrain.py [--frames 600] [--out bench/results]
"""
from __future__ import annotations

import argparse
import json
import os
import resource
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

from dna_models.bdna import RISE_A


def make_trajectory(directory, n_bp=158, frames=600, seed=0):
    from mdbridge.coarsegrain.synthetic import ar1_steps
    import MDAnalysis as mda
    from MDAnalysis.coordinates.memory import MemoryReader
    from mdbridge.md.builder.duplex import build_duplex
    from mdbridge.geometry.steps import frames_from_steps
    from mdbridge.md.gromacs.velocities import thermal_velocities
    from mdbridge.md.pdbio import write_pdb

    rng = np.random.default_rng(seed)
    seq = "".join(rng.choice(list("ACGT"), n_bp))
    rise, twist = RISE_A, 360.0 * 15 / n_bp
    mean = np.tile([0.0, 0.0, rise, 0.0, 0.0, twist], (n_bp - 1, 1))
    K = np.tile(np.diag(1 / np.array([0.5, 0.5, 0.2, 3.0, 4.5, 3.5]) ** 2), (n_bp - 1, 1, 1))
    q = ar1_steps(mean, K, frames, 0.5, rng)
    box = np.array([80.0, 80.0, n_bp * rise])
    pos = []
    for qt in q:
        R, o = frames_from_steps(qt)
        pos.append(build_duplex(seq, o, R, periodic_box=box).coords)
    R, o = frames_from_steps(q[0])
    d = Path(directory)
    write_pdb(d / "dna158.pdb", build_duplex(seq, o, R, periodic_box=box))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        u = mda.Universe(str(d / "dna158.pdb"))
    pos = np.array(pos, dtype=np.float32)
    vel = np.array([10.0 * thermal_velocities(u.atoms.masses, 300.0, k) for k in range(frames)],
                   dtype=np.float32)                                    # nm/ps -> A/ps
    dims = np.tile(np.r_[box, 90, 90, 90], (frames, 1)).astype(np.float32)
    u.load_new(pos, format=MemoryReader, velocities=vel, dimensions=dims, dt=10.0)
    with mda.Writer(str(d / "dna158.trr"), n_atoms=u.atoms.n_atoms) as w:
        for _ in u.trajectory:
            w.write(u.atoms)
    return d / "dna158.pdb", d / "dna158.trr", u.atoms.n_atoms


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--frames", type=int, default=600)
    ap.add_argument("--out", default=str(Path(__file__).resolve().parent / "results"))
    a = ap.parse_args()
    from dnarod.cli import main as dnarod
    with tempfile.TemporaryDirectory() as tmp:
        t0 = time.time()
        pdb, trr, n_atoms = make_trajectory(tmp, frames=a.frames)
        t_make = time.time() - t0
        r0 = resource.getrusage(resource.RUSAGE_SELF)
        w0 = time.time()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            rc = dnarod(["coarse-grain", str(pdb), str(trr), "--closed", "no",
                         "-o", str(Path(tmp) / "cg")])
        wall = time.time() - w0
        r1 = resource.getrusage(resource.RUSAGE_SELF)
        cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
        p = json.loads((Path(tmp) / "cg" / "params.json").read_text())
    res = {"frames": a.frames, "n_bp": 158, "atoms": int(n_atoms), "exit_code": rc,
           "wall_s": round(wall, 2), "cpu_s": round(cpu, 2), "trajectory_build_s": round(t_make, 1),
           "m_max": max(b["m"] for b in p["by_length"]), "bootstrap": p["bootstrap"],
           "temperature_K": p["temperature_K"], "temperature_source": p["temperature_source"],
           "threads": os.environ.get("OMP_NUM_THREADS", "default"), "load_avg": os.getloadavg(),
           "budget_s": 30.0}
    Path(a.out).mkdir(parents=True, exist_ok=True)
    (Path(a.out) / "coarsegrain.json").write_text(json.dumps(res, indent=1) + "\n")
    print(json.dumps(res, indent=1))


if __name__ == "__main__":
    main()
