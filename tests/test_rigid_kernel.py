"""The compiled rigid lines and frames (:mod:`sliders.lines.rigid_kernel`) against their numpy
references (:mod:`sliders.lines.rigid`), to roundoff."""

from __future__ import annotations

import numpy as np
import pytest

from sliders.lines.rigid import (
    CircularArc,
    CubicSpline,
    Helix,
    StraightLine,
    curvature_rate,
    frame_and_curvature,
)
from sliders.lines.rigid_kernel import curvature_rate_at, frame_at, line_at

EPS = np.finfo(float).eps

LINES = {
    "straight": StraightLine((0.1, -0.2, 0.3), (1.3, 0.4, -0.5), up=(0, 0, 1)),
    "arc": CircularArc((0.2, 0.1, 0.0), 0.7, 0.3, -1.9),
    "helix": Helix((0.0, 0.5, -0.2), 0.4, 0.3, 1.5),
    "spline": CubicSpline([(0, 0, 0), (0.5, 0.2, 0.1), (1.0, 0.1, 0.4), (1.4, -0.3, 0.5)]),
}


@pytest.mark.parametrize("name", list(LINES))
def test_line_and_frame_match_the_reference(name: str) -> None:
    """Point, derivatives, frame, curvature and its rate at abscissae over the whole line
    (pieces' ends included), each to a few ulp of its scale: the kernel evaluates the same
    closed forms (a spline by Horner's rule where scipy sums powers, hence the 64 ulp of the
    largest term); the curvature rate is the same central difference of the same frames."""
    line = LINES[name]
    shape, params, breaks = line.compiled()
    out, R, k, k_xi = np.empty((4, 3)), np.empty((3, 3)), np.empty(3), np.empty(3)
    up = np.asarray(line.up, dtype=float)
    for xi in np.concatenate([np.linspace(0, line.length, 23), breaks[1:-1]]):
        line_at(shape, params, breaks, xi, out)
        reference = np.array(line.derivatives(xi))
        scale = max(1.0, np.abs(reference).max())
        assert np.abs(out - reference).max() <= 64 * EPS * scale
        frame_at(reference[1], reference[2], up, R, k)
        R_ref, k_ref = frame_and_curvature(reference[1], reference[2], up)
        assert np.abs(R - R_ref).max() <= 16 * EPS
        assert np.abs(k - k_ref).max() <= 16 * EPS * max(1.0, np.abs(k_ref).max())
        curvature_rate_at(reference[1], reference[2], reference[3], up, k_xi)
        rate = curvature_rate(reference[1], reference[2], reference[3], up)
        # a difference quotient over 2d = 2e-4 / |l_xi| of frames exact to 16 ulp
        d = 1e-4 / max(np.linalg.norm(reference[2]), 1e-300)
        assert np.abs(k_xi - rate).max() <= 32 * EPS / d * max(1.0, np.abs(k_ref).max())
