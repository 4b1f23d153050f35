#!/usr/bin/python3
"""Stability stress tests of rodsim (fixed-step RK4 and adaptive schemes).

1. CFL: the exact spectral radius lambda_max of the semi-discrete system
   linearised about the rest state (eigenvalues of the Jacobian of the
   independent numpy RHS, bench/baseline_numpy.py) gives the exact RK4
   stability boundary dt* = 2 sqrt(2) / lambda_max (RK4's stability region
   meets the imaginary axis at +-2 sqrt 2; the rest-state spectrum is purely
   imaginary because both d/ds operators are skew). A dt sweep of rodsim
   (rest state + 1e-8 random noise, fixed-step RK4) finds the empirical
   boundary; rodsim must refuse, with a clear message, every dt it cannot run
   stably. Compared with the wave-speed estimate c kmax, c = max(sqrt C_i,
   sqrt(D_i / I_i)).
2. Folding: amplitude sweep of the untwisted wave until Gamma3 -> 0; rodsim
   must stop with its "folded" message (exit 3), never NaN.
3. Adversarial initial conditions: high-wavenumber noise and a discontinuous
   field, per operator, with and without dealiasing, adaptive DOP853: the
   outcome (completed / stopped, energy drift, steps) is recorded.
4. Long run: energy drift vs step count (1e6 steps at tight tolerance in the
   full run) for spectral + DOP853 on the DNA scene.

    stability.py --build BUILD --out bench/results [--quick]
"""
import argparse
import importlib.util
import json
import math
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import h5py
import numpy as np

from dna_models.units import Units
from mdbridge.rod.run import RodRun

HERE = Path(__file__).resolve().parent


def _bench_script(name):
    """bench/NAME.py as a module (bench/ is a folder of scripts, not a package)."""
    spec = importlib.util.spec_from_file_location(name, HERE.parent / f"{name}.py")
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


baseline_numpy = _bench_script("baseline_numpy")  # the independent RHS

FIELDS = ("gamma", "omega", "Gamma", "Omega")
_U = Units.paper()   # the paper's dimensionless material, from its one source (dna_models)
PAPER_MATERIAL = dict(C=_U.C_star, D=_U.D_star, I=_U.I_star)


def rest_state(N, Gamma0, Omega0):
    y = np.zeros((12, N))
    for c in range(3):
        y[6 + c] = Gamma0[c]
        y[9 + c] = Omega0[c]
    return y


def spectral_radius(N, L, Gamma0, Omega0, space, material=PAPER_MATERIAL):
    """(max |lambda|, max Re lambda) of the Jacobian of the semi-discrete RHS at rest.

    The RHS is quadratic in y, so a central difference with any step is exact
    up to round-off; step 1e-3 keeps round-off small."""
    rhs = baseline_numpy.make_rhs(N, L, material["C"], material["D"], material["I"], Gamma0, Omega0, space)
    y0 = rest_state(N, Gamma0, Omega0).ravel()
    n = y0.size
    J = np.empty((n, n))
    h = 1e-3
    for j in range(n):
        e = np.zeros(n)
        e[j] = h
        J[:, j] = (rhs(0.0, y0 + e) - rhs(0.0, y0 - e)) / (2 * h)
    lam = np.linalg.eigvals(J)
    return float(np.max(np.abs(lam))), float(np.max(lam.real))


def wave_speed(material=PAPER_MATERIAL):
    return max(max(math.sqrt(c) for c in material["C"]),
               max(math.sqrt(d / i) for d, i in zip(material["D"], material["I"])), 1.0)


def kmax(N, L, space):
    h = L / N
    if space == "fd4":
        c = 1.0 - math.sqrt(1.5)
        s = math.sqrt(1.0 - c * c)
        return (8.0 * s - 2.0 * s * c) / 6.0 / h
    return 2 * math.pi / L * (N // 2 - 1 if N % 2 == 0 else N // 2)


def write_scene(path, N, L, Gamma0, Omega0, initial_h5, solver, t_end, frames=2, fields=("internal",),
                checks=""):
    def vec(v):
        return "[" + ", ".join(repr(float(x)) for x in v) + "]"
    solver_lines = "\n".join(f"{k} = {json.dumps(v)}" for k, v in solver.items())
    path.write_text(f"""[rod]
length = {L!r}
points = {N}
Gamma0 = {vec(Gamma0)}
Omega0 = {vec(Omega0)}

[initial]
kind = "file"
path = "{initial_h5}"

[solver]
{solver_lines}

[output]
t_end = {t_end!r}
frames = {frames}
fields = {json.dumps(list(fields))}

[checks]
{checks}
""")


def write_initial(path, y, L):
    N = y.shape[1]
    with h5py.File(path, "w") as f:
        f["s"] = L * np.arange(N) / N
        for k, name in enumerate(FIELDS):
            f[f"fields/{name}"] = y[3 * k:3 * k + 3].T


def run(rodsim, scene, out, sets=()):
    cmd = [str(rodsim), "run", str(scene), "-o", str(out), "--quiet"]
    for s in sets:
        cmd += ["--set", s]
    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    res = dict(returncode=p.returncode, stderr=p.stderr.strip(), wall_s=wall)
    if Path(out).exists():
        r = RodRun.read(out)
        if "gamma" in r.fields and r.fields["gamma"].shape[0] > 0:
            res["y_last"] = np.concatenate([np.asarray(r.fields[n][-1]).T for n in FIELDS])
        if r.energy is not None:
            res["energy"] = np.asarray(r.energy)
            res["time"] = np.asarray(r.time)
        for k in ("steps", "energy_drift", "rhs_evaluations"):
            if k in r.summary:
                res[k] = float(r.summary[k])
    return res


def dt_sweep(rodsim, tmp, N, L, Gamma0, Omega0, space, factors, steps, seed=1):
    """Fixed-step RK4 at dt = factor * dt* (exact boundary); noise 1e-8 on the rest state."""
    lam, re_max = spectral_radius(N, L, Gamma0, Omega0, space)
    dt_star = 2 * math.sqrt(2) / lam
    dt_est = 2 * math.sqrt(2) / (wave_speed() * kmax(N, L, space))
    rng = np.random.default_rng(seed)
    y0 = rest_state(N, Gamma0, Omega0) + 1e-8 * rng.standard_normal((12, N))
    ic = tmp / f"noise_{space}_{N}.h5"
    write_initial(ic, y0, L)
    rows = []
    for f in factors:
        dt = f * dt_star
        scene = tmp / "cfl.toml"
        write_scene(scene, N, L, Gamma0, Omega0, ic, {"space": space, "time": "rk4", "dt": dt},
                    t_end=steps * dt, checks="stop_on_fold = false")
        r = run(rodsim, scene, tmp / "cfl.h5")
        row = dict(factor=f, dt=dt, returncode=r["returncode"])
        if r["returncode"] == 0:
            row["growth"] = float(np.max(np.abs(r["y_last"] - rest_state(N, Gamma0, Omega0))) / 1e-8)
        else:
            row["message"] = r["stderr"][:300]
        rows.append(row)
    return dict(N=N, L=L, space=space, Gamma0=list(Gamma0), Omega0=list(Omega0), lambda_max=lam,
                max_real_part=re_max, dt_star=dt_star, dt_wave_speed_estimate=dt_est,
                dt_rodsim_limit=2.8 / (wave_speed() * kmax(N, L, space)), steps=steps, runs=rows)


def fold_sweep(rodsim, tmp, epsilons, t_end=10.0):
    scene = Path(__file__).resolve().parents[1] / "scenes" / "p3_untwisted_wave.toml"
    rows = []
    for eps in epsilons:
        r = run(rodsim, scene, tmp / "fold.h5", [f"initial.epsilon={eps}", f"output.t_end={t_end}",
                                               "output.frames=101", 'output.fields=["internal","energy"]'])
        row = dict(epsilon=eps, returncode=r["returncode"], message=r["stderr"][:300])
        if "y_last" in r:
            row["min_Gamma3_last_frame"] = float(np.min(r["y_last"][8]))
        rows.append(row)
    return rows


def adversarial(rodsim, tmp, N=128, t_end=10.0, rtol=1e-8):
    """Rest state of the untwisted paper rod plus (a) 1e-3 white noise in every field,
    (b) a unit step (discontinuity) in gamma1; each operator, with and without dealiasing."""
    L, G0, O0 = 2 * math.pi, (0, 0, 1.0), (0, 0, 0.0)
    rng = np.random.default_rng(7)
    base = rest_state(N, G0, O0)
    noise = base + 1e-3 * rng.standard_normal((12, N))
    step = base.copy()
    step[0, : N // 2] = 0.1
    rows = []
    for icname, y0 in (("noise 1e-3", noise), ("step in gamma1 (0.1)", step)):
        ic = tmp / "adv.h5"
        write_initial(ic, y0, L)
        for space, dealias in (("fd4", False), ("spectral", False), ("spectral", True)):
            scene = tmp / "adv.toml"
            write_scene(scene, N, L, G0, O0, ic, {"space": space, "time": "dop853", "rtol": rtol, "atol": rtol,
                                                  "dealias": dealias},
                        t_end=t_end, frames=11, fields=("internal", "energy"))
            r = run(rodsim, scene, tmp / "adv.h5out")
            rows.append(dict(ic=icname, space=space, dealias=dealias, returncode=r["returncode"],
                             message=r["stderr"][:200], wall_s=r["wall_s"], steps=r.get("steps"),
                             energy_drift=r.get("energy_drift")))
    return rows


def long_run(rodsim, tmp, t_end, rtol, frames=201, N=160):
    scene = Path(__file__).resolve().parents[2] / "workflows" / "scenes" / "dna158.toml"
    r = run(rodsim, scene, tmp / "long.h5", [f"rod.points={N}", f"output.t_end={t_end}", f"output.frames={frames}",
                                             f"solver.rtol={rtol}", f"solver.atol={rtol}",
                                             'output.fields=["energy"]', f"solver.max_steps={10**8}"])
    if r["returncode"] != 0:
        return dict(error=r["stderr"])
    E = r["energy"]
    drift = np.abs(E - E[0]) / abs(E[0])
    steps = r["steps"]
    return dict(N=N, t_end=t_end, rtol=rtol, steps=steps, wall_s=r["wall_s"], time=r["time"].tolist(),
                drift=drift.tolist(), max_drift=float(drift.max()),
                steps_at_frame=(np.asarray(r["time"]) / t_end * steps).tolist())


def long_run_rk4(rodsim, tmp, steps, dt=0.01, N=32, frames=201):
    """Fixed-step RK4 (the paper's integrator without step control) on the P3 wave, `steps` steps."""
    scene = Path(__file__).resolve().parents[1] / "scenes" / "p3_untwisted_wave.toml"
    t_end = steps * dt
    r = run(rodsim, scene, tmp / "long_rk4.h5", [f"rod.points={N}", f"output.t_end={t_end}",
                                                 f"output.frames={frames}", "solver.time=rk4", f"solver.dt={dt}",
                                                 "solver.space=spectral", 'output.fields=["energy"]',
                                                 f"solver.max_steps={10**8}"])
    if r["returncode"] != 0:
        return dict(error=r["stderr"])
    E = r["energy"]
    drift = np.abs(E - E[0]) / abs(E[0])
    return dict(N=N, dt=dt, t_end=t_end, steps=r["steps"], wall_s=r["wall_s"], time=r["time"].tolist(),
                drift=drift.tolist(), max_drift=float(drift.max()),
                steps_at_frame=(np.asarray(r["time"]) / dt).tolist())


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--build", default="build")
    p.add_argument("--out", default=str(HERE.parent / "results"))
    p.add_argument("--quick", action="store_true")
    p.add_argument("--plot-only", action="store_true", help="redraw stress.png from stress.json in --out")
    a = p.parse_args(argv)
    rodsim = Path(a.build) / "bin" / "rodsim"
    out = Path(a.out)
    if a.plot_only:
        plot(json.loads((out / "stress.json").read_text()), out)
        return 0
    out.mkdir(parents=True, exist_ok=True)
    res = {}
    factors = [0.5, 0.8, 0.9, 0.95, 0.98, 1.02, 1.05, 1.1, 1.2]
    with tempfile.TemporaryDirectory(prefix="dnarod-stress-") as td:
        tmp = Path(td)
        cases = [(32, 2 * math.pi, (0, 0, 1.0), (0, 0, 0.0)),
                 (64, 2 * math.pi, (0, 0, 1.0), (0, 0, 1.0)),
                 (158 if not a.quick else 64, 106.792, (0, 0, 1.0), (0, 0, 0.8826))]
        res["cfl"] = []
        for N, L, G0, O0 in cases:
            for space in ("fd4", "spectral"):
                r = dt_sweep(rodsim, tmp, N, L, G0, O0, space, factors, steps=400)
                res["cfl"].append(r)
                print(f"CFL {space} N={N} L={L:g} O03={O0[2]}: dt*={r['dt_star']:.4g} "
                      f"(wave-speed estimate {r['dt_wave_speed_estimate']:.4g}, rodsim limit "
                      f"{r['dt_rodsim_limit']:.4g}); " +
                      ", ".join(f"{x['factor']}:{'refused' if x['returncode'] else '%.2g' % x['growth']}"
                                for x in r["runs"]), flush=True)
        res["fold"] = fold_sweep(rodsim, tmp, [0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 4.0])
        for x in res["fold"]:
            print("fold eps", x["epsilon"], x["returncode"], x.get("min_Gamma3_last_frame"), x["message"][:100])
        res["adversarial"] = adversarial(rodsim, tmp)
        for x in res["adversarial"]:
            print("adversarial", x)
        # DOP853 at tight tolerance: ~1e5 steps (full run) on the DNA scene.
        t_end = 2000.0 if a.quick else 4.0e4
        res["long_run"] = long_run(rodsim, tmp, t_end, 1e-12)
        lr = res["long_run"]
        print("long run dop853:", {k: lr.get(k) for k in ("steps", "wall_s", "max_drift", "error")}, flush=True)
        # Fixed-step RK4: 1e6 steps (full run).
        res["long_run_rk4"] = long_run_rk4(rodsim, tmp, 10**4 if a.quick else 10**6)
        lr = res["long_run_rk4"]
        print("long run rk4:", {k: lr.get(k) for k in ("steps", "wall_s", "max_drift", "error")}, flush=True)
    (out / "stress.json").write_text(json.dumps(res, indent=1))
    plot(res, out)
    return 0


def plot(res, out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    ax = axes[0]
    for r in res["cfl"]:
        xs = [x["factor"] for x in r["runs"] if x["returncode"] == 0]
        ys = [max(x["growth"], 1e-1) for x in r["runs"] if x["returncode"] == 0]
        line, = ax.semilogy(xs, ys, "o-", ms=3, label=f"{r['space']} N={r['N']} O03={r['Omega0'][2]:.2g}")
        bad = [x["factor"] for x in r["runs"] if x["returncode"] != 0]
        ax.semilogy(bad, [1e2] * len(bad), "x", color=line.get_color(), ms=6)
        lim = r["dt_rodsim_limit"] / r["dt_star"]
        ax.axvline(lim, color=ax.lines[-1].get_color(), lw=0.6, ls=":")
    ax.axvline(1.0, color="k", lw=0.8)
    ax.set_xlabel("dt / dt*   (dt* = 2 sqrt 2 / lambda_max, exact)")
    ax.set_ylabel("noise growth, 400 steps (x: blew up/refused)")
    ax.set_title("fixed-step RK4: stability boundary (dotted: rodsim's limit)")
    ax.legend(fontsize=6)
    ax = axes[1]
    for key, label in (("long_run", "DOP853 rtol 1e-12, DNA scene N=160"),
                       ("long_run_rk4", "RK4 dt=0.01, P3 wave N=32")):
        lr = res.get(key, {})
        if "drift" in lr:
            ax.loglog(np.maximum(lr["steps_at_frame"][1:], 1), np.maximum(lr["drift"][1:], 1e-17), "-",
                      label=f"{label} ({lr['steps']:.3g} steps)")
    ax.set_xlabel("steps")
    ax.set_ylabel("|E - E0| / E0")
    ax.set_title("energy drift in long runs")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "stress.png", dpi=110)


if __name__ == "__main__":
    sys.exit(main())
