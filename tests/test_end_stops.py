"""End stops: a sliding point pushed past the end of its line rests there; pulled back, it
leaves the stop; without stops, leaving the line is an error naming it."""

import numpy as np
import pytest

from fvbeam import Beam, Section, Structure, Support, straight
from sliders.joints.slider import Slider
from sliders.lines.rigid import StraightLine
from sliders.solve.statics import SliderStatics

EJ, GA, L = 4.0e4, 1.0e8, 1.0
SECTION = Section.diagonal(EA=1e9, GAy=GA, GAz=GA, GJ=EJ, EJy=EJ, EJz=EJ)


def cantilever_on_rail(F, end_stops):
    """A cantilever along y, clamped at (0, -L, 0), its tip at the far end of a rigid rail
    along x from (-1, 0, 0) to the origin; a force F along x at the tip."""
    beam = Beam(straight((0, -L, 0), (0, 0, 0), 4, 3), SECTION, "fv3")
    structure = Structure([beam])
    slider = Slider(
        "spherical",
        StraightLine((-1, 0, 0), (0, 0, 0)),
        (0, "end"),
        end_stops=end_stops,
        name="tip",
    )
    slider.line.name = "rail"
    f = structure.gather(0, beam.nodal_load("end", force=(F, 0, 0)))
    return structure, SliderStatics(structure, [Support(0, "start")], [slider]), f, beam


def test_pushed_past_the_end_the_point_rests_on_the_stop():
    """The stop takes the whole force: xi = length, the tip does not move along the rail, the
    stop force l . lambda equals F (equilibrium of the tip node, the beam unloaded)."""
    F = 50.0
    structure, statics, f, beam = cantilever_on_rail(F, True)
    solution = statics.solve(f)
    xi, lam = solution.unknowns[0][0], solution.unknowns[0][1:4]
    assert xi == 1.0
    assert lam[0] == pytest.approx(F, rel=1e-12)
    assert np.abs(solution.q).max() <= 1e-12 * F * L**3 / EJ


def test_pulled_back_the_point_leaves_the_stop():
    """Pulled inwards, the tip slides off the stop by the cantilever's end deflection
    F L^3 / 3EJ + F L / GA (Timoshenko, exact for fv3 under an end load; tolerance 1e-9,
    roundoff) and the reaction has no tangential part."""
    F = -50.0
    structure, statics, f, beam = cantilever_on_rail(F, True)
    solution = statics.solve(f)
    deflection = F * L**3 / (3 * EJ) + F * L / GA
    assert solution.unknowns[0][0] == pytest.approx(1.0 + deflection, rel=1e-9)
    assert abs(solution.unknowns[0][1]) <= 1e-9 * abs(F)


def test_without_stops_leaving_the_line_is_an_error_naming_it():
    structure, statics, f, beam = cantilever_on_rail(50.0, False)
    with pytest.raises(ValueError, match="rail"):
        statics.solve(f)
