"""Calibration of `dnarod modes`' overdamped regime (mdbridge/analysis/relaxation.py,
mode_spectra.regime_of) on the thermal rod in water, against the rod's own friction and
stiffness.

The series: Langevin runs of a short DNA rod (42 bp, 4 turns, the paper's material) in water
(`friction = "water"`, docs/thermal.md) at 0.03 K (linear: what linear theory describes),
each through the command's own code path (the rod file read as `dnarod modes` reads it,
mode_table on each run alone). The truth, for the axial modes, needs no fit and no
eigenvalue: a straight rod's stretch (twist) mode of wavenumber k is one damped harmonic
oscillator, rho Gamma3'' = C3 k^2 ... with the friction z_along per length (I3 Omega3'' with
D3 k^2 and z_about), so its integrated autocorrelation time is

    tau = zeta / k_mode = z_along / (C3 k^2)    (stretch),    z_about / (D3 k^2)    (twist),

from the file's own `material.C`, `material.D`, `thermal.friction_*` and `rod.length`.

Per mode over the realisations: how often it is overdamped (checked when in at least SETTLED
of them), the mean of tau / truth with its
error from the scatter between seeds, and the calibration ratio stated / RMS =
sqrt(mean stated^2) / sqrt(mean (tau - truth)^2) (pass 0.7-1.4, the band of
bench/mode_spectrum_calibration.py). Two controls must fail: the truth with the wrong
friction (the across friction in place of the one along the axis for stretch, which is
1.5x; for twist the across rotational friction, 4x), and the naive error of tau, the
white-noise one tau (2 / (M N))^1/2 of M series of N frames taken as independent samples,
which a correlated series defeats.

    nice -n 12 /usr/bin/python3 bench/overdamped_modes.py --realisations 12 [--seed 1] [--raw raw.json]
        [--keep DIR [--again]]    (~1 CPU-min per realisation)
    nice -n 12 /usr/bin/python3 bench/overdamped_modes.py --water-case results/modes_water   (~3 CPU-min)
"""
from __future__ import annotations

import argparse
import json
import math
import time
from pathlib import Path

import numpy as np

BP, TURNS = 42, 4
TEMPERATURE_K = 0.03
DT, FRAME, FRAMES = 0.1, 1.0, 4001      # tau: a 3.77-ns record of 0.94-ps frames
LOW, HIGH = 0.7, 1.4
SETTLED = 0.9          # a mode is checked when it is overdamped in at least this fraction of the seeds


def scene(seed: int) -> dict:
    return {"initial": {"kind": "dna_planar", "bp": BP, "turns": TURNS, "A_v_A_per_ps": 0.0, "A_A": 0.0},
            "solver": {"space": "spectral", "time": "langevin", "dt": DT},
            "output": {"t_end": FRAME * (FRAMES - 1), "frames": FRAMES,
                       "fields": ["internal", "centerline", "directors"]},
            # keep_closure false: no projection in the dynamics that linear theory lacks
            "thermal": {"temperature_K": TEMPERATURE_K, "seed": int(seed), "keep_closure": False,
                        "friction_translational": "water", "friction_rotational": "water"}}


def friction(attrs, kind: str, wrong: bool = False) -> float:
    """The friction per length (rod units) that damps an axial mode: along d3 for stretch,
    about d3 for twist; wrong: the control's, across."""
    zt = [float(v) for v in attrs["thermal.friction_translational"]]     # [along, across]
    zr = [float(v) for v in attrs["thermal.friction_rotational"]]        # [about the axis, across]
    return (zt if kind == "stretch" else zr)[1 if wrong else 0]


def truth(attrs, kind: str, n: int, wrong: bool = False) -> float | None:
    """tau = zeta / k [ps] of axial mode n from the rod file's attributes (module doc); None
    for bend. wrong: the control's friction (across in place of along / about the axis)."""
    if kind == "bend":
        return None
    k = 2 * math.pi * n / float(attrs["rod.length"])
    stiffness = float(attrs["material.C" if kind == "stretch" else "material.D"][2]) * k ** 2
    return friction(attrs, kind, wrong) / stiffness * float(attrs["tau_ps"])


def realisation(seed: int, workdir) -> dict:
    """One run through `dnarod modes`' code path: {"kind n": {regime, tau, tau_err, naive_err,
    omega, reason, truth, truth_wrong}} (ps)."""
    from mdbridge.analysis.mode_run import ModeInput
    from mdbridge.analysis.mode_spectra import mode_table
    from mdbridge.rod.run import run_scene
    from mdbridge.analysis.mode_spectra import load_npz, save_npz
    from mdbridge.jsonio import write_json
    npz, head = Path(workdir) / f"overdamped_{seed}.npz", Path(workdir) / f"overdamped_{seed}.json"
    if npz.is_file() and head.is_file():       # a kept realisation (--keep): analysed again
        series, attrs = load_npz(npz), json.loads(head.read_text())
    else:
        h5 = Path(workdir) / f"overdamped_{seed}.h5"
        run_scene(scene(seed), output=h5)
        inp = ModeInput(str(h5))
        attrs = {k: inp.run.attrs[k] for k in ("thermal.friction_translational", "thermal.friction_rotational",
                                               "rod.length", "material.C", "material.D", "tau_ps")}
        series = inp.mode_series(lambda *a, **k: None)
        h5.unlink()
        save_npz(npz, series)
        write_json(head, attrs)
    table = mode_table(series)
    out = {}
    for e in table["modes"]:
        kind, n = e["kind"], e["n"]
        r = e.get("relaxation") or {}
        naive = None
        if e["relaxation_time_ps"] is not None:
            M = 2 * len(series) * (2 if kind == "bend" else 1)
            naive = e["relaxation_time_ps"] * math.sqrt(2.0 / (M * table["n_frames"]))
        out[f"{kind} {n}"] = {"regime": e["regime"], "tau": e["relaxation_time_ps"],
                              "tau_err": e["relaxation_time_err_ps"], "naive_err": naive,
                              "tau_any": r.get("tau_ps"), "relaxation_reason": r.get("reason"),
                              "omega": e["omega_per_ps"], "reason": e["reason"],
                              "truth": truth(attrs, kind, n), "truth_wrong": truth(attrs, kind, n, wrong=True),
                              "friction": None if kind == "bend" else friction(attrs, kind)}
    return out


def summary(rows: list, key: str) -> dict:
    """One mode over the realisations (module doc)."""
    got = [r[key] for r in rows]
    t = got[0]["truth"]
    out: dict = {"mode": key, "truth_ps": t, "friction": got[0].get("friction"), "realisations": len(got),
                 "overdamped": sum(g["regime"] == "overdamped" for g in got),
                 "oscillating": sum(g["regime"] == "oscillating" for g in got)}
    od = [g for g in got if g["regime"] == "overdamped"]
    if t is None or len(od) < 3:
        return out
    # a mode resolved in only part of the seeds sits at the resolution threshold, where the
    # records that pass are those whose tau came out short (docs/modes.md): reported, not checked
    out["near_threshold"] = len(od) < SETTLED * len(got)
    tau = np.array([g["tau"] for g in od])
    err = np.array([g["tau_err"] for g in od])
    naive = np.array([g["naive_err"] for g in od])
    dev = tau - t
    rms = math.sqrt(float(np.mean(dev ** 2)))
    mean = float(np.mean(tau))
    mean_err = float(np.std(tau, ddof=1) / math.sqrt(len(tau)))
    tw = got[0]["truth_wrong"]
    out.update(tau_mean_ps=mean, tau_mean_err_ps=mean_err, tau_over_truth=mean / t,
               z_mean=(mean - t) / mean_err, stated_over_rms=math.sqrt(float(np.mean(err ** 2))) / rms,
               pass_=bool(abs(mean - t) < 3 * mean_err and LOW <= math.sqrt(float(np.mean(err ** 2))) / rms <= HIGH),
               control_friction={"truth_ps": tw, "z_mean": (mean - tw) / mean_err,
                                 "pass": bool(abs(mean - tw) < 3 * mean_err)},
               control_error={"stated_over_rms": math.sqrt(float(np.mean(naive ** 2))) / rms,
                              "pass": bool(LOW <= math.sqrt(float(np.mean(naive ** 2))) / rms <= HIGH)})
    out["pass"] = out.pop("pass_")
    return out


# The reported case: the paper's 158-bp rod at 300 K in water as docs/thermal.md shows it,
# 2127 tau (2.0 ns) of 1-tau frames (results/modes_water/, tests/python/test_modes_overdamped.py)
WATER_BP, WATER_TURNS, WATER_FRAMES, WATER_DT = 158, 15, 2128, 0.05


def water_scene(seed: int = 1) -> dict:
    return {"initial": {"kind": "dna_planar", "bp": WATER_BP, "turns": WATER_TURNS, "A_v_A_per_ps": 0.0, "A_A": 0.0},
            "solver": {"space": "spectral", "time": "langevin", "dt": WATER_DT},
            "output": {"t_end": float(WATER_FRAMES - 1), "frames": WATER_FRAMES,
                       "fields": ["internal", "centerline", "directors"]},
            "thermal": {"temperature_K": 300.0, "seed": int(seed), "friction_translational": "water",
                        "friction_rotational": "water"}}


def water_case(out, seed: int = 1, h5=None) -> None:
    """OUT/mode_series.npz and OUT/run.json of the reported case (above): the rod run (or an
    existing run of it, h5), its amplitudes, and per axial mode zeta / k with Gamma and 2 omega0
    (linear theory: overdamped when Gamma > 2 omega0)."""
    from mdbridge.analysis.mode_run import ModeInput
    from mdbridge.analysis.mode_spectra import save_npz
    from mdbridge.jsonio import write_json
    from mdbridge.rod.run import run_scene
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    if h5 is None:
        h5 = out / "rod.h5"
        run_scene(water_scene(seed), output=h5)
    inp = ModeInput(str(h5))
    attrs = inp.run.attrs
    save_npz(out / "mode_series.npz", inp.mode_series(lambda *a, **k: None))
    tau_ps = float(attrs["tau_ps"])
    rows = {}
    for kind, inertia in (("stretch", float(attrs["material.rho"])), ("twist", float(attrs["material.I"][2]))):
        for n in range(1, WATER_TURNS):
            t = truth(attrs, kind, n)
            Gamma = friction(attrs, kind) / inertia / tau_ps                       # 1/ps
            omega0 = math.sqrt(Gamma / t)                                          # tau = Gamma / omega0^2
            rows[f"{kind} {n}"] = {"truth_ps": t, "Gamma_per_ps": Gamma, "omega0_per_ps": omega0,
                                   "overdamped": bool(Gamma > 2 * omega0)}
    import datetime
    write_json(out / "run.json", {"what": "the reported case of docs/modes.md, 'Overdamped modes'",
                                  "date": datetime.date.today().isoformat(),
                                  "command": f"bench/overdamped_modes.py --water-case {out}",
                                  "scene": water_scene(seed),
                                  "friction_translational": attrs["thermal.friction_translational"],
                                  "friction_rotational": attrs["thermal.friction_rotational"],
                                  "tau_ps": tau_ps, "modes": rows})


def main(argv=None):
    import tempfile
    from mdbridge.jsonio import write_json
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--realisations", type=int, default=12)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--raw", default=None, metavar="JSON", help="keep each realisation's numbers here; resume")
    ap.add_argument("--out", default=str(Path(__file__).resolve().parent / "results"))
    ap.add_argument("--keep", default=None, metavar="DIR",
                    help="keep each realisation's mode_series.npz here, and analyse a kept one again (no run)")
    ap.add_argument("--again", action="store_true", help="analyse every realisation again (with --keep)")
    ap.add_argument("--water-case", default=None, metavar="DIR",
                    help="instead: the reported case (158 bp, 300 K, water, 2 ns) into DIR (results/modes_water)")
    ap.add_argument("--from-h5", default=None, help="with --water-case: an existing run of its scene")
    a = ap.parse_args(argv)
    if a.water_case:
        return water_case(a.water_case, h5=a.from_h5)
    raw = Path(a.raw) if a.raw else None
    rows = json.loads(raw.read_text()) if raw is not None and raw.is_file() and not a.again else {}
    t0, cpu0 = time.time(), time.process_time()
    with tempfile.TemporaryDirectory(prefix="overdamped-") as tmp:
        for seed in range(a.seed, a.seed + a.realisations):
            if str(seed) in rows:
                continue
            t = time.process_time()
            rows[str(seed)] = realisation(seed, a.keep or tmp)
            print(f"seed {seed}: {time.process_time() - t:.1f} s", flush=True)
            if raw is not None:
                write_json(raw, rows)
    use = [rows[str(s)] for s in range(a.seed, a.seed + a.realisations)]
    cases = [summary(use, key) for key in use[0]]
    for c in cases:
        line = f"{c['mode']:10s}: overdamped in {c['overdamped']}/{c['realisations']}, oscillating {c['oscillating']}"
        if "tau_mean_ps" in c:
            line += (f"; tau {c['tau_mean_ps']:.2f} +- {c['tau_mean_err_ps']:.2f} ps vs {c['truth_ps']:.2f} "
                     f"(z {c['z_mean']:+.1f}), stated/rms {c['stated_over_rms']:.2f}, pass {c['pass']} | controls: "
                     f"friction z {c['control_friction']['z_mean']:+.1f}, naive error stated/rms "
                     f"{c['control_error']['stated_over_rms']:.2f}")
        print(line, flush=True)
    from dna_models.units import Units
    checked = [c for c in cases if "tau_mean_ps" in c and not c["near_threshold"]]
    res = {"what": "calibration of dnarod modes' relaxation times of overdamped modes on the thermal rod in water "
                   "(bench/overdamped_modes.py)",
           "scene": scene(a.seed), "seeds": [a.seed, a.seed + a.realisations - 1], "realisations": a.realisations,
           "record_ps": Units.paper().time_to_ps(FRAME * FRAMES), "pass_band": [LOW, HIGH], "cases": cases,
           "checked": [c["mode"] for c in checked],
           "near_threshold": [c["mode"] for c in cases if c.get("near_threshold")],
           "all_pass": all(c["pass"] for c in checked),
           "friction_control_fails": all(not c["control_friction"]["pass"] for c in checked),
           "error_control_fails": all(not c["control_error"]["pass"] for c in checked),
           "cpu_s_this_call": time.process_time() - cpu0, "wall_s_this_call": time.time() - t0}
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    write_json(out / "overdamped_modes.json", res)
    print(f"all pass: {res['all_pass']}; controls fail: friction {res['friction_control_fails']}, error "
          f"{res['error_control_fails']}; wrote {out / 'overdamped_modes.json'}")


if __name__ == "__main__":
    main()
