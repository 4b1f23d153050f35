"""Third-party deprecation warnings kept away from users: the one filter for every entry point.

Debian's MDAnalysis 2.4 imports the standard library's deprecated `xdrlib`, and Python 3.11
says so on every import of MDAnalysis ("'xdrlib' is deprecated and slated for removal"). A
plain `warnings.filterwarnings("ignore", ...)` set before that import does not hold: MDAnalysis
puts its own filter in front of it (`once` for every DeprecationWarning raised inside
MDAnalysis, in MDAnalysis/__init__.py), and for the same reason neither does `-W` or
PYTHONWARNINGS. What holds is importing `xdrlib` first, quietly: MDAnalysis then finds it
loaded and nothing is raised.

`workflows/__init__.py` calls `quiet_third_party_deprecations()`, so it runs before anything
else in every process that starts from the `dnarod` package: the command line (`dnarod`,
`python -m dnarod.cli`), `python -m dnarod.steps`, `python -m dnarod.steps.cgloop`,
`python -m dnarod.report.report`, and the Snakefile (its first import is from `dnarod`). The
processes the workflow starts are those same entry points, so each is quiet on its own.
"""
from __future__ import annotations

import importlib
import warnings

# Standard-library modules that a dependency imports and that Python 3.11 deprecates on import.
DEPRECATED_ON_IMPORT = ("xdrlib",)


def quiet_third_party_deprecations() -> None:
    """Import the deprecated modules a dependency needs with their warning silenced."""
    for name in DEPRECATED_ON_IMPORT:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", DeprecationWarning)
            try:
                importlib.import_module(name)
            except ImportError:   # removed from the standard library (Python >= 3.13)
                pass
