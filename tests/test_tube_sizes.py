"""The sizes and parts of pictures (:mod:`sliders.app.shapes`, :mod:`sliders.app.render`):
tube radii from a section's shape or stiffness, the same radii in the VTU's ``radius``
field, and the rigid lines and force elements a picture draws.

Radii: a tube's or circle's outer radius is half its diameter, a rectangle's (or an
I-section's bounding rectangle's) enclosing radius half its diagonal (Pythagoras: a 30 x 40
rectangle's diagonal is 50); a thin-walled tube of mean radius ``R`` and wall ``t`` has ``EA
= E 2 pi R t`` and ``EJ = E pi R^3 t`` exactly in the thin-wall model, so ``sqrt(2 EJ /
EA)`` returns ``R`` to round-off (a few ``eps``: a product, a quotient, a square root).
Halving a float is exact, so a radius copied from a shape is compared exactly.

Parts: each drawn part is a named actor (:data:`sliders.app.render.ACTORS`); the shipped
scenes' parts are counted (the rigid-lines scene's four lines, the landing gear's strut,
wheel and ground), and the drawn rails and coils are checked against the lines' ends and the
strut's nodes (points the picture places, ``X + u_R + m (u - u_R)``, exact at zero
displacement).
"""

from __future__ import annotations

import meshio
import numpy as np
import pytest
from test_scenes import SCENES

from fvbeam import Section
from fvbeam.shapes import Circle, ISection, Material, Rectangle, Tube
from sliders.app.model import Model
from sliders.app.render import Canvas, Options, prepare
from sliders.app.scene import load_scene
from sliders.app.shapes import (
    COIL_FACTOR,
    INNER_FACTOR,
    RADIUS_LIMITS,
    axial_forces,
    coil,
    rigid_lines,
    section_radius,
    tube_sizes,
)
from sliders.app.vtu import PARTS, Frame, structure_size, write_vtu

EPS = np.finfo(float).eps
STEEL = Material(E=210e9, nu=0.3, density=7850.0)
WINDOW = (320, 240)


@pytest.mark.parametrize(
    ("shape", "radius"),
    [
        (Tube(outer=0.06, inner=0.05), 0.03),
        (Circle(diameter=0.04), 0.02),
        (Rectangle(width=0.03, height=0.04), 0.025),
        (ISection(height=0.2, width=0.15, web=0.008, flange=0.012), 0.125),
    ],
)
def test_a_shaped_section_is_drawn_at_its_enclosing_radius(shape, radius):
    section = Section.from_shape(STEEL, shape)
    assert section_radius(section) == pytest.approx(radius, rel=2 * EPS, abs=0)


def test_a_section_given_by_numbers_is_drawn_as_its_thin_walled_tube():
    """The thin tube of mean radius 25 mm and wall 4 mm, by its numbers: ``R`` back."""
    E, R, t = 210e9, 0.025, 0.004
    section = Section.diagonal(
        EA=E * 2 * np.pi * R * t,
        GAy=1e8,
        GAz=1e8,
        GJ=3e4,
        EJy=E * np.pi * R**3 * t,
        EJz=E * np.pi * R**3 * t,
    )
    assert section_radius(section) == pytest.approx(R, rel=8 * EPS, abs=0)


def model_of(name: str) -> tuple[Model, Frame]:
    """A shipped scene's model and its frame at rest (zero displacements)."""
    model = Model(load_scene(SCENES / name))
    structure = model.structure
    unknowns = [np.zeros(s.n_unknowns) for s in model.sliders]
    return model, Frame(0.0, structure, np.zeros(structure.n_dofs), model.sliders, unknowns)


def vtu_radii(model: Model, frame: Frame, path) -> tuple[dict[int, np.ndarray], np.ndarray]:
    """Per beam the ``radius`` field on its nodes, and the field on the sliders and bodies,
    read back from a VTU."""
    write_vtu(path, frame.structure, frame.q, frame.sliders, frame.unknowns)
    mesh = meshio.read(path)
    radius = mesh.point_data["radius"]
    beams: dict[int, list[float]] = {}
    markers: list[float] = []
    for block, part, ident in zip(
        mesh.cells, mesh.cell_data["part"], mesh.cell_data["id"], strict=True
    ):
        for cell, p, i in zip(block.data, part, ident, strict=True):
            if p == PARTS["beam"]:
                beams.setdefault(int(i), []).extend(radius[cell])
            elif p in (PARTS["slider"], PARTS["body"]):
                markers.extend(radius[cell])
    return {b: np.array(r) for b, r in beams.items()}, np.array(markers)


def test_the_vtu_carries_a_shaped_sections_radius(tmp_path):
    """The tube cantilever (60 x 50 mm tube, 2 m): its tube at 30 mm, within the limits."""
    model, frame = model_of("tube_cantilever.toml")
    size = structure_size(model.structure)
    low, high = RADIUS_LIMITS
    assert low * size < 0.03 < high * size
    beams, _ = vtu_radii(model, frame, tmp_path / "tube.vtu")
    assert list(beams) == [0] and np.all(beams[0] == 0.03)


def test_the_vtu_carries_the_telescopes_radii(tmp_path):
    """The landing gear: the cylinder at the thin-walled tube's radius of its numbers
    (``sqrt(2 EJ / EA)``, 25.1 mm), the piston inside it at ``INNER_FACTOR`` of that (equal
    sections: the one declared second is inside), the sliders and bodies at the
    cylinder's (two sliders, three bodies); the render draws the same."""
    model, frame = model_of("landing_gear.toml")
    outer = np.sqrt(2 * 4.1e4 / 1.3e8)
    beams, markers = vtu_radii(model, frame, tmp_path / "gear.vtu")
    assert beams[0] == pytest.approx(outer, rel=8 * EPS, abs=0)
    assert beams[1] == pytest.approx(INNER_FACTOR * outer, rel=8 * EPS, abs=0)
    assert len(markers) == 2 + 3 and np.all(markers == beams[0][0])
    style, _ = prepare([frame], model.forces, Options(window_size=WINDOW))
    assert style.sizes.radii.tolist() == [beams[0][0], beams[1][0]]
    assert style.sizes.translucent.tolist() == [True, False]
    sizes = tube_sizes(model.structure, model.sliders, structure_size(model.structure))
    assert sizes.radii.tolist() == style.sizes.radii.tolist()


def drawn_parts(model: Model, frame: Frame) -> list[str]:
    """The names of the parts one picture of ``frame`` draws."""
    pytest.importorskip("pyvista")
    style, (drawn,) = prepare([frame], model.forces, Options(window_size=WINDOW))
    canvas = Canvas(style)
    try:
        canvas.show(drawn, "parts")
        return canvas.parts()
    finally:
        canvas.close()


def test_the_rigid_lines_sliders_run_on_are_drawn():
    """The rigid-lines scene: four cantilevers, each tip sliding on its own rigid line
    (straight, arc, helix, spline); each line drawn once, through its ends."""
    model, frame = model_of("rigid_lines.toml")
    lines = rigid_lines(model.sliders)
    assert len(lines) == 4
    parts = drawn_parts(model, frame)
    beams = [f"{kind} {k}" for k in range(4) for kind in ("ghost", "beam")]
    assert parts == beams + [f"rigid line {k}" for k in range(4)] + ["sliders"]
    _, (drawn,) = prepare([frame], model.forces, Options(window_size=WINDOW))
    for line, rail in zip(lines, drawn.rails, strict=True):
        ends = np.array([line.at(0.0).x, line.at(line.length).x])
        assert np.abs(rail[[0, -1]] - ends).max() <= 4 * EPS * np.abs(ends).max()


def test_the_landing_gears_strut_wheel_and_ground_are_drawn():
    """The landing gear: cylinder and piston with their ghosts, the strut (an axial force
    element) as a coil from the cylinder's top to the piston's head, the sliders, the
    airframe and the axle (the wheel node is drawn as the wheel), the tyre, its hub and spin
    mark, and the ground."""
    model, frame = model_of("landing_gear.toml")
    (strut,) = axial_forces(model.forces)
    parts = drawn_parts(model, frame)
    expected = ["ghost 0", "beam 0", "ghost 1", "beam 1", "force element 0", "sliders"]
    expected += ["bodies", "tyre 0", "hub 0", "spin mark 0", "ground 0"]
    assert parts == expected
    style, (drawn,) = prepare([frame], model.forces, Options(window_size=WINDOW))
    structure = model.structure
    ends = np.array([structure.node_position(strut.a), structure.node_position(strut.b)])
    assert np.array_equal(drawn.springs[0], ends)
    # the coil's turns at COIL_FACTOR of the largest radius from the strut's axis (its
    # leads on the axis): inside the cylinder it is drawn in
    points = coil(*ends, COIL_FACTOR * style.sizes.marker)
    axis = (ends[1] - ends[0]) / np.linalg.norm(ends[1] - ends[0])
    off = (points - ends[0]) - np.outer((points - ends[0]) @ axis, axis)
    distance = np.linalg.norm(off, axis=1)
    turns = distance[distance > 0.5 * COIL_FACTOR * style.sizes.marker]
    assert np.allclose(turns, COIL_FACTOR * style.sizes.marker, rtol=16 * EPS, atol=0)
    assert turns.max() < style.sizes.radii[0]
