"""Atomic file output: a result file (or directory of files) is either the old one or the
complete new one; the checks that an output location can be written, made before any work;
and the removal of what a killed run left behind.

Every failure to write is an :class:`OutputError` naming the path and the reason in one
line, never a bare ``OSError`` with a temporary name.

:func:`replace_directory` fills a temporary directory ``.NAME.XXXXXXXX`` beside the output
directory ``NAME`` (``XXXXXXXX``: :func:`tempfile.mkdtemp`'s random suffix), which holds the
marker :data:`OUTPUT_MARKER` from its creation on and is locked (``flock``) by its process
while it lives; the previous output is renamed to ``.NAME.old.XXXXXXXX`` before it is
removed.  A run killed meanwhile leaves them behind: :func:`remove_leftovers` removes the
directories beside ``NAME`` with one of these names that hold the marker (or nothing at all)
and that no live process locks, and never anything else.
"""

from __future__ import annotations

import fcntl
import os
import re
import shutil
import stat
import tempfile
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path

#: The file :func:`replace_directory` leaves in every directory it fills.
OUTPUT_MARKER = ".fvslider-output"
#: Length of :func:`tempfile.mkdtemp`'s random suffix, and its characters.
SUFFIX = r"[a-z0-9_]{8}"
#: What the temporary names beside an output directory ``NAME`` add to it: the leading dot,
#: ``.old.`` and the suffix of ``.NAME.old.XXXXXXXX``.
TEMPORARY_EXTRA = len("..old.") + 8


class OutputError(ValueError, OSError):
    """An output location that cannot be written: the path and the reason, in one line.

    A ``ValueError`` (a bad output path is bad input, like a bad scene) and an ``OSError``
    (what code that catches failed writes expects)."""


def _umask() -> int:
    """The process's file-creation mask (read by setting it and putting it back)."""
    umask = os.umask(0)
    os.umask(umask)
    return umask


def _failure(path: Path, exc: OSError, tmp: Path | None = None) -> OutputError:
    """``exc`` as an :class:`OutputError` about ``path``; the temporary file or directory
    ``tmp`` (or a file inside it) is named by where it was going (``path`` for ``tmp``)."""
    where = Path(exc.filename) if exc.filename is not None else path
    if tmp is not None and where.is_relative_to(tmp):
        where = path / where.relative_to(tmp)
    return OutputError(f"cannot write {where}: {exc.strerror or exc}")


def _short(text: str, limit: int = 160) -> str:
    """``text`` cut in the middle to at most ``limit`` characters."""
    if len(text) <= limit:
        return text
    half = (limit - 3) // 2
    return f"{text[:half]}...{text[-half:]}"


def _limit(directory: Path, name: str, default: int) -> int:
    """The filesystem's ``pathconf`` limit ``name`` at ``directory`` (``default`` if it has
    none)."""
    try:
        value = os.pathconf(directory, name)
    except (OSError, ValueError):
        return default
    return value if value > 0 else default


def _nearest_existing(path: Path, extra: int) -> tuple[Path, list[str]]:
    """The longest existing prefix of the absolute ``path`` and the names below it.

    Every existing prefix must be a directory, and the path and its names no longer than
    the filesystem allows, with ``extra`` more bytes for the last name (a temporary name
    made from it); otherwise :class:`OutputError` naming the offending part."""
    shown = f"cannot write {_short(str(path))}"
    existing, names = Path(path.anchor), list(path.parts[1:])
    size, longest = len(os.fsencode(path)), _limit(existing, "PC_PATH_MAX", 4096) - 1 - extra
    if size > longest:
        raise OutputError(f"{shown}: the path is {size} bytes long, at most {longest} here")
    for k, name in enumerate(names):
        last = k == len(names) - 1
        size, longest = len(os.fsencode(name)), _limit(existing, "PC_NAME_MAX", 255)
        if size > longest - (extra if last else 0):
            room = f" ({longest} less {extra} for the temporary names)" if last and extra else ""
            raise OutputError(
                f"{shown}: the name {_short(name, 40)!r} is {size} bytes long, at most "
                f"{longest - (extra if last else 0)} here{room}"
            )
        try:
            mode = os.stat(existing / name).st_mode
        except FileNotFoundError:
            return existing, names[k:]
        except OSError as exc:
            raise OutputError(
                f"{shown}: cannot look up {existing / name} ({exc.strerror or exc})"
            ) from None
        if not stat.S_ISDIR(mode) and not last:
            raise OutputError(f"{shown}: {existing / name} is not a directory")
        existing = existing / name
    return existing, []


def _probe(directory: Path, prefix: str, path: Path) -> None:
    """Create ``directory`` (and its missing parents) and a temporary directory in it named
    ``prefix`` + a random suffix, as a write would, then remove everything created:
    :class:`OutputError` about ``path`` if any of it fails."""
    for attempt in range(3):
        try:
            _probe_once(directory, prefix, path)
            return
        except _Raced:  # another process made or removed a directory on the way meanwhile
            if attempt == 2:
                raise OutputError(
                    f"cannot write {path}: other processes keep creating and removing the "
                    "directories on its way"
                ) from None


class _Raced(Exception):
    """A directory on the way appeared or vanished while :func:`_probe` worked."""


def _probe_once(directory: Path, prefix: str, path: Path) -> None:
    """One attempt of :func:`_probe`: :class:`_Raced` when another process creates or removes
    a directory on the way at the same time (two runs checking one missing parent)."""
    existing, missing = _nearest_existing(directory, 0)
    created: list[Path] = []
    making: Path | None = None
    try:
        for name in missing:
            making = existing = existing / name
            os.mkdir(making)
            created.append(making)
        making = None
        os.rmdir(tempfile.mkdtemp(prefix=prefix, dir=directory))
    except OSError as exc:
        if isinstance(exc, FileExistsError) and making is not None and making.is_dir():
            raise _Raced from None  # made meanwhile by another process
        if isinstance(exc, FileNotFoundError):
            where = making.parent if making is not None else directory
            if not where.is_dir():  # a directory checked a moment ago removed meanwhile
                raise _Raced from None
        action = f"create {making}" if making is not None else f"create entries in {directory}"
        raise OutputError(f"cannot write {path}: cannot {action} ({exc.strerror or exc})") from None
    finally:
        for made in reversed(created):
            try:
                os.rmdir(made)
            except OSError:  # another process wrote in it meanwhile: its own
                pass


def check_writable(directory: str | Path) -> None:
    """:class:`OutputError` unless files can be written into ``directory``: an existing
    directory, or one that can be created, in which this process can create entries.

    Checked by doing it: the missing directories and a temporary one in ``directory`` are
    created and removed again, so that nothing is left and every obstacle (a file in the
    way, permissions, a read-only or pseudo filesystem, an over-long name) is found before
    any work."""
    directory = Path(os.path.abspath(directory))
    _nearest_existing(directory, 0)
    if directory.exists() and not directory.is_dir():
        raise OutputError(f"cannot write {directory}: it is not a directory")
    _probe(directory, ".fvslider-probe.", directory)


def check_replaceable(path: str | Path, marker: str = OUTPUT_MARKER) -> None:
    """:class:`OutputError` unless :func:`replace_directory` may replace ``path``: absent,
    an empty directory, or a directory holding the file ``marker``; its parent writable
    (as :func:`check_writable`) and its name short enough for the temporary names made from
    it."""
    path = Path(os.path.abspath(path))
    _nearest_existing(path, TEMPORARY_EXTRA)
    if path.exists() and (
        not path.is_dir() or (any(path.iterdir()) and not (path / marker).is_file())
    ):
        raise OutputError(
            f"{path} exists and was not written by this program (no {marker} "
            "in it); choose another output directory"
        )
    _probe(path.parent, f".{path.name}.old.", path)


def write_atomic(path: str | Path, write: Callable[[Path], None]) -> None:
    """Call ``write(tmp)`` on a temporary file beside ``path``, then rename it onto ``path``.

    The temporary file keeps the target's suffix so that writers choosing a format by
    extension (meshio, matplotlib) behave as for the final name.  On any error the
    temporary file is removed and ``path`` is left untouched; an ``OSError`` becomes an
    :class:`OutputError` naming ``path``.
    """
    path = Path(path)
    tmp: Path | None = None
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, name = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=path.suffix, dir=path.parent)
        os.close(fd)
        tmp = Path(name)
        write(tmp)
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, path)
    except OSError as exc:
        raise _failure(path, exc, tmp) from None
    finally:
        if tmp is not None:
            tmp.unlink(missing_ok=True)


@contextmanager
def _lock(directory: Path, wait: bool) -> Iterator[bool]:
    """Hold an exclusive ``flock`` on ``directory`` (it follows the directory through
    renames; the kernel drops it when its process dies); yield whether it was taken (always,
    when ``wait``: none other holds it)."""
    fd = os.open(directory, os.O_RDONLY | os.O_DIRECTORY)
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | (0 if wait else fcntl.LOCK_NB))
        except BlockingIOError:
            yield False
            return
        yield True
    finally:
        os.close(fd)


#: Beside an output directory ``NAME``, the file ``NAME.lock`` that a run holds locked while
#: it writes ``NAME`` and its checkpoint (:func:`writer`).
WRITER_SUFFIX = ".lock"


@contextmanager
def writer(out: str | Path, who: str) -> Iterator[None]:
    """Be the one writer of the output directory ``out`` (and of what lies beside it, its
    checkpoint) while the block runs: hold an exclusive ``flock`` on ``NAME.lock`` beside it,
    holding ``who`` (the process id is added), and remove the file at the end.  Another
    process holding it is an :class:`OutputError` naming it and what it wrote there.

    The kernel drops the lock of a process that dies, so a killed run's ``NAME.lock`` is
    taken over by the next run.  The file is removed while locked, and a lock taken on a file
    that is no longer the one at its path (removed by the writer before) is taken again, so
    two runs never both hold the lock of the path."""
    out = Path(out)
    out = out if out.name else out.absolute()
    path = out.with_name(out.name + WRITER_SUFFIX)
    try:  # where the run writes its output and checkpoint in any case
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise _failure(path.parent, exc) from None
    with _held(path, out, who):
        yield


@contextmanager
def _held(path: Path, out: Path, who: str) -> Iterator[None]:
    """The lock of :func:`writer` on the file ``path`` beside ``out``."""
    while True:
        try:
            fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o666)
        except OSError as exc:
            raise _failure(path, exc) from None
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = os.read(fd, 4096).decode(errors="replace").strip() or "another process"
            os.close(fd)
            raise OutputError(
                f"cannot write {out}: another fvslider run is writing it ({holder}); "
                "wait for it to end or choose another output directory"
            ) from None
        try:
            same = os.fstat(fd).st_ino == os.stat(path).st_ino
        except FileNotFoundError:
            same = False
        if same:
            break
        os.close(fd)  # removed by the writer that held it: take the new file's lock
    try:
        os.ftruncate(fd, 0)
        os.write(fd, f"pid {os.getpid()}: {who}\n".encode())
        yield
    finally:
        path.unlink(missing_ok=True)
        os.close(fd)


def _temporary_names(path: Path) -> re.Pattern[str]:
    """The names of :func:`replace_directory`'s temporary directories beside ``path``."""
    return re.compile(rf"\.{re.escape(path.name)}\.(old\.)?{SUFFIX}")


def remove_leftovers(path: str | Path, marker: str = OUTPUT_MARKER) -> list[Path]:
    """Remove what killed runs of :func:`replace_directory` into ``path`` left beside it; return
    what was removed.

    Removed are the directories (not links) beside ``path`` named ``.NAME.XXXXXXXX`` or
    ``.NAME.old.XXXXXXXX`` (``NAME`` the name of ``path``) that hold the file ``marker``, or
    nothing, and that no live process locks: the temporary directories of runs that died.
    Anything else is left alone.  The list is in the order of the names."""
    path = Path(os.path.abspath(path))
    names = _temporary_names(path)
    try:
        entries = sorted(
            (e for e in os.scandir(path.parent) if names.fullmatch(e.name)), key=lambda e: e.name
        )
    except (FileNotFoundError, NotADirectoryError):
        return []
    except OSError as exc:
        raise _failure(path.parent, exc) from None
    removed = []
    for entry in entries:
        candidate = Path(entry.path)
        try:
            if not entry.is_dir(follow_symlinks=False):
                continue
            with _lock(candidate, wait=False) as free:
                inside = os.listdir(candidate)
                ours = not inside or (marker in inside and (candidate / marker).is_file())
                if not free or not ours:
                    continue
                shutil.rmtree(candidate)
        except FileNotFoundError:
            continue
        except OSError as exc:
            raise _failure(candidate, exc) from None
        removed.append(candidate)
    return removed


def replace_directory(
    path: str | Path, fill: Callable[[Path], None], marker: str = OUTPUT_MARKER
) -> None:
    """Call ``fill(tmp)`` on a new temporary directory beside ``path``, then put it in the
    place of ``path``: afterwards ``path`` holds exactly what ``fill`` wrote, never a mix of
    old and new files.

    ``path`` must be absent, empty, or hold the file ``marker``, which this function writes
    into every directory it fills (so that it never replaces a directory it did not write);
    otherwise :class:`OutputError` and nothing changes (:func:`check_replaceable`).  The
    leftovers of killed runs into ``path`` are removed first (:func:`remove_leftovers`).  On
    any error in ``fill`` the temporary directory is removed and ``path`` is left untouched;
    an ``OSError`` becomes an :class:`OutputError` naming the file.  The old directory is
    renamed aside before the new one takes its name, then removed: an interruption between
    the two renames leaves ``path`` missing and both directories beside it, not a mix, and
    the next run removes them.
    """
    path = Path(path)
    check_replaceable(path, marker)
    remove_leftovers(path, marker)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = Path(tempfile.mkdtemp(prefix=f".{path.name}.", dir=path.parent))
    except OSError as exc:
        raise _failure(path, exc) from None
    try:
        with _lock(tmp, wait=True):
            (tmp / marker).write_text(
                "written by fvslider; the whole directory is replaced on the next run\n"
            )
            fill(tmp)
            if path.exists():
                old = Path(tempfile.mkdtemp(prefix=f".{path.name}.old.", dir=path.parent))
                os.replace(path, old)
                os.replace(tmp, path)
                shutil.rmtree(old, ignore_errors=True)
            else:
                os.replace(tmp, path)
    except OSError as exc:
        raise _failure(path, exc, tmp) from None
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
