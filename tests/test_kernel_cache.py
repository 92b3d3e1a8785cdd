"""numba's cache kept consistent with the sources (:mod:`fvbeam.kernel_cache`): a change in a
module a kernel calls or reads empties the cache of the kernel's module; a change anywhere
else, or none, keeps it."""

from __future__ import annotations

from pathlib import Path

import pytest

import fvbeam
from fvbeam import kernel_cache
from fvbeam.kernel_cache import STAMP, guard, sources

ROOT = Path(fvbeam.__file__).parent.parent


@pytest.fixture(autouse=True)
def fresh_reads():
    """Each guard below sees the files as they are (a process reads them once)."""
    kernel_cache._read.cache_clear()
    kernel_cache._module_file.cache_clear()
    yield
    kernel_cache._read.cache_clear()
    kernel_cache._module_file.cache_clear()


MODULES = {
    "fvbeam/__init__.py": "",
    "fvbeam/low.py": "import numba\n\n@numba.njit(cache=True)\ndef f(x):\n    return x\n",
    "fvbeam/constants.py": "from fvbeam.base import UNIT\n\nSCALE = 2.0 * UNIT\n",
    "fvbeam/base.py": "UNIT = 1.0\n",
    "fvbeam/typing_only.py": "class Thing:\n    pass\n",
    "fvbeam/unrelated.py": "def helper():\n    return 1\n",
    "sliders/__init__.py": "",
    "sliders/high.py": (
        "from typing import TYPE_CHECKING\n\nimport numba\n\nfrom fvbeam import constants\n"
        "from fvbeam.low import (\n    f,\n)\n\nif TYPE_CHECKING:\n"
        "    from fvbeam.typing_only import Thing\n\n"
        "@numba.njit(cache=True)\ndef g(x):\n    return f(x) * constants.SCALE\n"
    ),
}


def tree(root: Path) -> Path:
    """The modules of :data:`MODULES` under ``root``, each kernel module with a cache file
    (numba's names: ``MODULE.FUNCTION-LINE.pyXY.nbi`` and ``.nbc``); the caller's path."""
    for name, text in MODULES.items():
        path = root / name
        path.parent.mkdir(exist_ok=True)
        path.write_text(text)
    for name in ("fvbeam/low", "sliders/high"):
        cache(root / f"{name}.py")
    return root / "sliders/high.py"


def cache(module: Path) -> None:
    (module.parent / "__pycache__").mkdir(exist_ok=True)
    for suffix in ("nbi", "1.nbc"):
        (module.parent / "__pycache__" / f"{module.stem}.g-8.py311.{suffix}").write_text("x")


def cached(package: Path) -> list[str]:
    return sorted(p.name for p in package.rglob("*.nb[ic]"))


def edit(path: Path) -> None:
    kernel_cache._read.cache_clear()  # a new process
    path.write_text(path.read_text() + "# edited\n")


def test_sources_are_the_kernels_closure(tmp_path: Path) -> None:
    high = tree(tmp_path)
    names = [p.relative_to(tmp_path.resolve()).as_posix() for p in sources(high)]
    # the callee, the module of constants it reads and what that reads, the package; not
    # what is imported for type checking only, nor what nothing imports
    assert names == [
        "fvbeam/__init__.py",
        "fvbeam/base.py",
        "fvbeam/constants.py",
        "fvbeam/low.py",
        "sliders/high.py",
    ]


def test_a_change_in_a_callee_empties_the_callers_cache(tmp_path: Path) -> None:
    high = tree(tmp_path)
    guard(high)  # first import: no stamp, the cache of unknown origin goes
    assert cached(tmp_path / "sliders") == []
    assert (high.parent / "__pycache__" / f"high.{STAMP}").is_file()
    cache(high)  # compiled anew
    guard(high)
    assert cached(tmp_path / "sliders") == ["high.g-8.py311.1.nbc", "high.g-8.py311.nbi"]
    for elsewhere in ("fvbeam/unrelated.py", "fvbeam/typing_only.py"):
        edit(tmp_path / elsewhere)
        guard(high)
        assert len(cached(tmp_path / "sliders")) == 2, elsewhere  # not among its sources: kept
    edit(tmp_path / "fvbeam/low.py")
    guard(high)
    assert cached(tmp_path / "sliders") == []  # a callee changed: the caller's cache is stale
    assert len(cached(tmp_path / "fvbeam")) == 2  # low's own cache: numba's index checks it


@pytest.mark.parametrize("module", ["fvbeam/constants.py", "fvbeam/base.py"])
def test_a_change_in_a_read_constant_empties_the_cache(tmp_path: Path, module: str) -> None:
    """A constant the kernel reads, directly or through the module that defines it."""
    high = tree(tmp_path)
    guard(high)
    cache(high)
    edit(tmp_path / module)
    guard(high)
    assert cached(tmp_path / "sliders") == []


def test_the_projects_kernels_depend_on_their_callees_only() -> None:
    """The compiled time step's sources hold the Newton loop, the joints', lines' and test
    functions' kernels, and none of the application; the test functions' hold no slider
    module."""
    step = {
        p.relative_to(ROOT).as_posix() for p in sources(ROOT / "sliders/solve/dynamics_kernel.py")
    }
    assert {
        "sliders/solve/newton_kernel.py",
        "sliders/joints/packed.py",
        "sliders/lines/batched_kernel.py",
        "fvbeam/pointwise.py",
    } <= step
    assert not {p for p in step if p.startswith("sliders/app/")}
    assert "fvbeam/kernel_cache.py" not in step  # the guard is never compiled
    pointwise = {p.relative_to(ROOT).as_posix() for p in sources(ROOT / "fvbeam/pointwise.py")}
    assert not {p for p in pointwise if p.startswith("sliders/")}


def test_every_module_of_cached_kernels_is_guarded() -> None:
    unguarded = [
        path.relative_to(ROOT).as_posix()
        for package in ("fvbeam", "sliders")
        for path in sorted((ROOT / package).rglob("*.py"))
        if "cache=True" in (text := path.read_text()) and "\nguard(__file__)" not in text
    ]
    assert unguarded == []
