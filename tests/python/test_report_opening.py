"""The report opens with what the run found in at most five sentences, each reason for a
missing number once, and the reasons in full below (workflows/report/verdict.py, opening).

Made from the committed report of the dispersion workflow (results/dispersion/workflow/
results.json: no kicked run, the coarse-graining refused), and from the same with the main
job's kicked wave added as the main job has it (one seed, the coarse-grained rod's kicked
speed refused for the same reason as its modes: the page used to say that reason twice).
Controls: the sentence counter counts a planted sixth sentence; without the grouping of
reasons the coarse-graining's reason stands twice."""
import copy
import html
import json
import re
from pathlib import Path

import pytest

from dnarod.report import report, verdict

ROOT = Path(__file__).resolve().parents[2]
COMMITTED = ROOT / "results/dispersion/workflow/results.json"


def sentences(text: str) -> list[str]:
    """The sentences of plain text: a full stop, ! or ? followed by a capital letter."""
    return [s for s in re.split(r"(?<=[.!?])\s+(?=[A-Z])", text.strip()) if s]


def page_opening(page: str) -> str:
    """The text of the page's opening paragraph (the verdict section, without its heading)."""
    i = page.index('id="verdict"')
    sec = page[i:page.index("</section>", i)]
    return html.unescape(re.sub(r"<[^>]+>", " ", sec.split("</h2>", 1)[1])).strip()


@pytest.fixture(scope="module")
def committed():
    return json.loads(COMMITTED.read_text())


@pytest.fixture(scope="module")
def main_job(committed):
    """The committed results with the main job's kicked wave (results/main_job.json's speed and
    error, the paper rod's 1.674 +- 0.004 A/ps of docs/results.md) and its coarse-grained rod
    refused by the loop for the reason the dispersion gives."""
    res = copy.deepcopy(committed)
    mj = json.loads((ROOT / "results/main_job.json").read_text())
    floor = json.loads((ROOT / "results/main_job_realisations.json").read_text())["summary"]["floor_A_per_ps"]
    reason = res["dispersion"]["refused"]["cg_rod"]
    res.update(headline_A_v_A_per_ps=1.0, rod_wave_speed_A_per_ps=1.674, rod_wave_speed_err_A_per_ps=0.004,
               md_wave_speed_A_per_ps=mj["md_phase_speed_A_per_ps"],
               md_wave_speed_err_one_record_A_per_ps=mj["md_phase_speed_err_A_per_ps"],
               md_wave_speed_err_A_per_ps=(mj["md_phase_speed_err_A_per_ps"] ** 2 + floor ** 2) ** 0.5,
               md_wave_speed_realisations={"floor_A_per_ps": floor, "k": 3},
               cg_rod_wave_speed_A_per_ps=None, cg_rod_reason=reason.split(": ", 1)[1])   # the loop's wording
    assert reason.endswith(res["cg_rod_reason"]) and res["cg_rod_reason"].startswith("coarse-graining refused")
    return res


def test_committed_report_opening(committed, tmp_path):
    """The page made from the committed results.json opens with at most five sentences, and
    the coarse-graining's refusal stands once in them and in full in the dispersion section."""
    report.write_html({}, committed, {}, tmp_path / "index.html")
    page = (tmp_path / "index.html").read_text()
    text = page_opening(page)
    assert 2 <= len(sentences(text)) <= verdict.MAX_SENTENCES, sentences(text)
    core = committed["dispersion"]["refused"]["cg_rod"].split("; at least")[0]
    assert text.count("coarse-graining refused") == 1 and core.split(": ")[-1] in text, text
    section = html.unescape(page[page.index('id="dispersion-refused"'):])
    assert committed["dispersion"]["refused"]["cg_rod"] in section
    assert "tension" in text and "MD" in text


def test_main_job_opening_says_each_reason_once(main_job):
    said = verdict.opening(main_job)
    text = html.unescape(" ".join(said))
    assert len(sentences(text)) == len(said) <= verdict.MAX_SENTENCES, sentences(text)
    assert text.count("coarse-graining refused") == 1, text
    assert text.count("too few frames") == 1, text
    # the kicked wave first, with what its +- holds
    assert said[0].startswith("Kicked at A_v = 1 A/ps") and "scatter between 3 runs of this setting" in said[0]
    assert f"{main_job['md_wave_speed_A_per_ps']:.3g} &plusmn; {main_job['md_wave_speed_err_A_per_ps']:.2g}" in said[0]


def test_controls_the_counter_and_the_grouping_can_fail(main_job, monkeypatch):
    text = html.unescape(" ".join(verdict.opening(main_job)))
    assert len(sentences(text + " A sixth sentence, planted. And a seventh.")) == len(sentences(text)) + 2
    monkeypatch.setattr(verdict, "group_reasons", lambda items: [([w], r) for w, r in items])
    ungrouped = html.unescape(" ".join(verdict.opening(main_job)))
    assert ungrouped.count("too few frames") == 2


def test_reasons_with_a_shared_head_are_one():
    """Two rods refused at one tension (the tiny workflow's wording): one reason, its shared
    head; a different reason stays apart; "refused: " adds nothing and goes."""
    head = ("no prediction at the MD's tension -159 +- 66 pN: the straight rod is unstable between -225 and "
            "-92.4 pN (it buckles under a compression beyond Euler's load)")
    g = verdict.group_reasons([("the coarse-grained rod's modes", head + ": not conservative at k index 3"),
                               ("the paper rod's modes", head + ": not conservative at k index 1"),
                               ("the MD's kicked speed", "refused: the record (4 ps) holds a quarter period. "
                                                         "Run longer")])
    assert g == [(["the coarse-grained rod's modes", "the paper rod's modes"], head),
                 (["the MD's kicked speed"], "the record (4 ps) holds a quarter period; Run longer")]
    # short shared heads are not one reason
    assert len(verdict.group_reasons([("a", "too few: x"), ("b", "too few: y")])) == 2
