"""A killed MD continues from its checkpoint to the same trajectory.

The truth is an uninterrupted run of the same inputs with the same gmx, thread
count and mdrun -reprod: the interrupted-and-resumed run must give the same
frame times, each frame once, the same energies at every output time, and
the same final state (full-precision coordinates and velocities from the last
checkpoint). GROMACS documents -reprod as "the same result for the same
input, binary and hardware", which this test shows holds across a restart.
The kill is a SIGKILL of gmx mdrun itself (no chance to write a last
checkpoint), after at least one timed checkpoint, so mdrun must truncate its
output files back to the checkpoint before appending.
"""
import json
import os
import re
import shutil
import signal
import subprocess
import threading
import time
from pathlib import Path

import MDAnalysis as mda
import numpy as np
import pytest

from dna_models.errors import ExternalToolError
from mdbridge.md.gromacs.energy import read_energies
from mdbridge.md.gromacs.mdp import MdSettings
from mdbridge.md.gromacs.run import run_md
from test_gromacs_build import make  # noqa: F401  (the 21-bp build; gmx: conftest)

# 12 ps at 1 fs: ~12 s with Debian's gmx on an idle core, ~1 s with the AVX-512 build of
# scripts/build_gromacs.sh (3000 steps ended before the kill there: measured), so the kill
# lands mid-run with either; a multiple of the output interval, so the last frame is on it
STEPS = 12000
OUT_PS = 0.03         # 401 frames
RUN = dict(steps=STEPS, threads=2, output_ps=OUT_PS, reprod=True, checks=False, stream=None)


@pytest.fixture(scope="module")
def built(gmx, tmp_path_factory):
    d = tmp_path_factory.mktemp("resume_build")
    make(d, T=300.0, seed=11, gmx=gmx, minimize=True, settings=MdSettings(nsteps=STEPS))
    return d


def copy_build(src: Path, dst: Path) -> Path:
    shutil.copytree(src, dst)
    return dst


def mdrun_children():
    """PIDs of `gmx mdrun` processes whose parent is this test process."""
    me, out = os.getpid(), []
    for p in Path("/proc").iterdir():
        if not p.name.isdigit():
            continue
        try:
            stat = (p / "stat").read_text()
            cmd = (p / "cmdline").read_bytes().split(b"\0")
        except OSError:
            continue
        ppid = int(stat.rsplit(")", 1)[1].split()[1])
        if ppid == me and b"mdrun" in cmd:
            out.append(int(p.name))
    return out


def final_state(d: Path, gmx):
    """Full-precision x and v of the run's last checkpoint (md.cpt), via trjconv."""
    subprocess.run([gmx, "trjconv", "-f", "md.cpt", "-o", "final.trr"], cwd=d, input="0\n",
                   capture_output=True, text=True, check=True)
    u = mda.Universe(str(d / "confout.gro"), str(d / "final.trr"))
    ts = u.trajectory[-1]
    return ts.time, ts.positions.copy(), ts.velocities.copy()


def frames(d: Path):
    u = mda.Universe(str(d / "confout.gro"), str(d / "md.xtc"))
    t, x = [], []
    for ts in u.trajectory:
        t.append(ts.time)
        x.append(ts.positions.copy())
    return np.array(t), np.array(x)


def kill_after_first_checkpoint(d: Path, gmx) -> list:
    """Start the run in D with a checkpoint every 0.3 s, SIGKILL mdrun just after its first
    checkpoint (frames beyond it are written and must be truncated away); the run's error."""
    err: list[BaseException] = []

    def first_run():
        try:
            run_md(d, gmx=gmx, checkpoint_min=0.005, **RUN)
        except ExternalToolError as e:
            err.append(e)

    th = threading.Thread(target=first_run)
    th.start()
    deadline = time.time() + 600
    while not (d / "md.part.cpt").exists():
        assert th.is_alive() and time.time() < deadline, "mdrun ended before its first checkpoint"
        time.sleep(0.05)
    time.sleep(0.1)
    pids = mdrun_children()
    assert len(pids) == 1 and not (d / "md.done").exists(), "mdrun finished before the kill"
    os.kill(pids[0], signal.SIGKILL)
    th.join()
    return err


@pytest.fixture(scope="module")
def reference(built, gmx, tmp_path_factory):
    d = copy_build(built, tmp_path_factory.mktemp("ref") / "md")
    run_md(d, gmx=gmx, **RUN)
    return d


@pytest.fixture(scope="module")
def resumed(built, gmx, tmp_path_factory):
    d = copy_build(built, tmp_path_factory.mktemp("killed") / "md")
    err = kill_after_first_checkpoint(d, gmx)
    assert err and "signal 9" in str(err[0]), err
    assert not (d / "md.done").exists() and not (d / "md.xtc").exists()
    log = (d / "md.part.log").read_text()
    ckpt = [int(s) for s in re.findall(r"Writing checkpoint, step (\d+)", log)]
    assert ckpt and 0 < ckpt[-1] < STEPS
    rec = run_md(d, gmx=gmx, **RUN)
    return d, rec, ckpt[-1]


def test_resumed_run_continues_and_is_marked(resumed):
    d, rec, ckpt = resumed
    assert rec["resumed_from_checkpoint"] is True
    assert (d / "md.done").is_file() and not list(d.glob("*.part.*"))
    assert not (d / "md.run.json").exists()


def test_every_frame_exactly_once_and_equal_to_the_uninterrupted_run(resumed, reference):
    d, _, _ = resumed
    t, x = frames(d)
    t_ref, x_ref = frames(reference)
    n = STEPS // round(OUT_PS * 1000) + 1
    assert len(t) == n and len(t_ref) == n
    assert np.allclose(t, OUT_PS * np.arange(n), atol=1e-6, rtol=0)
    assert np.array_equal(t, t_ref)
    assert np.array_equal(x, x_ref)                      # xtc: 1e-4 nm grid, bitwise


def test_energy_file_continuous_and_equal(resumed, reference, gmx):
    d, _, _ = resumed
    e, e_ref = read_energies(d, gmx), read_energies(reference, gmx)
    t = e["time"]
    assert np.allclose(np.diff(t), OUT_PS, atol=1e-6) and t[0] == 0.0
    assert len(t) == len(e_ref["time"])
    for k in ("Potential", "Kinetic En.", "Total Energy"):
        assert np.array_equal(e[k], e_ref[k]), k


def test_final_state_bitwise_equal(resumed, reference, gmx):
    d, _, _ = resumed
    t, x, v = final_state(d, gmx)
    t_ref, x_ref, v_ref = final_state(reference, gmx)
    assert t == t_ref == pytest.approx(STEPS * 0.001)
    assert np.array_equal(x, x_ref) and np.array_equal(v, v_ref)


def test_control_a_fresh_run_from_the_checkpoint_time_differs(built, reference, gmx, tmp_path):
    """Control: the comparison can fail. A run whose thermal velocities differ (another
    seed) ends elsewhere; and --fresh ignores a checkpoint."""
    d = copy_build(built, tmp_path / "md")
    g = (d / "conf.gro").read_text().splitlines()
    # perturb one velocity component of atom 1 in its last digit
    ln = g[2]
    v = float(ln[44:52]) + 0.0001
    g[2] = ln[:44] + f"{v:8.4f}" + ln[52:]
    (d / "conf.gro").write_text("\n".join(g) + "\n")
    run_md(d, gmx=gmx, **RUN)
    _, x, _ = final_state(d, gmx)
    _, x_ref, _ = final_state(reference, gmx)
    assert not np.array_equal(x, x_ref)
    assert json.loads((d / "md.done").read_text())["resumed_from_checkpoint"] is False


def test_a_checkpoint_carried_without_its_outputs_continues_as_a_segment(resumed, reference, gmx,
                                                                          tmp_path):
    """What git carries to a new machine: the inputs, md.run.json, md.part.tpr and md.part.cpt,
    no trajectory. The run continues from the checkpoint as a new segment: md.xtc holds the
    frames from the checkpoint on, equal to the uninterrupted run's (-reprod)."""
    src, _, _ = resumed
    d = tmp_path / "carried"
    d.mkdir()
    # the state of an interrupted run: rebuild it from the killed run's inputs (a fresh
    # copy of the build, killed after its first checkpoint, then only git's files kept)
    for f in src.iterdir():
        if f.suffix in (".gro", ".top", ".itp", ".mdp", ".json") and f.name not in ("md.done", "checks.json"):
            shutil.copy(f, d / f.name)
    (d / "md.done").unlink(missing_ok=True)
    kill_after_first_checkpoint(d, gmx)
    kept = {"md.part.cpt", "md.part.tpr", "md.run.json", "conf.gro", "topol.top", "md.mdp", "build.json"}
    for f in d.iterdir():
        if f.name not in kept and f.suffix != ".itp":
            f.unlink()
    t_cpt = float(subprocess.run([gmx, "check", "-f", "md.part.cpt"], cwd=d, capture_output=True,
                                 text=True).stderr.split("Last frame")[-1].split("time")[1].split()[0])
    rec = run_md(d, gmx=gmx, **RUN)
    assert rec["resumed_from_checkpoint"] is True
    t, x = frames(d)
    t_ref, x_ref = frames(reference)
    assert 0 < t[0] and t[-1] == pytest.approx(t_ref[-1])
    assert t[0] == pytest.approx(t_cpt, abs=OUT_PS)
    k = np.searchsorted(t_ref, t[0] - 1e-6)
    assert np.array_equal(t, t_ref[k:])
    assert np.array_equal(x, x_ref[k:])
    assert not list(d.glob("*.part*"))
