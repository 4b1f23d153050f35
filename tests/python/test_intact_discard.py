"""The intact runs' discarded start from their own relaxation (workflows/steps/intact.py
discard_from_relaxation): every slow observable of every seed is asked when it has relaxed
(mdbridge/coarsegrain/equilibration.py), and the latest answer, rounded up to 50 ps, is the
discard.

Known answer: a 2-ns synthetic seed whose virial tension relaxes from +300 pN with
tau = 60 ps over AR(1) noise (sd 40 pN) is cut after 2-8 tau, and the bias the relaxation
leaves in the mean tension is below 0.35 of the tension's stated error; one whose bend n = 2
relaxes with tau = 300 ps asks for more than the 500 ps a record may spare and is refused
with the observable named. Control (must fail): no discard leaves a bias of several errors.
A stationary record loses at most 250 ps (the noisy maximum over 14 observables).
"""
import json

import numpy as np
import pytest

from dna_models.errors import InputError
from dnarod.steps.intact import discard_from_relaxation
from mdbridge.analysis.mode_spectra import ModeSeries, save_npz

DT, T_PS = 0.5, 2000.0


def _ar1(rng, n, phi=0.9):
    x = np.empty(n)
    x[0] = rng.normal()
    e = rng.normal(size=n) * np.sqrt(1 - phi ** 2)
    for i in range(1, n):
        x[i] = phi * x[i - 1] + e[i]
    return x


def _seed(d, rng, tension_tau_ps=None, bend2_tau_ps=None):
    t = np.arange(0, T_PS, DT)
    n = len(t)
    c = np.stack([_ar1(rng, n) + 1j * _ar1(rng, n) for _ in range(3)], axis=1)
    bend = np.stack([c, c], axis=-1)
    if bend2_tau_ps:
        bend[:, 1] *= 1 + 3 * np.exp(-t / bend2_tau_ps)[:, None]
    tension = 30 + 40 * _ar1(rng, n) + (300 * np.exp(-t / tension_tau_ps) if tension_tau_ps else 0)
    d.mkdir(parents=True)
    save_npz(d / "mode_series.npz", [ModeSeries(t, np.arange(1, 4), bend, c, c, 534.0, 158, 15, "synthetic",
                                                "md", np.zeros(n), {})])
    np.savez_compressed(d / "energies.npz", times_ps=t, tension_pN=tension, length_nm=np.full(n, 53.4),
                        restraint_kJ_mol=np.abs(_ar1(rng, n)))


@pytest.mark.parametrize("seed", [5, 6, 7, 8])
def test_the_discard_cuts_the_relaxation(tmp_path, seed):
    from dnarod.steps.dispersion import tension_record
    rng = np.random.default_rng(seed)
    _seed(tmp_path / "seed1", rng, tension_tau_ps=60)
    _seed(tmp_path / "seed2", rng)
    rec = discard_from_relaxation(tmp_path, ("seed1", "seed2"))
    T = rec["discard_ps"]
    assert 2 * 60 <= T <= 8 * 60, rec["per_seed"]["seed1"]["tension_pN"]
    assert rec["per_seed"]["seed1"]["tension_pN"]["start_ps"] == rec["longest_start_ps"]
    assert json.loads((tmp_path / "discard.json").read_text())["discard_ps"] == T
    e = np.load(tmp_path / "seed1" / "energies.npz")
    err = tension_record(e["times_ps"], e["tension_pN"], e["length_nm"], T, "synthetic")["tension_err_pN"]

    def bias(T):                                         # the relaxation's mean after T
        return 300 * 60 * (np.exp(-T / 60) - np.exp(-T_PS / 60)) / (T_PS - T)
    assert bias(T) < 0.35 * err, (bias(T), err)
    assert bias(0) > 2 * err                              # control: without the discard


@pytest.mark.parametrize("seed", [5, 6, 7, 8])
def test_a_stationary_record_loses_little(tmp_path, seed):
    rng = np.random.default_rng(seed)
    _seed(tmp_path / "seed1", rng)
    _seed(tmp_path / "seed2", rng)
    assert discard_from_relaxation(tmp_path, ("seed1", "seed2"))["discard_ps"] <= 250


def test_a_relaxation_longer_than_the_record_spares_is_refused(tmp_path):
    rng = np.random.default_rng(6)
    _seed(tmp_path / "seed1", rng, bend2_tau_ps=300)
    with pytest.raises(InputError, match="relaxes for"):
        discard_from_relaxation(tmp_path, ("seed1",))
    rec = json.loads((tmp_path / "discard.json").read_text())
    worst = max(rec["per_seed"]["seed1"].items(), key=lambda kv: kv[1]["start_ps"])
    assert worst[0] == "bend_2_squared"
