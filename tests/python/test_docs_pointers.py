"""Every docs page the code points at exists: a `docs/X.md` named anywhere in mdbridge/, workflows/,
dna_models/, bench/ or scripts/ (comments, docstrings, help texts) must be a file of docs/, so a page
that is renamed or merged leaves no comment pointing nowhere.

Control: a planted file naming a page that does not exist must fail, and one naming a page that does
must not."""
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
TREES = ("mdbridge", "workflows", "dna_models", "bench", "scripts")
SUFFIXES = {".py", ".yaml", ".yml", ".sh", ".toml", ".smk", ""}
POINTER = re.compile(r"docs/([A-Za-z0-9_.-]+\.md)\b")


def dangling(root: Path, trees=TREES) -> list[str]:
    """`file: docs/X.md` for every page named in the trees under ROOT that root/docs lacks."""
    faults = []
    for tree in trees:
        for f in sorted((root / tree).rglob("*")):
            if not f.is_file() or f.suffix not in SUFFIXES or "__pycache__" in f.parts:
                continue
            try:
                text = f.read_text()
            except UnicodeDecodeError:
                continue
            for page in sorted(set(POINTER.findall(text))):
                if not (root / "docs" / page).is_file():
                    faults.append(f"{f.relative_to(root)}: docs/{page}")
    return faults


def test_every_docs_page_named_in_the_code_exists():
    assert dangling(ROOT) == []


def test_control_a_pointer_to_a_missing_page_fails(tmp_path):
    (tmp_path / "docs").mkdir()
    (tmp_path / "docs" / "here.md").write_text("# Here\n")
    (tmp_path / "bench").mkdir()
    (tmp_path / "bench" / "ok.py").write_text('"""See docs/here.md, "Here"."""\n')
    assert dangling(tmp_path, ("bench",)) == []
    (tmp_path / "bench" / "bad.py").write_text("# moved: docs/gone.md\n")
    assert dangling(tmp_path, ("bench",)) == ["bench/bad.py: docs/gone.md"]
