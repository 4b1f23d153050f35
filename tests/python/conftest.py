"""pytest setup: Debian's Python, the source tree and build/python on sys.path,
and the location of third-party reference data (../shared/refdata or
$DNAROD_REFDATA)."""
import os
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
