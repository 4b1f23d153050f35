"""No accepted bad input, scene side: regressions found by the
scene-reader fuzz target (fuzz/scene_reader_fuzz.cpp), checked through
rodsim as a user meets them: a scene is either accepted (exit 0) or refused
with exit 2 and a message naming the file and key -- never exit 1."""
import subprocess

import pytest


@pytest.mark.parametrize("key,value", [("solver.dt", "1e-320"), ("solver.rtol", "4.9e-324"),
                                       ("rod.length", "1e-310"), ("output.t_end", "2e-315")])
def test_subnormal_numbers_are_handled(rodsim, tmp_path, key, value):
    # std::stod threw out_of_range on subnormals inside the reader's number
    # formatting: rodsim died with "error: stod" (exit 1).
    section, name = key.split(".")
    scene = tmp_path / "sub.toml"
    body = {"rod": {"length": "1.0", "points": "16"}}
    body.setdefault(section, {})[name] = value
    scene.write_text("".join(f"[{s}]\n" + "".join(f"{k} = {v}\n" for k, v in b.items())
                             for s, b in body.items()))
    p = subprocess.run([str(rodsim), "check", str(scene)], capture_output=True, text=True, timeout=60)
    assert p.returncode in (0, 2), p.stderr
    assert "stod" not in p.stderr
    if p.returncode == 2:
        assert str(scene) in p.stderr and ("solver." in p.stderr or "rod." in p.stderr or "output." in p.stderr)
