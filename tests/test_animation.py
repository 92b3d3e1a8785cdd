"""Animations (:func:`sliders.app.render.animate`) and the view of renders
(:mod:`sliders.app.view`).

The landing-gear scene, cut to a few steps, is animated from the command's output
(``[output] animation = "gif"``) and from Python (MP4): every frame is written with the
same camera, magnification and colour range, read back from the plotter as each frame was
written; the camera frames every frame's drawn points, the colour range covers every
frame's bending moment, and the magnification is the one of the frame that deforms most.
The views of shipped scenes in the x-y and x-z planes and of a 3-D shape are the ones
:func:`sliders.app.view.choose_view` promises.
"""

from __future__ import annotations

import numpy as np
import pytest
from test_scenes import SCENES, data, problems

from sliders.app.model import Model
from sliders.app.render import AUTO_FRACTION, Options, animate, beam_samples, prepare
from sliders.app.run_dynamic import integrate, write_dynamic
from sliders.app.scene import load_scene
from sliders.app.view import MODEL_REGION, choose_view, screen_axes
from sliders.app.vtu import Frame, rigid_part, structure_size

imageio = pytest.importorskip("imageio")
pytest.importorskip("pyvista")

STEPS = 3
WINDOW = (320, 240)


def gear_scene(animation: str = "none"):
    """The landing-gear scene, ``STEPS`` steps long, followed by the airframe."""
    scene = load_scene(SCENES / "landing_gear.toml")
    study = scene.study.model_copy(update={"t_end": STEPS * scene.study.step})
    render = scene.output.render.model_copy(update={"follow": "airframe", "window": WINDOW})
    output = scene.output.model_copy(update={"animation": animation, "render": render})
    return scene.model_copy(update={"study": study, "output": output})


@pytest.fixture(scope="module")
def gear(tmp_path_factory):
    """The short gear run, written with its GIF by the command's writer."""
    out = tmp_path_factory.mktemp("gear") / "out"
    run = integrate(Model(gear_scene("gif")), progress=False)
    assert run.error is None
    write_dynamic(run, out)
    return run, out


def test_the_scene_writes_its_gif_one_frame_per_kept_state(gear):
    run, out = gear
    frames = imageio.mimread(out / "animation.gif")
    assert len(frames) == len(run.frames()) == STEPS + 1
    assert all(f.shape[:2] == (WINDOW[1], WINDOW[0]) for f in frames)
    assert np.ptp(np.asarray(frames[-1], dtype=float)) > 0  # not blank


def test_camera_magnification_and_colour_range_are_fixed_over_the_frames(gear, tmp_path):
    run, _ = gear
    frames = run.frames()
    model = run.model
    options = Options(follow="airframe", window_size=WINDOW)
    record = animate(tmp_path / "a.mp4", frames, "gear", model.forces, options)
    style = record.style
    assert len(record.cameras) == len(record.ranges) == len(frames)
    assert all(c == record.cameras[0] for c in record.cameras)
    assert all(r == [style.clim] * len(r) and r for r in record.ranges)
    for text, frame in zip(record.titles, frames, strict=True):
        assert text.endswith(f"t = {frame.time:.4g} s")
    assert len(imageio.mimread(tmp_path / "a.mp4", format="FFMPEG")) == len(frames)
    # the magnification: the largest elastic displacement of any frame drawn at
    # AUTO_FRACTION of the structure's size
    structure = model.structure
    elastic = [
        np.abs((f.q - rigid_part(structure, f.q, f.sliders, f.unknowns, f.held)).reshape(-1, 6))[
            :, :3
        ].max()
        for f in frames
    ]
    assert style.scale == pytest.approx(AUTO_FRACTION * structure_size(structure) / max(elastic))
    # the colour range: the largest drawn bending moment of any frame
    bending = [
        max(b.max() for *_, b in beam_samples(structure, f.q, np.zeros_like(f.q))) for f in frames
    ]
    assert style.clim == (0.0, pytest.approx(max(bending), rel=1e-12))
    # the camera frames every frame's drawn points inside the model's region
    _, drawings = prepare(frames, model.forces, options)
    assert style.view == "xz"
    d, right, up = screen_axes(style.view)
    focal, scale = np.asarray(style.camera.focal_point), style.camera.parallel_scale
    aspect = WINDOW[0] / WINDOW[1]
    left, bottom, right_edge, top = MODEL_REGION
    for drawn in drawings:
        p = drawn.points() - focal
        x = 0.5 + (p @ right) / (2 * aspect * scale)
        y = 0.5 + (p @ up) / (2 * scale)
        tol = 1e-12
        assert x.min() >= left - tol and x.max() <= right_edge + tol
        assert y.min() >= bottom - tol and y.max() <= top + tol


def test_animation_bad_input(tmp_path, gear):
    run, _ = gear
    with pytest.raises(ValueError, match=r"must end in \.mp4 or \.gif"):
        animate(tmp_path / "a.avi", run.frames())
    with pytest.raises(ValueError, match=r"there are no frames to draw"):
        animate(tmp_path / "a.gif", [])
    with pytest.raises(ValueError, match=r"view must be one of auto, xy, xz, yz, iso"):
        animate(tmp_path / "a.gif", run.frames(), options=Options(view="top"))
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    ("scene", "view"),
    [
        ("fig1_cantilever.toml", "xy"),
        ("end_stops.toml", "xy"),
        ("landing_gear.toml", "xz"),
        ("carriage_on_chain.toml", "xz"),
    ],
)
def test_shipped_scenes_are_seen_in_their_plane(scene, view):
    model = Model(load_scene(SCENES / scene))
    structure = model.structure
    zero = np.zeros(structure.n_dofs)
    unknowns = [np.zeros(s.n_unknowns) for s in model.sliders]
    frame = Frame(0.0, structure, zero, model.sliders, unknowns)
    assert prepare([frame], model.forces, Options())[0].view == view


def test_a_shape_out_of_every_coordinate_plane_is_seen_isometric():
    """A cantilever along x bent along (0, 1, 1): its drawn shape spans x, y and z."""
    from fvbeam import Beam, LinearStatics, Section, Support, straight
    from fvbeam.structure import Structure

    section = Section.diagonal(EA=1e9, GAy=1e8, GAz=1e8, GJ=3e4, EJy=4e4, EJz=4e4)
    beam = Beam(straight((0, 0, 0), (1, 0, 0), n_elements=4, name="b"), section, "fv3")
    q = LinearStatics(beam, [Support("b.start")]).solve(beam.point_load(1.0, (0, 1e3, 1e3)))
    frame = Frame(0.0, Structure([beam]), q)
    assert prepare([frame], (), Options())[0].view == "iso"
    assert choose_view(np.array([[0, 0, 0], [1, 0, 0]])) == "xy"
    assert choose_view(np.array([[0, 0, 0], [0, 0, 1]])) == "xz"


def test_scene_render_keys_are_checked_at_their_key_paths():
    """An animation of a static study, a followed node that does not exist, a view and a
    window that are not ones: each reported at its key path, nothing solved."""
    scene = data("fig1_cantilever")
    scene["output"] = {"animation": "gif", "render": {"follow": "nowhere"}}
    found = {p.path: p.message for p in problems(scene)}
    assert "a dynamic study's states" in found["output.animation"]
    assert "nowhere" in found["output.render.follow"]
    scene["output"] = {"animation": "avi", "render": {"view": "top", "window": [0, 10]}}
    found = {p.path: p.message for p in problems(scene)}
    assert set(found) >= {"output.animation", "output.render.view", "output.render.window[0]"}
