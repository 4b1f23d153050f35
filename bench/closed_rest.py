"""The closed, pre-stressed rest state (mdbridge/rod/material/closed_rest.py): CPU time
and residuals of the method on this branch against the method before it (commit
486c5bb: statics in numpy, finite-difference closure Jacobian, shooting one
parameter set at a time), side by side, for random sequences (seed 1) under
Olson 1998 at one point per base pair, spectral operator. The old method runs
only at the sizes given by --old-sizes (at 158 bp it did not finish in 9 CPU
minutes). CPU time is process time (the machine is shared: wall time is not
the cost). Writes results/closed_rest.json (rows of sizes not run are kept).

  nice -n 15 python bench/closed_rest.py [--sizes 21 40 80 158] [--old-sizes 21 40]
"""
import argparse
import importlib.util
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

OLD_COMMIT = "486c5bb"
ROOT = Path(__file__).resolve().parents[1]


def old_module():
    src = subprocess.run(["git", "-C", str(ROOT), "show", f"{OLD_COMMIT}:mdbridge/rod/material/closed_rest.py"],
                         capture_output=True, text=True, check=True).stdout
    path = Path(tempfile.mkdtemp()) / "closed_rest_old.py"
    path.write_text(src)
    spec = importlib.util.spec_from_file_location("mdbridge.rod.material.closed_rest_old", path)
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod
    spec.loader.exec_module(mod)
    return mod


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sizes", type=int, nargs="+", default=[21, 40, 80, 158])
    ap.add_argument("--old-sizes", type=int, nargs="*", default=[21, 40])
    ap.add_argument("--out", type=Path, default=Path(__file__).parent / "results")
    a = ap.parse_args()
    from dna_models.sequence import random_sequence
    from mdbridge.rod.material import closed_rest as new
    from mdbridge.rod.material.parameter_sets import olson1998_steps
    from mdbridge.rod.material.steps_to_rod import grid_material, rod_material
    old = old_module() if a.old_sizes else None
    rows = []
    for n in sorted(set(a.sizes) | set(a.old_sizes)):
        rm = rod_material(olson1998_steps(random_sequence(n, seed=1)))
        g = grid_material(rm, n)
        L = rm.length
        for method in ("new", "old"):
            if (method == "new" and n not in a.sizes) or (method == "old" and n not in a.old_sizes):
                continue
            t0 = time.process_time()
            if method == "new":
                r = new.closed_rest_state(g, L, mode="closed")
            else:
                r = old.closed_rest_state(g, L, closure_weight=1e3)
            cpu = time.process_time() - t0
            T, M = new.tension_torque_physical(r)
            # both judged by the same yardstick: rodcore's RHS at zero velocity
            res = float(abs(new.SolverStatics(g, L).residual(new.np.concatenate([r.Gamma, r.Omega], 1))).max())
            row = {"n_bp": n, "method": method, "cpu_s": round(cpu, 2), "statics_residual": res,
                   "closure_rotation_rad": r.closure_rotation_rad, "closure_length_error": r.closure_length_error,
                   "tension_pN": round(T, 3), "torque_pN_nm": round(M, 3)}
            rows.append(row)
            print(json.dumps(row), flush=True)
    # rows of sizes not run now are kept from the previous file (each row says what it measured)
    a.out.mkdir(parents=True, exist_ok=True)
    f = a.out / "closed_rest.json"
    done = {(r["n_bp"], r["method"]) for r in rows}
    kept = [r for r in json.loads(f.read_text())["rows"] if (r["n_bp"], r["method"]) not in done] if f.exists() else []
    rows = sorted(kept + rows, key=lambda r: (r["n_bp"], r["method"]))
    f.write_text(json.dumps({"rows": rows, "old_commit": OLD_COMMIT}, indent=1))


if __name__ == "__main__":
    main()
