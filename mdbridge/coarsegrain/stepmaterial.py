"""The coarse-graining as a per-step DNA file (format "dnarod-steps/1", engineer seq's
mdbridge.rod.material.stepfile) and, for a closed duplex, as the rod's grid material file
(mdbridge.rod.material.steps_to_rod + gridfile), so rodsim runs with the MD-derived
shape, stiffness, rho and I.

Excluded steps (an opened base pair) carry the average of the usable steps in the
file, because the rod needs a material everywhere; which steps they are is written
into the file's `source` and into params.json, never silently.
"""
from __future__ import annotations

import numpy as np


def available() -> bool:
    try:
        import mdbridge.rod.material.stepfile  # noqa: F401
        return True
    except ImportError:
        return False


def step_material(cg, extras, source: str):
    """StepMaterial of a finished CoarseGrain (m = 1 per-step results)."""
    from mdbridge.rod.material.stepfile import StepMaterial
    ens, b1 = cg.ens, cg.results["by_m"][1]
    n = ens.n_steps
    P = np.tile(b1["mean_avg"], (n, 1))
    Pe = np.tile(b1["mean_avg_err"], (n, 1))
    K = np.tile(b1["K_series"], (n, 1, 1))
    Ke = np.tile(b1["K_series_err"], (n, 1, 1))
    rows = b1["first_step"]
    P[rows], Pe[rows], K[rows], Ke[rows] = b1["mean"], b1["mean_err"], b1["K"], b1["K_err"]
    exc = np.flatnonzero(ens.excluded) + 1
    note = "" if not len(exc) else (f"; steps {', '.join(map(str, exc))} excluded (base pair opened): "
                                    "they carry the compliance average of the other steps")
    mi = extras["mass_inertia"]
    return StepMaterial(sequence=ens.sequence, closed=ens.closed, step_params=P, stiffness=K,
                        temperature_K=cg.results["temperature_K"], mass=np.asarray(mi["mass"], float),
                        inertia=np.asarray(mi["inertia"], float),
                        source=f"dnarod coarse-grain of {source}{note}",
                        step_params_err=Pe, stiffness_err=Ke)


def write_material_files(directory, cg, extras, source: str) -> dict:
    """Write DIR/steps.h5 (and DIR/material.h5 for a closed duplex); returns what was
    written or why not."""
    from pathlib import Path
    d = Path(directory)
    if not available():
        return {"steps_file": None, "material_file": None,
                "note": "mdbridge.rod.material (per-step file format) is not in this tree; "
                        "params.json carries the same numbers"}
    from mdbridge.rod.material.stepfile import write_steps
    sm = step_material(cg, extras, source)
    write_steps(d / "steps.h5", sm)
    from mdbridge.rod.material.steps_to_rod import strains_from_steps
    from dna_models.units import Units
    G0, O0 = strains_from_steps(sm.step_params, Units.paper().rise_A)
    out = {"steps_file": "steps.h5", "material_file": None,
           "Gamma0_star_steps": np.asarray(G0).tolist(), "Omega0_star_steps": np.asarray(O0).tolist(),
           "strains_note": "rod's intrinsic shape per step (paper's units, fiducial step = paper's rise), "
                           "mdbridge.rod.material.steps_to_rod.strains_from_steps"}
    if cg.ens.closed:
        from mdbridge.rod.material.gridfile import write_grid_material
        from mdbridge.rod.material.steps_to_rod import grid_material, rod_material
        g = grid_material(rod_material(sm))
        write_grid_material(d / "material.h5", g, source=sm.source)
        out["material_file"] = "material.h5"
        out["grid_points"] = int(len(g["rho"]))
    else:
        out["note"] = "linear duplex: the rod solver is periodic, so no grid material file"
    return out
