"""A between-realisation floor for a quantity that one record measures with an error too small
for the scatter between records (docs/analysis.md, "Realisations of one setting").

k realisations of one setting give values x_i with stated errors s_i. When the errors cover
the scatter, Q = sum_i w_i (x_i - xbar)^2 (w_i = 1 / s_i^2, xbar the weighted mean) follows
chi^2 with k - 1 degrees of freedom. When they do not, each realisation carries an extra
scatter tau that its own error does not see (for the kicked wave: the thermal state the kick
lands on, the 2-thread MD's non-reproducibility), and the method of moments (DerSimonian &
Laird 1986) estimates

    tau^2 = max(0, (Q - (k - 1)) / (sum w - sum w^2 / sum w)).

With k realisations tau^2 has k - 1 degrees of freedom; with k = 2 it is one chi^2 draw, and
its 68 % interval spans more than a factor 10 in tau^2 (`tau_interval`: the Q-profile interval,
Viechtbauer 2007). A single record's error is sqrt(s^2 + floor^2), with the floor
  * tau itself from MIN_K_MOMENT realisations on: the z of each value about the truth then has
    variance 1.14 at k = 6 (tests/python/test_realisation_floor.py);
  * the upper end of tau's 68 % interval below that: from fewer realisations the moment
    estimate is too often small (z variance 3.1 at k = 2, 1.7 at k = 3, for a true tau of 2-4
    stated errors), the upper end covers (0.9 at k = 2, 0.35 at k = 3).
"""
from __future__ import annotations

import math

import numpy as np

MIN_K_MOMENT = 6


def _q(x, s, tau2):
    w = 1.0 / (s * s + tau2)
    m = float(np.sum(w * x) / np.sum(w))
    return float(np.sum(w * (x - m) ** 2)), m, float(np.sum(w) ** -0.5)


def tau_interval(x, s, level: float = 0.68) -> tuple[float, float]:
    """The Q-profile interval of tau: the taus at which Q(tau) (weights 1 / (s^2 + tau^2))
    equals the chi^2(k - 1) quantiles (1 +- level) / 2; 0 where Q(0) is already below."""
    from scipy.optimize import brentq
    from scipy.stats import chi2
    x, s = np.asarray(x, float), np.asarray(s, float)
    k = len(x)
    out = []
    for q in (chi2.ppf((1 + level) / 2, k - 1), chi2.ppf((1 - level) / 2, k - 1)):
        if _q(x, s, 0.0)[0] <= q:
            out.append(0.0)
            continue
        hi = float(np.ptp(x)) ** 2 * 1e4 + 1e-30
        out.append(math.sqrt(brentq(lambda t2: _q(x, s, t2)[0] - q, 0.0, hi)))
    return out[0], out[1]


def between_realisation_floor(values, errors) -> dict:
    """tau (module doc) from realisations `values` +- `errors` of one setting, with Q, its dof,
    the 68 % interval of tau, the weighted mean with and without tau, and each value's
    error with the floor."""
    x, s = np.asarray(values, float), np.asarray(errors, float)
    k = len(x)
    if k < 2 or x.shape != s.shape or np.any(~np.isfinite(x)) or np.any(~(s > 0)):
        raise ValueError(f"{k} values with errors {list(s)}: need at least 2 finite values with errors > 0")
    w = 1.0 / s ** 2
    Q, mean, mean_err = _q(x, s, 0.0)
    tau2 = max(0.0, (Q - (k - 1)) / (float(np.sum(w)) - float(np.sum(w * w) / np.sum(w))))
    _, mean_tau, mean_err_tau = _q(x, s, tau2)
    lo, hi = tau_interval(x, s)
    floor = math.sqrt(tau2) if k >= MIN_K_MOMENT else hi
    return {"k": k, "Q": Q, "dof": k - 1, "tau": math.sqrt(tau2), "tau_interval_68": [lo, hi],
            "floor": floor, "floor_rule": (f"tau (k >= {MIN_K_MOMENT})" if k >= MIN_K_MOMENT else
                                           f"the upper end of tau's 68 % interval (k < {MIN_K_MOMENT})"),
            "mean": mean, "mean_err": mean_err, "mean_with_floor": mean_tau, "mean_err_with_floor": mean_err_tau,
            "errors_with_floor": [float(math.hypot(e, floor)) for e in s],
            "sample_sd": float(np.std(x, ddof=1))}
