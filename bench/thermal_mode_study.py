"""When is a kicked frequency measurable over the thermal motion of the mode? The synthetic
study behind the table of docs/analysis.md, "Small amplitudes".

Each spatial quadrature of the fundamental is an underdamped Langevin oscillator at the
linear omega with quality factor Q, at the thermal rms of equipartition
(mdbridge/analysis/thermal_mode.py), sampled exactly; the kick adds a_kick e^{-gamma t/2}
sin(omega_d t) in one quadrature (the same damping, by fluctuation-dissipation), plus the
AR(1) local noise of tests/python/test_analysis_mode_error.py. The frequency is fitted by
mdbridge.analysis.mode_error.standing_mode_fit and its scatter, bias and stated error over
the realisations are printed as the table's rows (~2.5 min a row of four SNRs).

    /usr/bin/python3 bench/thermal_mode_study.py [--Q 3 10 30] [--snr 0 0.5 1 2]
"""
from __future__ import annotations

import argparse
import math

import numpy as np

from dna_models.bdna import RISE_A
from mdbridge.analysis.mode_error import standing_mode_fit
from mdbridge.analysis.thermal_mode import _oscillator

# the table's case: the linear omega of the 158-bp rod (0.342 A/ps, period 1.56 ns), its
# thermal rms at 300 K (24 A), 3-ns records of 4-ps frames, 20 realisations
OMEGA_PER_PS = 0.00402
A_THERMAL_A = 24.0
K_PER_A = 2 * math.pi / (158 * RISE_A)
RECORD_PS = 3000.0


def kicked_mode_study(a_kick_A: float, a_thermal_A: float, omega: float, Q: float, record_ps: float,
                      dt_ps: float = 4.0, n_real: int = 20, k_per_A: float = 1.0, seed: int = 0,
                      local_noise_A: float = 1.0, local_tau_ps: float = 5.0) -> dict:
    """Scatter, bias and stated error of the fitted frequency over n_real realisations."""
    from scipy.signal import lfilter
    rng = np.random.default_rng(seed)
    t = np.arange(0.0, record_ps, dt_ps)
    n = len(t)
    q = a_thermal_A / math.sqrt(2)
    xc = _oscillator(rng, n_real, n, dt_ps, omega, Q, q)
    xs = _oscillator(rng, n_real, n, dt_ps, omega, Q, q)
    g = omega / Q
    wd = math.sqrt(max(omega ** 2 - g ** 2 / 4, 0.0))
    kick = a_kick_A * np.exp(-g * t / 2) * np.sin(wd * t)
    phi = math.exp(-dt_ps / local_tau_ps)
    e = rng.standard_normal((2, n_real, n))
    e[..., 0] /= math.sqrt(1 - phi ** 2)
    ln = lfilter([math.sqrt(1 - phi ** 2) * local_noise_A], [1, -phi], e, axis=-1)
    est_list, err, refused = [], [], 0
    for r in range(n_real):
        c = (xc[r] + kick) - 1j * xs[r] + ln[0, r] + 1j * ln[1, r]
        f = standing_mode_fit(t, c, k_per_A, record_term=False)
        if not math.isfinite(f["speed_A_per_ps"]):
            refused += 1
            continue
        est_list.append(f["omega_per_ps"])
        err.append(f["omega_err_per_ps"])
    est = np.array(est_list)
    ok = len(est) >= 3
    return {"a_kick_A": a_kick_A, "a_thermal_A": a_thermal_A,
            "snr": a_kick_A / a_thermal_A if a_thermal_A else math.inf,
            "Q": Q, "record_ps": record_ps, "n_real": n_real, "refused": refused,
            "omega_true_per_ps": wd,
            "rel_bias": float(est.mean() / wd - 1) if ok else float("nan"),
            "rel_scatter": float(np.std(est, ddof=1) / wd) if ok else float("nan"),
            "rel_stated_err": float(np.mean(err) / wd) if ok else float("nan")}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--Q", type=float, nargs="+", default=[3.0, 10.0, 30.0])
    ap.add_argument("--snr", type=float, nargs="+", default=[0.0, 0.5, 1.0, 2.0])
    ap.add_argument("--n-real", type=int, default=20)
    a = ap.parse_args(argv)
    print("| Q | SNR | relative scatter of omega | bias | stated (fit) error | refused |")
    print("|---|---|---|---|---|---|")
    for Q in a.Q:
        for snr in a.snr:
            r = kicked_mode_study(snr * A_THERMAL_A, A_THERMAL_A, OMEGA_PER_PS, Q, RECORD_PS,
                                  n_real=a.n_real, k_per_A=K_PER_A)
            print(f"| {Q:g} | {snr:g} | {100 * r['rel_scatter']:.1f} % | {100 * r['rel_bias']:+.1f} % | "
                  f"{100 * r['rel_stated_err']:.1f} % | {r['refused']} |", flush=True)


if __name__ == "__main__":
    main()
