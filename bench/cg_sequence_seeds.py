"""The sequence-rod coarse-graining loop over independent seeds: are the per-step mean shape's
stated errors right, and is the shape unbiased, at a given Langevin step?

The loop of tests/python/test_coarsegrain_thermal_sequence_rod.py (42-bp Olson 1998 rod, 2
points per bp, friction 0.05, 16000 rod times, 4001 frames, keep_closure = false, then
`dnarod coarse-grain --discard 0 --m-max 2 --bootstrap 100`) for each seed, and then:

* per seed, chi^2 / 41 per parameter of the mean step parameters against the stationary
  truth with the six holonomy directions fitted out (mdbridge/rod/material/thermal_steps.py),
  and the same with each parameter's k = 0 and k = turns modes fitted out instead (the
  former check); the largest |z| of the 21 K(q -> 0) elements against the series average;
* over seeds, after the holonomy fit: the scatter of the per-step means / their stated
  error, and chi^2 / 41 of the seed-mean residual with errors err / sqrt(n) (a systematic
  bias makes it >> 1);
* the same on the grid strains themselves (the time-mean of x_i - x0_i less its least-energy
  holonomy part): t^2 of the seed-mean per strain component, expected (n - 1) / (n - 3).

    /usr/bin/python3 bench/cg_sequence_seeds.py --seeds 31-40 --dt 0.025 --work /tmp/cgseq
    [--samples 40000] [--out bench/results]

Runs already in --work (thermal<seed>_dt<dt>.h5 and cg<seed>_dt<dt>/params.json) are reused.
"""
from __future__ import annotations

import argparse
import json
import subprocess
import time
from pathlib import Path

import h5py
import numpy as np

HERE = Path(__file__).resolve().parent
N_BP = 42


def seeds_of(text):
    out = []
    for part in text.split(","):
        a, _, b = part.partition("-")
        out += list(range(int(a), int(b or a) + 1))
    return out


def make_rod(work):
    from dnarod.cli import main
    from mdbridge.rod.material.gridfile import write_initial_file
    rod = work / "rod"
    if not (rod / "material.h5").exists():
        assert main(["dna-rod", "--random", str(N_BP), "--seed", "1", "--params", "olson1998",
                     "--points-per-bp", "2", "--shape", "exact", "-o", str(rod)]) == 0
    with h5py.File(rod / "material.h5", "r") as f:
        material = {k: np.asarray(f[k]) for k in ("K", "Gamma0", "Omega0")}
        sequence = str(f.attrs["sequence"])
    rest = json.loads((rod / "rest.json").read_text())
    write_initial_file(rod / "intrinsic.h5", np.arange(rest["points"]) * rest["length"] / rest["points"],
                       material["Gamma0"], material["Omega0"])
    return rod, material, sequence, rest["length"], rest["points"]


def scene_text(L, N, dt, seed, temperature_K) -> str:
    """The thermal scene of the loop: the rod of make_rod from its intrinsic (rest) strains,
    Langevin at step dt, unboxed (keep_closure = false), 4001 frames over 16000 rod times."""
    return f"""[rod]
length = {L!r}
points = {N}

[material]
material_file = "material.h5"

[initial]
kind = "file"
path = "intrinsic.h5"

[solver]
space = "spectral"
time = "langevin"
dt = {dt!r}

[output]
t_end = 16000.0
frames = 4001
fields = ["centerline", "directors", "internal"]

[thermal]
temperature_K = {temperature_K!r}
seed = {seed}
keep_closure = false
friction_translational = 0.05
friction_rotational = 0.05
"""


def run_seed(work, rod, L, N, seed, dt, rodsim):
    from dnarod.cli import main
    from mdbridge.rod.material.parameter_sets import olson1998_table
    tag = f"{seed}_dt{dt:g}"
    h5, cg = work / f"thermal{tag}.h5", work / f"cg{tag}"
    if h5.exists() and (cg / "params.json").exists():
        return h5, cg, None
    toml = rod / f"thermal{tag}.toml"
    toml.write_text(scene_text(L, N, dt, seed, olson1998_table()["temperature_K"]))
    t0 = time.time()
    subprocess.run([str(rodsim), "run", str(toml), "-o", str(h5)], check=True, capture_output=True)
    wall = time.time() - t0
    assert main(["coarse-grain", str(h5), "-o", str(cg), "--discard", "0", "--m-max", "2", "--bootstrap", "100"]) == 0
    return h5, cg, wall


def closure_modes_out(dev, err, turns=4):
    """dev / err less each parameter's least-squares k = 0 and k = turns parts (the former check)."""
    j = np.arange(len(dev))
    A = np.stack([np.ones(len(j)), np.cos(2 * np.pi * turns * j / N_BP), np.sin(2 * np.pi * turns * j / N_BP)], axis=1)
    y = dev / err
    return y - A @ np.linalg.lstsq(A, y, rcond=None)[0]


def main(argv=None):
    import os
    from mdbridge.rod.material.closed_rest import holonomy_jacobian
    from mdbridge.rod.material.parameter_sets import dimers, olson1998_table
    from mdbridge.rod.material.thermal_steps import (holonomy_directions, off_holonomy, rest_strains,
                                                     stationary_step_means)
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", default="31-40")
    ap.add_argument("--dt", type=float, default=0.025)
    ap.add_argument("--work", required=True)
    ap.add_argument("--samples", type=int, default=40000, help="Monte Carlo samples of the truth")
    ap.add_argument("--out", default=str(HERE / "results"))
    args = ap.parse_args(argv)
    work = Path(args.work)
    work.mkdir(parents=True, exist_ok=True)
    rodsim = Path(os.environ.get("DNAROD_BUILD", HERE.parent / "build")) / "bin" / "rodsim"
    rod, material, sequence, L, N = make_rod(work)
    seeds = seeds_of(args.seeds)
    runs = [run_seed(work, rod, L, N, s, args.dt, rodsim) for s in seeds]
    with h5py.File(runs[0][0], "r") as f:
        kT = float(f.attrs["kT"])
    truth, mc_err = stationary_step_means(material, L, kT, N_BP, samples=args.samples, seed=99)
    truth, mc_err = truth[:-1], mc_err[:-1]
    G = holonomy_directions(material, L, N_BP)[:, :-1]
    F = np.array([olson1998_table()["steps"][xy][1] for xy in dimers(sequence, closed=True)])[:-1]
    series = np.linalg.inv(np.mean(np.linalg.inv(F), axis=0))
    iu = np.triu_indices(6)
    # grid strains: the least-energy holonomy directions and their K-metric projection
    x0 = rest_strains(material)
    K = material["K"]
    _, _, dzeta = holonomy_jacobian(x0, L, 8)
    D = np.einsum("gij,kgj->kgi", np.linalg.inv(K), dzeta.reshape(6, N, 6))
    gram = np.einsum("kgi,gij,lgj->kl", D, K, D)
    per_seed, resid, errs, grid = [], [], [], []
    for s, (h5, cg, wall) in zip(seeds, runs):
        p = json.loads((cg / "params.json").read_text())
        st = [x for x in p["steps"] if not x["excluded"]]
        mean = np.array([x["mean"] for x in st])
        err = np.hypot(np.array([x["mean_err"] for x in st]), mc_err)
        r = off_holonomy(mean - truth, err, G)
        Kq = np.array(p["average"]["stiffness"])
        z = ((Kq - series) / np.array(p["average"]["stiffness_err"]))[iu]
        per_seed.append({"seed": s, "chi2_per_41_holonomy": (r ** 2).mean(axis=0).tolist(),
                         "chi2_per_41_closure_modes": (closure_modes_out(mean - truth, err) ** 2).mean(axis=0).tolist(),
                         "K_q0_max_abs_z": float(np.abs(z).max()), "rodsim_wall_s": wall})
        resid.append(r * err)
        errs.append(err)
        with h5py.File(h5, "r") as f:
            x = np.concatenate([f["fields/Gamma"][:], f["fields/Omega"][:]], axis=-1).mean(axis=0) - x0
        lam = np.linalg.solve(gram, np.einsum("kgi,gij,gj->k", D, K, x))
        grid.append(x - np.einsum("k,kgi->gi", lam, D))
    resid, errs, grid = np.array(resid), np.array(errs), np.array(grid)
    n = len(seeds)
    t2 = (grid.mean(axis=0) / (grid.std(axis=0, ddof=1) / np.sqrt(n))) ** 2
    chi = np.array([r["chi2_per_41_holonomy"] for r in per_seed])
    out = {"what": "Sequence-rod coarse-graining loop over seeds: per-step mean shape against the stationary truth "
                   "given each run's holonomy (bench/cg_sequence_seeds.py)",
           "dt": args.dt, "seeds": seeds, "truth_samples": args.samples,
           "parameters": ["shift", "slide", "rise", "tilt", "roll", "twist"],
           "per_seed": per_seed,
           "chi2_per_41_holonomy_mean": chi.mean(axis=0).tolist(), "chi2_per_41_holonomy_max": float(chi.max()),
           "scatter_over_stated_error":
               np.sqrt((resid.var(axis=0, ddof=1) / (errs ** 2).mean(axis=0)).mean(axis=0)).tolist(),
           "seed_mean_chi2_per_41": ((resid.mean(axis=0) ** 2) / ((errs ** 2).mean(axis=0) / n)).mean(axis=0).tolist(),
           "grid_seed_mean_t2": t2.mean(axis=0).tolist(), "grid_t2_expected": (n - 1) / (n - 3)}
    name = Path(args.out) / f"cg_sequence_seeds_dt{args.dt:g}.json"
    name.write_text(json.dumps(out, indent=1) + "\n")
    print(json.dumps({k: v for k, v in out.items() if k != "per_seed"}, indent=1))
    print("wrote", name)


if __name__ == "__main__":
    main()
