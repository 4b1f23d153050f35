"""mdbridge/rod/scene.py, the one scene editor: what write_scene writes is read back as
exactly the dict it was given, by Python's own TOML parser (tomllib) and by rodcore
(rodcore.resolve of the file equals that of the dict); what is no scene value is refused
with the key named."""
import math
import tomllib

import pytest

from dna_models.errors import InputError
from mdbridge.rod.scene import new_scene, resolve_scene, scene_toml, set_output, straight_rod, write_scene

SCENE = {
    "rod": {"length": 14.000000000000002, "points": 21, "Gamma0": [0.0, 0.0, 1.0],
            "Omega0": [0.0, 0.0, 0.8975979010256551]},
    "material": {"K": [[1.0, 0.0, 0.0, 0.0, 0.1, 0.0], [0.0, 1.1, 0.0, 0.0, 0.0, 0.0],
                       [0.0, 0.0, 1.19, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0, 1.2, 0.0, 0.0],
                       [0.1, 0.0, 0.0, 0.0, 1.21, 0.0], [0.0, 0.0, 0.0, 0.0, 0.0, 2.0]],
                 "rho": 1.05},
    "initial": {"kind": "dna_planar", "bp": 21, "turns": 2, "A_v_A_per_ps": 1.0 / 3.0},
    "solver": {"space": "spectral", "time": "dop853", "rtol": 1e-10, "atol": 5e-11},
    "output": {"t_end": 637.2300305237051, "frames": 6, "fields": ["internal", "centerline", "directors"]},
    "checks": {"max_energy_drift": math.inf, "stop_on_fold": True},
}


def test_written_scene_reads_back_exactly(tmp_path):
    odd = dict(SCENE, notes={"path": 'a "quoted" C:\\dir\\é', "tiny": 5e-324, "big": 1.7976931348623157e308,
                             "neg": -0.0, "minus_inf": -math.inf})
    path = write_scene(tmp_path / "sub" / "scene.toml", odd, "made by a test\nof two lines")
    text = path.read_text()
    assert text.startswith("# made by a test\n# of two lines\n[rod]\n")
    back = tomllib.loads(text)
    assert back == odd
    # floats bit for bit (== would also accept -0.0 for 0.0)
    assert math.copysign(1.0, back["notes"]["neg"]) == -1.0
    assert back["initial"]["A_v_A_per_ps"].hex() == (1.0 / 3.0).hex()


def test_rodcore_reads_the_written_file_as_the_dict(tmp_path):
    dna = {k: v for k, v in SCENE.items() if k not in ("rod", "material")}   # the kind sets the rod
    path = write_scene(tmp_path / "scene.toml", dna)
    assert resolve_scene(path) == resolve_scene(dna)
    assert resolve_scene(path)["initial"]["A_v_A_per_ps"].hex() == (1.0 / 3.0).hex()


def test_made_and_edited_scene(tmp_path):
    sc = new_scene(straight_rod(2.0, 16), {"kind": "rest"}, t_end=1.0, frames=3, rtol=1e-9)
    assert sc["solver"] == {"space": "spectral", "time": "dop853", "rtol": 1e-9, "atol": 1e-9}
    set_output(sc, t_end=2.0, frames=5, fields=("internal",))
    assert sc["output"] == {"t_end": 2.0, "frames": 5, "fields": ["internal"]}
    assert tomllib.loads(scene_toml(sc)) == sc


@pytest.mark.parametrize("bad, key", [({"rod": {"length": {"nested": 1.0}}}, "rod.length"),
                                      ({"rod": {"points": None}}, "rod.points"),
                                      ({"length": 1.0}, "'length'")])
def test_what_is_no_scene_value_is_refused_naming_the_key(tmp_path, bad, key):
    with pytest.raises(InputError, match=key.replace(".", r"\.")):
        write_scene(tmp_path / "bad.toml", bad)
    assert not (tmp_path / "bad.toml").exists()
