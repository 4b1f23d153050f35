"""Linking number, twist and writhe of polygons: closed curves and box-periodic ones.

The algorithms live once, in C++ (rodcore/src/topology.cpp, which rodsim also runs per
frame of a closed rod); the functions here check their input and call them through the
rodcore module (rodcore.topology). What stays here is the all-atom side: the one-turn
axis of a duplex and its topology.

The three numbers of Calugareanu-White-Fuller, Lk = Tw + Wr, for a curve x (the axis)
and a ribbon along unit vectors u perpendicular to its tangent (docs/topology.md):

* `linking_number(A, B)`: the Gauss linking integral of two disjoint closed polygons,
  an exact integer, counted as the signed crossings of A over B in a projection (each
  crossing of two straight segments is exact, so no quadrature error); the crossings of
  B over A must give the same number, which is the check. O(N) for curves that are not
  knotted up in projection: segments are tested in blocks whose projected bounding
  boxes overlap.
* `twist(t, u)`: Tw = (1/2 pi) int (u x u') . t ds, as the sum of the angles between
  u_{i+1} and u_i parallel-transported from t_i to t_{i+1} (the minimal rotation):
  O(N), second order in the spacing.
* `writhe(x, stride)`: the writhe of a closed polygon, exact for the polygon, by Klenin &
  Langowski (Biopolymers 54:307, 2000): the Gauss double integral over two straight
  segments is the solid angle of the quadrilateral they span over 4 pi. O(N^2); coarsened
  (stride > 1): near pairs exact, far ones by chords.
* box-periodic curves (x_{i+n} = x_i + b): `linking_number(A, B, period=b)` and
  `periodic_writhe(x, b)` under the convention of docs/topology.md (the box axis
  closed into a circle far larger than the box, without twist).

Arrays of points are (n, 3); a closed polygon joins its last point to its first.
"""
from __future__ import annotations

import numpy as np

from dna_models.errors import InputError, NumericalError

from .compiled import rodcore_module

# Rounds of (axis -> twist -> one-turn window -> axis) in one_turn_axis: the centres
# wobble about the axis (the grooves are unequal), which biases the first twist; three
# rounds move the window by < 1e-3 bp on the test rings (tests/python/test_topology.py).
_AXIS_ITERATIONS = 3
# A ribbon turning by more than this between neighbouring points is not resolved (the C++
# kernel refuses it: rodcore.topology.MAX_TWIST_PER_POINT). DNA at one point per base
# pair turns by about 34 deg.
MAX_TWIST_PER_POINT = np.pi / 2


def _check_points(x, name, minimum=3):
    x = np.asarray(x, float)
    if x.ndim != 2 or x.shape[1] != 3 or len(x) < minimum:
        raise InputError(f"{name}: need an array of at least {minimum} points (n, 3), got shape {x.shape}")
    if not np.all(np.isfinite(x)):
        raise InputError(f"{name}: non-finite coordinates at point {int(np.argwhere(~np.isfinite(x))[0, 0])}")
    return x


# -- the curve topology: rodcore.topology (C++, rodcore/src/topology.cpp), the one home ------

def _kernel(name, *args, **kw):
    """rodcore.topology.NAME(*args, **kw), its errors as dnarod's (InputError, NumericalError)."""
    rodcore = rodcore_module()
    try:
        return getattr(rodcore.topology, name)(*args, **kw)
    except rodcore.InputError as e:
        raise InputError(str(e)) from None
    except rodcore.NumericalError as e:
        raise NumericalError(str(e)) from None


def polygon_writhe(x) -> float:
    """Writhe of the closed polygon x (n, 3), exact for the polygon (Klenin & Langowski):
    every unordered pair of non-adjacent segments. O(n^2) (bench/topology.py)."""
    return float(_kernel("polygon_writhe", _check_points(x, "writhe", 4)))


def writhe(x, stride: int = 1) -> float:
    """Writhe of the closed polygon x (n, 3). stride 1: exact (`polygon_writhe`), O(n^2).
    stride k > 1, coarsened: the segments fall into blocks of k; pairs in the same or in
    neighbouring blocks are summed exactly, and every other pair of blocks is replaced by
    the pair of their chords, i.e. the writhe of the polygon through every k-th point
    plus the exact near pairs. O((n/k)^2 + k n); its error, against the
    exact polygon, is measured in bench/topology.py (docs/topology.md)."""
    return float(_kernel("writhe", _check_points(x, "writhe", 4), int(stride)))


def gauss_linking_integral(A, B) -> float:
    """(1/4 pi) sum of the segment solid angles of two closed polygons: their linking
    number as a real number, O(n_A n_B). For checks; `linking_number` is the fast
    integer."""
    return float(_kernel("gauss_linking_integral", _check_points(A, "A"), _check_points(B, "B")))


def linking_number(A, B, period=None) -> int:
    """Linking number of the closed polygons A and B, an exact integer, from the signed
    crossings in a projection, counted twice (A over B, B over A; a disagreement moves to
    the next projection direction, and if none agree it is an error).

    period b (3,): A and B are one period of box-periodic curves (A_{i+n} = A_i + b,
    likewise B); the linking number is that of the box axis closed into a circle far
    larger than the box without twist (docs/topology.md), counted over one period in a
    projection along a direction perpendicular to b."""
    A = _check_points(A, "linking_number: A")
    B = _check_points(B, "linking_number: B")
    if period is not None:
        b = np.asarray(period, float)
        if b.shape != (3,) or not np.linalg.norm(b) > 0:
            raise InputError(f"linking_number: the period must be a nonzero 3-vector, got {period!r}")
        period = b
    return int(_kernel("linking_number", A, B, period))


def is_closed(x) -> bool:
    """A ring: the edge from the last point back to the first is no longer than twice the
    longest of the others (a box-periodic rod's is about its length); rodsim's rule."""
    return bool(_kernel("is_closed", _check_points(x, "is_closed", 2)))


def writhe_stride(n_points: int, writhe_points: int) -> int:
    """Stride of the coarsened writhe: at most writhe_points blocks of the n_points
    (writhe_points >= 8)."""
    return int(_kernel("writhe_stride", int(n_points), int(writhe_points)))


# -- twist, tangents, ribbons ----------------------------------------------------------------

def centred_tangents(x, period=None):
    """Unit tangents at the points of a closed (period None) or box-periodic polygon:
    x_{i+1} - x_{i-1}, second order."""
    return _kernel("centred_tangents", np.asarray(x, float), _period_or_none(period))


def perpendicular_unit(v, t):
    """v made perpendicular to the unit tangents t and normalised (the ribbon direction);
    an error where v is (nearly) along t."""
    return _kernel("perpendicular_unit", np.asarray(v, float), np.asarray(t, float))


def twist_angles(t, u):
    """Angle [rad] from u_i, parallel-transported from t_i to t_{i+1} (the minimal
    rotation), to u_{i+1}, about t_{i+1}; cyclic in i (closed and box-periodic curves
    alike). t, u: (n, 3) unit, u perpendicular to t."""
    return _kernel("twist_angles", np.asarray(t, float), np.asarray(u, float))


def twist(t, u) -> float:
    """Tw = (1/2 pi) sum of `twist_angles` (turns)."""
    return float(twist_angles(t, u).sum() / (2.0 * np.pi))


def periodic_writhe(x, period) -> float:
    """Writhe per period of a box-periodic polygon, relative to the straight box axis b
    (Fuller 1978, one integral): Wr = (1/2 pi) oint (e x t) . dt / (1 + e . t), e = b/|b|,
    over the polygon's tantrix (its edge directions joined by great-circle arcs, on which
    the integral is the signed area of the spherical triangle (e, t_i, t_{i+1})). Defined
    while no edge points against the axis (e . t > -1); an error otherwise."""
    return float(_kernel("periodic_writhe", np.asarray(x, float), np.asarray(period, float)))


# -- the helical axis of a duplex ---------------------------------------------------------------

def one_turn_average(c, bp_per_turn: float, period=None):
    """Points c (n, 3) (base-pair centres) averaged over a window of one helical turn,
    bp_per_turn long (a fractional window: the end points weigh what is left), cyclic
    (closed, or box-periodic with period b). The average of a helix over exactly one of
    its turns is its axis point (WrLINE: Sutthibutpong, Harris & Noy, JCTC 11:2768, 2015)."""
    c = np.asarray(c, float)
    n = len(c)
    w = float(bp_per_turn)
    if not (1.0 <= w < n):
        raise InputError(f"one-turn axis: {w:.2f} bp per turn is outside [1, {n}) for {n} base pairs")
    K = int(np.ceil(w / 2.0))
    k = np.arange(-K, K + 1)
    weights = np.clip(w / 2.0 + 0.5 - np.abs(k), 0.0, 1.0)
    out = np.zeros_like(c)
    for kk, wk in zip(k, weights):
        shifted = np.roll(c, -kk, axis=0)
        if period is not None and kk != 0:      # points past the end are the next period's
            i = np.arange(n) + kk
            shifted = shifted + np.floor_divide(i, n)[:, None] * np.asarray(period, float)[None]
        out += wk * shifted
    return out / weights.sum()


# -- the three numbers of a framed curve and of a duplex ------------------------------------

def _period_or_none(period):
    return None if period is None else np.asarray(period, float)


def ribbon_topology(x, v, period=None, writhe_stride: int = 1) -> dict:
    """Lk, Tw, Wr of the curve x (n, 3) framed by the vectors v (n, 3) made perpendicular
    to its tangent (centred differences of x): the ribbon of a rod (v = d1).

    Lk is the linking number of x with x + eps u (u the unit perpendicular part of v,
    eps a quarter of the median spacing), Tw the transported twist of u, Wr the writhe of
    x coarsened with writhe_stride (closed; `writhe`) or per period (box-periodic, period
    b). Also Wr_coarsening = Wr(stride) - Wr(2 stride) (0 for stride 1 and box-periodic
    curves; for a smooth curve the writhe's coarsening error is about -Wr_coarsening / 3,
    second order). A NumericalError when the ribbon turns by more than
    MAX_TWIST_PER_POINT between two points."""
    x = _check_points(x, "ribbon: centreline", 4)
    r = _kernel("ribbon_topology", x, np.asarray(v, float), _period_or_none(period), int(writhe_stride))
    return {"Lk": int(r["Lk"]), "Tw": float(r["Tw"]), "Wr": float(r["Wr"]),
            "Wr_coarsening": float(r["Wr_coarsening"])}


def one_turn_axis(c, ribbon_of, period=None, rounds: int = _AXIS_ITERATIONS):
    """The helical axis of points c (n, 3) that circle it once per helical turn (the base-pair
    centres of a duplex, the base-pair origins of a rod with intrinsic shift and slide):
    c averaged over a window of one turn (`one_turn_average`), the turn being the twist of
    the vectors ribbon_of(axis) (n, 3) about the axis, the points c themselves first
    (a fixed point, `rounds` rounds). Returns (axis, points per turn)."""
    c = np.asarray(c, float)
    axis = c
    per_turn = float("nan")
    for _ in range(rounds):
        ta = centred_tangents(axis, period)
        Tw = twist(ta, perpendicular_unit(ribbon_of(axis), ta))
        if abs(Tw) < 1.0:
            raise InputError(f"one-turn axis: the ribbon turns {Tw:.2f} times about the axis over {len(c)} "
                             "points; a helical turn is needed to average the axis over one")
        per_turn = len(c) / abs(Tw)
        axis = one_turn_average(c, per_turn, period)
    return axis, per_turn


def duplex_topology(strand_I, strand_II, period=None) -> dict:
    """Lk, Tw, Wr of a DNA duplex from its two backbone strands, (n, 3) each, point i of
    both in base pair i and both ordered along strand I (so relaxed B-DNA has Lk > 0).

    Lk: the linking number of the two strand polygons (exact integer). The axis: the
    base-pair centres (strand midpoints) averaged over one helical turn (`one_turn_axis`,
    the turn being strand I's twist about the axis).
    Tw: the twist of strand I about that axis; Wr: the axis's writhe. Also
    Wr_bp_centres, the writhe of the unaveraged centres (what a base-pair-origin axis
    gives; docs/topology.md), and bp_per_turn."""
    I = _check_points(strand_I, "duplex: strand I", 4)
    II = _check_points(strand_II, "duplex: strand II", 4)
    if I.shape != II.shape:
        raise InputError(f"duplex: the strands have {len(I)} and {len(II)} points; one per base pair each")
    period = _period_or_none(period)
    Lk = linking_number(I, II, period)
    c = 0.5 * (I + II)
    try:
        axis, bp_per_turn = one_turn_axis(c, lambda a: I - a, period)
    except InputError as e:
        raise InputError(f"duplex: strand I, {len(I)} base pairs: {e}") from None
    ta = centred_tangents(axis, period)
    Tw = twist(ta, perpendicular_unit(I - axis, ta))
    Wr = periodic_writhe(axis, period) if period is not None else writhe(axis)
    Wr_c = periodic_writhe(c, period) if period is not None else writhe(c)
    return {"Lk": Lk, "Tw": Tw, "Wr": Wr, "Wr_bp_centres": Wr_c, "bp_per_turn": bp_per_turn}
