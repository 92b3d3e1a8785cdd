"""Headless pyvista render (:mod:`studies.render`) of the sliding-beams setup, and the
promise that importing the packages does not import pyvista.

The render runs in a child process without ``DISPLAY`` and without
``VTK_DEFAULT_OPENGL_WINDOW``, as in CI, so the EGL fallback is what is tested.  The image
is compared with what its geometry predicts.  The camera is a parallel projection of
half-height ``S`` (:func:`sliders.app.view.fit_camera`), so a window ``H`` pixels high
draws ``H / 2S`` pixels per metre: a tube of radius ``r`` and visible length ``l`` covers
``(H / 2S)^2 2 r l`` pixels, a sphere of radius ``rho`` ``pi (rho H / 2S)^2``.  Up to two
pixel rows along each silhouette edge can fall out of the colour test (anti-aliasing, dark
shading at grazing light): with a tube about 10 pixels wide that is 40 % of its area, hence
the lower bounds at half the prediction; the upper bound, 1.25 times, allows the spheres'
and tubes' anti-aliased rims.  The outer tube of the telescope is translucent: its pixels
count in the upper bound only.
"""

from __future__ import annotations

import ctypes.util
import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from test_output import driven_piston, split_bound

from sliders.app.render import SPHERE_FACTOR, drawing, render
from sliders.app.vtu import rigid_part
from studies.fig4_stiffness import L, SlidingBeams

S_OVER_L = 0.3
WINDOW = (1200, 600)
ROOT = Path(__file__).resolve().parents[1]

CHILD = """
import json, os, sys
from pathlib import Path
from sliders.sliding_beams.model import SlidingBeams
from sliders.app.render import Options, prepare, render
from sliders.app.vtu import Frame
out = Path(sys.argv[1])
statics, load = SlidingBeams("fv3", 5, "classical").problem({s})
solution = statics.solve(load)
args = (statics.structure, solution.q, statics.sliders, solution.unknowns)
scale = render(out / "scene.png", *args, window_size={window}, scalar_bar=False)
style, _ = prepare([Frame(0.0, *args)], (), Options(window_size={window}))
import pyvista as pv
blank = pv.Plotter(off_screen=True, window_size=list({window}))
blank.set_background("white")
blank.screenshot(str(out / "blank.png"))
print(json.dumps(dict(scale=scale, window=blank.ren_win.GetClassName(),
                      variable=os.environ.get("VTK_DEFAULT_OPENGL_WINDOW"),
                      view=style.view, parallel_scale=style.camera.parallel_scale,
                      radii=style.sizes.radii.tolist(), marker=style.sizes.marker,
                      translucent=style.sizes.translucent.tolist())))
blank.close()
"""


def hsv(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """RGB in [0, 1] and its HSV of a PNG."""
    import matplotlib.colors as mcolors
    import matplotlib.image as mimage

    rgb = mimage.imread(path)[..., :3]
    return rgb, mcolors.rgb_to_hsv(rgb)


@pytest.fixture(scope="module")
def rendered(tmp_path_factory):
    out = tmp_path_factory.mktemp("render")
    env = {
        k: v
        for k, v in os.environ.items()
        if k not in ("DISPLAY", "WAYLAND_DISPLAY", "VTK_DEFAULT_OPENGL_WINDOW")
    }
    child = subprocess.run(
        [sys.executable, "-c", CHILD.format(s=S_OVER_L, window=WINDOW), str(out)],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert child.returncode == 0, child.stderr
    return out, json.loads(child.stdout.splitlines()[-1]), child.stderr


def test_headless_render_uses_egl_without_x(rendered):
    _, info, stderr = rendered
    assert "X server" not in stderr
    if ctypes.util.find_library("EGL"):
        assert info["variable"] == "vtkEGLRenderWindow"
        assert info["window"] == "vtkEGLRenderWindow"


def test_render_is_not_blank_and_shows_tube_and_sliders(rendered):
    out, info, _ = rendered
    rgb, image_hsv = hsv(out / "scene.png")
    h, s, v = np.moveaxis(image_hsv, -1, 0)
    blank, _ = hsv(out / "blank.png")
    assert rgb.shape[:2] == (WINDOW[1], WINDOW[0])
    assert blank.std() == 0.0 and rgb.std() > blank.std()
    assert info["view"] == "xy"
    pixels_per_m = WINDOW[1] / (2 * info["parallel_scale"])
    (outer, inner), marker = info["radii"], info["marker"]
    assert info["translucent"] == [True, False] and inner < outer
    rho = SPHERE_FACTOR * marker
    sphere = np.pi * (rho * pixels_per_m) ** 2
    opaque = pixels_per_m**2 * 2 * inner * (L - 2 * 2 * rho)
    everything = pixels_per_m**2 * 2 * (inner + outer) * L
    # viridis runs through hues 0.15 (yellow) .. 0.80 (purple) at saturation >= 0.51 and
    # value >= 0.33 (matplotlib's table); red markers sit at hue 0; grey and white at
    # saturation 0.
    viridis = (s > 0.3) & (h > 0.1) & (h < 0.85) & (v > 0.1)
    red = (s > 0.5) & ((h < 0.05) | (h > 0.95))
    assert 0.5 * opaque <= viridis.sum() <= 1.25 * everything
    assert 0.5 * 2 * sphere <= red.sum() <= 1.25 * 2 * sphere
    assert info["scale"] > 1.0


def test_the_driven_piston_is_drawn_at_its_place_and_its_bending_magnified():
    """The piston driven ``d`` along x (tests/test_output.py ``driven_piston``), drawn with
    its elastic part magnified ``m = 1000`` times: every node of the piston at ``X + (d, 0,
    0) + m u3`` (``u3`` the piston's displacement with its reference at ``s = 0.3 L``), the
    cylinder's at ``X + m u``, the ghost of the piston carried by ``d``, slider B's marker
    on the drawn piston.  Tolerance: ``m`` times the split's error (tests/test_output.py)
    plus the rounding of ``X + d`` (``eps``) and of the shape functions at a node (exact: 0
    and 1 at ``X = 0, 1/2, 1``)."""
    structure, q, sliders, unknowns, held, q3, d = driven_piston()
    m = 1000.0
    rigid = rigid_part(structure, q, sliders, unknowns, held)
    drawn = drawing(structure, q, sliders, unknowns, rigid, m)
    bound = m * (np.finfo(float).eps * np.abs(q).max() + split_bound(structure, q)) + 4 * (
        np.finfo(float).eps * L
    )
    for b, shift in ((0, np.zeros(3)), (1, np.array([d, 0.0, 0.0]))):
        mesh = structure.beams[b].mesh
        nodal = structure.local(b, q3 if b else q).reshape(-1, 6)[:, :3]
        ghost, (points, _) = drawn.ghosts[b], drawn.beams[b]
        for k, X in enumerate(mesh.points):
            (at,) = np.flatnonzero(np.abs(ghost - X - shift).max(axis=1) <= bound)
            assert np.abs(points[at] - (X + shift + m * nodal[k])).max() <= bound
    x3, _, _ = sliders[1].line.geometry(unknowns[1][0], np.zeros_like(q3))
    u3 = sliders[1].line.geometry(unknowns[1][0], q3)[0] - x3
    expected = x3 + np.array([d, 0.0, 0.0]) + m * u3
    assert np.abs(drawn.sliders[1] - expected).max() <= bound


def test_render_bad_input(tmp_path):
    statics, load = SlidingBeams("fv3", 1, "spherical").problem(S_OVER_L)
    solution = statics.solve(load)
    args = (statics.structure, solution.q, statics.sliders, solution.unknowns)
    with pytest.raises(ValueError, match=r"must end in \.png"):
        render(tmp_path / "a.jpg", *args)
    with pytest.raises(ValueError, match=r"view must be one of auto, xy, xz, yz, iso, got 'top'"):
        render(tmp_path / "a.png", *args, view="top")
    with pytest.raises(ValueError, match=r"magnification must be a positive number, got -2"):
        render(tmp_path / "a.png", *args, magnification=-2)
    assert list(tmp_path.iterdir()) == []


def test_packages_import_without_pyvista():
    code = (
        "import sys, fvbeam, sliders.app.vtu, studies.render; "
        "print(sorted(m for m in ('pyvista', 'vtk', 'vtkmodules', 'matplotlib') "
        "if m in sys.modules))"
    )
    child = subprocess.run(
        [sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, timeout=60
    )
    assert child.returncode == 0, child.stderr
    assert child.stdout.strip() == "[]"
