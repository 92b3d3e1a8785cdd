"""A sweep's points built from the last one moved (Structure.moved, Slider.moved) against the
same points built from scratch.

A moved point shares the last point's numbering, supports, checked sliders and condensed
operator; a fresh one builds them again.  The two solve the same problem, the reused operator
bordered by the piston's rigid modes about its first position and the fresh one about this
one (the same span, other roundoff), so their solutions are compared with the first-order
agreement bound of tests/test_condensed.py.
"""

import dataclasses
from pathlib import Path

import numpy as np
import pytest
from test_condensed import agreement_bound, state

from fvbeam import Beam, Structure, straight
from fvbeam.body import RigidBody
from sliders.app.model import Model
from sliders.app.scene import load_scene, parse_scene
from sliders.sliding_beams.model import PAPER

SCENE = Path(__file__).parents[1] / "studies" / "scenes" / "fig4_sliding_beams.toml"


def _scene(kind: str, values: tuple[float, ...], planar: bool = False):
    data = load_scene(SCENE).model_dump(mode="python", exclude_none=True)
    for beam in data["beam"]:
        beam["straight"]["elements"] = 3
    for slider in data["slider"]:
        slider["kind"] = kind
    data["study"]["range"] = None
    data["study"]["values"] = values
    data["study"]["planar"] = planar
    data["output"] = {}
    return parse_scene(data)


@pytest.mark.parametrize("planar", [False, True])
@pytest.mark.parametrize("kind", ["spherical", "classical"])
def test_moved_points_solve_as_fresh_ones(kind, planar):
    """Piston positions of the Figures 4-5 scene: each point built from the last one moved
    (what a sweep does; also on the in-plane dofs) has the numbering and solution of the
    point built anew on all dofs (whose full Jacobian the agreement bound reads)."""
    values = (0.0, 0.09, 0.3, 0.51)
    model = Model(_scene(kind, values, planar))
    for value in values:
        moved, f_moved = model.problem(value)
        fresh_model = Model(_scene(kind, values))
        fresh, f_fresh = fresh_model.problem(value)
        assert fresh_model._previous is fresh and fresh.structure is not moved.structure
        np.testing.assert_array_equal(f_moved, f_fresh)
        assert moved.plane == ("xy" if planar else None) and fresh.plane is None
        for a, b in zip(moved.structure.dof_maps, fresh.structure.dof_maps, strict=True):
            np.testing.assert_array_equal(a, b)
        for a, b in zip(moved.structure.beams, fresh.structure.beams, strict=True):
            np.testing.assert_array_equal(a.mesh.points, b.mesh.points)
        one, other = moved.solve(f_moved), fresh.solve(f_fresh)
        difference = np.abs(state(fresh, one) - state(fresh, other))
        assert np.all(difference <= agreement_bound(fresh, one, other, f_fresh))
        assert one.step_iterations == other.step_iterations


def _beam(x0: float) -> Beam:
    return Beam(straight((x0, 0, 0), (x0 + 1.0, 0, 0), 2), PAPER.section, "fv3")


def test_structure_moved_keeps_the_numbering_and_checks_what_a_move_can_break():
    """``Structure.moved``: the dof maps shared; a beam that is not a translated copy, or a
    tied body left behind, is refused by name."""
    a = _beam(0.0)
    hub = RigidBody("hub", np.array([1.0, 0.0, 0.0]))
    structure = Structure([a], ties=[("beam.end", "hub")], bodies=[hub])
    shift = np.array([0.0, 0.5, 0.0])
    moved = structure.moved(
        [a.translated(shift)], [dataclasses.replace(hub, position=hub.position + shift)]
    )
    assert moved.dof_maps is structure.dof_maps
    np.testing.assert_array_equal(moved.node_position("hub"), [1.0, 0.5, 0.0])
    np.testing.assert_array_equal(moved.node_position("beam.end"), [1.0, 0.5, 0.0])
    with pytest.raises(ValueError, match=r"beams\[0\] is not beam 0 moved"):
        structure.moved([_beam(0.0)], [hub])
    with pytest.raises(ValueError, match="apart"):
        structure.moved([a.translated(shift)], [hub])
    with pytest.raises(ValueError, match="1 beams and 1 bodies"):
        structure.moved([a, a], [hub])
