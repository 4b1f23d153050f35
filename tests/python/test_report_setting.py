"""The report names the setting of every MD number from the run's own build.json
(workflows/report/setting.py), not from the configuration: small build.json fixtures of each
kind, written with the keys and values build-md writes (mdbridge/md/gromacs/inputs.py: electrostatics,
pair_hold, solvent, md_settings, equilibration), and the report step on a configuration that
says vacuum while a build says water. No MD runs."""
import json

import pytest

from dnarod.report import report, setting

WATER = {"model": "tip3p", "salt_mM": 150.0, "cation": "NA", "anion": "CL",
         "ions": {"n_cation": 57, "n_anion": 15}}


def build(electrostatics="paper", pair_hold=None, solvent=None, tension=None, axial_pressure=None):
    b = {"forcefield": "charmm27", "electrostatics": electrostatics, "pair_hold": pair_hold, "solvent": solvent,
         "md_settings": {"axial_tension_pN": tension, "thermostat": tension is not None},
         "equilibration": None if axial_pressure is None else {"ps": 20.0, "axial_pressure": axial_pressure}}
    return b


@pytest.mark.parametrize("b, words", [
    ({"forcefield": "charmm27", "electrostatics": "paper"}, "full-charge vacuum"),   # a build.json before water
    (build(), "full-charge vacuum"),
    (build(electrostatics="neutral-phosphates"), "neutral-phosphate vacuum"),
    (build(pair_hold={"k_kJ_mol_nm2": 1000.0}), "held pairs, full-charge vacuum"),
    (build(axial_pressure={"zero_tension_length_nm": 53.1}), "full-charge vacuum, box at zero tension"),
    (build(solvent=WATER, tension=10.0), "TIP3P water, 150 mM NaCl, T = 10 pN"),
    (build(solvent=WATER), "TIP3P water, 150 mM NaCl, fixed box"),
    (build(solvent=dict(WATER, salt_mM=0.0), tension=0.0), "TIP3P water, no salt (Na counterions), T = 0 pN"),
    (build(solvent=WATER, tension=20.0, pair_hold={"k_kJ_mol_nm2": 1000.0}),
     "TIP3P water, 150 mM NaCl, T = 20 pN, held pairs"),
])
def test_label_of_each_kind_of_build(b, words):
    assert setting.label(b) == words


def _folder(out, name, b):
    d = out / "md" / name
    d.mkdir(parents=True)
    (d / "build.json").write_text(json.dumps(b))


def _report(tmp_path, cfg):
    (tmp_path / "cfg.yaml").write_text(json.dumps(cfg))
    assert report.main([str(tmp_path / "cfg.yaml"), str(tmp_path)]) == 0
    page = (tmp_path / "report" / "index.html").read_text()
    return json.loads((tmp_path / "results.json").read_text()), page


CFG = {"scene": "workflows/scenes/dna158.toml", "A_v_A_per_ps": [0], "seeds": [1, 2], "headline_A_v_A_per_ps": 0,
       "rod": {"run_ps": 10, "output_every_ps": 1}, "md": {"run_ps": 10, "solvent": "vacuum"},
       "analysis": {"waves": False}, "sweep": {"A_v_A_per_ps": []}}


def test_report_names_the_builds_setting_not_the_configs(tmp_path):
    """The configuration says vacuum, the builds were made in water: the page and results.json
    say water, at the build's tension."""
    for s in (1, 2):
        _folder(tmp_path, f"Av0_seed{s}", build(solvent=WATER, tension=10.0))
    res, page = _report(tmp_path, CFG)
    assert res["md_setting"] == {f"md/Av0_seed{s}": {"setting": "TIP3P water, 150 mM NaCl, T = 10 pN",
                                                      "forcefield": "charmm27"} for s in (1, 2)}
    para = page[page.index('id="md-setting"'):page.index("</p>", page.index('id="md-setting"'))]
    assert "one setting" in para and "TIP3P water, 150 mM NaCl, T = 10 pN" in para and "(charmm27)" in para
    assert "vacuum" not in para
    assert page.index('id="verdict"') < page.index('id="md-setting"')


def test_report_names_each_setting_when_runs_differ(tmp_path):
    """Control of the single sentence: two builds of different settings are each named with
    their runs, and no sentence claims one setting."""
    _folder(tmp_path, "Av0_seed1", build())
    _folder(tmp_path, "Av0_seed2", build(pair_hold={"k_kJ_mol_nm2": 1000.0}))
    _folder(tmp_path, "Av5_seed1", build(solvent=WATER))            # not a run of this configuration
    res, page = _report(tmp_path, CFG)
    assert set(res["md_setting"]) == {"md/Av0_seed1", "md/Av0_seed2"}
    assert {r["setting"] for r in res["md_setting"].values()} == {"full-charge vacuum",
                                                                   "held pairs, full-charge vacuum"}
    section = page[page.index('id="md-setting"'):page.index("</ul>", page.index('id="md-setting"'))]
    assert "one setting" not in section
    assert "<b>full-charge vacuum</b> (charmm27): md/Av0_seed1" in section
    assert "<b>held pairs, full-charge vacuum</b> (charmm27): md/Av0_seed2" in section
    # a run's row in the table of every run carries its own
    assert setting.of_run(res["md_setting"], {"kind": "md", "A_v_A_per_ps": 0.0, "seed": 2}) == \
        "held pairs, full-charge vacuum"
    assert setting.of_run(res["md_setting"], {"kind": "md", "A_v_A_per_ps": 1.0, "seed": 2}) == ""


def test_stretched_boxes_of_the_dispersion_are_named(tmp_path):
    _folder(tmp_path, "Av0_seed1", build())
    _folder(tmp_path, "Av0_seed1_box1.015", build())
    cfg = dict(CFG, seeds=[1], dispersion={"enabled": True, "box_scales": [1.015]})
    assert set(setting.collect(cfg, tmp_path)) == {"md/Av0_seed1", "md/Av0_seed1_box1.015"}


def test_no_md_no_setting(tmp_path):
    res, page = _report(tmp_path, dict(CFG, md={"run_ps": 10, "enabled": False}))
    assert res["md_setting"] == {} and 'id="md-setting"' not in page
