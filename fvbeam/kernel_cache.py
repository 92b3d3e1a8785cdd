"""Numba's on-disk cache kept consistent with the sources it was compiled from.

Numba keeps a compiled function beside its module (``__pycache__/*.nbi``, ``*.nbc``) and
checks it against that module's file only.  A kernel that calls kernels of other modules
(the compiled Newton loop calls the joints', which call the lines' and the test functions')
is cached with their code inside it, so after an edit or an upgrade that changes a callee's
module but not the caller's, numba would load the caller compiled against the old callee:
wrong results, silently.  :func:`guard` keeps a digest of every module of the packages whose
kernels call each other; when it changes, it deletes their cache files first, so the
kernels compile again from the sources as they are.  It costs a hash of the packages'
sources at import (a few milliseconds).
"""

from __future__ import annotations

import hashlib
from pathlib import Path

#: The stamp file, in each guarded package's ``__pycache__``.
STAMP = "kernel-sources.sha256"


def digest(packages: list[Path]) -> str:
    """The SHA-256 of every ``.py`` file under ``packages`` (names and contents, in order)."""
    sha = hashlib.sha256()
    for package in packages:
        for source in sorted(package.rglob("*.py")):
            sha.update(str(source.relative_to(package.parent)).encode())
            sha.update(source.read_bytes())
    return sha.hexdigest()


def guard(own: Path, packages: list[Path]) -> None:
    """Delete the numba cache files under ``own`` when the sources of ``packages`` (``own``
    and the packages its kernels call) differ from those its cache was made from; nothing
    when the directory is not writable (an installed copy nobody may change)."""
    stamp = own / "__pycache__" / STAMP
    current = digest(packages)
    try:
        if stamp.is_file() and stamp.read_text() == current:
            return
        for cached in [*own.rglob("*.nbi"), *own.rglob("*.nbc")]:
            cached.unlink(missing_ok=True)
        stamp.parent.mkdir(exist_ok=True)
        stamp.write_text(current)
    except OSError:
        return
