"""The installed toolkit is this checkout.

One install serves the whole machine (scripts/install.sh: pip's editable
install of mdbridge, dna_models, dnarod; CMake's install of the compiled
rodcore and rodsim), and other checkouts can install over it. scripts/test.sh
installs the checkout it tests; these tests fail if what a fresh shell, with
none of our environment variables, imports or runs is anything else: another
checkout's packages, a stale compiled module, or the source folder rodcore/
imported as an empty namespace package."""
import json
import os
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
BUILD = Path(os.environ.get("DNAROD_BUILD", ROOT / "build"))
CLEAN_PATH = "/usr/local/bin:/usr/bin:/bin"  # a login shell's PATH on Debian, nothing of ours

PROBE = """
import json, dna_models, dnarod, mdbridge, rodcore
from mdbridge.analysis import WaveAnalysis
print(json.dumps({m.__name__: m.__file__ for m in (dna_models, dnarod, mdbridge, rodcore)}))
"""


def clean_env(home: Path) -> dict:
    return {"PATH": CLEAN_PATH, "HOME": str(home), "LANG": "C.UTF-8"}


def built_module() -> Path:
    found = sorted((BUILD / "python").glob("rodcore*.so"))
    if len(found) != 1:
        pytest.fail(f"expected one compiled rodcore in {BUILD / 'python'}, found {found}: "
                    "run scripts/build.sh (with the same DNAROD_BUILD)")
    return found[0]


def origin_problems(files: dict) -> list[str]:
    """What is wrong with the modules a fresh interpreter imported ({name: __file__})."""
    problems = []
    for name, folder in (("mdbridge", "mdbridge"), ("dna_models", "dna_models"), ("dnarod", "workflows")):
        want = ROOT / folder / "__init__.py"
        if files.get(name) is None or Path(files[name]) != want:
            problems.append(f"{name} imports from {files.get(name)}, not {want}")
    so = files.get("rodcore")
    if so is None:
        problems.append("rodcore imports as the source folder rodcore/ (a namespace package), "
                        "not as the compiled module")
    elif Path(so).read_bytes() != built_module().read_bytes():
        problems.append(f"rodcore imports from {so}, which is not the module built in {BUILD}")
    return problems


def probe(cwd: Path, extra_env: dict | None = None) -> dict:
    p = subprocess.run(["/usr/bin/python3", "-c", PROBE], cwd=cwd, capture_output=True, text=True,
                       env={**clean_env(cwd), **(extra_env or {})}, timeout=120)
    assert p.returncode == 0, f"importing the toolkit in a clean shell failed:\n{p.stderr[-3000:]}"
    return json.loads(p.stdout.strip().splitlines()[-1])


def test_build_is_of_this_checkout():
    cache = (BUILD / "CMakeCache.txt").read_text()
    assert f"CMAKE_HOME_DIRECTORY:INTERNAL={ROOT}\n" in cache, f"{BUILD} was configured from another source tree"


def test_fresh_shell_imports_this_checkout(tmp_path):
    problems = origin_problems(probe(tmp_path))
    assert not problems, ("the installed toolkit is not this checkout; run scripts/install.sh:\n  "
                          + "\n  ".join(problems))


def test_this_session_imports_this_checkout():
    """The tests themselves run on the installed toolkit of this checkout."""
    import dna_models
    import dnarod
    import mdbridge
    import rodcore
    files = {m.__name__: m.__file__ for m in (dna_models, dnarod, mdbridge, rodcore)}
    assert not origin_problems(files)


def test_a_shadowing_package_is_caught(tmp_path):
    """Control: a stale copy of mdbridge ahead on the path is reported."""
    stale = tmp_path / "stale" / "mdbridge"
    (stale / "analysis").mkdir(parents=True)
    (stale / "__init__.py").write_text("")
    (stale / "analysis" / "__init__.py").write_text("WaveAnalysis = None\n")
    problems = origin_problems(probe(tmp_path, {"PYTHONPATH": str(tmp_path / "stale")}))
    assert len(problems) == 1 and problems[0].startswith(f"mdbridge imports from {stale}")


@pytest.mark.parametrize("tool", ["dnarod", "rodsim"])
def test_commands_run_from_path(tool, tmp_path):
    p = subprocess.run([tool, "--help"], cwd=tmp_path, env=clean_env(tmp_path), capture_output=True,
                       text=True, timeout=120)
    assert p.returncode == 0, p.stderr[-2000:]
    assert tool in p.stdout.splitlines()[0] or tool in p.stdout[:500]


def test_rodsim_on_path_is_this_build(tmp_path):
    installed = subprocess.run(["sh", "-c", "command -v rodsim"], env=clean_env(tmp_path),
                               capture_output=True, text=True).stdout.strip()
    assert installed, "rodsim is not on PATH: run scripts/install.sh"
    assert Path(installed).read_bytes() == (BUILD / "bin" / "rodsim").read_bytes(), \
        f"{installed} is not the rodsim built in {BUILD}: run scripts/install.sh"
