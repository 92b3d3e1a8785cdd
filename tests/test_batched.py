"""Batched Newton (``solve_many``, ``sweep_batched``) against the per-point solver.

Both run the same joint equations (the per-point evaluation is the batch of one) and the same
Newton loop and convergence rule; they differ in the order of floating-point operations (a
stacked solve of all members).  Two converged states therefore agree to the first-order
roundoff bound of tests/test_condensed.py (``agreement_bound``), with the same iteration
counts and the same failure messages.
"""

import dataclasses

import numpy as np
import pytest
from test_condensed import agreement_bound, state, tip_on_an_arc
from test_spline_slider import line_with_body

from fvbeam import Support
from sliders.joints.slider import SliderBatch
from sliders.sliding_beams.model import SlidingBeams
from sliders.solve.statics import SliderStatics, solve_many, solve_translated
from sliders.solve.sweep import sweep_batched

STATIONS = np.array([0.0, 0.13, 0.4, 0.77, 0.95])


def agree(statics, a, b, f):
    assert b.iterations == a.iterations
    difference = np.abs(state(statics, a) - state(statics, b))
    assert np.all(difference <= agreement_bound(statics, a, b, f))


def same_outcome(statics, f, outcome):
    """The per-point solve's solution (within the bound) or its error message."""
    try:
        expected = statics.solve(f)
    except ValueError as exc:
        assert outcome == str(exc)
        return False
    agree(statics, expected, outcome, f)
    return True


@pytest.mark.parametrize("kind", ["spherical", "classical"])
@pytest.mark.parametrize("name", ["fv2", "fv3", "galerkin-p2"])
@pytest.mark.parametrize("smearing", [0.0, 0.01])
def test_sliding_beams_sweep_equals_per_point_solves(kind, name, smearing):
    """The piston at several positions (one element per beam and three), solved together
    and one by one, on the condensed back end (fv2 with one element has singular classical
    pairs for short overlaps: the same message)."""
    for n in (1, 3):
        model = SlidingBeams(name, n, kind, smearing)
        built = [model.problem(s) for s in STATIONS]
        points = iter(built)
        batched = sweep_batched(STATIONS, lambda s, points=points: next(points))
        assert batched.values == list(STATIONS)
        converged = [
            same_outcome(statics, f, p.solution or p.error)
            for (statics, f), p in zip(built, batched.points, strict=True)
        ]
        assert sum(converged) >= 3


@pytest.mark.parametrize("kind", ["spherical", "classical"])
@pytest.mark.parametrize("name", ["fv3", "galerkin-p2"])
@pytest.mark.parametrize("smearing", [0.0, 0.01])
def test_translated_template_equals_the_built_members(kind, name, smearing):
    """The sweep from one template moved (``solve_translated``) and from a statics built per
    position (``solve_many``): failures with the same message, the same iterations and,
    without smearing, the same numbers (the moved node positions are the same sums); with
    smearing, equal to roundoff (the compiled smeared transfer reads the same moved node
    positions; measured equal exactly)."""
    model = SlidingBeams(name, 3, kind, smearing)
    built = [model.problem(s) for s in STATIONS]
    for (statics, f), a, b in zip(
        built,
        solve_many([m[0] for m in built], [m[1] for m in built]),
        model.solve(STATIONS),
        strict=True,
    ):
        if isinstance(a, str):
            assert b == a
            continue
        if smearing:
            agree(statics, a, b, f)
            continue
        assert b.step_iterations == a.step_iterations and b.residuals == a.residuals
        assert np.array_equal(b.q, a.q)
        assert all(np.array_equal(x, y) for x, y in zip(b.unknowns, a.unknowns, strict=True))


@pytest.mark.parametrize("kind", ["spherical", "classical"])
def test_translated_beam_on_a_rigid_line(kind):
    """A clamped beam's tip on a rigid arc (tests/test_condensed.py), the beam moved off the
    arc by a few shifts: the line stays, the body moves; the same numbers as statics built
    on the moved beams."""
    from fvbeam import Structure

    structure, slider, f = tip_on_an_arc(kind)
    supports = [Support(0, "start")]
    template = SliderStatics(structure, supports, [slider], method="condensed")
    shifts = np.zeros((3, 1, 3))
    shifts[:, 0] = [[0.0, 0.0, 0.0], [0.01, 0.0, 0.0], [-0.02, 0.01, 0.0]]
    built = []
    for shift in shifts[:, 0]:
        moved = Structure([structure.beams[0].translated(shift)])
        built.append(
            SliderStatics(
                moved, supports, [dataclasses.replace(slider)], reuse=template, method="condensed"
            )
        )
    expected = solve_many(built, [f] * 3)
    for a, b in zip(expected, solve_translated(template, shifts, [f] * 3), strict=True):
        assert b.step_iterations == a.step_iterations and np.array_equal(b.q, a.q)
        assert all(np.array_equal(x, y) for x, y in zip(b.unknowns, a.unknowns, strict=True))


def test_translated_shifts_and_loads_are_checked():
    model = SlidingBeams("fv3", 1, "spherical")
    statics, f = model.template
    with pytest.raises(ValueError, match=r"shifts must be \(B, 2, 3\)"):
        solve_translated(statics, np.zeros((2, 1, 3)), [f, f])
    with pytest.raises(ValueError, match="loads must be 2 finite vectors"):
        solve_translated(statics, model.shifts([0.1, 0.2]), [f])


def test_failures_carry_the_per_point_message():
    """The slope form's singular pair on one fv3 element (docs/sliders.md): the batch
    reports, per member, the message the per-point solve raises; the others converge."""
    model = SlidingBeams("fv3", 1, "classical", orientation="slope")
    stations = [0.5, 0.9, 0.6, 0.95]
    built = [model.problem(s) for s in stations]
    outcomes = solve_many([b[0] for b in built], [b[1] for b in built])
    converged = [
        same_outcome(statics, f, outcome)
        for (statics, f), outcome in zip(built, outcomes, strict=True)
    ]
    assert converged == [True, False, True, False]
    assert all("singular configuration" in outcomes[i] for i in (1, 3))
    assert [o if isinstance(o, str) else o.iterations for o in model.solve(stations)] == [
        o if isinstance(o, str) else o.iterations for o in outcomes
    ]


@pytest.mark.parametrize("method", ["bordered", "condensed"])
def test_spline_slider_on_a_chain_under_several_torques(method):
    """The twist test's problem (tests/test_spline_slider.py) under three torques: one
    statics shared by three members."""
    structure, supports, slider, f = line_with_body("fv3", 4, 0.37, 100.0)
    statics = SliderStatics(structure, supports, [slider], method=method)
    loads = [c * f for c in (1.0, -0.5, 3.0)]
    for g, b in zip(loads, solve_many([statics] * 3, loads), strict=True):
        agree(statics, statics.solve(g), b, g)


@pytest.mark.parametrize("kind", ["spherical", "classical"])
def test_rigid_line_under_several_loads(kind):
    """A clamped beam's tip on a rigid arc (tests/test_condensed.py) under three loads."""
    structure, slider, f = tip_on_an_arc(kind)
    statics = SliderStatics(structure, [Support(0, "start")], [slider], method="condensed")
    loads = [c * f for c in (1.0, 0.5, 2.0)]
    for g, b in zip(loads, solve_many([statics] * 3, loads), strict=True):
        agree(statics, statics.solve(g), b, g)


def test_members_must_share_the_operator():
    one, f = SlidingBeams("fv3", 3, "spherical").problem(0.2)
    other, g = SlidingBeams("fv3", 3, "spherical").problem(0.4)
    with pytest.raises(ValueError, match="does not share member 0's operator"):
        solve_many([one, other], [f, g])
    with pytest.raises(ValueError, match="loads must be 2 finite vectors"):
        solve_many([one, one], [f])


def test_members_must_have_alike_sliders():
    """A slider placed differently (offset, frame) in one member is named."""
    model = SlidingBeams("fv3", 3, "classical")
    members = [model.problem(s)[0] for s in (0.2, 0.4, 0.6)]
    sliders = [m.sliders[0] for m in members]
    structures = [m.structure for m in members]
    SliderBatch(sliders, structures)
    turned = dataclasses.replace(sliders[2], frame=np.eye(3)[:, [0, 2, 1]] * [1, 1, -1])
    with pytest.raises(ValueError, match="slider of member 2 of the batch differs"):
        SliderBatch(sliders[:2] + [turned], structures)
    moved = dataclasses.replace(sliders[1], offset=(0.0, 1e-3, 0.0))
    with pytest.raises(ValueError, match="slider of member 1 of the batch differs"):
        SliderBatch([sliders[0], moved, sliders[2]], structures)


@pytest.mark.parametrize("kind", ["spherical", "classical"])
def test_joined_batch_evaluates_each_slider_as_its_own(kind):
    """The two joints of the sliding-beams pair (on different beams, so different dof maps)
    joined in one batch (:meth:`SliderBatch.joined`, one evaluation per Newton iteration):
    each half is its slider's own evaluation, the same operations on the same numbers, so
    equal bit for bit; a joint differing in its frame is named."""
    statics, _ = SlidingBeams("fv3", 3, kind).problem(0.3)
    batches = [SliderBatch([s], [statics.structure]) for s in statics.sliders]
    rng = np.random.default_rng(0)
    q = 1e-2 * rng.standard_normal((1, statics.structure.n_dofs))
    ys = [
        np.concatenate([[0.2 * b.length], rng.standard_normal(b.n_unknowns - 1)])[None]
        for b in batches
    ]
    dofs, r, J = SliderBatch.joined(batches).evaluate(np.tile(q, (2, 1)), np.concatenate(ys))
    for k, (batch, y) in enumerate(zip(batches, ys, strict=True)):
        own_dofs, own_r, own_J = batch.evaluate(q, y)
        assert np.array_equal(dofs[k], own_dofs[0]) and np.array_equal(r[k], own_r[0])
        assert np.array_equal(J.subset(np.array([k])).dense(), own_J.dense())
    turned = dataclasses.replace(statics.sliders[1], frame=np.eye(3)[:, [0, 2, 1]] * [1, 1, -1])
    with pytest.raises(ValueError, match="B: its joints differ from A's"):
        SliderBatch.joined([batches[0], SliderBatch([turned], [statics.structure])])
