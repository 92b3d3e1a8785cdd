"""Atomic file output: a result file (or directory of files) is either the old one or the
complete new one."""

from __future__ import annotations

import os
import shutil
import tempfile
from collections.abc import Callable
from pathlib import Path


def _umask() -> int:
    """The process's file-creation mask (read by setting it and putting it back)."""
    umask = os.umask(0)
    os.umask(umask)
    return umask


def write_atomic(path: str | Path, write: Callable[[Path], None]) -> None:
    """Call ``write(tmp)`` on a temporary file beside ``path``, then rename it onto ``path``.

    The temporary file keeps the target's suffix so that writers choosing a format by
    extension (meshio, matplotlib) behave as for the final name.  On any error the
    temporary file is removed and ``path`` is left untouched.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, name = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=path.suffix, dir=path.parent)
    os.close(fd)
    tmp = Path(name)
    try:
        write(tmp)
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)


#: The file :func:`replace_directory` leaves in every directory it fills.
OUTPUT_MARKER = ".fvslider-output"


def check_replaceable(path: str | Path, marker: str = OUTPUT_MARKER) -> None:
    """``ValueError`` unless :func:`replace_directory` may replace ``path``: absent, an empty
    directory, or a directory holding the file ``marker``."""
    path = Path(path)
    if path.exists() and (
        not path.is_dir() or (any(path.iterdir()) and not (path / marker).is_file())
    ):
        raise ValueError(
            f"{path} exists and was not written by this program (no {marker} "
            "in it); choose another output directory"
        )


def replace_directory(
    path: str | Path, fill: Callable[[Path], None], marker: str = OUTPUT_MARKER
) -> None:
    """Call ``fill(tmp)`` on a new temporary directory beside ``path``, then put it in the
    place of ``path``: afterwards ``path`` holds exactly what ``fill`` wrote, never a mix of
    old and new files.

    ``path`` must be absent, empty, or hold the file ``marker``, which this function writes
    into every directory it fills (so that it never replaces a directory it did not write);
    otherwise ``ValueError`` and nothing changes.  On any error in ``fill`` the temporary
    directory is removed and ``path`` is left untouched.  The old directory is renamed aside
    before the new one takes its name, then removed: an interruption between the two renames
    leaves ``path`` missing and both directories beside it, not a mix.
    """
    path = Path(path)
    check_replaceable(path, marker)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{path.name}.", dir=path.parent))
    try:
        fill(tmp)
        (tmp / marker).write_text(
            "written by fvslider; the whole directory is replaced on the next run\n"
        )
        if path.exists():
            old = Path(tempfile.mkdtemp(prefix=f".{path.name}.old.", dir=path.parent))
            os.replace(path, old)
            os.replace(tmp, path)
            shutil.rmtree(old)
        else:
            os.replace(tmp, path)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
