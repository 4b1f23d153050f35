"""`dnarod modes` (mdbridge/analysis/modes.py, spectrum.py, mode_spectra.py): each part
against something true independently of it.

* the fit's frequency errors on exact damped-oscillator series of known frequency and Q
  (bench/mode_spectrum_calibration.py, a fast subset of its table): stated / RMS error
  within 0.7-1.4 over 30 realisations, damped and undamped; the control (every mode taken
  as a sinusoid in white noise) fails on a damped one;
* the mode amplitudes of a synthetic helix with a planted mode: amplitude, n, quadrature
  and direction exact, under a 1-A helical offset and a periodic box;
* the paper's 158-bp rod kicked in its lowest bend mode: n = 1 at Eq 26's lower branch at
  q = 2 pi / L (an independent linearisation), once the kick's own nonlinear shift
  (~ A_v^2: two kicks, extrapolated to zero) is removed; control: the larger kick alone
  misses it;
* an MD folder (the 21-bp MD the tests build) goes through the same path, and its
  mode_series.npz re-analyses to the same table;
* bad input exits 2 naming the path.
"""
from __future__ import annotations

import json
import math
import subprocess
from pathlib import Path

import numpy as np
import pytest

from benchscripts import load_bench

ROOT = Path(__file__).resolve().parents[2]
CAL = load_bench("mode_spectrum_calibration.py")


# -- the spectral fit ------------------------------------------------------------------------
@pytest.mark.parametrize("period_ps, Q", [(111.0, 10.0), (375.0, math.inf)])
def test_frequency_errors_are_calibrated(period_ps, Q):
    """30 realisations each (fixed seeds); the ratio's own sampling error is ~13 %."""
    r = CAL.calibrate(CAL.oscillator_input(period_ps, Q, 30, seed=11))
    assert not r["refused"], r["refused"]
    assert CAL.LOW <= r["omega_ratio"] <= CAL.HIGH, r
    assert abs(r["omega_bias_rel"]) < 0.5 * r["omega_rms_rel"] + 1e-4, r
    if math.isinf(Q):
        assert r["taken_as_line"] == r["realisations"], r
    else:
        assert r["taken_as_line"] == 0 and 0.6 <= r["gamma_ratio"] <= 1.6, r


def test_the_sinusoid_control_fails():
    """The control must be able to fail: the same records of a damped mode (Q = 30, 11
    periods) with every mode taken as a sinusoid in white noise (a wave fit's frequency and
    error) state an error far below the real scatter: the amplitude and phase wander."""
    r = CAL.calibrate(CAL.oscillator_input(375.0, 30.0, 30, seed=12), line="always")
    assert r["omega_ratio"] < CAL.LOW / 2, r


def test_simulated_oscillator_has_the_exact_autocovariance():
    """The synthetic series the calibration rests on: sampled exactly (any gamma >= 0)."""
    from mdbridge.analysis.spectrum import oscillator_acvf, simulate
    rng = np.random.default_rng(5)
    for w, g in ((0.1, 0.02), (0.5, 0.0)):
        x = simulate(rng, 4000, 200, 0.5, w, g)
        for lag in (0, 3, 40):
            emp = np.mean(x[:, 0] * x[:, lag])
            # 4000 independent pairs: the standard error of the mean product is <= sqrt(2 / 4000)
            assert emp == pytest.approx(oscillator_acvf(lag * 0.5, w, g), abs=4 * np.sqrt(2 / 4000))


# -- the mode amplitudes -----------------------------------------------------------------------
@pytest.mark.parametrize("n_planted", [3, 12])
def test_planted_mode_of_a_synthetic_helix(n_planted):
    """u_in = 2 cos(k x + 0.3 t) A and u_out = 0.5 sin(k x) A in mode n: c_n(t) = 2 e^{0.3 i t}
    on e_in and -0.5 i on e_out; every other bend mode and twist stay at round-off. The
    base-pair origins sit 1 A off the axis and are wrapped into a box; at n = 12 the
    one-turn window would pass 0.23 of it."""
    from mdbridge.analysis.modes import ModeAnalysis
    from mdbridge.analysis.synthetic import helix_trajectory
    L = 158 * 3.38
    k = 2 * np.pi * n_planted / L
    t = np.arange(5.0)
    traj, _ = helix_trajectory(t, lambda x, tt: 2.0 * np.cos(k * x + 0.3 * tt), lambda x, tt: 0.5 * np.sin(k * x),
                               offset_A=1.0, box_A=200.0)
    r = ModeAnalysis(traj).run().results
    assert r.helical_repeat == 15 and list(r.n) == list(range(1, 15))
    # helix_trajectory's e_in is lab Z and e_out = Y x Z = X; transverse_basis picks e1 = X
    # (the lab axis most perpendicular to the axis Y, first of X and Z), e2 = Y x X = -Z
    assert np.allclose(r.e1, [1, 0, 0]) and np.allclose(r.e2, [0, 0, -1])
    c = r.bend[:, n_planted - 1]
    assert np.allclose(c[:, 0], -0.5j, atol=1e-6)                 # e1 = e_out
    assert np.allclose(c[:, 1], -2.0 * np.exp(0.3j * t), atol=1e-6)  # e2 = -e_in
    assert np.abs(np.delete(r.bend, n_planted - 1, axis=1)).max() < 1e-3
    assert np.allclose(r.helical_offset_A[:, 0], 1.0, atol=0.01)
    assert np.abs(r.twist).max() < 1e-3


# -- the rod: Eq 26 --------------------------------------------------------------------------
def _kicked_rod(rodsim, tmp, A_v):
    out = tmp / f"kick_{A_v:g}.h5"
    subprocess.run([str(rodsim), "run", str(ROOT / "workflows" / "scenes" / "dna158.toml"), "-o", str(out), "-q",
                    "--set", f"initial.A_v_A_per_ps={A_v}", "--set", "output.t_end=5310",
                    "--set", "output.frames=532", "--set", "solver.rtol=1e-9", "--set", "solver.atol=1e-11"],
                   check=True, timeout=300)
    return out


def test_kicked_rod_lowest_mode_is_eq26(rodsim, tmp_path):
    """5 ns of the paper's rod (3.2 periods of n = 1). The kick's amplitude A_v / omega
    stiffens the ring by the tension its extra contour makes, a shift ~ A_v^2 (2.2e-2 at
    A_v = 0.01, 2.2e-4 at 0.001 A/ps, measured); extrapolated to A_v -> 0 from the two,
    n = 1 is Eq 26's lower branch at q = 2 pi / L to 2e-5 (the rod's own time
    integration and the 158-point grid)."""
    from dnarod.cli import main
    from mdbridge.analysis.dispersion import omega_pm
    from dna_models.units import Units
    u = Units.paper()
    q = 2 * np.pi / (158 * 3.38 / u.ell_A)
    omega_eq26 = float(omega_pm(q, u.D_star[0], 1.0, "minus")) / u.tau_ps
    w = {}
    for A_v in (0.001, 0.01):
        d = tmp_path / f"modes_{A_v:g}"
        assert main(["modes", str(_kicked_rod(rodsim, tmp_path, A_v)), "-o", str(d)]) == 0
        table = json.loads((d / "modes.json").read_text())
        e = next(m for m in table["modes"] if (m["kind"], m["n"]) == ("bend", 1))
        assert e["reason"] is None and e["undamped"], e
        assert table["n_bp"] == 158 and table["helical_repeat"] == 15
        w[A_v] = e["omega_per_ps"]
        # modes a planar kick of n = 1 leaves at round-off are refused, with the reason
        twist = [m for m in table["modes"] if m["kind"] == "twist"]
        assert all(m["reason"] and m["reason"].startswith("no signal") for m in twist)
        assert all(m["omega_per_ps"] is None for m in twist)
    shift = {a: w[a] / omega_eq26 - 1 for a in w}
    assert 80 < shift[0.01] / shift[0.001] < 120             # ~ A_v^2: the nonlinear shift
    w0 = w[0.001] - (w[0.01] - w[0.001]) / 99.0              # Richardson: w = w0 + c A_v^2
    assert w0 / omega_eq26 - 1 == pytest.approx(0.0, abs=2e-5)
    assert abs(shift[0.01]) > 100 * 2e-5                      # control: the larger kick alone misses


# -- MD and the saved series ---------------------------------------------------------------------
def test_md_folder_and_its_npz_go_through_the_same_path(tiny_run, tmp_path):
    """The tiny comparison's 21-bp MD (2 turns: mode n = 1 only; 4-40 ps) through the same
    path as a rod file. Its bend mode (a period of tens of ps) cannot be measured in it and
    is refused with its reason and null numbers, keeping its variance; every entry has the
    schema's keys, and a refused one null frequencies. The npz it writes re-analyses to
    the same table."""
    from dnarod.cli import main
    md = sorted((tiny_run[0] / "md").iterdir())[0]
    out = tmp_path / "m"
    assert main(["modes", str(md), "-o", str(out)]) == 0
    t = json.loads((out / "modes.json").read_text())
    assert t["n_bp"] == 21 and t["helical_repeat"] == 2 and len(t["modes"]) == 3
    for e in t["modes"]:
        assert set(e) >= {"kind", "n", "omega_per_ps", "omega_err_per_ps", "damping_per_ps", "variance",
                          "variance_unit", "periods_in_record", "reason"}
        assert (e["omega_per_ps"] is None) == (e["reason"] is not None)
        assert e["variance"] > 0
    bend = t["modes"][0]
    assert bend["kind"] == "bend" and bend["reason"] and bend["omega_per_ps"] is None
    assert t["realisations"][0]["kind"] == "md" and "open_fraction" in t["realisations"][0]
    for f in ("mode_series.npz", "spectra.png", "dispersion.png"):
        assert (out / f).is_file()
    again = tmp_path / "again"
    assert main(["modes", str(out / "mode_series.npz"), "-o", str(again)]) == 0
    t2 = json.loads((again / "modes.json").read_text())
    for a, b in zip(t["modes"], t2["modes"]):
        assert (a["reason"] is None) == (b["reason"] is None)
        assert b["variance"] == pytest.approx(a["variance"], rel=1e-5)   # float32 storage


def test_bad_input_exits_2_naming_the_path(tmp_path, capsys):
    from dnarod.cli import main
    junk = tmp_path / "notes.txt"
    junk.write_text("not a trajectory\n")
    assert main(["modes", str(junk), "-o", str(tmp_path / "o")]) == 2
    assert f"{junk}: not a rod output file" in capsys.readouterr().err
    empty = tmp_path / "folder"
    empty.mkdir()
    assert main(["modes", str(empty), "-o", str(tmp_path / "o")]) == 2
    assert str(empty) in capsys.readouterr().err
    # a short rod file: the discard is longer than its record
    from mdbridge.rod.run import run_scene
    run = run_scene(ROOT / "workflows" / "scenes" / "dna158.toml",
                    set=("output.t_end=20", "output.frames=5"))
    h5 = tmp_path / "short.h5"
    run.write(h5)
    assert main(["modes", str(h5), "--discard-ps", "50", "-o", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert f"{h5}: --discard-ps 50 is not shorter than its record" in err
    assert main(["modes", str(h5), "--until-ps", "50", "-o", str(tmp_path / "o")]) == 2
    assert f"{h5}: --until-ps 50 is beyond its record" in capsys.readouterr().err
    assert main(["modes", str(h5), "--discard-ps", "5", "--until-ps", "5", "-o", str(tmp_path / "o")]) == 2
    assert "--until-ps 5: a time in ps after --discard-ps (5)" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()                      # refused before any work


def test_one_window_of_every_realisation():
    """--discard-ps and --until-ps cut each realisation on its own clock: frames 1000-3000 ps
    of a 4-ns series, both ends kept."""
    s = _realisation(np.random.default_rng(3), 111.0, 10.0, "a")
    w = s.after(1000.0, 3000.0)
    assert w.times_ps[0] == 1000.0 and w.times_ps[-1] == 3000.0 and len(w.times_ps) == 4001
    assert np.array_equal(w.bend, s.bend[2000:6001])
    assert len(s.after(1000.0).times_ps) == 6000


def _realisation(rng, period_ps, Q, source):
    """A ModeSeries of one bend mode (n = 1) whose four quadratures are damped oscillators
    of the given period and Q (4 ns of 0.5-ps frames); twist and stretch empty."""
    from mdbridge.analysis.mode_spectra import ModeSeries
    w, g = CAL.gamma_of(period_ps, Q)
    from mdbridge.analysis.spectrum import simulate
    x = simulate(rng, 4, 8000, 0.5, w, g, 1.0, 0.01)
    bend = (x[0] + 1j * x[2])[:, None, None] * np.array([1, 0])[None, None, :] \
        + (x[1] + 1j * x[3])[:, None, None] * np.array([0, 1])[None, None, :]
    zeros = np.zeros((8000, 1), complex)
    return ModeSeries(np.arange(8000) * 0.5, np.array([1]), bend, zeros, zeros, 534.04, 158, 15, source, "md")


def test_between_seed_scatter_enters_with_two_realisations():
    """Two seeds of one mode: pooled, each fitted alone, and the error multiplied by the
    Birge ratio of their scatter when it exceeds 1. Two seeds whose frequencies differ by
    5 % (far beyond the ~0.8 % errors) get an error that covers the difference; two seeds
    of one frequency keep the pooled fit's error (the control)."""
    from mdbridge.analysis.mode_spectra import mode_table
    rng = np.random.default_rng(21)
    same = mode_table([_realisation(rng, 111.0, 10.0, "a"), _realisation(rng, 111.0, 10.0, "b")])["modes"][0]
    apart = mode_table([_realisation(rng, 111.0, 10.0, "a"), _realisation(rng, 111.0 * 1.05, 10.0, "b")])["modes"][0]
    assert same["reason"] is None and apart["reason"] is None
    assert same["seeds"]["birge_ratio_applied"] < 2.0
    assert apart["seeds"]["birge_ratio"] > 2.0
    w = apart["seeds"]["omega_per_ps"]
    assert apart["omega_err_per_ps"] > 0.5 * abs(w[0] - w[1])
    assert apart["omega_err_per_ps"] > 2 * same["omega_err_per_ps"]
