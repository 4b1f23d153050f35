"""The two stretch moduli of a duplex in water at a set tension (mdbridge/md/gromacs/tension.py),
on records of known answer: box lengths L(t) drawn as a correlated Gaussian process whose
variance is kT <L> / S, as the isotension ensemble of a semi-isotropic barostat gives them.

- isotension_stretch_modulus returns S with an error that covers the scatter of S across
  independent records (RMS z within 0.5-1.6; control: the error halved fails);
- force_extension recovers S from two tensions' mean lengths and says whether the gain is
  resolved; a record that did not stretch is not called consistent.
"""
from __future__ import annotations

import numpy as np

from mdbridge.md.gromacs.tension import force_extension, isotension_stretch_modulus

KT_300 = 1.380649e-23 * 300.0 * 1e21        # pN nm
L0_NM, S_PN, TAU_FRAMES, DT_PS = 7.1, 1100.0, 25.0, 0.2


def record(rng, n: int, tension_pN: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """(t ps, L nm): an AR(1) series with correlation time TAU_FRAMES frames, mean
    L0 (1 + T / S) and variance kT L / S."""
    mean = L0_NM * (1.0 + tension_pN / S_PN)
    sd = np.sqrt(KT_300 * mean / S_PN)
    a = np.exp(-1.0 / TAU_FRAMES)
    x = np.empty(n)
    x[0] = rng.normal()
    eps = rng.normal(size=n) * np.sqrt(1.0 - a * a)
    for i in range(1, n):
        x[i] = a * x[i - 1] + eps[i]
    return np.arange(n) * DT_PS, mean + sd * x


def test_isotension_modulus_error_covers_the_scatter_and_a_halved_error_fails():
    rng = np.random.default_rng(7)
    z, z_half = [], []
    for _ in range(24):
        t, L = record(rng, 5000)                   # 1 ns at 0.2 ps, ~200 correlation times
        r = isotension_stretch_modulus(t, L, 300.0, discard_ps=20.0)
        z.append((r["S_pN"] - S_PN) / r["S_err_pN"])
        z_half.append((r["S_pN"] - S_PN) / (0.5 * r["S_err_pN"]))
        assert abs(r["length_nm"]["mean"] - L0_NM) < 5 * r["length_nm"]["sem"]
    rms, rms_half = float(np.sqrt(np.mean(np.square(z)))), float(np.sqrt(np.mean(np.square(z_half))))
    assert 0.5 < rms < 1.6, rms
    assert abs(np.mean(z)) < 3.0 / np.sqrt(len(z)) + 0.4        # no gross bias
    assert rms_half > 1.6, rms_half                              # the control must fail


def test_force_extension_recovers_the_modulus_and_a_rigid_record_is_inconsistent():
    rng = np.random.default_rng(11)
    t, L_lo = record(rng, 20000)
    _, L_hi = record(rng, 20000, tension_pN=30.0)
    lo = isotension_stretch_modulus(t, L_lo, 300.0)
    hi = isotension_stretch_modulus(t, L_hi, 300.0)
    r = force_extension(lo["length_nm"], hi["length_nm"], 30.0, lo["S_pN"], lo["S_err_pN"])
    assert abs(r["delta_length_nm"] - L0_NM * 30.0 / S_PN) < 3 * r["delta_length_err_nm"]
    assert r["consistent_2_sigma"] and r["resolved_from_zero_2_sigma"]
    assert abs(r["S_force_extension_pN"] - S_PN) < 3 * r["S_force_extension_err_pN"]
    # control: the high-tension record without the stretch (a barostat that held the box)
    rigid = isotension_stretch_modulus(t, L_hi - L0_NM * 30.0 / S_PN, 300.0)
    c = force_extension(lo["length_nm"], rigid["length_nm"], 30.0, lo["S_pN"], lo["S_err_pN"])
    assert not c["consistent_2_sigma"] and not c["resolved_from_zero_2_sigma"]
