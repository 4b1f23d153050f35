"""Errors of correlated series: the one home of every estimator the toolkit uses for the
error of a mean (or of a fit) from frames that are not independent.

* Blocking (Flyvbjerg & Petersen 1989): `block_sem` (first plateau of the halving curve)
  and `sem_longest_blocks` (the longest blocks that leave 8).
"""
from __future__ import annotations

import math

import numpy as np


def block_sem(x) -> dict:
    """Standard error of the mean of a correlated series by blocking: the series is halved
    into block means repeatedly; the naive SEM of the block means rises with the block length
    until the blocks are longer than the correlation time and then levels off. The value
    returned is at the first level whose SEM is not exceeded by the next level's by more
    than the next level's own statistical error (sem / sqrt(2 (n_blocks - 1))); levels with
    fewer than 8 blocks are not used, and if no plateau is reached before that the largest
    SEM is returned with plateau = False."""
    x = np.asarray(x, float)
    x = x[np.isfinite(x)]
    n0 = len(x)
    if n0 < 16:
        return {"mean": float(np.mean(x)) if n0 else float("nan"), "sem": float("nan"),
                "n": n0, "reason": f"{n0} samples; block averaging needs at least 16"}
    levels = []
    y = x.copy()
    while len(y) >= 8:
        nb = len(y)
        sem = float(np.std(y, ddof=1) / math.sqrt(nb))
        levels.append((nb, sem, sem / math.sqrt(2 * (nb - 1))))
        y = 0.5 * (y[: 2 * (nb // 2)][0::2] + y[: 2 * (nb // 2)][1::2])
    pick, plateau = None, False
    for i in range(len(levels) - 1):
        if levels[i + 1][1] - levels[i][1] <= levels[i + 1][2]:
            pick, plateau = i, True
            break
    if pick is None:
        pick = int(np.argmax([s for _, s, _ in levels]))
    nb, sem, sem_err = levels[pick]
    return {"mean": float(np.mean(x)), "sem": sem, "sem_err": sem_err, "n": n0,
            "block_length": n0 // nb, "plateau": plateau,
            "naive_sem": levels[0][1]}


def sem_longest_blocks(y, min_blocks: int = 8) -> float:
    """Standard error of the mean from the means of the longest blocks that still leave
    MIN_BLOCKS of them (halving the series, as `block_sem` does)."""
    y = np.asarray(y, float)
    sem = float("nan")
    while len(y) >= min_blocks:
        sem = float(np.std(y, ddof=1) / np.sqrt(len(y)))
        y = 0.5 * (y[: 2 * (len(y) // 2)][0::2] + y[: 2 * (len(y) // 2)][1::2])
    return sem
