"""The medium of a comparison (md.solvent, md.salt_mM, md.axial_tension_pN;
workflows/configuration.py): vacuum by default with no option added to any build, so every
existing configuration's jobs are what they were (test_workflow_dispersion.py holds
dispersion.yaml's build arguments to the real run's, character for character); in water the
build gets --solvent/--salt-mM/--axial-tension-pN, read from the jobs Snakemake would run
(--dry-run) of workflows/config/dispersion_water.yaml; bad values stop before anything runs,
naming the key and what is allowed. ~30 s (two dry runs)."""
import re
import subprocess

import pytest
import yaml

from dna_models.errors import InputError
from dnarod.configuration import load, md_build_args, schema, validate
from dnarod.report import realisations
from test_workflow_config import GOOD, ROOT
from test_workflow_dispersion import ANALYSIS_RULES, _compare, _rules

WATER = ROOT / "workflows" / "config" / "dispersion_water.yaml"
VACUUM = ROOT / "workflows" / "config" / "dispersion.yaml"


def _job(text: str, rule: str) -> str:
    """The header of RULE's job in a dry run's listing (up to its shell command)."""
    i = text.index(f"rule {rule}:")
    return text[i:text.index("\n\n", i)]


def _err(md=None, **top) -> str:
    cfg = dict(GOOD, md=dict(GOOD["md"], **(md or {})), **top)
    with pytest.raises(InputError) as e:
        validate(cfg, "my.yaml")
    return str(e.value)


def test_the_allowed_solvents_are_the_registrys():
    """The schema's list is the build's (mdbridge/md/gromacs/solvent.py SOLVENTS: vacuum and
    every registered force field's water model), so the loader allows what build-md does."""
    from mdbridge.md.gromacs.solvent import SOLVENTS
    assert schema()["properties"]["md"]["properties"]["solvent"]["enum"] == list(SOLVENTS)


def test_vacuum_is_the_default_and_adds_no_option():
    cfg = validate(dict(GOOD, md={"run_ps": 4, "build_args": "--seed {seed}"}))
    assert (cfg["md"]["solvent"], cfg["md"]["salt_mM"], cfg["md"]["axial_tension_pN"]) == ("vacuum", 0, None)
    assert md_build_args(cfg, 5) == "--seed {seed}"
    for path in sorted((ROOT / "workflows" / "config").glob("*.yaml")):
        if path.name in ("schema.yaml", WATER.name):
            continue
        c = load(path)
        assert c["md"]["solvent"] == "vacuum" and "--solvent" not in md_build_args(c, c["A_v_A_per_ps"][0]), path


def test_water_config_builds_in_water_at_its_tension(tmp_path, dnarod):
    cfg = load(WATER)
    assert (cfg["md"]["solvent"], cfg["md"]["salt_mM"], cfg["md"]["axial_tension_pN"]) == ("tip3p", 150, 20)
    text = _compare(dnarod, tmp_path / "o", "--dry-run", config=WATER)
    assert _rules(text) == {"scene", "rod_run", "md_build", "md_run"} | ANALYSIS_RULES
    build = re.search(r"build-md rod/Av0/scene\.toml --rod rod/Av0/rod\.h5 -o md/Av0_seed1 (.*?) >", text).group(1)
    opts = build.split()
    for opt, value in (("--solvent", "tip3p"), ("--salt-mM", "150"), ("--axial-tension-pN", "20"),
                       ("--threads", "32"), ("--margin", "40")):
        assert opts[opts.index(opt) + 1] == value, build
    assert "--thermostat" in opts and "--ps 5000" in build
    assert "threads: 2" in _job(text, "md_build")            # md.threads, capped by compare's --cores 2
    assert "run-md md/Av0_seed1 --ps 5000.0 --threads 32 --output-ps 0.5" in text
    # dispersion.yaml's equilibrium analysis, unchanged: only the medium, margin and cores differ
    vac = load(VACUUM)
    for key in ("scene", "A_v_A_per_ps", "seeds", "rod", "analysis", "coarse_grain", "dispersion"):
        assert cfg[key] == vac[key], key
    strip = ("--margin", "--threads")
    assert [a for a in cfg["md"]["build_args"].split() if a not in strip and a not in ("40",)] == \
        [a for a in vac["md"]["build_args"].split() if a not in strip and a not in ("100",)]


def test_vacuum_build_gets_one_core_water_build_the_mds(tmp_path, dnarod):
    """Control of the test above: the same file in vacuum builds with none of the medium's
    options and on one core (the vacuum builds' setting before these keys)."""
    cfg = yaml.safe_load(WATER.read_text())
    for k in ("solvent", "salt_mM", "axial_tension_pN"):
        cfg["md"].pop(k)
    path = tmp_path / "vac.yaml"
    path.write_text(yaml.safe_dump(cfg))
    text = _compare(dnarod, tmp_path / "o", "--dry-run", config=path)
    build = re.search(r"build-md rod/Av0/scene\.toml .*? >", text).group(0)
    assert not {"--solvent", "--salt-mM", "--axial-tension-pN", "--threads"} & set(build.split()), build
    assert "threads:" not in _job(text, "md_build")          # Snakemake prints no line for one thread


@pytest.mark.parametrize("md, top, key, allowed", [
    ({"solvent": "water"}, {}, "md.solvent", "one of vacuum, tip3p"),
    ({"salt_mM": -5}, {}, "md.salt_mM", ">= 0"),
    ({"salt_mM": 150}, {}, "md.salt_mM", "salt needs water; set key 'md.solvent' to one of tip3p"),
    ({"salt_mM": float("inf"), "solvent": "tip3p"}, {}, "md.salt_mM", "finite"),
    ({"axial_tension_pN": 10}, {}, "md.axial_tension_pN", "held by the water's barostat"),
    ({"axial_tension_pN": 10, "solvent": "tip3p"}, {}, "md.axial_tension_pN", "needs --thermostat"),
    ({"axial_tension_pN": 10, "solvent": "tip3p", "build_args": "--thermostat"},
     {"dispersion": {"box_scales": [1.015]}}, "dispersion.box_scales", "the barostat sets the length"),
    ({"build_args": "--seed 1 --solvent tip3p"}, {}, "md.build_args", "set key 'md.solvent' instead"),
    ({"build_args_per_A_v": {5: "--salt-mM 100"}}, {}, "md.build_args_per_A_v[5]", "set key 'md.salt_mM'"),
    ({"solvent": "tip3p", "build_args": "--thermostat --axial-pressure"}, {}, "md.build_args",
     "key 'md.axial_tension_pN' (0 for none)"),
])
def test_bad_medium_names_key_and_allowed(md, top, key, allowed):
    msg = _err(md, **top)
    assert f"key '{key}'" in msg and allowed in msg, msg
    assert "my.yaml" in msg


def test_tension_with_thermostat_per_amplitude_is_accepted():
    """--thermostat may come from md.build_args_per_A_v of every amplitude; one missing is named."""
    md = {"solvent": "tip3p", "axial_tension_pN": 0, "build_args_per_A_v": {5: "--thermostat"}}
    assert validate(dict(GOOD, md=dict(GOOD["md"], **md)))["md"]["axial_tension_pN"] == 0
    msg = _err(md, A_v_A_per_ps=[0, 5])
    assert "A_v = 0" in msg and "A_v = 5" not in msg


def test_compare_refuses_a_bad_solvent_with_exit_2(tmp_path, dnarod):
    cfg = dict(GOOD, md={"run_ps": 4, "solvent": "spc"})
    path = tmp_path / "bad.yaml"
    path.write_text(yaml.safe_dump(cfg))
    p = subprocess.run([str(dnarod), "compare", "--config", str(path), "--out", str(tmp_path / "o")],
                       capture_output=True, text=True)
    assert p.returncode == 2, p.stderr
    assert "key 'md.solvent' = 'spc': must be one of vacuum, tip3p" in p.stderr and "Traceback" not in p.stderr


def test_water_run_is_not_a_realisation_of_the_vacuum_main_job():
    """The between-realisation floor of the main job (vacuum) must not be given to a run in water
    of otherwise the same configuration; the vacuum configuration itself still gets it (control)."""
    rec = realisations.load()
    if rec is None:
        pytest.skip("no results/main_job_realisations.json")
    default = load(ROOT / "workflows" / "config" / "default.yaml")
    assert realisations.setting(default) == rec["setting"]
    assert realisations.floor_for(default, 1)["floor_A_per_ps"] is not None
    water = dict(default, md=dict(default["md"], solvent="tip3p", salt_mM=150))
    assert realisations.setting(water) != rec["setting"]
    assert realisations.floor_for(water, 1)["floor_A_per_ps"] is None
