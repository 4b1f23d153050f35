"""`dnarod dna-rod`: the files it writes, checked on their own (format, shapes,
positive definiteness, agreement with the step -> rod map), and its inputs."""
import json
import tomllib

import h5py
import numpy as np
import pytest

from mdbridge.rod.material.parameter_sets import paper_steps
from mdbridge.rod.material.stepfile import read_steps
from mdbridge.rod.material.steps_to_rod import grid_material, rod_material
from dnarod.cli import main


def test_dna_rod_from_md_folder(tmp_path, capsys):
    seq = "ACGTTGCAAGTCCGATGCATG"          # 21 bp, 2 turns at the paper's twist
    md = tmp_path / "md"
    md.mkdir()
    (md / "build.json").write_text(json.dumps({"sequence": seq, "n_bp": 21}))
    out = tmp_path / "rod"
    assert main(["dna-rod", "--sequence-from-md", str(md), "--params", "paper", "--points-per-bp", "2",
                 "--kick", "1.0", "-o", str(out)]) == 0
    sm = read_steps(out / "steps.h5")
    assert sm.sequence == seq and sm.closed
    g = grid_material(rod_material(paper_steps(seq)), 42)
    with h5py.File(out / "material.h5") as f:
        assert f.attrs["format"] == "dnarod-material/1"
        assert f["K"].shape == (42, 6, 6) and f["I"].shape == (42, 3, 3) and f["rho"].shape == (42,)
        K = f["K"][()]
        assert np.allclose(K, np.swapaxes(K, 1, 2), atol=0) and np.linalg.eigvalsh(K)[:, 0].min() > 0
        assert np.allclose(K, np.diag([1, 1, 1.19, 1.21, 1.21, 1.21 * 1.67]), atol=1e-9)
        assert np.allclose(f["Omega0"][()], g["Omega0"], atol=1e-13)
        assert np.allclose(f["rho"][()], 1.0) and np.allclose(f["I"][()], np.diag([1.0, 1, 2]))
    scene = tomllib.loads((out / "scene.toml").read_text())
    assert scene["rod"]["points"] == 42 and scene["material"]["material_file"] == "material.h5"
    assert scene["initial"] == {"kind": "file", "path": "rest.h5"}
    assert scene["rod"]["length"] == pytest.approx(21 * 3.38 / 5.0, rel=1e-3)
    with h5py.File(out / "rest.h5") as f:
        assert np.allclose(f["s"][()], g["s"])
        # uniform rod: the rest state is the 2-turn twist, kicked transversally
        assert np.allclose(f["fields/Omega"][:, 2], 4 * np.pi / scene["rod"]["length"], atol=1e-9)
        gam = f["fields/gamma"][()]
        assert np.max(np.abs(gam)) == pytest.approx(1.0 / 5.31, rel=2e-2)
        assert np.max(np.abs(f["fields/omega"][()])) == 0
    info = json.loads((out / "rest.json").read_text())
    assert info["statics_residual"] < 1e-10 and info["n_bp"] == 21
    assert info["torque_pN_nm"] > 0       # 1.994 turns wound up to 2


def test_dna_rod_bad_inputs(tmp_path, capsys):
    assert main(["dna-rod", "--sequence", "ACGU", "-o", str(tmp_path)]) == 2
    assert "letter 'U' at position 4" in capsys.readouterr().err
    assert main(["dna-rod", "--sequence-from-md", str(tmp_path), "-o", str(tmp_path / "x")]) == 2
    assert "no build.json" in capsys.readouterr().err
    assert main(["dna-rod", "--sequence", "ACGTACGTAC", "--params", "olsen", "-o", str(tmp_path / "y")]) == 2
    assert "not 'paper', 'olson1998' or an existing per-step file" in capsys.readouterr().err


def test_dna_rod_coarse_segments(tmp_path, capsys):
    """--bp-per-point 10: 100 bp on 10 grid points, the material of mdbridge/rod/material/coarse.py, one
    whole turn dropped per segment and said so; a closed rest state of the coarse rod."""
    from mdbridge.rod.material.coarse import coarse_material
    from mdbridge.rod.material.parameter_sets import step_material
    seq = "ACGTTGCAAGTCCGATGCATGGATCCAGTCAGTTACGATCGGCTAGCATG" * 2       # 100 bp
    out = tmp_path / "rod"
    assert main(["dna-rod", "--sequence", seq, "--params", "olson1998", "--bp-per-point", "10",
                 "-o", str(out)]) == 0
    cm, turns = coarse_material(rod_material(step_material(seq, "olson1998")), 10)
    info = json.loads((out / "rest.json").read_text())
    assert info["points"] == 10 and info["bp_per_point"] == 10 and info["turns_dropped"] == 10 == turns.sum()
    assert info["n_bp"] == 100 and info["closure_rotation_rad"] < 1e-9
    with h5py.File(out / "material.h5") as f:
        assert f["K"].shape == (10, 6, 6) and f.attrs["bp_per_point"] == 10
        assert np.linalg.eigvalsh(f["K"][()])[:, 0].min() > 0
    assert tomllib.loads((out / "scene.toml").read_text())["rod"]["points"] == 10
    assert main(["dna-rod", "--sequence", seq, "--bp-per-point", "30", "-o", str(tmp_path / "x")]) == 2
    assert "--bp-per-point 30: must divide the 100 bp" in capsys.readouterr().err
    assert main(["dna-rod", "--sequence", seq, "--bp-per-point", "10", "--points-per-bp", "2",
                 "-o", str(tmp_path / "y")]) == 2
    assert "give one" in capsys.readouterr().err
