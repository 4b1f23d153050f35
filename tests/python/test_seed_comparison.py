"""Tension-corrected differences of realisations (mdbridge/analysis/seed_comparison.py) against
their independent truth: synthetic seeds of the paper's rod at different known tensions (22 and
44 pN, as the two full-charge vacuum seeds), each mode measured with Gaussian noise of a known
error and each tension measured with a known error. The chi^2 of the corrected differences
follows chi^2(dof); without the correction (the control) it blows up, and so it does when the
tension's error is left out of the residual's (the second control)."""
import math

import numpy as np
import pytest

from mdbridge.analysis.dispersion_prediction import Duplex, frequencies, paper_material
from mdbridge.analysis.seed_comparison import (compare_realisations, differences_by_kind, residuals,
                                               rod_frequency_and_slope)

DUPLEX = Duplex(158, 15)
N_MAX = 6
T_TRUE = (22.0, 44.0)
T_ERR = 3.0
REL_ERR = 0.01
DRAWS = 12


@pytest.fixture(scope="module")
def truth():
    mat = paper_material(DUPLEX)
    return mat, [frequencies(mat, DUPLEX, T, N_MAX) for T in T_TRUE]


def _draw(rng, exact):
    md = {}
    for kind, modes in exact.items():
        for n, (w, _, _) in modes.items():
            md[(kind, n)] = (w * (1 + REL_ERR * rng.standard_normal()), REL_ERR * w)
    return md


def test_rod_slope_is_the_string_beams():
    """The slope of the lowest bend mode against T is the string-beam's 1 / (2 (T + B k^2))
    per pN in ln omega, to 5 % (the rod adds shear and rotary inertia; docs/dispersion.md)."""
    mat = paper_material(DUPLEX)
    r = rod_frequency_and_slope(mat, DUPLEX, 22.0, 2)
    w, slope = r[("bend", 1)]
    B_pN_nm2 = 2.75e-28 * 1e30             # the paper's D
    k_per_nm = 2 * math.pi / (158 * 0.338)
    assert slope / w == pytest.approx(1 / (2 * (22.0 + B_pN_nm2 * k_per_nm ** 2)), rel=0.05)


def test_corrected_chi2_follows_dof_and_raw_blows_up(truth):
    mat, exact = truth
    rng = np.random.default_rng(7)
    chi2 = {"corrected": 0.0, "raw": 0.0, "no_tension_error": 0.0}
    dof = 0
    per_kind_dof = None
    for _ in range(DRAWS):
        md = [_draw(rng, e) for e in exact]
        T = [(t + T_ERR * rng.standard_normal(), T_ERR) for t in T_TRUE]
        c = compare_realisations(md, T, [mat, mat], DUPLEX, N_MAX)["differences_by_kind"][0]
        r = compare_realisations(md, T, None, DUPLEX, N_MAX)["differences_by_kind"][0]
        rods = [rod_frequency_and_slope(mat, DUPLEX, t, N_MAX) for t, _ in T]
        no_err = differences_by_kind(*[residuals(m, t, 0.0, rod) for m, (t, _), rod in zip(md, T, rods)])
        chi2["corrected"] += c["pooled"]["chi2"]
        chi2["raw"] += r["pooled"]["chi2"]
        chi2["no_tension_error"] += no_err["pooled"]["chi2"]
        dof += c["pooled"]["dof"]
        per_kind_dof = {k: v["dof"] for k, v in c.items() if k != "pooled"}
    assert per_kind_dof == {"bend": N_MAX, "twist": N_MAX, "stretch": N_MAX}
    # chi^2 of `dof` degrees of freedom: mean dof, sd sqrt(2 dof) (~0.07 dof here)
    assert abs(chi2["corrected"] / dof - 1) < 4 * math.sqrt(2 / dof), chi2["corrected"] / dof
    assert chi2["raw"] / dof > 10, chi2["raw"] / dof                  # the control: the tensions' effect
    assert chi2["no_tension_error"] / dof > 1 + 6 * math.sqrt(2 / dof), chi2["no_tension_error"] / dof


def test_shape_of_differences_by_kind():
    a = {("bend", 1): (1.0, 0.1, 0.0), ("twist", 2): (2.0, 0.1, 0.0)}
    b = {("bend", 1): (1.2, 0.1, 0.0), ("twist", 2): (2.0, 0.1, 0.0), ("stretch", 3): (1.0, 0.1, 0.0)}
    d = differences_by_kind(a, b)
    assert set(d) == {"bend", "twist", "pooled"}
    assert d["bend"]["chi2"] == pytest.approx(0.2 ** 2 / 0.02) and d["bend"]["dof"] == 1 and d["bend"]["n"] == [1]
    assert d["pooled"]["dof"] == 2
