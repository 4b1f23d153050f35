"""Section 5.1's accuracy claims, measured on the exact twisted wave of Eq (24) (Fig 3's
parameters), whose fields return to their initial values after one period 2 pi / omega:

- "reducing the time step by a factor of two increases accuracy by a factor of 2^4":
  classic RK4 at fixed dt = T/40, T/80, T/160 (spectral in s, N = 32), error after one
  period against the exact fields;
- "the energy does not vary from its initial value by more than 1e-13": relative drift of
  the energy (Appendix A) over the run, DOP853 at rtol = atol = 1e-13 and RK4 at T/160;
- "the magnitude of each director differs from unity by less than 1e-13": max | |d_k| - 1 |
  over the reconstructed directors of every frame.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from dnarod.paper import theory
from dnarod.paper.common import write_json
from mdbridge.rod.run import run_scene
from mdbridge.rod.scene import new_scene, straight_rod

K, A, O3, G3 = 2.0, 0.5, 1.0, 1.0


def _wave_scene(t_end, frames, time="dop853", rtol=1e-11, dt=None, fields=("internal", "energy")):
    sc = new_scene(straight_rod(2 * np.pi / K, 32, G3, O3),
               {"kind": "twisted_wave", "mode": 1, "A": A, "kappa": "p", "branch": "plus"},
               t_end=t_end, frames=frames, fields=fields, rtol=rtol)
    sc["solver"]["time"] = time
    if dt is not None:
        sc["solver"]["dt"] = dt
    return sc


def _period_error(run):
    return max(float(np.max(np.abs(run.fields[f][-1] - run.fields[f][0]))) for f in run.fields)


def check(outdir: Path | None = None, quick: bool = False) -> dict:
    w = float(theory.omega(K + O3, "plus"))
    T = 2 * np.pi / w
    rk4 = []
    for n in (40, 80, 160):
        run = run_scene(_wave_scene(T, 2, time="rk4", dt=T / n))
        assert run.energy is not None
        rk4.append({"dt": T / n, "error_after_one_period": _period_error(run),
                    "relative_energy_drift": float(np.max(np.abs(run.energy - run.energy[0])) / run.energy[0])})
    ratios = [rk4[i]["error_after_one_period"] / rk4[i + 1]["error_after_one_period"] for i in range(2)]
    periods = 2 if quick else 20
    tight = run_scene(_wave_scene(periods * T, 21, rtol=1e-13,
                                  fields=("internal", "energy", "centerline", "directors")))
    assert tight.energy is not None and tight.directors is not None
    norms = np.linalg.norm(tight.directors, axis=2)   # (T, N, 3): |d_k| per point
    data = {"check": "Sec 5.1 accuracy claims on the exact twisted wave", "period": T,
            "rk4_fixed_step": rk4, "rk4_error_ratio_when_halving_dt": ratios, "paper_ratio": 16,
            "dop853_rtol_1e-13": {"periods": periods,
                                  "relative_energy_drift": float(np.max(np.abs(tight.energy - tight.energy[0]))
                                                                 / tight.energy[0]),
                                  "max_field_error_after_last_period": _period_error(tight),
                                  "max_director_norm_error": float(np.max(np.abs(norms - 1.0)))},
            "paper_energy_claim": 1e-13, "paper_director_claim": 1e-13}
    if outdir is not None:
        write_json(outdir / "validation.json", data)
    return data
