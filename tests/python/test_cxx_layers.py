"""rodcore's include rule (docs/architecture.md, "rodcore inside"), read from the code's own
`#include "..."` lines: layers never include upward.

A unit is a source file with the headers of its name (rhs.cpp with rodcore/rhs.hpp); a header
with no source of its name is a unit of its own. Two rules:
  - no circle of units. A unit that includes a header of a unit above it, while that one
    includes (directly or through others) a header of the first, is an arrow that runs back
    up: every layering of the units has one where there is a circle, and none where there is
    none;
  - the folders are floors: the solver core (src/*.cpp; headers without a source) 0, the scene
    layer (src/scene/) 1, rodsim (cli/) and the Python module (python/) 2. A unit's floor is
    that of its source, and a unit includes only from its own floor or below.
Generated headers (rodcore/dna_units.hpp, rodcore/version.hpp) and system headers are not in
the tree and are not units. Each rule has a control that plants an include in a copy of
rodcore and must see it caught; a third runs the rules on rodcore as it was before its
System was built, whose four back-arrows (planted again) they must find.
"""
from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest

from graphs import circles as graph_circles

ROOT = Path(__file__).resolve().parents[2]
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)
SOURCE_FLOORS = {"src": 0, "src/scene": 1, "cli": 2, "python": 2}
HEADER_DIRS = ("include", "src", "cli")        # where `#include "x"` is looked up, after the file's own folder
SUFFIXES = (".cpp", ".hpp", ".inc")


def files(rodcore: Path) -> list[Path]:
    return sorted(p for p in rodcore.rglob("*") if p.suffix in SUFFIXES and p.is_file())


def unit_of(path: Path) -> str:
    return path.name.split(".")[0]


def floors(rodcore: Path) -> dict[str, int]:
    """The floor of every unit that has a source (a header-only unit is on the ground floor)."""
    out: dict[str, int] = {}
    for p in files(rodcore):
        folder = str(p.parent.relative_to(rodcore))
        if p.suffix == ".cpp" and folder in SOURCE_FLOORS:
            assert unit_of(p) not in out, f"two sources named {unit_of(p)}: units must have one"
            out[unit_of(p)] = SOURCE_FLOORS[folder]
    return out


def resolve(rodcore: Path, including: Path, name: str) -> Path | None:
    for base in (including.parent, *(rodcore / d for d in HEADER_DIRS)):
        if (base / name).is_file():
            return base / name
    return None


def arrows(rodcore: Path) -> list[tuple[str, str, str]]:
    """(unit, included unit, 'file:line') for every include of a file of the tree by another unit."""
    out = []
    for p in files(rodcore):
        text = p.read_text()
        for m in INCLUDE.finditer(text):
            target = resolve(rodcore, p, m.group(1))
            if target is None or unit_of(target) == unit_of(p):
                continue
            line = text.count("\n", 0, m.start()) + 1
            out.append((unit_of(p), unit_of(target), f"{p.relative_to(rodcore.parent)}:{line}"))
    return out


def upward(rodcore: Path) -> list[str]:
    """Each include of a unit on a higher floor, as 'file:line: a (floor) -> b (floor)'."""
    fl = floors(rodcore)
    return [f"{where}: {a} (floor {fl.get(a, 0)}) includes {b} (floor {fl.get(b, 0)})"
            for a, b, where in arrows(rodcore) if fl.get(b, 0) > fl.get(a, 0)]


def circles(rodcore: Path) -> list[list[str]]:
    """The circles of units (strongly connected components of more than one unit)."""
    g: dict[str, set[str]] = {}
    for a, b, _ in arrows(rodcore):
        g.setdefault(a, set()).add(b)
    return graph_circles(g)


def test_no_unit_includes_a_higher_floor():
    assert upward(ROOT / "rodcore") == []


def test_no_circle_of_units():
    assert circles(ROOT / "rodcore") == []


@pytest.fixture
def rodcore_copy(tmp_path):
    shutil.copytree(ROOT / "rodcore", tmp_path / "rodcore")
    return tmp_path / "rodcore"


def _plant(path: Path, include: str):
    path.write_text(f'#include "{include}"\n' + path.read_text())


def test_control_a_back_arrow_is_caught(rodcore_copy):
    # the Gaussian numbers (ground) reaching the run loop, which reaches them through the thermal rod
    _plant(rodcore_copy / "src/gaussian.cpp", "rodcore/simulation.hpp")
    found = circles(rodcore_copy)
    assert len(found) == 1 and {"gaussian", "simulation", "thermal"} <= set(found[0])


def test_control_an_include_of_the_scene_layer_is_caught(rodcore_copy):
    # the core's closed-form results reaching the scene layer's solvent table: no circle, a floor up
    _plant(rodcore_copy / "src/analytic.cpp", "rodcore/solvent.hpp")
    assert circles(rodcore_copy) == []
    bad = upward(rodcore_copy)
    assert len(bad) == 1 and "analytic (floor 0) includes solvent (floor 1)" in bad[0]


def test_control_the_four_old_back_arrows_are_caught(rodcore_copy):
    # rodcore before its System had four: observer.cpp -> simulation.hpp; diagnostics.hpp ->
    # material.hpp while material.cpp included guards.hpp (for the message format); and
    # integrators.hpp and simulation.hpp -> checkpoint.hpp (the scene layer's)
    _plant(rodcore_copy / "src/observer.cpp", "rodcore/simulation.hpp")
    _plant(rodcore_copy / "src/material.cpp", "rodcore/guards.hpp")
    _plant(rodcore_copy / "src/rodcore/integrators.hpp", "rodcore/checkpoint.hpp")
    _plant(rodcore_copy / "include/rodcore/simulation.hpp", "rodcore/checkpoint.hpp")
    in_circles = {u for c in circles(rodcore_copy) for u in c}
    assert {"observer", "simulation", "material", "guards", "diagnostics", "integrators"} <= in_circles
    assert sorted(b.split(": ")[1] for b in upward(rodcore_copy)) == [
        "integrators (floor 0) includes checkpoint (floor 1)",
        "simulation (floor 0) includes checkpoint (floor 1)"]
