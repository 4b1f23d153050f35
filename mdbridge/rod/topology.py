"""Linking number, twist and writhe of a rod run, frame by frame (docs/topology.md).

The rod's own curve, unsmoothed: the centreline r(s_i) and the ribbon along d1 made
perpendicular to the tangent r' (not to d3: under shear d3 is not the tangent, and the
twist about d3 is not the twist of the ribbon). The numbers themselves are
mdbridge.geometry.topology's `ribbon_topology`.

A rod closed into a ring has r(L) = r(0); a straight periodic rod (the box-held DNA) has
r(L) = r(0) + P, and gets the box-periodic convention of docs/topology.md.
"""
from __future__ import annotations

import numpy as np

from dna_models.errors import InputError
from dna_models.units import Units
from mdbridge.geometry.topology import is_closed, ribbon_topology, writhe_stride

from .run import RodRun

# Blocks of the coarsened writhe of a closed rod (rodcore.topology.writhe): Klenin-Langowski
# is O(N^2); coarsened to 955 blocks a 10.5-kbp frame is within 0.04 of the exact writhe
# (bench/topology.py, docs/topology.md). rodsim uses the same number.
WRITHE_POINTS = 1000


def rod_topology(run: RodRun, writhe_points: int = WRITHE_POINTS) -> dict:
    """Per frame of RUN: time_ps, Lk, Tw, Wr, Wr_coarsening (lists), and closed,
    writhe_stride, n_points. A periodic rod needs fields/Gamma for its period vector."""
    run.require("time", "s", "centerline", "directors")
    x = np.asarray(run.centerline, float)
    D = np.asarray(run.directors, float)
    T, N = x.shape[:2]
    closed = is_closed(x[0])
    if not closed:
        run.require("fields/Gamma")
        P = run.period()
    stride = writhe_stride(N, writhe_points) if closed else 1
    tau_ps = float(run.attrs.get("tau_ps", Units.paper().tau_ps))
    out: dict = {"time_ps": (np.asarray(run.time, float) * tau_ps).tolist(), "Lk": [], "Tw": [], "Wr": [],
                 "Wr_coarsening": []}
    for f in range(T):
        if is_closed(x[f]) != closed:
            raise InputError(f"{run.source}: frame {f} is {'open' if closed else 'closed'}, frame 0 "
                             f"{'closed' if closed else 'open'}; a rod stays a ring or stays periodic")
        r = ribbon_topology(x[f], D[f, :, :, 0], None if closed else P[f], stride)
        for k in ("Lk", "Tw", "Wr", "Wr_coarsening"):
            out[k].append(r[k])
    out.update(closed=closed, writhe_stride=stride, n_points=N)
    return out
