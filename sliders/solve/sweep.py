"""Continuation sweeps: a sequence of parameter values, each solved from the previous point.

``build(value)`` returns the statics and the load of one point (a slider position moves the
geometry, a load factor scales the load, ...); a list of load vectors on one structure is
``sweep(loads, lambda f: (statics, f))``.  Each point starts from a prediction when the
unknowns have the same shapes (continuation), else from the default start
(:meth:`sliders.solve.statics.SliderStatics.solve`): for real values, the secant through the last
two converged points (``z + (v - v_1) / (v_1 - v_0) (z_1 - z_0)``, exact for unknowns
linear in the value, such as the abscissae of a slider moved along its line); otherwise, or
with a single converged point, the last converged point.

Failures and interruptions keep what was computed:

- a point whose ``build`` raises ``ValueError`` is recorded as failed with its message;
- a point whose warm start fails (``ValueError``: singular configuration, no convergence) is
  retried from the default start; if that fails too, its message is recorded in
  :attr:`SweepPoint.error` and the sweep goes on (or stops, with ``stop_on_failure``), the
  next point starting from the last converged one;
- ``KeyboardInterrupt`` (in ``build`` or in Newton) ends the sweep: the completed points are
  returned with :attr:`SweepResult.interrupted` set, and the caller decides what to do.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from numbers import Real
from typing import Any

import numpy as np

from sliders.solve.statics import SliderSolution, SliderStatics, solve_many

Build = Callable[[Any], tuple[SliderStatics, np.ndarray]]


@dataclass(frozen=True)
class SweepPoint:
    """One parameter ``value``: its ``solution``, or ``None`` and the ``error`` message;
    ``warm`` when it converged from the predicted start."""

    value: Any
    solution: SliderSolution | None
    error: str | None = None
    warm: bool = False


@dataclass
class SweepResult:
    """The points computed, in order; ``interrupted`` when a ``KeyboardInterrupt`` ended the
    sweep, ``stopped`` when a failure did (``stop_on_failure``)."""

    points: list[SweepPoint] = field(default_factory=list)
    interrupted: bool = False
    stopped: bool = False

    @property
    def values(self) -> list[Any]:
        return [p.value for p in self.points]

    @property
    def solutions(self) -> list[SliderSolution | None]:
        return [p.solution for p in self.points]

    @property
    def failures(self) -> list[tuple[Any, str]]:
        """``(value, message)`` of every point that did not converge."""
        return [(p.value, p.error) for p in self.points if p.error is not None]


def sweep(
    values: Iterable[Any],
    build: Build,
    *,
    continuation: bool = True,
    stop_on_failure: bool = False,
    progress: bool = True,
    desc: str = "sweep",
    **solve_options: Any,
) -> SweepResult:
    """Solve ``build(value)`` for every value, each point from the previous converged one.

    Parameters
    ----------
    values
        The parameter values, in the order of the continuation.
    build
        ``value -> (statics, load vector)``.
    continuation
        Start each point from the last converged one (``False``: every point cold).
    stop_on_failure
        End the sweep at the first point that fails from both starts.
    progress
        A tqdm progress bar on a terminal (never when the output is not a terminal).
    **solve_options
        Passed to :meth:`SliderStatics.solve` (``tol``, ``max_iterations``, ``load_steps``).

    Returns
    -------
    SweepResult
        The points computed (all of them, unless interrupted or stopped).
    """
    from tqdm import tqdm

    if "start" in solve_options:
        raise ValueError("sweep chooses each point's start; do not pass start")
    result = SweepResult()
    converged: list[SweepPoint] = []
    values = list(values)
    with tqdm(values, disable=None if progress else True, desc=desc) as bar:
        try:
            for value in bar:
                try:
                    statics, f = build(value)
                except ValueError as exc:
                    point = SweepPoint(value, None, str(exc))
                else:
                    start = _predict(statics, value, converged) if continuation else None
                    point = _solve_point(statics, f, value, start, solve_options)
                result.points.append(point)
                if point.solution is not None:
                    converged = converged[-1:] + [point]
                elif stop_on_failure:
                    result.stopped = True
                    break
        except KeyboardInterrupt:
            result.interrupted = True
    return result


def _predict(
    statics: SliderStatics, value: Any, converged: list[SweepPoint]
) -> tuple[np.ndarray, list[np.ndarray]] | None:
    """Start of the point at ``value`` from the last (up to two) converged points, or None
    when they do not fit ``statics``' unknowns."""
    shape = _shape(statics)
    fitting = [
        p for p in converged if p.solution is not None and _solution_shape(p.solution) == shape
    ]
    if not fitting:
        return None
    last = fitting[-1].solution
    assert last is not None
    if len(fitting) == 2 and _secant(value, fitting[0].value, fitting[1].value):
        first = fitting[0].solution
        assert first is not None
        c = (value - fitting[1].value) / (fitting[1].value - fitting[0].value)
        return (
            last.q + c * (last.q - first.q),
            [y1 + c * (y1 - y0) for y1, y0 in zip(last.unknowns, first.unknowns, strict=True)],
        )
    return last.q, last.unknowns


def _secant(value: Any, v0: Any, v1: Any) -> bool:
    """Whether the secant through the points at ``v0`` and ``v1`` predicts ``value``: real
    values, ``v0`` and ``v1`` apart."""
    real = (float, int, np.floating, np.integer)
    if not all(isinstance(v, real) or isinstance(v, Real) for v in (value, v0, v1)):
        return False
    return bool(v0 != v1)


def _solve_point(
    statics: SliderStatics,
    f: np.ndarray,
    value: Any,
    start: tuple[np.ndarray, list[np.ndarray]] | None,
    options: dict[str, Any],
) -> SweepPoint:
    """One point: from ``start`` if any, then cold; the failure message otherwise."""
    if start is not None:
        try:
            return SweepPoint(value, statics.solve(f, start=start, **options), warm=True)
        except ValueError:
            pass
    try:
        return SweepPoint(value, statics.solve(f, **options))
    except ValueError as exc:
        return SweepPoint(value, None, str(exc))


def _shape(statics: SliderStatics) -> tuple[int, list[int]]:
    """The shapes of ``statics``' unknowns: its dofs and each slider's unknowns."""
    return statics.structure.n_dofs, [s.n_unknowns for s in statics.sliders]


def _solution_shape(solution: SliderSolution) -> tuple[int, list[int]]:
    """The shapes of ``solution``'s unknowns, as :func:`_shape` gives a problem's."""
    return len(solution.q), [len(y) for y in solution.unknowns]


def sweep_batched(
    values: Iterable[Any], build: Build, *, tol: float = 1e-8, max_iterations: int = 25
) -> SweepResult:
    """Solve ``build(value)`` for every value, all points at once (no continuation).

    The points are independent problems; those whose statics share an operator (built with
    ``reuse``, as :class:`studies.fig4_stiffness.SlidingBeams` does) are solved together by
    :func:`sliders.solve.statics.solve_many`, each from its default start, each converging or
    failing on its own.  Same points, solutions and failure messages as
    ``sweep(values, build, continuation=False)`` (to roundoff); a point whose ``build``
    raises ``ValueError`` is recorded as failed.  ``KeyboardInterrupt`` returns the groups
    completed, with :attr:`SweepResult.interrupted` set.
    """
    values = list(values)
    points: list[SweepPoint | None] = [None] * len(values)
    groups: dict[int, list[tuple[int, SliderStatics, np.ndarray]]] = {}
    result = SweepResult()
    try:
        for i, value in enumerate(values):
            try:
                statics, f = build(value)
            except ValueError as exc:
                points[i] = SweepPoint(value, None, str(exc))
                continue
            groups.setdefault(id(statics.K), []).append((i, statics, f))
        for group in groups.values():
            outcomes = solve_many(
                [g[1] for g in group], [g[2] for g in group], tol=tol, max_iterations=max_iterations
            )
            for (i, _, _), outcome in zip(group, outcomes, strict=True):
                points[i] = (
                    SweepPoint(values[i], None, outcome)
                    if isinstance(outcome, str)
                    else SweepPoint(values[i], outcome)
                )
    except KeyboardInterrupt:
        result.interrupted = True
    result.points = [p for p in points if p is not None]
    return result
