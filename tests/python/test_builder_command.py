"""`dnarod build-dna` end to end: every frame source, the printed report,
the PDB it writes, and exit code 2 with a clear message on bad input."""
import numpy as np
import pytest

from mdbridge.md.builder import read_pdb
from mdbridge.md.builder.params import read_3dna_par
from dnarod.cli import main


def run(argv, capsys):
    code = main(["build-dna", *argv])
    out = capsys.readouterr()
    return code, out.out, out.err


def test_ideal(tmp_path, capsys):
    code, out, _ = run(["--ideal", "--sequence", "CGCGAATTCGCG", "-o", str(tmp_path / "i.pdb")],
                       capsys)
    assert code == 0
    assert "verdict: OK" in out and "492 atoms" in out
    pdb = read_pdb(tmp_path / "i.pdb")
    assert len(pdb["names"]) == 492


def test_ideal_periodic_158(tmp_path, capsys):
    seq = "ACGT" * 39 + "GC"
    code, out, _ = run(["--ideal", "--sequence", seq, "--twist", str(360 * 15 / 158),
                        "--periodic", "-o", str(tmp_path / "p.pdb")], capsys)
    assert code == 0
    assert "junction through the box" in out and "verdict: OK" in out
    assert "534.04" in out  # box 158 x 3.38 A


def test_par_file_matches_3dna(refdata, tmp_path, capsys):
    d = refdata / "rebuild_3dna_bdna" / "355d_with_bp_params"
    code, out, _ = run(["--params", str(d / "in_step.par"), "-o", str(tmp_path / "r.pdb")], capsys)
    assert code == 0
    assert "verdict: PROBLEM" in out  # 3DNA itself reports broken O3'-P links here
    ours, ref = read_pdb(tmp_path / "r.pdb"), read_pdb(d / "355d_rebuilt_bdna.pdb")
    assert np.abs(ours["coords"] - ref["coords"]).max() < 1.5e-3


def test_csv_steps(refdata, tmp_path, capsys):
    par = read_3dna_par(refdata / "rebuild_3dna_bdna" / "355d_steps_zero_bp.par")
    csv = tmp_path / "steps.csv"
    csv.write_text("step,shift,slide,rise,tilt,roll,twist\n" + "".join(
        f"{k + 1}," + ",".join(f"{v:.3f}" for v in row) + "\n" for k, row in enumerate(par.steps)))
    code, out, _ = run(["--params", str(csv), "--sequence", par.sequence,
                        "-o", str(tmp_path / "c.pdb")], capsys)
    assert code == 0
    ref = read_pdb(refdata / "rebuild_3dna_bdna" / "rebuilt_355d_steps_zero_bp.pdb")
    assert np.abs(read_pdb(tmp_path / "c.pdb")["coords"] - ref["coords"]).max() < 1.5e-3
    # the helical-params format (frame,step,...) with two frames needs --frame
    csv2 = tmp_path / "hp.csv"
    lines = csv.read_text().splitlines()
    csv2.write_text("frame," + lines[0] + "\n" + "".join(f"{f},{ln}\n" for f in (0, 1)
                                                           for ln in lines[1:]))
    code, _, err = run(["--params", str(csv2), "--sequence", par.sequence,
                        "-o", str(tmp_path / "d.pdb")], capsys)
    assert code == 2 and "--frame" in err
    code, _, _ = run(["--params", str(csv2), "--frame", "1", "--sequence", par.sequence,
                      "-o", str(tmp_path / "d.pdb")], capsys)
    assert code == 0


@pytest.mark.parametrize("argv,match", [
    (["--ideal", "--sequence", "ACGU"], "letter 'U' at position 4"),
    (["--ideal"], "--sequence is required"),
    (["--params", "/nonexistent/steps.csv", "--sequence", "AC"], "/nonexistent/steps.csv"),
])
def test_errors(tmp_path, capsys, argv, match):
    code, _, err = run([*argv, "-o", str(tmp_path / "x.pdb")], capsys)
    assert code == 2
    assert match in err


def test_wrong_step_count(tmp_path, capsys):
    csv = tmp_path / "s.csv"
    csv.write_text("step,shift,slide,rise,tilt,roll,twist\n1,0,0,3.38,0,0,36\n")
    code, _, err = run(["--params", str(csv), "--sequence", "ACGT", "-o", str(tmp_path / "x.pdb")],
                       capsys)
    assert code == 2 and "1 steps for a 4-bp sequence; need 3" in err


def test_round_trip_with_helical_params(refdata, tmp_path, capsys):
    """build-dna -> PDB -> `dnarod helical-params` (3DNA analysis) -> CSV ->
    build-dna: the same atoms again, up to the PDB's 3-decimal rounding
    propagated through the analysis (measured max 2e-3 A)."""
    par = refdata / "rebuild_3dna_bdna" / "355d_steps_zero_bp.par"
    a, b, csv = tmp_path / "a.pdb", tmp_path / "b.pdb", tmp_path / "a.csv"
    assert run(["--params", str(par), "-o", str(a)], capsys)[0] == 0
    assert main(["helical-params", str(a), "--csv", str(csv)]) == 0
    capsys.readouterr()
    assert run(["--params", str(csv), "--sequence", "CGCGAATTCGCG", "-o", str(b)], capsys)[0] == 0
    assert np.abs(read_pdb(a)["coords"] - read_pdb(b)["coords"]).max() < 5e-3
