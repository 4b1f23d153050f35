"""The README's two commands leave every tracked file as it was: scripts/record_run.py, which
scripts/run.sh and scripts/test.sh call at the end, writes its record under out/records/, and
only its explicit `commit` replaces the committed results/ record that the docs quote."""
import importlib.util
import json
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def _record_run(root: Path):
    spec = importlib.util.spec_from_file_location("record_run", ROOT / "scripts" / "record_run.py")
    rr = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(rr)
    rr.ROOT, rr.RECORDS = root, root / "out" / "records"     # a stand-in checkout
    return rr


def test_records_go_under_out_and_commit_is_explicit(tmp_path):
    (tmp_path / "results").mkdir()
    committed = tmp_path / "results" / "test_times.json"
    committed.write_text('{"total_s": 1}')
    rr = _record_run(tmp_path)
    assert rr.main(["test-times", "--total-s", "1234", "--step", "pytest=1000"]) == 0
    assert json.loads(committed.read_text()) == {"total_s": 1}          # tracked file as it was
    assert json.loads((tmp_path / "out" / "records" / "test_times.json").read_text())["total_s"] == 1234
    assert rr.main(["commit", "test_times"]) == 0                       # the explicit step
    assert json.loads(committed.read_text())["total_s"] == 1234
    # the control: a record never made is not committed
    assert rr.main(["commit", "main_job"]) == 2 and not (tmp_path / "results" / "main_job.json").exists()


def test_the_scripts_do_not_write_results():
    for script in ("run.sh", "test.sh"):
        calls = [ln for ln in (ROOT / "scripts" / script).read_text().splitlines()
                 if "record_run.py" in ln and not ln.lstrip().startswith("#")]
        assert calls and not any("commit" in ln for ln in calls), calls


def test_committing_a_main_job_adds_its_realisation(tmp_path):
    """`commit main_job` also appends the run's kicked-MD speed (its one-record error) to the
    realisations of the main job's setting (workflows/report/realisations.py), once."""
    (tmp_path / "results").mkdir()
    real = tmp_path / "results" / "main_job_realisations.json"
    real.write_text((ROOT / "results" / "main_job_realisations.json").read_text())
    k = len(json.loads(real.read_text())["realisations"])
    rr = _record_run(tmp_path)
    rr.RECORDS.mkdir(parents=True)
    rec = {"date": "2026-12-07", "machine": "a stand-in", "md_phase_speed_A_per_ps": 1.2,
           "md_phase_speed_err_A_per_ps": 0.04}
    (rr.RECORDS / "main_job.json").write_text(json.dumps(rec))
    assert rr.main(["commit", "main_job"]) == 0 and rr.main(["commit", "main_job"]) == 0
    got = json.loads(real.read_text())
    assert len(got["realisations"]) == k + 1 and got["summary"]["k"] == k + 1
    assert got["realisations"][-1]["speed_err_A_per_ps"] == 0.04
