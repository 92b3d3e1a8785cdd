"""Rigid lines: derivatives against central finite differences, frames, projection.

Central differences with step h have truncation error ~ h^2 |x'''| / 6 and roundoff
~ eps |x| / h; h = 1e-5 on curves of unit size balances them near 1e-10, so 1e-7 is a
bound with three orders of margin.
"""

import numpy as np
import pytest

from sliders.lines.rigid import CircularArc, CubicSpline, Helix, StraightLine, axial

H, FD = 1e-5, 1e-7

LINES = {
    "straight": StraightLine((0.5, -1, 2), (1.5, 1, 1.5), up=(0, 0, 1)),
    "arc": CircularArc((1, 2, 0.5), 1.3, 0.2, 2.5),
    "arc backwards": CircularArc((0, 0, 0), 0.7, 1.0, -1.5),
    "helix": Helix((0, 0, 0), 0.8, 0.5, 1.5),
    "spline": CubicSpline([[0, 0, 0], [1, 0.5, 0.2], [2, 0.3, 0.9], [3, -0.4, 1.0], [4, 0, 0.5]]),
}


@pytest.fixture(params=list(LINES))
def line(request):
    return LINES[request.param]


def stations(line):
    return np.linspace(0.05, 0.95, 7) * line.length


def test_derivatives_match_finite_differences(line):
    for xi in stations(line):
        p, plus, minus = line.at(xi), line.at(xi + H), line.at(xi - H)
        np.testing.assert_allclose(p.l, (plus.x - minus.x) / (2 * H), atol=FD)
        np.testing.assert_allclose(p.l_xi, (plus.l - minus.l) / (2 * H), atol=FD)
        np.testing.assert_allclose(p.l_xixi, (plus.l_xi - minus.l_xi) / (2 * H), atol=FD)
        np.testing.assert_allclose(p.k, axial((plus.R - minus.R) / (2 * H) @ p.R.T), atol=FD)


def test_frame_is_orthonormal_and_follows_the_line(line):
    for xi in stations(line):
        p = line.at(xi)
        np.testing.assert_allclose(p.R.T @ p.R, np.eye(3), atol=1e-14)
        assert np.linalg.det(p.R) == pytest.approx(1.0, abs=1e-14)
        np.testing.assert_allclose(p.R[:, 0], p.l / np.linalg.norm(p.l), atol=1e-14)


@pytest.mark.parametrize("name", ["straight", "arc", "arc backwards", "helix"])
def test_arc_length_parametrisation(name):
    line = LINES[name]
    for xi in stations(line):
        assert np.linalg.norm(line.at(xi).l) == pytest.approx(1.0, abs=1e-14)


def test_arc_curvature_is_one_over_radius_about_its_axis():
    """A circle's frame turns at rate 1/r about the plane normal (sign: sense of travel)."""
    for line, sense in ((LINES["arc"], 1), (LINES["arc backwards"], -1)):
        p = line.at(0.3 * line.length)
        np.testing.assert_allclose(p.k, [0, 0, sense / line.radius], atol=1e-14)
        np.testing.assert_allclose(np.linalg.norm(p.l_xi), 1 / line.radius, rtol=1e-14)


def test_projection_recovers_the_abscissa_of_an_offset_point(line):
    """A point moved off the line along a normal direction projects back to its abscissa
    (the normal plane at xi contains it; offsets below the radius of curvature)."""
    for xi in stations(line):
        p = line.at(xi)
        normal = p.R[:, 1] * 0.05
        assert line.project(p.x + normal) == pytest.approx(xi, abs=1e-10 * line.length)


def test_bad_input_names_the_item():
    with pytest.raises(ValueError, match="xi = 5.0"):
        LINES["arc"].at(5.0)
    with pytest.raises(ValueError, match="radius"):
        CircularArc((0, 0, 0), -1.0, 0, 1)
    with pytest.raises(ValueError, match="length"):
        StraightLine((1, 1, 1), (1, 1, 1))
    with pytest.raises(ValueError, match="points 1 and 2 coincide"):
        CubicSpline([[0, 0, 0], [1, 0, 0], [1, 0, 0], [2, 0, 0]])
    with pytest.raises(ValueError, match="center"):
        Helix((0, np.nan, 0), 1, 1, 1)
