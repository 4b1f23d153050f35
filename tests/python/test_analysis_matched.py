"""Matched quantities (mdbridge/analysis/matched.py) against independent truths: the exact
variance of the mean of AR(1) series, the unit conversion bar x A^2 -> pN done by hand, the
known rise of synthetic helices, and the regime rule."""
import math

import numpy as np
import pytest
from scipy.signal import lfilter

from mdbridge.analysis.matched import axial_strain, regime, rod_tension_pN, step_rises
from mdbridge.md.gromacs.tension import md_tension_pN
from mdbridge.stats import block_sem
from mdbridge.analysis.synthetic import helix_trajectory


def exact_sem_ar1(phi, sigma, n):
    """sqrt(Var(mean)) of a stationary AR(1) series of variance sigma^2."""
    k = np.arange(1, n)
    return sigma * math.sqrt((1 + 2 * np.sum((1 - k / n) * phi ** k)) / n)


@pytest.mark.parametrize("phi", [0.0, 0.8, 0.95])
def test_block_sem_against_ar1(phi):
    rng = np.random.default_rng(4)
    n, sigma, R = 4096, 2.0, 200
    e = rng.standard_normal((R, n))
    e[:, 0] /= math.sqrt(1 - phi ** 2)
    x = lfilter([sigma * math.sqrt(1 - phi ** 2)], [1, -phi], e, axis=1) + 7.0
    truth = exact_sem_ar1(phi, sigma, n)
    sems = np.array([block_sem(xx)["sem"] for xx in x[:40]])
    assert np.mean(sems) == pytest.approx(truth, rel=0.2)
    assert np.std(x.mean(axis=1), ddof=1) == pytest.approx(truth, rel=0.15)  # the truth is the truth
    if phi > 0.5:  # control: the naive SEM is several times too small
        assert block_sem(x[0])["naive_sem"] < 0.5 * truth


def test_tension_units_and_sign():
    # -1 bar over 100 nm^2 = 1e5 Pa x 1e-16 m^2 = 1e-11 N = +10 pN (tension)
    assert md_tension_pN([-1.0], 100 * 100.0)[0] == pytest.approx(10.0)
    assert md_tension_pN([2.0], 1e4)[0] == pytest.approx(-20.0)  # compression
    # rod: 1 % strain x C3 = 1.19 x 9.08e-10 N = 10.8 pN
    assert rod_tension_pN([1.01])[0] == pytest.approx(0.01 * 1.19 * 9.08e-10 * 1e12)


def test_strain_from_rises_of_a_helix():
    t = np.array([0.0, 1.0, 2.0])
    for rise in (3.38, 3.42):
        traj, _ = helix_trajectory(t, lambda x, tt: 0 * x, rise_A=rise, offset_A=1.5, box_A=80.0)
        r = step_rises(traj.origins, traj.R, traj.period)
        assert np.allclose(r, rise, rtol=1e-9)
        s = axial_strain(traj, 3.38)
        assert s["contour_strain_mean"] == pytest.approx(rise / 3.38 - 1, abs=1e-12)
    # a bent helix in the same box: the contour is longer than the box
    traj, _ = helix_trajectory(t, lambda x, tt: 20.0 * np.cos(2 * np.pi * x / (158 * 3.38)))
    s = axial_strain(traj, 3.38)
    k = 2 * np.pi / (158 * 3.38)
    assert s["contour_strain_mean"] == pytest.approx((k * 20.0) ** 2 / 4, rel=0.05)
    assert s["end_to_end_strain_mean"] == pytest.approx(0.0, abs=1e-12)


def test_regime_labels():
    assert regime(3.0, 40.0)["regime"] == "linear"
    assert regime(3.0, None)["regime"] == "linear"
    assert regime(3.0, 5.0)["regime"] == "linear"
    assert regime(8.0, 20.0)["regime"] == "nonlinear elastic"  # not well below the baseline
    assert regime(30.0, 0.0)["regime"] == "nonlinear elastic"
    # no overstretching boundary for a ligated ring in vacuum (its force is unmeasured)
    assert regime(130.0, 0.0)["regime"] == "nonlinear elastic"
    assert "110 pN" in regime(130.0, 0.0)["rule"] and "unmeasured" in regime(130.0, 0.0)["rule"]
    assert regime(float("nan"))["regime"] == "unknown"
    assert regime(30.0, 0.0, err_pN=1.0)["regime"] == "nonlinear elastic"
    assert regime(-296.0, None, err_pN=564.0)["regime"].startswith("not resolved")


def test_thermal_mode_amplitude_and_oscillator():
    """Equipartition amplitude against the persistence-length form done by hand, and the
    sampled Langevin oscillator's variance and frequency against their exact values."""
    from mdbridge.analysis.thermal_mode import _oscillator, thermal_mode_rms_A
    L_A, D = 158 * 3.38, 2.75e-28            # D = 66.4 nm x kT(300 K)
    lp_A = D / (1.380649e-23 * 300) * 1e10
    k = 2 * np.pi / L_A
    assert thermal_mode_rms_A(L_A, D) == pytest.approx(math.sqrt(4 / (lp_A * k ** 4 * L_A)), rel=1e-9)
    assert thermal_mode_rms_A(L_A, D, tension_pN=10.0) < thermal_mode_rms_A(L_A, D)
    rng = np.random.default_rng(2)
    w, dt = 0.05, 2.0
    x = _oscillator(rng, 4000, 400, dt, w, 20.0, 3.0)
    # independent realisations at two times: stationary variance 3^2 (5 sigma ~ 11 %)
    assert np.mean(x[:, 0] ** 2) == pytest.approx(9.0, rel=0.11)
    assert np.mean(x[:, -1] ** 2) == pytest.approx(9.0, rel=0.11)
    spec = np.mean(np.abs(np.fft.rfft(x, axis=1)) ** 2, axis=0)
    nu = np.fft.rfftfreq(400, dt) * 2 * np.pi
    assert nu[np.argmax(spec)] == pytest.approx(w, abs=nu[1])  # to one frequency bin


def test_tension_error_covers_a_slow_part():
    """The MD tension is white noise (~400 pN) over a slow part (docs/md.md, 21 bp). Here:
    600 frames of 400 pN white noise plus an AR(1) part of 80 pN rms with tau = 40 frames,
    300 realisations. The stated error (larger of the first blocking plateau and the
    longest blocks) must match the scatter of the means within 30 %; the first plateau
    alone (the control) is ~2x too small and must fail that."""
    from mdbridge.analysis.matched import tension_summary
    rng = np.random.default_rng(7)
    n, tau, amp = 600, 40.0, 80.0
    phi = np.exp(-1.0 / tau)
    means, stated, first = [], [], []
    for _ in range(300):
        e = rng.normal(size=n) * amp * np.sqrt(1 - phi**2)
        slow = np.empty(n)
        slow[0] = rng.normal() * amp
        for i in range(1, n):
            slow[i] = phi * slow[i - 1] + e[i]
        s = tension_summary(400.0 * rng.normal(size=n) + slow)
        means.append(s["tension_pN"])
        stated.append(s["tension_sem_pN"])
        first.append(s["tension_sem_first_plateau_pN"])
    actual = np.std(means, ddof=1)
    rms = lambda x: float(np.sqrt(np.mean(np.square(x))))  # noqa: E731
    assert 0.7 < rms(stated) / actual < 1.3
    assert rms(first) / actual < 0.6
