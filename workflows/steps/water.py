"""The duplex in water at a set tension: what its runs measure (docs/md.md, "DNA in water: the
21-bp runs").

    python3 -m dnarod.steps.water RESULTS RUN [RUN ...] [--discard-ps 20] [--gmx gmx]
                                  [--no-coarse-grain]

Each RUN is a finished `dnarod build-md --solvent ... --axial-tension-pN T` + `run-md` folder
(bench/water_tension.py makes them). Per run, into RESULTS/T<T>/:

    checks.json     the run's own checks (mdbridge/md/gromacs/checks.py: the junction, the
                    side images, the Watson-Crick pairs per frame), copied from RUN
    integrity.json  the open fraction of the pairs after the discard (mdbridge/md/integrity.py),
                    the check: at least MIN_INTACT of the pair-frames intact
    tension.json    test 1: the tension (P_perp - P_zz) A after the discard against the set T,
                    within 2 sigma with sigma <= SIGMA_T_MAX_PN; the box length along the axis
                    and the isotension stretch modulus S = kT <L> / var L (tension.py)
    step_means.json the mean 3DNA step parameters (every step, the closing one too) with their
                    blocking errors: a mean needs no independent-sample floor
    cg/             `dnarod coarse-grain` of the run: 300 K (the thermostat's), the set tension
                    for the rest shape, the same discard, every pair given (or its refusal, in
                    summary.json)

Over the runs, into RESULTS: stretch.json (test 2, with two or more tensions: the length gained
between the lowest and the highest against <L>(T0) dT / S0, and the force-extension modulus it
implies) and summary.json, the one source of the figures docs/md.md quotes, with the published
solvated-MD values they are set against (dna_models/data/published_solvated_md.toml).

A run whose pairs fail the integrity check is an error (exit 2, after the files are written):
its stiffness would be the stiffness of a different molecule.
"""
from __future__ import annotations

import argparse
import json
import shutil
import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np

import dna_models
from dna_models.errors import DnarodError, InputError
from dna_models.units import BOLTZMANN_KJ_PER_MOL_K
from mdbridge.coarsegrain.constants import kT_pN_nm
from mdbridge.jsonio import write_json

DISCARD_PS = 20.0
MIN_INTACT = 0.97
SIGMA_T_MAX_PN = 3.0
PUBLISHED = Path(dna_models.__file__).resolve().parent / "data" / "published_solvated_md.toml"
STEP_NAMES = ("shift", "slide", "rise", "tilt", "roll", "twist")


def _run(run: Path) -> tuple[dict, dict, float]:
    """(build.json, md.done, the set tension) of a finished solvated run, or an InputError."""
    for need in ("build.json", "conf.gro", "md.xtc", "md.edr", "md.done"):
        if not (run / need).is_file():
            raise InputError(f"{run}: {need} missing; a finished `dnarod build-md --solvent ... "
                             f"--axial-tension-pN T` + `dnarod run-md` folder is needed")
    build = json.loads((run / "build.json").read_text())
    T = (build.get("md_settings") or {}).get("axial_tension_pN")
    if not build.get("solvent") or T is None:
        raise InputError(f"{run}/build.json: not a solvated run at a set tension "
                         f"(build-md --solvent tip3p --axial-tension-pN T)")
    return build, json.loads((run / "md.done").read_text()), float(T)


def measure_run(run: Path, record: tuple[dict, dict, float], out: Path, discard_ps: float, gmx: str,
                coarse_grain: bool) -> dict:
    """RESULTS/T<T>/: checks.json, integrity.json, tension.json and cg/ of one run."""
    from mdbridge.md.gromacs.checks import write_checks
    from mdbridge.md.gromacs.run import find_gmx
    from mdbridge.md.gromacs.tension import isotension_stretch_modulus, mean_with_error, tension_series
    from mdbridge.md.integrity import integrity_summary
    build, done, T = record                                   # _run(run), checked before any work
    gmx = find_gmx(gmx)
    out.mkdir(parents=True, exist_ok=True)
    checks = write_checks(run, gmx=gmx)
    shutil.copy2(run / "checks.json", out / "checks.json")
    z = np.load(run / "integrity.npz")
    g = integrity_summary(z["n1_n3_A"], z["times_ps"], discard_ps=discard_ps)
    g["intact_fraction"] = 1.0 - g["open_fraction"]
    g["min_intact"] = MIN_INTACT
    g["ok"] = bool(g["intact_fraction"] >= MIN_INTACT)
    write_json(out / "integrity.json", g)
    s = tension_series(run, gmx)
    F = mean_with_error(s["time"], s["tension_pN"], discard_ps=discard_ps)
    iso = isotension_stretch_modulus(s["time"], s["length_nm"], float(build["temperature_K"]), discard_ps=discard_ps)
    keep = s["time"] >= s["time"][0] + discard_ps
    tension = {"tension_set_pN": T, "formula": s["formula"], "tension_pN": F,
               "test_1": {"sigma_T_pN": F["sem"], "sigma_T_max_pN": SIGMA_T_MAX_PN,
                          "sigma_T_ok": bool(F["sem"] <= SIGMA_T_MAX_PN),
                          "within_2_sigma": bool(abs(F["mean"] - T) < 2.0 * F["sem"])},
               "area_nm2_mean": float(np.mean(s["area_nm2"][keep])), "isotension": iso,
               "discard_ps": discard_ps, "blocks_100_ps": _blocks(s, 100.0)}
    write_json(out / "tension.json", tension)
    means = step_means(run, int(build["n_bp"]), discard_ps)
    write_json(out / "step_means.json", means)
    # the rest shape at the set tension: the ensemble's, which test 1 checks; the measured mean
    # carries an error of 10-20 pN over 1 ns and would add that noise to the rest shape
    cg: dict = {"skipped": "--no-coarse-grain"}
    if coarse_grain:
        n = int(build["n_bp"])
        # the build's pairing (strand I residue k with strand II residue 2n + 1 - k), given
        # explicitly: a pair open in the first frame defeats the automatic pairing
        (out / "pairs.txt").write_text("".join(f"{k} {2 * n + 1 - k}\n" for k in range(1, n + 1)))
        r = subprocess.run([sys.executable, "-m", "dnarod.cli", "coarse-grain", str(run / "conf.gro"),
                            str(run / "md.xtc"), "--pairs", str(out / "pairs.txt"), "--temperature",
                            str(build["temperature_K"]), "--tension", f"{T:g}",
                            "--discard", str(int(round(discard_ps / _frame_spacing_ps(run)))), "-o", str(out / "cg")],
                           capture_output=True, text=True)
        if r.returncode == 2:        # refused (too few independent frames for a stiffness): said in the summary
            cg = {"refused": r.stderr.strip().splitlines()[-1] if r.stderr.strip() else "exit 2"}
        elif r.returncode != 0:
            raise DnarodError(f"dnarod coarse-grain of {run} failed (exit {r.returncode}): {r.stderr[-2000:]}")
        else:
            cg = {"params": out / "cg" / "params.json"}
    return {"build": build, "done": done, "checks": checks, "integrity": g, "tension": tension, "cg": cg,
            "step_means": means}


def step_means(run: Path, n_bp: int, discard_ps: float) -> dict:
    """The mean 3DNA step parameters of the run (every step, the closing one too), each the
    time mean of the step average after the discard with its blocking error (tension.py
    mean_with_error): a mean needs no independent-sample floor, unlike the stiffness, which
    inverts a covariance. The twist is not free: the box fixes the linking number."""
    import warnings
    from mdbridge.geometry.structure import BasePairFrames, load_universe
    from mdbridge.md.builder.duplex import base_pairs
    from mdbridge.md.gromacs.tension import mean_with_error
    u = load_universe(str(run / "conf.gro"), str(run / "md.xtc"))
    bpf = BasePairFrames(u, pairs=base_pairs(n_bp), pair_numbering="serial", pbc=True)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        bpf.run()
    P = bpf.step_parameters(periodic=True)                     # (T, n_bp, 6)
    t = np.asarray(bpf.results.time, float)
    out = {}
    for i, name in enumerate(STEP_NAMES):
        m = mean_with_error(t, P[:, :, i].mean(axis=1), discard_ps=discard_ps)
        out[name] = {"mean": m["mean"], "err": m["sem"], "stationary": m["halves"]["stationary"]}
    return out


def _blocks(s: dict, width_ps: float) -> dict:
    """Means of the box length and the tension over consecutive blocks of WIDTH_PS: how far the
    slow part of both wanders within the record (whole blocks only)."""
    t = np.asarray(s["time"], float)
    edges = np.arange(t[0], t[-1] - width_ps + 1e-9, width_ps)
    rows = [(t >= a) & (t < a + width_ps) for a in edges]
    return {"width_ps": width_ps, "start_ps": edges.tolist(),
            "length_nm": [float(np.mean(s["length_nm"][k])) for k in rows],
            "tension_pN": [float(np.mean(s["tension_pN"][k])) for k in rows]}


def _frame_spacing_ps(run: Path) -> float:
    """The md.xtc frame spacing of the run (nstxout-compressed x dt of its md_run.mdp)."""
    from mdbridge.md.gromacs.mdp import read_mdp_value
    text = (run / "md_run.mdp").read_text() if (run / "md_run.mdp").is_file() else (run / "md.mdp").read_text()
    every, dt = read_mdp_value(text, "nstxout-compressed"), read_mdp_value(text, "dt")
    if not every or not dt:
        raise InputError(f"{run}/md_run.mdp: no nstxout-compressed or dt; cannot tell the frame spacing")
    return float(every) * float(dt)


def published() -> dict:
    """The published solvated-MD values (dna_models/data/published_solvated_md.toml)."""
    return tomllib.loads(PUBLISHED.read_text())


def _against(value: float, err: float, ref: dict) -> dict:
    """One of ours (value +- err) against one published entry: the ratio; with the paper's error,
    whether the two agree within 2 combined errors; with its spread (sd), whether ours lies
    within it."""
    out = {"ours": value, "ours_err": err, "published": ref["value"], "unit": ref["unit"],
           "ratio": value / ref["value"], "source": ref["source"], "corresponds": ref.get("corresponds")}
    if "err" in ref:
        out.update(published_err=ref["err"],
                   within_2_errors=bool(abs(value - ref["value"]) <= 2.0 * float(np.hypot(err, ref["err"]))))
    else:
        out.update(published_sd=ref["sd"], within_published_sd=bool(abs(value - ref["value"]) <= ref["sd"]))
    return out


KJ_PER_KCAL = 4.184


def _complement(step: str) -> str:
    """Step XY read on strand II: Y'X' (' the Watson-Crick partner)."""
    pair = {"A": "T", "T": "A", "G": "C", "C": "G"}
    return pair[step[1]] + pair[step[0]]


def against_lankas(p: dict, ref: dict) -> dict:
    """Our steps' diagonal stiffness (kT units -> kcal/mol at the run's temperature) against the
    per-step constants of Lankas et al. 2003 for the same dimer (or its complement): per dimer
    and parameter the ratio ours / theirs, and per parameter the median ratio over the dimers."""
    kcal = BOLTZMANN_KJ_PER_MOL_K * float(p["temperature_K"]) / KJ_PER_KCAL     # kT in kcal/mol (0.596 at 300 K)
    rows: dict = {}
    for st in p["steps"]:
        d = st["dimer"]
        key = d if d in ref else _complement(d)
        if key not in ref:
            continue
        K = np.diag(np.asarray(st["stiffness"], float)) * kcal
        dK = np.diag(np.asarray(st["stiffness_err"], float)) * kcal
        rows.setdefault(key, []).append((K, dK))
    per_dimer = {}
    for key, v in sorted(rows.items()):
        K = np.mean([k for k, _ in v], axis=0)
        dK = np.sqrt(np.sum([e ** 2 for _, e in v], axis=0)) / len(v)
        per_dimer[key] = {"n_steps": len(v), "ours_kcal": K.tolist(), "ours_err_kcal": dK.tolist(),
                          "published_kcal": ref[key], "ratio": (K / np.asarray(ref[key])).tolist()}
    ratios = np.array([r["ratio"] for r in per_dimer.values()])
    return {"order": list(STEP_NAMES), "units": "kcal/mol/A^2 (shift, slide, rise), kcal/mol/deg^2 (tilt, roll, twist)",
            "per_dimer": per_dimer, "median_ratio": dict(zip(STEP_NAMES, np.median(ratios, axis=0).tolist())),
            "source": ref["source"], "status": ref["status"], "corresponds": ref["corresponds"]}


def olson_mean(sequence: str) -> dict:
    """The mean step of Olson et al. 1998 (protein-DNA crystals) over this ring's dimers: a
    crystal reference at our own sequence."""
    from mdbridge.rod.material.parameter_sets import dimers, olson1998_table
    tab = olson1998_table()["steps"]
    m = np.mean([tab[d][0] for d in dimers(sequence, closed=True)], axis=0)
    return dict(zip(STEP_NAMES, m.tolist()))


def summarise(results: Path, rows: list[dict], stretch: dict | None, ref: dict) -> dict:
    """RESULTS/summary.json: per run the record, the checks and the coarse-grained constants;
    each against the published values (REF, published()) where the quantities correspond."""
    rec: dict = {"runs": {}, "stretch": stretch}
    for r in rows:
        b, T = r["build"], r["tension"]["tension_set_pN"]
        sv = b["solvent"]
        name = f"T{T:g}"
        run = {"tension_set_pN": T, "length_ps": r["done"]["length_ps"], "ns_per_day": r["done"].get("ns_per_day"),
               "threads": r["done"].get("threads"), "n_atoms": sv["n_atoms"], "n_water": sv["n_water"],
               "n_cation": sv["ions"]["n_cation"], "n_anion": sv["ions"]["n_anion"],
               "forcefield": b["forcefield"], "water": sv["model"], "salt_mM": sv["salt_mM"],
               "sequence": b["sequence"],
               "intact_fraction": r["integrity"]["intact_fraction"], "integrity_ok": r["integrity"]["ok"],
               "junction_open_fraction": r["integrity"]["junction_open_fraction"],
               "junction_ok": r["checks"]["junction_ok"], "side_image_ok": r["checks"]["side_image"]["ok"],
               "tension_pN": r["tension"]["tension_pN"]["mean"], "tension_err_pN": r["tension"]["tension_pN"]["sem"],
               "test_1": r["tension"]["test_1"],
               # sigma_T falls as 1 / sqrt(length): the record sigma_T <= SIGMA_T_MAX_PN would need
               "length_ps_for_sigma_T_max": _length_for(r["tension"]),
               "S_isotension_pN": r["tension"]["isotension"]["S_pN"],
               "S_isotension_err_pN": r["tension"]["isotension"]["S_err_pN"],
               "length_blocks_100_ps_nm": r["tension"]["blocks_100_ps"]["length_nm"]}
        run["cg"] = (_cg_figures(json.loads(r["cg"]["params"].read_text()), ref, b) if "params" in r["cg"]
                     else r["cg"])
        run["against_published"] = {"stretch_modulus_isotension": _against(
            run["S_isotension_pN"], run["S_isotension_err_pN"], ref["stretch_modulus"])}
        run["step_means"] = _shape_against(r["step_means"], ref, b)
        rec["runs"][name] = run
    if stretch:
        S, dS = ref["stretch_modulus"]["value"], ref["stretch_modulus"]["err"]
        L0 = rows[0]["tension"]["isotension"]["length_nm"]["mean"]
        pred = L0 * stretch["delta_tension_pN"] / S
        err = float(np.hypot(stretch["delta_length_err_nm"], pred * dS / S))
        stretch["with_published_S"] = {"S_pN": S, "predicted_nm": pred, "predicted_err_nm": pred * dS / S,
                                       "consistent_2_sigma": bool(abs(stretch["delta_length_nm"] - pred) < 2.0 * err)}
    if stretch and stretch.get("S_force_extension_pN"):
        rec["against_published"] = {"stretch_modulus_force_extension": _against(
            stretch["S_force_extension_pN"], stretch["S_force_extension_err_pN"], ref["stretch_modulus"])}
    write_json(results / "summary.json", rec)
    return rec


def _shape_against(means: dict, ref: dict, build: dict) -> dict:
    """The mean step against CHARMM27's published averages and Olson 1998 at our sequence; the
    twist against the box's 360 turns / n_bp."""
    n, turns = int(build["n_bp"]), float(build["turns"])
    return {"means": means, "olson1998_same_sequence": olson_mean(build["sequence"]),
            "twist_fixed_by_the_box": {"turns_per_step_deg": 360.0 * turns / n, "mean_deg": means["twist"]["mean"]},
            "against_published": {f"mean_{k}": _against(means[k]["mean"], means[k]["err"], ref[f"mean_{k}"])
                                  for k in ("rise", "roll", "slide")}}


def _length_for(tension: dict) -> float:
    """The record length (ps, after the discard) at which the tension's error would reach
    SIGMA_T_MAX_PN, from this record's error and 1 / sqrt(length)."""
    w = tension["tension_pN"]["window_ps"]
    return float((w[1] - w[0]) * (tension["tension_pN"]["sem"] / SIGMA_T_MAX_PN) ** 2)


def _cg_figures(p: dict, ref: dict, build: dict) -> dict:
    """The coarse-grained figures docs quote: the mean step (rest shape at the measured tension),
    the rod's K(q -> 0) diagonal, the continuum constants at the longest segment, the effective
    samples; and those of them that published values correspond to."""
    a = p["average"]
    mean = a.get("rest_mean") or a["mean"]
    last = p["by_length"][-1]
    ph = last["physical"]
    frame_ps = float(p["frame_spacing_ps"])
    out = {"mean": dict(zip(STEP_NAMES, mean)), "mean_err": dict(zip(STEP_NAMES, a["mean_err"])),
           "K_diag": dict(zip(STEP_NAMES, np.diag(np.asarray(a["stiffness"], float)).tolist())),
           "K_diag_err": dict(zip(STEP_NAMES, np.diag(np.asarray(a["stiffness_err"], float)).tolist())),
           "K_units": "kT / A^2 (shift, slide, rise), kT / deg^2 (tilt, roll, twist)",
           "m": int(last["m"]), "segment_length_nm": ph["segment_length"]["value"],
           "physical": {k: {"value": ph[k]["value"], "err": ph[k]["err"], "unit": ph[k].get("unit")}
                        for k in ("bend_persistence_length", "torsional_modulus", "stretch_modulus",
                                  "twist_stretch_coupling") if ph.get(k)},
           "effective_samples": p["effective_samples"], "frames_used": p["frames_used"],
           "tau_int_max_ps": float(p["tau_int_max_frames"]) * frame_ps}
    out["against_published"] = {}
    # the ligated box fixes the linking number: the mean twist is 360 turns / n_bp up to the
    # writhe and the 3DNA step twist's bend terms, a check of the unwrapped twist, not a measurement
    n, turns = len(p["steps"]), float(build["turns"])
    out["twist_fixed_by_the_box"] = {"expected_deg": 360.0 * turns / n, "mean_deg": mean[5],
                                     "err_deg": a["mean_err"][5], "difference_deg": mean[5] - 360.0 * turns / n}
    for key in ("rise", "roll", "slide"):
        i = STEP_NAMES.index(key)
        out["against_published"][f"mean_{key}"] = _against(mean[i], a["mean_err"][i], ref[f"mean_{key}"])
    kT = kT_pN_nm(float(p["temperature_K"]))
    for key, scale in (("stretch_modulus", 1.0), ("torsional_modulus", 1.0), ("twist_stretch_coupling", 1.0 / kT)):
        if key in out["physical"]:
            v = out["physical"][key]
            out["against_published"][key] = _against(v["value"] * scale, v["err"] * scale, ref[key])
    out["olson1998_same_sequence"] = olson_mean(p["sequence"])
    out["lankas2003_steps"] = against_lankas(p, ref["lankas2003_steps"])
    return out


def analyse(results, runs, discard_ps: float = DISCARD_PS, gmx: str | None = None,
            coarse_grain: bool = True) -> dict:
    from mdbridge.md.gromacs.tension import force_extension
    results = Path(results)
    ref = published()                                         # every input checked before any work
    records = [_run(Path(run)) for run in runs]
    tensions = [r[2] for r in records]
    if len(set(tensions)) < len(tensions):
        raise InputError(f"two runs at the same tension ({', '.join(f'{T:g}' for T in tensions)} pN): "
                         "give one run per tension")
    rows = [measure_run(Path(run), rec, results / f"T{rec[2]:g}", discard_ps, gmx or "gmx", coarse_grain)
            for run, rec in zip(runs, records)]
    rows.sort(key=lambda r: r["tension"]["tension_set_pN"])
    stretch = None
    if len(rows) > 1:
        lo, hi = rows[0]["tension"], rows[-1]["tension"]
        stretch = force_extension(lo["isotension"]["length_nm"], hi["isotension"]["length_nm"],
                                  hi["tension_set_pN"] - lo["tension_set_pN"], lo["isotension"]["S_pN"],
                                  lo["isotension"]["S_err_pN"])
        n = int(rows[0]["build"]["n_bp"])
        stretch.update({"delta_rise_A": 10.0 * stretch["delta_length_nm"] / n,
                        "predicted_delta_rise_A": 10.0 * stretch["predicted_nm"] / n,
                        "tensions_pN": [lo["tension_set_pN"], hi["tension_set_pN"]]})
        write_json(results / "stretch.json", stretch)
    rec = summarise(results, rows, stretch, ref)
    failed = [f"T{r['tension']['tension_set_pN']:g}: {r['integrity']['intact_fraction']:.3f} of the pair-frames "
              f"intact (< {MIN_INTACT})" for r in rows if not r["integrity"]["ok"]]
    if failed:
        raise DnarodError("the duplex did not stay intact: " + "; ".join(failed)
                               + f" (files written to {results})")
    return rec


def main(argv=None) -> int:
    from dnarod.steps.analyse import run_step
    ap = argparse.ArgumentParser(prog="python3 -m dnarod.steps.water", description=__doc__.splitlines()[0])
    ap.add_argument("results", help="the output folder")
    ap.add_argument("runs", nargs="+", help="finished build-md --solvent + run-md folders, one per tension")
    ap.add_argument("--discard-ps", type=float, default=DISCARD_PS)
    ap.add_argument("--gmx", default=None)
    ap.add_argument("--no-coarse-grain", action="store_true")
    a = ap.parse_args(argv)
    return run_step("water", lambda: analyse(a.results, a.runs, a.discard_ps, a.gmx, not a.no_coarse_grain))


if __name__ == "__main__":
    sys.exit(main())
