"""`dnarod dispersion` CSV output and `dnarod paper-figures` end to end (--quick)."""
import csv
import io
import json
import math

import numpy as np
import pytest

from dnarod.cli import main
from dnarod.paper import theory


def _csv(capsys, argv):
    assert main(argv) == 0
    return list(csv.DictReader(io.StringIO(capsys.readouterr().out)))


def test_dispersion_kappa_csv(capsys):
    rows = _csv(capsys, ["dispersion", "--kappa", "0.5", "1", "0:4:5", "--D1", "1.5", "--Gamma03", "0.8"])
    assert list(rows[0]) == ["kappa", "omega_minus", "omega_plus"]
    assert [float(r["kappa"]) for r in rows] == [0.5, 1.0, 0.0, 1.0, 2.0, 3.0, 4.0]
    for r in rows:
        q, wm, wp = float(r["kappa"]), float(r["omega_minus"]), float(r["omega_plus"])
        for w in (wm, wp):  # each printed frequency solves Eq 25 (to the 10 printed digits)
            assert abs(theory.dispersion_residual(w, q, 1.5, 0.8)) < 1e-8 * max(w, q, 1) ** 4
        assert wm <= wp


def test_dispersion_twisted_and_ratios(capsys):
    rows = _csv(capsys, ["dispersion", "--k", "2", "--Omega03", "1", "--ratios"])
    r = rows[0]
    assert list(r)[:7] == ["k", "kappa_p", "kappa_m", "omega_minus_p", "omega_plus_p", "omega_minus_m", "omega_plus_m"]
    assert float(r["kappa_p"]) == 3.0 and float(r["kappa_m"]) == 1.0
    # Fig 1 at k = 2: omega_+^p(kappa = 3) by hand, 1/2 [sqrt(9 * 2.1^2 + 1) + sqrt(9 * 0.1^2 + 1)]
    assert float(r["omega_plus_p"]) == pytest.approx(0.5 * (math.sqrt(9 * 2.1 ** 2 + 1) + math.sqrt(1.09)), rel=1e-9)
    for pm, kap in (("p", 3.0), ("m", 1.0)):
        for b in ("minus", "plus"):
            w = float(r[f"omega_{b}_{pm}"])
            assert float(r[f"energy_ratio_{b}_{pm}"]) == pytest.approx(
                (w * w - 1.21 * kap ** 2) ** 2 / (1.21 * kap ** 2), rel=1e-8)
            assert float(r[f"shear_bend_{b}_{pm}"]) ** 2 / 1.21 == pytest.approx(float(r[f"energy_ratio_{b}_{pm}"]),
                                                                                rel=1e-8)


def test_dispersion_bad_input(capsys):
    assert main(["dispersion", "--kappa", "1:2"]) == 2
    assert "START:STOP:NUM" in capsys.readouterr().err
    assert main(["dispersion", "--kappa", "1", "--Omega03", "1"]) == 2
    assert "--Omega03 applies to --k" in capsys.readouterr().err
    assert main(["dispersion", "--kappa", "1", "--D1", "-1"]) == 2
    assert "--D1" in capsys.readouterr().err


@pytest.fixture(scope="module")
def quick_figures(tmp_path_factory):
    out = tmp_path_factory.mktemp("paper")
    assert main(["paper-figures", "-o", str(out), "--quick"]) == 0
    return out


def _json(out, name):
    return json.loads((out / f"{name}.json").read_text())


@pytest.mark.parametrize("name", ["fig1", "fig2", "fig3", "fig4", "fig5", "fig6", "fig7",
                                  "dispersion_check", "sec52_energy", "sec52_harmonic"])
def test_pngs_written(quick_figures, name):
    data = (quick_figures / f"{name}.png").read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    assert 5_000 < len(data) < 300_000
    assert _json(quick_figures, name)


def test_fig1_and_fig3_numbers(quick_figures):
    f1 = _json(quick_figures, "fig1")
    assert f1["parabolic_points_at_k_equal_Omega03"] == {"omega_minus_m": 0.0, "omega_plus_m": 1.0}
    f3 = _json(quick_figures, "fig3")
    assert f3["period_2pi_over_omega"] == pytest.approx(2 * np.pi / f3["omega_plus_p"], rel=1e-12)
    assert f3["max_field_error_after_one_period"] < 1e-6   # the exact wave comes back after one period
    assert f3["relative_energy_drift"] < 1e-8


def test_fig4_shear_oscillation_follows_eqs_28_30(quick_figures):
    f4 = _json(quick_figures, "fig4")
    assert f4["max_error_vs_ode_eqs_28_30"] < 1e-7
    assert f4["max_bend_Omega_perp"] < 1e-10       # the rod never bends
    assert f4["max_shear_angle_deg"] > 30           # and is strongly sheared


def test_fig7_equal_energy_and_bend_shear_ratio(quick_figures):
    r = _json(quick_figures, "fig7")["runs"]
    assert r["plus"]["initial_energy"] == pytest.approx(r["minus"]["initial_energy"], rel=1e-8)
    for b in ("plus", "minus"):
        assert r[b]["bend_over_shear_time_mean"] == pytest.approx(r[b]["bend_over_shear_linear_theory"], rel=1e-2)
    assert r["minus"]["min_Gamma3_over_norm"] < r["plus"]["min_Gamma3_over_norm"]  # omega_- shears more
    small = _json(quick_figures, "fig7")["small_k_0.5"]   # ... and the reverse for k < 1
    assert small["minus"]["initial_energy"] == pytest.approx(small["plus"]["initial_energy"], rel=1e-8)
    assert small["minus"]["min_Gamma3_over_norm"] > small["plus"]["min_Gamma3_over_norm"]


def test_max_displacement_formula_sec41(quick_figures):
    d = _json(quick_figures, "sec41_displacement")
    assert len(d["rows"]) == 6
    assert d["max_rel_diff"] < 1e-3   # the formula is first order: corrections O(eps), eps = 1e-3


def test_dispersion_check_numbers(quick_figures):
    d = _json(quick_figures, "dispersion_check")
    assert len(d["rows"]) == 2 * 2 + 4
    assert d["max_rel_diff"] < 1e-6


def test_second_harmonic(quick_figures):
    h = _json(quick_figures, "sec52_harmonic")
    assert h["loglog_slope_amplitude_vs_a"] == pytest.approx(2.0, abs=0.01)
    assert all(abs(x - 1) < 2e-3 for x in h["measured_over_Eq45_with_C3"])
    assert all(abs(x - 1) > 0.2 for x in h["measured_over_Eq45_with_C3_squared"])
    for row in h["rows"]:
        assert row["forced_frequency"] == pytest.approx(2 * row["omega_measured"], rel=1e-4)


def test_validation_claims(quick_figures):
    v = _json(quick_figures, "validation")
    assert all(abs(r - 16) < 0.5 for r in v["rk4_error_ratio_when_halving_dt"])   # RK4: 2^4
    assert v["dop853_rtol_1e-13"]["relative_energy_drift"] < 1e-11
    assert v["dop853_rtol_1e-13"]["max_director_norm_error"] < 1e-13


def test_energy_components_and_rings_and_wavespeed(quick_figures):
    e = _json(quick_figures, "sec52_energy")
    assert e["relative_total_energy_drift"] < 1e-8
    assert 0 < e["max_diff_over_total_energy_any_component_t_le_3.6"] < 0.05
    rings = _json(quick_figures, "rings")
    assert rings["rotating_ring"]["radius_max_dev"] < 1e-9
    ws = _json(quick_figures, "wavespeed")
    assert ws["predictions"]["lab_speed_minus_A_per_ps"] == pytest.approx(0.3423, rel=1e-3)
    assert 0.3 < ws["measured_A_per_ps"] < 5.0
    assert ws["planarity"] < 1e-3
