"""pytest setup: Debian's Python, the source tree and build/python on sys.path,
and the location of third-party reference data (../shared/refdata or
$DNAROD_REFDATA)."""
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
BUILD = Path(os.environ.get("DNAROD_BUILD", ROOT / "build"))
for p in (str(ROOT), str(BUILD / "python")):
    if p not in sys.path:
        sys.path.insert(0, p)
os.environ.setdefault("MPLBACKEND", "Agg")


def refdata_dir() -> Path | None:
    env = os.environ.get("DNAROD_REFDATA")
    for cand in ([Path(env)] if env else []) + [ROOT.parent / "shared" / "refdata"]:
        if cand.is_dir():
            return cand
    return None


@pytest.fixture(scope="session")
def refdata() -> Path:
    d = refdata_dir()
    if d is None:
        pytest.skip("third-party reference data not found: set DNAROD_REFDATA or "
                    "place it at ../shared/refdata (see README, 'Reference data')")
    return d


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


# The tiny comparison (workflows/config/tiny.yaml) run once locally; the local tiny
# test and the SLURM test (same results expected) both read it.
@pytest.fixture(scope="session")
def tiny_run(tmp_path_factory, bin_dir):
    if not (bin_dir / "rodsim").is_file():
        pytest.fail(f"{bin_dir / 'rodsim'} not built (scripts/build.sh)")
    if not list(bin_dir.parent.glob("python/rodcore*.so")):
        pytest.fail("rodcore Python module not built (scripts/build.sh)")
    if shutil.which(os.environ.get("DNAROD_GMX", "gmx")) is None:
        pytest.fail("gmx (GROMACS) not found: scripts/setup.sh installs it")
    out = tmp_path_factory.mktemp("compare_tiny")
    env = dict(os.environ, DNAROD_BIN_DIR=str(bin_dir),
               PYTHONPATH=os.pathsep.join([str(ROOT), str(bin_dir.parent / "python")]))
    cmd = [sys.executable, "-m", "workflows.cli", "compare", "--config",
           str(ROOT / "workflows" / "config" / "tiny.yaml"), "--out", str(out), "--cores", "2"]
    p = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=900)
    assert p.returncode == 0, p.stdout[-3000:] + p.stderr[-3000:]
    return out, cmd, env
