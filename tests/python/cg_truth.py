"""Independent truths for the coarse-graining tests: Olson et al. 1998's tables (copied
in tests/data/olson1998/) and z-score bookkeeping. Helpers only, no tests."""
from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
from scipy import stats

DATA = Path(__file__).resolve().parents[1] / "data"  # tests/data/README.md: sources, licences
# Olson's files order (tilt, roll, twist, shift, slide, rise); ours (shift, slide, rise, tilt, roll, twist)
TO_OURS = [3, 4, 5, 0, 1, 2]


def olson_tables():
    """{dimer: mean (6,)}, {dimer: F (6, 6) in kT/A^2, kT/(A deg), kT/deg^2}, both in our order."""
    means, F = {}, {}
    with open(DATA / "olson1998" / "olson1998_PplusDNA_step_means.csv") as f:
        for row in csv.DictReader(ln for ln in f if not ln.startswith("#")):
            means[row["step"]] = np.array([float(row[k]) for k in
                                           ("shift", "slide", "rise", "tilt", "roll", "twist")])
    with open(DATA / "olson1998" / "olson1998_force_constants_6x6.csv") as f:
        for row in csv.DictReader(ln for ln in f if not ln.startswith("#")):
            M = np.array([float(row[f"F{i}{j}"]) for i in range(6) for j in range(6)]).reshape(6, 6)
            F[row["step"]] = M[np.ix_(TO_OURS, TO_OURS)]
    return means, F


def per_step(sequence, closed=False):
    means, F = olson_tables()
    n = len(sequence) if closed else len(sequence) - 1
    dimers = [sequence[k] + sequence[(k + 1) % len(sequence)] for k in range(n)]
    return np.array([means[d] for d in dimers]), np.array([F[d] for d in dimers])


def allowed_beyond_3sigma(n_elements: int, confidence: float = 0.999) -> int:
    """Largest count of |z| > 3 a normal distribution gives with this confidence."""
    return int(stats.binom.ppf(confidence, n_elements, 2 * stats.norm.sf(3.0)))


def z_scores(est, err, truth):
    return (np.asarray(est) - np.asarray(truth)) / np.asarray(err)


UPPER = np.triu_indices(6)
