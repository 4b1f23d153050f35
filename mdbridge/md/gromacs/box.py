"""The periodic box: exact helix closure along the axis, the rod's own motion across it;
and the box of a ring closed in space (`plan_ring_box`).

Along the helix axis the box is the closure length L (n_bp rises for an
integer number of turns), so strand ends meet their own image. Across it we
use the rod model's prediction for the same scene and run length: the range
of the centerline over all times, plus the duplex diameter, plus twice the
cut-off (so no atom can interact with a side-wall image of itself) plus a
margin. In vacuum nothing fills the box, so a larger cross-section costs
nothing but neighbour-search cells.
"""
from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from dna_models.errors import InputError

DUPLEX_DIAMETER_A = 20.0   # B-DNA: phosphates at ~9-10 A from the axis


@dataclass
class BoxPlan:
    box_A: list            # (3,) orthorhombic edges
    axis: int | None       # 0, 1, 2 = x, y, z: the helix axis (None: a ring closed in space)
    shift_A: list          # (3,) added to every coordinate (rod origins too)
    closure_length_A: float
    centerline_range_A: list   # (3,) max - min of the rod centerline over the run
    max_transverse_excursion_A: float   # max |r_perp(s,t) - r_perp(s,0)| over the run
    rod_run_ps: float
    diameter_A: float
    cutoff_A: float
    margin_A: float

    def as_dict(self) -> dict:
        return asdict(self)


def helix_axis(origins_A, closure_length_A: float) -> int:
    """Index of the lab axis the duplex runs along (the rod's end-to-end direction
    must be a coordinate axis: GROMACS boxes here are orthorhombic)."""
    o = np.asarray(origins_A, dtype=float)
    n = len(o)
    # over one period the origins advance by L (n-1)/n along the axis
    d = o[-1] - o[0]
    k = int(np.argmax(np.abs(d)))
    expect = closure_length_A * (n - 1) / n
    off = np.delete(d, k)
    if abs(abs(d[k]) - expect) > 0.05 * closure_length_A or np.any(np.abs(off) > 0.05 * closure_length_A):
        raise InputError(f"the rod's base-pair origins run from {o[0].round(2)} to {o[-1].round(2)} A: "
                         "the periodic direction must be the x, y or z axis with closure length "
                         f"{closure_length_A:.3f} A")
    return k


def plan_box(centerline_A, origins0_A, closure_length_A: float, *, rod_run_ps: float,
             cutoff_A: float = 10.0, diameter_A: float = DUPLEX_DIAMETER_A,
             margin_A: float = 10.0) -> BoxPlan:
    """Box from the rod centerline over the MD run (T, N, 3) in A and the base-pair
    origins at t = 0 (n_bp, 3) in A."""
    c = np.asarray(centerline_A, dtype=float)
    if c.ndim != 3 or c.shape[-1] != 3 or not np.all(np.isfinite(c)):
        raise InputError(f"rod centerline: need a finite (T, N, 3) array, got shape {c.shape}")
    o0 = np.asarray(origins0_A, dtype=float)
    axis = helix_axis(o0, closure_length_A)
    lo = np.minimum(c.min(axis=(0, 1)), o0.min(axis=0))
    hi = np.maximum(c.max(axis=(0, 1)), o0.max(axis=0))
    rng = hi - lo
    box = rng + diameter_A + 2.0 * cutoff_A + margin_A
    box[axis] = closure_length_A
    shift = 0.5 * box - 0.5 * (lo + hi)
    # Along the axis: base pair 0 half a rise above the wall, so the periodic
    # boundary passes through the two junction O3'-P links (paper Sec 6.2).
    rise = closure_length_A / len(o0)
    shift[axis] = 0.5 * rise - o0[0, axis]
    perp = [k for k in range(3) if k != axis]
    disp = c[:, :, perp] - c[:1, :, perp]
    excursion = float(np.sqrt((disp ** 2).sum(axis=-1)).max())
    return BoxPlan(box_A=box.tolist(), axis=axis, shift_A=shift.tolist(),
                   closure_length_A=float(closure_length_A), centerline_range_A=rng.tolist(),
                   max_transverse_excursion_A=excursion, rod_run_ps=float(rod_run_ps),
                   diameter_A=diameter_A, cutoff_A=cutoff_A, margin_A=margin_A)


def plan_ring_box(centerline_A, origins0_A, *, rod_run_ps: float, cutoff_A: float = 10.0,
                  diameter_A: float = DUPLEX_DIAMETER_A, margin_A: float = 10.0) -> BoxPlan:
    """Box of a ring closed in space (a minicircle; periodic-molecules = no): on every
    edge the range of the rod centreline over the run (T, N, 3) and of the base-pair
    origins (n_bp, 3), plus the duplex diameter, twice the cut-off (no atom interacts
    with an image of the ring) and a margin; the ring centred in it."""
    c = np.asarray(centerline_A, dtype=float)
    if c.ndim != 3 or c.shape[-1] != 3 or not np.all(np.isfinite(c)):
        raise InputError(f"rod centerline: need a finite (T, N, 3) array, got shape {c.shape}")
    o0 = np.asarray(origins0_A, dtype=float)
    lo = np.minimum(c.min(axis=(0, 1)), o0.min(axis=0))
    hi = np.maximum(c.max(axis=(0, 1)), o0.max(axis=0))
    rng = hi - lo
    box = rng + diameter_A + 2.0 * cutoff_A + margin_A
    disp = c - c[:1]
    return BoxPlan(box_A=box.tolist(), axis=None, shift_A=(0.5 * box - 0.5 * (lo + hi)).tolist(),
                   closure_length_A=0.0, centerline_range_A=rng.tolist(),
                   max_transverse_excursion_A=float(np.sqrt((disp ** 2).sum(axis=-1)).max()),
                   rod_run_ps=float(rod_run_ps), diameter_A=diameter_A, cutoff_A=cutoff_A, margin_A=margin_A)
