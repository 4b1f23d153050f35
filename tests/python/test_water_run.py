"""A short run of the duplex in water at a set tension, for real: `dnarod build-md` of the 21-bp
scene in TIP3P with 150 mM NaCl at 30 pN (the minimised, unequilibrated build), `dnarod run-md`
for 1 ps, and `python3 -m dnarod.steps.water` on it (workflows/steps/water.py; its long runs are
results/water21, test_results_water21.py).

- the step writes checks.json, integrity.json and tension.json per run and summary.json over
  them; a 1-ps run of a minimised B-DNA keeps its pairs (the 97 % check passes), its junction
  and its side images; the tension is read with the water formula;
- a result that fails its own check is an error: with the integrity threshold above 1 the
  step exits 2 after writing its files (the control of the check);
- bad input exits 2 before any work: a vacuum run, a folder without md.done.
"""
from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from dna_models.errors import DnarodError

ROOT = Path(__file__).resolve().parents[2]
TENSION_PN = 30.0


def _step(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "dnarod.steps.water", *args], capture_output=True, text=True)


@pytest.fixture(scope="module")
def run(dnarod, gmx, tmp_path_factory) -> Path:
    d = tmp_path_factory.mktemp("water_run") / "T30"
    subprocess.run([str(dnarod), "build-md", str(ROOT / "workflows/scenes/dna21.toml"), "-o", str(d),
                    "--solvent", "tip3p", "--salt-mM", "150", "--minimize", "--constraints", "h-bonds",
                    "--dt", "0.002", "--cutoffs", "smooth", "--thermostat", "--protocol", "paper",
                    "--axial-tension-pN", str(TENSION_PN), "--seed", "4", "--ps", "1", "--gmx", gmx,
                    "--threads", "2"], check=True, capture_output=True)
    subprocess.run([str(dnarod), "run-md", str(d), "--ps", "1", "--output-ps", "0.02", "--gmx", gmx,
                    "--threads", "2"], check=True, capture_output=True)
    return d


def test_the_step_on_a_real_run(run, tmp_path, gmx):
    out = tmp_path / "results"
    r = _step(str(out), str(run), "--discard-ps", "0.2", "--no-coarse-grain", "--gmx", gmx)
    assert r.returncode == 0, r.stderr
    g = json.loads((out / "T30" / "integrity.json").read_text())
    assert g["intact_fraction"] >= 0.97 and g["ok"] and g["min_intact"] == 0.97     # a pair may flicker past 3.5 A
    c = json.loads((out / "T30" / "checks.json").read_text())
    assert c["junction_ok"] and c["side_image"]["ok"] and c["solvent"]["axial_tension_pN"] == TENSION_PN
    t = json.loads((out / "T30" / "tension.json").read_text())
    assert t["formula"].startswith("water") and t["tension_set_pN"] == TENSION_PN
    assert t["isotension"]["length_nm"]["n"] >= 30 and t["isotension"]["S_pN"] > 0
    s = json.loads((out / "summary.json").read_text())
    row = s["runs"]["T30"]
    assert row["n_atoms"] > 15000 and row["integrity_ok"] and row["forcefield"] == "charmm27"
    assert row["against_published"]["stretch_modulus_isotension"]["published"] == 1280.0
    assert s["stretch"] is None                    # one tension: no force-extension


def test_control_a_failed_integrity_check_is_an_error_after_the_files(run, tmp_path, gmx, monkeypatch):
    from dnarod.steps import water
    monkeypatch.setattr(water, "MIN_INTACT", 1.01)
    with pytest.raises(DnarodError, match="did not stay intact"):
        water.analyse(tmp_path / "results", [run], discard_ps=0.2, gmx=gmx, coarse_grain=False)
    assert (tmp_path / "results" / "summary.json").is_file()


def test_bad_input_exits_2_before_work(run, tmp_path):
    vac = tmp_path / "vacuum"
    shutil.copytree(run, vac, ignore=shutil.ignore_patterns("*.xtc", "*.trr", "*.cpt"))
    (vac / "md.xtc").write_bytes((run / "md.xtc").read_bytes())
    b = json.loads((vac / "build.json").read_text())
    b.pop("solvent")
    (vac / "build.json").write_text(json.dumps(b))
    r = _step(str(tmp_path / "o1"), str(vac))
    assert r.returncode == 2 and "not a solvated run at a set tension" in r.stderr and "build.json" in r.stderr
    (vac / "md.done").unlink()
    r = _step(str(tmp_path / "o2"), str(vac))
    assert r.returncode == 2 and "md.done missing" in r.stderr
    assert not (tmp_path / "o1").exists() and not (tmp_path / "o2").exists()
