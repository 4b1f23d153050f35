"""The bench/ scripts as modules for the tests that check them (the
benchmarks are scripts of the repository, not part of the installed toolkit,
so they are loaded by path; pytest puts this folder on sys.path)."""
import importlib.util
import sys
from pathlib import Path

BENCH = Path(__file__).resolve().parents[2] / "bench"


def load_bench(relpath: str):
    """bench/RELPATH (e.g. "stress/stability.py") as a module, loaded once."""
    name = "bench_" + relpath.removesuffix(".py").replace("/", "_")
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(name, BENCH / relpath)
        assert spec is not None and spec.loader is not None, BENCH / relpath
        mod = importlib.util.module_from_spec(spec)
        sys.modules[name] = mod
        spec.loader.exec_module(mod)
    return sys.modules[name]
