"""Linking number, twist and writhe of a rod run, frame by frame (docs/topology.md).

The ribbon along d1 made perpendicular to the tangent of the curve (not to d3: under shear
d3 is not the tangent, and the twist about d3 is not the twist of the ribbon), about two
curves, by mdbridge.geometry.topology's `ribbon_topology`:

* the helical axis (Lk, Tw, Wr): the centreline averaged over one helical turn
  (`one_turn_axis`, the axis the all-atom duplex gets, mdbridge.md.topology). A DNA rod's
  centreline is the base-pair origins, which circle the helix axis once per turn when the
  steps have shift and slide (Olson 1998: ~0.5 A); that small helix has a writhe of its
  own, about (1 - cos theta) per turn (theta its pitch angle; 0.007 per turn for Olson
  1998 DNA), which is not the DNA's supercoiling. The centreline is averaged only when it
  does circle an axis: the mean shear of the centreline in the base-pair frame (the d1, d2
  parts of r_{i+1} - r_{i-1}, `step_shear`) is at least SHEAR_FOR_AXIS of its d3 part,
  and the ribbon turns at least once. Otherwise (the paper's uniform DNA, a rod without intrinsic shear, a rod
  with less than a turn) the axis is the centreline: averaging a smooth curve over a
  window would only bend its writhe.
* the centreline itself (Tw_centreline, Wr_centreline): what rodsim writes per frame
  (topology/Tw, topology/Wr).

Both carry the same Lk (checked per frame).

A rod closed into a ring has r(L) = r(0); a straight periodic rod (the box-held DNA) has
r(L) = r(0) + P, and gets the box-periodic convention of docs/topology.md.
"""
from __future__ import annotations

import numpy as np

from dna_models.errors import InputError, NumericalError
from dna_models.units import Units
from mdbridge.geometry.topology import is_closed, one_turn_axis, ribbon_topology, writhe_stride

from .run import RodRun

# Blocks of the coarsened writhe of a closed rod (rodcore.topology.writhe): Klenin-Langowski
# is O(N^2); coarsened to 955 blocks a 10.5-kbp frame is within 0.04 of the exact writhe
# (bench/topology.py, docs/topology.md). rodsim uses the same number.
WRITHE_POINTS = 1000
# Mean shear of the steps / their rise above which the centreline circles a helical axis
# (module docstring). Olson 1998 DNA: 0.015-0.030 (slide). The writhe of that small helix
# grows as the shear squared: 0.007 per turn at 0.0275, below 3e-4 per turn under this.
SHEAR_FOR_AXIS = 0.005


def rod_topology(run: RodRun, writhe_points: int = WRITHE_POINTS) -> dict:
    """Per frame of RUN: time_ps, Lk, Tw, Wr, Wr_coarsening (about the helical axis),
    Tw_centreline, Wr_centreline, points_per_turn (None: no averaging) (lists), and closed,
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
    keys = ("Lk", "Tw", "Wr", "Wr_coarsening", "Tw_centreline", "Wr_centreline", "points_per_turn")
    out: dict = {"time_ps": (np.asarray(run.time, float) * tau_ps).tolist(), **{k: [] for k in keys}}
    for f in range(T):
        if is_closed(x[f]) != closed:
            raise InputError(f"{run.source}: frame {f} is {'open' if closed else 'closed'}, frame 0 "
                             f"{'closed' if closed else 'open'}; a rod stays a ring or stays periodic")
        r = frame_topology(x[f], D[f], None if closed else P[f], stride)
        if r["Lk"] != r["Lk_centreline"]:
            raise NumericalError(f"{run.source}: frame {f}: the ribbon about the helical axis links "
                                 f"{r['Lk']} times, about the centreline {r['Lk_centreline']} times")
        for k in keys:
            out[k].append(r[k])
    out.update(closed=closed, writhe_stride=stride, n_points=N)
    return out


def frame_topology(x, D, period=None, stride: int = 1) -> dict:
    """One frame, centreline x (N, 3), directors D (N, 3, 3) (D[i, :, k] = d_k): Lk, Tw, Wr,
    Wr_coarsening of the ribbon d1 about the helical axis of x (module docstring),
    Lk_centreline, Tw_centreline, Wr_centreline about x itself, and points_per_turn (None
    when the axis is x)."""
    x, D = np.asarray(x, float), np.asarray(D, float)
    d1 = D[:, :, 0]
    c = ribbon_topology(x, d1, period, stride)
    out = {"Lk_centreline": c["Lk"], "Tw_centreline": c["Tw"], "Wr_centreline": c["Wr"]}
    if abs(c["Tw"]) < 1.0 or step_shear(x, D, period) < SHEAR_FOR_AXIS:
        return {**c, **out, "points_per_turn": None}
    axis, per_turn = one_turn_axis(x, lambda _: d1, period)
    return {**ribbon_topology(axis, d1, period, stride), **out, "points_per_turn": per_turn}


def step_shear(x, D, period=None) -> float:
    """|mean over i of the (d1, d2) parts of r_{i+1} - r_{i-1}| / mean of their d3 parts, in
    the frame of point i (a closed or box-periodic centreline). The centred chord: its
    departure from the tangent of a curved rod is third order in the spacing (the chord to
    the next point bends off it by half the curvature times the spacing)."""
    ahead, behind = np.roll(x, -1, axis=0), np.roll(x, 1, axis=0)
    if period is not None:
        ahead[-1] += np.asarray(period, float)
        behind[0] -= np.asarray(period, float)
    body = np.einsum("nak,na->nk", D, ahead - behind)
    return float(np.linalg.norm(body[:, :2].mean(axis=0)) / abs(body[:, 2].mean()))
