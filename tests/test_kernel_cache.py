"""numba's cache kept consistent with the sources (:mod:`fvbeam.kernel_cache`): a change in a
module a kernel calls empties the cache of the package that calls it; an unchanged tree
keeps it."""

from __future__ import annotations

from pathlib import Path

from fvbeam.kernel_cache import STAMP, guard


def tree(root: Path) -> tuple[Path, Path]:
    """Two packages, ``low`` and ``high`` (whose kernels call ``low``'s), each with a cache
    file in its ``__pycache__``."""
    for name in ("low", "high"):
        package = root / name
        (package / "__pycache__").mkdir(parents=True)
        (package / "__init__.py").write_text("")
        (package / "kernel.py").write_text(f"# {name}\n")
        (package / "__pycache__" / "kernel.f-1.py311.nbi").write_text("index")
        (package / "__pycache__" / "kernel.f-1.py311.1.nbc").write_text("code")
    return root / "low", root / "high"


def cached(package: Path) -> list[str]:
    return sorted(p.name for p in package.rglob("*.nb[ic]"))


def test_a_change_below_empties_the_callers_cache(tmp_path: Path) -> None:
    low, high = tree(tmp_path)
    guard(high, [low, high])  # first import: no stamp, the cache of unknown origin goes
    assert cached(high) == [] and (high / "__pycache__" / STAMP).is_file()
    (high / "__pycache__" / "kernel.f-1.py311.nbi").write_text("index")  # compiled anew
    guard(high, [low, high])
    assert cached(high) == ["kernel.f-1.py311.nbi"]  # same sources: kept
    (low / "kernel.py").write_text("# low, edited\n")
    guard(high, [low, high])
    assert cached(high) == []  # a callee changed: the caller's cache is stale
    assert cached(low) == ["kernel.f-1.py311.1.nbc", "kernel.f-1.py311.nbi"]  # not guarded here
