"""Errors at the terminal: each says what failed, which file, and what
to try. One test per case that did not, run as a user runs the command.

Before: a missing rod file quoted h5py's low-level errno text; a file MDAnalysis cannot
read dumped MDAnalysis's whole list of formats; one structure and no trajectory for
coarse-grain said "need far more" frames without saying how to give them; `run-md
--ps -1` reported "-1000 steps"; an mdrun stopped by a TERM signal (a kill, a batch
system's time limit) was diagnosed as "The system blew up"."""
import os
import re
import signal
import subprocess
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "workflows" / "scenes"


def dnarod_fails(dnarod, *args, cwd=None) -> str:
    p = subprocess.run([str(dnarod), *map(str, args)], capture_output=True, text=True, cwd=cwd, timeout=600)
    assert p.returncode == 2, (p.returncode, p.stderr[-2000:])
    assert "Traceback" not in p.stderr
    first = [ln for ln in p.stderr.splitlines() if "error:" in ln]
    assert first, p.stderr
    return p.stderr[p.stderr.index(first[0]):]


@pytest.fixture(scope="module")
def md21(dnarod, gmx, tmp_path_factory):
    d = tmp_path_factory.mktemp("errors")
    p = subprocess.run([str(dnarod), "build-md", str(SCENES / "dna21.toml"), "-o", "md", "--ps", "50",
                        "--protocol", "paper", "--seed", "1"], cwd=d, capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr[-2000:]
    return d / "md"


def test_missing_or_wrong_rod_file(dnarod, md21, tmp_path):
    err = dnarod_fails(dnarod, "build-md", SCENES / "dna21.toml", "--rod", tmp_path / "none.h5", "-o", tmp_path / "x")
    assert f"{tmp_path / 'none.h5'}: no such rod run" in err and "rodsim run SCENE.toml -o none.h5" in err
    assert "errno" not in err
    err = dnarod_fails(dnarod, "rod-to-atoms", md21 / "build.json", "--coarse", "-o", tmp_path / "x.pdb")
    assert f"{md21 / 'build.json'}: cannot read as HDF5" in err and "rodsim run SCENE.toml -o ROD.h5" in err


def test_unreadable_structure_names_the_file_and_the_formats(dnarod, md21):
    for cmd in (["helical-params", md21 / "build.json"], ["coarse-grain", md21 / "build.json", "-o", md21 / "cg"]):
        err = dnarod_fails(dnarod, *cmd)
        assert f"{md21 / 'build.json'}: MDAnalysis cannot read it (ValueError: 'JSON' isn't a valid" in err
        assert "give a structure (PDB, GRO, TPR, ...)" in err
        # MDAnalysis's own list of every format it knows stays out of the message
        assert "Known FORMATs" not in err and len(err.splitlines()) == 1, err


def test_coarse_grain_of_one_structure_says_to_give_the_trajectory(dnarod, md21):
    err = dnarod_fails(dnarod, "coarse-grain", md21 / "conf.gro", "-o", md21 / "cg", "--temperature", "300")
    assert f"{md21 / 'conf.gro'}: 1 frames after discarding 0" in err
    assert "give the trajectory after the structure (e.g. md.tpr md.xtc)" in err
    assert "UserWarning" not in err


def test_run_md_negative_length(dnarod, md21):
    err = dnarod_fails(dnarod, "run-md", md21, "--ps", "-1")
    assert "--ps -1: the MD length must be > 0 ps" in err


def _children(pid: int) -> list[int]:
    out = []
    for task in Path(f"/proc/{pid}/task").iterdir():
        text = (task / "children").read_text().split()
        out += [int(c) for c in text]
    return out


def test_mdrun_stopped_by_a_signal_is_not_a_blow_up(dnarod, md21):
    """mdrun alone gets SIGTERM (as from a batch system): GROMACS stops cleanly at a
    checkpoint. The message says it was stopped from outside and how to continue, and
    blames neither the structure nor the time step."""
    p = subprocess.Popen([str(dnarod), "run-md", str(md21), "--threads", "1", "--output-ps", "0.2",
                          "--checkpoint-minutes", "0.01", "--no-checks"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        log = md21 / "md.part.log"
        end = time.time() + 300
        while time.time() < end and p.poll() is None:
            if log.is_file() and "Writing checkpoint, step" in log.read_text(errors="replace"):
                break
            time.sleep(0.2)
        assert p.poll() is None, "the 50-ps run ended before its first checkpoint"
        mdrun = [c for c in _children(p.pid)
                 if "mdrun" in Path(f"/proc/{c}/cmdline").read_bytes().decode(errors="replace")]
        assert len(mdrun) == 1
        os.kill(mdrun[0], signal.SIGTERM)
        _, err = p.communicate(timeout=300)
    finally:
        if p.poll() is None:
            p.kill()
    assert p.returncode == 2, err[-2000:]
    err = err[err.index("dnarod run-md: error:"):]
    assert "mdrun received the TERM signal and stopped" in err
    assert "stopped from outside" in err and "Rerun the same command to continue" in err
    step = re.search(r"Its last checkpoint is at step (\d+)", err)
    assert step and int(step.group(1)) > 0 and (md21 / "md.part.cpt").is_file()
    assert "blew up" not in err and "--minimize" not in err
    assert not (md21 / "md.done").exists()
