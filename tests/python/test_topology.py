"""Linking number, twist and writhe (mdbridge.geometry.topology, mdbridge.rod.topology,
mdbridge.md.topology, `dnarod topology`) against independently true things:

* the linking number of a ribbon on a torus, which is topological: a (p, q) torus curve
  pushed along the torus normal links itself p q times (with the orientation below,
  -p q), and m extra turns of the ribbon add m; checked also against a brute-force
  Gauss double integral;
* the writhe of smooth closed curves (a helix wound on a torus, a trefoil) from the Gauss
  double integral of the analytic curve, written here in numpy;
* the planar circle (Wr = 0 exactly, Tw = Lk);
* the writhe per period of a helical axis (Fuller: the area of the tangent's cone);
* Lk = Tw + Wr, its convergence order in N measured;
* a DNA rod whose base-pair origins circle its helical axis (shift and slide): the writhe
  is the axis's, as for the all-atom duplex;
* controls that must fail: the twist about d3 under shear, the writhe of the unaveraged
  base-pair centres and of a rod's unaveraged centreline.
"""
import json
import re
import subprocess

import h5py
import numpy as np
import pytest

from mdbridge.geometry.topology import (centred_tangents, duplex_topology, gauss_linking_integral,
                                        linking_number, periodic_writhe, perpendicular_unit, ribbon_topology,
                                        twist, writhe)

RISE_A = 3.38


# -- curves with a known answer --------------------------------------------------------------

def torus_curve(p, q, theta, R=3.0, r=1.0):
    """The (p, q) torus curve (p times around the torus's axis, q times around its tube):
    points, derivative d/dtheta and the torus's unit normal, analytically."""
    c, s = np.cos(q * theta), np.sin(q * theta)
    x = np.stack([(R + r * c) * np.cos(p * theta), (R + r * c) * np.sin(p * theta), r * s], 1)
    dx = np.stack([-r * q * s * np.cos(p * theta) - (R + r * c) * p * np.sin(p * theta),
                   -r * q * s * np.sin(p * theta) + (R + r * c) * p * np.cos(p * theta), r * q * c], 1)
    nu = np.stack([c * np.cos(p * theta), c * np.sin(p * theta), s], 1)
    return x, dx, nu


def framed_torus_curve(p, q, m, n, R=3.0, r=1.0, shear=None):
    """n points of the (p, q) torus curve and directors: d1 = the torus normal turned m
    times about the tangent, d3 the tangent; `shear` (a function of theta) tilts d3 away
    from the tangent by that angle about d2 (so d1 leaves the normal plane too).
    Linking number of the ribbon along d1: m - p q."""
    th = np.arange(n) * 2 * np.pi / n
    x, dx, nu = torus_curve(p, q, th, R, r)
    t = dx / np.linalg.norm(dx, axis=1)[:, None]
    b = np.cross(t, nu)
    u = np.cos(m * th)[:, None] * nu + np.sin(m * th)[:, None] * b
    v = np.cross(t, u)
    beta = np.zeros(n) if shear is None else shear(th)
    d1 = np.cos(beta)[:, None] * u - np.sin(beta)[:, None] * t
    d3 = np.sin(beta)[:, None] * u + np.cos(beta)[:, None] * t
    return x, np.stack([d1, v, d3], axis=2)


def gauss_writhe(p, q, M, R=3.0, r=1.0):
    """(1/4 pi) int int (x'(s) x x'(t)) . (x(s) - x(t)) / |x(s) - x(t)|^3 ds dt of the
    analytic torus curve by the trapezoid rule on M points (the integrand vanishes on the
    diagonal): converged to 1e-6 at M = 2000 for the curves here."""
    th = np.arange(M) * 2 * np.pi / M
    x, dx, _ = torus_curve(p, q, th, R, r)
    total = 0.0
    for i in range(0, M, 400):
        d = x[i:i + 400, None] - x[None]
        num = np.einsum("ijk,ijk->ij", np.cross(dx[i:i + 400, None], dx[None]), d)
        r3 = np.linalg.norm(d, axis=-1) ** 3
        total += np.divide(num, r3, out=np.zeros_like(num), where=r3 > 0).sum()
    return total * (2 * np.pi / M) ** 2 / (4 * np.pi)


def gauss_linking(A, B):
    """Midpoint-rule Gauss linking integral of two closed polygons (independent of the
    crossing count and of the exact solid angles)."""
    dA, dB = np.roll(A, -1, 0) - A, np.roll(B, -1, 0) - B
    total = 0.0
    for i in range(0, len(A), 300):
        d = (A + dA / 2)[i:i + 300, None] - (B + dB / 2)[None]
        total += np.sum(np.einsum("ijk,ijk->ij", d, np.cross(dA[i:i + 300, None], dB[None]))
                        / np.linalg.norm(d, axis=-1) ** 3)
    return total / (4 * np.pi)


def order(ns, errors):
    return -np.polyfit(np.log(ns), np.log(np.abs(errors)), 1)[0]


# -- linking number ------------------------------------------------------------------------------

@pytest.mark.parametrize("p, q, m", [(1, 0, 0), (1, 1, 0), (1, 3, 5), (2, 3, 0), (2, 3, -4), (3, 2, 1)])
def test_linking_number_of_torus_ribbons(p, q, m):
    x, D = framed_torus_curve(p, q, m, 300)
    ribbon = x + 0.1 * D[:, :, 0]
    Lk = linking_number(x, ribbon)
    assert Lk == m - p * q
    assert abs(gauss_linking_integral(x, ribbon) - Lk) < 1e-9     # exact solid angles
    xf, Df = framed_torus_curve(p, q, m, 1500)                   # brute force on a fine polygon
    assert abs(gauss_linking(xf, xf + 0.1 * Df[:, :, 0]) - Lk) < 0.02
    assert linking_number(ribbon, x) == Lk                         # symmetric
    assert linking_number(x, ribbon[::-1]) == -Lk                  # orientation


def test_linking_number_of_box_periodic_strands_is_their_winding():
    """A duplex along the box axis z whose axis is itself a helix (a supercoil): for
    strands monotone in z the convention's Lk is the winding number of the strand-to-strand
    vector projected on the plane normal to the axis, counted here independently."""
    n, turns, coils, c = 200, 19, 2, 200.0
    s = np.arange(n) / n
    axis = np.stack([12 * np.cos(2 * np.pi * coils * s), 12 * np.sin(2 * np.pi * coils * s), c * s], 1)
    ph = 2 * np.pi * turns * s
    side = np.stack([np.cos(ph), np.sin(ph), 0 * s], 1)
    I, II = axis + 6 * side, axis - 6 * side
    d = (II - I)[:, :2]
    ang = np.arctan2(d[:, 1], d[:, 0])
    winding = np.sum(np.angle(np.exp(1j * np.diff(np.append(ang, ang[0]))))) / (2 * np.pi)
    Lk = linking_number(I, II, period=[0, 0, c])
    assert Lk == round(winding) == turns
    assert linking_number(II, I, period=[0, 0, c]) == Lk


# -- writhe and twist ------------------------------------------------------------------------------

@pytest.mark.parametrize("m", [0, 15, -7])
def test_planar_circle(m):
    """A planar circle: Wr = 0 and Tw = Lk = m, to round-off."""
    x, D = framed_torus_curve(1, 0, m, 158, R=5.0, r=0.0)
    r = ribbon_topology(x, D[:, :, 0])
    assert r["Lk"] == m
    assert abs(r["Wr"]) < 1e-12 and abs(r["Tw"] - m) < 1e-12


@pytest.mark.parametrize("p, q", [(1, 5), (2, 3)], ids=["toroidal-helix", "trefoil"])
def test_writhe_converges_to_the_gauss_double_integral(p, q):
    """Klenin-Langowski on N points (exact for the polygon) against the analytic curve's
    Gauss double integral: second order in N."""
    exact = gauss_writhe(p, q, 2000)
    assert abs(exact - gauss_writhe(p, q, 1000)) < 3e-5     # its own convergence, far below what is checked
    ns = np.array([100, 200, 400])
    errors = [writhe(torus_curve(p, q, np.arange(n) * 2 * np.pi / n)[0]) - exact for n in ns]
    assert 1.9 < order(ns, errors) < 2.1
    assert abs(errors[-1]) < 2e-3


def test_tw_plus_wr_is_lk_to_round_off_on_a_sheared_158bp_ring():
    """A 158-bp ring with Lk = 15 whose centreline is a helix wound 3 times around a torus
    (Wr about -0.86) and whose d3 is sheared off the tangent by 0.3 +- 0.2 rad: Lk is 15 at
    every N, and the polygon's own twist (edge tangents) plus its exact writhe is Lk to round-off
    (Fuller's theorem for polygons, topology.hpp). Controls: the twist about the centred tangents
    misses by the discretisation error, which falls at second order; the twist about d3 (not the
    tangent) misses by far more."""
    shear = (lambda th: 0.3 + 0.2 * np.sin(5 * th))
    ns = np.array([158, 316, 632])
    residual, centred, control = [], [], []
    for n in ns:
        x, D = framed_torus_curve(1, 3, 18, n, R=3.0, r=1.0, shear=shear)
        x = x * 158 * RISE_A / np.sum(np.linalg.norm(np.roll(x, -1, 0) - x, axis=1))
        r = ribbon_topology(x, D[:, :, 0])
        assert r["Lk"] == 15
        residual.append(r["Lk"] - r["Tw"] - r["Wr"])
        t = centred_tangents(x)
        centred.append(r["Lk"] - twist(t, perpendicular_unit(D[:, :, 0], t)) - r["Wr"])
        control.append(r["Lk"] - twist(D[:, :, 2], D[:, :, 0]) - r["Wr"])
    assert max(np.abs(residual)) < 1e-9
    assert 1.9 < order(ns, centred) < 2.1 and abs(centred[0]) > 1e-4
    assert min(np.abs(control)) > 0.05


@pytest.mark.parametrize("p,q", [(2, 3), (1, 4), (3, 5)])
def test_tw_plus_wr_is_lk_on_rough_knots_and_rings(p, q):
    """Torus knots and links of few, rough points (noise 2 % of the size, a ribbon turning
    irregularly): Tw + Wr = Lk to 1e-9 however coarse the polygon; the centred-tangent twist
    misses by more than 1e-4 (control)."""
    rng = np.random.default_rng(p * 10 + q)
    for n in (40, 90):
        x, D = framed_torus_curve(p, q, 2 * p + q, n, R=3.0, r=1.0)
        x = x + 0.02 * 4.0 * rng.standard_normal(x.shape)
        r = ribbon_topology(x, D[:, :, 0])
        assert abs(r["Lk"] - r["Tw"] - r["Wr"]) < 1e-9, r
        t = centred_tangents(x)
        assert abs(r["Lk"] - twist(t, perpendicular_unit(D[:, :, 0], t)) - r["Wr"]) > 1e-4


def test_writhe_coarsening_error_is_second_order():
    """The stride-k polygon of a smooth ring: the error against the full polygon is second
    order, so Wr_coarsening (stride k against 2 k) is -3 times it, within 2x."""
    x = torus_curve(1, 5, np.arange(2400) * 2 * np.pi / 2400)[0]
    full = writhe(x)
    for k in (4, 8):
        r = ribbon_topology(x, framed_torus_curve(1, 5, 0, 2400)[1][:, :, 0], writhe_stride=k)
        err = r["Wr"] - full
        assert abs(err) < 1e-3 * k ** 2
        assert 0.5 < r["Wr_coarsening"] / (-3 * err) < 2.0   # second order: Wr(k) - Wr(2k) = -3 err


def test_periodic_writhe_of_a_helical_axis():
    """A box-periodic axis that is a circular helix (2 coils per period): its tangent runs
    on a cone of half-angle a about the box axis, and Fuller's writhe per period is
    coils (1 - cos a); second order in the points per period."""
    coils, radius, c = 2, 12.0, 200.0
    cos_a = c / np.hypot(c, 2 * np.pi * coils * radius)
    exact = coils * (1 - cos_a)
    ns = np.array([50, 100, 200])
    errors = []
    for n in ns:
        s = np.arange(n) / n
        x = np.stack([radius * np.cos(2 * np.pi * coils * s), radius * np.sin(2 * np.pi * coils * s), c * s], 1)
        errors.append(abs(periodic_writhe(x, [0, 0, c])) - exact)
    assert 1.9 < order(ns, errors) < 2.1 and abs(errors[-1]) < 5e-4
    # the sign follows the hand: the mirror image has the opposite writhe
    x = np.stack([radius * np.cos(2 * np.pi * coils * s), -radius * np.sin(2 * np.pi * coils * s), c * s], 1)
    assert periodic_writhe(x, [0, 0, c]) == pytest.approx(-periodic_writhe(x * [1, -1, 1], [0, 0, c]))


# -- all-atom duplexes ---------------------------------------------------------------------------

def ring_duplex(n_bp=336, Lk=32, coils=3, noise_A=0.0, seed=1):
    """Strand I and II C1' atoms of a closed duplex whose axis is a (1, coils) helix on a
    torus (a supercoiled ring, R = 130 A, r = 40 A): the strands at 5.9 A from the axis,
    138 deg apart about it (the minor groove), turning Lk + coils times about the torus
    normal, so the strands link Lk times. Returns (I, II, the axis)."""
    th = np.arange(n_bp) * 2 * np.pi / n_bp
    x, D = framed_torus_curve(1, coils, Lk + coils, n_bp, R=130.0, r=40.0)
    u, v = D[:, :, 0], D[:, :, 1]
    g = np.radians(138.0)
    I = x + 5.9 * u
    II = x + 5.9 * (np.cos(g) * u + np.sin(g) * v)
    rng = np.random.default_rng(seed)
    I, II = I + noise_A * rng.standard_normal(I.shape), II + noise_A * rng.standard_normal(II.shape)
    return I, II, x, th


@pytest.mark.parametrize("noise_A", [0.0, 0.5])
def test_all_atom_ring_lk_and_one_turn_axis(noise_A):
    """The strands link 32 times; the one-turn axis has the writhe of the curve the duplex
    was wound on, the base-pair centres (which circle the axis: the grooves are unequal)
    have a far larger one (WrLINE's finding)."""
    I, II, x, _ = ring_duplex(noise_A=noise_A)
    exact = gauss_writhe(1, 3, 2000, R=130.0, r=40.0)
    r = duplex_topology(I, II)
    assert r["Lk"] == 32
    assert abs(r["Wr"] - exact) < 0.02
    assert abs(r["Wr_bp_centres"] - exact) > 0.5
    assert abs(r["Lk"] - r["Tw"] - r["Wr"]) < 0.02
    assert r["bp_per_turn"] == pytest.approx(336 / (32 - exact), rel=0.01)


def write_gro(path, I, II, box_A):
    """A GRO file of the C1' atoms only, residues numbered as the builder does: strand I
    1..n, strand II n+1..2n with pair k = (k, 2n + 1 - k)."""
    n = len(I)
    rows = [(k + 1, "DA", I[k]) for k in range(n)] + [(n + j + 1, "DT", II[n - 1 - j]) for j in range(n)]
    lines = ["C1' ring", f"{2 * n:5d}"]
    for i, (resid, name, pos) in enumerate(rows):
        p = np.mod(pos, box_A) / 10.0            # wrapped into the box, nm
        lines.append(f"{resid % 100000:5d}{name:<5s}{'C1' + chr(39):>5s}{(i + 1) % 100000:5d}"
                     f"{p[0]:8.3f}{p[1]:8.3f}{p[2]:8.3f}")
    lines.append(" ".join(f"{b / 10.0:10.5f}" for b in box_A))
    path.write_text("\n".join(lines) + "\n")


def test_command_on_md_folders(tmp_path, dnarod):
    """`dnarod topology` on a ring closed in its box and on a box-periodic supercoiled
    duplex, both wrapped into the box (as GROMACS writes them)."""
    I, II, _, _ = ring_duplex()
    (tmp_path / "ring").mkdir()
    write_gro(tmp_path / "ring" / "conf.gro", I, II, np.array([250.0, 250.0, 250.0]))
    n, c = 210, 210 * RISE_A
    s = np.arange(n) / n
    axis = np.stack([60 + 12 * np.cos(4 * np.pi * s), 60 + 12 * np.sin(4 * np.pi * s), c * s], 1)
    ph = 2 * np.pi * 20 * s
    side = np.stack([np.cos(ph), np.sin(ph), 0 * s], 1)
    (tmp_path / "box").mkdir()
    write_gro(tmp_path / "box" / "conf.gro", axis + 5.9 * side, axis - 5.9 * side, np.array([120.0, 120.0, c]))
    out = subprocess.run([str(dnarod), "topology", str(tmp_path / "ring"), str(tmp_path / "box"),
                          "-o", str(tmp_path / "topo")], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    res = json.loads((tmp_path / "topo" / "topology.json").read_text())["paths"]
    ring, box = res[str(tmp_path / "ring")], res[str(tmp_path / "box")]
    assert ring["closed"] and ring["Lk"] == [32] and ring["Lk_minus_Tw_minus_Wr_max"] < 0.02
    assert not box["closed"] and box["Lk"] == [20] and box["Lk_minus_Tw_minus_Wr_max"] < 0.01
    assert box["Wr"][0] == pytest.approx(2 * (1 - c / np.hypot(c, 4 * np.pi * 12)), abs=0.01)
    for r in (ring, box):
        assert set(r) >= {"time_ps", "Lk", "Tw", "Wr"} and r["kind"] == "md"


# -- rods through rodsim ------------------------------------------------------------------------------

def twisted_ring_scene(folder, n_bp=158, turns=15, N=158, ell_A=5.0):
    """A 158-bp rod closed into a planar ring with 15 turns of twist (its intrinsic
    twist): Gamma = (0, 0, 1), Omega = (kappa sin tau s, kappa cos tau s, tau), the
    curvature turning with the frame (kappa = 2 pi / L, tau = 2 pi turns / L), so the
    frames close after one period. Written as an initial-condition file."""
    L = n_bp * RISE_A / ell_A
    s = np.arange(N) * L / N
    kappa, tau = 2 * np.pi / L, 2 * np.pi * turns / L
    z = np.zeros((N, 3))
    with h5py.File(folder / "ic.h5", "w") as f:
        f["s"] = s
        f["fields/gamma"], f["fields/omega"] = z, z
        f["fields/Gamma"] = np.tile([0.0, 0.0, 1.0], (N, 1))
        f["fields/Omega"] = np.stack([kappa * np.sin(tau * s), kappa * np.cos(tau * s), tau + 0 * s], 1)
    (folder / "ring.toml").write_text(f"""
[rod]
length = {L!r}
points = {N}
Gamma0 = [0.0, 0.0, 1.0]
Omega0 = [0.0, 0.0, {tau!r}]
[initial]
kind = "file"
path = "ic.h5"
[output]
t_end = 2.0
frames = 3
fields = ["internal", "centerline", "directors"]
""")
    return folder / "ring.toml"


def test_command_on_rodsim_rings(tmp_path, rodsim, dnarod):
    """The 158-bp ring with 15 turns (closed) and the paper's 158-bp periodic scene with a
    displacement (box-periodic, planar: Wr = 0), through rodsim and `dnarod topology`."""
    scene = twisted_ring_scene(tmp_path)
    subprocess.run([str(rodsim), "run", str(scene), "-o", str(tmp_path / "ring.h5")], check=True,
                   capture_output=True)
    subprocess.run([str(rodsim), "run", "workflows/scenes/dna158.toml", "-o", str(tmp_path / "box.h5"),
                    "--set", "initial.A_A=20", "--set", "output.t_end=2", "--set", "output.frames=3"],
                   check=True, capture_output=True)
    out = subprocess.run([str(dnarod), "topology", str(tmp_path / "ring.h5"), str(tmp_path / "box.h5"),
                          "-o", str(tmp_path / "topo")], capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    res = json.loads((tmp_path / "topo" / "topology.json").read_text())
    assert res["format"] == "dnarod-topology/1"
    ring, box = res["paths"][str(tmp_path / "ring.h5")], res["paths"][str(tmp_path / "box.h5")]
    assert ring["closed"] and ring["Lk"] == [15, 15, 15]
    assert np.allclose(ring["Tw"], 15, atol=1e-9) and np.allclose(ring["Wr"], 0, atol=1e-9)
    assert ring["time_ps"][-1] == pytest.approx(2 * 0.9416, rel=1e-3)
    assert not box["closed"] and box["Lk"] == [15, 15, 15]
    assert box["Lk_minus_Tw_minus_Wr_max"] < 1e-6
    # rodsim's own per-frame topology of the closed rod (the same C++ functions), none for
    # the box-periodic one
    with h5py.File(tmp_path / "ring.h5") as f:
        assert list(f["topology/Lk"][()]) == ring["Lk"] and f.attrs["topology_jumps"] == 0
        assert np.allclose(f["topology/Tw"][()], ring["Tw"], atol=1e-12)
        assert np.allclose(f["topology/Wr"][()], ring["Wr"], atol=1e-12)
    with h5py.File(tmp_path / "box.h5") as f:
        assert "topology" not in f and "topology_jumps" not in f.attrs


def test_one_writhe_coarsening_default():
    """rodsim (C++) and `dnarod topology` coarsen the writhe to the same number of blocks."""
    import rodcore
    from mdbridge.rod.topology import WRITHE_POINTS
    assert rodcore.topology.WRITHE_POINTS == WRITHE_POINTS


# -- bad input and failed checks --------------------------------------------------------------------

def test_bad_input_exits_2_before_work(tmp_path, dnarod):
    (tmp_path / "empty").mkdir()
    with h5py.File(tmp_path / "nodirectors.h5", "w") as f:
        f["time"], f["s"], f["centerline"] = np.zeros(3), np.arange(8.0), np.zeros((3, 8, 3))
    I, II, _, _ = ring_duplex(n_bp=40, Lk=4, coils=0)
    (tmp_path / "open").mkdir()
    write_gro(tmp_path / "open" / "conf.gro", I[:30], II[:30], np.array([400.0, 400.0, 400.0]))
    for args, says in [(["nothere.h5"], "nothere.h5: no such file or folder"),
                       ([str(tmp_path / "empty")], "no md.tpr + md.xtc and no conf.gro"),
                       ([str(tmp_path / "nodirectors.h5")], "dataset 'directors' missing"),
                       ([str(tmp_path / "open")], "strand I is not joined from its last base pair"),
                       ([str(tmp_path / "empty"), "--writhe-points", "3"],
                        "--writhe-points: 3: out of range (allowed: >= 8)")]:
        out = subprocess.run([str(dnarod), "topology", *args, "-o", str(tmp_path / "topo")],
                             capture_output=True, text=True, cwd=tmp_path)
        assert out.returncode == 2 and says in out.stderr, (args, out.stderr)
    assert not (tmp_path / "topo").exists()


def test_under_resolved_rod_is_refused(tmp_path, dnarod):
    """13 turns on 20 points (234 deg per segment) alias to -7 turns in Lk and Tw alike,
    so Lk = Tw + Wr cannot see it; the twist per point is checked instead."""
    x, D = framed_torus_curve(1, 0, 13, 20, R=10.0, r=0.0)
    with h5py.File(tmp_path / "coarse.h5", "w") as f:
        f["time"], f["s"] = np.zeros(1), np.arange(20.0)
        f["centerline"], f["directors"] = x[None], D[None]
    out = subprocess.run([str(dnarod), "topology", str(tmp_path / "coarse.h5"), "-o", str(tmp_path / "topo")],
                         capture_output=True, text=True)
    assert out.returncode == 2 and "turns -127 deg between points" in out.stderr, out.stderr


def test_coarse_writhe_fails_the_check(tmp_path, dnarod):
    """A (2, 5) torus-knot rod (Wr -6.11) with its writhe coarsened to 10 blocks of 40
    segments (Lk - Tw - Wr = -6.2): Lk = Tw + Wr fails; the file is written and the
    command exits 2, naming the frame. Control: 200 points pass."""
    x, D = framed_torus_curve(2, 5, 0, 400)
    with h5py.File(tmp_path / "knot.h5", "w") as f:
        f["time"], f["s"] = np.zeros(1), np.arange(400.0)
        f["centerline"], f["directors"] = x[None], D[None]
    run = (lambda points: subprocess.run([str(dnarod), "topology", str(tmp_path / "knot.h5"), "-o",
                                          str(tmp_path / "topo"), "--writhe-points", points],
                                         capture_output=True, text=True))
    out = run("10")
    assert out.returncode == 2 and "Lk = Tw + Wr fails" in out.stderr and "frame 0" in out.stderr
    assert (tmp_path / "topo" / "topology.json").is_file()
    assert run("200").returncode == 0


def wobbling_rod_frame(m, n_bp=336, points_per_bp=2, rho_A=0.7, ell_A=5.0):
    """A DNA rod on the (1, 3) torus helix of ring_duplex (R = 130 A, r = 40 A): the helix
    axis is that curve, d1 turns m times about it (the ribbon links m - 3 times), and the
    base-pair origins, the rod's centreline, sit rho_A off the axis along d1 + d2 (what a
    mean slide of -0.7 A does): they circle the axis once per turn. Rod units (ell_A)."""
    N = n_bp * points_per_bp
    axis, D = framed_torus_curve(1, 3, m, N, R=130.0 / ell_A, r=40.0 / ell_A)
    x = axis + (rho_A / ell_A) * (D[:, :, 0] + D[:, :, 1]) / np.sqrt(2.0)
    return x, D


def test_rod_writhe_is_the_helical_axis_writhe_and_the_summary_is_one_frame(tmp_path, dnarod):
    """`dnarod topology` on a rod whose centreline circles its helical axis (the base-pair
    origins of Olson 1998 DNA do, by about 0.5 A): Wr is the writhe of the curve the axis
    was wound on (the Gauss integral), within 0.02, for Lk = 32 and Lk = 31 alike, and
    Lk = Tw + Wr; the unaveraged centreline's writhe (rodsim's topology/Wr) carries that of
    its own small helix, (1 - cos theta) per turn, and is off by more than 0.1 (the
    control). The summary line prints each frame's Lk, Tw and Wr together: each printed
    triple adds up (Tw + Wr = Lk), which frame 0's Tw and Wr next to the last frame's Lk
    would not."""
    frames = [wobbling_rod_frame(m) for m in (35, 34)]
    with h5py.File(tmp_path / "dna.h5", "w") as f:
        f["time"], f["s"] = np.arange(2.0), np.arange(len(frames[0][0])) * 0.676
        f["centerline"] = np.stack([x for x, _ in frames])
        f["directors"] = np.stack([D for _, D in frames])
    out = subprocess.run([str(dnarod), "topology", str(tmp_path / "dna.h5"), "-o", str(tmp_path / "topo")],
                         capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    r = json.loads((tmp_path / "topo" / "topology.json").read_text())["paths"][str(tmp_path / "dna.h5")]
    exact = gauss_writhe(1, 3, 2000, R=130.0, r=40.0)
    assert r["Lk"] == [32, 31]
    for f in range(2):
        assert abs(r["Wr"][f] - exact) < 0.02, (r["Wr"], exact)
        assert abs(r["Lk"][f] - r["Tw"][f] - r["Wr"][f]) < 0.02
        assert abs(r["Wr_centreline"][f] - exact) > 0.1, (r["Wr_centreline"], exact)
        assert r["points_per_turn"][f] == pytest.approx(672 / (r["Lk"][f] - exact), rel=0.01)
    printed = re.search(r"first frame Lk (\S+), Tw (\S+), Wr (\S+); last frame Lk (\S+), Tw (\S+), Wr (\S+);",
                        out.stdout)
    assert printed, out.stdout
    first, last = np.array(printed.groups()[:3], float), np.array(printed.groups()[3:], float)
    for f, (Lk, Tw, Wr) in ((0, first), (-1, last)):
        assert (Lk, Tw, Wr) == (r["Lk"][f], round(r["Tw"][f], 4), round(r["Wr"][f], 4))
        assert abs(Lk - Tw - Wr) < 0.02
    assert abs(last[0] - first[1] - first[2]) > 0.9         # the mixed line of the report would not add up
