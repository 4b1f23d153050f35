"""The command line's manners: a closed pipe ends quietly, an empty file is called empty,
bad arguments are refused before any work and leave no folder behind, one spelling of
the output option (the old ones still accepted), --version as rodsim's, and compare's
help lists every shipped configuration."""
import re
import subprocess
import time
from pathlib import Path

import pytest

from dnarod.cli import build_parser, main

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "workflows" / "scenes"


def test_closed_pipe_ends_quietly(dnarod, tmp_path):
    """`dnarod helical-params X | head -3` on an output far larger than a pipe's buffer:
    exit 0, no traceback. Control: the same output read whole is the full table."""
    assert main(["build-dna", "--ideal", "--sequence", "ACGT" * 5, "-o", str(tmp_path / "one.pdb")]) == 0
    atoms = [ln for ln in (tmp_path / "one.pdb").read_text().splitlines() if ln.startswith(("ATOM", "TER"))]
    models = "".join(f"MODEL     {k + 1:4d}\n" + "\n".join(atoms) + "\nENDMDL\n" for k in range(400))
    big = tmp_path / "big.pdb"
    big.write_text(models + "END\n")
    whole = subprocess.run([str(dnarod), "helical-params", str(big)], capture_output=True, text=True)
    assert whole.returncode == 0 and len(whole.stdout) > 4 * 65536 and len(whole.stdout.splitlines()) == 1 + 400 * 19
    p = subprocess.Popen([str(dnarod), "helical-params", str(big)], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         text=True)
    assert p.stdout is not None
    head = [p.stdout.readline() for _ in range(3)]
    p.stdout.close()
    err = p.stderr.read() if p.stderr else ""
    assert p.wait(timeout=120) == 0, err
    assert head[0].startswith("frame,step") and "Traceback" not in err and "BrokenPipe" not in err


@pytest.mark.parametrize("name", ["empty.pdb", "empty.gro"])
def test_empty_file_is_called_empty(name, tmp_path, capsys):
    (tmp_path / name).write_text("")
    assert main(["helical-params", str(tmp_path / name)]) == 2
    assert f"{name}: the file is empty" in capsys.readouterr().err


def test_bad_arguments_refused_at_once_without_a_folder(tmp_path, capsys):
    out = tmp_path / "eq0"
    t0 = time.monotonic()
    assert main(["build-md", str(SCENES / "dna21.toml"), "--equilibrate-ps", "0", "-o", str(out)]) == 2
    assert time.monotonic() - t0 < 5.0          # before the rod run and pdb2gmx
    err = capsys.readouterr().err
    assert "--equilibrate-ps 0" in err and "--protocol paper" in err
    assert not out.exists()
    assert main(["dna-rod", "--random", "10", "--params", "no_such_set", "-o", str(tmp_path / "rod")]) == 2
    assert "no_such_set" in capsys.readouterr().err
    assert not (tmp_path / "rod").exists()
    # control: a folder that existed before stays, empty or not
    (tmp_path / "kept").mkdir()
    assert main(["dna-rod", "--random", "10", "--params", "no_such_set", "-o", str(tmp_path / "kept")]) == 2
    assert (tmp_path / "kept").is_dir()


def _subparsers():
    parser = build_parser()
    sub = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction")
    return sub.choices


def test_one_spelling_of_the_output_option():
    """Every subcommand that writes files takes -o/--output and lists no other spelling;
    --out, used before by some, still works."""
    writers = {"build-dna", "build-md", "coarse-grain", "compare", "dna-rod", "minicircle", "modes",
               "paper-figures", "rod-to-atoms", "topology"}
    for name, p in _subparsers().items():
        helptext = p.format_help()
        shown = set(re.findall(r"(?<![\w-])(--out\w*|-o)(?![\w-])", helptext))
        if name in writers:
            assert {"-o", "--output"} <= shown and "--out" not in shown, (name, shown)
        else:
            assert not shown & {"-o", "--output", "--out"}, (name, shown)
    for argv in (["rod-to-atoms", "r.h5", "--coarse"], ["compare"], ["paper-figures"], ["build-md", "s.toml"],
                 ["dna-rod", "--random", "10"], ["build-dna", "--ideal", "--sequence", "ACGT"],
                 ["coarse-grain", "x.pdb", "--temperature", "300"]):
        for spelling in ("-o", "--output", "--out"):
            assert build_parser().parse_args(argv + [spelling, "there"]).output == "there", (argv, spelling)


def test_version_is_rodsim_s(rodsim, capsys):
    assert main(["--version"]) == 0
    mine = capsys.readouterr().out.strip()
    theirs = subprocess.run([str(rodsim), "--version"], capture_output=True, text=True, check=True).stdout.strip()
    assert mine.split(" ", 1)[0] == "dnarod" and theirs.split(" ", 1)[0] == "rodsim"
    assert mine.split(" ", 1)[1] == theirs.split(" ", 1)[1]


def test_compare_help_lists_every_shipped_configuration():
    p = _subparsers()["compare"]
    text = p.format_help()
    shipped = sorted(f.name for f in (ROOT / "workflows" / "config").glob("*.yaml") if f.name != "schema.yaml")
    listed = re.findall(r"^  (\S+\.yaml) ", text, flags=re.M)
    assert sorted(listed) == shipped
    default = p.get_default("output")
    assert default == "out/compare"
    assert f"{default}/report/index.html" in (ROOT / "README.md").read_text()   # the Quickstart says where
