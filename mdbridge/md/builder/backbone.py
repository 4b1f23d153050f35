"""The O3'(i)-P(i+1) links of rigid nucleotides on strained frames, closed by two torsions.

Rigid B-DNA nucleotides (duplex.py) placed on base-pair frames whose steps are not
B-DNA's (a sequence-dependent rod: twist 27-40 deg, roll and slide of a few units)
leave the links between them anywhere from 1.2 to 3 A, where a covalent O3'-P bond is
1.60 A. Real DNA follows such steps by turning its backbone torsions, and so does this
module: for every link outside LINK_RANGE_A, the 5' end of nucleotide i+1 is turned
about its C4'-C5' bond (the torsion gamma: O5', P, O1P, O2P and the H5' hydrogens
move) and about its C5'-O5' bond (beta: P, O1P, O2P move) until P lies O3P_BOND_A from
O3'(i). Every bond length and every angle inside the nucleotides stays the template's;
among the (gamma, beta) turns that close the link, the one whose two new angles,
C3'-O3'-P and O3'-P-O5', are nearest CHARMM27's is taken. A link that no turn can
close keeps its best length, and `check_links` refuses it with the number.

Used by the builder (build_duplex) and by the back-mapping of rod frames
(mdbridge/md/backmap.py), so that the atoms of a rod frame are the atoms the builder
would make of it. Numbers: CHARMM27's bond O3'-P 0.160 nm, angles CN7-ON2-P 120.0 deg
and ON2-P-ON2 104.3 deg (GROMACS charmm27.ff/ffnabonded.itp).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from dna_models.errors import InputError
from mdbridge.md.forcefields import BUILDER

# the templates' force field (mdbridge/md/forcefields.py): CHARMM27
O3P_BOND_A = BUILDER.o3_p.length_A                # O3'-P
ANGLE_C3_O3_P_DEG = BUILDER.angle_c3_o3_p_deg     # CN7-ON2-P
ANGLE_O3_P_O5_DEG = BUILDER.angle_o3_p_o5_deg     # ON2-P-ON2
LINK_RANGE_A = (1.5, 1.8)         # a link inside is kept as placed; outside it is closed
# the choice among closing turns: squared angle errors in units of ANGLE_SCALE_DEG plus the
# squared move of P in units of MOVE_SCALE_A (so that the backbone is not turned inside out)
ANGLE_SCALE_DEG = 10.0
MOVE_SCALE_A = 0.5

# the 5' end of a nucleotide that each torsion turns (those absent, e.g. hydrogens, skipped)
GAMMA_MOVES = ("O5'", *BUILDER.phosphate, "H5'1", "H5'2")   # about C4'-C5'
BETA_MOVES = BUILDER.phosphate                               # about C5'-O5'
GAMMA_GRID_DEG = np.arange(-180.0, 180.0, 2.0)             # refined to 0.05 deg around the best


@dataclass(frozen=True)
class BackboneLinks:
    """Atom indices of the O3'(i)-P(i+1) links of a duplex (one row per link)."""
    o3: np.ndarray        # (L,) O3' of nucleotide i
    c3: np.ndarray        # (L,) C3' of nucleotide i
    c4: np.ndarray        # (L,) C4' of nucleotide i+1
    c5: np.ndarray        # (L,) C5' of nucleotide i+1
    o5: np.ndarray        # (L,) O5' of nucleotide i+1
    p: np.ndarray         # (L,) P of nucleotide i+1
    gamma_moves: np.ndarray   # (L, k) atoms of nucleotide i+1 turned about C4'-C5'
    beta_moves: np.ndarray    # (L, m) atoms of nucleotide i+1 turned about C5'-O5'
    labels: tuple             # (L,) "residue i -> residue i+1"


def duplex_links(names, resids, n_bp: int, *, periodic: bool) -> BackboneLinks:
    """The links of a duplex numbered as the builder numbers it (strand I residues
    1..n, strand II n+1..2n, each 5'->3'); periodic adds each strand's junction
    (last residue -> first)."""
    names = np.asarray(names).astype(str)
    resids = np.asarray(resids).astype(int)
    where: dict[tuple[int, str], int] = {}
    for k, (r, a) in enumerate(zip(resids, names)):
        where.setdefault((int(r), a), k)
    steps = []
    for first, last in ((1, n_bp), (n_bp + 1, 2 * n_bp)):
        steps += [(r, r + 1) for r in range(first, last)]
        if periodic:
            steps.append((last, first))

    def idx(r, a):
        if (r, a) not in where:
            raise InputError(f"residue {r}: atom {a} missing (a backbone link needs O3', C3' of one "
                             "nucleotide and C4', C5', O5', P of the next)")
        return where[(r, a)]

    def movers(r, atoms):
        return [where[(r, a)] for a in atoms if (r, a) in where]

    gm = [movers(b, GAMMA_MOVES) for _, b in steps]
    bm = [movers(b, BETA_MOVES) for _, b in steps]
    if len({len(x) for x in gm}) > 1 or len({len(x) for x in bm}) > 1:
        raise InputError("the nucleotides carry different sets of 5'-end atoms (hydrogens on some only)")
    return BackboneLinks(o3=np.array([idx(a, "O3'") for a, _ in steps]),
                         c3=np.array([idx(a, "C3'") for a, _ in steps]),
                         c4=np.array([idx(b, "C4'") for _, b in steps]),
                         c5=np.array([idx(b, "C5'") for _, b in steps]),
                         o5=np.array([idx(b, "O5'") for _, b in steps]),
                         p=np.array([idx(b, "P") for _, b in steps]),
                         gamma_moves=np.array(gm, dtype=int), beta_moves=np.array(bm, dtype=int),
                         labels=tuple(f"{a} -> {b}" for a, b in steps))


def _image(d, box):
    """Minimum image of difference vectors d (..., 3) along the periodic edges of box (3,)."""
    if box is None:
        return d
    b = np.asarray(box, dtype=float)
    per = b > 0
    d = d.copy()
    d[..., per] -= b[per] * np.round(d[..., per] / b[per])
    return d


def _rotate(v, k, c, s):
    """Rodrigues: v (..., 3) turned about unit axes k (..., 3) by the angle with cosine c, sine s (...)."""
    c, s = c[..., None], s[..., None]
    return v * c + np.cross(k, v) * s + k * (k * v).sum(-1, keepdims=True) * (1.0 - c)


def _unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def _angle_deg(a, b, c):
    u, w = a - b, c - b
    cos = (u * w).sum(-1) / (np.linalg.norm(u, axis=-1) * np.linalg.norm(w, axis=-1))
    return np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))


def _solve(X, C3, C4, C5, O5, P, gamma_deg):
    """For each link (...) and each gamma (G,): the beta turns (2 roots) that put P at
    O3P_BOND_A from X (O3'(i), imaged next to P), their cost (squared angle errors, deg^2;
    inf where the link cannot close at that gamma) and the turned O5' and P."""
    g = np.radians(gamma_deg)
    k1 = _unit(C5 - C4)[..., None, :]
    shape = np.broadcast_shapes(k1.shape[:-1], g.shape)
    cg, sg = np.broadcast_to(np.cos(g), shape), np.broadcast_to(np.sin(g), shape)
    C5e, Xe, C3e = C5[..., None, :], X[..., None, :], C3[..., None, :]
    O5g = C5e + _rotate((O5 - C5)[..., None, :], k1, cg, sg)
    Pg = C5e + _rotate((P - C5)[..., None, :], k1, cg, sg)
    # beta: P on a circle about the C5'-O5' axis; |P(b) - X|^2 = A + B cos(b - phi)
    k2 = _unit(O5g - C5e)
    centre = O5g + k2 * ((Pg - O5g) * k2).sum(-1, keepdims=True)
    u = Pg - centre
    w = np.cross(k2, u)
    q = centre - Xe
    A = (q * q).sum(-1) + (u * u).sum(-1)
    qu, qw = 2.0 * (q * u).sum(-1), 2.0 * (q * w).sum(-1)
    B = np.hypot(qu, qw)
    phi = np.arctan2(qw, qu)
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = (O3P_BOND_A ** 2 - A) / B
    ok = np.abs(ratio) <= 1.0
    acos = np.arccos(np.clip(ratio, -1.0, 1.0))
    best = None
    for b in (phi + acos, phi - acos):
        cb, sb = np.cos(b), np.sin(b)
        Pb = centre + u * cb[..., None] + w * sb[..., None]
        cost = (((_angle_deg(C3e, Xe, Pb) - ANGLE_C3_O3_P_DEG) / ANGLE_SCALE_DEG) ** 2
                + ((_angle_deg(Xe, Pb, O5g) - ANGLE_O3_P_O5_DEG) / ANGLE_SCALE_DEG) ** 2
                + (np.linalg.norm(Pb - P[..., None, :], axis=-1) / MOVE_SCALE_A) ** 2)
        cost = np.where(ok, cost, np.inf)
        if best is None:
            best = (cost, b)
        else:
            take = cost < best[0]
            best = (np.where(take, cost, best[0]), np.where(take, b, best[1]))
    return best


def _seat_phosphate_oxygens(x, links: BackboneLinks, link: int, o3) -> None:
    """Turn O1P and O2P of a closed link about its P-O5' bond (the torsion alpha) so
    that the fourth corner of the phosphate, opposite O5', O1P and O2P, points at O3'
    (x (n_atoms, 3) is changed in place)."""
    p, o5 = x[links.p[link]], x[links.o5[link]]
    oxygens = [k for k in links.beta_moves[link] if k != links.p[link]]
    k = _unit(o5 - p)
    corner = -(k + sum(_unit(x[j] - p) for j in oxygens))
    a = corner - k * (corner @ k)
    b = (o3 - p) - k * ((o3 - p) @ k)
    alpha = np.arctan2(k @ np.cross(a, b), a @ b)
    x[oxygens] = p + _rotate(x[oxygens] - p, k, np.cos(alpha), np.sin(alpha))


def close_links(x, links: BackboneLinks, box=None) -> np.ndarray:
    """Coordinates x (..., n_atoms, 3) in A (any leading axes: trajectory frames) with
    every link outside LINK_RANGE_A closed (module docstring); box (3,): the periodic
    edges (0: not periodic) for the links that close through it. Returns a new array."""
    x = np.array(x, dtype=float, copy=True)
    lead = x.shape[:-2]
    flat = x.reshape((-1,) + x.shape[-2:])
    X = flat[:, links.p] + _image(flat[:, links.o3] - flat[:, links.p], box)
    length = np.linalg.norm(X - flat[:, links.p], axis=-1)
    todo_t, todo_l = np.nonzero((length < LINK_RANGE_A[0]) | (length > LINK_RANGE_A[1]))
    if not len(todo_t):
        return x
    Xs = X[todo_t, todo_l]
    # C3' of nucleotide i imaged as its O3' was (the two are bonded)
    C3 = Xs + _image(flat[todo_t, links.c3[todo_l]] - flat[todo_t, links.o3[todo_l]], box)
    C4, C5 = flat[todo_t, links.c4[todo_l]], flat[todo_t, links.c5[todo_l]]
    O5, P = flat[todo_t, links.o5[todo_l]], flat[todo_t, links.p[todo_l]]
    cost, _ = _solve(Xs, C3, C4, C5, O5, P, GAMMA_GRID_DEG)
    g0 = GAMMA_GRID_DEG[np.argmin(cost, axis=1)]
    fine = g0[:, None] + np.arange(-2.0, 2.0001, 0.05)[None, :]
    # gamma refined around each link's best grid point
    cost_f, beta_f = _solve(Xs, C3, C4, C5, O5, P, fine)
    j = np.argmin(cost_f, axis=1)
    rows = np.arange(len(j))
    closable = np.isfinite(cost_f[rows, j])
    gamma = np.radians(fine[rows, j])
    beta = beta_f[rows, j]
    for n in np.flatnonzero(closable):
        t, link = todo_t[n], todo_l[n]
        c4, c5, o5 = flat[t, links.c4[link]], flat[t, links.c5[link]], flat[t, links.o5[link]]
        k1 = _unit(c5 - c4)
        gm = links.gamma_moves[link]
        flat[t, gm] = c5 + _rotate(flat[t, gm] - c5, k1, np.cos(gamma[n]), np.sin(gamma[n]))
        o5 = flat[t, links.o5[link]]
        k2 = _unit(o5 - c5)
        bm = links.beta_moves[link]
        # beta was measured from the gamma-turned P: turn by it about C5'-O5'
        flat[t, bm] = o5 + _rotate(flat[t, bm] - o5, k2, np.cos(beta[n]), np.sin(beta[n]))
        _seat_phosphate_oxygens(flat[t], links, link, X[t, link])
    return flat.reshape(lead + x.shape[-2:])


def link_lengths(x, links: BackboneLinks, box=None) -> np.ndarray:
    """O3'(i)-P(i+1) lengths (..., L) in A, minimum image through the box."""
    x = np.asarray(x, dtype=float)
    return np.linalg.norm(_image(x[..., links.p, :] - x[..., links.o3, :], box), axis=-1)


def check_links(x, links: BackboneLinks, box=None, *, where: str = "the built duplex") -> np.ndarray:
    """The link lengths (as link_lengths); an InputError naming the worst link when one
    lies outside LINK_RANGE_A."""
    d = link_lengths(x, links, box)
    lo, hi = LINK_RANGE_A
    bad = (d < lo) | (d > hi)
    if np.any(bad):
        flat = d.reshape(-1, d.shape[-1])
        dev = np.where(flat < lo, lo - flat, flat - hi)
        t, k = np.unravel_index(np.argmax(dev), flat.shape)
        frame = f" (frame {t})" if d.ndim > 1 else ""
        raise InputError(f"{where}: O3'-P link of residues {links.labels[k]} is {flat[t, k]:.2f} A{frame}, "
                         f"outside {lo}-{hi} A ({int(bad.sum())} links outside); a covalent O3'-P bond is "
                         f"{O3P_BOND_A} A: the base-pair frames are further from B-DNA than the backbone "
                         "torsions can follow (mdbridge/md/builder/backbone.py)")
    return d


def check_structure_links(structure, *, where: str = "the built duplex") -> np.ndarray:
    """check_links on a builder Structure (mdbridge/md/builder/structure.py)."""
    n_bp = len(np.unique(structure.resids)) // 2
    links = duplex_links(structure.names, structure.resids, n_bp, periodic=structure.closed)
    return check_links(structure.coords, links, structure.box, where=where)
