"""Speed of BasePairFrames on a synthetic trajectory (docs/geometry.md, "Speed").

    /usr/bin/python3 bench/geometry_frames.py [--n-bp 158] [--frames 10000] [--xtc]

Builds a duplex of n_bp base pairs with random step and base-pair parameters
per frame, and times BasePairFrames(...).run() + step_parameters(). With
--xtc the trajectory is first written to a temporary XTC file (full atoms of
the bases) and read back, so the time includes MDAnalysis' XTC decoding.
"""
from __future__ import annotations

import argparse
import os
import tempfile
import time
import warnings

import numpy as np


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n-bp", type=int, default=158)
    ap.add_argument("--frames", type=int, default=10000)
    ap.add_argument("--xtc", action="store_true", help="round-trip through an XTC file")
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    from dna_models.bdna import STEP_PARAMETERS
    from dna_models.sequence import random_sequence
    from mdbridge.geometry.structure import BasePairFrames
    from mdbridge.geometry.synthetic import duplex_universe

    rng = np.random.default_rng(0)
    n, T = args.n_bp, args.frames
    chunk = 1000
    seq = random_sequence(n, seed=1)
    # build in chunks to bound memory, then concatenate the float32 coordinates
    coords = []
    for t0 in range(0, T, chunk):
        m = min(chunk, T - t0)
        # the ideal step (rise 3.38 A) at the paper's twist, 34.18 deg, plus noise
        ideal = np.array(STEP_PARAMETERS[:5] + (34.18,))
        p = np.tile(ideal, (m, n - 1, 1)) + rng.normal(0, 0.3, (m, n - 1, 6))
        u = duplex_universe(seq, p)
        coords.append(u.trajectory.timeseries(order="fac"))
    X = np.concatenate(coords)
    import MDAnalysis as mda
    from MDAnalysis.coordinates.memory import MemoryReader
    u.load_new(X, format=MemoryReader)
    print(f"{n} bp, {T} frames, {u.atoms.n_atoms} atoms")
    if args.xtc:
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "traj.xtc")
            with mda.Writer(path, u.atoms.n_atoms) as w:
                for _ in u.trajectory:
                    w.write(u.atoms)
            u.load_new(path)
            _time(BasePairFrames, u)
    else:
        _time(BasePairFrames, u)


def _time(cls, u):
    """Wall time and this process's CPU time (the latter is what an unloaded
    machine would show as wall time: the work is single-threaded numpy)."""
    t0, c0 = time.perf_counter(), time.process_time()
    b = cls(u).run()
    t1, c1 = time.perf_counter(), time.process_time()
    s = b.step_parameters()
    t2, c2 = time.perf_counter(), time.process_time()
    print(f"BasePairFrames.run: {t1 - t0:.2f} s wall ({c1 - c0:.2f} s CPU), "
          f"step_parameters: {t2 - t1:.2f} s wall ({c2 - c1:.2f} s CPU), "
          f"total {t2 - t0:.2f} s wall ({c2 - c0:.2f} s CPU) -> {s.shape}; load average "
          f"{os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
