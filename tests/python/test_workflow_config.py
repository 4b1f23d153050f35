"""The workflow configuration is checked like a scene (workflows/configuration.py,
workflows/config/schema.yaml): before anything runs, every unknown, misspelt or
missing key and every value of the wrong type or range is an error naming the file
and the key, with what is allowed."""
import re
import subprocess
from pathlib import Path

import pytest
import yaml

from dna_models.errors import InputError
from dnarod.configuration import SCHEMA_PATH, load, schema, validate

ROOT = Path(__file__).resolve().parents[2]
SHIPPED = sorted((ROOT / "workflows" / "config").glob("*.yaml"))
GOOD = {"scene": "workflows/scenes/dna21.toml", "A_v_A_per_ps": [5], "seeds": [1],
        "headline_A_v_A_per_ps": 5, "rod": {"run_ps": 20, "output_every_ps": 0.2},
        "md": {"run_ps": 4}}


def _err(data) -> str:
    with pytest.raises(InputError) as e:
        validate(data, "my.yaml")
    return str(e.value)


@pytest.mark.parametrize("path", [p for p in SHIPPED if p != SCHEMA_PATH], ids=lambda p: p.name)
def test_shipped_configs_are_valid(path):
    cfg = load(path)
    assert cfg["md"]["threads"] >= 1 and "n_boot" in cfg["analysis"]


def test_defaults_are_filled_in():
    cfg = validate(GOOD)
    assert cfg["md"]["enabled"] is True and cfg["md"]["threads"] == 2
    assert cfg["sweep"] == {"A_v_A_per_ps": []}
    assert cfg["analysis"] == {"fit_modulus": False, "n_boot": 200, "waves": True}
    assert GOOD["md"] == {"run_ps": 4}  # the input is not modified


def test_the_reported_case_missing_run_ps_and_a_stray_key():
    """The case a new user met: md without run_ps, with a stray key; both are named."""
    bad = dict(GOOD, md={"threads": 2, "run_ps_": 4})
    msg = _err(bad)
    assert "my.yaml" in msg
    assert "missing key 'md.run_ps'" in msg
    assert "unknown key 'md.run_ps_'" in msg and "did you mean 'md.run_ps'" in msg


def test_misspelt_top_level_key_did_you_mean():
    bad = dict(GOOD)
    bad["seed"] = bad.pop("seeds")
    msg = _err(bad)
    assert "missing key 'seeds'" in msg and "unknown key 'seed' (did you mean 'seeds'?)" in msg


@pytest.mark.parametrize("change, key, allowed", [
    ({"md": {"run_ps": "long"}}, "md.run_ps", "must be number, > 0"),
    ({"md": {"run_ps": -1}}, "md.run_ps", "> 0"),
    ({"seeds": [1.5]}, "seeds[0]", "integer"),
    ({"A_v_A_per_ps": []}, "A_v_A_per_ps", "at least 1 item"),
    ({"md": {"run_ps": 4, "enabled": "yes"}}, "md.enabled", "boolean"),
    ({"analysis": {"n_boot": 3}}, "analysis.n_boot", ">= 10"),
])
def test_wrong_type_or_range_names_key_and_allowed(change, key, allowed):
    msg = _err(dict(GOOD, **change))
    assert f"key '{key}'" in msg and allowed in msg


def test_headline_must_be_one_of_the_amplitudes():
    msg = _err(dict(GOOD, headline_A_v_A_per_ps=1))
    assert "headline_A_v_A_per_ps" in msg and "[5]" in msg


def test_every_key_is_documented():
    """docs/workflow.md lists every key of the schema (dotted), in its key table."""
    doc = (ROOT / "docs" / "workflow.md").read_text()

    def keys(node, prefix=""):
        for name, sub in node.get("properties", {}).items():
            yield prefix + name
            if sub.get("type") == "object":
                yield from keys(sub, prefix + name + ".")
    missing = [k for k in keys(schema()) if not re.search(rf"`{re.escape(k)}`", doc)]
    assert not missing, f"docs/workflow.md does not document {missing}"


def test_compare_refuses_before_snakemake_runs(tmp_path, dnarod):
    cfg = dict(GOOD, md={"threads": 2, "run_sp": 4})
    path = tmp_path / "bad.yaml"
    path.write_text(yaml.safe_dump(cfg))
    p = subprocess.run([str(dnarod), "compare", "--config", str(path), "--out", str(tmp_path / "o")],
                       capture_output=True, text=True)
    assert p.returncode == 2, p.stderr
    assert str(path) in p.stderr and "missing key 'md.run_ps'" in p.stderr and "did you mean 'md.run_ps'" in p.stderr
    assert "Snakefile" not in p.stderr and "Traceback" not in p.stderr
    assert not (tmp_path / "o" / ".snakemake").exists()


def test_per_amplitude_md_arguments_and_the_rod_covering_its_md(tmp_path, dnarod):
    """md.build_args_per_A_v reaches build-md of that A_v only, and the rod run an MD starts
    from is lengthened to cover a longer per-A_v MD (build-md refuses a rod run shorter than
    the MD): read from the jobs Snakemake would run (--dry-run), not from the Snakefile."""
    cfg = dict(GOOD, A_v_A_per_ps=[0, 5], md={"run_ps": 4, "run_ps_per_A_v": {0: 30},
                                               "build_args": "--seed {seed}",
                                               "build_args_per_A_v": {0: "--thermostat"}})
    path = tmp_path / "per.yaml"
    path.write_text(yaml.safe_dump(cfg))
    p = subprocess.run([str(dnarod), "compare", "--config", str(path), "--out", str(tmp_path / "o"),
                        "--", "--dry-run"], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr + p.stdout
    builds = {m.group(1): m.group(0) for m in re.finditer(r"build-md rod/Av([0-9.]+)/scene\.toml.*", p.stdout)}
    assert set(builds) == {"0", "5"}, p.stdout
    assert "--seed 1 --thermostat" in builds["0"] and "--ps 30" in builds["0"]
    assert "--thermostat" not in builds["5"] and "--seed 1" in builds["5"] and "--ps 4" in builds["5"]
    scenes = dict(re.findall(r"steps scene \S+ rod/Av([0-9.]+)/scene\.toml --A-v \S+ --run-ps ([0-9.]+)", p.stdout))
    assert float(scenes["0"]) == 30.0            # lengthened to its MD
    assert float(scenes["5"]) == 20.0            # rod.run_ps, already longer than its MD


def test_prediction_is_the_main_job_with_a_long_equilibrium_run():
    """prediction.yaml says it is default.yaml with only the A_v = 0 run longer; a copy
    drifts, so the claim is checked key by key."""
    default = yaml.safe_load((ROOT / "workflows" / "config" / "default.yaml").read_text())
    pred = yaml.safe_load((ROOT / "workflows" / "config" / "prediction.yaml").read_text())
    assert pred["md"].pop("run_ps_per_A_v") == {0: 1200} and default["md"].pop("run_ps_per_A_v") == {0: 1000}
    assert pred == default
