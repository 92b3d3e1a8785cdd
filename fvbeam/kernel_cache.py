"""Numba's on-disk cache kept consistent with the sources it was compiled from.

Numba keeps a compiled function beside its module (``__pycache__/NAME.FUNCTION-LINE.*.nbi``,
``*.nbc``) and checks it against that module's file only.  A kernel that calls kernels of
other modules (the compiled Newton loop calls the joints', which call the lines' and the test
functions') is cached with their code inside it, so after an edit or an upgrade that changes
a callee's module but not the caller's, numba would load the caller compiled against the old
callee: wrong results, silently.

Each module of kernels calls :func:`guard` with its own file when it is imported, before any
of its kernels runs.  :func:`guard` keeps a digest of that module's sources
(:func:`sources`: the module and every module of the guarded packages it imports, directly
or through others) beside its cache; when the digest changes, it deletes that module's cache
files, so its kernels compile again from the sources as they are.  An edit elsewhere (a
module no kernel's module imports: the application, the scenes' checks, the studies) leaves
every cache alone.  It costs reading those modules once per process (a few tens of files),
about what a digest of every module of both packages cost.
"""

from __future__ import annotations

import hashlib
import re
from functools import cache
from pathlib import Path

#: The packages whose modules a kernel's cache depends on (importable side by side).
PACKAGES = ("fvbeam", "sliders")
#: The stamp of a module ``NAME.py``: ``__pycache__/NAME.`` followed by this.
STAMP = "kernel-sources.sha256"

_FROM = re.compile(r"^[ \t]*from[ \t]+([\w.]+)[ \t]+import[ \t]+(\([^)]*\)|[^\n]*)", re.MULTILINE)
_IMPORT = re.compile(r"^[ \t]*import[ \t]+([\w., ]+)", re.MULTILINE)
#: An ``if TYPE_CHECKING:`` block: the line and the indented (or blank) lines after it.
_TYPE_CHECKING = re.compile(r"^if TYPE_CHECKING:\n(?:(?:[ \t]+.*)?\n)*", re.MULTILINE)


@cache
def _module_file(root: Path, name: str) -> Path | None:
    """The file of module ``name`` under ``root`` (the directory holding the packages), or
    None when it is not one of :data:`PACKAGES`' modules."""
    if name.split(".")[0] not in PACKAGES:
        return None
    base = root.joinpath(*name.split("."))
    for candidate in (base.with_suffix(".py"), base / "__init__.py"):
        if candidate.is_file():
            return candidate.resolve()
    return None


@cache
def _read(path: Path) -> bytes:
    """The bytes of ``path``, read once per process (modules share their callees; each
    module is guarded once, when it is first imported)."""
    return path.read_bytes()


def imported(source: str, root: Path) -> set[Path]:
    """The files of the guarded packages' modules that ``source`` imports by name, outside
    ``if TYPE_CHECKING:`` blocks: ``from X import a, b`` names ``X`` and its submodules
    ``X.a``, ``X.b`` where they exist; ``import X.Y`` names ``X.Y``."""
    if "TYPE_CHECKING" in source:
        source = _TYPE_CHECKING.sub("", source)
    names: list[str] = []
    for module, items in _FROM.findall(source):
        names.append(module)
        for item in re.split(r"[\s,()]+", items.split("#")[0]):
            if item and item != "as" and item.isidentifier():
                names.append(f"{module}.{item}")
    for group in _IMPORT.findall(source):
        names += [part.split(" as ")[0].strip() for part in group.split(",")]
    found = {path for name in names if (path := _module_file(root, name)) is not None}
    return found - {Path(__file__).resolve()}  # the guard itself is never compiled


def sources(module: Path) -> list[Path]:
    """The module ``module`` and every module of :data:`PACKAGES` it imports, directly or
    through the others, sorted: what its compiled kernels may contain (the kernels they
    call, and the constants they read, which numba freezes into the code).  Imports under
    ``if TYPE_CHECKING:`` are not followed (they never run)."""
    module = module.resolve()
    root = _root(module)
    seen, todo = {module}, [module]
    while todo:
        for path in imported(_read(todo.pop()).decode(), root):
            if path not in seen:
                seen.add(path)
                todo.append(path)
    return sorted(seen)


def digest(files: list[Path], root: Path) -> str:
    """The SHA-256 of ``files`` (their names relative to ``root`` and their contents)."""
    sha = hashlib.sha256()
    for source in files:
        sha.update(str(source.relative_to(root)).encode())
        sha.update(_read(source))
    return sha.hexdigest()


def guard(module_file: str | Path) -> None:
    """Delete the numba cache files of the module ``module_file`` when its sources
    (:func:`sources`) differ from those its cache was made from; nothing when its cache
    directory is not writable (an installed copy nobody may change)."""
    module = Path(module_file).resolve()
    directory = module.parent / "__pycache__"
    stamp = directory / f"{module.stem}.{STAMP}"
    current = digest(sources(module), _root(module))
    try:
        if stamp.is_file() and stamp.read_text() == current:
            return
        for suffix in ("nbi", "nbc"):
            for cached in directory.glob(f"{module.stem}.*.{suffix}"):
                cached.unlink(missing_ok=True)
        directory.mkdir(exist_ok=True)
        stamp.write_text(current)
    except OSError:
        return


def _root(module: Path) -> Path:
    """The directory holding the top package of ``module`` (its first ancestor that is not
    a package)."""
    return next(p for p in module.parents if not (p / "__init__.py").is_file())
