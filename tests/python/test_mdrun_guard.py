"""run-md stops an MD that has blown up (mdbridge/md/gromacs/run.py: blow_up), reading
mdrun's log as GROMACS writes it (mdbridge/md/gromacs/mdlog.py).

The energy blocks below are GROMACS 2022.5's own: the first from a sheared 21-bp
duplex at step 0 (tests/python/test_reliability_gromacs.py builds it), the second from
an intact one at 300 K. The guard's mechanics are run on a stand-in process that hangs
and ignores TERM, as the real mdrun was seen to (a real one is in the reliability tests)."""
import math
import sys
import time

import pytest

from dna_models.errors import ExternalToolError
from mdbridge.md.gromacs.gmx import run_gmx_with_progress
from mdbridge.md.gromacs.mdlog import block_energies, last_energy_block, tail_text
from mdbridge.md.gromacs.run import BLOWN_UP_TEMPERATURE_K, blow_up, mdrun_diagnosis

BLOWN = """\
Started mdrun on rank 0 Fri Dec  4 17:26:22 2026

           Step           Time
              0        0.00000

   Energies (kJ/mol)
           Bond            U-B    Proper Dih.  Improper Dih.          LJ-14
    6.23572e+03    6.45653e+03    5.83083e+03    0.00000e+00    2.13576e+05
     Coulomb-14        LJ (SR)   Coulomb (SR)      Potential    Kinetic En.
   -1.58574e+04    4.18800e+06   -1.11038e+04    4.39313e+06    7.37192e+10
   Total Energy    Temperature Pressure (bar)
    7.37236e+10    4.44430e+09    3.83679e+09

"""

INTACT = """\
           Step           Time
          20000       20.00000

   Energies (kJ/mol)
           Bond            U-B    Proper Dih.  Improper Dih.          LJ-14
    1.61238e+03    4.24551e+03    5.02193e+03    1.54467e+02    1.78834e+03
     Coulomb-14        LJ (SR)   Coulomb (SR)      Potential    Kinetic En.
    2.88573e+04   -2.43150e+03   -4.02261e+04   -9.77827e+02    4.88427e+03
   Total Energy  Conserved En.    Temperature Pressure (bar)
    3.90644e+03    3.99713e+03    2.95012e+02    2.55071e+01

"""


def test_the_last_block_is_read_column_by_column():
    text = INTACT + BLOWN          # two blocks: the last is the one read
    step, e = block_energies(last_energy_block(text))
    assert step == 0 and len(e) == 13
    assert e["LJ (SR)"] == 4.18800e+06 and e["Temperature"] == 4.44430e+09
    assert e["Pressure (bar)"] == 3.83679e+09 and e["Improper Dih."] == 0.0
    step, e = block_energies(last_energy_block(INTACT))
    assert step == 20000 and e["Conserved En."] == 3.99713e+03 and e["Temperature"] == 2.95012e+02
    assert last_energy_block("no energies yet\n") == []
    assert block_energies([]) == (-1, {})


def test_a_block_cut_short_gives_the_rows_written_so_far():
    lines = BLOWN.splitlines()
    cut = "\n".join(lines[:lines.index("   Energies (kJ/mol)") + 3]) + "\n    7.37"
    step, e = block_energies(last_energy_block(cut))
    assert step == 0 and set(e) == {"Bond", "U-B", "Proper Dih.", "Improper Dih.", "LJ-14"}


def test_blow_up_is_told_from_an_intact_run(tmp_path):
    log = tmp_path / "md.part.log"
    assert blow_up(log) is None                  # not written yet
    log.write_text(INTACT)
    assert blow_up(log) is None                  # the control: 295 K is a run, not a blow-up
    log.write_text(INTACT + BLOWN)
    reason = blow_up(log)
    assert reason and "4.44e+09 K at step 0" in reason and "blew up" in reason
    log.write_text(INTACT.replace("2.95012e+02", "        nan"))
    reason = blow_up(log)
    assert reason and "Temperature = nan at step 20000" in reason
    # at the limit, not above it: not a blow-up (the rule is strict)
    log.write_text(INTACT.replace("2.95012e+02", f"{BLOWN_UP_TEMPERATURE_K:.5e}"))
    assert blow_up(log) is None


def test_tail_text_reads_only_the_end_of_a_long_log(tmp_path):
    log = tmp_path / "md.log"
    log.write_text(BLOWN + "x" * 100_000 + "\n" + INTACT)
    step, e = block_energies(last_energy_block(tail_text(log)))
    assert step == 20000 and math.isclose(e["Temperature"], 295.012)


def hanging_gmx(tmp_path, log_text):
    """A stand-in gmx that writes LOG_TEXT to md.part.log, prints a step report and then
    hangs, ignoring TERM (what mdrun did inside its neighbour search); one process, as
    mdrun is (its threads are not processes), so the kill closes its output."""
    (tmp_path / "log.txt").write_text(log_text)
    exe = tmp_path / "gmx"
    exe.write_text("#!/bin/sh\ntrap '' TERM\ncp log.txt md.part.log\necho 'step 0'\n"
                   "exec sleep ${HANG_S:-600}\n")
    exe.chmod(0o755)
    return str(exe)


def test_the_guard_kills_a_hung_run_and_says_why(tmp_path):
    gmx = hanging_gmx(tmp_path, BLOWN)
    t0 = time.time()
    with pytest.raises(ExternalToolError) as e:
        run_gmx_with_progress(gmx, ["mdrun"], tmp_path, log_name="gmx_mdrun_md.log",
                              watch=lambda: blow_up(tmp_path / "md.part.log"), watch_every_s=0.2)
    assert time.time() - t0 < 30                 # not the 600 s the stand-in would hang
    msg = str(e.value)
    assert msg.startswith("`gmx mdrun` failed (stopped by dnarod: mdrun logged a temperature of 4.44e+09 K")
    assert e.value.returncode is None            # our kill, not a signal from outside
    assert "stopped by dnarod" in (tmp_path / "gmx_mdrun_md.log").read_text()
    # the diagnosis then quotes the energies, and does not call it a stop from outside
    diag = mdrun_diagnosis("", (tmp_path / "md.part.log").read_text(), e.value.returncode)
    assert "last energies in md.part.log:" in diag and "stopped from outside" not in diag
    assert "rebuild with --minimize" in diag


def test_control_an_intact_run_is_left_to_finish(tmp_path, monkeypatch):
    """The control: the same stand-in with an intact log runs to its end (2 s) under
    the same guard."""
    monkeypatch.setenv("HANG_S", "2")
    gmx = hanging_gmx(tmp_path, INTACT)
    steps = []
    run_gmx_with_progress(gmx, ["mdrun"], tmp_path, log_name="gmx_mdrun_md.log", on_step=steps.append,
                          watch=lambda: blow_up(tmp_path / "md.part.log"), watch_every_s=0.2)
    assert steps == [0] and "stopped by dnarod" not in (tmp_path / "gmx_mdrun_md.log").read_text()


def test_control_without_the_guard_the_hung_run_is_not_stopped(tmp_path):
    """What the guard is for: without WATCH, the hung stand-in is still running after
    the time the guarded one took to stop (run here in a child with a timeout)."""
    import os
    import signal
    import subprocess
    code = ("from pathlib import Path; from mdbridge.md.gromacs.gmx import run_gmx_with_progress; "
            f"run_gmx_with_progress({hanging_gmx(tmp_path, BLOWN)!r}, ['mdrun'], Path({str(tmp_path)!r}), "
            "log_name='gmx_mdrun_md.log')")
    child = subprocess.Popen([sys.executable, "-c", code], cwd=tmp_path, start_new_session=True,
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        with pytest.raises(subprocess.TimeoutExpired):
            child.wait(timeout=5)
    finally:
        os.killpg(child.pid, signal.SIGKILL)     # the child and its stand-in gmx
        child.wait()


TERM_LOGGER = "#!/bin/sh\ntrap 'echo term > got_term; exit 0' TERM\necho 'step 0'\nwhile :; do sleep 0.1; done\n"


def orphan_gets_term(tmp_path, code) -> bool:
    """Start CODE (a parent running the stand-in gmx TERM_LOGGER), SIGKILL the parent once
    the stand-in runs, and say whether the stand-in then received TERM within 5 s."""
    import os
    import signal
    import subprocess
    exe = tmp_path / "gmx"
    exe.write_text(TERM_LOGGER)
    exe.chmod(0o755)
    parent = subprocess.Popen([sys.executable, "-c", code.format(gmx=str(exe), cwd=str(tmp_path))],
                              cwd=tmp_path, start_new_session=True)
    try:
        for _ in range(100):
            if (tmp_path / "gmx_mdrun_md.log").exists() or (tmp_path / "started").exists():
                break
            time.sleep(0.1)
        time.sleep(0.5)
        parent.kill()
        parent.wait()
        for _ in range(50):
            if (tmp_path / "got_term").exists():
                return True
            time.sleep(0.1)
        return False
    finally:
        os.killpg(parent.pid, signal.SIGKILL)      # whatever is left of the session


def test_mdrun_never_outlives_a_killed_run_md(tmp_path):
    """A dnarod killed with SIGKILL (a test's timeout, the OOM killer) takes its mdrun with
    it: the kernel sends mdrun TERM (its own checkpoint-and-stop) when the parent dies."""
    code = ("from pathlib import Path; from mdbridge.md.gromacs.gmx import run_gmx_with_progress; "
            "Path('{cwd}', 'started').touch(); "
            "run_gmx_with_progress('{gmx}', ['mdrun'], Path('{cwd}'), log_name='gmx_mdrun_md.log')")
    assert orphan_gets_term(tmp_path, code)


def test_control_a_plain_child_outlives_its_killed_parent(tmp_path):
    """The control: the same stand-in started with a plain Popen is not told."""
    code = ("import subprocess; from pathlib import Path; Path('{cwd}', 'started').touch(); "
            "subprocess.run(['{gmx}'], cwd='{cwd}')")
    assert not orphan_gets_term(tmp_path, code)
