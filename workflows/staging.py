"""Nothing lost on a failed rebuild: a command that writes a set of files into a folder
writes them into FOLDER.building beside it, and moves them in only when it succeeds
(docs/reliability.md). A failed or interrupted build leaves FOLDER as it was, and its own
files (the logs its error message names) in FOLDER.building until the next attempt."""
from __future__ import annotations

import os
import shutil
import sys
from contextlib import contextmanager
from pathlib import Path


@contextmanager
def written_on_success(folder, last: str | None = None, stale: tuple[str, ...] = ()):
    """Yield FOLDER.building, new and empty (on the same file system, so the moves are
    renames). On success each file written there replaces its namesake in FOLDER (made if
    missing); files of FOLDER that the command did not write stay, except the names in
    STALE, which are removed first (records of an earlier run that no longer apply). LAST
    is moved last, so that a folder with it is complete. On failure FOLDER is untouched;
    FOLDER.building is removed if empty, else kept for its logs, and said so."""
    folder = Path(os.path.abspath(folder))
    folder.mkdir(parents=True, exist_ok=True)
    tmp = folder.with_name(folder.name + ".building")
    _remove(tmp)
    tmp.mkdir()
    try:
        yield tmp
    except BaseException:
        if any(tmp.iterdir()):
            print(f"{folder.name}: left as it was; the failed build's files are in {tmp}", file=sys.stderr)
        else:
            tmp.rmdir()
        raise
    for name in stale + ((last,) if last else ()):
        _remove(folder / name)
    names = sorted(p.name for p in tmp.iterdir())
    if last in names:
        names.remove(last)
        names.append(last)
    for name in names:
        _remove(folder / name)
        os.replace(tmp / name, folder / name)
    tmp.rmdir()


def _remove(p: Path) -> None:
    if p.is_dir() and not p.is_symlink():
        shutil.rmtree(p)
    elif os.path.lexists(p):
        p.unlink()
