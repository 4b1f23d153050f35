"""Planarity of the transverse motion.

Given the transverse displacement in a fixed reference plane, u_in (T, n), and out of
it, u_out (T, n):
  - in_rms(t), out_rms(t): RMS over s of each component;
  - ratio(t) = out_rms / in_rms;
  - angle_deg(t): angle of the best-fit plane through the axis at time t, measured
    from the reference plane, from the SVD of the (n x 2) matrix [u_in, u_out]: its
    leading right singular vector is the direction of largest displacement;
  - svd_ratio(t) = s2 / s1: how far that frame is from any plane (0: planar);
  - planarity = RMS(u_out) / RMS(u_in) over the whole run: 0 for motion that stays
    in the reference plane, tan(alpha) for motion in a plane tilted by alpha.
"""
from __future__ import annotations

import numpy as np


def planarity(u_in: np.ndarray, u_out: np.ndarray) -> dict:
    u_in, u_out = np.asarray(u_in, float), np.asarray(u_out, float)
    in_rms = np.sqrt(np.mean(u_in ** 2, axis=1))
    out_rms = np.sqrt(np.mean(u_out ** 2, axis=1))
    angle = np.empty(len(u_in))
    svd_ratio = np.empty(len(u_in))
    for t in range(len(u_in)):
        M = np.column_stack([u_in[t], u_out[t]])
        _, sv, Vt = np.linalg.svd(M, full_matrices=False)
        v = Vt[0] * (1 if Vt[0, 0] >= 0 else -1)  # a plane has no sign: fold into (-90, 90]
        angle[t] = np.degrees(np.arctan2(v[1], v[0]))
        svd_ratio[t] = sv[1] / sv[0] if sv[0] > 0 else np.nan
    total_in = np.sqrt(np.mean(u_in ** 2))
    # overall best-fit plane of the whole run
    _, _, Vt = np.linalg.svd(np.column_stack([u_in.ravel(), u_out.ravel()]), full_matrices=False)
    v = Vt[0] * (1 if Vt[0, 0] >= 0 else -1)
    with np.errstate(invalid="ignore", divide="ignore"):
        return {"in_rms_A": in_rms, "out_rms_A": out_rms, "ratio": out_rms / in_rms,
                "angle_deg": angle, "svd_ratio": svd_ratio,
                # no in-plane motion (a rod at rest): planarity is undefined, not 0
                "planarity": float(np.sqrt(np.mean(u_out ** 2)) / total_in) if total_in > 1e-9 else float("nan"),
                "plane_angle_deg": float(np.degrees(np.arctan2(v[1], v[0])))}
