"""Nothing lost on a failed rebuild: a command that writes a set of files into a folder
writes them into a temporary folder beside it, and moves them in only when it succeeds
(docs/reliability.md). A failed or interrupted build leaves the folder as it was."""
from __future__ import annotations

import os
import shutil
import tempfile
from contextlib import contextmanager
from pathlib import Path


@contextmanager
def written_on_success(folder, last: str | None = None, stale: tuple[str, ...] = ()):
    """Yield a new temporary folder beside FOLDER (same file system, so the moves are
    renames). On success each file written there replaces its namesake in FOLDER (made if
    missing); files of FOLDER that the command did not write stay, except the names in
    STALE, which are removed first (records of an earlier run that no longer apply). LAST
    is moved last, so that a folder with it is complete. On failure FOLDER is untouched
    and the temporary folder removed."""
    folder = Path(os.path.abspath(folder))
    folder.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(dir=folder.parent, prefix=f".{folder.name}.new-"))
    umask = os.umask(0)
    os.umask(umask)
    tmp.chmod(0o777 & ~umask)
    try:
        yield tmp
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
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
