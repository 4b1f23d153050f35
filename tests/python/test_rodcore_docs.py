"""docs/scenes.md cannot go stale: it must document every scene key the reader
resolves, every initial kind of the registry with every parameter, and every
example scene."""
import re
import tomllib
from pathlib import Path


import rodcore

ROOT = Path(__file__).resolve().parents[2]
DOC = (ROOT / "docs" / "scenes.md").read_text()


def kind_sections():
    """{kind: text of its section} from the '#### `kind`' headings."""
    parts = re.split(r"^#### `([^`]+)`\n", DOC, flags=re.M)
    return {parts[i]: parts[i + 1].split("\n## ")[0] for i in range(1, len(parts), 2)}


def test_every_kind_and_parameter_is_documented():
    sections = kind_sections()
    for kind in rodcore.kinds():
        assert kind["name"] in sections, f"docs/scenes.md lacks initial kind {kind['name']!r}"
        for p in kind["numbers"] + kind["strings"]:
            assert f"| `{p['name']}` |" in sections[kind["name"]], \
                f"docs/scenes.md: kind {kind['name']!r} lacks parameter {p['name']!r} (paste `rodsim kinds`)"


def test_every_scene_key_is_documented():
    resolved = tomllib.loads(rodcore.resolve("[rod]\nlength = 1.0\npoints = 8\n"))
    for section, keys in resolved.items():
        assert f"## `[{section}]`" in DOC, section
        body = DOC.split(f"## `[{section}]`")[1].split("\n## ")[0]
        for key in keys:
            if section == "initial" and key != "kind":
                continue  # kind parameters: checked above
            assert f"| `{key}` |" in body, f"docs/scenes.md: [{section}] lacks key {key!r}"
    for extra in ("intrinsic_file", "path"):
        assert f"| `{extra}` |" in DOC


def test_every_example_scene_is_mentioned():
    # the paper_*.toml scenes belong to `dnarod paper-figures` and are listed as a group
    for scene in (ROOT / "workflows" / "scenes").glob("*.toml"):
        name = "paper_*.toml" if scene.name.startswith("paper_") else scene.name
        assert name in DOC, f"docs/scenes.md does not mention {name}"
