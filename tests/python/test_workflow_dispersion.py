"""workflows/config/dispersion.yaml through `dnarod compare --dry-run` (no MD): the jobs it
would run, with the arguments of the 5-ns dispersion run made outside the workflow
(its build.json: build-md --ps 5000 --seed 1 --constraints h-bonds --dt 0.002 --cutoffs
smooth --minimize --equilibrate-ps 20 --thermostat --tau-t-ps 2 --margin 100; run-md --ps
5000 --output-ps 0.5), and the adoption of such a folder (docs/dispersion.md): after the
scene file is written by the workflow's own step and the MD's chain is touched, only the
analysis steps remain. ~20 s."""
import os
import re
import subprocess
import sys
from pathlib import Path

import yaml

ROOT = Path(__file__).resolve().parents[2]
CONFIG = ROOT / "workflows" / "config" / "dispersion.yaml"
REAL_BUILD = ("--ps 5000 --seed 1 --constraints h-bonds --dt 0.002 --cutoffs smooth --minimize "
              "--equilibrate-ps 20 --thermostat --tau-t-ps 2 --margin 100")
ANALYSIS_RULES = {"config_record", "cg", "md_tension", "md_modes", "dispersion", "report"}


def _compare(dnarod, out, *extra, config=CONFIG):
    p = subprocess.run([str(dnarod), "compare", "--config", str(config), "-o", str(out), "--", *extra],
                       capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stdout[-3000:] + p.stderr[-3000:]
    return p.stdout + p.stderr


def _rules(text):
    return set(re.findall(r"^(?:local)?rule (\w+):", text, re.M)) - {"all"}


def test_dry_run_has_the_real_runs_arguments(tmp_path, dnarod):
    text = _compare(dnarod, tmp_path / "o", "--dry-run")
    assert _rules(text) == {"scene", "rod_run", "md_build", "md_run"} | ANALYSIS_RULES
    build = re.search(r"build-md rod/Av0/scene\.toml --rod rod/Av0/rod\.h5 -o md/Av0_seed1 (.*?) >", text).group(1)
    assert build.replace("--ps 5000.0", "--ps 5000") == REAL_BUILD
    run = re.search(r"run-md md/Av0_seed1 (.*?) >", text).group(1)
    assert run.replace("5000.0", "5000") == "--ps 5000 --threads 2 --output-ps 0.5"
    assert "--run-ps 5000.0 --every-ps 1.0" in text          # the rod run the box is sized from
    assert "--discard 2000" in text and "--discard-ps 1000.0" in text   # 0.5 ns + 4 ns of production
    # no wave analysis, no kicked coarse-grained rod: this run is unkicked
    assert not {"rod_analysis", "md_analysis", "cg_rod"} & _rules(text)
    cfg = yaml.safe_load(CONFIG.read_text())
    assert cfg["md"]["run_ps"] - cfg["dispersion"]["discard_ps"] >= 4000 and cfg["dispersion"]["discard_ps"] >= 500


def test_second_seed_and_stretched_boxes_are_options(tmp_path, dnarod):
    cfg = yaml.safe_load(CONFIG.read_text())
    cfg["seeds"] = [1, 2]
    cfg["dispersion"]["box_scales"] = [1.015, 1.03]
    path = tmp_path / "more.yaml"
    path.write_text(yaml.safe_dump(cfg))
    text = _compare(dnarod, tmp_path / "o", "--dry-run", config=path)
    assert "build-md rod/Av0/scene.toml --rod rod/Av0/rod.h5 -o md/Av0_seed2" in text
    for s in ("1.015", "1.03"):
        assert f"stretch md/Av0_seed1 md/Av0_seed1_box{s} --factor {s}" in text
        assert f"run-md md/Av0_seed2_box{s} --ps 5000.0 --threads 2 --output-ps 0.5" in text
        assert f"modes md/Av0_seed1_box{s} md/Av0_seed2_box{s} --discard-ps 1000.0" in text
    assert "modes md/Av0_seed1 md/Av0_seed2 --discard-ps 1000.0 -o dispersion/box1/md_modes" in text


def test_adopting_a_run_made_outside_the_workflow(tmp_path, dnarod):
    """The folder of the real run: rod.h5 and the MD's outputs, no scene.toml (stand-in empty
    files, dated like the real ones). The procedure of docs/dispersion.md leaves only the
    analysis, and a control without the touch would rerun the MD."""
    d = tmp_path / "dispersion"
    (d / "rod" / "Av0").mkdir(parents=True)
    (d / "md" / "Av0_seed1").mkdir(parents=True)
    for f, t in (("rod/Av0/rod.h5", 1), ("md/Av0_seed1/build.json", 2), ("md/Av0_seed1/md.xtc", 3),
                 ("md/Av0_seed1/md.tpr", 3), ("md/Av0_seed1/checks.json", 3)):
        (d / f).write_text("")
        os.utime(d / f, (1.7e9 + 100 * t, 1.7e9 + 100 * t))
    p = subprocess.run([sys.executable, "-m", "dnarod.steps", "scene",
                        str(ROOT / "workflows/scenes/dna158.toml"), str(d / "rod/Av0/scene.toml"), "--A-v", "0",
                        "--run-ps", "5000", "--every-ps", "1"], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    assert "rule md_run:" in _compare(dnarod, d, "--dry-run")          # control: the MD would rerun
    _compare(dnarod, d, "--touch", "--until", "md_run")
    assert (d / "md/Av0_seed1/md.xtc").read_text() == ""                  # touched, not run
    assert _rules(_compare(dnarod, d, "--dry-run")) == ANALYSIS_RULES
