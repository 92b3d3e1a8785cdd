"""What a command imports: ``import sliders`` and ``import fvbeam`` load a public name's module
on its first use (PEP 562), so ``fvslider --help`` loads none of the numerical libraries and
``fvslider check`` neither plotting nor rendering.

Each case runs in a fresh interpreter (a subprocess: this one has imported everything) and
reads ``sys.modules`` at its end.
"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest
from test_scenes import SCENES

import fvbeam
import sliders
import sliders.forces

HEAVY = ("numba", "scipy", "skfem", "pydantic", "numpy", "meshio", "matplotlib", "pyvista")


def loaded(code: str) -> set[str]:
    """The packages of :data:`HEAVY` that ``code`` leaves imported, in a fresh interpreter."""
    script = f"""
import json, sys
{code}
print(json.dumps(sorted({{m.split(".")[0] for m in sys.modules}} & set({list(HEAVY)!r}))))
"""
    done = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, check=True
    )
    return set(json.loads(done.stdout.splitlines()[-1]))


def test_help_imports_no_numerical_library():
    code = """
from sliders.app.cli import main
try:
    main(["--help"])
except SystemExit:
    pass
"""
    assert loaded(code) == set()


def test_the_packages_import_their_names_when_used():
    assert loaded("import sliders, fvbeam") == set()
    assert "scipy" in loaded("import fvbeam; fvbeam.Beam")


@pytest.mark.parametrize("scene", ["pushed_body.toml", "arch.toml"])
def test_check_imports_no_plotting_or_rendering(scene, tmp_path):
    code = f"""
from sliders.app.cli import main
assert main(["check", {str(SCENES / scene)!r}, "--out", {str(tmp_path / "out")!r}]) == 0
"""
    imported = loaded(code)
    assert "pydantic" in imported  # it did validate
    assert not imported & {"matplotlib", "pyvista"}


@pytest.mark.parametrize("package", [sliders, fvbeam, sliders.forces], ids=lambda p: p.__name__)
def test_every_public_name_resolves(package):
    assert set(package.__all__) <= set(dir(package))
    for name in package.__all__:
        assert getattr(package, name) is not None, name
    with pytest.raises(AttributeError, match="has no attribute 'nothing'"):
        package.nothing  # noqa: B018


def test_the_run_path_imports_neither_meshio_nor_interpolation():
    """What ``fvslider run`` imports to solve and write a scene of beams, sliders and
    drives: meshio is read where a mesh file is read or a VTU written, scipy's interpolation
    where a spline line, a cubic drive table or a curved line's frames need it."""
    code = """
import sliders.app.cli, sliders.app.run, sliders.app.run_dynamic, sliders.app.tables
import sliders.app.model
print(json.dumps(sorted(m for m in ("meshio", "scipy.interpolate") if m in sys.modules)))
raise SystemExit
"""
    script = f"import json, sys\n{code}"
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert json.loads(done.stdout.splitlines()[-1]) == []


#: What a static run of beams, loads and supports does not use: the time integration and
#: its recording, the modes (and scipy's optimisation they match modes with), the exact
#: joints (and scipy's rotations), scipy's special functions (a rectangle's torsion series),
#: the moving load and user laws (scipy's differentiation), plotting and rendering.
STATIC_UNUSED = (
    "sliders.solve.dynamics",
    "sliders.solve.dynamics_kernel",
    "sliders.app.run_dynamic",
    "sliders.app.render",
    "sliders.solve.modes",
    "sliders.joints.exact_model",
    "sliders.forces.moving_load",
    "sliders.forces.user",
    "scipy.optimize",
    "scipy.special",
    "scipy.spatial",
    "scipy.differentiate",
    "matplotlib",
    "pyvista",
)

CANTILEVER = """
kinematics = "linear"
formulation = "fv3"
[[section]]
name = "steel"
EA = 2.1e9
GAy = 8e8
GAz = 8e8
GJ = 1.6e6
EJy = 1.75e6
EJz = 1.75e6
[[beam]]
name = "cantilever"
section = "steel"
straight = { start = [0.0, 0.0, 0.0], end = [10.0, 0.0, 0.0], elements = 10 }
[[support]]
node = "cantilever.start"
[[load]]
kind = "nodal"
node = "cantilever.end"
force = [0.0, 1e3, 0.0]
[study]
kind = "static"
[output]
csv = ["nodes"]
"""


def test_a_static_run_imports_only_what_it_uses(tmp_path):
    """``fvslider run`` of a static cantilever: solved and written, and none of
    :data:`STATIC_UNUSED` imported."""
    scene = tmp_path / "cantilever.toml"
    scene.write_text(CANTILEVER)
    code = f"""
import json, sys
from sliders.app.cli import main
assert main(["run", {str(scene)!r}, "--out", {str(tmp_path / "out")!r}]) == 0
print(json.dumps(sorted(set(sys.modules) & set({list(STATIC_UNUSED)!r}))))
"""
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert json.loads(done.stdout.splitlines()[-1]) == []
    assert (tmp_path / "out" / "nodes.csv").is_file()
