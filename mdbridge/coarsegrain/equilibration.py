"""Where the equilibrium part of a trajectory starts, and how long it must be.

Rule (Chodera 2016 J Chem Theory Comput 12:1799, "automated equilibration
detection"): for candidate starts t0 on a grid of T/40 frames (or a given spacing) up to T/2, the
frames after t0 are worth N_eff(t0) = (T - t0) / (2 tau_int(t0)) independent
samples; the equilibration stretch is the t0 that maximises N_eff. Discarding too
little keeps the drift, which inflates tau_int; discarding too much throws samples
away. It is applied to the six sequence-averaged step parameters per frame (the
slowest, most collective signals of a drift) and the latest t0 of the six is used. The
intact MD's discard applies it to its slow observables (workflows/steps/intact.py).
"""
from __future__ import annotations

import numpy as np

from mdbridge.stats import integrated_time

GRID = 40


def equilibration_start(x: np.ndarray, step: int | None = None) -> tuple[int, np.ndarray]:
    """(t0, N_eff at t0 per series) for series x (T, k) or (T,), candidates every STEP frames
    (default T / GRID): the frames [t0, T) form the equilibrium ensemble."""
    x = np.asarray(x, dtype=float)
    if x.ndim == 1:
        x = x[:, None]
    T = x.shape[0]
    step = max(1, T // GRID) if step is None else int(step)
    cands = np.arange(0, T // 2 + 1, step)
    neff = np.array([(T - t0) / (2.0 * integrated_time(x[t0:])) for t0 in cands])  # (n_cand, k)
    best = np.argmax(neff, axis=0)
    k = int(np.argmax(cands[best]))
    t0 = int(cands[best[k]])
    return t0, neff[best[k]]
