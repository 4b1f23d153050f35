"""Calibration of the coarse-graining's moving-block bootstrap against its block length.

The realisation test (tests/python/test_coarsegrain_synthetic.py) found the stated errors
~12-14 % small at b = 6 tau_int. This measures, on the same ensembles (Olson 1998's
coupled Gaussian of 3 steps, AR(1) with phi = 0.9, tau_int = 9.5 frames, 2000 frames, 24
independent realisations, means and K diagonals: 36 elements), the median over elements
of scatter-over-realisations / rms stated error for several block lengths b (in units of
tau_int; b is capped at T / 8 by the estimator, 26 tau here), and the same for the
moving-block variance's leading bias, 2 sum_k k rho(k) / (b 2 tau_int) for the mean
of an AR(1) series (Kuensch 1989; Lahiri 2003 Sec 3.2), as the expectation.

    /usr/bin/python3 bench/cg_block_length.py [--out bench/results]
"""
from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import numpy as np


def realisation(seed, phi, T, block, mean, K):
    from mdbridge.coarsegrain import CoarseGrain, StepEnsemble
    from mdbridge.coarsegrain.synthetic import ar1_steps
    rng = np.random.default_rng(seed)
    q = ar1_steps(mean, K, T, phi, rng)
    cg = CoarseGrain(StepEnsemble(q, "ACGT"), 300.0, m_values=[1], n_boot=100, seed=seed, block=block,
                     discard=0).run()
    b = cg.results["by_m"][1]
    est = np.concatenate([b["mean"].ravel(), np.diagonal(b["K"], axis1=1, axis2=2).ravel()])
    err = np.concatenate([b["mean_err"].ravel(), np.diagonal(b["K_err"], axis1=1, axis2=2).ravel()])
    return est, err, cg.results["tau_int_max_frames"]


def main(argv=None):
    from mdbridge.rod.material.parameter_sets import step_material
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(Path(__file__).resolve().parent / "results"))
    ap.add_argument("--realisations", type=int, default=24)
    a = ap.parse_args(argv)
    sm = step_material("ACGT", "olson1998", closed=False)
    mean, K = sm.step_params, sm.stiffness
    phi, T = 0.9, 2000
    tau = (1 + phi) / (2 * (1 - phi))
    sum_k_rho = phi / (1 - phi) ** 2
    rows = []
    t0 = time.process_time()
    for b_tau in (2, 4, 6, 8, 12, 16, 26):
        b = int(np.ceil(b_tau * tau))
        runs = [realisation(s, phi, T, b, mean, K) for s in range(a.realisations)]
        est = np.array([r[0] for r in runs])
        err = np.array([r[1] for r in runs])
        ratio = est.std(axis=0, ddof=1) / np.sqrt((err ** 2).mean(axis=0))
        bias = 2 * sum_k_rho / (b * 2 * tau)
        rows.append({"block_tau": b_tau, "block_frames": b, "median_ratio": float(np.median(ratio)),
                     "median_ratio_means": float(np.median(ratio[:12])),
                     "median_ratio_K": float(np.median(ratio[12:])),
                     "min_ratio": float(ratio.min()), "max_ratio": float(ratio.max()),
                     "expected_ratio_from_leading_bias_of_the_mean": float(1 / np.sqrt(max(1 - bias, 1e-9)))})
        print(json.dumps(rows[-1]))
    out = {"what": __doc__.splitlines()[0], "phi": phi, "frames": T, "tau_int_frames": tau,
           "realisations": a.realisations, "elements": 36, "rows": rows,
           "cpu_s": time.process_time() - t0}
    p = Path(a.out) / "cg_block_length.json"
    p.write_text(json.dumps(out, indent=1) + "\n")
    print(f"wrote {p}")


if __name__ == "__main__":
    main()
