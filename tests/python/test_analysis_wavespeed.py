"""Wave-speed estimators against synthetic waves of known speed (independent truth:
the speed we put in), through the full path: base-pair frames on a periodic helix ->
helical axis -> u(s, t) -> k-mode -> fit."""
import numpy as np
import pytest

from mdbridge.analysis import WaveAnalysis, fit_wave_speed, phase_velocity
from mdbridge.analysis.synthetic import helix_trajectory

N_BP, RISE = 158, 3.38
L = N_BP * RISE
K = 2 * np.pi / L


def analyse(u_in, times, **kw):
    traj, _ = helix_trajectory(times, u_in, n=N_BP, rise_A=RISE, **kw)
    return WaveAnalysis(traj, n_boot=50).run().results


@pytest.mark.parametrize("sign", [+1, -1])
def test_travelling_wave_with_noise(sign):
    c = 2.2
    w = c * K
    times = np.arange(0.0, 300.0, 1.0)  # ~1.2 periods
    r = analyse(lambda x, t: 5.0 * np.cos(K * x - sign * w * t + 0.7), times,
                offset_A=1.5, noise_A=0.5, box_A=120.0, seed=3)
    assert r.wave["speed_A_per_ps"] == pytest.approx(c, rel=0.01)
    assert r.wave_check["speed_A_per_ps"] == pytest.approx(c, rel=0.01)
    assert r.wave["direction"] == ("forward" if sign > 0 else "backward")
    assert r.wave_check["direction"] == r.wave["direction"]
    assert abs(r.wave["speed_A_per_ps"] - c) < 5 * r.wave["speed_err_A_per_ps"]


def test_standing_wave_with_noise():
    c = 1.4
    w = c * K
    times = np.arange(0.0, 3 * 2 * np.pi / w, 2.0)  # three periods
    r = analyse(lambda x, t: 4.0 * np.cos(K * x + 0.2) * np.cos(w * t + 0.4), times,
                offset_A=1.0, noise_A=0.5, seed=5)
    wf = r.wave
    assert wf["speed_A_per_ps"] == pytest.approx(c, rel=0.01)
    assert wf["amplitude_forward_A"] == pytest.approx(wf["amplitude_backward_A"], rel=0.05)
    assert "frequency" in r.wave_check["method"]  # the split path was taken
    assert r.wave_check["speed_A_per_ps"] == pytest.approx(c, rel=0.01)


def test_short_record_less_than_a_period():
    """The MD of the default workflow covers under half a period: the NLS must still
    find the speed of a travelling wave."""
    c = 2.2
    w = c * K
    times = np.arange(0.0, 100.0, 0.5)  # 0.41 periods
    r = analyse(lambda x, t: 5.0 * np.cos(K * x - w * t), times, noise_A=0.3, seed=1)
    assert r.wave["speed_A_per_ps"] == pytest.approx(c, rel=0.01)
    assert r.wave_check["speed_A_per_ps"] == pytest.approx(c, rel=0.01)


def test_dominant_of_two_frequencies():
    """A weak fast (shear-branch-like) oscillation on top of the slow wave does not
    pull the estimate: the global scan picks the dominant component."""
    c = 0.35
    w = c * K
    times = np.arange(0.0, 2000.0, 2.0)
    r = analyse(lambda x, t: 5.0 * np.cos(K * x - w * t) + 0.5 * np.cos(K * x) * np.cos(1.06 * t),
                times, seed=2)
    assert r.wave["speed_A_per_ps"] == pytest.approx(c, rel=0.01)


def test_uncertainty_is_honest():
    """Across independent noise realisations the scatter of the estimate matches the
    reported standard error (within a factor 2), for white and correlated noise."""
    rng = np.random.default_rng(11)
    w, k = 0.03, 0.02
    t = np.arange(0.0, 400.0, 1.0)
    clean = 3.0 * np.exp(-1j * (w * t - 0.3)) + 0.5 * np.exp(1j * (w * t + 1.0))
    for rho in (0.0, 0.8):  # AR(1) coefficient of the noise
        est, err = [], []
        for _ in range(20):
            e = rng.standard_normal(len(t)) + 1j * rng.standard_normal(len(t))
            noise = np.empty_like(e)
            noise[0] = e[0]
            for i in range(1, len(t)):
                noise[i] = rho * noise[i - 1] + np.sqrt(1 - rho ** 2) * e[i]
            f = fit_wave_speed(t, clean + 0.5 * noise, k, n_boot=40, seed=int(rng.integers(1 << 30)))
            est.append(f["speed_A_per_ps"])
            err.append(f["speed_err_A_per_ps"])
        scatter = np.std(est, ddof=1)
        assert np.mean(est) == pytest.approx(w / k, rel=0.01)
        assert 0.5 < np.mean(err) / scatter < 2.0, (rho, np.mean(err), scatter)


def test_phase_velocity_is_independent_of_the_fit():
    t = np.arange(0.0, 200.0, 1.0)
    c = 2.0 * np.exp(-1j * 0.05 * t)
    pv = phase_velocity(t, c, 0.01)
    assert pv["speed_A_per_ps"] == pytest.approx(5.0, rel=1e-9)
    assert pv["direction"] == "forward"


def test_record_too_short_gives_no_speed():
    """A record of 2 % of a period cannot give a frequency: NaN with the reason, not a
    number with a tiny error bar."""
    t = np.arange(0.0, 5.0, 0.4)
    w = 2 * np.pi / 250.0
    c = 3.0 * np.exp(-1j * w * t) + 3.0 * np.exp(1j * w * t)
    f = fit_wave_speed(t, c, 0.01, n_boot=10)
    assert np.isnan(f["speed_A_per_ps"]) and "quarter period" in f["reason"]


@pytest.mark.parametrize("periods", [0.34, 2.0])
def test_api_refuses_a_short_standing_record(periods):
    """WaveAnalysis refuses where the workflow refuses (mdbridge/analysis/mode_error.py:
    a standing mode with fewer than 0.75 fitted periods): speed None with the reason.
    Control: the same standing mode over 2 periods gives its speed."""
    c = 1.7
    w = c * K
    times = np.arange(0.0, periods * 2 * np.pi / w, 2.0)
    r = analyse(lambda x, t: 8.0 * np.cos(K * x) * np.sin(w * t + 0.3) + 0.5 * np.sin(K * x), times,
                noise_A=0.2, seed=5)
    if periods < 0.75:
        assert r.wave["speed_A_per_ps"] is None and r.wave["speed_err_A_per_ps"] is None
        assert "refused" in r.wave["reason"] and "periods" in r.wave["reason"]
    else:
        assert r.wave["speed_A_per_ps"] == pytest.approx(c, rel=0.02)
        assert "reason" not in r.wave
