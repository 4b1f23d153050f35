"""Numbers read back from the workflow's result files, and their mean over seeds.

JSON writes NaN as null (mdbridge/jsonio.py), so a missing number reads as None: `number`
turns it, and anything that is not a number, into NaN.
"""
from __future__ import annotations

import math

import numpy as np


def number(x) -> float:
    """float(x); NaN for None or anything float() refuses."""
    try:
        return float("nan") if x is None else float(x)
    except (TypeError, ValueError):
        return float("nan")


def mean_over_seeds(values, errors) -> tuple[float, float]:
    """Mean over seeds; error = sqrt(fit errors^2 / n^2 summed + between-seed variance / n)."""
    v = np.array([number(x) for x in values])
    e = np.array([number(x) for x in errors])
    ok = np.isfinite(v)
    if not ok.any():
        return float("nan"), float("nan")
    v, e = v[ok], e[ok]
    n = len(v)
    between = np.var(v, ddof=1) / n if n > 1 else 0.0
    return float(v.mean()), float(math.sqrt(np.nansum(e ** 2) / n ** 2 + between))
