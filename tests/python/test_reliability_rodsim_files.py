"""rodsim's files checked before any work (docs/reliability.md, "Bad input"): a scene path that
is not a scene file, and an output path that cannot take rodsim's HDF5 file, each exit 2 with a
`rodsim: error:` line naming the path and what is allowed, and nothing written or lost.

In a new user's trial `rodsim run -o` an existing folder failed only after the whole run and
left OUT.partial, and `rodsim check` of a folder or an empty file said "rod.length: is required".
The output rules are the dnarod commands' (workflows/validate.py): a missing parent folder is
made, like `mkdir -p`, and removed again if the run then fails while it is still empty."""
import os
import subprocess
import time
from pathlib import Path

import h5py
import pytest

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "workflows" / "scenes"
SCENE = SCENES / "twisted_wave.toml"
SHORT = ("--set", "output.t_end=0.1", "--set", "output.frames=3", "-q")
# A run of this length takes hours: a refusal within the timeout is one made before the work.
ENDLESS = ("--set", "output.t_end=1e7", "--set", "output.frames=3", "-q")
REFUSE_WITHIN_S = 60


def run(rodsim, *args, timeout=REFUSE_WITHIN_S):
    return subprocess.run([str(rodsim), *map(str, args)], capture_output=True, text=True, timeout=timeout)


def refused(p: subprocess.CompletedProcess, *names: str) -> str:
    """Exit 2, one `rodsim: error:` message naming NAMES, no crash."""
    assert p.returncode == 2, (p.returncode, p.stderr[-3000:])
    assert p.stderr.startswith("rodsim: error: "), p.stderr
    assert "terminate called" not in p.stderr and "Traceback" not in p.stderr, p.stderr
    for n in names:
        assert n in p.stderr, (n, p.stderr)
    return p.stderr


def tree(folder: Path) -> dict[str, bytes | None]:
    """Every path under FOLDER with its bytes (None for a folder or a FIFO): what "nothing
    written, nothing lost" compares."""
    return {str(p.relative_to(folder)): (p.read_bytes() if p.is_file() else None)
            for p in sorted(folder.rglob("*"))}


# --- the scene file ------------------------------------------------------------------------

SCENE_CASES = {
    # name: (how to make it, what the message says)
    "folder": (lambda p: p.mkdir(), "is a folder, not a scene TOML file"),
    "empty": (lambda p: p.write_bytes(b""), "is empty; a scene TOML file is expected"),
    "white space": (lambda p: p.write_bytes(b" \n\t\r\n"), "is empty (only white space)"),
    "binary": (lambda p: p.write_bytes(bytes(range(256)) * 4), "is not a TOML file: its bytes are binary"),
    "NUL in text": (lambda p: p.write_bytes(SCENE.read_bytes() + b"\n# \0\n"), "(a NUL byte on line"),
    "Latin-1": (lambda p: p.write_bytes(SCENE.read_bytes() + "# 5 \u00c5\n".encode("latin-1")),
                "(bytes that are not UTF-8 on line"),
    "missing": (lambda p: None, "no such file (a scene TOML file is expected)"),
}


@pytest.mark.parametrize("command", ["check", "run"])
@pytest.mark.parametrize("case", list(SCENE_CASES))
def test_a_scene_path_that_is_not_a_scene_is_named(rodsim, tmp_path, case, command):
    make, says = SCENE_CASES[case]
    scene = tmp_path / "scene.toml"
    make(scene)
    before = tree(tmp_path)
    args = ["-o", tmp_path / "out.h5", *ENDLESS] if command == "run" else []
    err = refused(run(rodsim, command, scene, *args), f"scene file '{scene}'", says)
    assert "rod.length" not in err and "not valid TOML" not in err, err
    assert tree(tmp_path) == before, "nothing written"


def test_control_a_scene_with_non_ascii_utf8_is_accepted(rodsim, tmp_path):
    # the binary check must not refuse UTF-8 text: the same comment as the Latin-1 case above
    scene = tmp_path / "scene.toml"
    scene.write_bytes(SCENE.read_bytes() + "# 5 \u00c5, \u03c9 = 2.67, \U0001d6c4\n".encode("utf-8"))
    p = run(rodsim, "check", scene)
    assert p.returncode == 0, p.stderr
    p = run(rodsim, "run", scene, "-o", tmp_path / "o.h5", *SHORT)
    assert p.returncode == 0, p.stderr


def test_a_line_of_the_latin1_case_is_the_line_of_the_byte(rodsim, tmp_path):
    scene = tmp_path / "scene.toml"
    text = SCENE.read_bytes()
    scene.write_bytes(text + "# \u00c5\n".encode("latin-1"))
    line = text.count(b"\n") + 1
    err = refused(run(rodsim, "check", scene))
    assert f"on line {line})" in err, err


# --- the output file -----------------------------------------------------------------------

@pytest.fixture
def place(tmp_path):
    """A folder with a file in it, a plain text file, a FIFO, and the scene copied in."""
    (tmp_path / "runs").mkdir()
    (tmp_path / "runs" / "keep.txt").write_text("an earlier result\n")
    (tmp_path / "notes.txt").write_text("not HDF5\n")
    os.mkfifo(tmp_path / "pipe")
    (tmp_path / "scene.toml").write_bytes(SCENE.read_bytes())
    return tmp_path


OUTPUT_CASES = {
    # name: (the -o argument under the place, what the message says)
    "an existing folder": ("runs", "is a folder; give a file name (rodsim writes one HDF5 file"),
    "a name ending in /": ("new/", "names a folder (it ends in '/'); give a file name"),
    "the scene itself": ("scene.toml", "is an existing file that is not HDF5; rodsim replaces only an HDF5 file"),
    "a text file": ("notes.txt", "is an existing file that is not HDF5"),
    "a FIFO": ("pipe", "is a FIFO (named pipe); give a file name"),
    "under a regular file": ("notes.txt/o.h5", "notes.txt is a file, not a folder, so nothing can be written"),
    "under a file, deeper": ("notes.txt/a/b/o.h5", "notes.txt is a file, not a folder"),
    "its .partial a folder": ("runs/o.h5", "rodsim writes the file {out}.partial while it runs, and that is a folder"),
}


@pytest.mark.parametrize("case", list(OUTPUT_CASES))
def test_an_output_that_cannot_be_written_is_refused_before_any_work(rodsim, place, case):
    arg, says = OUTPUT_CASES[case]
    out = f"{place}/{arg}"  # as typed: a Path would drop the trailing '/'
    if case == "its .partial a folder":
        Path(out + ".partial").mkdir()
    before = tree(place)
    t0 = time.monotonic()
    err = refused(run(rodsim, "run", place / "scene.toml", "-o", out, *ENDLESS), f"-o {out}", says.format(out=out))
    assert time.monotonic() - t0 < REFUSE_WITHIN_S, err
    assert tree(place) == before, f"nothing written, nothing lost: {err}"


def test_an_output_under_proc_is_refused(rodsim, tmp_path):
    # root may write almost anywhere, but not here: the write is tried, not read from permission bits
    err = refused(run(rodsim, "run", SCENE, "-o", "/proc/dnarod-test/o.h5", *ENDLESS), "-o /proc/dnarod-test/o.h5")
    assert "cannot create the folder /proc/dnarod-test" in err or "cannot write in /proc" in err, err
    refused(run(rodsim, "run", SCENE, "-o", "/proc/o.h5", *ENDLESS), "-o /proc/o.h5", "cannot write in /proc")


def test_an_earlier_hdf5_output_and_an_empty_file_are_replaced(rodsim, tmp_path):
    out = tmp_path / "o.h5"
    assert run(rodsim, "run", SCENE, "-o", out, *SHORT).returncode == 0
    p = run(rodsim, "run", SCENE, "-o", out, "--set", "output.t_end=0.1", "--set", "output.frames=5", "-q")
    assert p.returncode == 0, p.stderr
    with h5py.File(out, "r") as f:
        assert f["time"].shape == (5,) and f.attrs["complete"] == 1
    empty = tmp_path / "made-by-mktemp.h5"
    empty.write_bytes(b"")
    assert run(rodsim, "run", SCENE, "-o", empty, *SHORT).returncode == 0
    with h5py.File(empty, "r") as f:
        assert f["time"].shape == (3,)
    # the control of the "not HDF5" refusal: the same kind of file, one byte not HDF5, is kept
    (tmp_path / "n.h5").write_bytes(b"x")
    refused(run(rodsim, "run", SCENE, "-o", tmp_path / "n.h5", *SHORT), "is an existing file that is not HDF5")
    assert (tmp_path / "n.h5").read_bytes() == b"x"


def test_a_missing_parent_folder_is_made_and_removed_if_the_run_fails(rodsim, tmp_path):
    # made, like mkdir -p (workflows/validate.py's rule, the same for every command)
    out = tmp_path / "new" / "deeper" / "o.h5"
    p = run(rodsim, "run", SCENE, "-o", out, *SHORT)
    assert p.returncode == 0, p.stderr
    with h5py.File(out, "r") as f:
        assert f.attrs["complete"] == 1
    # a run refused after the folders were made (the contact cut-off is checked against the rod's
    # period when the rod is set up) leaves none of them
    gone = tmp_path / "gone" / "deeper" / "o.h5"
    p = run(rodsim, "run", SCENE, "-o", gone, *SHORT, "--set", "contact.diameter=3")
    refused(p, "[contact]", "shorter than twice the contact cut-off")
    assert not (tmp_path / "gone").exists()
    # a numerical stop keeps its frames, so the folder made for them stays
    kept = tmp_path / "kept" / "o.h5"
    p = run(rodsim, "run", SCENE, "-o", kept, "--set", "checks.max_energy_drift=1e-14", "--set", "solver.rtol=1e-3",
            "--set", "solver.atol=1e-3")
    assert p.returncode == 3, p.stderr
    with h5py.File(kept, "r") as f:
        assert f.attrs["complete"] == 0


@pytest.mark.parametrize("value,says", [("nan", "not a finite number"), ("inf", "not a finite number"),
                                        ("-1", "out of range"), ("soon", "not a number")])
def test_checkpoint_interval_must_be_finite(rodsim, tmp_path, value, says):
    # NaN passed CLI11's NonNegativeNumber (a comparison) and was silently ignored
    p = run(rodsim, "run", SCENE, "-o", tmp_path / "o.h5", *ENDLESS, "--checkpoint-every", value)
    refused(p, f"--checkpoint-every: {value}: {says} (allowed: seconds >= 0)")
    assert list(tmp_path.iterdir()) == []
    # the control: 0 (checkpoints only on a signal) is allowed
    assert run(rodsim, "run", SCENE, "-o", tmp_path / "o.h5", *SHORT, "--checkpoint-every", "0").returncode == 0
