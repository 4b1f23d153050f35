"""One source for each quoted number: the measured figures the README and docs quote (the
main job's time, MD speed and drift; the test command's time per step; the headline
results) live once, in the results file their run or benchmark writes, and the prose must
quote that file, to its printed rounding. Old figures for the same things must be gone.

Each check has a control: the same check on a results file with one number changed fails."""
import copy
import importlib.util
import json
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
RESULTS = ROOT / "results"


def _load_script(name):
    spec = importlib.util.spec_from_file_location(name, ROOT / "scripts" / f"{name}.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _results() -> dict:
    return {p.stem: json.loads(p.read_text()) for p in sorted(RESULTS.glob("*.json"))}


def _pages() -> dict:
    pages = {"README.md": (ROOT / "README.md").read_text()}
    pages.update({f"docs/{p.name}": p.read_text() for p in sorted((ROOT / "docs").glob("*.md"))})
    return pages


def quotes(r: dict) -> list[tuple[str, str]]:
    """(page, text) pairs: each text is a figure of a results file as the page prints it."""
    mj, tt = r["main_job"], r["test_times"]
    ns = "{}-{} ns/day".format(*mj["md_ns_per_day"])
    drift = f"{mj['md_energy_drift_kJ_mol_per_ns_per_atom']:.2f} kJ/mol/ns per atom"
    total_min = f"{tt['total_s'] / 60:.1f} min"
    costs = json.loads((ROOT / "bench" / "results" / "costs.json").read_text())["rod_vs_md"]
    x158 = "~{}-{}x faster in wall time".format(*(int(round(v, -1)) for v in costs["speedup_wall_N158"]))
    pred = r["prediction"]
    return [
        ("README.md", f"{mj['wall_min']:g} min in all"),
        ("README.md", f"the MD at {ns}"),
        ("README.md", f"energy drift {drift}"),
        ("README.md", f"Measured: {total_min}"),
        ("docs/md.md", f"ran at {ns}"),
        ("docs/md.md", f"**{drift}** at {ns}"),
        ("docs/workflow.md", f"**measured {mj['wall_min']:g} min**"),
        ("docs/workflow.md", f"the {ns} it measured"),
        ("docs/workflow.md", f"**measured {total_min}**"),
        ("docs/performance.md", f"at the {ns}"),
        ("docs/performance.md", x158),
        ("docs/testing.md", f"| pytest, all of `tests/python` | {tt['steps_s']['pytest']} s |"),
        ("docs/testing.md", f"| {tt['steps_s']['sanitizers + fuzz']} s |"),
        ("docs/testing.md", f"**{total_min}**"),
        ("README.md", f"with the 1000-ps run: {r['main_job_1000ps']['wall_min']:g} min in all"),
        ("docs/workflow.md", f"**measured {r['main_job_1000ps']['wall_min']:g} min in all**"),
        ("docs/results.md", f"gave {r['main_job_1000ps']['md_phase_speed_A_per_ps']:.2f} +- "
                            f"{r['main_job_1000ps']['md_phase_speed_err_A_per_ps']:.2f} A/ps"),
        ("docs/results.md", f"the MD's mode runs at {mj['md_phase_speed_A_per_ps']:.2f} +- "
                            f"{mj['md_phase_speed_err_A_per_ps']:.2f} A/ps"),
        ("docs/coarse-graining.md", f"**{pred['md_speed_A_per_ps']:.3f} +- {pred['md_speed_err_A_per_ps']:.3f}**"),
        ("docs/coarse-graining.md", f"**{pred['cg_rod_speed_A_per_ps']:.3f} +- "
                                    f"{pred['cg_rod_speed_err_A_per_ps']:.3f}**"),
        ("docs/coarse-graining.md", f"Measured: {pred['cg_rod_speed_A_per_ps']:.2f} vs "
                                    f"{pred['md_speed_A_per_ps']:.2f} A/ps; {pred['status']}"),
        ("docs/results.md", f"Measured: {pred['cg_rod_speed_A_per_ps']:.2f} vs "
                            f"{pred['md_speed_A_per_ps']:.2f} A/ps; {pred['status']}"),
    ]


def _unquoted(r: dict, pages: dict) -> list[tuple[str, str]]:
    flat = {k: re.sub(r"\s+", " ", v) for k, v in pages.items()}   # prose wraps lines
    return [(page, text) for page, text in quotes(r) if text not in flat[page]]


def test_every_results_file_says_when_where_and_how():
    r = _results()
    assert {"main_job", "test_times", "prediction", "headline"} <= set(r)
    for name, rec in r.items():
        if name == "headline":
            continue
        for key in ("what", "date", "machine", "command"):
            assert rec.get(key), f"results/{name}.json: no {key!r}"
        assert re.fullmatch(r"\d{4}-\d{2}-\d{2}", rec["date"]), rec["date"]


def test_prose_quotes_its_results_files():
    assert _unquoted(_results(), _pages()) == []


def test_control_a_changed_figure_is_caught():
    r = _results()
    for path in (("main_job", "wall_min"), ("test_times", "total_s"), ("prediction", "md_speed_A_per_ps")):
        bad = copy.deepcopy(r)
        bad[path[0]][path[1]] = bad[path[0]][path[1]] * 1.1 + 1
        assert _unquoted(bad, _pages()), f"changing {path} went unnoticed"


STALE = [  # (pattern, pages or None for all): older figures for the same quantities,
    #         replaced by the results files, and claims a re-derivation refuted
    (r"\b(21|29\.7|36-40|57-62|20\.7) ns/day", None),
    (r"\b73 min", None),
    (r"\b0\.90 kJ/mol/ns per atom", ("README.md", "docs/md.md", "docs/workflow.md")),  # the main job's drift
    (r"1\.5x too (high|stiff)", None),
    (r"equals the paper's", None),
    (r"beyond the bootstrap errors", None),
    (r"65.pN overstretching", None),
    (r"beyond the (overstretching )?plateau", None),
]


def test_old_and_refuted_figures_are_gone():
    pages = {k: re.sub(r"\s+", " ", v) for k, v in _pages().items()}
    hits = [(page, m.group(0)) for page, text in pages.items() for pat, where in STALE
            if where is None or page in where for m in re.finditer(pat, text)]
    assert hits == []
    assert re.search(STALE[0][0], "the MD ran at 57-62 ns/day")     # the pattern can match


def test_readme_headline_is_rendered_from_its_sources():
    """The README's headline block is scripts/headline_table.py's rendering, and every
    row's value comes from its source file (a control: a changed source changes the table)."""
    ht = _load_script("headline_table")
    readme = (ROOT / "README.md").read_text()
    m = re.search(r"<!-- headline:.*?-->\n(.*?)\n<!-- /headline -->", readme, re.S)
    assert m, "README: no <!-- headline --> block"
    assert m.group(1) == ht.table()
    rows = ht.rows()
    assert len(rows) >= 4 and all((ROOT / r["source"]).is_file() and (ROOT / r["docs"]).is_file()
                                  for r in rows)
    src = json.loads((ROOT / "docs/figures/wavespeed.json").read_text())
    row = next(r for r in rows if r["source"] == "docs/figures/wavespeed.json")
    assert row["value"] == f"{src['measured_A_per_ps']:.3f} +- {src['measured_err_A_per_ps']:.3f} A/ps"


def test_readme_stays_short_and_finds_every_moved_page():
    readme = (ROOT / "README.md").read_text()
    assert len(readme.splitlines()) <= 150
    for page in ("results", "performance", "dependencies", "architecture", "contracts", "testing"):  # units: contracts
        assert f"(docs/{page}.md" in readme, page
        assert (ROOT / "docs" / f"{page}.md").is_file()


def test_recorders_write_what_the_docs_quote(tmp_path, monkeypatch):
    """scripts/record_run.py (run by scripts/run.sh and scripts/test.sh) writes every key
    that quotes() reads, so the next run replaces the figures rather than adding new ones."""
    rr = _load_script("record_run")
    out = tmp_path / "compare"
    (out / "md" / "Av1_seed1").mkdir(parents=True)
    (out / "md" / "Av0_seed1").mkdir(parents=True)
    (out / "results.json").write_text(json.dumps({
        "md_energy_drift_kJ_mol_per_ns_per_atom": 0.8712, "md_energy_drift_target_kJ_mol_per_ns_per_atom": 0.1,
        "md_wave_speed_A_per_ps": 1.1234, "md_wave_speed_err_A_per_ps": 0.0312}))
    (out / "md" / "Av1_seed1" / "md.done").write_text(json.dumps({"ns_per_day": 48.4}))
    (out / "md" / "Av0_seed1" / "md.done").write_text(json.dumps({"ns_per_day": 51.6}))
    args = type("A", (), {"out": str(out), "wall_s": 1644.0})
    rec = rr.main_job(args)
    assert rec["md_ns_per_day"] == [48, 52] and rec["wall_min"] == pytest.approx(27.4)
    assert rec["md_energy_drift_kJ_mol_per_ns_per_atom"] == 0.87 and rec["md_phase_speed_A_per_ps"] == 1.12
    assert set(_results()["main_job"]) <= set(rec)
    t = rr.test_times(type("A", (), {"step": ["pytest=617", "sanitizers + fuzz=392"], "total_s": 1026.0}))
    assert t["steps_s"] == {"pytest": 617, "sanitizers + fuzz": 392} and t["total_s"] == 1026
    assert set(_results()["test_times"]) <= set(t)
