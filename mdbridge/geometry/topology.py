"""Linking number, twist and writhe of polygons: closed curves and box-periodic ones.

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

# Projection directions for the crossing count: generic (no symmetry of a test curve or
# a box axis lies in them), tried in turn until the over and under counts agree.
_DIRECTIONS = np.array([[0.2917, 0.5189, 0.8037], [-0.6571, 0.2279, 0.7185],
                        [0.5330, -0.7936, 0.2934], [0.1187, 0.9251, -0.3607]])
_BLOCK = 32
# Rounds of (axis -> twist -> one-turn window -> axis) in duplex_topology: the centres
# wobble about the axis (the grooves are unequal), which biases the first twist; three
# rounds move the window by < 1e-3 bp on the test rings (tests/python/test_topology.py).
_AXIS_ITERATIONS = 3
# A ribbon turning by more than this between neighbouring points is not resolved: a turn
# of 270 deg reads as -90 deg in the twist and in the ribbon polygon's linking alike, so
# Lk = Tw + Wr would still hold and could not flag it. DNA at one point per base pair
# turns by about 34 deg.
MAX_TWIST_PER_POINT = np.pi / 2


def _unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def _check_points(x, name, minimum=3):
    x = np.asarray(x, float)
    if x.ndim != 2 or x.shape[1] != 3 or len(x) < minimum:
        raise InputError(f"{name}: need an array of at least {minimum} points (n, 3), got shape {x.shape}")
    if not np.all(np.isfinite(x)):
        raise InputError(f"{name}: non-finite coordinates at point {int(np.argwhere(~np.isfinite(x))[0, 0])}")
    return x


# -- the Gauss integral of two straight segments (Klenin & Langowski) ------------------------

def segment_solid_angles(p1, p2, p3, p4):
    """4 pi times the Gauss integral over the segments p1 -> p2 and p3 -> p4, exactly: the
    signed solid angle under which the parallelogram of the vectors p_j - p_i (p_i on the
    first segment, p_j on the second; corners p3 - p1, p4 - p1, p4 - p2, p3 - p2) is seen
    from the origin (Klenin & Langowski 2000), as two triangles by the formula of Van
    Oosterom & Strackee (IEEE Trans Biomed Eng 30:125, 1983). Components first: arrays
    (3, ...) broadcasting over the rest. Segments that touch give 0.

    Sign: (1/4 pi) times the sum over the segment pairs of two closed polygons is their
    linking number, and over the ordered pairs i != j of one closed polygon its writhe.
    """
    v1, v2, v3, v4 = p3 - p1, p4 - p1, p4 - p2, p3 - p2
    l1, l2, l3, l4 = (np.sqrt(np.einsum("k...,k...->...", v, v)) for v in (v1, v2, v3, v4))
    dot = (lambda a, b: np.einsum("k...,k...->...", a, b))

    def triple(a, b, c):
        return (a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2])
                + a[2] * (b[0] * c[1] - b[1] * c[0]))
    d13 = dot(v1, v3)
    first = np.arctan2(triple(v1, v2, v3), l1 * l2 * l3 + dot(v1, v2) * l3 + d13 * l2 + dot(v2, v3) * l1)
    second = np.arctan2(triple(v1, v3, v4), l1 * l3 * l4 + d13 * l4 + dot(v1, v4) * l3 + dot(v3, v4) * l1)
    return -2.0 * (first + second)


def _pair_sum(a, b, i, j):
    """Sum of the solid angles of segment pairs (i, j) (index arrays; a, b the segment
    starts and ends, components first)."""
    return segment_solid_angles(a[:, i], b[:, i], a[:, j], b[:, j]).sum()


def polygon_writhe(x, pairs_per_chunk: int = 300_000) -> float:
    """Writhe of the closed polygon x (n, 3), exact for the polygon (Klenin & Langowski):
    every unordered pair of non-adjacent segments. O(n^2): 12 CPU s at 10,500 points,
    0.15 s at 1000 (bench/topology.py)."""
    x = _check_points(x, "writhe", 4)
    n = len(x)
    a, b = x.T, np.roll(x, -1, axis=0).T
    # row 0 with 2 .. n-2, rows i >= 1 with j >= i + 2 (segment n-1 is adjacent to segment 0)
    total = segment_solid_angles(a[:, :1], b[:, :1], a[:, 2:n - 1], b[:, 2:n - 1]).sum()
    rows = max(1, pairs_per_chunk // n)
    for i0 in range(1, n - 2, rows):
        i1 = min(i0 + rows, n - 2)
        i = np.arange(i0, i1)[:, None]
        j = np.arange(i0 + 2, n)[None, :]
        omega = segment_solid_angles(a[:, i0:i1, None], b[:, i0:i1, None], a[:, None, i0 + 2:],
                                     b[:, None, i0 + 2:])
        total += np.where(j >= i + 2, omega, 0.0).sum()
    return float(2.0 * total / (4.0 * np.pi))


def writhe(x, stride: int = 1) -> float:
    """Writhe of the closed polygon x (n, 3). stride 1: exact (`polygon_writhe`), O(n^2).
    stride k > 1, coarsened: the segments fall into blocks of k; pairs in the same or in
    neighbouring blocks are summed exactly, and every other pair of blocks is replaced by
    the pair of their chords, i.e. the writhe of the polygon through every k-th point
    plus the exact near pairs. O((n/k)^2 + k n); its error, against the
    exact polygon, is measured in bench/topology.py (docs/topology.md)."""
    x = _check_points(x, "writhe", 4)
    k = int(stride)
    if k <= 1:
        return polygon_writhe(x)
    n = len(x)
    starts = np.arange(0, n, k)
    if len(starts) < 4:
        raise InputError(f"writhe: stride {k} leaves {len(starts)} of {n} points; at least 4 are needed")
    ends = np.append(starts[1:], n)
    a, b = x.T, np.roll(x, -1, axis=0).T
    near = 0.0
    for blk in range(len(starts)):
        nxt = (blk + 1) % len(starts)
        i = np.arange(starts[blk], ends[blk])
        j = np.concatenate([i, np.arange(starts[nxt], ends[nxt])])
        gap = (j[None, :] - i[:, None]) % n                         # forward index distance
        in_same = np.arange(len(j))[None, :] < len(i)
        keep = (gap >= 2) & (gap <= n - 2) & (~in_same | (j[None, :] > i[:, None]))
        ii, jj = np.nonzero(keep)
        near += _pair_sum(a, b, i[ii], j[jj])
    return polygon_writhe(x[starts]) + float(2.0 * near / (4.0 * np.pi))


def gauss_linking_integral(A, B) -> float:
    """(1/4 pi) sum of the segment solid angles of two closed polygons: their linking
    number as a real number, O(n_A n_B). For checks; `linking_number` is the fast
    integer."""
    A = _check_points(A, "A")
    B = _check_points(B, "B")
    a1, a2 = A.T[:, :, None], np.roll(A, -1, axis=0).T[:, :, None]
    b1, b2 = B.T[:, None, :], np.roll(B, -1, axis=0).T[:, None, :]
    return float(segment_solid_angles(a1, a2, b1, b2).sum() / (4.0 * np.pi))


# -- exact linking number by crossings ----------------------------------------------------------

def _blocks(P, Q):
    """Per block of _BLOCK segments (P -> Q, (m, 2) projected): min and max corners."""
    m = len(P)
    nb = -(-m // _BLOCK)
    pad = nb * _BLOCK - m
    lo = np.minimum(P, Q)
    hi = np.maximum(P, Q)
    lo = np.concatenate([lo, np.repeat(lo[-1:], pad, axis=0)]).reshape(nb, _BLOCK, 2).min(axis=1)
    hi = np.concatenate([hi, np.repeat(hi[-1:], pad, axis=0)]).reshape(nb, _BLOCK, 2).max(axis=1)
    return lo, hi


def _crossings(a1, a2, b1, b2, p):
    """Signed crossings of segments a (a1 -> a2) and b in the projection along p:
    (sum over crossings with a above b, sum with b above a); crossing sign
    sign((d_upper x d_lower) . p), the right-hand rule."""
    e1 = _unit(np.cross(p, [1.0, 0.0, 0.0] if abs(p[0]) < 0.9 else [0.0, 1.0, 0.0]))
    e2 = np.cross(p, e1)
    E = np.stack([e1, e2], axis=1)                      # (3, 2): plane coordinates
    A1, A2, B1, B2 = a1 @ E, a2 @ E, b1 @ E, b2 @ E
    loA, hiA = _blocks(A1, A2)
    loB, hiB = _blocks(B1, B2)
    overlap = np.all((loA[:, None] <= hiB[None]) & (loB[None] <= hiA[:, None]), axis=-1)
    ia, ib = np.nonzero(overlap)
    above = below = 0
    k = np.arange(_BLOCK)
    for c0 in range(0, len(ia), 256):                   # candidate block pairs in chunks
        sa = (ia[c0:c0 + 256, None] * _BLOCK + k[None]).reshape(-1)
        sb = (ib[c0:c0 + 256, None] * _BLOCK + k[None]).reshape(-1)
        nb_ = len(sa) // _BLOCK
        sa = np.repeat(sa.reshape(nb_, _BLOCK, 1), _BLOCK, axis=2).reshape(-1)
        sb = np.repeat(sb.reshape(nb_, 1, _BLOCK), _BLOCK, axis=1).reshape(-1)
        ok = (sa < len(A1)) & (sb < len(B1))
        sa, sb = sa[ok], sb[ok]
        r = A2[sa] - A1[sa]
        q = B2[sb] - B1[sb]
        w = B1[sb] - A1[sa]
        den = r[:, 0] * q[:, 1] - r[:, 1] * q[:, 0]
        with np.errstate(divide="ignore", invalid="ignore"):
            s = (w[:, 0] * q[:, 1] - w[:, 1] * q[:, 0]) / den
            t = (w[:, 0] * r[:, 1] - w[:, 1] * r[:, 0]) / den
        hit = (den != 0) & (s >= 0) & (s < 1) & (t >= 0) & (t < 1)
        if not np.any(hit):
            continue
        sa, sb, s, t, den = sa[hit], sb[hit], s[hit], t[hit], den[hit]
        za = (a1[sa] + s[:, None] * (a2[sa] - a1[sa])) @ p
        zb = (b1[sb] + t[:, None] * (b2[sb] - b1[sb])) @ p
        sign = np.sign(den)                              # sign((d_a x d_b) . p)
        above += int(np.sum(np.where(za > zb, sign, 0)))
        below += int(np.sum(np.where(za < zb, -sign, 0)))
    return above, below


def linking_number(A, B, period=None) -> int:
    """Linking number of the closed polygons A and B, an exact integer.

    period b (3,): A and B are one period of box-periodic curves (A_{i+n} = A_i + b,
    likewise B); the linking number is that of the box axis closed into a circle far
    larger than the box without twist (docs/topology.md), counted over one period in a
    projection along a direction perpendicular to b.

    Counted twice, A over B and B over A; a disagreement (a crossing at a vertex in
    round-off) moves to the next projection direction, and if none agree it is an error.
    """
    A = _check_points(A, "linking_number: A")
    B = _check_points(B, "linking_number: B")
    if period is None:
        segs = (A, np.roll(A, -1, axis=0), B, np.roll(B, -1, axis=0))
    else:
        b = np.asarray(period, float)
        if b.shape != (3,) or not np.linalg.norm(b) > 0:
            raise InputError(f"linking_number: the period must be a nonzero 3-vector, got {period!r}")
        # one period of A against B over the neighbouring periods: every crossing of the
        # periodic diagram once (by its segment of A)
        Aone = np.concatenate([A, A[:1] + b])
        Bext = np.concatenate([B - b, B, B + b, B[:1] + 2 * b])
        segs = (Aone[:-1], Aone[1:], Bext[:-1], Bext[1:])
    for p in _DIRECTIONS:
        p = p / np.linalg.norm(p)
        if period is not None:     # project along a direction normal to the box axis
            bh = b / np.linalg.norm(b)
            p = _unit(p - (p @ bh) * bh)
        up, down = _crossings(*segs, p)
        if up == down:
            return up
    raise NumericalError("linking_number: the crossings of A over B and of B over A disagree in every "
                         "projection tried; the curves touch or nearly intersect")


# -- twist, tangents, ribbons ----------------------------------------------------------------

def centred_tangents(x, period=None):
    """Unit tangents at the points of a closed (period None) or box-periodic polygon:
    x_{i+1} - x_{i-1}, second order."""
    x = np.asarray(x, float)
    nxt = np.roll(x, -1, axis=0)
    prv = np.roll(x, 1, axis=0)
    if period is not None:
        nxt[-1] += period
        prv[0] -= period
    return _unit(nxt - prv)


def perpendicular_unit(v, t):
    """v made perpendicular to the unit tangents t and normalised (the ribbon direction);
    an error where v is (nearly) along t."""
    w = v - np.einsum("...k,...k->...", v, t)[..., None] * t
    nw = np.linalg.norm(w, axis=-1)
    if np.any(nw < 1e-6 * np.linalg.norm(v, axis=-1)):
        i = int(np.argmin(nw))
        raise NumericalError(f"ribbon: the ribbon vector is along the tangent at point {i}; its "
                             "perpendicular part is undefined there")
    return w / nw[..., None]


def twist_angles(t, u):
    """Angle [rad] from u_i, parallel-transported from t_i to t_{i+1} (the minimal
    rotation), to u_{i+1}, about t_{i+1}; cyclic in i (closed and box-periodic curves
    alike). t, u: (n, 3) unit, u perpendicular to t."""
    t2 = np.roll(t, -1, axis=0)
    u2 = np.roll(u, -1, axis=0)
    c = np.einsum("ik,ik->i", t, t2)
    if np.any(c <= -1 + 1e-12):
        raise NumericalError(f"twist: the tangent reverses between points {int(np.argmin(c))} and the next")
    Pu = u - (np.einsum("ik,ik->i", t2, u) / (1.0 + c))[:, None] * (t + t2)
    return np.arctan2(np.einsum("ik,ik->i", np.cross(Pu, u2), t2), np.einsum("ik,ik->i", Pu, u2))


def twist(t, u) -> float:
    """Tw = (1/2 pi) sum of `twist_angles` (turns)."""
    return float(twist_angles(t, u).sum() / (2.0 * np.pi))


def periodic_writhe(x, period) -> float:
    """Writhe per period of a box-periodic polygon, relative to the straight box axis b
    (Fuller 1978, one integral): Wr = (1/2 pi) oint (e x t) . dt / (1 + e . t), e = b/|b|,
    over the polygon's tantrix (its edge directions joined by great-circle arcs, on which
    the integral is the signed area of the spherical triangle (e, t_i, t_{i+1})). Defined
    while no edge points against the axis (e . t > -1); an error otherwise."""
    x = np.asarray(x, float)
    b = np.asarray(period, float)
    e = b / np.linalg.norm(b)
    edges = np.roll(x, -1, axis=0) - x
    edges[-1] += b
    t = _unit(edges)
    et = t @ e
    if np.any(et < -0.9):
        raise InputError(f"periodic writhe: edge {int(np.argmin(et))} turns back against the box axis "
                         f"(cosine {et.min():.2f}); the writhe relative to the straight axis is defined "
                         "only while the axis never reverses (docs/topology.md)")
    t2 = np.roll(t, -1, axis=0)
    num = np.einsum("k,ik->i", e, np.cross(t, t2))
    den = 1.0 + et + np.roll(et, -1) + np.einsum("ik,ik->i", t, t2)
    return float(2.0 * np.arctan2(num, den).sum() / (2.0 * np.pi))


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

def _writhe_and_coarsening(x, period, stride):
    """(Wr, Wr(stride) - Wr(2 stride)): the writhe of a closed polygon coarsened with
    stride (`writhe`), with the change on coarsening twice as much (0 when stride is 1:
    nothing was coarsened), or the box-periodic writhe (O(n), never coarsened)."""
    if period is not None:
        return periodic_writhe(x, period), 0.0
    Wr = writhe(x, stride)
    if stride == 1:
        return Wr, 0.0
    return Wr, Wr - writhe(x, 2 * stride)


def _period_or_none(period):
    return None if period is None else np.asarray(period, float)


def ribbon_topology(x, v, period=None, writhe_stride: int = 1) -> dict:
    """Lk, Tw, Wr of the curve x (n, 3) framed by the vectors v (n, 3) made perpendicular
    to its tangent (centred differences of x): the ribbon of a rod (v = d1).

    Lk is the linking number of x with x + eps u (u the unit perpendicular part of v,
    eps a quarter of the median spacing), Tw the transported twist of u, Wr the writhe of
    x coarsened with writhe_stride (closed; `writhe`) or per period (box-periodic, period
    b). Also Wr_coarsening (see `_writhe_and_coarsening`; for a smooth curve the writhe's
    coarsening error is about -Wr_coarsening / 3, second order). A NumericalError when the
    ribbon turns by more than MAX_TWIST_PER_POINT between two points."""
    x = _check_points(x, "ribbon: centreline", 4)
    period = _period_or_none(period)
    t = centred_tangents(x, period)
    u = perpendicular_unit(np.asarray(v, float), t)
    edges = np.roll(x, -1, axis=0) - x
    if period is not None:
        edges[-1] += period
    eps = 0.25 * float(np.median(np.linalg.norm(edges, axis=1)))
    angles = twist_angles(t, u)
    if np.max(np.abs(angles)) > MAX_TWIST_PER_POINT:
        i = int(np.argmax(np.abs(angles)))
        raise NumericalError(f"ribbon: it turns {np.degrees(angles[i]):.0f} deg between points {i} and "
                             f"{(i + 1) % len(x)}; at most {np.degrees(MAX_TWIST_PER_POINT):.0f} deg per point "
                             "is resolved (a faster twist aliases to a slower one in Lk and Tw alike)")
    Lk = linking_number(x, x + eps * u, period)
    Wr, dWr = _writhe_and_coarsening(x, period, writhe_stride)
    return {"Lk": Lk, "Tw": float(angles.sum() / (2.0 * np.pi)), "Wr": Wr, "Wr_coarsening": dWr}


def duplex_topology(strand_I, strand_II, period=None) -> dict:
    """Lk, Tw, Wr of a DNA duplex from its two backbone strands, (n, 3) each, point i of
    both in base pair i and both ordered along strand I (so relaxed B-DNA has Lk > 0).

    Lk: the linking number of the two strand polygons (exact integer). The axis: the
    base-pair centres (strand midpoints) averaged over one helical turn, n / Tw base pairs
    long, Tw the twist of strand I about the axis before (a fixed point: the centres
    themselves first, _AXIS_ITERATIONS rounds).
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
    axis = c
    for _ in range(_AXIS_ITERATIONS):
        ta = centred_tangents(axis, period)
        Tw = twist(ta, perpendicular_unit(I - axis, ta))
        if abs(Tw) < 1.0:
            raise InputError(f"duplex: strand I turns {Tw:.2f} times about the axis over {len(I)} base "
                             "pairs; a helical turn is needed to average the axis over one")
        bp_per_turn = len(I) / abs(Tw)
        axis = one_turn_average(c, bp_per_turn, period)
    ta = centred_tangents(axis, period)
    Tw = twist(ta, perpendicular_unit(I - axis, ta))
    Wr = periodic_writhe(axis, period) if period is not None else writhe(axis)
    Wr_c = periodic_writhe(c, period) if period is not None else writhe(c)
    return {"Lk": Lk, "Tw": Tw, "Wr": Wr, "Wr_bp_centres": Wr_c, "bp_per_turn": bp_per_turn}
