"""pytest setup. The toolkit (mdbridge, dna_models, dnarod, the compiled
rodcore) is imported from its install (scripts/install.sh, run by
scripts/test.sh); test_install.py checks that the install is this checkout.
Fixtures: the built binaries (a missing one is a failure, never a skip), the
`dnarod` command, and the third-party reference files
committed under tests/data/ (their sources and licences: tests/data/README.md)."""
import os
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
BUILD = Path(os.environ.get("DNAROD_BUILD", ROOT / "build"))
DATA = Path(__file__).resolve().parents[1] / "data"
os.environ.setdefault("MPLBACKEND", "Agg")


@pytest.fixture(scope="session")
def refdata() -> Path:
    """The third-party reference files (PDB entries, 3DNA outputs, Olson 1998
    tables), committed in tests/data/ so the comparisons run on a fresh clone."""
    if not (DATA / "README.md").is_file():
        pytest.fail(f"{DATA} is missing: the reference files are part of the repository")
    return DATA


@pytest.fixture(scope="session")
def bin_dir() -> Path:
    return BUILD / "bin"


@pytest.fixture(scope="session")
def rodsim(bin_dir) -> Path:
    """The built `rodsim`. The test command builds it first, so a missing
    binary is a failure (a skip would hide a broken build)."""
    exe = bin_dir / "rodsim"
    if not exe.is_file():
        pytest.fail(f"{exe} not built: run scripts/build.sh (with the same DNAROD_BUILD)")
    return exe


@pytest.fixture(scope="session")
def dnarod() -> Path:
    """The installed `dnarod` command on PATH (scripts/install.sh puts it
    there; test_install.py checks that it runs this checkout)."""
    exe = shutil.which("dnarod")
    if exe is None:
        pytest.fail("`dnarod` is not on PATH: run scripts/install.sh (scripts/build.sh does)")
    return Path(exe)


@pytest.fixture(scope="session")
def gmx() -> str:
    """The GROMACS `gmx` the toolkit would use ($DNAROD_GMX or PATH).
    scripts/setup.sh installs it, so its absence is a failure."""
    from dna_models.errors import ExternalToolError
    from mdbridge.md.gromacs.gmx import find_gmx
    try:
        return find_gmx()
    except ExternalToolError as e:
        pytest.fail(f"GROMACS is part of the toolkit's dependencies (scripts/setup.sh): {e}")


# The tiny comparison (workflows/config/tiny.yaml) run once locally; the local tiny
# test and the SLURM test (same results expected) both read it.
@pytest.fixture(scope="session")
def tiny_run(tmp_path_factory, rodsim, dnarod, gmx):
    out = tmp_path_factory.mktemp("compare_tiny")
    env = dict(os.environ, DNAROD_BIN_DIR=str(rodsim.parent))
    cmd = [str(dnarod), "compare", "--config",
           str(ROOT / "workflows" / "config" / "tiny.yaml"), "--out", str(out), "--cores", "2"]
    p = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=900)
    assert p.returncode == 0, p.stdout[-3000:] + p.stderr[-3000:]
    return out, cmd, env
