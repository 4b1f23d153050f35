"""The layer rule of docs/architecture.md, read from the code's own imports (Python's `ast`).

Floors, from the ground up:
  0  dna_models
  1  mdbridge.geometry, mdbridge.stats, mdbridge.jsonio (and the package mdbridge itself)
  2  mdbridge.rod
  3  mdbridge.md
  4  mdbridge.analysis, mdbridge.coarsegrain
  5  dnarod (the folder workflows/)
A module may import only from its own floor or the floors below, and the modules of the
three packages must not import each other in a circle. Every import counts, at the top of a
file or inside a function: a deferred import is still a dependency. Each check has a control
that plants the fault in a copy of the tree and must see it caught.
"""
from __future__ import annotations

import ast
import shutil
from pathlib import Path

import pytest

from graphs import circles as graph_circles

ROOT = Path(__file__).resolve().parents[2]
PACKAGES = {"dna_models": "dna_models", "mdbridge": "mdbridge", "dnarod": "workflows"}
FLOORS = [("dna_models", 0), ("mdbridge.geometry", 1), ("mdbridge.stats", 1),
          ("mdbridge.jsonio", 1), ("mdbridge.rod", 2), ("mdbridge.md", 3),
          ("mdbridge.analysis", 4), ("mdbridge.coarsegrain", 4), ("dnarod", 5)]


def floor(module: str) -> int:
    """The floor of a module: the longest prefix of FLOORS it falls under."""
    best = None
    for prefix, f in FLOORS:
        if module == prefix or module.startswith(prefix + "."):
            if best is None or len(prefix) > len(best[0]):
                best = (prefix, f)
    if best is None:
        if module == "mdbridge":
            return 1
        raise AssertionError(f"{module}: on no floor; add its package to FLOORS and to "
                             "docs/architecture.md, 'Layers'")
    return best[1]


def modules(root: Path) -> dict[str, Path]:
    """Every module of the three packages under ROOT: dotted name -> file."""
    out = {}
    for pkg, folder in PACKAGES.items():
        for f in sorted((root / folder).rglob("*.py")):
            rel = f.relative_to(root / folder).with_suffix("")
            parts = [pkg] + list(rel.parts)
            if parts[-1] == "__init__":
                parts = parts[:-1]
            if "profiles" in parts:     # Snakemake's SLURM profile: a script, not a module
                continue
            out[".".join(parts)] = f
    return out


def imports(name: str, path: Path, known: set[str]) -> list[tuple[str, int]]:
    """(imported module of this tree, line) for every import in the file."""
    is_pkg = path.name == "__init__.py"
    here = name.split(".") if is_pkg else name.split(".")[:-1]
    found = []
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        targets: list[str] = []
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                up = here[:len(here) - (node.level - 1)]
                base = ".".join(up + ([node.module] if node.module else []))
            # `from pkg import sub` imports the module pkg.sub when there is one
            targets = [f"{base}.{a.name}" if f"{base}.{a.name}" in known else base
                       for a in node.names]
        for t in targets:
            while t and t not in known:      # a name inside a module: the module
                t = t.rpartition(".")[0]
            if t and t != name:
                found.append((t, node.lineno))
    return found


def graph(root: Path) -> dict[str, list[tuple[str, int]]]:
    mods = modules(root)
    return {m: imports(m, p, set(mods)) for m, p in mods.items()}


def upward(root: Path) -> list[str]:
    """Each import that runs to a higher floor, as 'file:line: a (floor) -> b (floor)'."""
    mods = modules(root)
    bad = []
    for m, deps in graph(root).items():
        for d, line in deps:
            if floor(d) > floor(m):
                bad.append(f"{mods[m].relative_to(root)}:{line}: {m} (floor {floor(m)}) imports "
                           f"{d} (floor {floor(d)})")
    return bad


def circles(root: Path) -> list[list[str]]:
    """The import circles (strongly connected components of more than one module)."""
    return graph_circles({m: [d for d, _ in deps] for m, deps in graph(root).items()})


def test_no_module_imports_upward():
    assert upward(ROOT) == []


def test_no_import_circles():
    assert circles(ROOT) == []


def test_every_module_is_on_a_floor():
    for m in modules(ROOT):
        floor(m)


@pytest.fixture
def tree_copy(tmp_path):
    for folder in PACKAGES.values():
        shutil.copytree(ROOT / folder, tmp_path / folder,
                        ignore=shutil.ignore_patterns("__pycache__", "*.egg-info"))
    return tmp_path


def _plant(path: Path, line: str, inside_function: bool = False):
    text = path.read_text()
    if inside_function:
        text += f"\n\ndef _planted():\n    {line}\n"
    else:
        text += f"\n{line}\n"
    path.write_text(text)


@pytest.mark.parametrize("inside_function", [False, True])
def test_control_an_upward_import_is_caught(tree_copy, inside_function):
    # geometry (floor 1) reaching the analysis (floor 4), at the top of the file or deferred
    _plant(tree_copy / "mdbridge/geometry/pbc.py", "from mdbridge.analysis import WaveAnalysis",
           inside_function)
    bad = upward(tree_copy)
    assert len(bad) == 1 and "mdbridge.geometry.pbc (floor 1) imports mdbridge.analysis" in bad[0]


def test_control_a_relative_upward_import_is_caught(tree_copy):
    # md (floor 3) reaching the analysis (floor 4) by a relative import
    _plant(tree_copy / "mdbridge/md/gromacs/tension.py", "from ...analysis.matched import regime")
    bad = upward(tree_copy)
    assert len(bad) == 1 and "imports mdbridge.analysis.matched" in bad[0]


def test_control_a_circle_is_caught(tree_copy):
    # two modules of one floor that import each other
    _plant(tree_copy / "mdbridge/md/gromacs/gro.py", "from .box import BoxPlan")
    _plant(tree_copy / "mdbridge/md/gromacs/box.py", "from .gro import read_gro")
    assert ["mdbridge.md.gromacs.box", "mdbridge.md.gromacs.gro"] in circles(tree_copy)
