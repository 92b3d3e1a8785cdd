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
from sliders.joints.packed import JointPack
from sliders.joints.slider import Slider
from sliders.lines.chain import BeamChain
from sliders.sliding_beams.model import PAPER, SlidingBeams
from sliders.solve.planar import moved_in_plane
from sliders.solve.statics import SliderStatics

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


def _models(kind: str = "classical"):
    """The sliding-beams statics at ``s / L``, each built anew on one model's beams (their
    stiffness shared: the piston is the cylinder translated)."""
    model = SlidingBeams("fv3", 3, kind, smearing=0.3)

    def fresh(s: float):
        model._previous = None
        return model.problem(s)[0]

    return fresh


@pytest.mark.parametrize("kind", ["spherical", "classical"])
def test_moved_joints_pack_as_fresh_ones(kind):
    """``JointPack.moved``: the joints of a moved problem packed as a pack built anew on it
    (every float and integer equal, bit for bit: the node positions are copied, the sliding
    points' offsets added as the fresh pack adds them), from the placement made once, and
    from one made again when the structure is not a moved copy (built anew, same beams);
    the template's pack is left as it was."""
    fresh_at = _models(kind)
    first = fresh_at(0.0)
    joints = [dataclasses.replace(x, offset=(0.0, 0.01, 0.002)) for x in first.sliders]
    pack = JointPack(joints, first.structure)
    for s in (0.09, 0.51):
        fresh = fresh_at(s)
        moved_structure = first.structure.moved(fresh.structure.beams)
        sliders = [slider.moved(moved_structure) for slider in joints]
        rebuilt = Structure(fresh.structure.beams)
        again = [Slider(**{**vars_of(x), "line": x.line.moved(rebuilt)}) for x in joints]
        expected = JointPack(
            [dataclasses.replace(x, offset=joints[0].offset) for x in fresh.sliders],
            fresh.structure,
        )
        for structure, on_it in ((moved_structure, sliders), (rebuilt, again)):
            moved = pack.moved(on_it, structure)
            assert moved is not None
            np.testing.assert_array_equal(moved.floats, expected.floats)
            np.testing.assert_array_equal(moved.ints, expected.ints)
        assert pack.moved(sliders, moved_structure)._placement is pack._placement
    np.testing.assert_array_equal(pack.floats, JointPack(joints, first.structure).floats)


def vars_of(slider):
    """The constructor arguments of a slider (its dataclass fields)."""
    return {f.name: getattr(slider, f.name) for f in dataclasses.fields(slider)}


def test_moved_chain_is_the_chain_of_the_moved_beams():
    """``BeamChain.moved`` on a moved structure: the chain of the same beams built anew
    there (same beams, abscissae, name); on a structure built anew, a chain built and
    checked anew."""
    fresh_at = _models()
    first, fresh = fresh_at(0.0), fresh_at(0.3)
    for slider, new in zip(first.sliders, fresh.sliders, strict=True):
        for structure in (first.structure.moved(fresh.structure.beams), fresh.structure):
            chain = slider.line.moved(structure)
            assert isinstance(chain, BeamChain) and chain.structure is structure
            assert chain.beams == [structure.beams[i] for i in new.line.indices]
            assert chain.name == new.line.name and chain.length == new.line.length
            np.testing.assert_array_equal(chain.offsets, new.line.offsets)
            x = chain.geometry(0.2, np.zeros(structure.n_dofs))[0]
            np.testing.assert_array_equal(x, new.line.geometry(0.2, np.zeros(structure.n_dofs))[0])


def test_slot_points_hold_every_node_before_ties():
    """``Structure.slot_points`` and ``node_slot``: the row of a beam's node or a body is its
    reference position (:meth:`Structure.node_position`), tied nodes keep a row each."""
    a, b = _beam(0.0), _beam(1.0)
    hub = RigidBody("hub", np.array([2.0, 0.0, 0.0]))
    structure = Structure([a, b], ties=[(0, "end", 1, "start"), ((1, "end"), "hub")], bodies=[hub])
    points = structure.slot_points()
    assert points.shape == (a.mesh.n_nodes + b.mesh.n_nodes + 1, 3)
    for ref in [(0, "start"), (0, "end"), (1, "start"), (1, 3), "hub"]:
        np.testing.assert_array_equal(
            points[structure.node_slot(ref)], structure.node_position(ref)
        )


def test_structure_moved_refuses_a_renamed_beam():
    """A beam renamed on the way (``Beam.translated(..., name=)``) is not the beam it
    replaces moved: node references by name would name other nodes."""
    a = _beam(0.0)
    structure = Structure([a])
    with pytest.raises(ValueError, match=r"beams\[0\] is not beam 0 moved"):
        structure.moved([a.translated((0.0, 0.5, 0.0), name="P")])


@pytest.mark.parametrize("kind", ["spherical", "classical"])
def test_statics_moved_is_the_statics_built_with_reuse(kind):
    """``SliderStatics.moved``: the problem that ``SliderStatics(structure.moved(...),
    supports, moved sliders, reuse=...)`` builds, without its checks: the operator, its
    factorisation and the cached columns shared, the joints packed bit for bit alike, and
    so the same solution bit for bit (the compiled loop reads the same arrays).  The
    problem it was moved from is left as it was."""
    model = SlidingBeams("fv3", 3, kind)
    first, f = model.problem(0.0)
    before = first.solve(f)
    floats = first.compiled.pack.floats.copy()
    piston = model.cylinder.translated((0.3 * PAPER.length, 0.0, 0.0))
    moved = first.moved([model.cylinder, piston])
    structure = first.structure.moved([model.cylinder, piston])
    built = SliderStatics(
        structure,
        model.supports,
        [s.moved(structure) for s in first.sliders],
        reuse=first,
        method="condensed",
    )
    assert moved.K is built.K and moved._condensed is built._condensed
    assert moved.compiled.store is built.compiled.store is first.compiled.store
    np.testing.assert_array_equal(moved.compiled.pack.floats, built.compiled.pack.floats)
    np.testing.assert_array_equal(moved.structure.beams[1].mesh.points, piston.mesh.points)
    one, other = moved.solve(f), built.solve(f)
    np.testing.assert_array_equal(one.q, other.q)
    for a, b in zip(one.unknowns, other.unknowns, strict=True):
        np.testing.assert_array_equal(a, b)
    assert one.residuals == other.residuals
    np.testing.assert_array_equal(first.compiled.pack.floats, floats)
    np.testing.assert_array_equal(first.solve(f).q, before.q)


def test_statics_moved_checks_what_a_move_can_break():
    """``SliderStatics.moved`` refuses, by name, a beam that is not a translated copy of
    the one it replaces (:meth:`Structure.moved`), and a planar problem moved out of its
    plane (its sliders checked in the plane again)."""
    model = SlidingBeams("fv3", 1, "spherical")
    statics, _ = model.problem(0.0)
    with pytest.raises(ValueError, match=r"beams\[1\] is not beam 1 moved"):
        statics.moved([model.cylinder, _beam(0.3)])
    planar = Model(_scene("classical", (0.0, 0.3), planar=True))
    on_plane, _ = planar.problem(0.0)
    beams = on_plane.structure.beams
    with pytest.raises(ValueError, match="plane"):
        on_plane.moved([beams[0], beams[1].translated((0.0, 0.0, 0.1))])


def test_a_move_within_the_plane_is_not_checked_again(monkeypatch):
    """A planar problem moved within its plane keeps every node's normal coordinate
    (``moved_in_plane``), so its planar check does not run again; a move with a normal
    component runs it (and is refused, ``test_statics_moved_checks_what_a_move_can_break``).
    The moved problem solves as the one built with ``reuse``, which runs the check."""
    import sliders.solve.statics as statics_module

    model = Model(_scene("classical", (0.0, 0.3), planar=True))
    start, f = model.problem(0.0)
    beams = start.structure.beams
    calls = []
    real = statics_module.check
    monkeypatch.setattr(statics_module, "check", lambda *a, **k: calls.append(a) or real(*a, **k))
    piston = beams[1].translated((0.3, 0.0, 0.0))
    assert moved_in_plane(start.structure, start.structure.moved([beams[0], piston]), "xy")
    moved = start.moved([beams[0], piston])
    assert calls == []
    structure = start.structure.moved([beams[0], piston])
    built = SliderStatics(
        structure,
        start._supports,
        [s.moved(structure) for s in start.sliders],
        reuse=start,
        method=start.method,
        plane="xy",
    )
    assert len(calls) == 1
    np.testing.assert_array_equal(moved.solve(f).q, built.solve(f).q)
    lifted = beams[1].translated((0.3, 0.0, 1e-3))
    assert not moved_in_plane(start.structure, start.structure.moved([beams[0], lifted]), "xy")
    with pytest.raises(ValueError, match="off the plane"):
        start.moved([beams[0], lifted])
    assert len(calls) == 2
