"""Prescribed dof values (drives) on geometrically exact beams (``solve_static``'s
``drives``): a clamp turned about a global axis and a tip moved along one, against closed
forms, the reactions at the driven dofs included.

Tolerances: as ``tests/test_exact_statics.py``: positions to twice their Richardson
estimate at the scheme's order (2 for fv2, 4 for fv3) plus, for the elastica, the model's
share ``P L / GA + P L / EA``, and the round-off of the positions' sums (``16 eps`` per
element); reactions (the residual at a driven dof) to its round-off floor
(``FLOOR_FACTOR eps`` times its terms, ``ExactBeam.residual_floor``).
"""

import numpy as np
import pytest

from fvbeam.elastica import tip_loaded_cantilever
from fvbeam.exact_statics import FLOOR_FACTOR, solve_static
from studies.bench_exact import rod

EPS = np.finfo(float).eps


def floor(exact, state, dof: int) -> float:
    """The round-off floor of the residual at ``dof`` (the solver's convergence test): with
    ``EA = 1e8 EJ / L^2`` the axial stiffness magnifies the positions' rounding to about
    ``1e-5`` of a unit force on 16 elements, below which a reaction holds no information."""
    return FLOOR_FACTOR * EPS * float(exact.residual_floor(state)[dof])


@pytest.mark.parametrize("name,order", [("fv2", 2), ("fv3", 4)])
def test_a_tip_turned_about_a_global_axis_bends_the_rod_into_an_arc(name, order):
    """The tip's rotations held but the one about z, driven to pi: the rod bends into a half
    circle of radius L / pi, the tip at (0, 2 L / pi) (4 and 8 elements: within twice the
    Richardson estimate at the scheme's order), under the reaction couple ``EJ pi / L``
    (the rotation about a fixed axis is interpolated exactly: the curvature is ``pi / L``
    at every point, the couple to its residual's round-off floor)."""
    tips = []
    for n in (4, 8):
        exact = rod(name, n, slenderness=1e4)
        beam = exact.beam
        end = beam.node_dofs("end")
        fixed = np.concatenate([beam.node_dofs("start"), end[3:5]])
        result = solve_static(exact, np.zeros(beam.n_dofs), fixed, drives={int(end[5]): np.pi})
        tips.append(result.state.x[beam.node_index("end")])
        couple = exact.residual(result.state)[end[5]]
        assert abs(couple - np.pi) <= floor(exact, result.state, end[5])
    richardson = np.abs(tips[0] - tips[1]) / (2**order - 1)
    error = np.abs(tips[1] - [0.0, 2 / np.pi, 0.0])
    assert np.all(error <= 2 * richardson + 16 * EPS * 8), error


def test_a_tip_moved_along_a_global_axis_is_the_elastica():
    """The tip moved by the elastica's deflection at ``P L^2 / EJ = 2`` (its other dofs
    free): it shortens by the elastica's shortening, turns by its rotation, and its
    reaction is the force ``P``; 8 and 16 fv3 elements."""
    closed = tip_loaded_cantilever(2.0)
    values = []
    for n in (8, 16):
        exact = rod("fv3", n)
        beam = exact.beam
        end = beam.node_dofs("end")
        drives = {int(end[1]): -closed.deflection}
        result = solve_static(exact, np.zeros(beam.n_dofs), beam.node_dofs("start"), drives=drives)
        d = exact.displacements(result.state)[beam.node_index("end")]
        reaction = exact.residual(result.state)[end[1]]
        values.append(np.array([-d[0], -d[5], -reaction]))
    expected = np.array([closed.shortening, closed.rotation, 2.0])
    richardson = np.abs(values[0] - values[1]) / 15
    model = 2 * 2.0 / 1e8
    rounding = np.array([0.0, 0.0, floor(exact, result.state, end[1])])
    error = np.abs(values[1] - expected)
    assert np.all(error <= 2 * richardson + model + rounding), error


def test_drives_take_load_stepping_only():
    exact = rod("fv2", 2)
    with pytest.raises(ValueError, match="drives take method 'load'"):
        solve_static(
            exact,
            np.zeros(exact.n_dofs),
            exact.beam.node_dofs("start"),
            method="arc-length",
            drives={13: 0.1},
        )
