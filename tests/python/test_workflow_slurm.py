"""`dnarod compare` through the shipped SLURM profile (workflows/profiles/slurm) on a
real SLURM cluster: Debian's slurm-wlm and munge, brought up on this machine for the
test (slurmctld + slurmd, one node with the machine's cores, proctrack/linuxproc so
it also runs in a container) and stopped at the end.

Checks the same things as the local tiny run (tests/python/test_workflow_tiny.py):
the same results.json keys and the same rod numbers (the rod part is deterministic;
the MD part is not bitwise reproducible across runs, so only its presence is checked).
"""
import json
import os
import re
import shutil
import socket
import subprocess
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PROFILE = ROOT / "workflows" / "profiles" / "slurm"


def _need(exe: str) -> str:
    path = shutil.which(exe) or (f"/usr/sbin/{exe}" if Path(f"/usr/sbin/{exe}").is_file() else None)
    if path is None:
        pytest.fail(f"{exe} not found: scripts/setup.sh installs slurm-wlm and munge")
    return path


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _cpus() -> int:
    return os.cpu_count() or 1


@pytest.fixture(scope="module")
def slurm_cluster(tmp_path_factory):
    """A one-node SLURM cluster on localhost; yields the environment that points the
    SLURM clients (sbatch, scontrol) at it."""
    if os.geteuid() != 0:
        pytest.skip("a local SLURM cluster needs root (slurmd runs jobs as their user); "
                    "run the test command as root, as CI does")
    munged, mungekey = _need("munged"), _need("mungekey")
    slurmctld, slurmd = _need("slurmctld"), _need("slurmd")
    d = tmp_path_factory.mktemp("slurm")
    for sub in ("state", "spool", "log", "munge"):
        (d / sub).mkdir()
    host = socket.gethostname().split(".")[0]
    key, sock = d / "munge" / "munge.key", d / "munge" / "munge.socket"
    subprocess.run([mungekey, "--create", "--force", "--keyfile", str(key)], check=True)
    conf = d / "slurm.conf"
    conf.write_text(f"""\
ClusterName=dnarodtest
SlurmctldHost={host}
SlurmctldPort={_free_port()}
SlurmdPort={_free_port()}
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket={sock}
CryptoType=crypto/munge
MpiDefault=none
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
MinJobAge=600
KillWait=5
StateSaveLocation={d / 'state'}
SlurmdSpoolDir={d / 'spool'}
SlurmctldPidFile={d / 'slurmctld.pid'}
SlurmdPidFile={d / 'slurmd.pid'}
SlurmctldLogFile={d / 'log' / 'slurmctld.log'}
SlurmdLogFile={d / 'log' / 'slurmd.log'}
NodeName={host} CPUs={_cpus()} RealMemory=4000 State=UNKNOWN
PartitionName=debug Nodes={host} Default=YES MaxTime=INFINITE State=UP
""")
    env = dict(os.environ, SLURM_CONF=str(conf))
    started = []
    try:
        subprocess.run([munged, f"--key-file={key}", f"--socket={sock}", f"--pid-file={d / 'munge' / 'pid'}",
                        f"--log-file={d / 'munge' / 'log'}", f"--seed-file={d / 'munge' / 'seed'}", "--force"],
                       check=True, env=env)
        started.append(d / "munge" / "pid")
        subprocess.run([slurmctld, "-f", str(conf)], check=True, env=env)
        started.append(d / "slurmctld.pid")
        subprocess.run([slurmd, "-f", str(conf)], check=True, env=env)
        started.append(d / "slurmd.pid")
        deadline = time.time() + 60
        while True:
            p = subprocess.run(["sinfo", "-h", "-o", "%T"], capture_output=True, text=True, env=env)
            if p.returncode == 0 and p.stdout.strip() == "idle":
                break
            if time.time() > deadline:
                logs = "".join(f.read_text()[-2000:] for f in (d / "log").glob("*.log"))
                pytest.fail(f"local SLURM did not come up within 60 s (sinfo: {p.stdout!r} {p.stderr!r})\n{logs}")
            time.sleep(0.5)
        yield env
    finally:
        subprocess.run(["scancel", "--user", "root"], env=env, capture_output=True)
        for pid_file in reversed(started):
            try:
                os.kill(int(pid_file.read_text().split()[0]), 15)
            except (OSError, ValueError):
                pass
        time.sleep(1)


def _compare(out: Path, env: dict, dnarod: Path, *extra: str, timeout: int = 1200) -> subprocess.CompletedProcess:
    cmd = [str(dnarod), "compare", "--config", str(ROOT / "workflows" / "config" / "tiny.yaml"),
           "--out", str(out), "--cores", str(_cpus()), "--", "--profile", str(PROFILE), *extra]
    return subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=timeout)


def test_profile_is_a_valid_snakemake_profile():
    import yaml
    cfg = yaml.safe_load((PROFILE / "config.yaml").read_text())
    assert cfg["cluster"].startswith("mkdir -p slurm && sbatch --parsable")
    assert os.access(PROFILE / cfg["cluster-status"], os.X_OK)


def test_status_script_maps_slurm_states(slurm_cluster):
    """The status script against real jobs: one that completes, one that fails, one
    that SLURM kills at its time limit."""
    env = slurm_cluster
    status = PROFILE / "slurm_status.py"

    def submit(*args: str) -> str:
        p = subprocess.run(["sbatch", "--parsable", "-o", "/dev/null", *args], env=env,
                           capture_output=True, text=True, check=True)
        return p.stdout.strip().split(";")[0]

    def wait_state(job: str, allowed: set[str], seconds: float = 120) -> str:
        end = time.time() + seconds
        while time.time() < end:
            s = subprocess.run([str(status), job], env=env, capture_output=True, text=True).stdout.strip()
            if s in allowed:
                return s
            time.sleep(0.5)
        return s

    ok = submit("--wrap", "true")
    bad = submit("--wrap", "exit 3")
    assert wait_state(ok, {"success", "failed"}) == "success"
    assert wait_state(bad, {"success", "failed"}) == "failed"
    long = submit("--time=1", "--wrap", "sleep 600")  # 1 minute: SLURM kills it
    assert wait_state(long, {"running"}, 30) == "running"
    assert wait_state(long, {"success", "failed"}, 180) == "failed"


def test_tiny_comparison_through_slurm(slurm_cluster, tiny_run, dnarod, tmp_path):
    local_out = tiny_run[0]
    out = tmp_path / "slurm_tiny"
    p = _compare(out, slurm_cluster, dnarod)
    assert p.returncode == 0, p.stdout[-3000:] + p.stderr[-3000:]
    jobs = list((out / "slurm").glob("*.out"))
    assert any(j.name.startswith("md_run-") for j in jobs), "the MD did not run as a SLURM job"
    assert any(j.name.startswith("rod_run-") for j in jobs)
    local = json.loads((local_out / "results.json").read_text())
    res = json.loads((out / "results.json").read_text())
    assert set(res) == set(local)
    for key in ("rod_wave_speed_A_per_ps", "rod_wave_speed_err_A_per_ps", "rod_planarity", "rod_run_ps"):
        assert res[key] == local[key], key
    # the MD ran and was analysed (its numbers differ run to run: GROMACS is not bitwise
    # reproducible across runs and loads)
    assert len(res["runs"]["md"]) == len(local["runs"]["md"]) >= 1
    assert 0.0 <= res["md_bp_intact_fraction"] <= 1.0


def _md_ps_per_s(md_dir: Path, dnarod: Path, tmp: Path) -> float:
    """This machine's MD speed now, 1 thread: a 1-ps run of a copy of the tiny build."""
    copy = tmp / "speed"
    copy.mkdir()
    for f in md_dir.iterdir():
        if f.suffix in (".gro", ".top", ".itp", ".mdp") or f.name == "build.json":
            shutil.copy(f, copy / f.name)
    p = subprocess.run([str(dnarod), "run-md", str(copy), "--ps", "1", "--threads", "1", "--no-checks"],
                       capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr[-2000:]
    return json.loads((copy / "md.done").read_text())["ns_per_day"] * 1000.0 / 86400.0


def test_time_limit_kills_md_and_the_rerun_resumes(slurm_cluster, tiny_run, dnarod, rodsim, tmp_path):
    """SLURM kills md_run at a 1-minute time limit; the checkpoint survives Snakemake's
    clean-up of the failed job; the rerun (default limit) continues the MD from it and
    the workflow ends with the local tiny run's results.json keys."""
    import MDAnalysis
    import numpy as np
    import yaml

    from dnarod.progress import parse_line
    from terminal import in_terminal, progress_lines

    env = dict(slurm_cluster, DNAROD_BIN_DIR=str(rodsim.parent))
    local_out = tiny_run[0]
    # the MD must outlast the limit: slurmctld checks limits every 30 s, so the job is killed
    # 60-90 s after it starts, the MD ~10 s after the job; 130 s of MD at the speed measured
    # now (>= 10 ps) outlasts that, and leaves 40-70 s for the rerun
    rate = _md_ps_per_s(local_out / "md" / "Av5_seed1", dnarod, tmp_path)
    md_ps = round(float(max(10.0, 0.2 * np.ceil(rate * 130.0 / 0.2))), 1)
    cfg = yaml.safe_load((ROOT / "workflows" / "config" / "tiny.yaml").read_text())
    # one MD job, the kicked one (without the unkicked run the coarse-graining loop is off)
    cfg["A_v_A_per_ps"] = [cfg["headline_A_v_A_per_ps"]]
    cfg["md"].pop("run_ps_per_A_v", None)
    cfg["rod"]["run_ps"] = max(cfg["rod"]["run_ps"], md_ps)       # the rod covers the MD
    cfg["md"].update(run_ps=md_ps, threads=1,
                     run_args="--threads 1 --output-ps 0.2 --checkpoint-minutes 0.2")
    config = tmp_path / "timelimit.yaml"
    config.write_text(yaml.safe_dump(cfg))
    out = tmp_path / "timelimit"
    md = out / "md" / "Av5_seed1"
    base = [str(dnarod), "compare", "--config", str(config), "--out", str(out), "--cores", str(_cpus()),
            "--", "--profile", str(PROFILE)]

    t0 = time.time()
    rc, seen = in_terminal(base + ["--set-resources", "md_run:runtime=1"], env=env, timeout=1800)
    t_first = time.time() - t0
    assert rc == 2, seen[-3000:]
    assert "Error in rule md_run" in seen
    jobs = sorted((out / "slurm").glob("md_run-*.out"))
    assert len(jobs) == 1, jobs
    job = jobs[0].stem.split("-")[-1]
    state = subprocess.run(["scontrol", "show", "job", "-o", job], env=env, capture_output=True,
                           text=True).stdout
    assert "JobState=TIMEOUT" in state and "TimeLimit=00:01:00" in state, state
    assert "DUE TO TIME LIMIT" in jobs[0].read_text()
    # the live line counted jobs and named the MD while it ran
    assert any(p["label"] == "compare [running md_run (av=5, seed=1)]" for p in progress_lines(seen))
    # Snakemake removed nothing of the unfinished MD but its declared outputs
    assert not (md / "md.done").exists() and not (md / "md.xtc").exists()
    assert (md / "md.part.cpt").is_file() and (md / "md.run.json").is_file()
    step = [int(s) for s in re.findall(r"Writing checkpoint, step (\d+)", (md / "md.part.log").read_text())]
    assert step and 0 < step[-1] < json.loads((md / "md.run.json").read_text())["steps"]

    t0 = time.time()
    p = subprocess.run(base, env=env, capture_output=True, text=True, timeout=1800)
    t_second = time.time() - t0
    assert p.returncode == 0, p.stdout[-3000:] + p.stderr[-3000:]
    done = json.loads((md / "md.done").read_text())
    assert done["resumed_from_checkpoint"] is True and done["length_ps"] == pytest.approx(md_ps)
    assert re.search(r"continuing from the checkpoint md\.part\.cpt \(step \d+", (md / "run-md.log").read_text())
    # every frame once, times continuous across the resume: 0, 0.2, ..., md_ps
    u = MDAnalysis.Universe(str(md / "md.tpr"), str(md / "md.xtc"))
    times = np.array([ts.time for ts in u.trajectory])
    n = int(round(md_ps / 0.2)) + 1
    assert len(times) == n and np.allclose(times, 0.2 * np.arange(n), atol=1e-4)
    assert len(list((out / "slurm").glob("md_run-*.out"))) == 2
    res = json.loads((out / "results.json").read_text())
    # the local tiny run's keys; its 4-ps MD gives no finite wave speed, this longer one may, and
    # then the report adds the speed's Eq-39 modulus (workflows/report/report.py); with the
    # kicked MD alone the dispersion steps (an unkicked run's modes) are off
    optional = {"bend_modulus_for_md_speed_small_amplitude", "dispersion"}
    assert set(res) - optional == set(json.loads((local_out / "results.json").read_text())) - optional
    assert res["md_run_ps"] == pytest.approx(md_ps)
    # no plain progress line of the workflow is lost in the pipe: each parses
    assert all(parse_line(ln) for ln in p.stderr.splitlines() if ": progress " in ln)
    print(f"time-limit test: MD {md_ps:g} ps at {rate * 86400 / 1000:.3g} ns/day (1 thread); killed run "
          f"{t_first:.0f} s, resumed run {t_second:.0f} s")
