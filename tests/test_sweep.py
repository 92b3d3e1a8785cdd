"""Continuation sweeps: iterations against cold starts, same solutions, failures, interruption.

Solutions are compared with the first-order agreement bound of tests/test_condensed.py.
"""

import numpy as np
import pytest
from test_condensed import agreement_bound, state

from sliders.sliding_beams.model import SlidingBeams
from sliders.solve.sweep import sweep

STATIONS = np.arange(0, 93, 4) / 100


@pytest.mark.parametrize("kind", ["spherical", "classical"])
def test_continuation_needs_no_more_iterations_than_cold_starts(kind):
    """Sliding-beams sweep (fv3, 3 elements): from the secant prediction every point takes at
    most the iterations of a cold start, and the same solution."""
    cold = sweep(STATIONS, SlidingBeams("fv3", 3, kind).problem, continuation=False, progress=False)
    model = SlidingBeams("fv3", 3, kind)
    built = []

    def build(s):
        built.append(model.problem(s))
        return built[-1]

    warm = sweep(STATIONS, build, progress=False)
    assert not cold.failures and not warm.failures
    assert all(p.warm for p in warm.points[1:])
    for (statics, f), a, b in zip(built, cold.solutions, warm.solutions, strict=True):
        assert b.iterations <= a.iterations
        difference = np.abs(state(statics, a) - state(statics, b))
        assert np.all(difference <= agreement_bound(statics, a, b, f))
    assert sum(s.iterations for s in warm.solutions) < sum(s.iterations for s in cold.solutions)


def test_failed_points_are_recorded_and_the_sweep_goes_on():
    """Classical sliders of the slope form on one fv3 element go singular for short overlaps
    (docs/sliders.md): those points carry the diagnostic, the others converge."""
    stations = np.array([0.5, 0.6, 0.9, 0.95, 0.7])
    result = sweep(
        stations, SlidingBeams("fv3", 1, "classical", orientation="slope").problem, progress=False
    )
    assert result.values == list(stations) and not result.interrupted
    failed = dict(result.failures)
    assert set(failed) == {0.9, 0.95}
    assert all("singular configuration" in message for message in failed.values())
    assert result.points[-1].solution is not None

    stopped = sweep(
        stations,
        SlidingBeams("fv3", 1, "classical", orientation="slope").problem,
        stop_on_failure=True,
        progress=False,
    )
    assert stopped.stopped and stopped.values == [0.5, 0.6, 0.9]


def test_interruption_keeps_the_completed_points():
    model = SlidingBeams("fv3", 3, "spherical")

    def build(s):
        if s > 0.15:
            raise KeyboardInterrupt
        return model.problem(s)

    result = sweep([0.0, 0.1, 0.2, 0.3], build, progress=False)
    assert result.interrupted and result.values == [0.0, 0.1]
    assert all(p.solution is not None for p in result.points)


def test_load_sweep_on_one_structure():
    """A list of load vectors (not real values: each point starts from the previous one)
    gives the solutions of separate solves."""
    statics, f = SlidingBeams("fv3", 3, "classical").problem(0.4)
    loads = [c * f for c in (1.0, 2.0, 3.0)]
    result = sweep(loads, lambda g: (statics, g), progress=False)
    for g, b in zip(loads, result.solutions, strict=True):
        a = statics.solve(g)
        difference = np.abs(state(statics, a) - state(statics, b))
        assert np.all(difference <= agreement_bound(statics, a, b, g))


def test_start_is_chosen_by_the_sweep():
    statics, f = SlidingBeams("fv3", 1, "spherical").problem(0.4)
    with pytest.raises(ValueError, match="do not pass start"):
        sweep([f], lambda g: (statics, g), start=None, progress=False)


@pytest.mark.parametrize("kind", ["spherical", "classical"])
def test_a_swept_point_is_freed_as_soon_as_it_is_dropped(kind):
    """A sweep's points hold no reference cycles (the compiled loop holds its statics
    weakly): with the garbage collector off, a sweep of moved problems and a cold solve
    leave nothing for it to collect, and a dropped problem is gone at once.  (The kernels
    are called once before, so that what numba builds when it first loads them is not
    counted.)"""
    import gc
    import weakref

    model = SlidingBeams("fv3", 1, kind)

    def sweep_and_cold_solve() -> tuple:
        result = sweep(STATIONS[:6], model.problem, progress=False)
        statics, f = model.problem(0.5)
        return result, statics, statics.solve(f)

    sweep_and_cold_solve()
    gc.collect()
    gc.disable()
    try:
        result, statics, _ = sweep_and_cold_solve()
        gone = weakref.ref(statics)
        model._previous = None
        del statics
        assert gone() is None
        assert gc.collect() == 0
    finally:
        gc.enable()
    assert not result.failures
