"""Never lose a run: rodsim stopped by SIGTERM, SIGINT or SIGKILL
continues with `--resume` to a file equal, bit for bit, to the file of an
uninterrupted run of the same scene (the independent truth), for a
fixed-step and an adaptive scheme; checkpoints of another scene are refused;
a half-written file never looks finished."""
import signal
import subprocess
import time
from pathlib import Path

import h5py
import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "workflows" / "scenes"
DATASETS = ("time", "s", "fields/gamma", "fields/omega", "fields/Gamma", "fields/Omega", "energy",
            "centerline", "directors")

# dna158 (paper Table 1) at full length: ~2 s of CPU, long enough to be
# interrupted after a few frames on a loaded machine.
CASES = {
    "dop853": (SCENES / "dna158.toml", []),
    "rk4": (SCENES / "dna158.toml", ["--set", "solver.time=rk4", "--set", "solver.dt=0.2",
                                     "--set", "output.t_end=300", "--set", "output.frames=301",
                                     "--set", "checks.max_energy_drift=1e-3"]),
}


def run(rodsim, *args):
    return subprocess.run([str(rodsim), *map(str, args)], capture_output=True, text=True, timeout=300)


def frames_in(path):
    try:
        with h5py.File(path, "r") as f:
            return f["time"].shape[0]
    except (OSError, KeyError):
        return 0  # caught mid-flush or not created yet


def start_and_stop(rodsim, scene, out, extra, sig, after_frames=4, wait_for_checkpoint=False):
    """Start a run, wait for `after_frames` flushed frames (and a checkpoint
    file if asked), send `sig`; return the finished process."""
    partial, ckpt = Path(str(out) + ".partial"), Path(str(out) + ".ckpt")
    p = subprocess.Popen([str(rodsim), "run", str(scene), "-o", str(out), *extra],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.time() + 120
        while time.time() < deadline and p.poll() is None:
            time.sleep(0.02)
            if frames_in(partial) >= after_frames and (not wait_for_checkpoint or ckpt.exists()):
                break
        assert p.poll() is None, "the run ended before it could be interrupted: " + p.stderr.read()
        p.send_signal(sig)
        p.wait(timeout=120)
    finally:
        if p.poll() is None:
            p.kill()
            p.wait()
    return p


def assert_same_file(a, b):
    with h5py.File(a, "r") as fa, h5py.File(b, "r") as fb:
        for name in DATASETS:
            if name in fa:
                x, y = fa[name][...], fb[name][...]
                assert x.shape == y.shape, name
                assert np.array_equal(x, y), f"{name} differs (max {np.max(np.abs(x - y))})"
        for key in ("complete", "summary.steps", "summary.rejected", "summary.rhs_evaluations",
                    "summary.energy_drift"):
            assert fa.attrs[key] == fb.attrs[key], key


@pytest.fixture(scope="module")
def reference(rodsim, tmp_path_factory):
    """Uninterrupted runs, one per case."""
    d = tmp_path_factory.mktemp("ref")
    refs = {}
    for name, (scene, extra) in CASES.items():
        out = d / f"{name}.h5"
        p = run(rodsim, "run", scene, "-o", out, *extra)
        assert p.returncode == 0, p.stderr
        refs[name] = out
    return refs


@pytest.mark.parametrize("case,sig", [("dop853", signal.SIGTERM), ("rk4", signal.SIGINT)])
def test_signal_writes_checkpoint_and_resume_gives_the_same_bits(rodsim, reference, tmp_path, case, sig):
    scene, extra = CASES[case]
    out = tmp_path / "run.h5"
    p = start_and_stop(rodsim, scene, out, extra, sig)
    assert p.returncode == 128 + sig, p.stderr
    err = p.stderr.read()
    name = "SIGTERM" if sig == signal.SIGTERM else "SIGINT"
    assert f"{name} received: stopped at t = " in err
    assert "--resume" in err and str(out) in err
    ckpt, partial = Path(str(out) + ".ckpt"), Path(str(out) + ".partial")
    assert ckpt.exists() and partial.exists() and not out.exists()
    with h5py.File(partial, "r") as f:  # a stopped run never looks finished
        assert f.attrs["complete"] == 0
        n_before = f["time"].shape[0]
    with h5py.File(ckpt, "r") as f:
        assert f.attrs["next_frame"] == n_before
        assert f.attrs["method"] == case
    q = run(rodsim, "run", scene, "-o", out, *extra, "--resume")
    assert q.returncode == 0, q.stderr
    assert "resuming from" in q.stderr
    assert not ckpt.exists() and not partial.exists()
    assert_same_file(out, reference[case])


def test_sigkill_after_a_timed_checkpoint_resumes_exactly(rodsim, reference, tmp_path):
    """SIGKILL cannot be caught: the last timed checkpoint is the restart
    point, frames flushed after it are cut and written again."""
    scene, extra = CASES["dop853"]
    out = tmp_path / "run.h5"
    # the scene key (not --checkpoint-every) here; the resume below omits it:
    # the checkpoint interval may differ between a run and its resume
    p = start_and_stop(rodsim, scene, out, [*extra, "--set", "output.checkpoint_interval_s=0.05"], signal.SIGKILL,
                       after_frames=30, wait_for_checkpoint=True)
    assert p.returncode == -signal.SIGKILL
    with h5py.File(str(out) + ".ckpt", "r") as f:
        assert 1 <= f.attrs["next_frame"] <= frames_in(str(out) + ".partial")
    q = run(rodsim, "run", scene, "-o", out, *extra, "--resume")
    assert q.returncode == 0, q.stderr
    assert_same_file(out, reference["dop853"])


def test_resume_without_checkpoint_starts_from_zero(rodsim, reference, tmp_path):
    scene, extra = CASES["dop853"]
    out = tmp_path / "run.h5"
    q = run(rodsim, "run", scene, "-o", out, *extra, "--resume")
    assert q.returncode == 0, q.stderr
    assert "no checkpoint" in q.stderr and "starting from t = 0" in q.stderr
    assert_same_file(out, reference["dop853"])


def test_checkpoint_of_another_scene_is_refused(rodsim, tmp_path):
    scene, extra = CASES["dop853"]
    out = tmp_path / "run.h5"
    p = start_and_stop(rodsim, scene, out, extra, signal.SIGTERM)
    assert p.returncode == 128 + signal.SIGTERM
    q = run(rodsim, "run", scene, "-o", out, *extra, "--set", "output.frames=600", "--resume")
    assert q.returncode == 2
    assert "run.h5.ckpt' was written by a run of a different scene" in q.stderr
    assert "frames = 600" in q.stderr and "without --resume" in q.stderr
    # the interrupted run is untouched and still resumes
    assert Path(str(out) + ".partial").exists()
    assert run(rodsim, "run", scene, "-o", out, *extra, "--resume").returncode == 0


def test_resume_needs_the_partial_output(rodsim, tmp_path):
    scene, extra = CASES["dop853"]
    out = tmp_path / "run.h5"
    p = start_and_stop(rodsim, scene, out, extra, signal.SIGTERM)
    assert p.returncode == 128 + signal.SIGTERM
    Path(str(out) + ".partial").unlink()
    q = run(rodsim, "run", scene, "-o", out, *extra, "--resume")
    assert q.returncode == 2
    assert "cannot resume" in q.stderr and "run.h5.partial" in q.stderr and "does not exist" in q.stderr


def test_fresh_run_removes_a_stale_checkpoint(rodsim, tmp_path):
    scene, extra = CASES["dop853"]
    out = tmp_path / "run.h5"
    p = start_and_stop(rodsim, scene, out, extra, signal.SIGTERM)
    assert p.returncode == 128 + signal.SIGTERM
    q = run(rodsim, "run", scene, "-o", out, *extra, "--set", "output.t_end=10", "--set", "output.frames=3")
    assert q.returncode == 0, q.stderr
    assert not Path(str(out) + ".ckpt").exists()
    with h5py.File(out, "r") as f:
        assert f.attrs["complete"] == 1 and f["time"].shape == (3,)


def test_numerical_error_leaves_no_checkpoint(rodsim, tmp_path):
    out = tmp_path / "bad.h5"
    p = run(rodsim, "run", SCENES / "twisted_wave.toml", "-o", out, "--checkpoint-every", "0",
            "--set", "checks.max_energy_drift=1e-14", "--set", "solver.rtol=1e-3", "--set", "solver.atol=1e-3")
    assert p.returncode == 3
    assert not Path(str(out) + ".ckpt").exists()
    with h5py.File(out, "r") as f:
        assert f.attrs["complete"] == 0


def test_negative_checkpoint_interval_is_refused(rodsim, tmp_path):
    p = run(rodsim, "run", SCENES / "dna21.toml", "-o", tmp_path / "x.h5", "--checkpoint-every", "-1")
    assert p.returncode == 2 and "--checkpoint-every" in p.stderr
