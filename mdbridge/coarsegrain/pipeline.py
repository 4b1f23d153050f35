"""The coarse-graining pipeline: a trajectory in, DIR/params.json and the material files out.

`coarse_grain(CoarseGrainRequest(...))` is what `dnarod coarse-grain` runs
(workflows/commands/coarse_grain.py parses, calls this and prints) and what the
comparison's loop runs on its equilibrium MD (workflows/steps/cgloop.py), in the manner
of mdbridge/md/build.py's `BuildRequest` / `build_md`. The input is an MD structure with
its trajectories, a rod output file (mdbridge/md/realisation.py), which is the whole
input, or a run's input folder with its segments' steps.npz (reader.py
read_steps_ensemble); the steps: read the step ensemble (reader.py), the temperature
(temperature.py), the estimator (estimator.py), params.json (params.py), the figures, the per-step and
grid material files (stepmaterial.py) and the bootstrap replicas (cgrod.py).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

from dna_models.errors import InputError
from mdbridge.md.realisation import kind_of

CLOSED = {"auto": None, "yes": True, "no": False}


@dataclass
class CoarseGrainRequest:
    """What to coarse-grain and how; the fields are `dnarod coarse-grain`'s options."""
    structure: str                       # topology/coordinates, or a rod output file (the whole input)
    output: str                          # output directory
    trajectories: list[str] = field(default_factory=list)
    temperature: str | float | None = None   # K; wins over edr and the kinetic temperature
    edr: str | None = None               # GROMACS energy file: T from gmx energy
    length: int | None = None            # m of the rod's K and headline constants (default: largest)
    m_max: int | None = None
    pairs_file: str | None = None        # 3DNA bpfile or lines 'resid_I resid_II'
    closed: str = "auto"                 # auto, yes, no
    tension: float | None = None         # pN, rest shape corrected
    torque: float | None = None          # pN nm
    discard: int | None = None           # frames (default: Chodera's rule)
    min_effective: float | None = None   # default estimator.MIN_EFFECTIVE
    max_open_fraction: float = 0.05
    bootstrap: int = 200
    seed: int = 0
    start: int | None = None
    stop: int | None = None
    step: int | None = None
    window_ps: list[float] | None = None  # compliance by timescale (timescale.py); None: the default W
    leave_out_open_frames: bool = False  # a step's local estimates without the frames it touches an open pair


@dataclass
class CoarseGrainResult:
    """What `coarse_grain` wrote (params.json's content in `params`) and what it says."""
    output: Path
    params: dict
    n_steps: int
    T_K: float
    T_source: str
    caveats: list[str]
    results: dict                        # the estimator's results (frames used, N_eff, ...)

    @property
    def written(self) -> list[Path]:
        """The files written, params.json first."""
        files = self.params["files"]
        extra = [f for f in (files.get("steps_file"), files.get("material_file"), "replicas.h5") if f]
        return [self.output / f for f in ("params.json", "q_stiffness.png", "convergence.png", "by_length.png")] \
            + [self.output / f for f in extra]


def _close(progress) -> None:
    if hasattr(progress, "close"):
        progress.close()


def _quiet(*args, **kwargs):
    pass


def read_input(req: CoarseGrainRequest, progress):
    """(ensemble, extras, universe or None, source) of the request's input."""
    from mdbridge.coarsegrain.reader import is_steps_file, read_ensemble, read_rod_ensemble, read_steps_ensemble
    from mdbridge.geometry.structure import load_universe, read_pairs_file
    if kind_of(req.structure) == "rod":
        if req.trajectories:
            raise InputError(f"{req.structure}: a rod output file is the whole input; give no trajectory "
                             f"({' '.join(req.trajectories)})")
        ens, extras = read_rod_ensemble(req.structure, req.start, req.stop, req.step)
        return ens, extras, None, req.structure
    if req.trajectories and all(is_steps_file(t) for t in req.trajectories):
        ens, extras = read_steps_ensemble(req.structure, req.trajectories, req.max_open_fraction,
                                          req.leave_out_open_frames)
        return ens, extras, None, f"{req.structure} + {' + '.join(req.trajectories)}"
    u = load_universe(req.structure, *req.trajectories)
    source = " + ".join([req.structure] + list(req.trajectories))
    pairs, numbering = (None, "resid")
    if req.pairs_file:
        pairs, numbering = read_pairs_file(req.pairs_file)
    ens, extras = read_ensemble(u, pairs, numbering, CLOSED[req.closed], req.start, req.stop, req.step,
                                req.max_open_fraction, source, progress=progress,
                                leave_out_open_frames=req.leave_out_open_frames)
    return ens, extras, u, source


def temperature(req: CoarseGrainRequest, u, source: str, extras: dict, caveats: list) -> tuple[float, str]:
    """(T in K, where it came from): --temperature, the rod file's, the .edr's or the
    kinetic temperature of the velocities, in that order."""
    from mdbridge.coarsegrain.temperature import edr_temperature, kinetic_temperature, parse_temperature
    if req.temperature is not None:
        return parse_temperature(req.temperature), "given"
    if u is None:
        if extras.get("temperature_K") is None:
            raise InputError(f"{source}: the rod file has no attribute 'temperature_K' (a scene with "
                             "[thermal] temperature_K writes it): give --temperature K")
        return float(extras["temperature_K"]), extras.get("temperature_source", "rod file (attribute temperature_K)")
    if req.edr:
        T_K, sd = edr_temperature(req.edr)
        return T_K, f"edr ({req.edr}: mean of gmx energy 'Temperature', s.d. {sd:.1f} K)"
    kin = kinetic_temperature(u, req.start, req.stop, req.step)
    if kin is None:
        raise InputError(f"{source}: no velocities in the trajectory, so no kinetic temperature: "
                         "give --temperature K (or --edr FILE)")
    T_K, sd, n_at, note = kin
    caveats.append(f"kinetic temperature {T_K:.1f} K (s.d. {sd:.1f} K over frames) from {n_at} atoms: {note}")
    return T_K, "kinetic"


def input_caveats(req: CoarseGrainRequest, ens, extras: dict, min_eff: float) -> list[str]:
    """The caveats the input and the options give, before the estimator runs."""
    from mdbridge.coarsegrain.estimator import MIN_EFFECTIVE
    caveats = []
    if min_eff < MIN_EFFECTIVE:
        caveats.append(f"--min-effective {min_eff:g} is below the default {MIN_EFFECTIVE}: few independent "
                       f"frames, stiffness errors ~ sqrt(2 / N_eff) = {100 * math.sqrt(2 / max(min_eff, 1)):.0f} % "
                       "or more, and the bias correction is large")
    if extras["opened_pairs"].size:
        caveats.append("opened base pairs (1-based, opening rule): "
                       + ", ".join(str(i + 1) for i in extras["opened_pairs"])
                       + "; their steps are used, and left out only for the rule's sensitivity")
    if ens.closed and req.tension is None and req.torque is None:
        caveats.append("closed duplex: the means are the box's pre-stressed shape (no --tension/--torque given)")
    if "mass_inertia" not in extras:
        caveats.append("the rod file carries no uniform rho and I (a material file): no mass and inertia")
    elif not extras["mass_inertia"]["hydrogens"]:
        caveats.append("the topology has no hydrogens: masses and inertia are those of the heavy atoms only")
    return caveats


def _m_values(req: CoarseGrainRequest, ens) -> tuple[list, int]:
    from mdbridge.coarsegrain.estimator import default_m_values
    m_values = default_m_values(ens.n_steps, ens.closed, req.m_max, ens.excluded)
    m_rod = req.length if req.length is not None else max(m_values)
    if m_rod < 1 or m_rod > max(m_values):
        raise InputError(f"--length {m_rod}: allowed 1..{max(m_values)} (raise --m-max; "
                         f"{'n_bp / 4 for a closed duplex' if ens.closed else 'at most the number of steps'})")
    return m_values, m_rod


def write_outputs(out: Path, cg, params: dict, extras: dict, source: str) -> None:
    """params.json, the three figures, the material files and replicas.h5."""
    from mdbridge.coarsegrain.cgrod import write_replicas
    from mdbridge.coarsegrain.figure import convergence_figure, length_figure, q_stiffness_figure
    from mdbridge.coarsegrain.params import write_params
    from mdbridge.coarsegrain.stepmaterial import write_material_files
    out.mkdir(parents=True, exist_ok=True)
    write_params(out / "params.json", params)
    params["convergence"]["figure"] = "convergence.png"
    convergence_figure(out / "convergence.png", params)
    length_figure(out / "by_length.png", params)
    params["by_length_figure"] = "by_length.png"
    q_stiffness_figure(out / "q_stiffness.png", params)
    params["q_stiffness"]["figure"] = "q_stiffness.png"
    params["files"] = write_material_files(out, cg, extras, source)
    write_replicas(out / "replicas.h5", cg, extras)
    params["files"]["replicas_file"] = "replicas.h5"
    write_params(out / "params.json", params)


def coarse_grain(req: CoarseGrainRequest, progress=None) -> CoarseGrainResult:
    """Coarse-grain REQ's trajectory into the rod's material and write REQ.output
    (docs/coarse-graining.md). progress: as dnarod.progress.Stages (the frames read, the
    base-pair check and the coarse-graining lengths analysed)."""
    from mdbridge.coarsegrain.estimator import MIN_EFFECTIVE, CoarseGrain
    from mdbridge.coarsegrain.params import build_params
    if not (0.0 <= req.max_open_fraction < 1.0):
        raise InputError(f"--max-open-fraction {req.max_open_fraction}: allowed 0 <= F < 1")
    if req.closed not in CLOSED:
        raise InputError(f"--closed {req.closed!r}: allowed {', '.join(CLOSED)}")
    progress = progress or _quiet
    ens, extras, u, source = read_input(req, progress)
    _close(progress)
    extras["max_open_fraction"] = req.max_open_fraction
    caveats: list[str] = []
    T_K, T_src = temperature(req, u, source, extras, caveats)
    m_values, m_rod = _m_values(req, ens)
    min_eff = MIN_EFFECTIVE if req.min_effective is None else req.min_effective
    caveats += input_caveats(req, ens, extras, min_eff)
    windows = req.window_ps
    # with --window-ps the whole-record (relaxed) estimate is written with its caveat, not refused
    cg = CoarseGrain(ens, T_K, m_values=m_values, m_rod=m_rod, n_boot=req.bootstrap, seed=req.seed,
                     discard=req.discard, min_effective=0.0 if windows else min_eff, progress=progress).run()
    _close(progress)
    if windows and cg.results["effective_samples"] < min_eff:
        caveats.append(f"the whole-record (relaxed) estimate: {cg.results['effective_samples']:.1f} independent "
                       f"samples, fewer than {min_eff:g}; written because --window-ps was given, not to be trusted")
    n_modes = cg.results["effective_samples_fit_modes"]
    if n_modes < min_eff:
        caveats.append(f"the slowest mode of the q -> 0 fit (autocorrelation time "
                       f"{cg.results['tau_int_fit_modes_frames']:.0f} frames) has {n_modes:.0f} independent samples, "
                       f"fewer than {min_eff:g}: the bootstrap's blocks are capped at T / 8, so the rod's K's error "
                       "may be understated; a longer run settles it")
    params = build_params(cg, T_src, extras, req.tension, req.torque, min_eff, caveats)
    params.update(_timescale(cg, ens, windows, min_eff, req, source))
    out = Path(req.output)
    write_outputs(out, cg, params, extras, source)
    return CoarseGrainResult(out, params, ens.n_steps, T_K, T_src, caveats, cg.results)


def _timescale(cg, ens, windows, min_eff, req: CoarseGrainRequest, source) -> dict:
    """params.json's "unrelaxed" and "compliance_by_window" from the frames the estimator used."""
    from mdbridge.coarsegrain.timescale import params_section
    t0 = cg.results["discarded_frames"]
    fr = cg.frames[t0:]
    return params_section(ens.q[fr], ~ens.excluded, ens.closed, ens.times_ps[fr], windows, min_eff,
                          req.bootstrap, req.seed, source)
