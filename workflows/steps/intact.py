"""The intact duplex's results from its reduced segments (docs/intact.md):

    python3 -m dnarod.steps.intact RESULTS [--discard-ps T] [--seeds seed1 seed2] [--kinds ...]

RESULTS holds one folder per seed with its reduced segments (seedS/segments/segNN, written by
`python3 -m dnarod.steps.segments reduce`) and the run input (run/seedS/build.json). For each
seed it writes into RESULTS/seedS:

    mode_series.npz, integrity.json, energies.npz   the segments joined (segments.join_segments;
                                                    the series whole, the open fraction after T)
    tension.json                                    the virial tension after T, with its error
    modes.json, spectra.png                         `dnarod modes` of the series after T
    prediction.json                                 the paper's rod at this seed's tension, as it
                                                    is and at the box with the MD's rho and I

The discarded start T comes from the run's own relaxation unless given (RESULTS/discard.json):
for each seed and each slow observable (the virial tension, the restraint energy, the squared
amplitudes of bend n = 1-3, twist n = 1 and stretch n = 1), the start after which the
record holds the most effectively independent frames (Chodera 2016,
mdbridge/coarsegrain/equilibration.py); T is the latest of them, rounded up to 50 ps. On
the known answer (tests/python/test_intact_discard.py) the bias a relaxation leaves in the
mean tension is below 0.35 of its stated error; on a stationary record the noisy maximum
over 14 observables costs up to ~10 % of it. A T above MAX_DISCARD_PS is
refused: the record would be too short for the modes it must resolve.

With --coarse-grain, each seed is coarse-grained from its steps.npz (seedS/cg: `dnarod
coarse-grain`'s outputs, the same discard, W = the default unrelaxed window) and the rod of
each seed's material predicts every seed's modes at that seed's tension, relaxed and with each
mode's own storage stiffness (unrelaxed_A_on_B.json; workflows/steps/unrelaxed.py): A on B
with A != B is the cross-validation.

Over the seeds, into RESULTS: blocks_KIND.json (block errors pooled over the seeds),
seeds.json (the tension-corrected seed differences; `differences_by_kind` with the block
errors), prediction.json (the reference seed's, the first) and summary.json (`summarise`: the
figures docs/intact.md and the README quote, each from one of these files).
"""
from __future__ import annotations

import argparse
import json
import shutil
import sys
import tempfile
from pathlib import Path

import numpy as np

from dna_models.errors import InputError
from mdbridge.jsonio import write_json

KINDS = ("bend", "twist", "stretch")
MAX_DISCARD_PS = 500.0
CANDIDATE_STEP_PS = 10.0


def _observables(seed_dir: Path) -> dict:
    """The slow observables of one joined seed (module doc): name -> (times_ps, values)."""
    from mdbridge.analysis.mode_spectra import load_npz
    s = load_npz(seed_dir / "mode_series.npz")[0]
    e = np.load(seed_dir / "energies.npz")
    obs = {"tension_pN": (e["times_ps"], e["tension_pN"])}
    if "restraint_kJ_mol" in e.files:
        obs["restraint_kJ_mol"] = (e["times_ps"], e["restraint_kJ_mol"])
    for kind, ns in (("bend", (1, 2, 3)), ("twist", (1,)), ("stretch", (1,))):
        a = np.abs(getattr(s, kind)) ** 2
        for n in ns:
            i = int(np.flatnonzero(np.asarray(s.n) == n)[0])
            obs[f"{kind}_{n}_squared"] = (s.times_ps, a[:, i].reshape(len(s.times_ps), -1).sum(axis=1))
    return obs


def discard_from_relaxation(results: Path, seeds, given_ps: float | None = None) -> dict:
    """RESULTS/discard.json: each seed's and observable's equilibration start (module doc) and
    the discard T they give; the seeds must be joined (join_segments) without a discard. With
    GIVEN_PS (--discard-ps) the starts are still written beside it, as the record of what the
    rule found, and nothing is refused."""
    import math
    from mdbridge.coarsegrain.equilibration import equilibration_start
    per_seed: dict[str, dict] = {}
    for seed in seeds:
        per_seed[seed] = {}
        for name, (t, y) in _observables(results / seed).items():
            t = np.asarray(t, float)
            dt = float(np.median(np.diff(t)))
            step = max(1, int(round(CANDIDATE_STEP_PS / dt)))
            start, n_eff = equilibration_start(y, step)
            per_seed[seed][name] = {"start_ps": float(t[start] - t[0]), "n_effective": float(n_eff[0]),
                                    "record_ps": float(t[-1] - t[0])}
    longest = max(v["start_ps"] for obs in per_seed.values() for v in obs.values())
    T = 50.0 * math.ceil(longest / 50.0)
    rec = {"discard_ps": T, "longest_start_ps": longest, "max_discard_ps": MAX_DISCARD_PS, "per_seed": per_seed,
           "rule": "per seed and observable, the start after which the record holds the most effectively "
                   "independent frames, N / (2 tau_int) (Chodera 2016, J Chem Theory Comput 12:1799; candidates "
                   f"every {CANDIDATE_STEP_PS:g} ps up to half the record); the discard is the latest, "
                   "rounded up to 50 ps (workflows/steps/intact.py, mdbridge/coarsegrain/equilibration.py)"}
    if given_ps is not None:
        rec = {**rec, "discard_ps": float(given_ps), "rule_discard_ps": T, "given": "--discard-ps"}
    write_json(results / "discard.json", rec)
    if given_ps is None and T > MAX_DISCARD_PS:
        raise InputError(f"{results / 'discard.json'}: the run relaxes for {longest:g} ps, more than the "
                         f"{MAX_DISCARD_PS:g} ps the record can spare; see per_seed for the observable")
    return rec


def _segments(seed_dir: Path) -> list[Path]:
    segs = sorted(p for p in (seed_dir / "segments").glob("seg[0-9][0-9]") if p.is_dir())
    if not segs:
        raise InputError(f"{seed_dir / 'segments'}: no segment folders segNN (segments reduce writes them)")
    return segs


def analyse_seed(results: Path, seed: str, discard_ps: float) -> dict:
    """One seed's joined series, integrity, tension, modes and paper-rod prediction."""
    from dnarod.steps.dispersion import predict_and_compare, tension_record
    from dnarod.steps.segments import join_segments
    from mdbridge.analysis.mode_run import mode_spectra
    d = results / seed
    build = results / "run" / seed / "build.json"
    if not build.is_file():
        raise InputError(f"{build}: missing: the run input's build.json gives the atoms' rho and I")
    join_segments(_segments(d), d, discard_ps)
    e = np.load(d / "energies.npz")
    rec = tension_record(e["times_ps"], e["tension_pN"], e["length_nm"], discard_ps, d / "energies.npz")
    rec = {"md_dir": str(d / "segments"), **rec,
           "temperature_K": float(json.loads(build.read_text())["temperature_K"])}
    write_json(d / "tension.json", rec)
    with tempfile.TemporaryDirectory(prefix="dnarod-intact-") as tmp:
        mode_spectra([str(d / "mode_series.npz")], Path(tmp), discard_ps)
        for name in ("modes.json", "spectra.png"):
            shutil.copy(Path(tmp) / name, d / name)
    predict_and_compare(d / "modes.json", d / "prediction.json", [d / "tension.json"], md_inertia=build)
    return rec


def coarse_grain_seeds(results: Path, seeds, discard_ps: float) -> None:
    """seedS/cg of every seed from its steps.npz, and unrelaxed_A_on_B.json for every pair (module doc)."""
    from dnarod.steps.unrelaxed import predict_unrelaxed
    from mdbridge.coarsegrain.pipeline import CoarseGrainRequest, coarse_grain
    from mdbridge.coarsegrain.timescale import DEFAULT_WINDOW_PS
    steps = {s: [g / "steps.npz" for g in _segments(results / s)] for s in seeds}
    for s in seeds:
        r = coarse_grain(CoarseGrainRequest(structure=str(results / "run" / s), output=str(results / s / "cg"),
                                            trajectories=[str(f) for f in steps[s]],
                                            discard=int(round(discard_ps / _frame_ps(steps[s][0]))),
                                            window_ps=[DEFAULT_WINDOW_PS], m_max=1))
        # m_max 1: the rod reads K(q -> 0) and the one-step moments only; the m >= 2 windows
        # of a 3-ns record hold fewer than the 8 samples their inversion needs at slow steps
        write_json(results / s / "cg" / "cg.json", {"ok": True, "caveats": r.caveats})
    for a in seeds:
        for b in seeds:
            predict_unrelaxed(results / a / "cg", steps[a], results / b / "modes.json", results / b / "tension.json",
                              results / f"unrelaxed_{a}_on_{b}.json")


def _frame_ps(steps_file: Path) -> float:
    t = np.load(steps_file)["times_ps"]
    return float(np.median(np.diff(t)))


def analyse(results, discard_ps: float | None = None, seeds=("seed1", "seed2"), kinds=KINDS,
            coarse_grain: bool = False) -> dict:
    """Every seed (analyse_seed), then the block errors and the seed differences over them;
    the discard from the run's relaxation (discard_from_relaxation) unless given."""
    from dnarod.steps.dispersion import block_errors_step, seed_differences_step
    from dnarod.steps.segments import join_segments
    results = Path(results)
    for seed in seeds:
        join_segments(_segments(results / seed), results / seed, 0.0)
    T: float = discard_from_relaxation(results, seeds, discard_ps)["discard_ps"]
    for seed in seeds:
        analyse_seed(results, seed, T)
    series = {s: (results / s / "mode_series.npz", results / s / "modes.json") for s in seeds}
    blocks = []
    for kind in kinds:
        blocks.append(results / f"blocks_{kind}.json")
        block_errors_step(series, blocks[-1], T, None, (kind,))
    if coarse_grain:
        coarse_grain_seeds(results, seeds, T)
    runs = {s: (results / s / "modes.json", results / s / "tension.json") for s in seeds}
    rec = seed_differences_step(runs, results / "seeds.json", blocks, results / "run" / seeds[0] / "build.json")
    shutil.copy(results / seeds[0] / "prediction.json", results / "prediction.json")
    summarise(results, seeds)
    return rec


def _ratios(rows, md_key, rod_key, z_key=None) -> dict:
    """Per kind: the modes n with both numbers, MD / rod (min, max, median) and z (min, max)."""
    out = {}
    for kind in KINDS:
        rs = [r for r in rows if r["kind"] == kind and r.get(md_key) is not None and r.get(rod_key)]
        if not rs:
            continue
        q = np.array([r[md_key] / r[rod_key] for r in rs])
        rec = {"n": [int(r["n"]) for r in rs], "ratio": q.tolist(), "ratio_min": float(q.min()),
               "ratio_max": float(q.max()), "ratio_median": float(np.median(q))}
        if z_key:
            z = np.array([r[z_key] for r in rs if r.get(z_key) is not None], float)
            rec.update(z=z.tolist(), z_min=float(z.min()) if len(z) else None,
                       z_max=float(z.max()) if len(z) else None,
                       within_2=int(np.sum(np.abs(z) <= 2.0)), with_z=int(len(z)))
        out[kind] = rec
    return out


def summarise(results, seeds=("seed1", "seed2")) -> dict:
    """RESULTS/summary.json: per seed the record (discard, end, open and unstacked fractions,
    tension) and the MD over the paper's rod as published and at the box (per kind); over the
    seeds the pooled chi2; per pair of seeds A on B the coarse-grained rod's relaxed and
    unrelaxed frequencies and dampings over the MD's, where those files exist."""
    results = Path(results)

    def load(name):
        return json.loads((results / name).read_text())
    rec: dict = {"discard_ps": load("discard.json")["discard_ps"], "seeds": {}}
    for s in seeds:
        g, t, p = load(f"{s}/integrity.json"), load(f"{s}/tension.json"), load(f"{s}/prediction.json")
        times = np.load(results / s / "mode_series.npz")["r0_times_ps"]
        rec["seeds"][s] = {
            "end_ps": float(times[-1]), "open_fraction": g["open_fraction"],
            "junction_open_fraction": g["junction_open_fraction"],
            "unstacked_fraction": (g.get("stacking") or {}).get("unstacked_fraction"),
            "tension_pN": t["tension_pN"], "tension_err_pN": t["tension_err_pN"],
            "paper_rod": _ratios(p["rows"], "md_omega0_per_ps", "paper_rod_omega_per_ps", "z_paper_rod"),
            "paper_rod_box": _ratios(p["rows"], "md_omega0_per_ps", "paper_rod_box_omega_per_ps", "z_paper_rod_box")}
    d = load("seeds.json")
    rec["seed_differences"] = {"errors": d["errors"], **d["differences_by_kind"][0]}
    rec["cg"] = {}
    for a in seeds:
        for b in seeds:
            f = results / f"unrelaxed_{a}_on_{b}.json"
            if f.is_file():
                rows = json.loads(f.read_text())["rows"]
                rec["cg"][f"{a}_on_{b}"] = {
                    "relaxed": _ratios(rows, "md_omega0_per_ps", "relaxed_omega_per_ps", "z_relaxed"),
                    "unrelaxed": _ratios(rows, "md_omega0_per_ps", "unrelaxed_omega_per_ps", "z_unrelaxed"),
                    "gamma": _ratios(rows, "md_gamma_per_ps", "gamma_per_ps", "z_gamma"),
                    "refused": [f"{r['kind']} {r['n']}" for r in rows if r.get("unrelaxed_omega_per_ps") is None]}
    write_json(results / "summary.json", rec)
    return rec


def main(argv=None) -> int:
    from dnarod.steps.analyse import run_step
    ap = argparse.ArgumentParser(prog="python3 -m dnarod.steps.intact", description=__doc__.splitlines()[0])
    ap.add_argument("results", help="the folder with seedS/segments/segNN and run/seedS/build.json")
    ap.add_argument("--discard-ps", type=float, default=None,
                    help="the discarded start (default: from the run's relaxation, RESULTS/discard.json, "
                         "which records the rule's starts either way)")
    ap.add_argument("--seeds", nargs="+", default=["seed1", "seed2"])
    ap.add_argument("--kinds", nargs="+", default=list(KINDS), choices=KINDS)
    ap.add_argument("--coarse-grain", action="store_true",
                    help="coarse-grain each seed from its steps and cross-predict the seeds' modes")
    a = ap.parse_args(argv)
    return run_step("intact", lambda: analyse(a.results, a.discard_ps, tuple(a.seeds), tuple(a.kinds),
                                              a.coarse_grain))


if __name__ == "__main__":
    sys.exit(main())
