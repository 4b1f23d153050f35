"""A command's output is valid input to the next: each command of the toolkit run on
what another of its commands wrote (build-dna, dna-rod, rodsim, build-md,
rod-to-atoms, helical-params), and either right or refused with exit 2.

Truths: the rod scene's own numbers (a uniform rod's rise and twist, its period),
MDAnalysis's reading of the files, the builder's frames re-analysed with the
3DNA-exact geometry (mdbridge.geometry, checked against 3DNA in test_geometry_3dna.py)."""
import csv
import io

import numpy as np
import pytest

from dnarod.cli import main

ROOT = __import__("pathlib").Path(__file__).resolve().parents[2]
SCENES = ROOT / "workflows" / "scenes"


def dnarod(argv, capsys):
    code = main([str(a) for a in argv])
    out = capsys.readouterr()
    return code, out.out, out.err


def steps_csv(text: str) -> np.ndarray:
    rows = list(csv.DictReader(io.StringIO(text)))
    return np.array([[float(r[k]) for k in ("shift", "slide", "rise", "tilt", "roll", "twist")]
                     for r in rows])


def test_build_dna_periodic_box_is_read_by_helical_params(tmp_path, capsys):
    """build-dna --periodic writes the box as CRYST1: MDAnalysis reads the period, and
    helical-params --periodic gives the closing step the rise of every other step (the
    uniform dna21 scene: 3.38 A, 360 x 2 / 21 deg). Without the box the closing step is
    refused, naming how to give it; --box gives it back."""
    import MDAnalysis as mda
    pdb = tmp_path / "dna21.pdb"
    code, out, _ = dnarod(["build-dna", "--scene", SCENES / "dna21.toml", "--periodic", "--seed", "1",
                           "-o", pdb], capsys)
    assert code == 0, out
    period = 21 * 3.38
    box = mda.Universe(str(pdb)).dimensions
    assert box is not None and box[1] == pytest.approx(period, abs=1e-3)
    assert min(box[0], box[2]) > 40.0      # the non-periodic edges: twice the extent + 10 A
    code, out, err = dnarod(["helical-params", pdb, "--periodic"], capsys)
    assert code == 0, err
    P = steps_csv(out)
    assert P.shape == (21, 6)
    np.testing.assert_allclose(P[:, 2], 3.38, atol=2e-3)
    np.testing.assert_allclose(P[:, 5], 360.0 * 2 / 21, atol=0.02)

    # control: the same file without its CRYST1 record
    bare = tmp_path / "bare.pdb"
    bare.write_text("".join(ln for ln in pdb.read_text().splitlines(True) if not ln.startswith("CRYST1")))
    code, out, err = dnarod(["helical-params", bare, "--periodic"], capsys)
    assert code == 2 and out == ""
    assert "closing step (base pair 21 -> 1) spans" in err and "CRYST1" in err and "--box" in err
    code, out, err = dnarod(["helical-params", bare, "--periodic", "--no-pbc"], capsys)
    assert code == 2 and "--no-pbc" in err
    code, out, err = dnarod(["helical-params", bare, "--periodic", "--box", 60, period, 60], capsys)
    assert code == 0, err
    np.testing.assert_allclose(steps_csv(out), P, atol=2e-4)
    # a linear duplex needs no box (the closing step is not asked for)
    code, out, err = dnarod(["helical-params", bare], capsys)
    assert code == 0 and steps_csv(out).shape == (20, 6)
