"""mdbridge.rod.run: the one Python path to the rod solver and its output file.

Truths: rodsim's own HDF5 writer (C++) against the module's in-memory result of the
same scene; rodcore.resolve's filled-in scene against the kind defaults Python reads;
the error classes a caller relies on; and the workflow's rod.h5 against a fresh run of
the MD-length scene (build-md --rod must hand the builder the same t = 0 state)."""
import json
import math
import subprocess

import numpy as np
import pytest

from dna_models.errors import InputError, NumericalError
from dna_models.units import Units
from mdbridge.jsonio import dumps, jsonable, write_json
from mdbridge.rod.run import RodRun, run_scene
from mdbridge.rod.scene import load_scene, resolve_scene, scene_bp_turns, scene_n_bp

DNA21 = '[initial]\nkind = "dna_planar"\nbp = 21\nturns = 2\nA_v_A_per_ps = 1.0\n'


def _rodsim(rodsim, scene, out, *sets):
    cmd = [str(rodsim), "run", str(scene), "-o", str(out), "--quiet"]
    for s in sets:
        cmd += ["--set", s]
    subprocess.run(cmd, check=True, capture_output=True)
    return out


def test_module_result_equals_rodsim_file_and_round_trips(rodsim, tmp_path):
    scene = tmp_path / "dna21.toml"
    scene.write_text(DNA21 + '[output]\nt_end = 0.5\nframes = 3\n'
                     'fields = ["internal", "centerline", "directors", "energy", "energy_parts"]\n')
    mem = run_scene(scene)                                     # rodcore.run, in memory
    disk = RodRun.read(_rodsim(rodsim, scene, tmp_path / "r.h5"))  # rodsim's C++ writer
    for name in ("time", "s", "energy", "centerline", "directors"):
        np.testing.assert_array_equal(getattr(mem, name), getattr(disk, name), err_msg=name)
    assert set(disk.fields) == {"gamma", "omega", "Gamma", "Omega"} == set(mem.fields)
    for k in disk.fields:
        np.testing.assert_array_equal(mem.fields[k], disk.fields[k], err_msg=k)
    assert set(disk.energy_parts) == set(mem.energy_parts) and len(disk.energy_parts) == 6
    assert disk.complete and disk.ell_A == pytest.approx(Units.paper().ell_A, rel=1e-15)
    assert disk.attrs["initial.bp"] == 21 and disk.summary["steps"] >= 1
    # the module's result carries the same resolved scene values as the file's attributes
    for key in ("rod.length", "rod.points", "initial.bp", "initial.turns", "material.D", "output.frames"):
        np.testing.assert_array_equal(mem.attrs[key], disk.attrs[key], err_msg=key)
    assert mem.attrs["ell_A"] == disk.attrs["ell_A"]
    mem.write(tmp_path / "mem.h5")      # a module run saved is a rod output file like rodsim's
    again = RodRun.read(tmp_path / "mem.h5")
    np.testing.assert_array_equal(again.directors, disk.directors)
    assert again.attrs["initial.bp"] == 21 and again.complete
    # write -> read keeps every array, attribute and summary entry
    disk.write(tmp_path / "copy.h5")
    back = RodRun.read(tmp_path / "copy.h5")
    for name in ("time", "s", "energy", "centerline", "directors"):
        np.testing.assert_array_equal(getattr(back, name), getattr(disk, name))
    for k in disk.fields:
        np.testing.assert_array_equal(back.fields[k], disk.fields[k])
    assert back.summary == disk.summary
    assert back.attrs["initial.bp"] == 21 and back.attrs["scene"] == disk.attrs["scene"]
    # until(): the frames up to a time, nothing else changed
    half = disk.until(disk.time[1])
    assert len(half.time) == 2 and half.fields["Gamma"].shape[0] == 2 and half.s is disk.s


def test_missing_datasets_are_named(tmp_path):
    import h5py
    with h5py.File(tmp_path / "x.h5", "w") as f:
        f["time"] = [0.0, 1.0, 2.0]
        f["s"] = np.arange(8) / 8
    run = RodRun.read(tmp_path / "x.h5")
    with pytest.raises(InputError, match=r"x\.h5: dataset 'centerline' missing, dataset 'directors' "
                                         r"missing"):
        run.bp_frames(4)
    with pytest.raises(InputError, match="dataset 'fields/Gamma' missing"):
        run.require("fields/Gamma")
    (tmp_path / "not.h5").write_text("text")
    with pytest.raises(InputError, match=r"not\.h5: cannot read as HDF5"):
        RodRun.read(tmp_path / "not.h5")


def test_error_mapping(tmp_path):
    with pytest.raises(InputError, match=r"^my scene: .*rtoll"):
        run_scene({"rod": {"length": 1.0, "points": 8}, "solver": {"rtoll": 1e-8}}, source="my scene")
    # an energy-drift stop is a NumericalError, which is also a FloatingPointError
    # (what mdbridge.analysis.modulus catches at the ends of its bracket)
    sc = {"rod": {"length": 2 * math.pi, "points": 16},
          "initial": {"kind": "twisted_wave", "A": 0.5},
          "solver": {"time": "rk4", "dt": 0.5, "space": "fd4"},
          "output": {"t_end": 50.0, "frames": 2, "fields": ["energy"]},
          "checks": {"max_energy_drift": 1e-12}}
    with pytest.raises(NumericalError) as e:
        run_scene(sc, source="drift")
    assert isinstance(e.value, FloatingPointError) and str(e.value).startswith("drift: ")
    with pytest.raises(InputError, match="scene file not found"):
        load_scene(tmp_path / "none.toml")
    (tmp_path / "bad.toml").write_text("[rod\n")
    with pytest.raises(InputError, match=r"bad\.toml: not valid TOML"):
        load_scene(tmp_path / "bad.toml")


def test_base_pairs_of_a_scene_come_from_rodcore():
    # Given: read from the scene. Left out: rodcore's kind default, which must be what
    # rodcore.resolve fills in (two routes through the C++ side).
    assert scene_bp_turns({"initial": {"kind": "dna_planar", "bp": 21, "turns": 2}}) == (21, 2)
    bare = {"initial": {"kind": "dna_planar"}}
    ini = resolve_scene(bare)["initial"]
    assert scene_bp_turns(bare) == (int(ini["bp"]), int(ini["turns"])) == (158, 15)
    assert scene_n_bp({"initial": {"kind": "dna_planar", "turns": 2}}) == 158
    with pytest.raises(InputError, match=r"s\.toml: \[initial\] bp = 20\.5: need an integer >= 4"):
        scene_bp_turns({"initial": {"kind": "dna_planar", "bp": 20.5}}, "s.toml")
    with pytest.raises(InputError, match=r"turns = 0: need an integer >= 1"):
        scene_bp_turns({"initial": {"kind": "dna_planar", "turns": 0}})
    with pytest.raises(InputError, match=r"kind = 'twisted_wave'.*dna_planar"):
        scene_n_bp({"initial": {"kind": "twisted_wave"}})


def test_build_md_takes_the_workflow_rod_run(rodsim, tmp_path):
    """The frames of the workflow's rod.h5 up to the MD length give the builder the same
    t = 0 base pairs and velocities, and nearly the same box, as build-md's own run."""
    from mdbridge.md.gromacs.rod import md_scene, rod_for_md, rod_initial_from_run
    u = Units.paper()
    scene = tmp_path / "dna21.toml"
    scene.write_text(DNA21.replace("1.0", "5.0"))
    # the workflow's run: 8 ps, a frame every 0.2 ps (workflows/config/tiny.yaml's spacing)
    h5 = _rodsim(rodsim, scene, tmp_path / "rod.h5", f"output.t_end={u.time_to_rod(8.0)!r}",
                 "output.frames=41", 'output.fields=["internal","centerline","directors"]')
    resolved = resolve_scene(scene)
    given = rod_for_md(RodRun.read(h5), md_ps=4.0, scene=resolved, units=u)
    assert u.time_to_ps(given.time[-1]) == pytest.approx(4.0, rel=1e-9) and len(given.time) == 21
    own = run_scene(md_scene(load_scene(scene), md_ps=4.0))
    rod_a, c_a = rod_initial_from_run(given, 21, u)
    rod_b, c_b = rod_initial_from_run(own, 21, u)
    np.testing.assert_allclose(rod_a.origins_A, rod_b.origins_A, atol=1e-12)
    np.testing.assert_allclose(rod_a.R, rod_b.R, atol=1e-12)
    np.testing.assert_allclose(rod_a.gamma_lab_A_ps, rod_b.gamma_lab_A_ps, atol=1e-12)
    np.testing.assert_allclose(rod_a.omega_lab_rad_ps, rod_b.omega_lab_rad_ps, atol=1e-12)
    assert rod_a.closure_length_A == pytest.approx(rod_b.closure_length_A, rel=1e-12)
    # the same motion sampled at other times: the box-sizing extent agrees closely
    span = lambda c: np.ptp(c.reshape(-1, 3), axis=0)  # noqa: E731
    np.testing.assert_allclose(span(c_a), span(c_b), rtol=0.02, atol=0.05)
    with pytest.raises(InputError, match=r"covers 8 ps, the MD 10 ps"):
        rod_for_md(RodRun.read(h5), md_ps=10.0, scene=resolved, units=u)
    # a run of another scene (other bp, other kick) is refused, naming what differs
    other = resolve_scene({"initial": {"kind": "dna_planar", "bp": 22, "turns": 2, "A_v_A_per_ps": 5.0}})
    with pytest.raises(InputError, match=r"rod\.h5: not a run of this scene: rod\.length = .*"
                                         r"initial\.bp = 21\.0 \(scene: 22\.0\)"):
        rod_for_md(RodRun.read(h5), md_ps=4.0, scene=other, units=u)
    kick = resolve_scene({"initial": {"kind": "dna_planar", "bp": 21, "turns": 2, "A_v_A_per_ps": 1.0}})
    with pytest.raises(InputError, match=r"initial\.A_v_A_per_ps = 5\.0 \(scene: 1\.0\)"):
        rod_for_md(RodRun.read(h5), md_ps=4.0, scene=kick, units=u)


def test_results_json_is_strict_json(tmp_path):
    data = {"speed": np.float64("nan"), "err": float("inf"), "n": np.int64(3), "ok": np.bool_(True),
            "arr": np.array([1.0, np.nan, -np.inf]), "nested": {1: (np.float32(0.5),)}}
    # the control: Python's default writes tokens that strict readers reject
    assert "NaN" in json.dumps({"x": float("nan")})
    text = dumps(data)
    assert "NaN" not in text and "Infinity" not in text
    back = json.loads(text, parse_constant=lambda c: pytest.fail(f"non-JSON constant {c}"))
    assert back == {"speed": None, "err": None, "n": 3, "ok": True, "arr": [1.0, None, None],
                    "nested": {"1": [0.5]}}
    assert jsonable(np.float64(2.5)) == 2.5 and type(jsonable(np.float64(2.5))) is float
    p = write_json(tmp_path / "r.json", data)
    assert json.loads(p.read_text()) == back


def test_report_writes_strict_results_json(tmp_path):
    """The report's results.json goes through the same sanitiser: a run with no MD
    (NaN speeds) must give null, not NaN."""
    from dnarod.report import report
    cfg = {"A_v_A_per_ps": [1.0], "seeds": [1], "headline_A_v_A_per_ps": 1.0,
           "rod": {"run_ps": 10.0}, "md": {"enabled": False, "run_ps": 10.0}}
    res = report.results_json(cfg, {"rod": {}, "md": {}, "sweep": {}, "modulus": None})
    write_json(tmp_path / "results.json", res)
    back = json.loads((tmp_path / "results.json").read_text(),
                      parse_constant=lambda c: pytest.fail(f"non-JSON constant {c}"))
    assert back["rod_wave_speed_A_per_ps"] is None and back["md_planarity"] is None
