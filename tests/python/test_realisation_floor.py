"""The between-realisation floor (mdbridge/analysis/realisation_floor.py) against realisations
drawn with a known extra scatter tau: the moment estimate of tau^2 is right on average, its
68 % Q-profile interval covers the true tau in ~68 % of the sets, and the errors with the floor
make the z of each value about the truth of variance ~1, where the stated errors alone (the
control) give several."""
import numpy as np
import pytest

from mdbridge.analysis.realisation_floor import between_realisation_floor

TRUTH, TAU = 1.2, 0.12


@pytest.mark.parametrize("k, z_var", [(2, (0.6, 1.3)), (3, (0.2, 0.6)), (6, (0.8, 1.5))])
def test_floor_recovers_the_extra_scatter(k, z_var):
    """(k = 2, 3: the floor is the upper end of tau's interval, module doc; the moment estimate
    alone leaves z variances of ~3.1 and ~1.7 there, the second control.)"""
    rng = np.random.default_rng(k)
    s = np.linspace(0.03, 0.08, k)
    tau2, cover, z_floor, z_bare, z_moment = [], 0, [], [], []
    sets = 400
    for _ in range(sets):
        x = TRUTH + rng.normal(0, TAU, k) + rng.normal(0, s)
        r = between_realisation_floor(x, s)
        tau2.append(r["tau"] ** 2)
        lo, hi = r["tau_interval_68"]
        cover += lo <= TAU <= hi
        z_floor += list((x - TRUTH) / np.array(r["errors_with_floor"]))
        z_bare += list((x - TRUTH) / s)
        z_moment += list((x - TRUTH) / np.hypot(s, r["tau"]))
    # the truncation at 0 biases tau^2 up a little; the moment estimate is right within 20 %
    assert np.mean(tau2) == pytest.approx(TAU ** 2, rel=0.25)
    assert 0.6 < cover / sets < 0.76
    assert np.var(z_bare) > 4                         # the control: one record's error alone
    assert z_var[0] < np.var(z_floor) < z_var[1]
    if k < 6:
        assert np.var(z_moment) > 1.5


def test_no_extra_scatter_gives_a_small_floor():
    rng = np.random.default_rng(1)
    s = np.full(5, 0.05)
    taus = [between_realisation_floor(TRUTH + rng.normal(0, s), s)["tau"] for _ in range(300)]
    assert np.median(taus) == 0.0 and np.mean(taus) < 0.5 * 0.05


def test_the_kicked_waves_committed_realisations():
    """results/main_job.json and results/main_job_1000ps.json: 1.12 +- 0.03 and 1.32 +- 0.06 A/ps."""
    r = between_realisation_floor([1.12, 1.32], [0.03, 0.06])
    assert r["Q"] == pytest.approx((0.2 / np.hypot(0.03, 0.06)) ** 2)
    assert r["tau"] == pytest.approx(0.133, abs=0.001)
    with pytest.raises(ValueError):
        between_realisation_floor([1.12], [0.03])
