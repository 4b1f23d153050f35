"""The README's worked example is a test: its shell block and its Python block, taken from
README.md, run as written in a temporary folder, and what they print must be what the
README quotes (the `#    ` lines under a command, the `# ` lines under a print).

Only two documented substitutions change the commands, each of which must occur in the
README exactly once (so an edit that removes it fails here, not silently):

* MD_SHORT: the MD lengths, `--equilibrate-ps 20` -> 2 and `--ps 600` -> 2 (run-md). The
  rod (step 1) and everything else run at full length; build-md's MD length follows the
  rod run it is given (step 3), so the box is still sized for the rod's 600 ps.
* TINY: step 5, the whole comparison, runs on workflows/config/tiny.yaml into the session's
  tiny comparison folder (conftest.py `tiny_run`, which ran that same command), so CI runs
  the tiny comparison once: the command must exit 0 with nothing left to do, and its
  report must exist. Setup and install are not re-run (step 5 is a `dnarod compare` line).

About 2 min on 2 loaded cores (build-md 40 s, run-md 35 s, rod-to-atoms 30 s)."""
import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]

MD_SHORT = {"--equilibrate-ps 20": "--equilibrate-ps 2", "--ps 600": "--ps 2"}
TINY = {"--config workflows/config/headline.yaml -o out/headline":
        "--config workflows/config/tiny.yaml -o {tiny_out}"}
WALL = re.compile(r"\d+(\.\d+)? s wall")       # the one printed figure that is a timing


def worked_example(readme: str) -> tuple[list[dict], str]:
    """The README's worked example: its shell commands, each {cmd, quoted: [lines]}
    (continuation lines joined), and its Python block."""
    sec = readme.split("## Worked example", 1)[1].split("\n## ", 1)[0]
    sh = re.search(r"```sh\n(.*?)```", sec, re.S).group(1)
    py = re.search(r"```python\n(.*?)```", sec, re.S).group(1)
    cmds: list[dict] = []
    pending = ""
    after_command = False     # a quote follows its command (or another quote) directly
    for line in sh.splitlines():
        if line.startswith("#    ") and after_command:
            cmds[-1]["quoted"].append(line[5:])
            continue
        after_command = False
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        line = line.split("  #", 1)[0].rstrip()           # a comment after the command
        if line.endswith("\\"):
            pending += line[:-1] + " "
            continue
        cmds.append({"cmd": " ".join((pending + line).split()), "quoted": []})
        pending, after_command = "", True
    return cmds, py


def substitute(cmds: list[dict], subs: dict) -> list[dict]:
    out = [dict(c) for c in cmds]
    for old, new in subs.items():
        hits = [c for c in out if old in c["cmd"]]
        assert len(hits) == 1, f"README worked example: {old!r} occurs {len(hits)} times, expected once"
        hits[0]["cmd"] = hits[0]["cmd"].replace(old, new)
    return out


def test_parser_reads_the_commands_and_quotes():
    """The parser itself, on a made-up block (the control of the extraction)."""
    cmds, py = worked_example("## Worked example\n```sh\n# 1. x\nrodsim run a.toml -o a.h5\n"
                              "#    wrote a.h5\n\n# 2. a comment\n#    that goes on\n"
                              "b --x 1 \\\n    --y 2   # comment\n```\n"
                              "```python\nprint(1)\n# 1\n```\n## Next\n")
    assert cmds == [{"cmd": "rodsim run a.toml -o a.h5", "quoted": ["wrote a.h5"]},
                    {"cmd": "b --x 1 --y 2", "quoted": []}]
    assert py == "print(1)\n# 1\n"
    with pytest.raises(AssertionError, match="occurs 0 times"):
        substitute(cmds, {"--ps 600": "--ps 2"})


def test_readme_worked_example_runs_as_written(tmp_path, tiny_run, rodsim):
    readme = (ROOT / "README.md").read_text()
    cmds, py = worked_example(readme)
    assert len(cmds) == 7 and cmds[0]["cmd"].startswith("rodsim run")
    cmds = substitute(substitute(cmds, MD_SHORT), {k: v.format(tiny_out=tiny_run[0]) for k, v in TINY.items()})
    (tmp_path / "workflows").symlink_to(ROOT / "workflows")      # the README runs from a clone's root
    env = dict(os.environ, PATH=f"{rodsim.parent}{os.pathsep}{os.environ['PATH']}",
               DNAROD_BIN_DIR=str(rodsim.parent))
    for c in cmds:
        p = subprocess.run(["bash", "-c", c["cmd"]], cwd=tmp_path, env=env, capture_output=True,
                           text=True, timeout=600)
        assert p.returncode == 0, f"{c['cmd']}\n{p.stdout[-2000:]}\n{p.stderr[-3000:]}"
        printed = [WALL.sub("- s wall", x) for x in (p.stdout + p.stderr).splitlines()]
        for q in c["quoted"]:
            assert WALL.sub("- s wall", q) in printed, f"{c['cmd']}: README quotes {q!r}; it printed {printed}"
        if c["cmd"].startswith("dnarod compare"):
            assert "Nothing to be done" in p.stdout + p.stderr
            assert (tiny_run[0] / "report" / "index.html").is_file()
    # step 3 works as written: build-md's MD length is the rod run's (599.97 ps in 2-fs steps)
    build = json.loads((tmp_path / "md158" / "build.json").read_text())
    assert build["md_length_ps"] == pytest.approx(599.97, abs=1e-9)
    assert json.loads((tmp_path / "md158" / "md.done").read_text())["length_ps"] == pytest.approx(2.0)
    assert (tmp_path / "rod_atoms.xtc").stat().st_size > 0
    # the Python block, verbatim, after steps 1-4
    p = subprocess.run([sys.executable, "-c", py], cwd=tmp_path, env=env, capture_output=True,
                       text=True, timeout=300)
    assert p.returncode == 0, p.stderr[-3000:]
    quoted = [line[2:] for line in py.splitlines() if line.startswith("# ")]
    assert len(quoted) == 2 and p.stdout.splitlines() == quoted, (p.stdout, quoted)
