#!/usr/bin/python3
"""The kicked comparison at 300 K, rod side: does thermal slack explain the MD's slower,
smaller mode? (docs/results.md, "The kicked comparison at 300 K").

The kicked MD (the main job) is a 158-bp duplex at 300 K held in its box, kicked with the
transverse velocity A_v sin(2 pi s / L), A_v = 1 A/ps. The paper's rod gets the same kick at
0 K. Here the rod gets it at 300 K, as the MD did:

1. **The box.** A box-held rod at 300 K stores contour in thermal bending, so at the MD's
   built length it pulls on the box with its slack tension (23 pN for the paper's material,
   docs/thermal.md). The box is set instead so that the rod holds the MD's measured tension F:
   mean field of mdbridge/rod/slack.py, X / L = 1 + F / C3 - <s + c>(F) (`box_for_tension`),
   with the rod's rest length L = 158 x 3.38 A (the 0-K rod's) and X = Gamma03 L. The tension
   the rod then holds is measured during its equilibration and reported (the check of the box).
2. **Equilibration.** The straight twisted rod at Gamma3 = Gamma03, at rest, run as a Langevin
   rod at 300 K with the box kept (closure projection, docs/thermal.md): the bath heats it and
   it buckles into its thermal slack. Not from the [thermal] sample, which is exact only about
   a stress-free state (the compressed straight rod is pre-stressed; docs/thermal.md); its
   closure there held at linear order only (nonlinear gap 0.27 at Gamma03 = 0.965).
   Rotations in water; translations with a weak friction (`--friction`, per time unit), near
   the critical damping of the slowest bending mode. The equilibrium state does not depend on
   the friction, only the time to reach it: in water (0.84 /ps across) the n = 1 bend of the
   158-bp rod is overdamped and relaxes in ~20 ns. The tension is measured over the second
   half of the equilibration (the first half is reported too: it shows the approach).
3. **The kick.** The equilibrated state plus the lab velocity A_v sin(2 pi s / L) e_kick at
   every point (e_kick perpendicular to the box axis), then NVE (no friction, no noise; the
   closure projection keeps the box), 600 ps, a frame per ps, as the MD.
4. **The analysis.** The same wave analysis as the MD's and the 0-K rod's
   (mdbridge.analysis.WaveAnalysis, the standing-mode fit of matched.mode_fit): speed and
   amplitude of the kicked mode per run; across the runs, their distribution.

Materials: the paper's (Sec 2.1-2.2) and the provisional coarse-grained rod of the 5-ns MD
(results/dispersion/cg_provisional/params.json["rod"]: its K(q -> 0) K*, I*, rho*). Both are
run as intrinsically straight rods with 15 turns, the MD's: the box and the ring's linking fix
the MD's length and twist, so the coarse-grained rest rise and twist (Gamma0*, Omega0*) do not
enter, and the box ratio does the rest length's work.

    /usr/bin/python3 bench/warm_kick.py [--runs 20] [--tension-pN 5] [--material paper cg]
        [--out results/warm_kick/warm_kick.json]
    /usr/bin/python3 bench/warm_kick.py --cold --out results/warm_kick/cold.json   # the 0-K rods

Needs rodcore on PYTHONPATH (build/python). 30-60 s per run on the shared 2-core machine.
"""
from __future__ import annotations

import argparse
import json
import math
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from dna_models.errors import InputError
from dna_models.units import Units
from mdbridge.jsonio import write_json
from mdbridge.rod.slack import box_for_tension

HERE = Path(__file__).resolve().parent

U = Units.paper()
N_BP = 158
TURNS = 15
L = N_BP * U.rise_A / U.ell_A                 # the 0-K rod's rest length, rod units
FORCE_PN = U.C * 1e12
CG_PARAMS = HERE.parent / "results/dispersion/cg_provisional/params.json"
MACHINE = "2 cores shared with a GROMACS run and other jobs (wall times per run are not timings)"
DT = 0.0531                                   # 20 steps per 1-ps frame (1.062 time units)


def material(name: str) -> dict:
    """K (6, 6), I (3, 3), rho of a material, with where it came from."""
    if name == "paper":
        return {"name": "paper", "K": np.diag([*U.C_star, *U.D_star]), "I": np.diag(U.I_star), "rho": 1.0,
                "source": "the paper's constants (dna_models/units.py)"}
    if name == "cg":
        p = json.loads(CG_PARAMS.read_text())
        rod = p["rod"]
        return {"name": "cg", "K": np.asarray(rod["K_star"], float), "I": np.asarray(rod["I_star"], float),
                "rho": float(rod["rho_star"]),
                "source": f"{CG_PARAMS.relative_to(HERE.parent)} rod (K(q -> 0), {p['format']})"}
    raise InputError(f"material {name!r}: allowed 'paper', 'cg'")


def iso_constants(mat: dict) -> dict:
    """Bend B, shear C1 (compliance averages over the two body directions, which the helical
    twist puts in series), stretch C3 = K_33 (the box holds every other mean strain)."""
    c = np.diagonal(np.linalg.inv(mat["K"]))
    return {"B": 2.0 / (c[3] + c[4]), "C1": 2.0 / (c[0] + c[1]), "C3": float(mat["K"][2, 2])}


def scene(mat: dict, thermal: dict, t_end: float, frames: int, temperature_K: float = 300.0) -> dict:
    return {"rod": {"length": L, "points": N_BP, "Gamma0": [0.0, 0.0, 1.0],
                    "Omega0": [0.0, 0.0, 2 * math.pi * TURNS / L]},
            "material": {"K": mat["K"].tolist(), "I": mat["I"].tolist(), "rho": mat["rho"]},
            "thermal": {"temperature_K": temperature_K, **thermal},
            "solver": {"space": "spectral", "time": "langevin" if thermal.get("friction_translational") else "rk4",
                       "dt": DT},
            "output": {"t_end": t_end, "frames": frames, "fields": ["internal", "centerline", "directors"]}}


def straight(Gamma03: float) -> dict:
    """The straight twisted rod in a box Gamma03 L long, at rest."""
    z = np.zeros((N_BP, 3))
    G, O = z.copy(), z.copy()
    G[:, 2] = Gamma03
    O[:, 2] = 2 * math.pi * TURNS / L
    return {"gamma": z.copy(), "omega": z.copy(), "Gamma": G, "Omega": O}


def box_force_pN(f: dict, mat: dict) -> float:
    """The force on the box of one frame: the lab force n = R K (e) averaged along the rod,
    projected on the box axis (at rest the periodic rod's lab force is the same at every s)."""
    Gm, Om = f["fields"]["Gamma"], f["fields"]["Omega"]
    e = np.hstack([Gm - [0.0, 0.0, 1.0], Om - [0.0, 0.0, 2 * math.pi * TURNS / L]])
    n_body = (e @ mat["K"].T)[:, :3]
    box = np.asarray(f["end_to_end"], float)
    axis = box / np.linalg.norm(box)
    n_lab = np.einsum("ijk,ik->ij", f["directors"], n_body)
    return float((n_lab @ axis).mean() * FORCE_PN)


def equilibrate(mat: dict, Gamma03: float, seed: int, t_eq: float, friction: float,
                temperature_K: float = 300.0) -> dict:
    """The Langevin rod from the straight state at rest (no sample: the bath heats it); returns
    the final internal state and the box force per frame (every 10 time units)."""
    import rodcore
    frames = int(round(t_eq / 10.0)) + 1
    t_eq = (frames - 1) * 10.0
    sc = scene(mat, {"seed": seed, "friction_translational": friction, "friction_rotational": "water",
                     "sample_initial": False},
               t_eq, frames, temperature_K)
    sc["solver"]["dt"] = 0.05            # divides the 10-unit frame interval
    sim = rodcore.Simulation(sc, initial=straight(Gamma03))
    F: list[float] = []
    last: dict = {}

    def frame(f):
        F.append(box_force_pN(f, mat))
        last.update({k: np.array(v) for k, v in f["fields"].items()})

    sim.add_observer(frame)
    sim.run()
    return {"state": last, "force_pN": np.array(F), "kinetic_kT": float(sim.kinetic_kT)}


def lab_frame(mat: dict, state: dict) -> tuple[np.ndarray, np.ndarray]:
    """The directors (N, 3, 3), directors[i, :, k] = d_k, and the box vector of a state as
    a run from it sees them: an initial-fields run anchors s = 0 at the identity frame."""
    import rodcore
    probe = rodcore.Simulation(scene(mat, {"sample_initial": False}, DT, 2), initial=state)
    first: dict = {}
    probe.add_observer(lambda f: first.setdefault("f", (np.array(f["directors"]),
                                                        np.array(f["end_to_end"], float))))
    probe.run()
    return first["f"]


def add_kick(state: dict, R: np.ndarray, box: np.ndarray, A_v_A_per_ps: float) -> tuple[dict, np.ndarray]:
    """The state plus the lab velocity A_v sin(2 pi s / L) e_kick at every point, e_kick the
    lab X axis made perpendicular to the box axis; the body-frame velocity gets R^T v."""
    axis = box / np.linalg.norm(box)
    e_kick = np.array([1.0, 0.0, 0.0]) - axis[0] * axis
    e_kick /= np.linalg.norm(e_kick)
    s = np.arange(N_BP) * L / N_BP
    v_lab = (A_v_A_per_ps / U.velocity_A_per_ps) * np.sin(2 * math.pi * s / L)[:, None] * e_kick
    fields = {k: np.array(v) for k, v in state.items()}
    fields["gamma"] = fields["gamma"] + np.einsum("ikj,ik->ij", R, v_lab)   # R^T v per point
    return fields, e_kick


def kicked(mat: dict, state: dict, A_v_A_per_ps: float, run_ps: float, workdir: Path, seed: int,
           temperature_K: float = 300.0) -> dict:
    """NVE from the equilibrated state plus the kick; the wave analysis of the run."""
    import rodcore
    from mdbridge.analysis import BasePairTrajectory, WaveAnalysis
    from mdbridge.rod.run import RodRun

    from dnarod.steps.matched import mode_fit
    R, box = lab_frame(mat, state)
    fields, e_kick = add_kick(state, R, box, A_v_A_per_ps)
    t_end = float(U.time_to_rod(run_ps))
    frames = int(round(run_ps)) + 1
    sc = scene(mat, {"sample_initial": False}, t_end, frames, temperature_K)
    sc["solver"]["dt"] = t_end / (frames - 1) / 20
    h5 = workdir / f"{mat['name']}_{seed}.h5"
    rodcore.run(sc, initial=fields, output=str(h5))
    run = RodRun.read(h5)
    traj = BasePairTrajectory.from_rod(run, N_BP)
    a = WaveAnalysis(traj, in_plane=e_kick.tolist(), offset=True, n_boot=20).run()
    fit = mode_fit(a)
    h5.unlink()
    rep = fit.get("unreported", fit)
    F_nve = [box_force_pN({"fields": {"Gamma": run.fields["Gamma"][t], "Omega": run.fields["Omega"][t]},
                           "directors": run.directors[t],
                           "end_to_end": box}, mat) for t in range(len(run.time))]
    return {"omega_per_ps": rep.get("omega_per_ps"), "omega_err_per_ps": rep.get("omega_err_per_ps"),
            "speed_A_per_ps": rep.get("speed_A_per_ps"), "speed_err_A_per_ps": rep.get("speed_err_A_per_ps"),
            "mode_amplitude_A": rep.get("mode_amplitude_A"), "wave_kind": rep.get("wave_kind"),
            "periods_in_record": rep.get("periods_in_record"), "reason": fit.get("reason"),
            "box_length_A": float(np.linalg.norm(box) * U.ell_A),
            "kicked_tension_mean_pN": float(np.mean(F_nve)), "kicked_tension_max_pN": float(np.max(F_nve))}


def ensemble(mat_name: str, tension_pN: float, runs: int, seed0: int, t_eq: float, run_ps: float,
             friction: float, A_v: float, workdir: Path, log=print, temperature_K: float = 300.0,
             Gamma03: float | None = None) -> dict:
    """`runs` rods (seeds seed0, seed0 + 1, ...) equilibrated and kicked; Gamma03 (the box over
    the rest length) from the tension unless given."""
    mat = material(mat_name)
    c = iso_constants(mat)
    kT = U.kT_to_rod(temperature_K)
    if Gamma03 is None:
        Gamma03 = box_for_tension(tension_pN / FORCE_PN, L, N_BP, kT, c["B"], c["C1"], c["C3"])
    per_run = []
    for i in range(runs):
        seed = seed0 + i
        t0 = time.time()
        eq = equilibrate(mat, Gamma03, seed, t_eq, friction, temperature_K)
        F = eq["force_pN"]
        tail = F[len(F) // 2:]
        r = kicked(mat, eq["state"], A_v, run_ps, workdir, seed, temperature_K)
        r.update(seed=seed, equilibrium_tension_pN=float(tail.mean()),
                 equilibrium_tension_first_half_pN=float(F[1:len(F) // 2].mean()),
                 wall_s=round(time.time() - t0, 1))
        per_run.append(r)
        log(f"{mat_name} seed {seed}: F_eq {r['equilibrium_tension_pN']:.1f} pN, speed {r['speed_A_per_ps']} A/ps, "
            f"amplitude {r['mode_amplitude_A']} A, {r['reason'] or ''} ({r['wall_s']} s)")
    return {"material": mat_name, "material_source": mat["source"], "constants_rod_units": c,
            "target_tension_pN": tension_pN, "Gamma03": Gamma03, "box_length_A": Gamma03 * L * U.ell_A,
            "rest_length_A": L * U.ell_A, "summary": summarise(per_run), "runs": per_run}


def cold_reference(mat_name: str, run_ps: float, A_v: float, workdir: Path) -> dict:
    """The same kick on the same rod at 0 K in its built box (Gamma03 = 1: no slack, no
    tension at rest), through the same analysis: the 0-K rod of the comparison."""
    r = kicked(material(mat_name), straight(1.0), A_v, run_ps, workdir, 0, temperature_K=0.0)
    return dict(r, material=mat_name, temperature_K=0.0, Gamma03=1.0)


def _dist(x) -> dict:
    x = np.asarray([v for v in x if v is not None and math.isfinite(v)], float)
    if len(x) < 2:
        return {"n": int(len(x))}
    return {"n": int(len(x)), "mean": float(x.mean()), "sd": float(x.std(ddof=1)),
            "sem": float(x.std(ddof=1) / math.sqrt(len(x))), "min": float(x.min()),
            "median": float(np.median(x)), "max": float(x.max())}


def summarise(per_run: list[dict]) -> dict:
    """Across the runs: every run's fitted values, refused or not (a refusal is a record
    shorter than the fit's minimum, still a measured number), with how many were refused."""
    return {"speed_A_per_ps": _dist([r["speed_A_per_ps"] for r in per_run]),
            "omega_per_ps": _dist([r["omega_per_ps"] for r in per_run]),
            "mode_amplitude_A": _dist([r["mode_amplitude_A"] for r in per_run]),
            "equilibrium_tension_pN": _dist([r["equilibrium_tension_pN"] for r in per_run]),
            "kicked_tension_mean_pN": _dist([r["kicked_tension_mean_pN"] for r in per_run]),
            "refused": sum(1 for r in per_run if r["reason"]),
            "standing": sum(1 for r in per_run if r["wave_kind"] == "standing")}


MD_BOX_A = N_BP * U.rise_A         # the MD's box: the duplex as built
MD_AMPLITUDE_A = 35.9              # the main job's kicked mode amplitude (docs/results.md, "The rod against the MD")
MD_KICKED_TENSION_PN = (31.0, 8.0)  # and its mean tension while kicked (the same table)


def speed_in_md_box(omega_per_ps: float) -> float:
    """The phase speed the MD's analysis would print for this frequency: omega L_box / 2 pi
    with the MD's box (the warm rod's box is shorter or longer by its Gamma03)."""
    return omega_per_ps * MD_BOX_A / (2 * math.pi)


def table(paths: list[str], md_speed: float, md_speed_err: float, md_amplitude_A: float) -> str:
    """The docs' table from the result files: per ensemble the tension it held, the speed and
    the amplitude (mean, sd over the runs, sem), the speed in the MD's box, and where the MD's
    single record falls among the runs (the fraction of runs below it)."""
    rows = ["| rod | T [pN] held (set) | speed [A/ps] mean +- sd (sem) | in the MD's box | amplitude [A] "
            "mean +- sd (sem) | T [pN] kicked, mean +- sd | runs below the MD: speed, amplitude | "
            "refused by the noise test | a run's stated speed error, median |",
            "|---|---|---|---|---|---|---|---|---|"]
    for p in paths:
        d = json.loads(Path(p).read_text())
        for c in d.get("cold", []):
            rows.append(f"| {c['material']}, 0 K, built box | 0 (0) | {c['speed_A_per_ps']:.3f} +- "
                        f"{c['speed_err_A_per_ps']:.3f} (fit) | {speed_in_md_box(c['omega_per_ps']):.3f} | "
                        f"{c['mode_amplitude_A']:.1f} | {c['kicked_tension_mean_pN']:.1f} | | "
                        f"{'no' if c['reason'] is None else 'yes'} | {c['speed_err_A_per_ps']:.3f} |")
        for e in d.get("ensembles", []):
            # a run whose fit found no frequency at all (fewer than a quarter period) has none
            runs = [r for r in e["runs"] if r["omega_per_ps"] is not None and math.isfinite(r["omega_per_ps"])]
            sp = np.array([r["speed_A_per_ps"] for r in runs], float)
            am = np.array([r["mode_amplitude_A"] for r in runs], float)
            md_box = np.array([speed_in_md_box(r["omega_per_ps"]) for r in runs], float)
            ft, fk = e["summary"]["equilibrium_tension_pN"], e["summary"]["kicked_tension_mean_pN"]
            n = len(runs)
            no_fit = "" if n == len(e["runs"]) else f" ({len(e['runs']) - n} without a frequency)"
            rows.append(
                f"| {e['material']}, 300 K, box {e['box_length_A']:.1f} A, {len(e['runs'])} runs{no_fit} | "
                f"{ft['mean']:.1f} +- "
                f"{ft['sem']:.1f} ({e['target_tension_pN']:g}) | {sp.mean():.2f} +- {sp.std(ddof=1):.2f} "
                f"({sp.std(ddof=1) / math.sqrt(n):.2f}) | {md_box.mean():.2f} | {am.mean():.1f} +- "
                f"{am.std(ddof=1):.1f} ({am.std(ddof=1) / math.sqrt(n):.1f}) | {fk['mean']:.1f} +- {fk['sd']:.1f} | "
                f"{np.sum(sp < md_speed)}/{n}, {np.sum(am < md_amplitude_A)}/{n} | "
                f"{e['summary']['refused']}/{len(e['runs'])} | "
                f"{np.median([r['speed_err_A_per_ps'] for r in runs]):.2f} |")
    rows.append(f"| the MD (main job, one record) | 5 +- 13 (unkicked baseline) | {md_speed:.2f} +- "
                f"{md_speed_err:.2f} | {md_speed:.2f} | {md_amplitude_A:.1f} | {MD_KICKED_TENSION_PN[0]:g} +- "
                f"{MD_KICKED_TENSION_PN[1]:g} (its error) | | no | {md_speed_err:.2f} |")
    return "\n".join(rows)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=20)
    ap.add_argument("--seed", type=int, default=1, help="first seed; run i has seed + i")
    ap.add_argument("--material", nargs="+", default=["paper", "cg"], choices=["paper", "cg"])
    ap.add_argument("--tension-pN", type=float, default=5.0,
                    help="the tension the box is set to hold (the kicked MD's unkicked baseline: 5 pN)")
    ap.add_argument("--equilibrate", type=float, default=1500.0, help="Langevin time [time units]")
    ap.add_argument("--friction", type=float, default=0.01,
                    help="translational friction of the equilibration [per time unit]")
    ap.add_argument("--run-ps", type=float, default=600.0)
    ap.add_argument("--A-v", type=float, default=1.0, help="kick [A/ps]")
    ap.add_argument("--cold", action="store_true",
                    help="instead: the 0-K rods in their built box, one run per material")
    ap.add_argument("--out", default=str(HERE.parent / "results/warm_kick/warm_kick.json"))
    ap.add_argument("--table", nargs="+", metavar="JSON",
                    help="instead: print the docs' table from these result files")
    a = ap.parse_args(argv)
    if a.table:
        mj = json.loads((HERE.parent / "results/main_job.json").read_text())
        print(table(a.table, mj["md_phase_speed_A_per_ps"], mj["md_phase_speed_err_A_per_ps"],
                    MD_AMPLITUDE_A))
        return 0
    if a.runs < 2 and not a.cold:
        raise SystemExit("warm_kick: --runs must be >= 2 (a distribution)")
    out = {"what": "the paper's kick (A_v sin(2 pi s / L)) on box-held 158-bp rods equilibrated at 300 K, "
                   "box set to hold the MD's tension; the MD's wave analysis (bench/warm_kick.py)",
           "command": "/usr/bin/python3 bench/warm_kick.py " + " ".join(sys.argv[1:] if argv is None else argv),
           "date": time.strftime("%Y-%m-%d"), "machine": MACHINE, "settings": vars(a), "ensembles": []}
    Path(a.out).parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        if a.cold:
            out["what"] = "the paper's kick on the 0-K 158-bp rods in their built box, the MD's wave analysis"
            out["cold"] = [cold_reference(m, a.run_ps, a.A_v, Path(tmp)) for m in a.material]
            write_json(a.out, out)
            return 0
        for m in a.material:
            out["ensembles"].append(ensemble(m, a.tension_pN, a.runs, a.seed, a.equilibrate, a.run_ps,
                                             a.friction, a.A_v, Path(tmp)))
            write_json(a.out, out)          # each finished ensemble is kept
    return 0


if __name__ == "__main__":
    sys.exit(main())
