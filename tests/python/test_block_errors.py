"""Block errors of mode frequencies (mdbridge/analysis/block_errors.py) against their
independent truth: the scatter of the whole record's frequency over 100 independent
realisations of synthetic damped oscillators of known frequency (omega 0.6 rad/ps, Q 3, four
series as a bend mode's, 1000 ps of 0.5-ps frames: 8 blocks of 125 ps by the rule).

* stationary: the z of the whole record's frequency with the block error has variance ~1
  (Student-t inflated: err_chi2), and so has the fit's curvature error (it is calibrated
  for a stationary oscillator); a block error halved (the control) does not;
* episodes: the frequency jumps by 5 % rms between eight 125-ps episodes of each record (the
  slow episodes of the vacuum duplex in small), one per block: the realisations scatter by
  ~1.8 %, which the curvature error does not see (its z variance is several: it fails, as it
  should), while the block error covers it;
* longer episodes (four of 250 ps, two blocks each): a wander slower than the blocks, which
  the rule says the block error does not cover, and it does not (the limit, held as a
  control that must fail)."""
import math

import numpy as np
import pytest

from mdbridge.analysis.block_errors import (block_count, block_frequencies, block_length_ps, mode_block_errors,
                                            pooled_block_error)
from mdbridge.analysis.mode_spectra import ModeSeries, fit_kind, pooled_series
from mdbridge.analysis.spectrum import simulate

W, G, DT, RECORD_PS = 0.6, 0.1, 0.5, 1000.0
N = int(RECORD_PS / DT)
REALISATIONS = 100
V_BLOCK = (0.4, 1.8)        # the z variance of the block error (err_chi2) over the realisations


def _series(x) -> ModeSeries:
    """One bend mode (n = 1) of two transverse directions from four real series (Re, Im each)."""
    bend = np.stack([x[0] + 1j * x[1], x[2] + 1j * x[3]], axis=-1)[:, None, :]
    t = np.arange(x.shape[1]) * DT
    z = np.zeros((len(t), 1), complex)
    return ModeSeries(t, np.array([1]), bend, z, z, 534.04, 158, 15, "synthetic", "rod")


def _realisation(rng, episodes: int = 0, spread: float = 0.0) -> ModeSeries:
    if not episodes:
        return _series(simulate(rng, 4, N, DT, W, G))
    m = N // episodes
    return _series(np.concatenate([simulate(rng, 4, m, DT, W * (1 + spread * rng.standard_normal()), G)
                                   for _ in range(episodes)], axis=1))


def _estimates(episodes, spread, seed):
    out = []
    for i in range(REALISATIONS):
        s = _realisation(np.random.default_rng(seed + i), episodes, spread)
        (fit, why), = fit_kind([pooled_series([s], "bend", 0, len(s.times_ps))], DT)
        assert why is None
        B = block_count(RECORD_PS, fit.omega_per_ps, fit.damping_per_ps)
        r = pooled_block_error([fit.omega_per_ps], [block_frequencies(s, "bend", B)[:, 0, 0]])
        out.append((fit.omega_per_ps, fit.omega_err_per_ps, r["err_chi2"][0], B))
    return np.array(out)


@pytest.fixture(scope="module")
def stationary():
    return _estimates(0, 0.0, 1000)


@pytest.fixture(scope="module")
def episodic():
    return _estimates(8, 0.05, 5000)


@pytest.fixture(scope="module")
def long_episodes():
    return _estimates(4, 0.05, 7000)


def _zvar(est, col):
    return float(np.mean(((est[:, 0] - W) / est[:, col]) ** 2))


def test_rule():
    # 3 periods (31 ps) and 2 / gamma (20 ps): blocks of >= 31.4 ps; 8 (the most, so the
    # longest blocks that leave 8) in 1000 ps; 4 where 8 would be too short
    assert block_length_ps(W, G) == pytest.approx(3 * 2 * math.pi / W)
    assert block_count(RECORD_PS, W, G) == 8
    assert block_count(RECORD_PS, 0.1, 0.01) == 4                # 200-ps blocks (2 / gamma)
    assert block_count(RECORD_PS, 0.01, 0.001) is None         # 2000-ps blocks: none fit


def test_stationary_block_error_covers_the_scatter(stationary):
    assert set(stationary[:, 3]) == {8}
    v_block, v_fit = _zvar(stationary, 2), _zvar(stationary, 1)
    assert 0.4 < v_block < 1.6, v_block
    assert 0.6 < v_fit < 1.6, v_fit
    halved = float(np.mean(((stationary[:, 0] - W) / (stationary[:, 2] / 2)) ** 2))
    assert halved > 2.0, halved                                  # the control


def test_episodes_defeat_the_fit_error_not_the_block_error(episodic):
    v_block, v_fit = _zvar(episodic, 2), _zvar(episodic, 1)
    assert v_fit > 2.5, v_fit                                    # the curvature error fails, as it should
    assert V_BLOCK[0] < v_block < V_BLOCK[1], v_block


def test_a_wander_slower_than_the_blocks_is_not_covered(long_episodes):
    """The rule's limit (module doc): episodes of two blocks; the block error fails too."""
    assert _zvar(long_episodes, 1) > 2.5
    assert _zvar(long_episodes, 2) > V_BLOCK[1]


def test_pooled_block_error_student_t():
    """nu = sum (m_r - 1); err = omega s / sqrt(m_r), s pooled over realisations in relative
    units; err_chi2 = err sqrt(nu / (nu - 2)); a realisation with most blocks refused is left out."""
    rng = np.random.default_rng(3)
    a = 1 + 0.02 * rng.standard_normal(8)
    r = pooled_block_error([1.0], [a])
    assert r["nu"] == 7
    assert r["err"][0] == pytest.approx(np.std(a / a.mean(), ddof=1) / math.sqrt(8))
    assert r["err_chi2"][0] == pytest.approx(r["err"][0] * math.sqrt(7 / 5))
    b = 2 * (1 + 0.02 * rng.standard_normal(6))
    r = pooled_block_error([1.0, 2.0], [a, b])
    s2 = (np.var(a / a.mean(), ddof=1) * 7 + np.var(b / b.mean(), ddof=1) * 5) / 12
    assert r["nu"] == 12 and r["err"][1] == pytest.approx(2 * math.sqrt(s2 / 6))
    b[:4] = np.nan
    assert pooled_block_error([1.0, 2.0], [a, b])["blocks_per_realisation"] == [8, 0]
    assert pooled_block_error([1.0], [np.array([1.0, 1.01])])["err"] is None


def test_mode_block_errors_on_two_realisations():
    rng = np.random.default_rng(11)
    series = [_realisation(rng) for _ in range(2)]
    tables = []
    for s in series:
        (fit, _), = fit_kind([pooled_series([s], "bend", 0, len(s.times_ps))], DT)
        tables.append({"modes": [{"kind": "bend", "n": 1, "omega_per_ps": fit.omega_per_ps,
                                  "omega_err_per_ps": fit.omega_err_per_ps, "damping_per_ps": fit.damping_per_ps,
                                  "omega0_per_ps": fit.omega0_per_ps, "omega0_err_per_ps": fit.omega0_err_per_ps}]})
    e, = mode_block_errors(series, tables, kinds=("bend",))
    assert e["reason"] is None and e["n_blocks"] == 8
    b = e["omega0_block"]
    assert len(b["err"]) == 2 and b["nu"] >= 10
    assert 0.3 < b["err"][0] / tables[0]["modes"][0]["omega0_err_per_ps"] < 3
