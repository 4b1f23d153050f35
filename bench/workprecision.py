#!/usr/bin/python3
"""Work-precision benchmark of the rod solver: error vs process wall time.

Three problems (scenes in bench/scenes/):
  P1  exact twisted-rod wave (Eq 24), k = 2, A = 0.5, t = 10: error vs the exact solution;
  P2  158-bp DNA planar scene (Sec 6.1), t = 100: error vs a converged reference;
  P3  untwisted wave, k = 2, eps = 0.5 (Sec 5.2), t = 10: error vs a converged reference.

Error of a run = max over the 12 fields and the grid of |y - y_true| at t_end,
divided by max |y_true - y_rest| (y_rest: the intrinsic shape, i.e. the size
of the motion). y_true at the run's grid points: the exact solution (P1), or
the reference run Fourier-interpolated (exact for a band-limited reference).

Reference (P2, P3): spectral + DOP853 at rtol = atol = 1e-13 on two grids
(N_ref and 1.5 N_ref); their difference is recorded as the reference's own
error ("ref_self_convergence" in the JSON) and must be far below the errors
being measured.

Wall time = wall time of the whole `rodsim run` process (start-up, scene
parsing, HDF5 output included), best of `--repeat` runs; the numpy/scipy
baseline (bench/baseline_numpy.py) is timed the same way (Python start-up
and imports included).

    workprecision.py --build BUILD_DIR --out bench/results [--quick] [--problems P1,P2,P3]
"""
import argparse
import json
import math
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from mdbridge.rod.run import RodRun

HERE = Path(__file__).resolve().parent
SCENES = HERE / "scenes"
FIELDS = ("gamma", "omega", "Gamma", "Omega")


# ----------------------------------------------------------------- running
def children_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run_rodsim(rodsim, scene, sets, out, repeat=1):
    """Run rodsim; return (best process wall time, summary attributes, y[T,12,N], time).

    The summary also holds cpu_s, the best user+sys CPU time of the process:
    on a shared, loaded machine it is the fairer measure of the work done."""
    cmd = [str(rodsim), "run", str(scene), "-o", str(out), "--quiet"]
    for k, v in sets.items():
        cmd += ["--set", f"{k}={v}"]
    best = best_cpu = math.inf
    for k in range(repeat):
        c0, t0 = children_cpu(), time.perf_counter()
        p = subprocess.run(cmd, capture_output=True, text=True)
        wall, cpu = time.perf_counter() - t0, children_cpu() - c0
        if p.returncode != 0:
            return None, {"error": p.stderr.strip()}, None, None
        best, best_cpu = min(best, wall), min(best_cpu, cpu)
        if wall > 3.0:  # slow runs are timed once (their noise is relatively small)
            break
    r = RodRun.read(out)
    y = np.concatenate([np.transpose(r.fields[n], (0, 2, 1)) for n in FIELDS], axis=1)
    info = {"cpu_s": best_cpu}
    for k in ("steps", "rejected", "rhs_evaluations", "wall_seconds", "energy_drift", "reduced"):
        if k in r.summary:
            info[k] = float(r.summary[k])
    info["energy"] = r.energy
    return best, info, y, r.time


def run_baseline(initial_h5, space, rtol, t_end, out, repeat=1):
    cmd = [sys.executable, str(HERE / "baseline_numpy.py"), str(initial_h5), "--space", space,
           "--rtol", repr(rtol), "--t-end", repr(t_end), "-o", str(out)]
    best = best_cpu = math.inf
    for _ in range(repeat):
        c0, t0 = children_cpu(), time.perf_counter()
        p = subprocess.run(cmd, capture_output=True, text=True)
        wall, cpu = time.perf_counter() - t0, children_cpu() - c0
        if p.returncode != 0:
            return None, {"error": p.stderr.strip()[-500:]}, None
        best, best_cpu = min(best, wall), min(best_cpu, cpu)
        if wall > 3.0:
            break
    d = np.load(out)
    return best, {"rhs_evaluations": int(d["nfev"]), "cpu_s": best_cpu}, d["y"]


# ----------------------------------------------------------------- truths
def twisted_wave_exact(s, t, L, mode, A, Gamma03, Omega03, D1):
    """Eq 24 in the checked form of docs/numerics.md (kappa_p branch, w_+); rows gamma1..Omega3.

    Deliberately a second, independent implementation of Eq 24 and of its frequency
    (Eq 26): rodsim's twisted_wave initial state is rodcore.analytic's, so checking
    rodsim and bench/baseline_numpy.py against that same code would prove nothing
    (tests/python/test_stress_baseline_crosscheck.py)."""
    k = 2 * math.pi * mode / L
    kappa, sigma = k + Omega03, -1.0
    w = 0.5 * (math.sqrt(kappa**2 * (math.sqrt(D1) + 1) ** 2 + Gamma03**2)
               + math.sqrt(kappa**2 * (math.sqrt(D1) - 1) ** 2 + Gamma03**2))
    aw = w * Gamma03 * A / (w**2 - D1 * kappa**2)
    th = w * t - k * s
    c, sn = np.cos(th), np.sin(th)
    z = np.zeros_like(s)
    return np.array([-kappa * A / w * c, -sigma * kappa * A / w * sn, z,
                     sigma * aw * c, aw * sn, z,
                     A * c, sigma * A * sn, z + Gamma03,
                     -sigma * kappa * aw / w * c, -kappa * aw / w * sn, z + Omega03])


def fourier_resample(y, N):
    """Band-limited interpolation of periodic rows y[..., M] onto N equispaced points."""
    M = y.shape[-1]
    Y = np.fft.rfft(y, axis=-1)
    K = min(M, N) // 2
    Z = np.zeros(y.shape[:-1] + (N // 2 + 1,), dtype=complex)
    Z[..., :K] = Y[..., :K]
    if K < Y.shape[-1] and K < Z.shape[-1]:
        # Nyquist mode of the coarser grid: keep it symmetric (half weight) so
        # the result is real and exact for band-limited data below it.
        Z[..., K] = Y[..., K] * (0.5 if (M != N) else 1.0)
    return np.fft.irfft(Z, n=N, axis=-1) * (N / M)


def rest_state(attrs_like, N):
    G0, O0 = attrs_like
    y = np.zeros((12, N))
    for c in range(3):
        y[6 + c] = G0[c]
        y[9 + c] = O0[c]
    return y


def rel_error(y, ytrue, yrest):
    return float(np.max(np.abs(y - ytrue)) / np.max(np.abs(ytrue - yrest)))


# ----------------------------------------------------------------- problems
PROBLEMS = {
    "P1": dict(scene="p1_twisted_wave.toml", t_end=10.0, exact=True, N_ref=None,
               points_key=True, Gamma0=(0, 0, 1.0), Omega0=(0, 0, 1.0)),
    # The workflow's DNA scene itself, with its output reduced to the final state.
    "P2": dict(scene="../../workflows/scenes/dna158.toml", t_end=100.0, exact=False, N_ref=256,
               points_key=False),
    "P3": dict(scene="p3_untwisted_wave.toml", t_end=10.0, exact=False, N_ref=128, points_key=True,
               Gamma0=(0, 0, 1.0), Omega0=(0, 0, 0.0)),
}


def methods(problem, quick):
    """(label, space, time, [N], [rtol]) swept per problem; N = None keeps the scene's."""
    if problem == "P2":
        Nfd = [158, 316, 632, 1264] if quick else [158, 316, 632, 1264, 2528, 5056]
        Nsp = [160, 192] if quick else [128, 160, 192]
    else:
        Nfd = [64, 128, 256] if quick else [64, 128, 256, 512, 1024]
        Nsp = [48, 64] if quick else [32, 48, 64, 96]
    # FD4's error is dominated by space beyond rtol ~1e-7, so few tolerances.
    r_fd = [1e-4, 1e-6, 1e-8] if quick else [1e-5, 1e-7, 1e-9]
    r_lo = [1e-4, 1e-6, 1e-8] if quick else [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10]
    r_hi = [1e-5, 1e-8, 1e-11] if quick else [1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12]
    return [
        ("paper: fd4 + rk4-doubling", "fd4", "rk4-doubling", Nfd, r_fd),
        ("fd4 + dop853", "fd4", "dop853", Nfd, r_fd),
        ("spectral + dop853", "spectral", "dop853", Nsp, r_hi),
        ("spectral + dopri5", "spectral", "dopri5", Nsp, r_lo),
    ]


# The numpy/scipy baseline is run on one grid per problem (its spatial error
# there is far below the errors compared), at every spectral + dop853 tolerance.
BASELINE_N = {"P1": 64, "P2": 160, "P3": 64}


def pareto(points):
    """Lower-left front of (wall, err) points, sorted by wall time."""
    front, best = [], math.inf
    for w, e in sorted(points):
        if e < best:
            front.append((w, e))
            best = e
    return front


def wall_at_error(points, target):
    """Wall time needed to reach error <= target, log-log interpolated along the Pareto front."""
    front = pareto(points)
    for i, (w, e) in enumerate(front):
        if e <= target:
            if i == 0:
                return w
            w0, e0 = front[i - 1]
            f = (math.log(target) - math.log(e0)) / (math.log(e) - math.log(e0))
            return math.exp(math.log(w0) + f * (math.log(w) - math.log(w0)))
    return None


def exact_truth(name, P, rodsim, scene, base, tmp, result):
    """(truth(N), Gamma0, Omega0): the exact solution (Eq 24) at the scene's t_end."""
    t_end = P["t_end"]
    if run_rodsim(rodsim, scene, dict(base), tmp / "probe.h5")[0] is None:
        raise SystemExit(f"{name}: probe run of {scene} failed")
    a = RodRun.read(tmp / "probe.h5").attrs
    L = float(a["rod.length"])
    params = dict(mode=float(a["initial.mode"]), A=float(a["initial.A"]),
                  Gamma03=float(a["rod.Gamma0"][2]), Omega03=float(a["rod.Omega0"][2]),
                  D1=float(a["material.D"][0]))
    G0, O0 = P["Gamma0"], P["Omega0"]

    def truth(N):
        s = L * np.arange(N) / N
        return twisted_wave_exact(s, t_end, L, **params)
    result["truth"] = "exact solution (Eq 24, checked form)"
    return truth, G0, O0


def reference_truth(name, P, rodsim, scene, base, tmp, result, log):
    """(truth(N), Gamma0, Omega0): a spectral DOP853 reference at rtol = atol = 1e-13, its
    self-convergence against a coarser one recorded in RESULT."""
    Nr = P["N_ref"]
    refs = []
    for Nref in (Nr, Nr * 3 // 2):
        sets = dict(base, **{"solver.space": "spectral", "solver.time": "dop853", "solver.rtol": 1e-13,
                             "solver.atol": 1e-13, "rod.points": Nref})
        w, info, y, _ = run_rodsim(rodsim, scene, sets, tmp / f"ref{Nref}.h5")
        if y is None:
            raise SystemExit(f"{name}: reference run failed: {info['error']}")
        refs.append(y[-1])
        log(f"{name}: reference N={Nref} rtol=1e-13: {w:.2f} s")
    a = RodRun.read(tmp / f"ref{Nr}.h5").attrs
    G0, O0 = tuple(a["rod.Gamma0"]), tuple(a["rod.Omega0"])
    yref = refs[1]
    Nfine = yref.shape[-1]
    self_conv = rel_error(fourier_resample(refs[0], Nfine), yref, rest_state((G0, O0), Nfine))
    result["truth"] = (f"reference: spectral N={Nfine} + DOP853 rtol=atol=1e-13; "
                       f"vs N={Nr}: relative difference {self_conv:.2e}")
    result["ref_self_convergence"] = self_conv
    log(f"{name}: reference self-convergence {self_conv:.2e}")

    def truth(N):
        return fourier_resample(yref, N)
    return truth, G0, O0


def bench_problem(name, rodsim, tmp, quick, repeat, log):
    P = PROBLEMS[name]
    scene = (SCENES / P["scene"]).resolve()
    t_end = P["t_end"]
    # Only the final internal state is written, and the scene's own drift check
    # is lifted so that loose-tolerance runs are measured rather than stopped.
    base = {"output.t_end": t_end, "output.frames": 2, "output.fields": '["internal"]',
            "checks.max_energy_drift": 1.0}
    result = {"problem": name, "scene": str(scene.relative_to(HERE.parent)), "t_end": t_end, "runs": []}

    if P["exact"]:
        truth, G0, O0 = exact_truth(name, P, rodsim, scene, base, tmp, result)
    else:
        truth, G0, O0 = reference_truth(name, P, rodsim, scene, base, tmp, result, log)

    # Sweeps.
    for label, space, tm, Ns, rtols in methods(name, quick):
        for N in Ns:
            for rtol in rtols:
                sets = dict(base, **{"solver.space": space, "solver.time": tm, "solver.rtol": rtol,
                                     "solver.atol": rtol, "rod.points": N})
                out = tmp / "run.h5"
                w, info, y, _ = run_rodsim(rodsim, scene, sets, out, repeat)
                rec = dict(method=label, space=space, time=tm, N=N, rtol=rtol)
                if y is None:
                    rec["failed"] = info["error"][:300]
                    log(f"{name} {label} N={N} rtol={rtol:g}: FAILED {rec['failed'][:120]}")
                else:
                    rec.update(wall_s=w, error=rel_error(y[-1], truth(N), rest_state((G0, O0), N)),
                               **{k: v for k, v in info.items() if k != "energy"})
                    log(f"{name} {label} N={N} rtol={rtol:g}: {w:.3f} s, error {rec['error']:.2e}")
                result["runs"].append(rec)
            # Baseline: same operator (spectral) and integrator (DOP853), same tolerances.
            if space == "spectral" and tm == "dop853" and N == BASELINE_N[name]:
                init = tmp / f"init{N}.h5"
                run_rodsim(rodsim, scene, dict(base, **{"rod.points": N, "output.t_end": 1e-6}), init)
                for rtol in rtols:
                    if rtol < 1e-11 and quick:
                        continue
                    w, info, y = run_baseline(init, "spectral", rtol, t_end, tmp / "base.npz", repeat)
                    rec = dict(method="baseline numpy/scipy: spectral + DOP853", space="spectral",
                               time="scipy-DOP853", N=N, rtol=rtol)
                    if y is None:
                        rec["failed"] = info["error"]
                    else:
                        rec.update(wall_s=w, error=rel_error(y[-1], truth(N), rest_state((G0, O0), N)), **info)
                        log(f"{name} baseline N={N} rtol={rtol:g}: {w:.3f} s, error {rec['error']:.2e}")
                    result["runs"].append(rec)
    return result


def summarize(result, target):
    for key, name in (("wall_s", "wall"), ("cpu_s", "cpu")):
        by = {}
        for r in result["runs"]:
            if "error" in r:
                by.setdefault(r["method"], []).append((r[key], r["error"]))
        walls = {m: wall_at_error(pts, target) for m, pts in by.items()}
        result[f"{name}_at_error"] = {"target": target, key: walls}
        d = walls.get("spectral + dop853")
        result[f"{name}_ratios_at_error"] = {m: (w / d if (w and d) else None) for m, w in walls.items()}
    # Same operator, integrator, tolerance and N: rodsim vs the baseline.
    same = []
    for r in result["runs"]:
        if r["method"].startswith("baseline") and "error" in r:
            for q in result["runs"]:
                if (q["method"] == "spectral + dop853" and q["N"] == r["N"] and q["rtol"] == r["rtol"]
                        and "error" in q):
                    same.append(dict(N=r["N"], rtol=r["rtol"], baseline_s=r["wall_s"], rodsim_s=q["wall_s"],
                                     ratio=r["wall_s"] / q["wall_s"], baseline_cpu_s=r["cpu_s"],
                                     rodsim_cpu_s=q["cpu_s"], cpu_ratio=r["cpu_s"] / q["cpu_s"],
                                     baseline_error=r["error"],
                                     rodsim_error=q["error"],
                                     baseline_rhs=r.get("rhs_evaluations"),
                                     rodsim_rhs=q.get("rhs_evaluations")))
    result["baseline_same_settings"] = same
    return result


def plot(results, outdir):
    plot_work(results, outdir, "wall_s", "process wall time [s]", "workprecision.png")
    plot_work(results, outdir, "cpu_s", "process CPU time (user + sys) [s]", "workprecision_cpu.png")
    plot_tolerance(results, outdir)


STYLES = {"paper: fd4 + rk4-doubling": "o-", "fd4 + dop853": "s-", "spectral + dop853": "D-",
          "spectral + dopri5": "^-", "baseline numpy/scipy: spectral + DOP853": "x--"}


def plot_work(results, outdir, key, xlabel, filename):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    styles = STYLES
    fig, axes = plt.subplots(1, len(results), figsize=(5.2 * len(results), 4.4), squeeze=False)
    for ax, res in zip(axes[0], results):
        by = {}
        for r in res["runs"]:
            if "error" in r:
                by.setdefault(r["method"], []).append((r[key], r["error"]))
        for m, pts in by.items():
            f = pareto(pts)
            line, = ax.loglog([p[0] for p in f], [p[1] for p in f], styles.get(m, "o-"), label=m, ms=4)
            # every run, faint; the line is the lower-left (Pareto) front over N and tolerance
            ax.loglog([p[0] for p in pts], [p[1] for p in pts], styles.get(m, "o")[0], alpha=0.25, ms=3,
                      color=line.get_color())
        ax.axhline(1e-6, color="gray", lw=0.5, ls=":")
        ax.set_xlabel(xlabel)
        ax.set_ylabel("relative error at t_end")
        ax.set_title(f"{res['problem']}: {Path(res['scene']).stem} (t = {res['t_end']:g})")
        ax.grid(True, which="both", lw=0.2)
    axes[0][0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(outdir / filename, dpi=110)


def plot_tolerance(results, outdir):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    styles = STYLES
    # Tolerance vs error (one panel per problem, spectral N fixed at the finest swept).
    fig, axes = plt.subplots(1, len(results), figsize=(5.2 * len(results), 4.4), squeeze=False)
    for ax, res in zip(axes[0], results):
        by = {}
        for r in res["runs"]:
            if "error" in r:
                by.setdefault((r["method"], r["N"]), []).append((r["rtol"], r["error"]))
        for (m, N), pts in sorted(by.items()):
            if m.startswith("paper") or m.startswith("fd4"):
                continue  # FD4 error is dominated by space: shown in the work-precision plot
            pts.sort()
            ax.loglog([p[0] for p in pts], [p[1] for p in pts], styles.get(m, "o-"), label=f"{m}, N={N}", ms=3)
        lims = [1e-13, 1e-3]
        ax.loglog(lims, lims, "k:", lw=0.6, label="error = rtol")
        ax.set_xlabel("rtol (= atol)")
        ax.set_ylabel("relative error at t_end")
        ax.set_title(res["problem"])
        ax.grid(True, which="both", lw=0.2)
        ax.legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(outdir / "tolerance_error.png", dpi=110)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--build", default=os.environ.get("DNAROD_BUILD", str(HERE.parent / "build")))
    p.add_argument("--out", default=str(HERE / "results"))
    p.add_argument("--problems", default="P1,P2,P3")
    p.add_argument("--quick", action="store_true", help="coarse sweeps (a test-sized run)")
    p.add_argument("--repeat", type=int, default=None, help="best of R timings (default 2, quick 1)")
    p.add_argument("--target", type=float, default=1e-6, help="error at which wall times are compared")
    p.add_argument("--plot-only", action="store_true", help="redraw the figures from the JSON in --out")
    a = p.parse_args(argv)
    if a.plot_only:
        outdir = Path(a.out)
        plot([json.loads((outdir / f"workprecision_{n}.json").read_text()) for n in a.problems.split(",")], outdir)
        return 0
    rodsim = Path(a.build) / "bin" / "rodsim"
    if not rodsim.exists():
        raise SystemExit(f"{rodsim} not found: build first (scripts/build.sh)")
    repeat = a.repeat or (1 if a.quick else 2)
    outdir = Path(a.out)
    outdir.mkdir(parents=True, exist_ok=True)
    results = []
    with tempfile.TemporaryDirectory(prefix="dnarod-wp-") as td:
        for name in a.problems.split(","):
            res = bench_problem(name, rodsim, Path(td), a.quick, repeat, lambda m: print(m, flush=True))
            res = summarize(res, a.target)
            res["quick"] = a.quick
            res["repeat"] = repeat
            results.append(res)
            (outdir / f"workprecision_{name}.json").write_text(json.dumps(res, indent=1))
            print(json.dumps({k: res[k] for k in ("problem", "wall_at_error", "wall_ratios_at_error",
                                                  "cpu_at_error", "cpu_ratios_at_error")}, indent=1))
    plot(results, outdir)
    return 0


if __name__ == "__main__":
    sys.exit(main())
