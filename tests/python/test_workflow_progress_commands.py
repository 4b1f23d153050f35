"""Progress displays of the commands that run long, each run for real
on tiny inputs, once under a pseudo-terminal and once in a pipe.

On a terminal each shows a live line (dnarod.progress: redrawn with a carriage return);
in a pipe a short run prints no progress line at all, so that an error stays the first
line of stderr. The truths the last drawn numbers are checked against come from
elsewhere: mdrun's own count of minimisation steps (build.json), the requested lengths,
the models in the PDB file, the frames of the rod file, Snakemake's own "M of M steps"."""
import gzip
import json
import os
import re
import subprocess
import time
from pathlib import Path

import h5py
import pytest

from terminal import in_terminal, progress_lines

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "workflows" / "scenes"
DATA = Path(__file__).resolve().parents[1] / "data"


def last(lines: list[dict], label: str) -> dict:
    mine = [p for p in lines if p["label"] == label]
    assert mine, f"no progress line labelled {label!r} in {sorted({p['label'] for p in lines})}"
    return mine[-1]


def in_pipe(cmd, **kw) -> subprocess.CompletedProcess:
    return subprocess.run([str(c) for c in cmd], capture_output=True, text=True, timeout=600, **kw)


def test_build_md_stages(dnarod, gmx, tmp_path):
    """The rod run, the minimisation and the equilibration stage of one 21-bp build."""
    args = [SCENES / "dna21.toml", "--seed", "2", "--ps", "2", "--minimize", "--equilibrate-ps", "0.2",
            "--threads", "1"]
    rc, seen = in_terminal([dnarod, "build-md", *args, "-o", tmp_path / "tty"])
    assert rc == 0, seen[-3000:]
    assert "\r" in seen
    lines = progress_lines(seen)
    rod = last(lines, "build-md: rod run")
    assert (float(rod["done"]), float(rod["total"]), rod["unit"]) == (2.0, 2.0, "ps")
    build = json.loads((tmp_path / "tty" / "build.json").read_text())
    em = last(lines, "build-md: minimisation")
    # the last step drawn is mdrun's own count ("converged ... in N steps"), of em.mdp's nsteps
    assert float(em["done"]) == build["minimization"]["steps"] > 0
    assert float(em["total"]) == 5000 and em["unit"] == "steps"
    eq = last(lines, "build-md: equilibration")
    assert float(eq["done"]) == pytest.approx(0.2) and float(eq["total"]) == pytest.approx(0.2)
    assert eq["unit"] == "ps" and "ns/day" in (eq["rate"] or "")
    # a warning (the 0.2-ps stage is too short to be stationary) starts on a line of its own
    assert re.search(r"left\r?\n.*UserWarning", seen) or "UserWarning" not in seen

    q = in_pipe([dnarod, "build-md", *args, "-o", tmp_path / "pipe"])
    assert q.returncode == 0, q.stderr[-3000:]
    assert progress_lines(q.stderr) == [] and "\r" not in q.stderr


def test_coarse_grain_frames(dnarod, tmp_path):
    d = DATA / "md_sample_3dna"
    args = [d / "sample_md0.pdb.gz", "--pairs", d / "bpfile.dat", "--temperature", "300",
            "--min-effective", "5", "--discard", "0", "--max-open-fraction", "0.05", "-m", "4", "--m-max", "4"]
    with gzip.open(d / "sample_md0.pdb.gz", "rt") as f:
        models = sum(1 for ln in f if ln.startswith("MODEL"))
    rc, seen = in_terminal([dnarod, "coarse-grain", *args, "-o", tmp_path / "tty"])
    assert rc == 0, seen[-3000:]
    lines = progress_lines(seen)
    for label in ("coarse-grain: frames read", "coarse-grain: pairs checked"):
        p = last(lines, label)
        assert float(p["done"]) == float(p["total"]) == models == 21
    params = json.loads((tmp_path / "tty" / "params.json").read_text())
    p = last(lines, "coarse-grain: lengths analysed")
    assert float(p["done"]) == float(p["total"]) == len(params["by_length"]) > 1

    q = in_pipe([dnarod, "coarse-grain", *args, "-o", tmp_path / "pipe"])
    assert q.returncode == 0, q.stderr[-3000:]
    assert progress_lines(q.stderr) == [] and "\r" not in q.stderr


@pytest.fixture(scope="module")
def rod_and_build(rodsim, dnarod, gmx, tmp_path_factory):
    """A 21-bp rod run (101 frames) and the MD build made from it (paper protocol)."""
    d = tmp_path_factory.mktemp("rod_to_atoms")
    p = in_pipe([rodsim, "run", SCENES / "dna21.toml", "-o", d / "rod.h5"])
    assert p.returncode == 0, p.stderr
    p = in_pipe([dnarod, "build-md", SCENES / "dna21.toml", "--rod", d / "rod.h5", "--ps", "2",
                 "--protocol", "paper", "--seed", "1", "-o", d / "md"])
    assert p.returncode == 0, p.stderr[-3000:]
    return d / "rod.h5", d / "md"


def test_rod_to_atoms_frames_and_relaxation(dnarod, rod_and_build, tmp_path):
    import MDAnalysis
    rod, md = rod_and_build
    with h5py.File(rod, "r") as f:
        n_rod = f["time"].shape[0]
    every = 20
    want = len(range(0, n_rod, every))
    args = [rod, "--like", md, "--every", str(every), "--relax-steps", "5"]
    rc, seen = in_terminal([dnarod, "rod-to-atoms", *args, "-o", tmp_path / "tty.xtc"])
    assert rc == 0, seen[-3000:]
    lines = progress_lines(seen)
    for stage in ("frames back-mapped", "frames relaxed", "frames written", "frames checked"):
        p = last(lines, f"rod-to-atoms: {stage}")
        assert float(p["done"]) == float(p["total"]) == want, stage
    u = MDAnalysis.Universe(str(tmp_path / "tty.gro"), str(tmp_path / "tty.xtc"))
    assert len(u.trajectory) == want

    q = in_pipe([dnarod, "rod-to-atoms", *args, "-o", tmp_path / "pipe.xtc"])
    assert q.returncode == 0, q.stderr[-3000:]
    assert progress_lines(q.stderr) == [] and "\r" not in q.stderr


ROD_ONLY = """\
scene: workflows/scenes/dna21.toml
A_v_A_per_ps: [5]
seeds: [1]
headline_A_v_A_per_ps: 5
rod: {run_ps: 20, output_every_ps: 0.2}
md: {enabled: false, run_ps: 4}
analysis: {n_boot: 20}
"""


def test_compare_jobs_done_and_running(dnarod, rodsim, tmp_path):
    """A rod-only comparison: the live line counts Snakemake's jobs and names the running
    one; a short rerun in a pipe adds no line to Snakemake's own output."""
    cfg = tmp_path / "rod_only.yaml"
    cfg.write_text(ROD_ONLY)
    env = dict(os.environ, DNAROD_BIN_DIR=str(rodsim.parent))
    out = tmp_path / "out"
    cmd = [dnarod, "compare", "--config", cfg, "--out", out, "--cores", "1"]
    rc, seen = in_terminal(cmd, env=env, cwd=ROOT)
    assert rc == 0, seen[-3000:]
    lines = progress_lines(seen)
    # Snakemake's own count: "M of M steps (100%) done"
    m = re.findall(r"(\d+) of (\d+) steps \(\d+%\) done", seen)
    assert m and m[-1][0] == m[-1][1]
    total = int(m[-1][1])
    final = last(lines, "compare")
    assert float(final["done"]) == float(final["total"]) == total and final["unit"] == "jobs"
    running = {p["label"] for p in lines if p["label"].startswith("compare [running ")}
    assert "compare [running rod_run (group=rod, av=5)]" in running, running
    assert any(lab.startswith("compare [running report") for lab in running), running
    # Snakemake's lines are passed on whole, each starting on a fresh line
    assert "\nFinished job" in seen.replace("\033[K", "\n").replace("\r", "")

    (out / "results.json").unlink()
    t0 = time.time()
    q = in_pipe(cmd, env=env, cwd=ROOT)
    wall = time.time() - t0
    assert q.returncode == 0, q.stderr[-3000:]
    assert q.stderr.startswith("Building DAG of jobs")
    assert "1 of " in q.stderr and "\r" not in q.stderr
    # quiet: the first plain line is due 60 s after the start
    assert progress_lines(q.stderr) == [] or wall >= 60.0, q.stderr
