"""The package as a user installs it: the wheel built from the checkout, installed into a fresh
virtual environment, and ``fvslider`` run there from a directory outside the checkout.

Offline, about 15 s.  The wheel is built without build isolation (setuptools is in the
``test`` extra) from a copy of the sources, so the checkout gets no ``build/`` or
``*.egg-info``.  The new environment gets the wheel alone (``--no-deps``) and finds the
dependencies on this interpreter's import path through a ``.pth`` file.  A directory named
in a ``.pth`` file is not scanned for ``.pth`` files itself, so an editable install of the
checkout here (``make test`` makes one) stays inactive there, and the wheel's metadata comes
first on the new environment's path.  The numba kernels fig1 needs compile into the
installed copy's cache on first use (a few seconds).
"""

from __future__ import annotations

import csv
import json
import os
import shutil
import subprocess
import sys
import tomllib
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
CONFIG = tomllib.loads((ROOT / "pyproject.toml").read_text())
SETUPTOOLS = CONFIG["tool"]["setuptools"]
#: Installed top-level package -> the directory of the checkout that holds it.
DIRECTORIES = {
    package: SETUPTOOLS["package-dir"].get(package, package)
    for package in SETUPTOOLS["packages"]
    if "." not in package
}
STUDIES = set(CONFIG["project"]["entry-points"]["fvslider.studies"])
#: The columns of ``fig1_tip_response.csv`` as README.md documents them, and its rows: the
#: five formulations README.md lists at 101 load stations, ``xi / L = 0, 0.01, ..., 1``.
FIG1_COLUMNS = ["formulation", "xi_over_L", "v_flexural", "v_shear", "phi"]
FIG1_ROWS = 5 * 101
#: Where the new environment imports our packages from, and whether it has a ``studies``.
PROBE = """\
import importlib.util, json
import fvbeam, fvslider_studies, sliders
print(json.dumps({
    "files": [m.__file__ for m in (fvbeam, sliders, fvslider_studies)],
    "studies": importlib.util.find_spec("studies") is not None,
}))
"""


def run(command: list, cwd: Path, hint: str = "") -> str:
    """Run ``command`` from ``cwd`` without ``PYTHONPATH`` (which could name a checkout);
    its standard output.  ``hint`` ends the message if it fails."""
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME")}
    done = subprocess.run(
        [str(c) for c in command],
        cwd=cwd,
        env=env | {"PYTHONNOUSERSITE": "1"},
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 0, f"{command} failed:\n{done.stdout}\n{done.stderr}\n{hint}"
    return done.stdout


def package_files(root: Path) -> set[str]:
    """Every file of the packages under ``root``, named as a wheel names it."""
    return {
        f"{package}/{path.relative_to(root / directory).as_posix()}"
        for package, directory in DIRECTORIES.items()
        for path in (root / directory).rglob("*")
        if path.is_file() and "__pycache__" not in path.parts
    }


def build_wheel(tmp_path: Path) -> Path:
    """The wheel of a copy of the checkout's sources (without its caches)."""
    source = tmp_path / "source"
    for directory in DIRECTORIES.values():
        shutil.copytree(
            ROOT / directory, source / directory, ignore=shutil.ignore_patterns("__pycache__")
        )
    for name in ("pyproject.toml", "README.md"):
        shutil.copy2(ROOT / name, source / name)
    wheels = tmp_path / "wheels"
    pip = [sys.executable, "-m", "pip", "wheel", "-q", "--no-deps", "--no-build-isolation"]
    requires = ", ".join(CONFIG["build-system"]["requires"])
    hint = f"building without isolation needs {requires} here: pip install -e '.[test]'"
    run([*pip, "--no-index", "--wheel-dir", wheels, source], cwd=tmp_path, hint=hint)
    (wheel,) = wheels.glob("fvslider-*.whl")
    return wheel


def dependency_path() -> list[str]:
    """This interpreter's import path less the checkout and its tests (``python -m pytest``
    and pytest put them there): where the new environment finds the dependencies."""
    checkout = {ROOT, ROOT / "tests"}
    return [p for p in sys.path if p and Path(p).resolve() not in checkout]


def install(wheel: Path, environment: Path) -> Path:
    """A new virtual environment at ``environment`` holding ``wheel``, with this environment's
    site-packages for the dependencies; its site-packages."""
    run([sys.executable, "-m", "venv", "--without-pip", environment], cwd=environment.parent)
    script = "import sysconfig; print(sysconfig.get_path('purelib'))"
    site = Path(run([environment / "bin" / "python", "-c", script], cwd=environment).strip())
    (site / "dependencies.pth").write_text("".join(f"{path}\n" for path in dependency_path()))
    pip = [sys.executable, "-m", "pip", "--python", environment / "bin" / "python", "install"]
    run([*pip, "-q", "--no-deps", "--no-index", wheel], cwd=environment)
    return site


@pytest.fixture(scope="module")
def wheel(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return build_wheel(tmp_path_factory.mktemp("wheel"))


def test_wheel_ships_every_module_and_scene_under_its_installed_name(wheel):
    """Every file of fvbeam/, sliders/ and studies/ (as fvslider_studies/: its scenes and
    meshes included), and nothing else; pyproject.toml lists packages one by one."""
    with zipfile.ZipFile(wheel) as archive:
        shipped = {name for name in archive.namelist() if ".dist-info/" not in name}
    assert shipped == package_files(ROOT)
    assert "fvslider_studies/scenes/meshes/arch.msh" in shipped


def test_installed_wheel_reproduces_fig1_outside_the_checkout(wheel, tmp_path):
    """Our packages import from the new environment, ``studies`` is not one of them, the
    entry points list the studies, a shipped scene reads its shipped mesh, and
    ``fvslider reproduce fig1`` writes its CSV and PNG."""
    environment = tmp_path / "env"
    site = install(wheel, environment)
    user = tmp_path / "user"
    user.mkdir()

    probe = json.loads(run([environment / "bin" / "python", "-c", PROBE], cwd=user))
    assert all(Path(file).is_relative_to(site) for file in probe["files"]), probe
    assert not probe["studies"], "a top-level package `studies` is installed"

    fvslider = environment / "bin" / "fvslider"
    listed = {line.split()[0] for line in run([fvslider, "studies"], cwd=user).splitlines()}
    assert listed == STUDIES
    scene = site / "fvslider_studies" / "scenes" / "arch_mesh.toml"
    assert "valid" in run([fvslider, "check", scene], cwd=user)

    run([fvslider, "reproduce", "fig1", "--out", "out"], cwd=user)
    with open(user / "out" / "fig1_tip_response.csv", newline="") as handle:
        rows = list(csv.reader(handle))
    assert rows[0] == FIG1_COLUMNS and len(rows) - 1 == FIG1_ROWS
    assert (user / "out" / "fig1_tip_response.png").is_file()
