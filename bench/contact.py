"""Cost of self-contact ([contact], rodcore/src/rodcore/contact.hpp) per right-hand-side
evaluation, against the same RHS without it, on closed DNA rings at one point per base pair
(the paper's DNA material, 5-nm effective diameter), for contact.stride 1, 2, 3.

The ring is a circle with the thermal roughness of bench/topology.py's curve absent: no two
distant parts touch, so the cost is the floor of the cell-list walk (each bead visits the
beads of its own chain within the 27 cells around it, about 3 d_c / h of them, and the
sweep that rebuilds the centreline from the strains). A plectoneme adds its contacts on top.

Timing: rodcore.Simulation.rhs in a loop, with and without contact taken in turn (7
pairs), the ratio per pair; process time (the machine is shared). Writes
results/contact.json.

  nice -n 10 python bench/contact.py [--bp 1050 4200 10500]
"""
import argparse
import time
from pathlib import Path

import numpy as np
import rodcore

from dna_models.units import Units
from mdbridge.jsonio import write_json

UNITS = Units.paper()


def ring(N, L, Lk):
    """A closed ring of Lk turns of twist (Omega = (k sin tau s, k cos tau s, tau))."""
    s = np.arange(N) * L / N
    kap, tau = 2 * np.pi / L, 2 * np.pi * Lk / L
    z = np.zeros((N, 3))
    Omega = np.stack([kap * np.sin(tau * s), kap * np.cos(tau * s), np.full(N, tau)], 1)
    return {"gamma": z, "omega": z, "Gamma": np.tile([0, 0, 1.0], (N, 1)), "Omega": Omega}


def per_call(sim, y, calls):
    t = time.process_time()
    for _ in range(calls):
        sim.rhs(y)
    return (time.process_time() - t) / calls


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bp", type=int, nargs="+", default=[1050, 4200, 10500])
    ap.add_argument("--strides", type=int, nargs="+", default=[1, 2, 3])
    ap.add_argument("--pairs", type=int, default=7)
    ap.add_argument("--out", type=Path, default=Path(__file__).parent / "results")
    a = ap.parse_args()
    rows = []
    for bp in a.bp:
        L = bp * UNITS.rise_A / UNITS.ell_A
        init = ring(bp, L, round(bp / 10.5))
        base = {"rod": {"length": L, "points": bp, "Omega0": [0, 0, 2 * np.pi / 10.5 * bp / L]},
                "solver": {"space": "spectral"}}
        plain = rodcore.Simulation(base, initial=init)
        y = plain.y
        calls = max(20, 200_000 // bp)
        for stride in a.strides:
            sim = rodcore.Simulation({**base, "contact": {"diameter_nm": 5.0, "stride": stride}}, initial=init)
            t0, t1 = [], []
            for _ in range(a.pairs):
                t0.append(per_call(plain, y, calls))
                t1.append(per_call(sim, y, calls))
            ratio = np.array(t1) / np.array(t0)
            row = {"bp": bp, "stride": stride, "rhs_us": 1e6 * float(np.median(t0)),
                   "rhs_with_contact_us": 1e6 * float(np.median(t1)),
                   "ratio_median": float(np.median(ratio)), "ratio_range": [float(ratio.min()), float(ratio.max())]}
            print(row, flush=True)
            rows.append(row)
    a.out.mkdir(parents=True, exist_ok=True)
    write_json(a.out / "contact.json", {"what": "RHS cost with and without [contact] (5 nm) on a ring, "
                                        "1 point per bp; Simulation.rhs, process time, median of paired runs",
                                        "rows": rows})


if __name__ == "__main__":
    main()
