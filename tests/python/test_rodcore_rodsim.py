"""build/bin/rodsim as a user runs it: exit codes, messages that name the
problem, the summary line, the `complete` attribute, a progress bar only on a
terminal, and a killed run that leaves its flushed frames readable."""
import os
import pty
import re
import signal
import subprocess
import time
import tomllib
from pathlib import Path

import h5py
import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "workflows" / "scenes"


def run(rodsim, *args, **kw):
    return subprocess.run([str(rodsim), *map(str, args)], capture_output=True, text=True, timeout=120, **kw)


def test_help_is_for_newcomers(rodsim):
    p = run(rodsim, "--help")
    assert p.returncode == 0
    for word in ("run", "check", "kinds", "docs/scenes.md", "--set", "Exit status"):
        assert word in p.stdout, word
    p = run(rodsim, "run", "--help")
    assert p.returncode == 0 and "--output" in p.stdout and "--quiet" in p.stdout


def test_version_is_what_every_output_file_records(rodsim, tmp_path):
    p = run(rodsim, "--version")
    assert p.returncode == 0 and p.stderr == "", p.stderr
    m = re.fullmatch(r"rodsim (\S+) \(git revision (\S+)\)\n", p.stdout)
    assert m, p.stdout
    # The version is the one project(dnarod VERSION ...) sets, and both values
    # are the attributes the same rodsim writes into its output.
    cmake = (ROOT / "CMakeLists.txt").read_text()
    assert m.group(1) == re.search(r"project\(dnarod VERSION (\S+)", cmake).group(1)
    out = tmp_path / "v.h5"
    q = run(rodsim, "run", SCENES / "twisted_wave.toml", "-o", out, "-q", "--set", "output.t_end=0.1")
    assert q.returncode == 0, q.stderr
    with h5py.File(out, "r") as f:
        assert (f.attrs["rodcore_version"], f.attrs["git_revision"]) == (m.group(1), m.group(2))


def test_run_writes_a_complete_file_and_a_summary_line(rodsim, tmp_path):
    out = tmp_path / "wave.h5"
    p = run(rodsim, "run", SCENES / "twisted_wave.toml", "-o", out)
    assert p.returncode == 0, p.stderr
    assert p.stderr == ""  # not a terminal: no progress bar
    assert re.fullmatch(r"rodsim: wrote .*wave\.h5: 11 frames to t = 2\.3545; \d+ steps \(\d+ rejected\), "
                        r"\d+ RHS evaluations, \S+ s wall, energy drift \S+ \(spectral\+dop853\)\n", p.stdout), p.stdout
    assert not Path(str(out) + ".partial").exists()
    with h5py.File(out, "r") as f:
        assert f.attrs["complete"] == 1
        assert f["time"].shape == (11,)
        assert f["fields/Gamma"].shape == (11, 32, 3)
        assert f["directors"].shape == (11, 32, 3, 3)
        steps = int(re.search(r"; (\d+) steps", p.stdout).group(1))
        assert f.attrs["summary.steps"] == steps
        assert f.attrs["initial.kind"] == "twisted_wave"
        # the scene as written, byte for byte, and no overrides
        assert f.attrs["scene_file"] == (SCENES / "twisted_wave.toml").read_text()
        assert f.attrs["scene_overrides"] == ""
        # the resolved scene in the file is valid TOML with every section
        sc = tomllib.loads(f.attrs["scene"])
        assert set(sc) == {"rod", "material", "initial", "solver", "output", "checks"}
    q = run(rodsim, "run", SCENES / "twisted_wave.toml", "-o", tmp_path / "q.h5", "--quiet")
    assert q.returncode == 0 and q.stdout == "" and q.stderr == ""


def test_progress_bar_only_on_a_terminal(rodsim, tmp_path):
    master, slave = pty.openpty()
    try:
        p = subprocess.Popen([str(rodsim), "run", str(SCENES / "dna21.toml"), "-o", str(tmp_path / "a.h5")],
                             stdout=subprocess.PIPE, stderr=slave)
        p.wait(timeout=120)
        os.close(slave)
        slave = None
        seen = b""
        while True:
            try:
                chunk = os.read(master, 4096)
            except OSError:
                break
            if not chunk:
                break
            seen += chunk
    finally:
        if slave is not None:
            os.close(slave)
        os.close(master)
    assert p.returncode == 0
    assert b"%" in seen and b"[" in seen and b"t = " in seen, seen


def test_bad_key_exits_2_naming_file_line_key_and_suggestion(rodsim, tmp_path):
    scene = tmp_path / "bad.toml"
    scene.write_text("[rod]\nlength = 1.0\npoints = 16\n[solver]\nrtoll = 1e-8\n")
    p = run(rodsim, "run", scene, "-o", tmp_path / "x.h5")
    assert p.returncode == 2
    assert p.stderr.startswith("rodsim: error: ")
    assert f"{scene}:5: solver.rtoll: unknown key in [solver]; did you mean solver.rtol?" in p.stderr
    assert not (tmp_path / "x.h5").exists() and not (tmp_path / "x.h5.partial").exists()


def test_set_overrides_and_their_errors(rodsim, tmp_path):
    out = tmp_path / "o.h5"
    p = run(rodsim, "run", SCENES / "twisted_wave.toml", "-o", out, "--set", "output.frames=4",
            "--set", "solver.space=fd4", "--set", "rod.points=40")
    assert p.returncode == 0, p.stderr
    with h5py.File(out, "r") as f:
        assert f["time"].shape == (4,) and f["s"].shape == (40,)
        assert f.attrs["solver.space"] == "fd4"
        assert f.attrs["scene_overrides"] == "output.frames=4\nsolver.space=fd4\nrod.points=40\n"
    p = run(rodsim, "run", SCENES / "twisted_wave.toml", "-o", out, "--set", "solver.rtol=2")
    assert p.returncode == 2
    assert "--set solver.rtol: found 2; allowed: a number > 0 and < 1" in p.stderr
    p = run(rodsim, "run", SCENES / "twisted_wave.toml", "-o", out, "--set", "rtol=1e-8")
    assert p.returncode == 2 and "expected section.key=value" in p.stderr


def test_input_problems_exit_2(rodsim, tmp_path):
    p = run(rodsim, "run", tmp_path / "none.toml", "-o", tmp_path / "x.h5")
    assert p.returncode == 2 and "none.toml': no such file" in p.stderr
    (tmp_path / "plain").write_text("a file\n")
    p = run(rodsim, "run", SCENES / "dna21.toml", "-o", tmp_path / "plain" / "x.h5")
    assert p.returncode == 2 and "plain is a file, not a folder" in p.stderr
    p = run(rodsim, "run", SCENES / "dna21.toml")  # no -o
    assert p.returncode == 2 and "--output" in p.stderr
    p = run(rodsim, "frobnicate")
    assert p.returncode == 2
    scene = tmp_path / "ic.toml"
    scene.write_text('[rod]\nlength = 1.0\npoints = 16\n[initial]\nkind = "file"\npath = "missing.h5"\n')
    p = run(rodsim, "run", scene, "-o", tmp_path / "x.h5")
    assert p.returncode == 2 and "initial.path" in p.stderr and "missing.h5' does not exist" in p.stderr


def test_numerical_error_exits_3_and_keeps_the_frames(rodsim, tmp_path):
    out = tmp_path / "bad.h5"
    p = run(rodsim, "run", SCENES / "twisted_wave.toml", "-o", out, "--set", "checks.max_energy_drift=1e-14",
            "--set", "solver.rtol=1e-3", "--set", "solver.atol=1e-3")
    assert p.returncode == 3
    assert p.stderr.startswith("rodsim: error: ") and "energy drift" in p.stderr
    m = re.search(r"(\d+) frame\(s\) written so far", p.stderr)
    assert m, p.stderr
    with h5py.File(out, "r") as f:
        assert f.attrs["complete"] == 0
        assert "energy drift" in f.attrs["error"]
        n = int(m.group(1))
        assert f["time"].shape == (n,)
        assert f["fields/gamma"].shape[0] == n


def test_killed_run_leaves_a_readable_partial_file(rodsim, tmp_path):
    """SIGKILL mid-run: OUT.h5.partial holds every frame flushed so far, read
    here from a second process while the writer is still running, and equal
    to the same frames of an uninterrupted run."""
    out = tmp_path / "long.h5"
    partial = Path(str(out) + ".partial")
    # dna158 for 10x the paper's time: ~25 s if left alone; frame spacing 1.062.
    p = subprocess.Popen([str(rodsim), "run", str(SCENES / "dna158.toml"), "-o", str(out),
                          "--set", "output.t_end=6372.0", "--set", "output.frames=6001"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    try:
        seen = 0
        deadline = time.time() + 60
        while seen < 5 and time.time() < deadline and p.poll() is None:
            time.sleep(0.05)
            if partial.exists():
                try:
                    with h5py.File(partial, "r") as f:  # while the writer has it open
                        seen = f["time"].shape[0]
                except (OSError, KeyError):
                    pass  # caught mid-flush: try again
        assert p.poll() is None, "the run ended before it could be killed"
        assert seen >= 5
    finally:
        p.send_signal(signal.SIGKILL)
        p.wait()
    assert p.returncode == -signal.SIGKILL
    assert not out.exists() and partial.exists()
    with h5py.File(partial, "r") as f:
        T = f["time"].shape[0]
        assert T >= seen
        assert f.attrs["complete"] == 0
        for name in ("fields/gamma", "fields/omega", "fields/Gamma", "fields/Omega", "centerline", "directors"):
            assert f[name].shape[0] >= T  # `time` is written last in each frame
        t = f["time"][:T]
        gamma = f["fields/gamma"][:T]
        centerline = f["centerline"][:T]
    np.testing.assert_allclose(t, np.arange(T) * 6372.0 / 6000, rtol=1e-14)
    # the same frames from a short, complete run of the same scene
    ref = tmp_path / "ref.h5"
    q = run(rodsim, "run", SCENES / "dna158.toml", "-o", ref, "--set", f"output.t_end={(T - 1) * 6372.0 / 6000!r}",
            "--set", f"output.frames={T}")
    assert q.returncode == 0, q.stderr
    with h5py.File(ref, "r") as f:
        np.testing.assert_allclose(f["time"][:], t, rtol=1e-14)
        np.testing.assert_allclose(f["fields/gamma"][:], gamma, rtol=0, atol=1e-9)
        np.testing.assert_allclose(f["centerline"][:], centerline, rtol=0, atol=1e-8)


def test_check_prints_the_resolved_scene(rodsim):
    p = run(rodsim, "check", SCENES / "dna158.toml")
    assert p.returncode == 0, p.stderr
    sc = tomllib.loads(p.stdout)
    assert sc["rod"]["points"] == 158
    # rod length = bp * rise / ell (Sec 6.1), from dna_models.units
    from dna_models.units import Units
    u = Units.paper()
    assert sc["rod"]["length"] == pytest.approx(158 * u.rise_A / u.ell_A, rel=1e-14)
    assert sc["rod"]["Omega0"][2] == pytest.approx(2 * np.pi * 15 / sc["rod"]["length"], rel=1e-14)


def test_kinds_lists_the_registry(rodsim):
    import rodcore
    p = run(rodsim, "kinds")
    assert p.returncode == 0
    for k in rodcore.kinds():
        assert f"### `{k['name']}`" in p.stdout
        for param in k["numbers"] + k["strings"]:
            assert f"| `{param['name']}` |" in p.stdout


@pytest.mark.parametrize("scene", sorted(p.name for p in SCENES.glob("*.toml")))
def test_every_example_scene_is_valid(rodsim, scene):
    p = run(rodsim, "check", SCENES / scene)
    assert p.returncode == 0, p.stderr
