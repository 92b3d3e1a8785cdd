"""Static equilibrium of a geometrically exact beam: Newton with automatic load stepping.

The problem is ``r(q) = lambda f`` on the free dofs, ``r`` the internal forces of an
:class:`~fvbeam.exact_beam.ExactBeam`, ``f`` *dead* nodal forces and couples (fixed in
global axes; with the spatial rotation increments of the beam a dead couple does no work on
the tangent, so none is added to it), ``lambda`` the load factor raised from 0 to 1, and the
supports clamping the dofs they name (zero increment, so a clamped node keeps its reference
position and rotation).

**Newton** on each load step: ``K_ff dq = lambda f_f - r_f(q)``, the state updated on the
manifold (:meth:`~fvbeam.exact_beam.ExactState.updated`).

**Convergence** is judged against the round-off floor of the residual, not a fixed tolerance:
each dof's residual is a sum of terms (:meth:`~fvbeam.exact_beam.ExactBeam.residual_floor`)
that carry rounding errors of ``eps`` times their magnitudes and of the stresses' own
rounding (``eps`` times the stiffness times the magnitudes of the terms of the strains, which
cancel: ``Lambda^T x' - x0'``); a residual below :data:`FLOOR_FACTOR` times that bound
holds no more information, whatever the load's size.  So a slender member with
``EA L^2 / EJ = 1e8``, whose axial stiffness magnifies the strains' rounding into forces far
above ``eps`` times the load, converges instead of stalling.  A step is also accepted when its
residual is below ``tolerance`` times the load.

**Load stepping**: a step that does not converge in ``max_iterations``, or whose residual
is still above its first after :data:`STALL` iterations, is halved and retried from the
last converged state; a step that converges in few iterations is doubled (up to the rest of
the load).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from fvbeam.exact_beam import ExactState
from fvbeam.geometry import sized

#: The residual's round-off floor: a dof's residual is a sum of a few terms (at most two per
#: evaluation point of its elements and the load), each with a relative rounding error of a
#: few ``eps``; 16 bounds their sum.
FLOOR_FACTOR = 16.0
#: Fewest iterations that make the next load step larger.
FAST = 5
#: Iterations after which a step whose residual is still above its first is given up (and
#: halved): Newton's residual may rise for a few iterations on the way to a large rotation.
STALL = 10


@dataclass(frozen=True)
class ExactStaticResult:
    """A converged equilibrium and how it was reached.

    ``load_factors`` the converged load steps, ``iterations`` Newton iterations per step,
    ``attempts`` the steps tried (failed ones included), ``newton_iterations`` the
    iterations of all of them (the cost), ``floor_ratio`` the final residual over its
    round-off floor (the largest over the free dofs; below 1 when converged on the floor).
    """

    state: ExactState
    load_factors: list[float] = field(default_factory=list)
    iterations: list[int] = field(default_factory=list)
    attempts: int = 0
    newton_iterations: int = 0
    floor_ratio: float = 0.0


class StaticOperator(Protocol):
    """What :func:`solve_static` needs of a structure: an
    :class:`~fvbeam.exact_beam.ExactBeam`, or the beams of a structure on its global dofs
    (:class:`~fvbeam.exact_structure.ExactStructure`)."""

    n_dofs: int

    @property
    def name(self) -> str: ...

    def reference(self) -> ExactState: ...

    def points(self, state: ExactState) -> Any: ...

    def residual(self, state: ExactState, pts: Any = None) -> np.ndarray: ...

    def residual_floor(self, state: ExactState, pts: Any = None) -> np.ndarray: ...

    def tangent(self, state: ExactState, pts: Any = None, keep: Any = None) -> sp.spmatrix: ...


class NotConverged(RuntimeError):
    """The load step fell below ``min_step`` without converging."""


def _free(n_dofs: int, fixed: np.ndarray) -> np.ndarray:
    """The dofs not in ``fixed``, or ``ValueError`` naming a fixed dof outside the beam."""
    held = np.asarray(fixed, dtype=np.int64).ravel()
    outside = held[(held < 0) | (held >= n_dofs)]
    if outside.size:
        raise ValueError(f"fixed dof {int(outside[0])} is not one of the beam's 0..{n_dofs - 1}")
    mask = np.ones(n_dofs, dtype=bool)
    mask[held] = False
    return np.flatnonzero(mask)


def solve_static(
    beam: StaticOperator,
    load: np.ndarray,
    fixed: np.ndarray,
    state: ExactState | None = None,
    tolerance: float = 1e-12,
    max_iterations: int = 25,
    first_step: float = 1.0,
    min_step: float = 1e-6,
) -> ExactStaticResult:
    """Equilibrium of ``beam`` under the dead nodal ``load`` (6 per node), the dofs
    ``fixed`` clamped, from ``state`` (default the reference), by Newton with automatic load
    stepping (module docstring).

    Raises
    ------
    NotConverged
        When a load step below ``min_step`` fails, naming the load factor reached.
    """
    name = beam.name
    f = sized(load, beam.n_dofs, "load", f"6 per node of beam {name!r}")
    if not np.all(np.isfinite(f)):
        raise ValueError(f"load on beam {name!r} has a non-finite entry")
    free = _free(beam.n_dofs, fixed)
    current = beam.reference() if state is None else state
    done, step = 0.0, min(first_step, 1.0)
    factors: list[float] = []
    iterations: list[int] = []
    attempts, total, ratio = 0, 0, 0.0
    while done < 1.0:
        target = min(1.0, done + step)
        attempts += 1
        trial, its, ok, ratio = _newton(beam, f, target, free, current, tolerance, max_iterations)
        total += its
        if ok:
            current, done = trial, target
            factors.append(target)
            iterations.append(its)
            if its <= FAST:
                step *= 2.0
            continue
        step /= 2.0
        if step < min_step:
            raise NotConverged(
                f"{name}: Newton did not converge beyond load factor "
                f"{done:.6g} (a step of {step:.3g} failed; residual {ratio:.3g} times its "
                "round-off floor)"
            )
    return ExactStaticResult(current, factors, iterations, attempts, total, ratio)


def _newton(
    beam: StaticOperator,
    f: np.ndarray,
    factor: float,
    free: np.ndarray,
    state: ExactState,
    tolerance: float,
    max_iterations: int,
) -> tuple[ExactState, int, bool, float]:
    """Newton at one load factor: the state, the iterations, whether it converged and the
    residual over its floor."""
    target = factor * f[free]
    scale = tolerance * max(float(np.abs(target).max(initial=0.0)), np.finfo(float).tiny)
    ratio = np.inf
    first = np.inf
    for it in range(max_iterations + 1):
        pts = beam.points(state)
        g = target - beam.residual(state, pts)[free]
        terms = beam.residual_floor(state, pts)[free] + np.abs(target)
        floor = FLOOR_FACTOR * np.finfo(float).eps * terms
        ratio = float(np.max(np.abs(g) / np.maximum(floor, np.finfo(float).tiny)))
        size = float(np.abs(g).max(initial=0.0))
        if ratio <= 1.0 or size <= scale:
            return state, it, True, ratio
        if it == 0:
            first = size
        stalled = it >= STALL and size > first
        if it == max_iterations or stalled or not np.isfinite(size):
            break
        try:
            dq_free = spla.splu(beam.tangent(state, pts, free)).solve(g)
        except RuntimeError:  # an exactly singular tangent: let the load step shrink
            break
        dq = np.zeros(beam.n_dofs)
        dq[free] = dq_free
        state = state.updated(dq)
    return state, it, False, ratio
