"""The coarse-grained rod's prediction with each mode's own storage stiffness, against an MD's
modes (docs/coarse-graining.md, "Compliance by timescale"; mdbridge/analysis/unrelaxed_prediction.py):

    python3 -m dnarod.steps.unrelaxed CG_DIR STEPS.npz... --modes MODES.json \
        --tension TENSION.json -o OUT.json

CG_DIR: a `dnarod coarse-grain` of a run's steps files STEPS.npz (its replicas.h5 gives the relaxed
K(q -> 0), the mean shape, mass and inertia; its params.json the frames it discarded).
MODES.json and TENSION.json: the MD whose modes are predicted, the coarse-grained one's own
or another seed's (the cross-validation). Per mode that MD resolves: the relaxed rod's
omega (its error from the coarse-graining's bootstrap replicas of K(q -> 0)), the
self-consistent unrelaxed one (its error from the replicas of J*), the MD's omega0, and z of
each against the MD with both errors; and the damping gamma that the loss part of J* gives
(mdbridge/analysis/unrelaxed_prediction.py) against the MD's fitted `damping_per_ps`.
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

from dna_models.errors import InputError, NumericalError
from mdbridge.jsonio import write_json


def predict_unrelaxed(cg_dir, steps_files, modes_json, tension_json, out, n_boot: int = 50) -> dict:
    """OUT.json (module doc)."""
    from mdbridge.analysis.dispersion_prediction import Duplex, frequencies, md_natural_frequency, z_score
    from mdbridge.analysis.unrelaxed_prediction import unrelaxed_mode
    from mdbridge.coarsegrain.cgrod import materials, read_replicas, with_stiffness
    from mdbridge.md.segments import read_steps
    from mdbridge.rod.linear import UniformMaterial
    cg_dir = Path(cg_dir)
    reps = read_replicas(cg_dir / "replicas.h5")
    params = json.loads((cg_dir / "params.json").read_text())
    central, replicas = materials(reps, None)
    T_K = float(reps["temperature_K"])
    r = read_steps(steps_files)
    q = r["q"][int(params["discarded_frames"]):]
    dt = float(np.median(np.diff(r["times_ps"])))
    keep = ~np.array([bool(s.get("excluded")) for s in params["steps"]])
    table = json.loads(Path(modes_json).read_text())
    tension = json.loads(Path(tension_json).read_text())
    T_pN = float(tension["tension_pN"])
    duplex = Duplex(int(table["n_bp"]), int(table["helical_repeat"]), T_K)
    if duplex.n_bp != len(r["sequence"]):
        raise InputError(f"{modes_json}: {duplex.n_bp} bp; the coarse-grained steps are of {len(r['sequence'])}")
    relaxed = frequencies(UniformMaterial.from_dict(central), duplex, T_pN)
    relaxed_reps = []
    for m in replicas:
        try:
            relaxed_reps.append(frequencies(UniformMaterial.from_dict(m), duplex, T_pN))
        except (InputError, NumericalError):   # a replica whose linear rod has no real modes
            pass

    def relaxed_err(kind, n):
        w = [f[kind][n][0] for f in relaxed_reps if n in f[kind]]
        return float(np.std(w, ddof=1)) if len(w) >= 10 else None

    def material_of(F):
        return UniformMaterial.from_dict(with_stiffness(reps, F))

    rows = []
    for e in table["modes"]:
        kind, n = e["kind"], int(e["n"])
        md, md_err = md_natural_frequency(e)
        if md is None or n not in relaxed[kind]:
            continue
        w_rel, w_rel_err = relaxed[kind][n][0], relaxed_err(kind, n)
        row: dict = {"kind": kind, "n": n, "md_omega0_per_ps": md, "md_omega0_err_per_ps": md_err,
                     "md_gamma_per_ps": e.get("damping_per_ps"), "md_gamma_err_per_ps": e.get("damping_err_per_ps"),
                     "relaxed_omega_per_ps": w_rel, "relaxed_omega_err_per_ps": w_rel_err,
                     "z_relaxed": z_score(md, md_err, w_rel, w_rel_err)}
        try:
            res = unrelaxed_mode(kind, n, q, keep, True, dt, material_of,
                                 lambda mat, kind=kind, n=n: frequencies(mat, duplex, T_pN, n_max=n)[kind][n][0],
                                 w_rel, n_boot=n_boot)
        except (InputError, NumericalError) as err:   # K'(omega) of a finite record need not be a stable rod
            rows.append({**row, "unrelaxed_omega_per_ps": None, "reason": str(err)})
            continue
        rows.append({**row, "unrelaxed_omega_per_ps": res["omega_per_ps"],
                     "unrelaxed_omega_err_per_ps": res["omega_err_per_ps"],
                     "z_unrelaxed": z_score(md, md_err, res["omega_per_ps"], res["omega_err_per_ps"]),
                     "gamma_per_ps": res["gamma_per_ps"], "gamma_err_per_ps": res["gamma_err_per_ps"],
                     "z_gamma": z_score(row["md_gamma_per_ps"], row["md_gamma_err_per_ps"], res["gamma_per_ps"],
                                        res["gamma_err_per_ps"]),
                     "converged": res["converged"], "iterations": res["iterations"],
                     "left_out_wavenumber": res["left_out_wavenumber"], "max_lag_frames": res["max_lag_frames"]})
    rec = {"cg": str(cg_dir), "steps": [str(f) for f in steps_files], "modes": str(modes_json),
           "tension": {"tension_pN": T_pN, "tension_err_pN": tension.get("tension_err_pN"),
                       "source": str(tension_json)},
           "frames": int(len(q)), "frame_ps": dt, "rows": rows,
           "definition": "per mode the MD resolves: the coarse-grained rod's omega with the relaxed K(q -> 0), and "
                         "with the storage stiffness Re J*(omega)^-1 at its own omega, self-consistent (mdbridge/"
                         "analysis/unrelaxed_prediction.py), each with its bootstrap error; the MD's omega0 (dnarod "
                         "modes); z with both errors; gamma, the amplitude decay rate the loss part of J* gives, "
                         "against the MD's damping_per_ps; the rod at the MD's virial tension, the coarse-graining's "
                         "mean shape, mass and inertia",
           "stiffness": {"relaxed": "K(q -> 0) of the whole record (replicas.h5)",
                         "unrelaxed": "Re J*(omega_n)^-1 of the q -> 0 coordinates at each mode's own omega"}}
    write_json(out, rec)
    return rec


def main(argv=None) -> int:
    from dnarod.steps.analyse import run_step
    ap = argparse.ArgumentParser(prog="python3 -m dnarod.steps.unrelaxed", description=__doc__.splitlines()[0])
    ap.add_argument("cg_dir")
    ap.add_argument("steps", nargs="+")
    ap.add_argument("--modes", required=True)
    ap.add_argument("--tension", required=True)
    ap.add_argument("-o", "--output", required=True)
    ap.add_argument("--bootstrap", type=int, default=50)
    a = ap.parse_args(argv)
    return run_step("unrelaxed", lambda: predict_unrelaxed(a.cg_dir, a.steps, a.modes, a.tension,
                                                          a.output, a.bootstrap))


if __name__ == "__main__":
    sys.exit(main())
