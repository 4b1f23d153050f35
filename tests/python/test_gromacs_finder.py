"""Which gmx runs (mdbridge/md/gromacs/gmx.py: find_gmx; docs/dependencies.md "GROMACS:
which `gmx` runs"): --gmx, else DNAROD_GMX, else the project's own build of
scripts/build_gromacs.sh when it exists, else `gmx` on PATH.

The real build takes ~20 min, so here the project's build is stood in for by
wrapper executables in a temporary prefix, given by DNAROD_GROMACS_PREFIX (the
variable the build script installs into). Each wrapper appends its name and
arguments to a log and then runs the real GROMACS, so `dnarod build-md` and
`dnarod run-md` really work through it and the log shows which binary did the
work. The controls: without the prefix (or with a non-executable file in it)
the same calls resolve to Debian's gmx, so a finder that ignored the project's
build fails these tests.
"""
import json
import os
import shlex
import shutil
import subprocess
from pathlib import Path

import pytest
import yaml

from mdbridge.md.gromacs.gmx import built_gmx, built_gmx_prefix, find_gmx

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "scripts" / "build_gromacs.sh"


def real_gmx(name: str) -> str:
    """The real binary a wrapper hands over to (Debian's, or the project's build if
    the checkout has one): resolved before the test points the finder elsewhere."""
    return find_gmx(name)


@pytest.fixture
def prefix(tmp_path, monkeypatch, gmx):
    """A stand-in project build: PREFIX/bin/gmx and gmx_d, logging wrappers."""
    targets = {"gmx": real_gmx("gmx"), "gmx_d": real_gmx("gmx_d")}
    p = tmp_path / "prefix"
    (p / "bin").mkdir(parents=True)
    log = tmp_path / "wrapper.log"
    for name, target in targets.items():
        w = p / "bin" / name
        w.write_text(f'#!/bin/sh\necho "{name} $1" >> {shlex.quote(str(log))}\n'
                     f'exec {shlex.quote(target)} "$@"\n')
        w.chmod(0o755)
    monkeypatch.delenv("DNAROD_GMX", raising=False)
    monkeypatch.setenv("DNAROD_GROMACS_PREFIX", str(p))
    return p, log, targets


def test_the_finder_looks_where_the_build_script_installs(tmp_path):
    """The script's --print-prefix and the finder agree, by default (the checkout's
    .local/gromacs: the installed package must be this checkout) and when
    DNAROD_GROMACS_PREFIX is set."""
    env = {k: v for k, v in os.environ.items() if k != "DNAROD_GROMACS_PREFIX"}
    out = subprocess.run(["bash", str(SCRIPT), "--print-prefix"], env=env, capture_output=True,
                         text=True, check=True).stdout.strip()
    assert out == str(ROOT / ".local" / "gromacs")
    old = os.environ.pop("DNAROD_GROMACS_PREFIX", None)
    try:
        assert built_gmx_prefix() == Path(out)
    finally:
        if old is not None:
            os.environ["DNAROD_GROMACS_PREFIX"] = old
    env["DNAROD_GROMACS_PREFIX"] = str(tmp_path / "elsewhere")
    out = subprocess.run(["bash", str(SCRIPT), "--print-prefix"], env=env, capture_output=True,
                         text=True, check=True).stdout.strip()
    assert out == str(tmp_path / "elsewhere")


def test_project_build_first_and_overrides(prefix, monkeypatch, tmp_path):
    p, _, targets = prefix
    assert find_gmx() == str(p / "bin" / "gmx") == built_gmx()
    assert built_gmx(double=True) == str(p / "bin" / "gmx_d")
    # a bare name (paper.yaml's `--gmx gmx_d`) is a command looked up in the build first
    assert find_gmx("gmx_d") == str(p / "bin" / "gmx_d")
    monkeypatch.setenv("DNAROD_GMX", "gmx_d")
    assert find_gmx() == str(p / "bin" / "gmx_d")
    # a path overrides the project's build: DNAROD_GMX, and --gmx over DNAROD_GMX
    monkeypatch.setenv("DNAROD_GMX", targets["gmx"])
    assert find_gmx() == targets["gmx"]
    assert find_gmx(targets["gmx_d"]) == targets["gmx_d"]
    monkeypatch.delenv("DNAROD_GMX")
    # controls: no project build, or a file there that is not executable -> PATH
    (p / "bin" / "gmx").chmod(0o644)
    assert find_gmx() == shutil.which("gmx") != str(p / "bin" / "gmx")
    monkeypatch.setenv("DNAROD_GROMACS_PREFIX", str(tmp_path / "empty"))
    assert find_gmx() == shutil.which("gmx")
    assert find_gmx("gmx_d") == shutil.which("gmx_d") != str(p / "bin" / "gmx_d")
    assert built_gmx() is None


def test_build_md_and_run_md_run_the_project_build(prefix, dnarod, tmp_path):
    """The commands, as a user (and the workflow's rules) call them: no --gmx."""
    p, log, _ = prefix
    scene = ROOT / "workflows" / "scenes" / "dna21.toml"
    out = tmp_path / "md21"
    for cmd in (["build-md", str(scene), "-o", str(out), "--ps", "0.1", "--temperature", "0",
                 "--seed", "3"],
                ["run-md", str(out), "--steps", "50", "--threads", "1", "--output-ps", "0.05",
                 "--no-checks"]):
        r = subprocess.run([str(dnarod), *cmd], capture_output=True, text=True, timeout=600)
        assert r.returncode == 0, r.stderr[-3000:]
    tools = log.read_text().split("\n")
    assert {"gmx pdb2gmx", "gmx grompp", "gmx mdrun"} <= set(tools), tools
    assert json.loads((out / "build.json").read_text())["gmx"]["path"] == str(p / "bin" / "gmx")
    assert json.loads((out / "md.done").read_text())["gmx"]["path"] == str(p / "bin" / "gmx")


def test_the_workflow_passes_no_path_that_bypasses_the_project_build(prefix):
    """The workflow's MD rules run `dnarod build-md` / `run-md` with the shipped
    configuration's build_args / run_args and nothing else about gmx: every --gmx
    they give must resolve to the project's build when it exists."""
    p, _, _ = prefix
    snakefile = (ROOT / "workflows" / "Snakefile").read_text()
    assert "--gmx" not in snakefile and "DNAROD_GMX" not in snakefile
    given = {}
    for cfg in sorted((ROOT / "workflows" / "config").glob("*.yaml")):
        md = (yaml.safe_load(cfg.read_text()) or {}).get("md") or {}
        for key in ("build_args", "run_args"):
            words = shlex.split(md.get(key) or "")
            for i, w in enumerate(words):
                if w == "--gmx" or w.startswith("--gmx="):
                    name = w.split("=", 1)[1] if "=" in w else words[i + 1]
                    given[f"{cfg.name}: md.{key}"] = name
                    assert Path(find_gmx(name)).parent == p / "bin", (cfg.name, key, name)
    assert given.get("paper.yaml: md.run_args") == "gmx_d"   # the one shipped --gmx, checked above


@pytest.mark.parametrize("cpu_has_rdtscp", [True, False])
@pytest.mark.parametrize("built_with_rdtscp", [True, False])
def test_a_build_that_uses_rdtscp_is_rebuilt_where_the_cpu_lacks_it(tmp_path, cpu_has_rdtscp, built_with_rdtscp):
    """scripts/build_gromacs.sh --check: a kept gmx of the right version is rebuilt only
    when it uses rdtscp and the CPU does not list it (mdrun would refuse to start:
    docs/dependencies.md, "GROMACS built for the machine"). The stand-in gmx prints what a real one's --version does."""
    bin_dir = tmp_path / "prefix" / "bin"
    bin_dir.mkdir(parents=True)
    gmx = bin_dir / "gmx"
    gmx.write_text("#!/bin/sh\necho 'GROMACS version:    2022.5-Debian_2022.5_2_dnarod'\n"
                   "echo 'SIMD instructions:  AVX2_256'\n"
                   f"echo 'RDTSCP usage:       {'enabled' if built_with_rdtscp else 'disabled'}'\n")
    gmx.chmod(0o755)
    cpuinfo = tmp_path / "cpuinfo"
    cpuinfo.write_text("flags\t\t: fpu sse4_1 avx2" + (" rdtscp" if cpu_has_rdtscp else "") + " lm\n")
    env = dict(os.environ, DNAROD_GROMACS_PREFIX=str(tmp_path / "prefix"), DNAROD_CPUINFO=str(cpuinfo))
    r = subprocess.run(["bash", str(SCRIPT), "--check"], env=env, capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    rebuilt = built_with_rdtscp and not cpu_has_rdtscp
    assert ("would be built" in r.stdout) == rebuilt, r.stdout + r.stderr
    assert ("already built; kept" in r.stdout) == (not rebuilt), r.stdout
    if rebuilt:
        assert "uses rdtscp, which this CPU lacks" in r.stdout


def stand_in_gmx(bin_dir: Path, built_with_rdtscp: bool) -> None:
    """A gmx whose --version says what a real one's does about rdtscp."""
    bin_dir.mkdir(parents=True, exist_ok=True)
    gmx = bin_dir / "gmx"
    gmx.write_text("#!/bin/sh\necho 'GROMACS version:    2022.5-Debian_2022.5_2'\n"
                   f"echo 'RDTSCP usage:       {'enabled' if built_with_rdtscp else 'disabled'}'\n")
    gmx.chmod(0o755)


@pytest.mark.parametrize("cpu_has_rdtscp", [True, False])
@pytest.mark.parametrize("built_with_rdtscp", [True, False])
def test_if_needed_builds_only_where_the_systems_gmx_cannot_run(tmp_path, cpu_has_rdtscp, built_with_rdtscp):
    """scripts/build_gromacs.sh --if-needed (what scripts/setup.sh runs): a build only when
    the gmx on PATH uses rdtscp and the CPU lacks it; with no project build yet, --check
    then says it would build."""
    stand_in_gmx(tmp_path / "system", built_with_rdtscp)
    cpuinfo = tmp_path / "cpuinfo"
    cpuinfo.write_text("flags\t\t: fpu sse4_1 avx2" + (" rdtscp" if cpu_has_rdtscp else "") + " lm\n")
    env = dict(os.environ, DNAROD_GROMACS_PREFIX=str(tmp_path / "prefix"), DNAROD_CPUINFO=str(cpuinfo),
               PATH=f"{tmp_path / 'system'}:{os.environ['PATH']}")
    r = subprocess.run(["bash", str(SCRIPT), "--if-needed", "--check"], env=env, capture_output=True,
                       text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    needed = built_with_rdtscp and not cpu_has_rdtscp
    assert ("no build needed" in r.stdout) == (not needed), r.stdout
    assert ("gmx would be built" in r.stdout) == needed, r.stdout
    if needed:
        assert f"{tmp_path / 'system' / 'gmx'} uses rdtscp, which this CPU lacks" in r.stdout


ARGON_TOP = """[ defaults ]
1 1 no 1.0 1.0
[ atomtypes ]
AR 39.948 0.0 A 6.2e-3 9.7e-6
[ moleculetype ]
AR 1
[ atoms ]
1 AR 1 AR AR 1 0.0 39.948
[ system ]
two argon atoms
[ molecules ]
AR 2
"""
ARGON_GRO = "two argon atoms\n2\n    1AR      AR    1   1.000   1.000   1.000\n" \
            "    2AR      AR    2   1.400   1.000   1.000\n   3.00000   3.00000   3.00000\n"
ARGON_MDP = "integrator = md\nnsteps = 10\ndt = 0.002\ncutoff-scheme = Verlet\nrvdw = 1.0\n" \
            "rcoulomb = 1.0\ncoulombtype = reaction-field\n"


def test_if_needed_agrees_with_whether_debians_mdrun_starts_on_this_cpu(tmp_path):
    """The real case: Debian's gmx (the one on PATH) runs 10 steps of two argon atoms on
    this machine's CPU or refuses to, and --if-needed's decision must be the same (on a
    CPU with rdtscp: no build; without: a build). Either outcome checks the rule."""
    system_gmx = shutil.which("gmx", path=os.environ["PATH"])
    assert system_gmx, "Debian's gmx is part of the toolkit's dependencies (scripts/setup.sh)"
    for name, text in (("topol.top", ARGON_TOP), ("conf.gro", ARGON_GRO), ("md.mdp", ARGON_MDP)):
        (tmp_path / name).write_text(text)
    g = subprocess.run([system_gmx, "grompp", "-f", "md.mdp", "-c", "conf.gro", "-p", "topol.top",
                        "-o", "md.tpr"], cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert g.returncode == 0, g.stderr[-2000:]
    md = subprocess.run([system_gmx, "mdrun", "-s", "md.tpr", "-nt", "1"], cwd=tmp_path,
                        capture_output=True, text=True, timeout=120)
    starts = md.returncode == 0
    if not starts:
        assert "rdtscp" in md.stdout + md.stderr, (md.stdout + md.stderr)[-2000:]
    env = dict(os.environ, DNAROD_GROMACS_PREFIX=str(tmp_path / "prefix"))
    r = subprocess.run(["bash", str(SCRIPT), "--if-needed", "--check"], env=env, capture_output=True,
                       text=True, timeout=60)
    assert r.returncode == 0, r.stderr
    assert ("no build needed" in r.stdout) == starts, (starts, r.stdout)
    assert ("gmx would be built" in r.stdout) == (not starts), (starts, r.stdout)
