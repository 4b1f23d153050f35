"""The overdamped rod on rings, measured (docs/thermal.md, "Rings, measured"): the committed reduced
results of bench/brownian_ring_dt.py, bench/ring_size.py and bench/kilobase_equipartition.py held to
the prose, and the Monte Carlo that is the size's reference checked against exact limits here:

- the discrete worm-like ring (crankshaft moves, bench/ring_size.py) at infinite stiffness is the
  regular polygon (Rg^2 = R^2 exactly) and without stiffness the freely jointed ring, whose Rg^2
  follows from its bonds' exchangeability (within 4 standard errors of the chains' scatter);
- control: a contour 2 % short moves the 350-bp reference by far more than the rod's error, so the
  comparison can fail (a persistence length 10 % long hardly moves it: at 1.8 persistence lengths the
  ring is nearly its circle).
"""
import json
import math
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "bench"))
import ring_size  # noqa: E402

RESULTS = ROOT / "bench" / "results"


def load(name):
    return json.loads((RESULTS / name).read_text())


def doc():
    return " ".join((ROOT / "docs" / "thermal.md").read_text().split())


def test_monte_carlo_reference_meets_its_exact_limits():
    n = 35
    stiff, _, _, _ = ring_size.monte_carlo(n, 1.0, 1e5, 16, 40)
    R = 1.0 / (2 * math.sin(math.pi / n))
    assert abs(stiff / R ** 2 - 1) < 1e-5
    # the freely jointed ring: its bonds are exchangeable with sum zero, so b_i . b_j = -1 / (N - 1) and
    # r_ij^2 = k (N - k) / (N - 1) for k = |i - j|: Rg^2 = sum_k k (N - k)^2 / (N^2 (N - 1))
    n = 30
    exact = sum(k * (n - k) ** 2 for k in range(1, n)) / (n ** 2 * (n - 1))
    flexible, err, _, _ = ring_size.monte_carlo(n, 1.0, 0.0, 128, 200)
    assert abs(flexible - exact) < 4 * err and err < 0.02 * exact


def test_ring_size_reference_can_tell_a_short_contour_not_a_persistence_length():
    # a 350-bp ring (1.8 persistence lengths) is nearly its circle: its Rg^2 tells a contour 2 % short by
    # many errors, a persistence length 10 % long hardly (so the comparison tests lengths, not bending)
    r = load("ring_size.json")
    b, mc, rod_err = r["segment_nm"], r["monte_carlo"]["Rg2_nm2"], r["rod"]["err"]
    short, err, _, _ = ring_size.monte_carlo(r["points"], 0.98 * b, r["kappa"], 128, 150)
    assert abs(short - mc) > 5 * math.hypot(err, rod_err)
    kappa_long = ring_size.kappa_for(b / (1.1 * r["persistence_length_nm"]))
    longer, err, _, _ = ring_size.monte_carlo(r["points"], b, kappa_long, 128, 150)
    assert abs(longer - mc) < 3 * math.hypot(err, rod_err)


def test_ring_sizes_and_their_bias_are_what_the_docs_say():
    text = doc()
    coarse, fine = load("ring_size.json"), load("ring_size_dt25.json")
    for r, dt in ((coarse, 100.0), (fine, 25.0)):
        assert r["rod"].get("dt_ps", 100.0) == dt
        ratio = r["rod_over_mc"]
        rod, mc = r["rod"], r["monte_carlo"]
        err = ratio * math.hypot(rod["err"] / rod["Rg2_nm2"], mc["err"] / mc["Rg2_nm2"])
        assert f"{ratio:.3f} +- {err:.3f}" in text
    # the bias grows as dt shrinks (more projections): the two differ by many errors
    assert coarse["rod"]["Rg2_nm2"] - fine["rod"]["Rg2_nm2"] > 5 * math.hypot(coarse["rod"]["err"], fine["rod"]["err"])
    assert coarse["z"] < -3 and fine["z"] < -3


def test_ring_dt_convergence_is_what_the_docs_say():
    r = load("brownian_ring_dt.json")
    text = doc()
    ratios = [m["ratio"] for m in r["modes"]]
    assert all(abs(q - 1) < 1e-3 for q in ratios) and r["dt_ps"] == 100.0 and r["fine_dt_ps"] == 6.25
    assert f"{min(ratios):.4f}-{max(ratios):.4f}" in text
    bend = {m["n"]: m["tau_fine_ns"] for m in r["modes"] if m["kind"] == "bend"}
    twist = [m["tau_fine_ns"] for m in r["modes"] if m["kind"] == "twist"][0]
    assert f"tau {bend[2] / 1000:.2f} us to {bend[10]:.1f} ns" in text and f"({twist:.0f} ns)" in text
    m = r["msd"]
    q = m["internal_ratio"]
    assert m["lags_ns"][0] == 1.0 and m["lags_ns"][-1] == 100.0
    assert f"{q[0]:.2f}x (1 ns) to {q[-1]:.2f}x (100 ns)" in text
    assert f"{m['internal_nm2'][0]:.1f} vs {m['internal_fine_nm2'][0]:.1f} nm^2" in text
    assert f"{m['msd_nm2'][0]:.0f} nm^2" in text
    assert max(abs(x - 1) for x in q) > 0.05            # not converged: what the docs say


def test_shipped_ring_equipartition_from_rest_is_what_the_docs_say():
    r = load("kilobase_equipartition.json")
    assert r["scene"] == "workflows/scenes/dna10k_water.toml" and r["window_ns"] == [50.0, 100.0]
    assert r["mean_in_window"] >= 0.95
    assert f"{r['mean_in_window']:.3f} of equipartition over 50-100 ns (frames scatter " \
           f"{r['frame_scatter_in_window']:.3f})" in doc()
    assert np.isclose(r["dt_ps"], 100.0)
