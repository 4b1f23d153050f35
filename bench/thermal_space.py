#!/usr/bin/python3
"""What the spatial operator does to the mode frequencies of a thermal rod (docs/thermal.md,
"Spatial operator of thermal runs").

The paper's 158-bp rod (15 turns, one point per base pair), linearised about its uniform
state at zero tension and at the 300-K slack tension, through rodcore's own right-hand side
with solver.space = "spectral" (exact on every resolved Fourier mode: the continuum operator)
and "fd4" (mdbridge/rod/linear.py's LinearRod, whose scene is given the operator). Per kind
(bend, twist, stretch) and lab mode number n = 1 .. 40: the fd4 frequency's relative error
against spectral, and the same for every resolved mode (the thermal state fills them all).

    /usr/bin/python3 bench/thermal_space.py [--out bench/results/thermal_space.json]

Needs the Python module rodcore on PYTHONPATH (build/python); a few seconds.
"""
from __future__ import annotations

import argparse
import dataclasses
import sys
from pathlib import Path

import numpy as np

from dna_models.units import Units
from mdbridge.jsonio import write_json
from mdbridge.rod.linear import LinearRod, UniformMaterial, dispersion

HERE = Path(__file__).resolve().parent


@dataclasses.dataclass(frozen=True)
class WithOperator(UniformMaterial):
    space: str = "spectral"

    def scene(self, length: float, points: int) -> dict:
        sc = super().scene(length, points)
        sc["solver"] = {"space": self.space}
        return sc


def frequencies(space: str, tension: float, n_max: int) -> dict:
    u = Units.paper()
    L = 158 * u.length_to_rod(u.rise_A)
    base = UniformMaterial.paper(2 * np.pi * 15 / L)
    mat = WithOperator(**{f.name: getattr(base, f.name) for f in dataclasses.fields(base)}, space=space)
    modes = LinearRod(mat, L, 158, tension=tension, turns=15).modes(n_max)
    return {kind: {n: v["omega"] for n, v in dispersion(modes, kind).items() if n >= 1}
            for kind in ("bend", "twist", "stretch")}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=HERE / "results" / "thermal_space.json")
    args = ap.parse_args(argv)
    u = Units.paper()
    result = {"rod": "the paper's 158-bp rod, 15 turns, 158 points", "rows": [],
              "command": "/usr/bin/python3 bench/thermal_space.py"}
    for tension_pN in (0.0, 23.0):
        T = tension_pN * 1e-12 / u.C
        spec, fd4 = frequencies("spectral", T, 79), frequencies("fd4", T, 79)
        for kind in spec:
            for n in sorted(spec[kind]):
                if n not in fd4[kind]:
                    continue
                err = fd4[kind][n] / spec[kind][n] - 1
                result["rows"].append({"tension_pN": tension_pN, "kind": kind, "n": n,
                                       "omega_spectral": spec[kind][n], "omega_fd4": fd4[kind][n],
                                       "relative_error_fd4": err})
        for kind in spec:
            errs = {r["n"]: r["relative_error_fd4"] for r in result["rows"]
                    if r["kind"] == kind and r["tension_pN"] == tension_pN}
            show = {n: f"{errs[n]:+.2e}" for n in (1, 2, 4, 8, 15, 30, 60) if n in errs}
            print(f"T = {tension_pN:4.1f} pN {kind:8s} fd4 / spectral - 1: {show}; "
                  f"largest over n <= 79: {max(abs(e) for e in errs.values()):.3f}", flush=True)
    write_json(args.out, result)
    return 0


if __name__ == "__main__":
    sys.exit(main())
