"""Find the user's `gmx` and run it; GROMACS failures become ExternalToolError.

Order of precedence: --gmx, then the environment variable DNAROD_GMX, then the
project's own GROMACS built for this machine by scripts/build_gromacs.sh (in
$DNAROD_GROMACS_PREFIX, default <checkout>/.local/gromacs), then `gmx` on PATH.
Debian's GROMACS is built for SSE4.1 only, hence the project's build first.

--gmx and DNAROD_GMX take a path (anything with a "/": used as given) or a
bare command name such as `gmx_d`, which is looked up like a command with the
project's build directory ahead of PATH: `--gmx gmx_d` (paper.yaml) runs the
project's double-precision build when it exists, Debian's /usr/bin/gmx_d
otherwise. To force Debian's binary, give its path (/usr/bin/gmx).
"""
from __future__ import annotations

import ctypes
import os
import re
import shutil
import signal
import subprocess
import sys
import threading
from pathlib import Path

from dna_models.errors import ExternalToolError

INSTALL_HINT = ("install GROMACS (Debian/Ubuntu: `sudo apt-get install gromacs`, or run "
                "scripts/setup.sh), or point dnarod at your own build with --gmx PATH or "
                "the environment variable DNAROD_GMX=/path/to/gmx")


ROOT = Path(__file__).resolve().parents[3]   # the checkout: mdbridge/md/gromacs/gmx.py


def built_gmx_prefix() -> Path:
    """Where scripts/build_gromacs.sh installs (the same rule as that script)."""
    return Path(os.environ.get("DNAROD_GROMACS_PREFIX") or ROOT / ".local" / "gromacs")


def built_gmx(double: bool = False) -> str | None:
    """The project's machine-specific build, if scripts/build_gromacs.sh made one."""
    return _executable(built_gmx_prefix() / "bin" / ("gmx_d" if double else "gmx"))


def _executable(path: Path) -> str | None:
    return str(path) if path.is_file() and os.access(path, os.X_OK) else None


def _lookup(name: str) -> str | None:
    """A path as given; a bare command name in the project's build, then on PATH."""
    if os.sep in name:
        return _executable(Path(name))
    return _executable(built_gmx_prefix() / "bin" / name) or shutil.which(name)


def find_gmx(explicit: str | None = None) -> str:
    """Path of the gmx executable to use, or ExternalToolError saying how to get one."""
    for source, cand in (("--gmx", explicit), ("DNAROD_GMX", os.environ.get("DNAROD_GMX"))):
        if cand:
            path = _lookup(cand)
            if path is None:
                raise ExternalToolError(
                    f"gmx given by {source} ({cand!r}) is not an executable file (a bare name is "
                    f"looked up in {built_gmx_prefix() / 'bin'}, then on PATH); {INSTALL_HINT}")
            return path
    path = _lookup("gmx")
    if path is None:
        raise ExternalToolError(f"GROMACS `gmx` not found on PATH (nor in {built_gmx_prefix() / 'bin'}, "
                                f"where scripts/build_gromacs.sh installs); {INSTALL_HINT}")
    return path


def gmx_version(gmx: str) -> str:
    out = subprocess.run([gmx, "--version"], capture_output=True, text=True)
    m = re.search(r"GROMACS version:\s*(\S+)", out.stdout + out.stderr)
    return m.group(1) if m else "unknown"


def gmx_top_dir(gmx: str) -> Path:
    """The force-field directory of this gmx ($GMXDATA/top or <Data prefix>/share/gromacs/top)."""
    if os.environ.get("GMXDATA"):
        return Path(os.environ["GMXDATA"]) / "top"
    out = subprocess.run([gmx, "--version"], capture_output=True, text=True)
    m = re.search(r"Data prefix:\s*(\S+)", out.stdout + out.stderr)
    if not m:
        raise ExternalToolError(f"cannot find the data directory of {gmx} (`gmx --version` "
                                "prints no 'Data prefix'); set GMXDATA")
    return Path(m.group(1)) / "share" / "gromacs" / "top"


def exit_text(rc: int) -> str:
    """How a process ended, for a message: "exit 1", or the signal that killed it
    (subprocess gives -N for signal N; a bare "exit -11" hides a segmentation fault)."""
    if rc >= 0:
        return f"exit {rc}"
    try:
        return f"killed by signal {-rc}, {signal.Signals(-rc).name}: {signal.strsignal(-rc)}"
    except ValueError:
        return f"killed by signal {-rc}"


def error_block(text: str, max_lines: int = 40) -> str:
    """The part of GROMACS output that says what went wrong.

    GROMACS frames fatal errors between a dashed line and "For more information
    and tips for troubleshooting"; grompp also prints ERROR n [file, line n]
    blocks. Everything else (the quote, the banner) is noise."""
    lines = text.splitlines()
    picked: list[str] = []
    i = 0
    while i < len(lines):
        ln = lines[i]
        if ln.startswith(("ERROR ", "WARNING ", "Fatal error", "Invalid ")) or "Program:" in ln \
                or "Error in user input" in ln:
            j = i
            while j < len(lines) and not lines[j].startswith("For more information") \
                    and not (j > i and lines[j].startswith("-----")) \
                    and not (j > i and ln.startswith(("WARNING ", "ERROR ")) and not lines[j].strip()):
                picked.append(lines[j])
                j += 1
            picked.append("")
            i = j
        i += 1
    if not picked:  # fall back to the tail, which usually holds the reason
        picked = [ln for ln in lines if ln.strip()][-15:]
    picked = [ln for ln in picked if not ln.startswith("GROMACS reminds you")]
    return "\n".join(picked[:max_lines]).strip()


def run_gmx(gmx: str, args: list[str], cwd: Path, *, stdin: str | None = None,
            log_name: str | None = None, timeout_s: float | None = None) -> subprocess.CompletedProcess:
    """Run `gmx ARGS` in cwd; on failure raise ExternalToolError with GROMACS's own words.

    The full output is kept in cwd/LOG_NAME (default gmx_<tool>.log) so nothing is lost."""
    cwd = Path(cwd)
    cmd = [gmx, *args]
    try:
        proc = subprocess.run(cmd, cwd=cwd, input=stdin if stdin is not None else "",
                              capture_output=True, text=True, timeout=timeout_s)
    except subprocess.TimeoutExpired:
        raise ExternalToolError(f"`gmx {args[0]}` did not finish within {timeout_s:g} s of wall time in {cwd}: "
                                "it waits for interactive input, or the machine is too loaded to give it the "
                                "CPU (see `uptime`)") from None
    log = cwd / (log_name or f"gmx_{args[0]}.log")
    log.write_text(f"$ {' '.join(cmd)}\n--- stdout\n{proc.stdout}\n--- stderr\n{proc.stderr}")
    if proc.returncode != 0:
        raise ExternalToolError(
            f"`gmx {args[0]}` failed ({exit_text(proc.returncode)}) in {cwd}; full output in {log}:\n"
            + error_block(proc.stderr + "\n" + proc.stdout))
    return proc


def _die_with_parent() -> None:
    """In the child, before exec (Linux): SIGTERM when the process that started it dies.

    Without it an mdrun whose dnarod was killed (SIGKILL, a test's timeout, the OOM killer)
    runs on as an orphan, writing into the same md.part.* files a rerun would use; two such
    orphans were seen here holding 1.4 of 2 cores for 1.5 h. TERM, not KILL: mdrun then
    stops at its next step with a checkpoint, as under a batch system's time limit. (Linux
    ties it to the thread that started the child; run_gmx_with_progress waits in that thread.)"""
    if _LIBC is not None:
        _LIBC.prctl(_PR_SET_PDEATHSIG, signal.SIGTERM, 0, 0, 0)


# looked up in the parent: the child, between fork and exec, only makes the call
_LIBC = ctypes.CDLL(None, use_errno=True) if sys.platform == "linux" else None
_PR_SET_PDEATHSIG = 1        # <linux/prctl.h>


def run_gmx_with_progress(gmx: str, args: list[str], cwd: Path, *, log_name: str,
                          on_step=None, append_log: bool = False, watch=None,
                          watch_every_s: float = 2.0, env: dict | None = None) -> None:
    """Run gmx (mdrun -v) calling on_step(step) for each of its step reports;
    ExternalToolError on failure.

    mdrun reports "step N, will finish ..." (dynamics) or "Step=  N, Dmax= ..."
    (minimisation) on stderr with carriage returns; we read it as it comes. The whole
    output goes to cwd/LOG_NAME (appended to it with append_log, e.g. when a run
    continues from its checkpoint).

    WATCH, if given, is called every WATCH_EVERY_S seconds while gmx runs, from a
    thread of its own (so also while gmx prints nothing); a string it returns stops gmx
    with SIGKILL (an mdrun stuck inside a step never reads TERM) and is the failure's
    reason. The error's returncode is then None: the kill was ours, not the user's.
    ENV: gmx's environment (default: this process's)."""
    cwd = Path(cwd)
    cmd = [gmx, *args]
    log = cwd / log_name
    chunks: list[str] = []
    stopped: list[str] = []
    with subprocess.Popen(cmd, cwd=cwd, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, text=True, bufsize=1, env=env,
                          preexec_fn=_die_with_parent) as proc:
        finished = threading.Event()
        if watch is not None:
            def guard():
                while not finished.wait(watch_every_s):
                    reason = watch()
                    if reason and proc.poll() is None:
                        stopped.append(reason)
                        proc.kill()
                        return
            threading.Thread(target=guard, daemon=True).start()
        buf = ""
        assert proc.stdout is not None
        while True:
            c = proc.stdout.read(1)
            if not c:
                break
            chunks.append(c)
            if c in "\r\n":
                m = re.match(r"\s*(?:imb F\s+\S+\s+)?(?:step\s+|Step=\s*)(\d+)", buf)
                if m and on_step is not None:
                    on_step(int(m.group(1)))
                buf = ""
            else:
                buf += c
        rc = proc.wait()
        finished.set()
    text = "".join(chunks)
    with open(log, "a" if append_log else "w") as f:
        f.write(f"$ {' '.join(cmd)}\n{text}")
        if stopped:
            f.write(f"\n[stopped by dnarod: {stopped[0]}]\n")
    if stopped:
        raise ExternalToolError(f"`gmx {args[0]}` failed (stopped by dnarod: {stopped[0]}) in {cwd}; "
                                f"full output in {log}:\n" + error_block(text), returncode=None)
    if rc != 0:
        raise ExternalToolError(f"`gmx {args[0]}` failed ({exit_text(rc)}) in {cwd}; full output in "
                                f"{log}:\n" + error_block(text), returncode=rc)
