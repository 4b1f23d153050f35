"""The compiled solver module `rodcore` (rodcore/python/module.cpp): the rod solver and the
curve topology (rodcore.topology), which every floor of mdbridge may call."""
from __future__ import annotations

from dna_models.errors import DnarodError


def rodcore_module():
    """The compiled module. The source folder rodcore/ imports as an empty namespace
    package when the module is not installed, so test for `run`, not the import."""
    try:
        import rodcore  # type: ignore
    except ImportError:
        rodcore = None
    if not hasattr(rodcore, "run"):
        raise DnarodError("the compiled rodcore Python module is not installed: run "
                          "`bash scripts/build.sh` (it builds and installs it)")
    return rodcore
