"""The checks every `dnarod` command makes on its files and numbers before it does any work
(docs/reliability.md, "Bad input"): each failure is an InputError (exit 2) that names the
option, the path or value, and what is allowed.

  outputs  writable, and not an existing file of the other kind (a folder where a file is
           written, a file where a folder is). An output folder that holds another command's
           output (its marker file, OUTPUT_MARKERS) is refused: the two would mix, and a
           rebuild replaces the files it writes (workflows/staging.py). A missing parent folder is created, like
           `mkdir -p`, the same for every command; the folders made are removed again if the
           command then fails and they are still empty (remove_made_folders, called by
           workflows/cli.py). Writability is tried, not inferred from permission bits:
           root may write almost anywhere, but not under a regular file or under /proc.
  inputs   exist, are of the right kind (file or folder), are readable and not empty; a
           text format (TOML, YAML, CSV) is "not a TOML file" when its bytes are binary.
  numbers  finite, and in range.

The argparse types (finite, integer) refuse at parse time, which argparse reports with the
option's name and exit 2; the path checks run at the top of each command's run()."""
from __future__ import annotations

import argparse
import math
import os
import tempfile
from pathlib import Path

from dna_models.errors import InputError

# The file that marks each folder command's output: written by every run of it, by no other
# command. A folder holding one is that command's; the same command may write into it again.
OUTPUT_MARKERS = {
    "build-md": "build.json",
    "coarse-grain": "params.json",
    "compare": "results.json",
    "dna-rod": "rest.json",
    "minicircle": "minicircle.json",
    "modes": "modes.json",
    "topology": "topology.json",
}

# folders this process made for outputs, deepest last (remove_made_folders)
_made: list[Path] = []


def _name(option: str | None, path) -> str:
    return f"{option} {path}" if option else f"{path}"


def _reason(e: OSError) -> str:
    return e.strerror or type(e).__name__


def _first_existing(path: Path) -> Path:
    p = path
    while not os.path.lexists(p) and p != p.parent:
        p = p.parent
    return p


def _make_folder(folder: Path, what: str) -> None:
    """Make FOLDER and its missing parents, each recorded; refuse a file in the way."""
    anchor = _first_existing(folder.absolute())
    if not anchor.is_dir():
        raise InputError(f"{what}: {anchor} is a file, not a folder, so nothing can be written under it")
    missing = []
    p = folder.absolute()
    while p != anchor:
        missing.append(p)
        p = p.parent
    for m in reversed(missing):
        try:
            m.mkdir()
        except FileExistsError:
            continue
        except OSError as e:
            raise InputError(f"{what}: cannot create the folder {m} ({_reason(e)})") from None
        _made.append(m)


def _probe(folder: Path, what: str) -> None:
    """Write and remove a file in FOLDER: the one reliable test of writability."""
    try:
        fd, name = tempfile.mkstemp(dir=folder, prefix=".dnarod-write-test-")
        os.close(fd)
        os.unlink(name)
    except OSError as e:
        raise InputError(f"{what}: cannot write in {folder} ({_reason(e)})") from None


def output_file(path, option: str | None = "-o") -> Path:
    """An output file: not a folder; its folder made if missing, and writable. An existing
    file is replaced by the command."""
    p = Path(path)
    what = _name(option, path)
    if p.is_dir():
        raise InputError(f"{what}: is a folder; give a file name (the command writes a file)")
    _make_folder(p.parent if str(p.parent) else Path("."), what)
    if p.exists() and not os.access(p, os.W_OK):
        raise InputError(f"{what}: the existing file cannot be written (permissions)")
    _probe(p.parent, what)
    return p


def output_folder(path, option: str | None = "-o", command: str | None = None) -> Path:
    """An output folder: not an existing file; made (with missing parents) and writable. With
    COMMAND (a key of OUTPUT_MARKERS), a folder holding another command's output is refused."""
    p = Path(path)
    what = _name(option, path)
    if os.path.lexists(p) and not p.is_dir():
        raise InputError(f"{what}: is an existing file, and the command writes a folder: give a folder "
                         "name (a new one, or a folder to write into)")
    if command is not None and p.is_dir():
        if command not in OUTPUT_MARKERS:
            raise ValueError(f"output_folder: {command!r} is not a key of OUTPUT_MARKERS")
        for other, marker in OUTPUT_MARKERS.items():
            if other != command and (p / marker).is_file():
                raise InputError(f"{what}: holds the output of `dnarod {other}` ({p / marker}); `dnarod "
                                 f"{command}` would mix its files with it: give a new folder, or one of "
                                 f"`dnarod {command}`'s own")
    _make_folder(p, what)
    _probe(p, what)
    return p


def remove_made_folders() -> None:
    """After a failure: remove the folders output_file/output_folder made that are still
    empty, deepest first, so that a refused command leaves nothing behind."""
    while _made:
        p = _made.pop()
        try:
            p.rmdir()
        except OSError:
            pass


def input_file(path, option: str | None = None, kind: str | None = None) -> Path:
    """An input file: exists, is a file, is readable and not empty. KIND ("TOML", "YAML",
    "CSV", ...) names a text format: then binary bytes (a NUL, or not UTF-8) are refused."""
    p = Path(path)
    what = _name(option, path)
    a = f"a {kind} file" if kind else "a file"
    if p.is_dir():
        raise InputError(f"{what}: is a folder; {a} is expected")
    if not p.exists():
        raise InputError(f"{what}: no such file ({a} is expected)")
    try:
        with open(p, "rb") as f:
            head = f.read(65536)
    except OSError as e:
        raise InputError(f"{what}: cannot read it ({_reason(e)})") from None
    if not head:
        raise InputError(f"{what}: empty file; {a} is expected")
    if kind is not None and not _is_text(head):
        raise InputError(f"{what}: not a {kind} file (its bytes are binary)")
    return p


def _is_text(head: bytes) -> bool:
    if b"\0" in head:
        return False
    try:
        head.decode("utf-8")
    except UnicodeDecodeError as e:
        # a multi-byte character cut by the 64 KiB read is still text
        return e.start >= len(head) - 3 and e.reason == "unexpected end of data"
    return True


def input_folder(path, option: str | None = None, what_folder: str = "a folder") -> Path:
    """An input folder: exists and is a folder."""
    p = Path(path)
    what = _name(option, path)
    if not p.exists():
        raise InputError(f"{what}: no such folder ({what_folder} is expected)")
    if not p.is_dir():
        raise InputError(f"{what}: is a file; {what_folder} is expected")
    return p


def number(value, option: str, *, min: float | None = None, max: float | None = None,
           above: float | None = None, below: float | None = None) -> float:
    """VALUE as a finite float in range: >= min, <= max, > above, < below (those given)."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{option} {value!r}: not a number") from None
    allowed = _allowed(min, max, above, below)
    if not math.isfinite(x):
        raise InputError(f"{option} {value}: not a finite number (allowed: {allowed})")
    if ((min is not None and x < min) or (max is not None and x > max) or (above is not None and x <= above)
            or (below is not None and x >= below)):
        raise InputError(f"{option} {value}: out of range (allowed: {allowed})")
    return x


def _allowed(min, max, above, below) -> str:
    parts = [f">= {min:g}" if min is not None else "", f"> {above:g}" if above is not None else "",
             f"<= {max:g}" if max is not None else "", f"< {below:g}" if below is not None else ""]
    return " and ".join(p for p in parts if p) or "any finite number"


def finite(min: float | None = None, max: float | None = None, above: float | None = None,
           below: float | None = None):
    """An argparse type: a finite float in range (argparse names the option, exit 2)."""
    def parse(text: str) -> float:
        try:
            return number(text, "", min=min, max=max, above=above, below=below)
        except InputError as e:
            raise argparse.ArgumentTypeError(str(e).strip()) from None
    parse.__name__ = "number"
    return parse


def integer(min: int | None = None, max: int | None = None):
    """An argparse type: an integer in range."""
    def parse(text: str) -> int:
        try:
            n = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r}: not an integer") from None
        if (min is not None and n < min) or (max is not None and n > max):
            allowed = " and ".join(s for s in (f">= {min}" if min is not None else "",
                                               f"<= {max}" if max is not None else "") if s)
            raise argparse.ArgumentTypeError(f"{n}: out of range (allowed: {allowed})")
        return n
    parse.__name__ = "integer"
    return parse
