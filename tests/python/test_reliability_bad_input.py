"""Bad input to any `dnarod` command: exit 2 and a message that names the file or option,
before any work, never a traceback (workflows/validate.py; docs/reliability.md, "Bad input").

Each case below ended in a Python traceback (exit 1), came after minutes of work, or said
the wrong thing, in a new user's trial of the README. The fuzz-style test at the end feeds
every command a binary file, an empty file, a folder, NaN and an unwritable output.
The listed cases run through the installed command, as a user runs it; the sweep calls the
command's main() in this process, where any exception that escapes fails the test."""
import gzip
import json
import subprocess
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "workflows" / "scenes"
DATA = ROOT / "tests" / "data"


def run(dnarod, *args, cwd=None, timeout=600):
    return subprocess.run([str(dnarod), *map(str, args)], capture_output=True, text=True, cwd=cwd, timeout=timeout)


def refused(dnarod, *args, names=(), cwd=None) -> str:
    """Run, expect exit 2 with no traceback and a `dnarod CMD: error:` line naming NAMES."""
    p = run(dnarod, *args, cwd=cwd)
    assert p.returncode == 2, (args, p.returncode, p.stderr[-3000:])
    assert "Traceback" not in p.stderr, p.stderr[-3000:]
    assert "error:" in p.stderr, p.stderr
    for n in names:
        assert str(n) in p.stderr, (n, p.stderr)
    return p.stderr


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """A binary file, an empty one, a folder, and a regular file to put outputs under."""
    d = tmp_path_factory.mktemp("bad")
    (d / "binary.bin").write_bytes(bytes(range(256)) * 16 + b"\0\xff\xfe")
    (d / "empty.txt").write_bytes(b"")
    (d / "folder").mkdir()
    (d / "plain").write_text("a regular file\n")
    return d


@pytest.fixture(scope="module")
def rod21(rodsim, tmp_path_factory):
    """A short run of the 21-bp DNA scene (centreline and directors): a valid rod input."""
    d = tmp_path_factory.mktemp("rod21")
    p = subprocess.run([str(rodsim), "run", str(SCENES / "dna21.toml"), "-o", str(d / "rod.h5"),
                        "--set", "output.t_end=5", "--set", "output.frames=6"],
                       capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    return d / "rod.h5"


@pytest.fixture(scope="module")
def sample_pdb(tmp_path_factory):
    d = tmp_path_factory.mktemp("sample")
    with gzip.open(DATA / "md_sample_3dna" / "sample_md0.pdb.gz", "rb") as f:
        (d / "sample_md0.pdb").write_bytes(f.read())
    return d / "sample_md0.pdb"


# --- the listed cases ---------------------------------------------------------------------

def test_dna_rod_random_zero_and_one(dnarod, tmp_path):
    # --random 0 was taken for "not given"; --random 1 raised rodcore's error and left a folder
    refused(dnarod, "dna-rod", "--random", "0", "--seed", "1", "--params", "paper", "-o", tmp_path / "r0",
            names=["--random", "0", ">= 1"])
    err = refused(dnarod, "dna-rod", "--random", "1", "--seed", "1", "--params", "paper", "-o", tmp_path / "r1",
                  names=["1 bp", "grid points", "at least 4"])
    assert not (tmp_path / "r0").exists() and not (tmp_path / "r1").exists(), err


@pytest.mark.parametrize("cmd", ["modes", "topology", "dna-rod", "coarse-grain"])
def test_unwritable_output_is_refused_before_any_work(dnarod, files, rod21, sample_pdb, cmd):
    args = {"modes": [rod21], "topology": [rod21],
            "dna-rod": ["--random", "8", "--seed", "1", "--params", "paper"],
            "coarse-grain": [sample_pdb, "--pairs", DATA / "md_sample_3dna" / "bpfile.dat", "--temperature", "300",
                             "--min-effective", "8"]}[cmd]
    for out, why in ((files / "plain" / "out", "is a file, not a folder"), (Path("/proc/dnarod-test/out"),
                                                                              "cannot create the folder")):
        t0 = time.monotonic()
        err = refused(dnarod, cmd, *args, "-o", out, names=[f"-o {out}", why])
        # coarse-grain found out only after the whole analysis; now it is refused before
        # the trajectory is read: no stage of the work is reported
        assert "frames" not in err.lower() or cmd != "coarse-grain", err
        assert time.monotonic() - t0 < 60


def test_topology_output_an_existing_file(dnarod, files, rod21):
    refused(dnarod, "topology", rod21, "-o", files / "plain", names=[f"-o {files / 'plain'}", "is an existing file"])


def test_missing_parent_folder_is_made_for_every_output(dnarod, tmp_path, files):
    # the one rule: a missing parent folder is made (build-dna, rod-to-atoms and
    # helical-params --csv failed after all their work)
    out = tmp_path / "new" / "deeper" / "ideal.pdb"
    p = run(dnarod, "build-dna", "--ideal", "--sequence", "ACGTACGTAC", "-o", out)
    assert p.returncode == 0 and out.is_file(), p.stderr
    csv = tmp_path / "new2" / "steps.csv"
    p = run(dnarod, "helical-params", out, "--csv", csv)
    assert p.returncode == 0 and csv.read_text().startswith("frame,step"), p.stderr
    # a file in the way of the folder: refused before the work, and nothing made
    err = refused(dnarod, "build-dna", "--ideal", "--sequence", "ACGTACGTAC", "-o", files / "plain" / "x" / "a.pdb",
                  names=[f"{files / 'plain'} is a file, not a folder"])
    assert "atoms" not in err


def test_rod_to_atoms_output_under_a_missing_folder(dnarod, rod21, tmp_path):
    out = tmp_path / "views" / "rod.pdb"
    p = run(dnarod, "rod-to-atoms", rod21, "--coarse", "--bp", "21", "-o", out)
    assert p.returncode == 0 and out.is_file(), p.stderr


def test_a_failed_command_removes_the_folders_it_made(dnarod, tmp_path):
    refused(dnarod, "dna-rod", "--sequence", "ACG", "--params", "paper", "-o", tmp_path / "a" / "b" / "c",
            names=["3 bp"])
    refused(dnarod, "modes", tmp_path / "nothing.h5", "-o", tmp_path / "m" / "n", names=["nothing.h5"])
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("cmd,kind", [("build-md", "TOML"), ("compare", "YAML"), ("build-dna", "CSV"),
                                      ("coarse-grain", "pairs")])
def test_a_binary_file_is_not_a_text_file(dnarod, files, sample_pdb, tmp_path, cmd, kind):
    b = files / "binary.bin"
    args = {"build-md": [b, "-o", tmp_path / "md"],
            "compare": ["--config", b, "-o", tmp_path / "cmp"],
            "build-dna": ["--params", b, "--sequence", "ACGTAC", "-o", tmp_path / "x.pdb"],
            "coarse-grain": [sample_pdb, "--pairs", b, "--temperature", "300", "-o", tmp_path / "cg"]}[cmd]
    err = refused(dnarod, cmd, *args, names=[b])
    assert f"not a {kind if kind != 'pairs' else 'text'} file" in err, err
    assert "UnicodeDecodeError" not in err


def test_build_md_nan_time_step(dnarod, tmp_path):
    refused(dnarod, "build-md", SCENES / "dna21.toml", "--dt", "nan", "-o", tmp_path / "md",
            names=["--dt", "not a finite number"])
    assert not (tmp_path / "md").exists()


def test_dispersion_refuses_non_finite_output_and_precision_zero(dnarod):
    refused(dnarod, "dispersion", "--kappa", "1e308", names=["--kappa 1e+308", "not a finite number"])
    refused(dnarod, "dispersion", "--kappa", "1", "--precision", "0", names=["--precision", ">= 1"])
    # the control: a large but representable wavenumber, and the documented 0/0 ratios at kappa = 0
    p = run(dnarod, "dispersion", "--kappa", "0", "1e10", "--ratios")
    assert p.returncode == 0, p.stderr
    rows = [r.split(",") for r in p.stdout.split()[1:]]
    assert "nan" in rows[0] or "inf" in rows[0]
    assert all(x not in ("nan", "inf") for x in rows[1][:3]), rows


def test_coarse_grain_of_an_md_folder_says_give_the_files(dnarod, files):
    err = refused(dnarod, "coarse-grain", files / "folder", "-o", files / "cgx", names=[files / "folder", "a folder"])
    assert "file not found" not in err and "md.tpr" in err


def test_bad_temperature_is_refused_before_any_work(dnarod, sample_pdb, tmp_path):
    t0 = time.monotonic()
    err = refused(dnarod, "build-md", SCENES / "dna21.toml", "--temperature", "-5", "-o", tmp_path / "md",
                  names=["--temperature", ">= 0"])
    # refused as the arguments are parsed: no stage of the build (rod run, pdb2gmx, grompp) reported
    assert err.startswith("usage: dnarod build-md")
    assert not [ln for ln in err.splitlines() if ln.startswith("build-md:")]
    err = refused(dnarod, "coarse-grain", sample_pdb, "--temperature", "-300", "-o", tmp_path / "cg",
                  names=["--temperature '-300'", "positive temperature"])
    assert "frames" not in err
    assert time.monotonic() - t0 < 60
    assert not (tmp_path / "md").exists() and not (tmp_path / "cg").exists()


# --- nothing lost: a failed rebuild leaves the previous build ----------------------------

@pytest.fixture(scope="module")
def build21(dnarod, gmx, tmp_path_factory):
    d = tmp_path_factory.mktemp("rebuild")
    p = run(dnarod, "build-md", SCENES / "dna21.toml", "-o", "md", "--ps", "5", "--protocol", "paper",
            "--temperature", "0", "--seed", "1", cwd=d)
    assert p.returncode == 0, p.stderr[-2000:]
    return d / "md"


def _snapshot(folder: Path) -> dict:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir()) if p.is_file()}


# --- a different existing output is refused up front -------------------------------------

def test_every_folder_command_is_in_the_marker_registry():
    # every command that checks an output folder names itself, with a marker of its own
    import re
    from dnarod import validate
    calls = {}
    for f in (ROOT / "workflows" / "commands").glob("*.py"):
        for cmd in re.findall(r"output_folder\([^)]*\)", f.read_text()):
            calls[f.name] = cmd
    # paper-figures writes only files named after its figures (fig1.png, fig1.json, ...), which
    # no other command writes, so it neither mixes with nor is recognised by another output
    calls.pop("paper_figures.py")
    assert calls and all("command=" in c for c in calls.values()), calls
    named = {re.search(r'command="([a-z-]+)"', c).group(1) for c in calls.values()}
    assert named == set(validate.OUTPUT_MARKERS)
    assert len(set(validate.OUTPUT_MARKERS.values())) == len(validate.OUTPUT_MARKERS)


@pytest.mark.parametrize("cmd", ["modes", "topology", "dna-rod"])
def test_a_folder_of_another_command_s_output_is_refused(dnarod, rod21, build21, cmd, tmp_path):
    # a folder holding build-md's build.json: refused before any work, the build untouched
    args = {"modes": [rod21], "topology": [rod21], "dna-rod": ["--random", "8", "--seed", "1", "--params", "paper"]}
    before = _snapshot(build21)
    refused(dnarod, cmd, *args[cmd], "-o", build21, names=[f"-o {build21}", "dnarod build-md", "build.json"])
    assert _snapshot(build21) == before
    # control: the same command may write into its own earlier output (run twice)
    for _ in range(2):
        p = run(dnarod, cmd, *args[cmd], "-o", tmp_path / "own")
        assert p.returncode == 0, p.stderr[-2000:]
    from dnarod.validate import OUTPUT_MARKERS
    assert (tmp_path / "own" / OUTPUT_MARKERS[cmd]).is_file()   # the command writes its marker


def test_build_md_into_another_command_s_output_is_refused(dnarod, rod21, tmp_path):
    p = run(dnarod, "topology", rod21, "-o", tmp_path / "top")
    assert p.returncode == 0, p.stderr[-2000:]
    before = _snapshot(tmp_path / "top")
    refused(dnarod, "build-md", SCENES / "dna21.toml", "--ps", "5", "-o", tmp_path / "top",
            names=["dnarod topology", "topology.json"])
    assert _snapshot(tmp_path / "top") == before and not (tmp_path / "top.building").exists()


def test_a_refused_rebuild_leaves_the_build(dnarod, build21):
    before = _snapshot(build21)
    refused(dnarod, "build-md", SCENES / "dna21.toml", "--temperature", "-5", "-o", build21, names=["--temperature"])
    assert _snapshot(build21) == before


def test_a_rebuild_failing_late_leaves_the_build(dnarod, build21):
    # grompp refuses dt = 10 fs with h-bond constraints: after the rod run, pdb2gmx and the
    # junction check, i.e. after the old code had deleted build.json
    before = _snapshot(build21)
    err = refused(dnarod, "build-md", SCENES / "dna21.toml", "--constraints", "h-bonds", "--dt", "0.01",
                  "--ps", "5", "--protocol", "paper", "--temperature", "0", "--seed", "1", "-o", build21)
    assert "grompp" in err or "time step" in err, err
    assert _snapshot(build21) == before
    # the failed build's own files stay beside it, so that the log the message names exists
    logs = [w.rstrip(":;,") for w in err.split() if w.rstrip(":;,").endswith(".log")]
    assert logs and all(Path(p).is_file() and Path(p).parent.name == "md.building" for p in logs), err
    # the control: the same rebuild that succeeds replaces the build (a new seed: new velocities)
    p = run(dnarod, "build-md", SCENES / "dna21.toml", "--ps", "5", "--protocol", "paper", "--temperature", "0",
            "--seed", "2", "-o", build21)
    assert p.returncode == 0, p.stderr[-2000:]
    after = _snapshot(build21)
    assert after["build.json"] != before["build.json"] and set(before) <= set(after)
    assert '"seed": 2' in after["build.json"].decode()
    assert not (build21.parent / "md.building").exists()


# --- the fuzz: every command, every kind of bad file, NaN, an unwritable output ----------

def _commands(rod21, sample_pdb):
    """(command, arguments with the slots FILE / OUT / NUM, what FILE is, the NUM option):
    one line per way a command takes a file, an output or a number."""
    seq = "ACGTACGTAC"
    return [
        ("build-dna", ["--params", "FILE", "--sequence", seq, "-o", "OUTFILE.pdb"], "--params"),
        ("build-dna", ["--scene", "FILE", "--sequence", seq, "-o", "OUTFILE.pdb"], "--scene"),
        ("build-dna", ["--ideal", "--sequence", seq, "--rise", "NUM", "-o", "OUTFILE.pdb"], None),
        ("build-md", ["FILE", "-o", "OUT"], None),
        ("build-md", [SCENES / "dna21.toml", "--dt", "NUM", "-o", "OUT"], None),
        ("build-md", [SCENES / "dna21.toml", "--rod", "FILE", "-o", "OUT"], None),
        ("coarse-grain", ["FILE", "--temperature", "300", "-o", "OUT"], None),
        ("coarse-grain", [sample_pdb, "--pairs", "FILE", "--temperature", "300", "-o", "OUT"], "--pairs"),
        ("coarse-grain", [sample_pdb, "--temperature", "NUM", "-o", "OUT"], None),
        ("coarse-grain", [sample_pdb, "--tension", "NUM", "--temperature", "300", "-o", "OUT"], None),
        ("compare", ["--config", "FILE", "-o", "OUT"], "--config"),
        ("dispersion", ["--kappa", "NUM"], None),
        ("dispersion", ["--kappa", "1", "--D1", "NUM"], None),
        ("dna-rod", ["--random", "8", "--seed", "1", "--params", "FILE", "-o", "OUT"], None),
        ("dna-rod", ["--sequence-from-md", "FILE", "-o", "OUT"], None),
        ("dna-rod", ["--random", "8", "--seed", "1", "--params", "paper", "--kick", "NUM", "-o", "OUT"], None),
        ("helical-params", ["FILE"], None),
        ("helical-params", [DATA / "355d" / "355d.pdb", "--pairs", "FILE", "--csv", "OUTFILE.csv"], "--pairs"),
        ("helical-params", [DATA / "355d" / "355d.pdb", "--box", "NUM", "1", "1"], None),
        ("minicircle", ["--bp", "20", "--delta-lk", "0", "--no-atoms", "--relax-ps", "NUM", "-o", "OUT"], None),
        ("modes", ["FILE", "-o", "OUT"], None),
        ("modes", [rod21, "--discard-ps", "NUM", "-o", "OUT"], None),
        ("paper-figures", ["--only", "fig1", "-o", "OUT"], None),
        ("rod-to-atoms", ["FILE", "--coarse", "--bp", "21", "-o", "OUTFILE.pdb"], None),
        ("rod-to-atoms", [rod21, "--coarse", "--every", "NUM", "-o", "OUTFILE.pdb"], None),
        ("run-md", ["FILE"], None),
        ("run-md", ["FILE", "--ps", "NUM"], None),
        ("topology", ["FILE", "-o", "OUT"], None),
        ("topology", [rod21, "--writhe-points", "NUM", "-o", "OUT"], None),
        ("compare", ["--cores", "NUM", "-o", "OUT"], None),
    ]


def refused_here(capsys, *args, names=()) -> str:
    """`refused` in this process (the sweep below makes ~100 calls; a process each costs
    minutes on a loaded machine): exit 2, and no exception escapes the command."""
    from dnarod.cli import main
    capsys.readouterr()
    code = main([str(a) for a in args])     # argparse's refusals too: main returns their status
    err = capsys.readouterr().err
    assert code == 2, (args, code, err[-3000:])
    assert "error:" in err, err
    for n in names:
        assert str(n) in err, (args, n, err)
    return err


def test_fuzz_every_command_every_bad_input(dnarod, files, rod21, sample_pdb, tmp_path, capsys):
    bad_files = [files / "binary.bin", files / "empty.txt", files / "folder"]
    unwritable = [files / "plain" / "sub", Path("/proc/dnarod-fuzz/sub")]
    # a valid FILE per command, for the unwritable-output cases (None: the line has none)
    valid = {"build-md": SCENES / "dna21.toml", "coarse-grain": sample_pdb,
             "helical-params": DATA / "355d" / "355d.pdb", "modes": rod21, "rod-to-atoms": rod21, "topology": rod21}
    outs = ("OUT", "OUTFILE.pdb", "OUTFILE.csv")
    seen = set()
    lines = _commands(rod21, sample_pdb)
    for k, (cmd, args, _) in enumerate(lines):
        out_slot = next((a for a in args if a in outs), None)
        suffix = "" if out_slot in (None, "OUT") else out_slot[out_slot.index("."):]

        opt = args[args.index("NUM") - 1] if "NUM" in args else None
        ok_num = "100" if opt == "--writhe-points" else "2"     # a valid number for the other cases

        def fill(file, out, num=ok_num):
            return [file if a == "FILE" else out if a in outs else num if a == "NUM" else a for a in args]

        ok_out = tmp_path / f"out{k}{suffix}"
        if "FILE" in args:                      # a bad file, every other argument valid
            for f in bad_files:
                refused_here(capsys, cmd, *fill(f, ok_out), names=[f])
                seen.add((cmd, "file"))
        if "NUM" in args:                       # NaN, refused when the arguments are parsed
            err = refused_here(capsys, cmd, *fill(files / "folder", ok_out, "nan"), names=["nan"])
            assert opt in err if opt.startswith("-") else True, err
            seen.add((cmd, "nan"))
        if out_slot is not None and ("FILE" not in args or cmd in valid):
            for u in unwritable:                # an unwritable output, every other argument valid
                out = u / f"x{suffix}" if suffix else u
                refused_here(capsys, cmd, *fill(valid.get(cmd), out), names=[out])
                seen.add((cmd, "out"))
    assert list(tmp_path.iterdir()) == []      # a refused command makes nothing
    commands = {c for c, _, _ in lines}
    assert commands == {m.stem.replace("_", "-") for m in (ROOT / "workflows" / "commands").glob("[a-z]*.py")}
    assert {c for c, kind in seen if kind == "out"} == commands - {"dispersion", "run-md"}
    assert {c for c, kind in seen if kind == "file"} == commands - {"dispersion", "paper-figures", "minicircle"}
    assert {c for c, kind in seen if kind == "nan"} == commands - {"paper-figures"}


def test_topology_prints_one_frame_s_numbers_together(rod21, tmp_path, capsys):
    # the summary printed frame 0's Tw and Wr next to "Lk a -> b"; now each frame's three together
    from dnarod.cli import main
    assert main(["topology", str(rod21), "-o", str(tmp_path / "topo")]) == 0
    line = next(ln for ln in capsys.readouterr().out.splitlines() if ln.startswith(str(rod21)))
    r = json.loads((tmp_path / "topo" / "topology.json").read_text())["paths"][str(rod21)]
    for which, f in (("first", 0), ("last", -1)):
        assert f"{which} frame Lk {r['Lk'][f]:.0f}, Tw {r['Tw'][f]:.4f}, Wr {r['Wr'][f]:.4f}" in line, line
