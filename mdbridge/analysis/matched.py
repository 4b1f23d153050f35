"""Quantities that match a rod run to an MD run: amplitude of the fundamental, mean axial
strain, axial tension, and the regime label they imply.

* Strain (rod and MD, the same code): the sum of the 3DNA-like rises of the n steps around
  the ring, over n times the rod's fiducial rise, minus 1. The rise of step i is the
  step vector o_{i+1} - o_i projected on the mid-step z axis (z_i + z_{i+1}, normalised);
  the closing step uses o_0 + P. This is the contour (local) stretch; the end-to-end
  strain |P| / (n rise) - 1 is fixed by the MD box and reported beside it.
* Tension, MD: F = -<P_yy> A_xz, with P_yy the pressure-tensor component along the helix
  axis (the box axis along the period vector P; Y for `dnarod build-md`) and A_xz the box
  cross-section. Sign: F > 0 is tension (the duplex pulls the box's faces together: a
  negative axial pressure), F < 0 compression. In vacuum the kinetic part of P is the atoms'
  own, so -P_yy A is the mean force the molecule transmits across a plane normal to the
  axis. 1 bar over 100 nm^2 is 10 pN.
* Tension, rod: n3 = C3 (Gamma3 - 1) in physical units (C from `dna_models.units`).
* Standard errors of time means by blocking (Flyvbjerg & Petersen 1989): `mdbridge.stats.block_sem`.
* Regime (by the tension the kick adds above the A_v = 0 baseline): "linear" (below
  LINEAR_PN and well below the baseline) or "nonlinear elastic". No overstretching
  boundary is drawn (OVERSTRETCH_NOTE): the ~65-pN plateau is a torsionally free duplex's
  in water, a torsionally constrained one (a ligated ring is one) overstretches near 110 pN
  in experiment, and where vacuum CHARMM27 overstretches has not been measured.
"""
from __future__ import annotations

import math

import numpy as np

from dna_models.units import Units
from mdbridge.stats import block_sem, sem_longest_blocks

LINEAR_PN = 10.0
LINEAR_FRACTION_OF_BASELINE = 0.3
OVERSTRETCH_NOTE = ("no overstretching boundary: a torsionally constrained duplex (a ligated ring) "
                    "overstretches near 110 pN in water (experiment), and vacuum CHARMM27's "
                    "overstretching force is unmeasured")


def step_rises(origins, R, period) -> np.ndarray:
    """Rise of each of the n steps of a ring of base pairs (T, n) [A]; see module doc."""
    o = np.asarray(origins, float)
    z = np.asarray(R, float)[..., :, 2]
    P = np.asarray(period, float)
    nxt = np.concatenate([o[:, 1:], o[:, :1] + P[:, None, :]], axis=1)
    zn = np.concatenate([z[:, 1:], z[:, :1]], axis=1)
    zm = z + zn
    zm /= np.linalg.norm(zm, axis=-1, keepdims=True)
    return np.einsum("tix,tix->ti", nxt - o, zm)


def axial_strain(traj, rise_fiducial_A: float) -> dict:
    """Contour strain (sum of rises) and end-to-end strain of a BasePairTrajectory over time."""
    n = traj.n_bp
    contour = step_rises(traj.origins, traj.R, traj.period).sum(axis=1) / (n * rise_fiducial_A) - 1
    e2e = np.linalg.norm(traj.period, axis=1) / (n * rise_fiducial_A) - 1
    b = block_sem(contour)
    return {"contour_strain_mean": b["mean"], "contour_strain_sem": b["sem"],
            "contour_strain_min": float(contour.min()), "contour_strain_max": float(contour.max()),
            "end_to_end_strain_mean": float(e2e.mean()), "rise_fiducial_A": rise_fiducial_A,
            "series": contour}


def rod_tension_pN(Gamma3, units: Units | None = None) -> np.ndarray:
    """n3 = C3 (Gamma3 - 1) [pN] (Gamma3 dimensionless, paper scaling C1 = 1)."""
    u = units or Units.paper()
    return u.C * u.C_star[2] * (np.asarray(Gamma3, float) - 1.0) * 1e12


def box_axis_and_area(period, box_lengths_A) -> tuple[int, float]:
    """Index of the box axis along the period vector and the cross-section [A^2]
    (orthorhombic box)."""
    P = np.asarray(period, float)
    ax = int(np.argmax(np.abs(P)))
    L = np.asarray(box_lengths_A, float)[:3]
    return ax, float(np.prod(np.delete(L, ax)))


def tension_summary(series_pN, times_ps=None) -> dict:
    # The larger of the first blocking plateau and the longest blocks: the MD tension is
    # white noise over a slow part, which gives the blocking curve a false early plateau
    # (validated on 21 bp: docs/md.md, "Tension: validation on 21 bp").
    b = block_sem(series_pN)
    long = sem_longest_blocks(series_pN)
    out = {"tension_pN": b["mean"], "tension_sem_pN": max(b["sem"], long), "tension_sem_method":
           "larger of blocking (Flyvbjerg-Petersen, first plateau) and the longest blocks leaving 8",
           "tension_sem_first_plateau_pN": b["sem"], "tension_sem_longest_blocks_pN": long,
           "tension_sem_plateau": b.get("plateau"),
           "tension_naive_sem_pN": b.get("naive_sem"), "n_samples": b["n"]}
    if "reason" in b:
        out["tension_sem_reason"] = b["reason"]
    return out


def regime(added_pN: float, baseline_pN: float | None = None, err_pN: float | None = None) -> dict:
    """The regime label of a run from the tension its kick adds above the baseline; with its
    standard error err_pN, a label the error could change (the interval +-2 err straddles a
    boundary) is reported as "not resolved" with the labels at both ends."""
    if added_pN is None or not math.isfinite(added_pN):
        return {"regime": "unknown", "reason": "no tension measured"}
    if err_pN is not None and math.isfinite(err_pN) and err_pN > 0:
        lo = regime(abs(added_pN) - 2 * err_pN if abs(added_pN) > 2 * err_pN else 0.0, baseline_pN)
        hi = regime(abs(added_pN) + 2 * err_pN, baseline_pN)
        out = regime(added_pN, baseline_pN)
        out["added_tension_err_pN"] = err_pN
        if lo["regime"] != hi["regime"]:
            out["regime"] = f"not resolved ({lo['regime']} .. {hi['regime']} within 2 standard errors)"
        return out
    a = abs(added_pN)
    base_ok = baseline_pN is not None and math.isfinite(baseline_pN)
    if a < LINEAR_PN and (baseline_pN is None or not base_ok
                          or a < LINEAR_FRACTION_OF_BASELINE * abs(baseline_pN)
                          or abs(baseline_pN) < LINEAR_PN):
        lab = "linear"
    else:
        lab = "nonlinear elastic"
    return {"regime": lab, "added_tension_pN": added_pN,
            "baseline_tension_pN": baseline_pN if base_ok else None,
            "rule": f"linear: added < {LINEAR_PN:g} pN and < {LINEAR_FRACTION_OF_BASELINE:g} x "
                    f"|baseline| (when the baseline exceeds {LINEAR_PN:g} pN); else nonlinear elastic; "
                    + OVERSTRETCH_NOTE
                    + ("" if base_ok else "; no A_v = 0 run: baseline taken as 0")}
