"""Run the MD of a build-md directory: grompp, then mdrun, resumable.

A half-finished MD must never look finished: grompp writes md.part.tpr and
mdrun writes md.part.{xtc,edr,log,cpt} and confout.part.gro, which become
md.tpr, md.xtc, md.edr, md.log, md.cpt, confout.gro only after mdrun exits
cleanly; the marker md.done (JSON) is written after them, checks.json
follows (written whole or not at all). Anything that reads MD results should
require md.done.

An interrupted run (killed, crashed, out of wall time) continues from its last
checkpoint: mdrun writes md.part.cpt every `checkpoint_min` minutes of wall
time, and the next run_md of the same request (md.run.json: the md_run.mdp,
conf.gro and topol.top it was made from, and the gmx) runs `mdrun -cpi
md.part.cpt -append`. GROMACS then truncates md.part.xtc/.edr/.log to the
checkpoint's step and appends, so every frame is written exactly once. The
part files are never declared as Snakemake outputs, so Snakemake's clean-up of
an incomplete job leaves them for the rerun (workflows/Snakefile, md_run).
"""
from __future__ import annotations

import hashlib
import json
import math
import os
import re
import sys
import time
from pathlib import Path

from dna_models.errors import ExternalToolError, InputError

from .defaults import CHECKPOINT_MIN
from .gmx import find_gmx, gmx_version, run_gmx, run_gmx_with_progress
from .mdlog import block_energies, last_energy_block, tail_text
from .mdp import read_mdp_value
from mdbridge.jsonio import write_json

PARTS = {"md.part.xtc": "md.xtc", "md.part.edr": "md.edr", "md.part.log": "md.log",
         "confout.part.gro": "confout.gro", "md.part.cpt": "md.cpt", "md.part.tpr": "md.tpr"}
FINAL = ("md.tpr", "md.xtc", "md.edr", "md.log", "confout.gro", "md.cpt", "md.done", "checks.json")
STATE = ("md.run.json", "md.part_prev.cpt", "md.part.trr")
# what a continuation appends to; without them a checkpoint continues as a new segment
SEGMENT_OUTPUTS = ("md.part.xtc", "md.part.edr", "md.part.log")


def _set_keys(mdp_text: str, values: dict) -> str:
    out, done = [], set()
    for ln in mdp_text.splitlines():
        key = ln.split(";")[0].split("=")[0].strip().lower().replace("_", "-")
        if key in values:
            out.append(f"{key:<23s} = {values[key]}")
            done.add(key)
        else:
            out.append(ln)
    out += [f"{k:<23s} = {v}" for k, v in values.items() if k not in done]
    return "\n".join(out) + "\n"


# A temperature no MD of a biomolecule that holds together reaches (runs at 300 K
# fluctuate by a few K; heated unfolding runs stay below ~10^3 K). Above it the system
# has blown up, and mdrun does not always stop by itself: with atoms flown ~1e6 nm
# apart, an AVX2 build of GROMACS 2022 was seen to spend over 5 min at one step
# (tests/python/test_reliability_gromacs.py), so run-md stops it.
BLOWN_UP_TEMPERATURE_K = 1e5


def blow_up(log_path: Path) -> str | None:
    """Why the run in LOG_PATH (mdrun's log, being written) has blown up, from the last
    energies mdrun logged: a temperature above BLOWN_UP_TEMPERATURE_K or an energy that
    is not a number; None while neither."""
    step, energies = block_energies(last_energy_block(tail_text(log_path)))
    bad = [k for k, v in energies.items() if not math.isfinite(v)]
    if bad:
        return f"mdrun logged {bad[0]} = {energies[bad[0]]} at step {step}: the system blew up"
    T = energies.get("Temperature")
    if T is not None and T > BLOWN_UP_TEMPERATURE_K:
        return (f"mdrun logged a temperature of {T:.3g} K at step {step}, above the "
                f"{BLOWN_UP_TEMPERATURE_K:.0e} K no intact molecule reaches: the system blew up")
    return None


STOPPED_FROM_OUTSIDE = ("It was stopped from outside (a kill, Ctrl-C, a batch system's time or "
                        "memory limit), not by the physics.")


def mdrun_diagnosis(output: str, log: str, returncode: int | None = None) -> str:
    """Why mdrun stopped, in GROMACS's own lines, for the error message.

    A TERM/INT signal (GROMACS prints "Received the TERM signal") or a SIGKILL is a
    stop from outside: say so and how to continue. Otherwise a blown-up system often
    ends in a segmentation fault with no GROMACS error block, so quote what shows the
    blow-up: the first LINCS warning (constraints that could not be satisfied) and the
    last energies mdrun logged."""
    sig = re.search(r"Received the (\w+) signal", output)
    if sig or returncode in (-9, -15, -2):
        how = (f"mdrun received the {sig.group(1)} signal and stopped" if sig else
               f"mdrun was killed by signal {-int(returncode or 0)}")
        step = re.findall(r"Writing checkpoint, step (\d+)", log)
        return (f"{how}. {STOPPED_FROM_OUTSIDE} "
                + (f"Its last checkpoint is at step {step[-1]}. " if step else "")
                + "Rerun the same command to continue from the last checkpoint; under a batch "
                  "system ask for more time (the workflow on SLURM: "
                  "--set-resources md_run:runtime=MINUTES).")
    out: list[str] = []
    lincs = [i for i, ln in enumerate(output.splitlines()) if "LINCS WARNING" in ln]
    if lincs:
        lines = output.splitlines()
        first = lines[lincs[0]:lincs[0] + 3]      # "Step n ... LINCS WARNING", deviation, rms/max
        out.append(f"mdrun printed {len(lincs)} LINCS warning(s): the bond constraints could "
                   "not be satisfied; the first:")
        out += ["  " + ln for ln in first]
    block = last_energy_block(log)
    if block:
        out.append("last energies in md.part.log:")
        out += ["  " + ln for ln in block]
    out.append("The system blew up. Usual causes: atoms too close in the starting structure "
               "(build-md warns about close contacts: rebuild with --minimize), or a time step "
               "too large (--dt; with --constraints h-bonds at most 0.002 ps).")
    return "\n".join(out)


def _request(d: Path, mdp_text: str, gmx_path: str, steps: int) -> dict:
    """What identifies a run: a checkpoint continues only the same request."""
    h = hashlib.sha256()
    for name in ("conf.gro", "topol.top"):
        h.update((d / name).read_bytes())
    for itp in sorted(d.glob("*.itp")):
        h.update(itp.name.encode() + itp.read_bytes())
    h.update(mdp_text.encode())
    return {"inputs_sha256": h.hexdigest(), "steps": steps, "gmx": gmx_path}


def _resumable(d: Path, request: dict) -> bool:
    """The same inputs and length, and a checkpoint to continue. The gmx may differ (a run
    carried through git to a machine whose CPU needs the project's own GROMACS build:
    scripts/build_gromacs.sh): mdrun itself checks that a checkpoint fits its run input."""
    try:
        old = json.loads((d / "md.run.json").read_text())
    except (OSError, ValueError):
        return False
    same = all(old.get(k) == request[k] for k in ("inputs_sha256", "steps"))
    return same and (d / "md.part.cpt").is_file() and (d / "md.part.tpr").is_file()


def _checkpoint_step(d: Path) -> int | None:
    """The step of md.part.cpt, from mdrun's log (the last 'Writing checkpoint, step N')."""
    log = d / "md.part.log"
    if not log.is_file():
        return None
    steps = re.findall(r"Writing checkpoint, step (\d+)", log.read_text(errors="replace"))
    return int(steps[-1]) if steps else None


def ns_per_day(log_text: str) -> float | None:
    """ns/day from an mdrun log's last "Performance:" line (ns/day, then hour/ns), None without one."""
    m = re.findall(r"Performance:\s+(\S+)\s+(\S+)", log_text)
    return float(m[-1][0]) if m else None


def run_md(directory: Path, *, ps: float | None = None, steps: int | None = None,
           gmx: str | None = None, threads: int | None = None, output_ps: float | None = None,
           checks: bool = True, checkpoint_min: float = CHECKPOINT_MIN, reprod: bool = False,
           fresh: bool = False, progress=None, stream=sys.stderr) -> dict:
    """grompp + mdrun in DIRECTORY (a build-md output). Returns the md.done record.

    Continues an interrupted run of the same request from its checkpoint unless
    FRESH. PROGRESS, if given, is called as progress(ps_done, ps_total) while
    mdrun runs (workflows/progress.py draws it)."""
    d = Path(directory)
    for need in ("conf.gro", "topol.top", "md.mdp", "build.json"):
        if not (d / need).is_file():
            raise InputError(f"{d}: {need} missing; run `dnarod build-md SCENE -o {d}` first")
    if ps is not None and steps is not None:
        raise InputError("give --ps or --steps, not both")
    if ps is not None and not ps > 0:
        raise InputError(f"--ps {ps:g}: the MD length must be > 0 ps")
    if not checkpoint_min > 0:
        raise InputError(f"--checkpoint-minutes {checkpoint_min}: must be > 0")
    gmx_path = find_gmx(gmx)
    build = json.loads((d / "build.json").read_text())
    mdp = (d / "md.mdp").read_text()
    dt = float(read_mdp_value(mdp, "dt") or 0.001)
    steps = _md_steps(d, build, dt, ps, steps, stream)
    run_mdp = _set_keys(mdp, _run_keys(steps, dt, output_ps))
    request = _request(d, run_mdp, gmx_path, steps)
    resume = _start_or_resume(d, request, run_mdp, gmx_path, dt, fresh, stream)
    wall = _mdrun(d, gmx_path, resume=resume, reprod=reprod, threads=threads, checkpoint_min=checkpoint_min,
                  on_step=(lambda k: progress(k * dt, steps * dt)) if progress is not None else None)
    for src, dst in PARTS.items():
        if (d / src).exists():
            (d / src).replace(d / dst)
    for f in STATE:
        (d / f).unlink(missing_ok=True)
    log = (d / "md.log").read_text() if (d / "md.log").exists() else ""
    record: dict = {"steps": steps, "dt_ps": dt, "length_ps": steps * dt, "wall_s": round(wall, 2),
                    "ns_per_day": ns_per_day(log), "threads": threads,
                    "resumed_from_checkpoint": resume, "checkpoint_min": checkpoint_min,
                    "reprod": reprod,
                    "gmx": {"path": gmx_path, "version": gmx_version(gmx_path)}}
    # written after every MD output is in place: its presence means the MD is complete
    write_json(d / "md.done", record)
    if checks:
        from .checks import write_checks
        write_checks(d, gmx=gmx_path)
        record["checks"] = "checks.json"
    return record


def _md_steps(d: Path, build: dict, dt: float, ps, steps, stream) -> int:
    """The MD's steps: --steps, else --ps, else the length the build was made for; a
    warning when the run outlasts the rod run that sized the box."""
    if steps is None:
        if ps is None:
            ps = float(build.get("md_length_ps") or 0.0)
            if ps <= 0:
                raise InputError(f"{d}/build.json has no md_length_ps: give --ps or --steps")
        steps = int(round(ps / dt))
    if steps < 1:
        raise InputError(f"--steps/--ps: need at least one MD step (got {steps})")
    run_ps = steps * dt
    planned = float(build.get("box", {}).get("rod_run_ps", run_ps))
    if run_ps > planned * (1 + 1e-9) and stream is not None:
        stream.write(f"warning: running {run_ps:g} ps but the box was sized from a rod run of "
                     f"{planned:g} ps; check min_side_image_distance in checks.json\n")
    return steps


def _run_keys(steps: int, dt: float, output_ps) -> dict:
    """The md.mdp keys this run sets: nsteps, and with --output-ps the output intervals
    (nstcalcenergy divides both the output interval and 100 steps)."""
    values = {"nsteps": steps}
    if output_ps is not None:
        if output_ps <= 0:
            raise InputError(f"--output-ps {output_ps}: must be > 0")
        every = max(1, int(round(output_ps / dt)))
        values.update({"nstxout-compressed": every, "nstenergy": every, "nstlog": every,
                       "nstcalcenergy": math.gcd(every, 100)})
    return values


def _start_or_resume(d: Path, request: dict, run_mdp: str, gmx_path: str, dt: float, fresh: bool,
                     stream) -> bool:
    """True when an interrupted run of the same request continues from its checkpoint
    (the finished files of any earlier run removed); otherwise every earlier output goes
    and grompp makes md.part.tpr. The request is recorded in md.run.json."""
    resume = not fresh and _resumable(d, request)
    if resume:
        for f in FINAL:      # a finished earlier run of something else is not this run
            (d / f).unlink(missing_ok=True)
        step0 = _checkpoint_step(d)
        if stream is not None:
            stream.write("run-md: continuing from the checkpoint md.part.cpt"
                         + (f" (step {step0}, {step0 * dt:g} ps)" if step0 is not None else "") + "\n")
        return True
    for f in FINAL + tuple(PARTS) + STATE:
        (d / f).unlink(missing_ok=True)
    (d / "md_run.mdp").write_text(run_mdp)
    run_gmx(gmx_path, ["grompp", "-f", "md_run.mdp", "-c", "conf.gro", "-p", "topol.top",
                       "-o", "md.part.tpr", "-po", "mdout.mdp", "-maxwarn", "0"], d,
            log_name="gmx_grompp_md.log")
    write_json(d / "md.run.json", request)
    return False


def _current_log(d: Path) -> Path:
    """mdrun's log being written: md.part.log, or a new segment's md.part.partNNNN.log."""
    seg = sorted(d.glob("md.part.part[0-9][0-9][0-9][0-9].log"))
    return seg[-1] if seg else d / "md.part.log"


def _mdrun(d: Path, gmx_path: str, *, resume: bool, reprod: bool, threads, checkpoint_min: float,
           on_step) -> float:
    """mdrun into the part files (appending to them when RESUME); on failure an
    ExternalToolError with mdrun_diagnosis. Returns the wall time, s."""
    args = ["mdrun", "-v", "-s", "md.part.tpr", "-x", "md.part.xtc", "-e", "md.part.edr",
            "-g", "md.part.log", "-c", "confout.part.gro", "-cpo", "md.part.cpt",
            "-o", "md.part.trr", "-cpt", f"{checkpoint_min:g}"]
    segment = resume and not all((d / f).is_file() for f in SEGMENT_OUTPUTS)
    if resume:
        # A checkpoint without the outputs it continues (a run carried to a new machine
        # through git: inputs and md.part.cpt, no trajectory) starts a new segment: mdrun
        # -noappend writes *.partNNNN.* files, renamed below to the usual part names.
        args += ["-cpi", "md.part.cpt", "-noappend" if segment else "-append"]
    if reprod:
        args += ["-reprod"]
    env = None
    if threads:
        args += ["-nt", str(int(threads))]
        # OMP_NUM_THREADS (Snakemake sets it to a rule's threads) is an OpenMP request mdrun
        # refuses beside an -nt it does not divide: the thread count asked for here decides
        env = {k: v for k, v in os.environ.items() if k != "OMP_NUM_THREADS"}
    t0 = time.time()
    try:
        run_gmx_with_progress(gmx_path, args, d, log_name="gmx_mdrun_md.log", on_step=on_step,
                              append_log=resume, watch=lambda: blow_up(_current_log(d)), env=env)
    except ExternalToolError as e:
        output = (d / "gmx_mdrun_md.log").read_text(errors="replace")
        log = (d / "md.part.log").read_text(errors="replace") if (d / "md.part.log").exists() else ""
        raise ExternalToolError(f"{e}\n{mdrun_diagnosis(output, log, e.returncode)}"
                                "\nNo MD result was kept "
                                f"(no md.done; partial files md.part.* in {d}; rerunning the "
                                "same command continues from the last checkpoint).") from None
    if segment:
        for name in SEGMENT_OUTPUTS + ("confout.part.gro",):
            stem, ext = name.rsplit(".", 1)
            for f in sorted(d.glob(f"{stem}.part[0-9][0-9][0-9][0-9].{ext}"))[-1:]:
                f.replace(d / name)
    return time.time() - t0
