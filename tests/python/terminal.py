"""Running a command as on a terminal, for the progress tests: stderr on a
pseudo-terminal, and the progress lines it drew (dnarod.progress's one format)."""
import os
import re
import subprocess
import time

from dnarod.progress import parse_line


def in_terminal(cmd, *, cwd=None, env=None, timeout=600) -> tuple[int, str]:
    """Run CMD with stderr on a pseudo-terminal (stdout to a pipe); (exit code, what the
    terminal received)."""
    master, slave = os.openpty()
    try:
        p = subprocess.Popen([str(c) for c in cmd], stdout=subprocess.DEVNULL, stderr=slave,
                             stdin=subprocess.DEVNULL, cwd=cwd, env=env)
    finally:
        os.close(slave)
    seen = b""
    end = time.time() + timeout
    try:
        while time.time() < end:
            try:
                chunk = os.read(master, 65536)
            except OSError:        # EIO: the last writer closed the terminal
                break
            if not chunk:
                break
            seen += chunk
        rc = p.wait(timeout=max(1.0, end - time.time()))
    finally:
        os.close(master)
        if p.poll() is None:
            p.kill()
    return rc, seen.decode(errors="replace")


def progress_lines(text: str) -> list[dict]:
    """Every progress line drawn: live redraws (carriage return, erase-line) and plain
    lines alike, parsed with the one format (dnarod.progress.parse_line)."""
    out = []
    for piece in re.split(r"[\r\n]", text.replace("\033[K", "")):
        p = parse_line(piece)
        if p:
            out.append(p)
    return out
