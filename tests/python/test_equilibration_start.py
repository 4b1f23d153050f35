"""The discarded start of a run from its own relaxation (mdbridge/coarsegrain/equilibration.py,
used by the coarse-graining and by workflows/steps/intact.py).

Known answer: AR(1) noise (correlation time ~10 frames) on top of an offset that relaxes
as exp(-t / tau_relax). Cutting the start must remove the relaxation: the chosen start lies
beyond ~2 tau_relax (where the offset has fallen below the noise's standard error over the
rest) and before the record's middle; a longer relaxation gives a later start.
Control (must fail): the same noise without a relaxing start gives a start near 0, so a
rule that always cut a fixed amount would fail one of the two checks.
"""
import numpy as np
import pytest

from mdbridge.coarsegrain.equilibration import equilibration_start

T, PHI = 20000, 0.9


def _ar1(rng):
    e = rng.normal(size=T) * np.sqrt(1 - PHI ** 2)
    x = np.empty(T)
    x[0] = rng.normal()
    for i in range(1, T):
        x[i] = PHI * x[i - 1] + e[i]
    return x


@pytest.mark.parametrize("tau_relax", [300, 1000])
def test_the_relaxing_start_is_cut(tau_relax):
    rng = np.random.default_rng(tau_relax)
    found = []
    for _ in range(5):
        y = _ar1(rng) + 8.0 * np.exp(-np.arange(T) / tau_relax)
        found.append(equilibration_start(y, 50)[0])
    assert min(found) >= 2 * tau_relax, found
    assert max(found) <= 8 * tau_relax, found


def test_control_a_stationary_series_keeps_its_start():
    rng = np.random.default_rng(7)
    found = [equilibration_start(_ar1(rng), 50)[0] for _ in range(5)]
    assert np.median(found) <= 600, found          # far below the 2 x 300 frames cut above


def test_several_series_take_the_latest_start():
    """The coarse-graining's use: the latest start of the series (T, k) is the ensemble's."""
    rng = np.random.default_rng(3)
    y = np.stack([_ar1(rng), _ar1(rng) + 8.0 * np.exp(-np.arange(T) / 1000)], axis=1)
    assert equilibration_start(y, 50)[0] == equilibration_start(y[:, 1], 50)[0]
