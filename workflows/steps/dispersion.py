"""The dispersion steps of `dnarod compare` (workflows/Snakefile; docs/dispersion.md):

    python -m dnarod.steps.dispersion stretch MD_DIR OUT_DIR --factor F
    python -m dnarod.steps.dispersion tension MD_DIR OUT.json [--discard-ps T]
    python -m dnarod.steps.dispersion predict MODES.json -o OUT.json --tension T.json... \
        [--cg CG_DIR...] [--m M] [--replicas R] [--n-fit-max N]
    python -m dnarod.steps.dispersion series NAME=PREDICTION.json... -o OUT.json [--n 1 2 3 4] \
        [--inertia-from PARAMS.json]
    python -m dnarod.steps.dispersion table DISPERSION.json [-o TABLE.md]
    python -m dnarod.steps.dispersion invariance REF=MODES.json NAME=MODES.json... -o OUT.json \
        [--checks NAME=CHECKS.json...]
    python -m dnarod.steps.dispersion block-errors NAME=SERIES.npz:MODES.json... -o OUT.json \
        [--discard-ps T] [--until-ps T] [--kinds bend twist stretch]
    python -m dnarod.steps.dispersion seed-differences NAME=MODES.json:TENSION.json... -o OUT.json \
        [--block-errors BLOCKS.json...] [--md-inertia BUILD_OR_PARAMS.json]

`stretch` copies a build-md folder with its box and coordinates scaled by F along the helix
axis (mdbridge/md/gromacs/tension.py stretch_box), for a run at another box length.

`tension` measures the MD's axial tension from the virial (mdbridge/md/gromacs/tension.py:
-P_aa x A from MD_DIR/md.edr, through `gmx energy`) after the discarded start, with its
blocking error.

`predict` turns the coarse-grained material of each seed (CG_DIR/replicas.h5, through
mdbridge.coarsegrain.cgrod.materials: the central material and its bootstrap replicas) and
the paper's rod into every mode's predicted frequency at the MD's tension (seeds pooled),
compares them with the MD's measured modes (`dnarod modes` -> MODES.json) as z-scores, and
fits the MD's own T and B to its lowest bend frequencies and, independently, to the static
variances of their fitted oscillators (`dnarod modes` oscillator_variance; the record's whole
variance is fitted beside; docs/dispersion.md, "The statics";
mdbridge/analysis/dispersion_prediction.py). A coarse-graining that was refused
leaves the paper rod's prediction and says why.

`series` sets the bend frequencies of runs that differ in tension (seeds, box lengths) against
their virial tensions: per mode, the slope of omega0^2 against T, which the rod predicts with no
stiffness in it (k^2 / mu for a string; mdbridge/analysis/tension_series.py).

With `--md-inertia` (the MD's build.json or a coarse-graining's params.json) `predict` adds
`paper_rod_box`: the paper's rod at the MD's box length (Gamma3 = 1 under the MD's tension) with
the MD's own rho and I (mdbridge/analysis/box_rod.py), beside `paper_rod`.

`table` prints (or writes) a dispersion.json's prediction-vs-MD table as Markdown
(dnarod.report.dispersion.markdown_table).

`invariance` sets the modes of runs that differ from a reference run in one setting only (a
thermostat switched off, a shorter time step) against the reference's, mode by mode, and pools
the bend modes n >= 3 (docs/md.md, "Does the drift move what is measured?"); each run's energy
record (run-md's checks.json) goes beside it.

`block-errors` gives every mode's frequency an error from the scatter of independent blocks of
each realisation's record, pooled over the realisations (mdbridge/analysis/block_errors.py):
SERIES.npz is the realisation's mode_series.npz (its first realisation, cut to the window),
MODES.json its `dnarod modes` table of the same window.

`seed-differences` compares realisations that differ in tension mode by mode: each one's
frequency minus the linear rod's at its own virial tension, the tension's error carried
through d omega / dT, and the chi^2 of the differences per kind and pooled, with the fit
errors and with the block errors (mdbridge/analysis/seed_comparison.py).
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

from dna_models.errors import DnarodError, InputError
from mdbridge.jsonio import write_json
from mdbridge.md.gromacs.defaults import TEMPERATURE_K

from dnarod.steps.analyse import run_step

KINDS = ("bend", "twist", "stretch")


def measure_tension(md_dir, out, discard_ps: float = 0.0, gmx: str | None = None) -> dict:
    """OUT.json: the MD's mean axial tension [pN] after discard_ps, with its error."""
    from mdbridge.md.gromacs.gmx import find_gmx
    from mdbridge.md.gromacs.tension import tension_series
    d = Path(md_dir)
    s = tension_series(d, find_gmx(gmx))
    rec = tension_record(s["time"], s["tension_pN"], s["length_nm"], discard_ps, d / "md.edr")
    rec = {"md_dir": str(d), **rec, "axis": s["axis"], "temperature_K": _build_temperature(d)}
    write_json(out, rec)
    return rec


def tension_record(time_ps, tension_pN, length_nm, discard_ps: float, source) -> dict:
    """The mean axial tension after discard_ps with its error and stationarity, and the mean
    box length, of one record's tension series (from md.edr, or a run's joined segments)."""
    from mdbridge.md.gromacs.tension import mean_with_error
    t = np.asarray(time_ps, float)
    if len(t) < 16 or discard_ps >= t[-1] - t[0]:
        raise InputError(f"{source}: {len(t)} energy frames over {t[-1] - t[0] if len(t) else 0:g} ps; the "
                         f"tension needs a record longer than the discarded {discard_ps:g} ps")
    m = mean_with_error(t, tension_pN, discard_ps=discard_ps)
    keep = t >= t[0] + discard_ps
    return {"tension_pN": m["mean"], "tension_err_pN": m["sem"], "discard_ps": discard_ps,
            "window_ps": m["window_ps"], "stationary": m["halves"]["stationary"], "halves": m["halves"],
            "box_length_A": float(np.mean(np.asarray(length_nm, float)[keep])) * 10.0,
            "definition": "F = -P_aa A (virial, kinetic term included; mdbridge/md/gromacs/tension.py); error: "
                          + m["sem_rule"]}


def _build_temperature(d: Path):
    """The MD's reference temperature (its thermostat's, build.json), None when not recorded."""
    bj = d / "build.json"
    t = json.loads(bj.read_text()).get("temperature_K") if bj.is_file() else None
    return float(t) if t else None


def _pooled_tension(records: list[dict]) -> tuple[float, float]:
    from dnarod.report.values import mean_over_seeds
    return mean_over_seeds([r["tension_pN"] for r in records], [r["tension_err_pN"] for r in records])


def _materials(cg_dirs, m: int | None, n_replicas: int):
    """[(seed dir, central, replicas)] of the seeds whose coarse-graining succeeded, and the
    reasons of those that did not."""
    from mdbridge.coarsegrain.cgrod import materials, read_replicas
    from mdbridge.rod.linear import UniformMaterial
    ok, reasons = [], []
    for d in map(Path, cg_dirs):
        rec = json.loads((d / "cg.json").read_text()) if (d / "cg.json").is_file() else {}
        if not rec.get("ok"):
            reasons.append(f"{d}: coarse-graining refused: {rec.get('reason', 'cg.json missing')}")
            continue
        try:
            central, boot = materials(read_replicas(d / "replicas.h5"), m, n_replicas)
        except InputError as e:
            reasons.append(f"{d}: {e}")
            continue
        ok.append((d, UniformMaterial.from_dict(central),
                   [UniformMaterial.from_dict(b) for b in boot if b is not None]))
    return ok, reasons


def _pool_predictions(preds: list[dict]) -> dict:
    """The seeds' predictions as one: mean over seeds, error from each seed's error and the
    between-seed scatter (dnarod.report.values.mean_over_seeds)."""
    from dnarod.report.values import mean_over_seeds
    if len(preds) == 1:
        return preds[0]
    out = dict(preds[0], seeds=len(preds), modes=[])
    for i, m0 in enumerate(preds[0]["modes"]):
        w, e = mean_over_seeds([p["modes"][i]["omega_per_ps"] for p in preds],
                               [p["modes"][i]["omega_err_per_ps"] for p in preds])
        out["modes"].append(dict(m0, omega_per_ps=w, omega_err_per_ps=e))
    return out


def _fit(kind_rows, observable, template, duplex, T0):
    """The T/B fit of one observable, or its refusal."""
    from mdbridge.analysis.dispersion_prediction import fit_tension_bend
    key, err = {"omega": ("md_omega0_per_ps", "md_omega0_err_per_ps"),
                "variance": ("md_oscillator_variance_A2", "md_oscillator_variance_err_A2"),
                "total_variance": ("md_variance_A2", "md_variance_err_A2")}[observable]
    use = [r for r in kind_rows if r.get(key) is not None and r.get(err)]
    ns = [r["n"] for r in use]
    try:
        return fit_tension_bend(ns, [r[key] for r in use], [r[err] for r in use], template, duplex,
                                "omega" if observable == "omega" else "variance", T0)
    except DnarodError as e:
        return {"observable": observable, "n": ns, "reason": str(e)}


def _predictions(paper, mats, cg_reasons, duplex, T, T_err, n_max, md_inertia=None) -> tuple[dict, dict, str | None]:
    """(predictions, refused) by model: the paper's rod; the coarse-grained one as it is, and
    with its intrinsic twist at the box's (torque-free when ligated); a rod that buckles at
    the MD's tension is refused with the reason. With md_inertia (a build.json or params.json),
    also the paper's rod at the box's length with the MD's own rho and I; the third item
    names where that mass and inertia came from (None without)."""
    from mdbridge.analysis.dispersion_prediction import box_twist, predict
    predictions, refused = {}, {}
    models: list[tuple[str, list]] = [("paper_rod", [(paper, [])])]     # per seed: (material, replicas)
    box_source = None
    if md_inertia is not None:
        # the paper's rod at the box's length with the MD's own mass and inertia (mdbridge/analysis/box_rod.py)
        from mdbridge.analysis.box_rod import md_mass_inertia, paper_rod_box
        mi = md_mass_inertia(md_inertia)
        box_source = mi["source"]
        models.append(("paper_rod_box", [(paper_rod_box(paper, T, mi["rho_star"], mi["I_star"]), [])]))
    if mats:
        models.append(("cg_rod", [(c, reps) for _, c, reps in mats]))
        models.append(("cg_rod_box_twist", [(box_twist(c, duplex), [box_twist(r, duplex) for r in reps])
                                            for _, c, reps in mats]))
    for name, seeds in models:
        try:
            predictions[name] = _pool_predictions([predict(c, duplex, T, T_err, reps, n_max) for c, reps in seeds])
        except DnarodError as e:
            refused[name] = f"no prediction at the MD's tension {T:.3g} +- {T_err:.2g} pN: {e}"
    if not mats:
        refused["cg_rod"] = refused["cg_rod_box_twist"] = "; ".join(cg_reasons) or "no coarse-graining"
    return predictions, refused, box_source


def _rows(table: dict, predictions: dict) -> list:
    """Per MD mode: the comparison with each prediction and the MD's own numbers."""
    from mdbridge.analysis.dispersion_prediction import compare
    rows = compare(table["modes"], predictions)
    for r, entry in zip(rows, table["modes"]):
        bend = entry["kind"] == "bend"
        r.update(md_omega_damped_per_ps=entry.get("omega_per_ps"), md_damping_per_ps=entry.get("damping_per_ps"),
                 md_variance_A2=entry.get("variance") if bend else None,
                 md_variance_err_A2=entry.get("variance_err") if bend else None,
                 md_oscillator_variance_A2=entry.get("oscillator_variance") if bend else None,
                 md_oscillator_variance_err_A2=entry.get("oscillator_variance_err") if bend else None,
                 k_per_A=2 * np.pi * r["n"] / table["length_A"])
    return rows


def _statics_over_dynamics(rows, template, duplex, dyn) -> list:
    """Every measured oscillator variance over the variance of the rod the dynamics fit gives
    (its T and B, the template's every other constant): where the statics agree with the
    dynamics, mode by mode, beyond the modes the fits use."""
    if dyn.get("tension_pN") is None:
        return []
    from mdbridge.analysis.dispersion_prediction import bend_variances_A2, scaled_bend
    use = [r for r in rows if r["kind"] == "bend" and r.get("md_oscillator_variance_A2") is not None]
    if not use:
        return []
    rod = bend_variances_A2(scaled_bend(template, dyn["bend_scale_of_template"]), duplex, dyn["tension_pN"],
                            [r["n"] for r in use])
    return [{"n": r["n"], "ratio": r["md_oscillator_variance_A2"] / v,
             "ratio_err": r["md_oscillator_variance_err_A2"] / v, "rod_variance_A2": float(v)}
            for r, v in zip(use, rod)]


def _checks(dyn: dict, stat: dict, T: float, T_err: float) -> dict:
    """z of the dynamics' and the statics' tension against the virial's, and of their B."""
    from mdbridge.analysis.dispersion_prediction import z_score

    def z(a, b, key):
        err = {"tension_pN": "tension_err_pN", "B_pN_nm2": "B_err_pN_nm2"}[key]
        return z_score(a.get(key), a.get(err), b.get(key), b.get(err))
    virial = {"tension_pN": T, "tension_err_pN": T_err}
    return {"z_T_dynamics_vs_virial": z(dyn, virial, "tension_pN"),
            "z_T_statics_vs_virial": z(stat, virial, "tension_pN"),
            "z_B_dynamics_vs_statics": z(dyn, stat, "B_pN_nm2")}


def predict_and_compare(modes_json, out, tension_jsons, cg_dirs=(), m: int | None = None, n_replicas: int = 20,
                        n_fit_max: int = 4, temperature_K: float | None = None, md_inertia=None) -> dict:
    from mdbridge.analysis.dispersion_prediction import (Duplex, bend_stiffness_pN_nm2, box_twist, paper_material,
                                                         persistence_nm)
    table = json.loads(Path(modes_json).read_text())
    tensions = [json.loads(Path(p).read_text()) for p in tension_jsons]
    if not tensions:
        raise InputError("no tension file: the prediction is taken at the MD's measured tension")
    T, T_err = _pooled_tension(tensions)
    temp = float(temperature_K or tensions[0].get("temperature_K") or TEMPERATURE_K)
    duplex = Duplex(int(table["n_bp"]), int(table["helical_repeat"]), temp)
    n_max = int(table["helical_repeat"]) - 1
    paper = paper_material(duplex)
    mats, cg_reasons = _materials(cg_dirs, m, n_replicas)
    predictions, refused, box_source = _predictions(paper, mats, cg_reasons, duplex, T, T_err, n_max, md_inertia)
    rows = _rows(table, predictions)
    # the MD's own T and B: the lowest bend modes that are measured
    # the template: the coarse-grained material (mass, inertia, shear, stretch, couplings of the
    # MD) with the box's twist, as the MD's mean state is (the ligation's torque is unknown)
    template, template_name = (box_twist(mats[0][1], duplex), f"the coarse-grained material of {mats[0][0]}, "
                               "intrinsic twist at the box's") if mats else \
        (paper, "the paper's rod (no coarse-grained material: " + "; ".join(cg_reasons) + ")")
    low = [r for r in rows if r["kind"] == "bend" and r["n"] <= n_fit_max]
    # statics: the oscillators' own variances (modes.json oscillator_variance), without the
    # floor and the slow background; the record's total variance is fitted too, to show
    # what that background does (docs/dispersion.md, "The statics")
    fits = {obs: _fit(low, obs, template, duplex, T) for obs in ("omega", "variance", "total_variance")}
    dyn, stat = fits["omega"], fits["variance"]
    over_dyn = _statics_over_dynamics(rows, template, duplex, dyn)
    checks = _checks(dyn, stat, T, T_err)
    refs = {name: {"B_pN_nm2": bend_stiffness_pN_nm2(mat),
                   "persistence_length_nm": persistence_nm(bend_stiffness_pN_nm2(mat), temp)}
            for name, mat in ([("paper_rod", paper)] + ([("cg_rod", mats[0][1])] if mats else []))}
    # the twist and stretch modes' inertia from kinetic equipartition, against the paper's and
    # the coarse-grained material's (docs/dispersion.md, "What moves the twist modes")
    from mdbridge.analysis.dispersion_prediction import axial_inertia_table
    inertia = axial_inertia_table(table["modes"], duplex.n_bp, table["length_A"], temp,
                                  {"paper_rod": paper, **({"cg_rod": mats[0][1]} if mats else {})})
    rec = {"n_bp": duplex.n_bp, "turns": duplex.turns, "length_A": table["length_A"],
           "record_ps": table.get("record_ps"), "temperature_K": temp,
           "tension": {"tension_pN": T, "tension_err_pN": T_err, "per_seed": tensions},
           "rows": rows, "predictions": predictions,
           **({"paper_rod_box": {"mass_inertia": box_source,
                                 "definition": "the paper's stiffness at Gamma3 = 1 at the box's length under the "
                                               "MD's tension (Gamma0_3 = 1 - T / C3), with the MD's own rho and I "
                                               "(mdbridge/analysis/box_rod.py)"}} if box_source else {}),
           "refused": refused, "cg_rod_reason": refused.get("cg_rod"),
           "cg_notes": cg_reasons if mats else [],
           "fit": {"template": template_name, "n_fit_max": n_fit_max, "dynamics": dyn, "statics": stat,
                   "statics_total_variance": fits["total_variance"], "statics_over_dynamics_rod": over_dyn,
                   **checks, "materials": refs, "axial_inertia": inertia},
           "definition": "rows: per MD mode, the MD's undamped frequency omega0 = sqrt(omega^2 + gamma^2) "
                         "(dnarod modes) and the linear rod's (mdbridge/rod/linear.py) of the coarse-grained "
                         "and the paper's material at the MD's virial tension; errors: MD fit; rod: material "
                         "replicas and tension error in quadrature; z = (MD - rod) / sqrt(err_MD^2 + err_rod^2). "
                         "fit: T and B of the linear rod that reproduce the MD's lowest bend frequencies "
                         "(dynamics) and the static variances of their fitted oscillators (statics; "
                         "statics_total_variance: the record's whole variance), every other constant the template's "
                         "(docs/dispersion.md)"}
    write_json(out, rec)
    return rec


def tension_series(predictions: dict[str, Path], out, ns=(1, 2, 3, 4), inertia_from: Path | None = None) -> dict:
    """The bend frequencies against the virial tension across runs of one duplex (other seeds,
    other box lengths): each run's `predict` output (prediction.json) gives its tension and
    omega0 per mode; per mode n, the measured slope of omega0^2 against T and the linear
    rod's (mdbridge/analysis/tension_series.py). The rod: the paper's material, with the
    atoms' own mass and inertia when `inertia_from` (a coarse-graining's params.json, rod
    rho_star and I_star) is given."""
    from mdbridge.analysis.dispersion_prediction import Duplex, paper_material
    from mdbridge.analysis.tension_series import frequency_against_tension
    from mdbridge.rod.linear import UniformMaterial
    records = {name: json.loads(path.read_text()) for name, path in predictions.items()}
    first = next(iter(records.values()))
    runs = []
    for name, p in records.items():
        path = predictions[name]
        if (p["n_bp"], p["turns"]) != (first["n_bp"], first["turns"]):
            raise InputError(f"{path}: {p['n_bp']} bp, {p['turns']} turns; the first run has "
                             f"{first['n_bp']} bp, {first['turns']} turns: a series is of one duplex")
        bend = {r["n"]: (r["md_omega0_per_ps"], r["md_omega0_err_per_ps"]) for r in p["rows"] if r["kind"] == "bend"}
        runs.append({"name": name, "source": str(path), "tension_pN": p["tension"]["tension_pN"],
                     "tension_err_pN": p["tension"]["tension_err_pN"], "length_A": p["length_A"],
                     "record_ps": p.get("record_ps"), "omega0": bend,
                     "dynamics_tension_pN": p["fit"]["dynamics"].get("tension_pN"),
                     "dynamics_tension_err_pN": p["fit"]["dynamics"].get("tension_err_pN"),
                     "dynamics_B_pN_nm2": p["fit"]["dynamics"].get("B_pN_nm2"),
                     "dynamics_B_err_pN_nm2": p["fit"]["dynamics"].get("B_err_pN_nm2")})
    duplex = Duplex(int(first["n_bp"]), int(first["turns"]), float(first["temperature_K"]))
    mat, inertia = paper_material(duplex), "the paper's"
    if inertia_from is not None:
        rod = json.loads(Path(inertia_from).read_text())["rod"]
        mat = UniformMaterial(K=mat.K, I=np.asarray(rod["I_star"], float), rho=float(rod["rho_star"]),
                              Gamma0=mat.Gamma0, Omega0=mat.Omega0)
        inertia = f"the atoms' own ({inertia_from}: rod rho_star, I_star)"
    rec = {"runs": [{k: v for k, v in r.items() if k != "omega0"} | {"omega0_per_ps": {str(n): w for n, w in
                                                                                      r["omega0"].items()}}
                    for r in runs],
           "material": f"the paper's stiffness, {inertia} mass and inertia", "rho_rod_units": float(mat.rho),
           "modes": frequency_against_tension(runs, mat, duplex, [int(n) for n in ns]),
           "definition": "per bend mode n: the straight line omega0^2 = a + slope T through the runs (T the "
                         "virial tension, both errors), against the linear rod's d omega^2/dT at the runs' mean "
                         "tension; z = (measured - rod) / measured error (mdbridge/analysis/tension_series.py)"}
    write_json(out, rec)
    return rec


def _named(pairs: list[str], what: str) -> dict[str, Path]:
    named = {}
    for pair in pairs:
        name, sep, path = pair.partition("=")
        if not sep or not name or not Path(path).is_file():
            raise InputError(f"{what} {pair!r}: expected NAME=FILE with an existing FILE")
        named[name] = Path(path)
    return named


def _named_pairs(pairs: list[str], what: str) -> dict[str, tuple[Path, Path]]:
    """NAME=A:B arguments, each file existing."""
    named = {}
    for pair in pairs:
        name, sep, files = pair.partition("=")
        a, sep2, b = files.partition(":")
        if not sep or not sep2 or not name or not Path(a).is_file() or not Path(b).is_file():
            raise InputError(f"{what} {pair!r}: expected NAME=FILE:FILE with both files existing")
        named[name] = (Path(a), Path(b))
    return named


def block_errors_step(runs: dict[str, tuple[Path, Path]], out, discard_ps: float = 0.0,
                      until_ps: float | None = None, kinds=KINDS) -> dict:
    """OUT.json: every mode's block error (mdbridge/analysis/block_errors.py), pooled over the
    realisations `runs` (name -> (mode_series.npz, modes.json of the same window))."""
    from mdbridge.analysis.block_errors import (BLOCK_CORRELATION_TIMES, BLOCK_COUNTS, BLOCK_PERIODS,
                                                mode_block_errors)
    from mdbridge.analysis.mode_spectra import load_npz
    series, tables = [], []
    for name, (npz, modes) in runs.items():
        s = load_npz(npz)[0].after(discard_ps, until_ps)
        t = json.loads(modes.read_text())
        if abs(t["n_frames"] - len(s.times_ps)) > 1:
            raise InputError(f"{modes}: {t['n_frames']} frames, but {npz} cut to {discard_ps:g}-{until_ps} ps holds "
                             f"{len(s.times_ps)}: the table must be of the same window")
        series.append(s)
        tables.append(t)
    rows = mode_block_errors(series, tables, kinds)
    rec = {"runs": {k: [str(a), str(b)] for k, (a, b) in runs.items()}, "discard_ps": discard_ps,
           "until_ps": until_ps, "kinds": list(kinds),
           "open_fraction": {name: (None if s.open_fraction is None else float(np.mean(s.open_fraction)))
                             for name, s in zip(runs, series)},
           "rule": {"block_periods": BLOCK_PERIODS, "block_correlation_times": BLOCK_CORRELATION_TIMES,
                    "block_counts": list(BLOCK_COUNTS)},
           "modes": rows,
           "definition": "per mode: each realisation's record cut into the most blocks (of block_counts) that hold "
                         "block_periods periods and block_correlation_times times 1/gamma each; every mode of the kind "
                         "fitted per block as in `dnarod modes`; the blocks' relative scatter pooled over the "
                         "realisations; err = omega s / sqrt(blocks), "
                         "err_chi2 = err sqrt(nu / (nu - 2)) (Student-t); mdbridge/analysis/block_errors.py"}
    write_json(out, rec)
    return rec


def seed_differences_step(runs: dict[str, tuple[Path, Path]], out, block_files: tuple | list = (),
                          md_inertia=None, n_max: int = 14) -> dict:
    """OUT.json: realisations (name -> (modes.json, tension.json of the same window)) against the
    first, mode by mode, each minus the linear rod at its own virial tension
    (mdbridge/analysis/seed_comparison.py): chi^2 per kind and pooled, with the fit errors and,
    given block-errors outputs of these realisations, with the block errors; beside them the
    same without the tension correction (the control), and the open fraction of each record."""
    from mdbridge.analysis.dispersion_prediction import Duplex, md_natural_frequency, paper_material
    from mdbridge.analysis.seed_comparison import compare_realisations
    names = list(runs)
    tables = {k: json.loads(m.read_text()) for k, (m, _) in runs.items()}
    tensions = {k: json.loads(t.read_text()) for k, (_, t) in runs.items()}
    t0 = tables[names[0]]
    duplex = Duplex(int(t0["n_bp"]), int(t0["helical_repeat"]), float(tensions[names[0]].get("temperature_K") or 300))
    TdT = [(float(tensions[k]["tension_pN"]), float(tensions[k]["tension_err_pN"])) for k in names]
    paper = paper_material(duplex)
    mats, rod_name, rod_source = [paper] * len(names), "paper_rod", "the paper's rod (Sec 2.1-2.2)"
    if md_inertia is not None:
        from mdbridge.analysis.box_rod import md_mass_inertia, paper_rod_box
        mi = md_mass_inertia(md_inertia)
        mats = [paper_rod_box(paper, T, mi["rho_star"], mi["I_star"]) for T, _ in TdT]
        rod_name, rod_source = "paper_rod_box", mi["source"]
    fit = [{(e["kind"], int(e["n"])): md_natural_frequency(e) for e in tables[k]["modes"]} for k in names]
    damped = [{(e["kind"], int(e["n"])): (e.get("omega_per_ps"), e.get("omega_err_per_ps"))
               for e in tables[k]["modes"]} for k in names]
    variants: dict = {}

    def both(label, md):
        variants[label] = {"tension_corrected": compare_realisations(md, TdT, mats, duplex, n_max),
                           "raw": compare_realisations(md, TdT, None, duplex, n_max)}

    both("fit_errors", fit)
    variants["fit_errors_damped_raw"] = {"raw": compare_realisations(damped, TdT, None, duplex, n_max)}
    blocks = {}
    for f in block_files:
        rec = json.loads(Path(f).read_text())
        order = list(rec["runs"])
        if sorted(order) != sorted(names):
            raise InputError(f"{f}: block errors of {order}; the runs are {names}")
        for e in rec["modes"]:
            b = e.get("omega0_block") or {}
            if b.get("err_chi2"):
                blocks[(e["kind"], int(e["n"]))] = {name: (e["omega0_per_ps"][order.index(name)],
                                                           b["err_chi2"][order.index(name)]) for name in order}
    if blocks:
        md_block = [{key: v[k] for key, v in blocks.items()} for k in names]
        both("block_errors", md_block)
    rec = {"runs": {k: [str(a), str(b)] for k, (a, b) in runs.items()}, "reference": names[0],
           "tension_pN": {k: {"tension_pN": T, "tension_err_pN": dT} for k, (T, dT) in zip(names, TdT)},
           "open_fraction": {k: [r.get("open_fraction", {}).get("mean") for r in tables[k].get("realisations", [])]
                             for k in names},
           "rod": {"name": rod_name, "mass_inertia": rod_source}, "block_error_files": [str(f) for f in block_files],
           "variants": variants,
           # the headline: the tension-corrected differences, with the block errors when given
           "differences_by_kind": variants["block_errors" if blocks else "fit_errors"]["tension_corrected"][
               "differences_by_kind"],
           "errors": "block_errors" if blocks else "fit_errors",
           "definition": "per mode: each realisation's MD omega0 minus the linear rod's at that realisation's own "
                         "virial tension, err^2 = err_md^2 + (d omega_rod/dT dT)^2; per kind chi2 = sum z^2 of the "
                         "differences against the reference, dof the number of modes; raw: the MD's omega0 without "
                         "the rod (no tension correction: the control); fit_errors_damped_raw: the damped omega with "
                         "the fit errors, as the invariance step's differences_by_kind (mdbridge/analysis/"
                         "seed_comparison.py)"}
    write_json(out, rec)
    return rec


def pooled_relative_difference(rows: list[dict], name: str, reference: str, n_min: int = 3) -> dict | None:
    """Weighted mean of omega_name / omega_reference - 1 over the bend modes n >= N_MIN that
    both records resolve (first-order error propagation), its standard error, and the chi2
    of the differences about it."""
    diff, err = [], []
    for x in rows:
        a, b = x.get(f"{name}_omega_per_ps"), x.get(f"{reference}_omega_per_ps")
        if x["kind"] == "bend" and x["n"] >= n_min and a and b:
            diff.append(a / b - 1)
            err.append(np.hypot(x[f"{name}_omega_err_per_ps"] / a, x[f"{reference}_omega_err_per_ps"] / b))
    if len(diff) < 2:
        return None
    r, e = np.array(diff), np.array(err)
    w = 1 / e**2
    mean = float((w * r).sum() / w.sum())
    return {"modes": len(r), "mean": mean, "err": float(w.sum() ** -0.5),
            "chi2": float((((r - mean) / e) ** 2).sum()), "dof": len(r) - 1,
            "max_abs_z": float(np.abs(r / e).max())}


def differences_by_kind(rows: list[dict], name: str, reference: str) -> dict:
    """Per kind, over the modes both records resolve: chi2 = sum z^2 of z = (omega_name -
    omega_reference) / sqrt(err_name^2 + err_reference^2), its dof (the number of modes) and
    those n. Two independent realisations of one system give chi2 ~ dof when the stated
    errors are the scatter between realisations (docs/results.md, "A second seed")."""
    out: dict = {}
    for x in rows:
        a, b = x.get(f"{name}_omega_per_ps"), x.get(f"{reference}_omega_per_ps")
        if a and b:
            z = (a - b) / np.hypot(x[f"{name}_omega_err_per_ps"], x[f"{reference}_omega_err_per_ps"])
            e = out.setdefault(x["kind"], {"chi2": 0.0, "dof": 0, "n": []})
            e["chi2"] += float(z * z)
            e["dof"] += 1
            e["n"].append(x["n"])
    return out


def compare_runs(modes: dict[str, Path], reference: str, out, checks: dict[str, Path] | None = None) -> dict:
    """The invariance record: one row per mode with every run's omega, error and reason."""
    if reference not in modes:
        raise InputError(f"invariance: the reference {reference!r} is not among the runs {sorted(modes)}")
    rows: dict[tuple, dict] = {}
    for name, path in modes.items():
        for m in json.loads(path.read_text())["modes"]:
            row = rows.setdefault((KINDS.index(m["kind"]), m["n"]), {"kind": m["kind"], "n": m["n"]})
            row[f"{name}_omega_per_ps"] = m["omega_per_ps"]
            row[f"{name}_omega_err_per_ps"] = m["omega_err_per_ps"]
            row[f"{name}_reason"] = m["reason"]
    ordered = [rows[k] for k in sorted(rows)]
    rec = {"reference": reference, "modes": {k: str(v) for k, v in modes.items()}, "rows": ordered,
           "pooled_bend_n3": {name: pooled_relative_difference(ordered, name, reference)
                              for name in modes if name != reference},
           "differences_by_kind": {name: differences_by_kind(ordered, name, reference)
                                   for name in modes if name != reference},
           "energy": {name: json.loads(p.read_text())["energy"] for name, p in (checks or {}).items()}}
    write_json(out, rec)
    return rec


def _add_error_steps(sub) -> None:
    """The subcommands of the errors that cover realisations (docs/dispersion.md)."""
    p = sub.add_parser("block-errors")
    p.add_argument("runs", nargs="+", help="NAME=SERIES.npz:MODES.json (one per realisation)")
    p.add_argument("-o", "--output", required=True)
    p.add_argument("--discard-ps", type=float, default=0.0)
    p.add_argument("--until-ps", type=float, default=None)
    p.add_argument("--kinds", nargs="+", default=list(KINDS), choices=KINDS)
    p = sub.add_parser("seed-differences")
    p.add_argument("runs", nargs="+", help="NAME=MODES.json:TENSION.json (one per realisation; the first is the "
                                           "reference)")
    p.add_argument("-o", "--output", required=True)
    p.add_argument("--block-errors", nargs="*", default=[], help="block-errors outputs of the same realisations")
    p.add_argument("--md-inertia", default=None,
                   help="the MD's build.json (its atoms' mass and inertia) or a coarse-graining's params.json: the "
                        "rod of the tension correction gets them")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m dnarod.steps.dispersion", description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="step", required=True)
    _add_error_steps(sub)
    p = sub.add_parser("stretch")
    p.add_argument("md_dir")
    p.add_argument("out_dir")
    p.add_argument("--factor", type=float, required=True)
    p = sub.add_parser("tension")
    p.add_argument("md_dir")
    p.add_argument("out")
    p.add_argument("--discard-ps", type=float, default=0.0)
    p = sub.add_parser("predict")
    p.add_argument("modes")
    p.add_argument("-o", "--output", required=True)
    p.add_argument("--tension", nargs="+", required=True)
    p.add_argument("--cg", nargs="*", default=[])
    p.add_argument("--m", type=int, default=None,
                   help="the m-step compliance average as the rod's K (default: K(q -> 0), docs/coarse-graining.md)")
    p.add_argument("--replicas", type=int, default=20)
    p.add_argument("--n-fit-max", type=int, default=4)
    p.add_argument("--temperature", type=float, default=None)
    p.add_argument("--md-inertia", default=None,
                   help="the MD's build.json or a coarse-graining's params.json: adds the paper_rod_box prediction "
                        "(the paper's rod at the box's length with the MD's rho and I)")
    p = sub.add_parser("series")
    p.add_argument("runs", nargs="+", help="NAME=PREDICTION.json (each run's predict output)")
    p.add_argument("-o", "--output", required=True)
    p.add_argument("--n", type=int, nargs="+", default=[1, 2, 3, 4])
    p.add_argument("--inertia-from", default=None, help="a coarse-graining's params.json: the atoms' mass and inertia")
    p = sub.add_parser("table")
    p.add_argument("dispersion")
    p.add_argument("-o", "--output", default=None)
    p = sub.add_parser("invariance")
    p.add_argument("runs", nargs="+", help="NAME=MODES.json; the first is the reference")
    p.add_argument("-o", "--output", required=True)
    p.add_argument("--checks", nargs="*", default=[], help="NAME=CHECKS.json (run-md's), for the energy record")
    a = ap.parse_args(argv)

    def step():
        if a.step == "stretch":
            from mdbridge.md.gromacs.tension import stretch_box
            print(stretch_box(Path(a.md_dir), Path(a.out_dir), a.factor))
        elif a.step == "tension":
            measure_tension(a.md_dir, a.out, a.discard_ps)
        elif a.step == "block-errors":
            block_errors_step(_named_pairs(a.runs, "block-errors: run"), a.output, a.discard_ps, a.until_ps,
                              tuple(a.kinds))
        elif a.step == "seed-differences":
            seed_differences_step(_named_pairs(a.runs, "seed-differences: run"), a.output,
                                  [Path(p) for p in a.block_errors], a.md_inertia)
        elif a.step == "invariance":
            runs = _named(a.runs, "invariance: run")
            compare_runs(runs, next(iter(runs)), a.output, _named(a.checks, "invariance: --checks"))
        elif a.step == "series":
            tension_series(_named(a.runs, "series: run"), a.output, a.n, a.inertia_from)
        elif a.step == "table":
            from dnarod.report.dispersion import markdown_table
            if not Path(a.dispersion).is_file():
                raise InputError(f"{a.dispersion}: no such file (the dispersion step writes "
                                 "dispersion/box1/dispersion.json)")
            text = markdown_table(json.loads(Path(a.dispersion).read_text()))
            if a.output:
                Path(a.output).write_text(text)
            else:
                print(text, end="")
        else:
            predict_and_compare(a.modes, a.output, a.tension, a.cg, a.m, a.replicas, a.n_fit_max, a.temperature,
                                a.md_inertia)
    return run_step(f"dispersion {a.step}", step)


if __name__ == "__main__":
    sys.exit(main())
