#!/usr/bin/python3
"""The README's headline table ("What it found"), rendered from results/headline.json.

Each row's value is a format string filled from the row's one source file (a results
file its run or benchmark wrote), so the README never holds a number of its own.
Paste the output between the README's `headline` markers; tests/python/test_docs_numbers.py
fails when the README and this rendering differ.

    /usr/bin/python3 scripts/headline_table.py
"""
import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
HEADLINE = ROOT / "results" / "headline.json"


class _Fields(dict):
    """A results file's JSON for str.format_map: nested keys as attributes (a.b),
    list items by index (a[0])."""

    def __getitem__(self, key):
        return _wrap(dict.__getitem__(self, key))

    def __getattr__(self, key):
        return self[key]


def _wrap(x):
    if isinstance(x, dict):
        return _Fields(x)
    if isinstance(x, list):
        return [_wrap(v) for v in x]
    return x


def rows(headline: Path = HEADLINE) -> list[dict]:
    """[{finding, value, source, docs}] with each value filled from its source file."""
    out = []
    for r in json.loads(headline.read_text())["rows"]:
        data = json.loads((ROOT / r["source"]).read_text())
        out.append(dict(r, value=r["value"].format_map(_Fields(data))))
    return out


def table(headline: Path = HEADLINE) -> str:
    lines = ["| finding | measured | source |", "|---|---|---|"]
    for r in rows(headline):
        lines.append(f"| {r['finding']} ([docs]({r['docs']})) | {r['value']} | "
                     f"[{Path(r['source']).name}]({r['source']}) |")
    return "\n".join(lines)


if __name__ == "__main__":
    sys.stdout.write(table() + "\n")
