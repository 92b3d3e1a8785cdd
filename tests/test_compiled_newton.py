"""The compiled Newton loop (:mod:`sliders.solve.newton`) against the Python loop
:func:`sliders.solve.statics.newton_many` on the condensed back end, the reference.

Both take the same Newton steps from the same start: the same joint equations and small
systems, in compiled code throughout for one and with numpy between the kernels for the
other, which sums the structure residual and applies the factorisation in another order.
Each step's increments therefore agree to the roundoff of a solve with the operator,
``~ cond eps``, and the converged states to the solver's tolerance ``tol`` (both stop on
the same rule): the test asserts ``tol`` relative to the largest displacement and
multiplier, and the same number of iterations.  A wrong equation or a wrong step changes
the solution at the size of the load's effect, and the iteration count.
"""

from __future__ import annotations

import numpy as np
import pytest
from test_joint_reference import JOINTS, OFFSETS, batch_of
from test_sliders import SECTION, sliding_beams_model

from fvbeam import Beam, RigidBody, Structure, Support, arc, straight
from sliders.joints.drives import Linear
from sliders.joints.slider import Slider
from sliders.lines.chain import BeamChain
from sliders.lines.rigid import CubicSpline, StraightLine
from sliders.solve.statics import SliderStatics, newton_many

TOL = 1e-10


def assert_same_solve(statics: SliderStatics, f: np.ndarray, time: float = 0.0) -> None:
    """The compiled solve of ``statics`` (condensed) against ``newton_many``, cold start."""
    assert statics.method == "condensed"
    compiled = statics.newton(f, None, TOL, 25, time)
    batches = [s.batch(statics.structure) for s in statics.sliders]
    reference = newton_many([statics], batches, f[None], [None], TOL, 25, time)[0]
    assert not isinstance(reference, str), reference
    assert not isinstance(compiled, str), compiled
    q, y, history = compiled
    q_ref, y_ref, history_ref = reference
    assert len(history) == len(history_ref)
    assert np.abs(q - q_ref).max() <= TOL * np.abs(q_ref).max() * 10
    for a, b in zip(y, y_ref, strict=True):
        assert abs(a[0] - b[0]) <= TOL * statics.sliders[0].line.length * 10
        assert np.abs(a[1:] - b[1:]).max(initial=0.0) <= TOL * 10 * max(
            np.abs(b[1:]).max(initial=0.0), np.abs(f).max()
        )


@pytest.mark.parametrize("smearing", [0.0, 0.02])
@pytest.mark.parametrize("formulation", ["fv3", "fv2", "galerkin-p2"])
@pytest.mark.parametrize("kind,orientation", JOINTS)
def test_sliding_beams(kind, orientation, formulation, smearing) -> None:
    """The paper's sliding beams (the piston held only by the two sliders: four rigid modes
    bordering the operator), every kind and orientation, point and smeared."""
    structure, supports, sliders, P = sliding_beams_model(
        0.37 * 0.6, 3, kind, formulation, smearing, orientation=orientation
    )
    statics = SliderStatics(structure, supports, sliders, method="condensed")
    f = structure.gather(1, P.nodal_load("end", (30.0, 1.0e3, -4.0e2), (5.0, 0.0, 0.0)))
    assert_same_solve(statics, f)


@pytest.mark.parametrize("line", ["arc", "helix"])
@pytest.mark.parametrize("kind", ["spherical", "classical"])
def test_rigid_lines(kind, line) -> None:
    """A beam's tip on a rigid arc and helix, off the node (the lever arm).  (The spline
    slider needs its frame matched to the line's where it starts: it is solved on the chains
    of the sliding beams above.)"""
    batch = batch_of(kind, "section", line, OFFSETS["off the node"])
    slider, structure = batch.sliders[0], batch.structures[0]
    statics = SliderStatics(structure, [Support(0, "start")], [slider], method="condensed")
    f = structure.nodal_load((0, "end"), (0.0, 0.02, -0.01))
    assert_same_solve(statics, f)


@pytest.mark.parametrize("kind", ["spherical", "classical"])
def test_curved_chain_and_driven_body(kind) -> None:
    """A massless body driven along an arched chain of two beams across their junction
    (curved elements, a drive in place of the ``xi`` equation), and a bead on a cubic
    spline with end stops."""
    a = Beam(arc((0, 0, 0), 1.0, 0.0, 0.8, 3, 3, name="a"), SECTION, "fv3")
    b = Beam(arc((0, 0, 0), 1.0, 0.8, 1.6, 2, 3, name="b"), SECTION, "fv3")
    body = RigidBody("cart", (np.cos(0.5), np.sin(0.5), 0.0))
    structure = Structure([a, b], ties=[("a.end", "b.start")], bodies=[body])
    line = BeamChain(structure, ["a", "b"], "arch")
    motion = Linear(0.5, 0.4)
    slider = Slider(kind, line, "cart", drive=motion, smearing=0.03, name="cart")
    supports = [Support("a.start"), Support("b.end"), Support("cart", kind="rx+ry+rz")]
    statics = SliderStatics(structure, supports, [slider], method="condensed")
    f = structure.nodal_load("cart", (0.0, 0.0, -3.0e2))
    for time in (0.0, 0.7, 0.8):  # xi = 0.5, 0.78, 0.82
        assert_same_solve(statics, f, time)
    rail = CubicSpline([(0, 0, 0), (0.5, 0.2, 0.0), (1.0, 0.1, 0.0), (1.4, -0.3, 0.0)])
    tip = Beam(straight((0, 0, 0), (1.0, 0.1, 0.0), 2, 3, name="tip"), SECTION, "fv3")
    structure = Structure([tip])
    bead = Slider(kind, rail, "tip.end", end_stops=True, name="bead")
    statics = SliderStatics(structure, [Support("tip.start")], [bead], method="condensed")
    assert_same_solve(statics, structure.nodal_load("tip.end", (5.0e3, -1.0e3, 0.0)))


def test_failures_are_reported_as_the_reference_reports_them() -> None:
    """A tip pushed along its rail past the rail's end: the error naming the slider, as the
    reference raises it; the piston's spin about its axis left free: the message naming
    the motion."""
    rail = StraightLine((1.0, -1.0, 0.0), (1.0, 1.0, 0.0), up=(0, 0, 1))
    tip = Beam(straight((0, 0, 0), (1.0, 0.0, 0.0), 2, 3, name="tip"), SECTION, "fv3")
    structure = Structure([tip])
    bead = Slider("spherical", rail, "tip.end", name="bead")
    push = structure.nodal_load("tip.end", (0.0, 1.0e6, 0.0))
    messages = []
    for method in ("condensed", "bordered"):
        statics = SliderStatics(structure, [Support("tip.start")], [bead], method=method)
        with pytest.raises(ValueError) as error:
            statics.solve(push)
        messages.append(str(error.value))
    # the abscissa where each left the line differs in its last digits (other roundoff)
    for message in messages:
        assert message.startswith("slider 'bead': straight line: xi = ")
        assert message.endswith("lies outside the line [0, 2.0]")
    structure, supports, sliders, P = sliding_beams_model(0.2 * 0.6, 3, "spherical")
    unheld = [supports[0], Support(1, "start", "ux")]
    spinning = SliderStatics(structure, unheld, sliders, method="condensed")
    load = structure.gather(1, P.nodal_load("end", (0, 1.0, 0)))
    message = spinning.newton(load, None, TOL, 25)
    assert isinstance(message, str) and "rotating about x" in message


def test_a_problem_too_large_for_the_columns_turns_bordered(monkeypatch) -> None:
    """With the columns' memory capped below what the sliding beams need, ``auto`` solves on
    the bordered back end (the same solution), and ``condensed`` says why it cannot."""
    from sliders.solve import newton

    monkeypatch.setattr(newton, "COLUMN_BYTES", 1024)
    structure, supports, sliders, P = sliding_beams_model(0.3 * 0.6, 3, "spherical")
    f = structure.gather(1, P.nodal_load("end", (0, 1.0, 0)))
    auto = SliderStatics(structure, supports, sliders)
    q = auto.solve(f).q
    assert auto.method == "bordered"
    reference = SliderStatics(structure, supports, sliders, method="bordered").solve(f).q
    assert np.array_equal(q, reference)
    with pytest.raises(ValueError, match="solve with method='bordered'"):
        SliderStatics(structure, supports, sliders, method="condensed").solve(f)
