"""The kicked MD's speed between realisations of one setting: the floor that a single run's
error gets in the report (docs/results.md, "The rod against the MD").

One kicked MD record states the error of its own fit (mdbridge/analysis/mode_error.py), not
the scatter between records of the same setting: what the kick lands on (the thermal state)
and mdrun's non-reproducibility on 2 threads make every rerun a new realisation. The main
job's reruns of one seed differ by several of their stated errors (Q = 16 for 2 dof). So
results/main_job_realisations.json lists the realisations of the main job's setting (each
run's speed and its one-record error), and a run of that setting with one seed states

    err = sqrt(err_record^2 + floor^2),

the floor from those realisations by mdbridge/analysis/realisation_floor.py (the upper end of
tau's 68 % interval below 6 realisations, tau itself from 6 on). A run of another setting
has no measured floor; the report then says that its error is one record's.

`record(path, rec)` appends a committed main-job record's realisation and rewrites the file's
summary (scripts/record_run.py commit); tests/python/test_report_realisations.py holds the
floor to the committed realisations' spread, with the one-record error as the control.
"""
from __future__ import annotations

import json
import math
from pathlib import Path

from dnarod.configuration import md_build_args
from mdbridge.analysis.realisation_floor import between_realisation_floor
from mdbridge.jsonio import write_json

ROOT = Path(__file__).resolve().parents[2]
RECORD = ROOT / "results" / "main_job_realisations.json"


def setting(cfg: dict) -> dict:
    """What makes two kicked MD runs realisations of one setting: the scene, the headline
    kick, the MD's length and its build and run arguments at that kick (the seed is not:
    another seed is another realisation)."""
    head = float(cfg.get("headline_A_v_A_per_ps", 1.0))
    md = cfg.get("md", {}) or {}

    def at_head(key):
        return {float(k): v for k, v in (md.get(key) or {}).items()}.get(head)
    return {"scene": str(cfg.get("scene")), "A_v_A_per_ps": head,
            "md_run_ps": float(at_head("run_ps_per_A_v") or md.get("run_ps", float("nan"))),
            "build_args": md_build_args(dict(cfg, md=md), head),     # with the medium's, if not vacuum
            "run_args": " ".join(filter(None, [md.get("run_args", ""), at_head("run_args_per_A_v")]))}


def summary(realisations: list[dict]) -> dict:
    """The between-realisation floor of the listed speeds (realisation_floor.py), their range
    and the chi^2 of their scatter with the one-record errors and with the floor."""
    x = [float(r["speed_A_per_ps"]) for r in realisations]
    s = [float(r["speed_err_A_per_ps"]) for r in realisations]
    f = between_realisation_floor(x, s)
    return {"k": f["k"], "min_A_per_ps": min(x), "max_A_per_ps": max(x), "sample_sd_A_per_ps": f["sample_sd"],
            "tau_A_per_ps": f["tau"], "tau_interval_68_A_per_ps": f["tau_interval_68"],
            "floor_A_per_ps": f["floor"], "floor_rule": f["floor_rule"],
            "chi2_one_record": f["Q"], "chi2_with_floor": chi2_about_mean(x, f["errors_with_floor"]),
            "dof": f["dof"]}


def chi2_about_mean(values, errors) -> float:
    """sum ((x - xbar) / s)^2 about the weighted mean xbar (weights 1 / s^2)."""
    w = [1.0 / (e * e) for e in errors]
    mean = sum(wi * x for wi, x in zip(w, values)) / sum(w)
    return float(sum(((x - mean) / e) ** 2 for x, e in zip(values, errors)))


def load(path: Path = RECORD) -> dict | None:
    """The realisations record, None when there is none (an installed copy without results/)."""
    return json.loads(path.read_text()) if path.is_file() else None


def floor_for(cfg: dict, n_seeds: int, path: Path = RECORD) -> dict:
    """The floor a single run of `cfg`'s setting gets: {"floor_A_per_ps", "k", "source", ...},
    or {"floor_A_per_ps": None, "reason"} when the realisations of this setting are not
    measured (or the run has several seeds, whose own scatter mode_error.combine_seeds takes)."""
    if n_seeds != 1:
        return {"floor_A_per_ps": None, "n_seeds": n_seeds,
                "reason": f"{n_seeds} seeds: their own scatter enters the error (mode_error.combine_seeds)"}
    rec = load(path)
    if rec is None:
        return {"floor_A_per_ps": None, "reason": f"no record of realisations ({path.name} not found)"}
    if setting(cfg) != rec["setting"]:
        return {"floor_A_per_ps": None,
                "reason": "the scatter between realisations of this setting is not measured (the main job's "
                          f"setting, {path.name}, scatters by {rec['summary']['sample_sd_A_per_ps']:.2f} A/ps sd "
                          f"in {rec['summary']['k']} runs): the error is one record's"}
    s = rec["summary"]
    return {"floor_A_per_ps": s["floor_A_per_ps"], "k": s["k"], "floor_rule": s["floor_rule"],
            "range_A_per_ps": [s["min_A_per_ps"], s["max_A_per_ps"]], "source": f"results/{path.name}"}


def record(path: Path, rec: dict) -> bool:
    """Append the realisation of a main-job record `rec` (results/main_job.json's keys) to the
    realisations file at `path` unless it is there (same date, speed and error), and rewrite
    its summary. True when appended."""
    data = json.loads(path.read_text())
    new = {"speed_A_per_ps": rec["md_phase_speed_A_per_ps"], "speed_err_A_per_ps": rec["md_phase_speed_err_A_per_ps"],
           "date": rec.get("date"), "source": f"scripts/record_run.py commit main_job ({rec.get('machine')})"}
    same = [r for r in data["realisations"] if r.get("date") == new["date"]
            and math.isclose(r["speed_A_per_ps"], new["speed_A_per_ps"])
            and math.isclose(r["speed_err_A_per_ps"], new["speed_err_A_per_ps"])]
    if same:
        return False
    data["realisations"].append(new)
    data["summary"] = summary(data["realisations"])
    write_json(path, data)
    return True
