"""MD that fails must say so clearly and must never look finished.

The real chain through the command line: `dnarod build-md` of a sheared 21-bp
duplex without --minimize, then `dnarod run-md`. The paper's dna_planar scene
with a shear amplitude A_A = 5 A shifts neighbouring base pairs sideways; the
rigid templates and pdb2gmx's hydrogens then overlap (an H2' of one nucleotide
0.66 A from an H5' of the next), which build-md reports, and mdrun blows up at
step 0 (LJ energy 4e6-1e10 kJ/mol). That the system is unphysical is independent
of dnarod: GROMACS's own energies and LINCS say so. How the run ends depends on the
GROMACS build: Debian's (SSE4.1) stops with its own error; the project's AVX2 build
logs 4.4e9 K at step 0 and then hangs in one step, which run-md's guard stops
(mdbridge/md/gromacs/run.py: blow_up; tests/python/test_mdrun_guard.py). (From A_A ~ 6 A the builder
refuses earlier: its O3'-P links leave 1.5-1.8 A, mdbridge/md/builder/backbone.py.)
"""
import json
import os
import re
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
FINISHED_LOOKING = ("md.xtc", "md.edr", "md.log", "confout.gro", "md.done", "checks.json")


def run_dnarod(dnarod, *args, cwd):
    # GMX_MAXCONSTRWARN (GROMACS's own variable, default 999): with h-bond constraints this
    # system otherwise keeps stepping with LINCS warnings while coordinates run off, and can
    # hang in the neighbour search; a low limit makes mdrun stop with its fatal error at once
    env = dict(os.environ, GMX_MAXCONSTRWARN="5")
    return subprocess.run([str(dnarod), *map(str, args)], cwd=cwd, capture_output=True, text=True,
                          timeout=300, env=env)


def sheared_build(dnarod, tmp, *extra):
    """dna21.toml with A_A = 5 A, built at 0 K without the restrained minimisation."""
    scene = (ROOT / "workflows" / "scenes" / "dna21.toml").read_text()
    assert "A_A = 0.0" in scene
    (tmp / "sheared.toml").write_text(scene.replace("A_A = 0.0", "A_A = 5.0"))
    b = run_dnarod(dnarod, "build-md", "sheared.toml", "-o", "md", "--ps", "0.2", "--temperature",
                   "0", "--seed", "3", *extra, cwd=tmp)
    assert b.returncode == 0, b.stderr
    # the build itself warns: the clash is real, and not of dnarod's run-md making
    assert "closer than 1.5 A" in b.stderr and "--minimize" in b.stderr
    contact = json.loads((tmp / "md" / "build.json").read_text())["closest_nonbonded_contact"]
    assert contact["min_distance_A"] < 1.0
    return tmp / "md"


def run_md_fails(dnarod, d):
    (d / "md.done").write_text("{}")                # a stale marker from an earlier run
    # one thread: with two thread-MPI ranks mdrun can hang on this blown-up system (measured:
    # minutes at step 0, SIGTERM ignored)
    r = run_dnarod(dnarod, "run-md", "md", "--steps", "100", "--threads", "1", "--output-ps",
                   "0.05", cwd=d.parent)
    assert r.returncode == 2, (r.returncode, r.stdout, r.stderr)
    assert r.stderr.startswith("dnarod run-md: error: `gmx mdrun` failed"), r.stderr
    assert "Traceback" not in r.stderr
    # nothing that looks like a finished MD, and the stale marker is gone
    for f in FINISHED_LOOKING:
        assert not (d / f).exists(), f
    assert "run-md: done" not in r.stdout
    # the full GROMACS output is kept where the message says
    assert "full output in md/gmx_mdrun_md.log" in r.stderr
    assert (d / "gmx_mdrun_md.log").is_file()
    assert "rebuild with --minimize" in r.stderr
    return r.stderr


def quoted_energy(err, name):
    """A value from the energy table quoted in the message (names row, then values row)."""
    lines = err.splitlines()
    for i, ln in enumerate(lines):
        cols = [ln[k:k + 15].strip() for k in range(2, len(ln), 15)]   # GROMACS: %15s columns
        if name in cols:
            vals = [lines[i + 1][k:k + 15] for k in range(2, len(lines[i + 1]), 15)]
            return float(vals[cols.index(name)])
    raise AssertionError(f"{name} not quoted in:\n{err}")


def test_mdrun_blow_up_is_a_clear_error_and_never_looks_finished(gmx, dnarod, tmp_path):
    d = sheared_build(dnarod, tmp_path)
    err = run_md_fails(dnarod, d)
    # GROMACS's own lines: the step it stopped at and the energies it logged there
    assert "last energies in md.part.log:" in err and "Energies (kJ/mol)" in err
    step = re.search(r"Step\s+Time\n\s+(\d+)\s", err)
    assert step and int(step.group(1)) < 100
    # a duplex at 0 K has |LJ| of order 1e3-1e4 kJ/mol; 1e6 means overlapping atoms
    assert quoted_energy(err, "LJ (SR)") > 1e6
    # a signal death is named, not shown as a bare negative exit code
    assert "exit -" not in err
    if "stopped by dnarod" in err:          # the guard's stop names the temperature it read
        assert re.search(r"temperature of \S+ K at step \d+", err), err


def test_lincs_warnings_are_named_in_the_error(gmx, dnarod, tmp_path):
    d = sheared_build(dnarod, tmp_path, "--constraints", "h-bonds")
    assert "constraints             = h-bonds" in (d / "md.mdp").read_text()
    err = run_md_fails(dnarod, d)
    m = re.search(r"mdrun printed (\d+) LINCS warning\(s\)", err)
    assert m and int(m.group(1)) >= 1, err
    # the first LINCS WARNING quoted as GROMACS printed it, with its deviation: a relative
    # constraint deviation above 1 means an H-bond more than twice its length
    assert re.search(r"Step \d+, time \S+ \(ps\)\s+LINCS WARNING", err)
    dev = re.search(r"relative constraint deviation after LINCS:\n\s*rms \S+, max (\S+)", err)
    assert dev and float(dev.group(1)) > 1.0, err


def test_absurd_time_step_is_refused_before_any_md(gmx, dnarod, tmp_path):
    """A 10 fs step never reaches mdrun: without constraints build-md refuses it (X-H
    bonds), with h-bond constraints grompp does (heavy-atom bonds: period ~19 fs < 5 dt,
    GROMACS's own rule), and the directory is then not a build run-md accepts."""
    scene = ROOT / "workflows" / "scenes" / "dna21.toml"
    r = run_dnarod(dnarod, "build-md", scene, "-o", "plain", "--ps", "1", "--dt", "0.01",
                   cwd=tmp_path)
    assert r.returncode == 2 and "--dt 0.01" in r.stderr and "dt <= 0.001 ps" in r.stderr
    r = run_dnarod(dnarod, "build-md", scene, "-o", "md", "--ps", "1", "--dt", "0.01",
                   "--constraints", "h-bonds", "--temperature", "0", "--seed", "3", cwd=tmp_path)
    assert r.returncode == 2, r.stderr
    assert "`gmx grompp` failed" in r.stderr and "oscillational period" in r.stderr
    assert "time step of 1.0e-02 ps" in r.stderr and "Traceback" not in r.stderr
    assert not (tmp_path / "md" / "build.json").exists()
    r = run_dnarod(dnarod, "run-md", "md", cwd=tmp_path)
    # the failed build left no folder md (it is built beside it and moved in on success)
    assert r.returncode == 2 and "md: no such folder" in r.stderr
    for f in FINISHED_LOOKING:
        assert not (tmp_path / "md" / f).exists(), f
