"""The docs stay a manual, not a lab book: docs/ holds at most 4,000 lines in all and no page
over 400 (history lives in git, measured results in docs/results.md and results/), and every
relative link of README.md and docs/*.md points at a file that exists.

Each check has a control: a planted oversized page, an oversized folder and a broken link in a
temporary folder must fail."""
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
MAX_TOTAL_LINES = 4000
MAX_PAGE_LINES = 400
LINK = re.compile(r"\[[^\]]*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")


def over_limits(docs: Path) -> list[str]:
    """What breaks the limits in the folder DOCS (its *.md pages), empty if nothing."""
    lines = {p.name: len(p.read_text().splitlines()) for p in sorted(docs.glob("*.md"))}
    faults = [f"{docs.name}/{name}: {n} lines > {MAX_PAGE_LINES}" for name, n in lines.items()
              if n > MAX_PAGE_LINES]
    if sum(lines.values()) > MAX_TOTAL_LINES:
        faults.append(f"{docs.name}/: {sum(lines.values())} lines in all > {MAX_TOTAL_LINES}")
    return faults


def broken_links(pages: list[Path]) -> list[str]:
    """Relative links of PAGES whose target file does not exist (web links and anchors within
    the page are not files and are skipped; text inside code spans and blocks is not a link)."""
    faults = []
    for page in pages:
        text = re.sub(r"```.*?```", "", page.read_text(), flags=re.S)
        text = re.sub(r"`[^`\n]*`", "", text)
        for target in LINK.findall(text):
            if re.match(r"[a-z][a-z0-9+.-]*:", target) or target.startswith("#"):
                continue
            path = target.split("#")[0]
            if not (page.parent / path).exists():
                faults.append(f"{page.parent.name}/{page.name}: {target}")
    return faults


def test_docs_within_limits():
    assert over_limits(ROOT / "docs") == []


def test_control_an_oversized_page_and_folder_fail(tmp_path):
    docs = tmp_path / "docs"
    docs.mkdir()
    (docs / "small.md").write_text("line\n" * 10)
    assert over_limits(docs) == []
    (docs / "big.md").write_text("line\n" * (MAX_PAGE_LINES + 1))
    assert over_limits(docs) == [f"docs/big.md: {MAX_PAGE_LINES + 1} lines > {MAX_PAGE_LINES}"]
    (docs / "big.md").unlink()
    for i in range(MAX_TOTAL_LINES // MAX_PAGE_LINES + 1):      # every page within, the folder not
        (docs / f"p{i}.md").write_text("line\n" * MAX_PAGE_LINES)
    assert over_limits(docs) and all("in all" in f for f in over_limits(docs))


def test_relative_links_resolve():
    pages = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
    assert broken_links(pages) == []


def test_control_a_broken_link_fails(tmp_path):
    docs = tmp_path / "docs"
    docs.mkdir()
    (docs / "there.md").write_text("# there\n")
    page = docs / "page.md"
    page.write_text("[ok](there.md#top) [web](https://example.org) [self](#here) `[code](nowhere.md)`\n")
    assert broken_links([page]) == []
    page.write_text("[ok](there.md) and [gone](nowhere.md#x)\n")
    assert broken_links([page]) == ["docs/page.md: nowhere.md#x"]
