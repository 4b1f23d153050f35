"""No third-party deprecation warning reaches a user: every entry point starts from the
`dnarod` package, whose import runs workflows/quiet.py before MDAnalysis is imported."""
import subprocess
import sys

import pytest

XDRLIB = "'xdrlib' is deprecated"


def stderr_of(code: str) -> str:
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=120, check=True).stderr


def test_control_mdanalysis_alone_warns():
    """The control: MDAnalysis imported on its own does print the warning (otherwise the
    test below could not fail), also with a plain filter set before the import."""
    if sys.version_info >= (3, 13):
        pytest.fail("xdrlib is gone from Python 3.13: workflows/quiet.py and this test can go")
    assert XDRLIB in stderr_of("import MDAnalysis")
    assert XDRLIB in stderr_of("import warnings; warnings.filterwarnings('ignore', message=\"'xdrlib'\", "
                               "category=DeprecationWarning); import MDAnalysis")


@pytest.mark.parametrize("entry", ["dnarod.cli", "dnarod.steps.analyse", "dnarod.steps.cgloop",
                                   "dnarod.report.report", "dnarod.configuration"])
def test_entry_points_quiet(entry):
    """Each module a process starts from (the command line, the workflow's steps and report;
    the Snakefile's first import is dnarod.configuration), then MDAnalysis and mdbridge."""
    err = stderr_of(f"import {entry}; import MDAnalysis; import mdbridge.md.gromacs.checks")
    assert "DeprecationWarning" not in err, err
