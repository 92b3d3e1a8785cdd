"""Static equilibrium of a geometrically exact beam: Newton with automatic load stepping.

The problem is ``r(q) = lambda f`` on the free dofs, ``r`` the internal forces of an
:class:`~fvbeam.exact_beam.ExactBeam`, ``f`` *dead* loads (fixed in global axes; with the
spatial rotation increments of the beam a dead couple does no work on the tangent, so none
is added to it): nodal forces and couples, or loads between nodes, whose lever arms follow
the configuration, with their load stiffness in the tangent (:mod:`fvbeam.exact_loads`);
``lambda`` the load factor raised from 0 to 1, and the supports clamping the dofs they name
(zero increment, so a clamped node keeps its reference position and rotation).

**Newton** on each load step: ``K_ff dq = lambda f_f - r_f(q)``, the state updated on the
manifold (:meth:`~fvbeam.exact_beam.ExactState.updated`), then its **positions corrected**
so that the force balances hold exactly.  A Newton update leaves strains of the order of its
rotations squared (the linearisation's error in ``nu = Lambda^T x' - x0'``), which the axial
and shear stiffness of a slender member turn into forces of ``EA |dphi|^2``: Newton then
spends every other iteration removing them, and diverges from a load a soft member carries
easily.  At fixed rotations, though, the strains ``nu``, and so the forces ``F`` and the
force balances ``r_u``, are *affine* in the positions (``kappa`` does not depend on them):
one solve with the tangent's position block, ``K_uu du = lambda f_u - r_u``, the rotations
kept, satisfies them exactly (a nonlinear elimination of the positions, one step of it per
iteration).  Newton's remaining error is in the moment balances, governed by the bending
stiffness.

**Step length**: an increment that turns a node by more than :data:`MAX_TURN` (a radian) in
any component is scaled down to it, its direction kept.  The linearisation behind it (the
tangent operators of the rotations, the lever arms) holds for small turns only, and the
first iterate of a large load (the linear solution: a tip rotation of 5 rad for the elastica
at ``P L^2 / EJ = 10``) lies far outside it; near the solution the increments are small and
Newton's quadratic convergence is untouched.  With both, the elastica at ``P L^2 / EJ = 10``
with ``EA L^2 / EJ = 1e8`` converges in one load step of 4 iterations (56 in 4 steps
without them), the 45-degree bend in 4 (62).

**Convergence** is judged against the round-off floor of the residual, not a fixed tolerance:
each dof's residual is a sum of terms (:meth:`~fvbeam.exact_beam.ExactBeam.residual_floor`)
that carry rounding errors of ``eps`` times their magnitudes and of the stresses' own
rounding (``eps`` times the stiffness times the magnitudes of the terms of the strains, which
cancel: ``Lambda^T x' - x0'``); a residual below :data:`FLOOR_FACTOR` times that bound
holds no more information, whatever the load's size.  So a slender member with
``EA L^2 / EJ = 1e8``, whose axial stiffness magnifies the strains' rounding into forces far
above ``eps`` times the load, converges instead of stalling.  A step is also accepted when its
residual is below ``tolerance`` times the load.

**Arc length** (``method="arc-length"``), for paths with limit points, where the load
passes a maximum and no equilibrium is near a larger load (a snap-through): Crisfield's
cylindrical arc length (Crisfield, Comput. Struct. 13 (1981) 55-62).  The load factor joins
the unknowns; each step keeps the increment of the free positions from the last equilibrium
on the cylinder ``|Delta u| = arc``: its predictor along the tangent's response to the load,
``K dq_f = f``, in the direction of the last step, each correction ``dq_g + dlambda dq_f``
(``K dq_g = lambda f - r``) with the root ``dlambda`` of the constraint whose increment turns
least from the current one; the positions' force correction follows each iteration, at its
load factor.  The first arc is the linear response's position change at the load factor
``first_step``; a step converging in few iterations doubles the next (up to the linear
response at the full load), a step that fails, turns back along the path or turns a node by
more than :data:`MAX_TURN` halves it and is retried.  The path ends at the first crossing of
the full load, landed on by Newton at the load factor 1; ``result.path`` and
``result.load_factors`` hold the path traced
(``tests/test_exact_arc_length.py``: a shallow two-bar truss snapping through, against its
closed form).

**Load stepping**: a step that does not converge in ``max_iterations``, or whose residual
is still above its first after :data:`STALL` iterations, is halved and retried from the
last converged state; a step that converges in few iterations is doubled (up to the rest of
the load).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from fvbeam import rotations
from fvbeam.exact_beam import ExactState
from fvbeam.geometry import sized

#: The residual's round-off floor: a dof's residual is a sum of a few terms (at most two per
#: evaluation point of its elements and the load), each with a relative rounding error of a
#: few ``eps``; 16 bounds their sum.
FLOOR_FACTOR = 16.0
#: The largest rotation (radians, any component of a node's increment) a Newton iteration
#: applies; a larger increment is scaled down to it, the direction kept (module docstring).
MAX_TURN = 1.0
#: The most unknowns :func:`_solve` factorises densely: below it LAPACK's dense LU of a
#: beam's tangent (a few tens of nonzeros per row) costs less than SuperLU's ordering and
#: set-up (measured: fv3 with 8 elements, 96 and 48 unknowns, 135 and 44 us against 240 and
#: 90 us; 384 unknowns of fv2 with 64 elements, 3.4 ms against 0.75 ms).
DENSE = 128
#: The static solver's methods: load stepping, arc length (module docstring).
METHODS = ("load", "arc-length")
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
    round-off floor (the largest over the free dofs; below 1 when converged on the floor),
    ``path`` the converged state of each step (with ``load_factors``, the equilibrium path
    traced: through limit points with ``method="arc-length"``).
    """

    state: ExactState
    load_factors: list[float] = field(default_factory=list)
    iterations: list[int] = field(default_factory=list)
    attempts: int = 0
    newton_iterations: int = 0
    floor_ratio: float = 0.0
    path: list[ExactState] = field(default_factory=list)


class StaticOperator(Protocol):
    """What :func:`solve_static` needs of a structure: an
    :class:`~fvbeam.exact_beam.ExactBeam`, or the beams of a structure on its global dofs
    (:class:`~fvbeam.exact_structure.ExactStructure`)."""

    n_dofs: int
    #: The multipliers (dofs after the nodes' ``6 n``) of rows that hold positions: with
    #: the positions, the unknowns the force balances are affine in at fixed rotations
    #: (:func:`_balance_forces`); none for beams alone.
    position_multipliers: np.ndarray

    @property
    def name(self) -> str: ...

    def reference(self) -> ExactState: ...

    def points(self, state: ExactState) -> Any: ...

    def residual(self, state: ExactState, pts: Any = None) -> np.ndarray: ...

    def residual_floor(self, state: ExactState, pts: Any = None) -> np.ndarray: ...

    def tangent(self, state: ExactState, pts: Any = None, keep: Any = None) -> sp.spmatrix: ...


class Load(Protocol):
    """A dead load that depends on the configuration (:class:`fvbeam.exact_loads.DeadLoad`:
    loads between nodes, whose lever arms turn): its vector at a state and its derivative
    in the spatial increments, the load stiffness.  Dead: its forces are fixed, only its
    moments move, so the stiffness has no rows on positions (the position correction,
    :func:`_balance_forces`, takes none)."""

    def vector(self, state: Any) -> np.ndarray: ...

    def stiffness(self, state: Any) -> sp.spmatrix: ...


@dataclass(frozen=True)
class _Fixed:
    """Loads at nodes: the same vector in every configuration, no load stiffness."""

    f: np.ndarray

    def vector(self, state: Any) -> np.ndarray:
        return self.f

    def stiffness(self, state: Any) -> None:
        return None


def _tangent(
    beam: StaticOperator, load: Load, factor: float, state: Any, pts: Any, keep: np.ndarray
) -> sp.spmatrix:
    """The tangent of ``r(q) - factor f(q)`` on the dofs ``keep``."""
    K = beam.tangent(state, pts, keep)
    S = load.stiffness(state)
    return K if S is None or factor == 0 else sp.csc_matrix(K - factor * S[keep][:, keep])


class NotConverged(RuntimeError):
    """The load step (or arc length) fell below ``min_step`` without converging, or the
    arc length did not reach the full load in ``max_steps``."""


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
    load: np.ndarray | Load,
    fixed: np.ndarray,
    state: ExactState | None = None,
    tolerance: float = 1e-12,
    max_iterations: int = 25,
    first_step: float = 1.0,
    min_step: float = 1e-6,
    method: str = "load",
    max_steps: int = 1000,
    drives: Mapping[int, float] | None = None,
) -> ExactStaticResult:
    """Equilibrium of ``beam`` under the dead ``load`` (6 per node, or a :class:`Load` whose
    vector depends on the configuration: :class:`fvbeam.exact_loads.DeadLoad`), the dofs
    ``fixed`` clamped, from ``state`` (default the reference), by Newton with automatic load
    stepping (``method="load"``) or along the equilibrium path by arc length
    (``method="arc-length"``, through limit points; ``first_step`` sets the first arc length
    as the linear response's displacement at that load factor, ``min_step`` the smallest
    as a fraction of it, ``max_steps`` the most steps): module docstring.

    ``drives``: prescribed values of dofs at the full load (the load factor's share of
    each at every step, as the loads; load stepping only), held as ``fixed`` dofs are: a
    position dof moves its node along the global axis by the value (m); a rotation dof turns
    it about the global axis by the value (rad), each step's share applied on the manifold,
    ``R <- exp(d alpha e_k) R``, the spatial increments about that axis held otherwise (a
    node whose other rotations are held too, a clamp turned by a drive, ends at
    ``exp(alpha e_k)`` exactly); a step turns a driven node by at most :data:`MAX_TURN`.

    Raises
    ------
    NotConverged
        When a load step (arc length) below ``min_step`` fails, naming the load factor
        reached, or the arc length does not reach the full load in ``max_steps``.
    """
    name = beam.name
    if isinstance(load, np.ndarray | list | tuple):
        fixed_load = sized(load, beam.n_dofs, "load", f"6 per node of beam {name!r}")
        if not np.all(np.isfinite(fixed_load)):
            raise ValueError(f"load on beam {name!r} has a non-finite entry")
        f: Load = _Fixed(fixed_load)
    else:
        f = load
    if method not in METHODS:
        raise ValueError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    driven = {} if drives is None else {int(k): float(v) for k, v in drives.items()}
    if driven and method != "load":
        raise ValueError(f"drives take method 'load', not {method!r}")
    held = np.concatenate([np.asarray(fixed, dtype=np.int64).ravel(), list(driven)])
    free = _free(beam.n_dofs, held.astype(np.int64))
    move = np.zeros(beam.n_dofs)
    move[list(driven)] = list(driven.values())
    turns = np.abs(move[: 6 * len(beam.reference().x)].reshape(-1, 6)[:, 3:])
    # a driven turn of more than MAX_TURN per step is beyond the rotations' linearisation (and
    # a half turn, log's branch cut, could take either way round)
    cap = MAX_TURN / turns.max() if turns.size and turns.max() > 0 else np.inf
    current = beam.reference() if state is None else state
    if method == "arc-length":
        return _arc_length(
            beam, f, free, current, tolerance, max_iterations, first_step, min_step, max_steps
        )
    done, step = 0.0, min(first_step, 1.0)
    factors: list[float] = []
    iterations: list[int] = []
    path: list[ExactState] = []
    attempts, total, ratio = 0, 0, 0.0
    while done < 1.0:
        target = min(1.0, done + step, done + cap)
        attempts += 1
        start = current.updated((target - done) * move) if driven else current
        trial, its, ok, ratio = _newton(beam, f, target, free, start, tolerance, max_iterations)
        total += its
        if ok:
            current, done = trial, target
            factors.append(target)
            iterations.append(its)
            path.append(current)
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
    return ExactStaticResult(current, factors, iterations, attempts, total, ratio, path)


def _newton(
    beam: StaticOperator,
    f: Load,
    factor: float,
    free: np.ndarray,
    state: ExactState,
    tolerance: float,
    max_iterations: int,
) -> tuple[ExactState, int, bool, float]:
    """Newton at one load factor: the state, the iterations, whether it converged and the
    residual over its floor."""
    ratio = np.inf
    first = np.inf
    for it in range(max_iterations + 1):
        load = factor * f.vector(state)
        pts, g, ratio, size, converged = _unbalance(beam, state, load, free, tolerance)
        if converged:
            return state, it, True, ratio
        if it == 0:
            first = size
        stalled = it >= STALL and size > first
        if it == max_iterations or stalled or not np.isfinite(size):
            break
        try:
            dq_free = _solve(_tangent(beam, f, factor, state, pts, free), g)
        except (RuntimeError, np.linalg.LinAlgError):  # singular: let the load step shrink
            break
        dq = np.zeros(beam.n_dofs)
        dq[free] = dq_free
        turn = float(np.abs(dq[: 6 * len(state.x)].reshape(-1, 6)[:, 3:]).max(initial=0.0))
        if turn > MAX_TURN:
            dq *= MAX_TURN / turn
        state = _balance_forces(beam, f, factor, free, state.updated(dq))
    return state, it, False, ratio


def _solve(K: sp.csc_matrix, rhs: np.ndarray) -> np.ndarray:
    """``K^-1 rhs`` (one or more columns): by LAPACK's dense LU up to :data:`DENSE` unknowns,
    else by SuperLU; ``RuntimeError`` (SuperLU) or ``LinAlgError`` (LAPACK) when ``K`` is
    exactly singular."""
    if K.shape[0] <= DENSE:
        return np.linalg.solve(K.toarray(), rhs)
    return spla.splu(K).solve(rhs)


def _unbalance(
    beam: StaticOperator, state: ExactState, load: np.ndarray, free: np.ndarray, tolerance: float
) -> tuple[Any, np.ndarray, float, float, bool]:
    """The state's points, its free residual ``g = load - r`` and its largest ratio to its
    round-off floor, its largest entry, and whether it is converged: on the floor or below
    ``tolerance`` times the load (module docstring)."""
    target = load[free]
    pts = beam.points(state)
    g = target - beam.residual(state, pts)[free]
    terms = beam.residual_floor(state, pts)[free] + np.abs(target)
    floor = FLOOR_FACTOR * np.finfo(float).eps * terms
    ratio = float(np.max(np.abs(g) / np.maximum(floor, np.finfo(float).tiny)))
    size = float(np.abs(g).max(initial=0.0))
    scale = tolerance * max(float(np.abs(target).max(initial=0.0)), np.finfo(float).tiny)
    return pts, g, ratio, size, bool(ratio <= 1.0 or size <= scale)


def _arc_length(
    beam: StaticOperator,
    f: Load,
    free: np.ndarray,
    state: ExactState,
    tolerance: float,
    max_iterations: int,
    first_step: float,
    min_step: float,
    max_steps: int,
) -> ExactStaticResult:
    """The equilibrium path from ``state`` (at load factor 0) by Crisfield's cylindrical arc
    length, to the load factor 1 (module docstring)."""
    moved = _node_positions(free, state)  # whose increments the arc length measures
    if moved.size == 0:
        raise ValueError("method 'arc-length' needs free positions: every position is fixed")
    linear = np.zeros(beam.n_dofs)
    linear[free] = _solve(beam.tangent(state, None, free), f.vector(state)[free])
    longest = float(np.linalg.norm(linear[moved]))
    first = min(first_step, 1.0) * longest
    arc, factor = first, 0.0
    previous: np.ndarray | None = None
    factors: list[float] = []
    iterations: list[int] = []
    path: list[ExactState] = []
    attempts, total, ratio = 0, 0, 0.0
    for _ in range(max_steps):
        attempts += 1
        trial, reached, its, ok, ratio = _arc_step(
            beam, f, free, moved, state, factor, arc, previous, tolerance, max_iterations
        )
        total += its
        if ok and reached >= 1.0 > factor:  # past the full load: land on it by Newton
            trial, landing, ok, ratio = _newton(
                beam, f, 1.0, free, trial, tolerance, max_iterations
            )
            total += landing
            its, reached = its + landing, 1.0
        step = (trial.x - state.x).ravel()[_positions(moved)]
        if ok and previous is not None and float(step @ previous) <= 0.0:
            ok = False  # turned back along the path (or jumped to another branch)
        if ok and _largest_turn(state, trial) > MAX_TURN:
            ok = False  # beyond the linearisation's reach: a shorter arc follows the path
        if not ok:
            arc /= 2.0
            if arc < min_step * first:
                raise NotConverged(
                    f"{beam.name}: the arc length did not converge beyond load "
                    f"factor {factor:.6g} (an arc of {arc:.3g} failed; residual {ratio:.3g} "
                    "times its round-off floor)"
                )
            continue
        state, factor, previous = trial, reached, step
        factors.append(factor)
        iterations.append(its)
        path.append(state)
        if factor == 1.0:
            return ExactStaticResult(state, factors, iterations, attempts, total, ratio, path)
        if its <= FAST:
            arc = min(2.0 * arc, longest)
    raise NotConverged(
        f"{beam.name}: the arc length did not reach the full load in {max_steps} "
        f"steps (load factors {min(factors, default=0.0):.6g} to "
        f"{max(factors, default=0.0):.6g})"
    )


def _largest_turn(start: ExactState, end: ExactState) -> float:
    """The largest component of the nodes' turns from ``start`` to ``end`` (radians)."""
    turns = rotations.log_map(end.R @ np.swapaxes(start.R, -1, -2))
    return float(np.abs(turns).max(initial=0.0))


def _node_positions(dofs: np.ndarray, state: ExactState) -> np.ndarray:
    """The ``dofs`` that are the nodes' positions (not rotations, nor multipliers after the
    nodes' ``6 n``)."""
    return dofs[(dofs < 6 * len(state.x)) & (dofs % 6 < 3)]


def _positions(dofs: np.ndarray) -> np.ndarray:
    """The entries of the flattened node positions (n, 3) that position dofs stand for."""
    return (dofs // 6) * 3 + dofs % 6


def _arc_step(
    beam: StaticOperator,
    f: Load,
    free: np.ndarray,
    moved: np.ndarray,
    start: ExactState,
    factor: float,
    arc: float,
    previous: np.ndarray | None,
    tolerance: float,
    max_iterations: int,
) -> tuple[ExactState, float, int, bool, float]:
    """One arc-length step from the equilibrium ``start`` at ``factor``: the state, its load
    factor, the iterations, whether it converged and the residual over its floor.

    Predictor along the tangent ``K dq_f = f`` with ``|dlambda| |dq_f| = arc`` (the sign
    keeping the direction of the ``previous`` step); each correction
    ``dq = dq_g + dlambda dq_f`` (``K dq_g = g``) with the ``dlambda`` that keeps the
    position increment from ``start`` on the cylinder ``|Delta u| = arc``, the root whose
    increment turns least from the last (Crisfield 1981); then the positions' force
    correction at the new load factor."""
    index = _positions(moved)
    slot = np.searchsorted(free, moved)  # the free positions among the free dofs

    def moved_by(state: ExactState) -> np.ndarray:
        return (state.x - start.x).ravel()[index]

    state, lam, ratio = start, factor, np.inf
    for it in range(max_iterations + 1):
        load = f.vector(state)
        if it > 0:
            pts, g, ratio, size, converged = _unbalance(beam, state, lam * load, free, tolerance)
            if converged:
                return state, lam, it, True, ratio
            if not np.isfinite(size):
                break
        else:
            pts, g = beam.points(state), np.zeros(len(free))
        try:
            K = _tangent(beam, f, lam, state, pts, free)
            dq_g, dq_f = _solve(K, np.column_stack([g, load[free]])).T
        except (RuntimeError, np.linalg.LinAlgError):
            break
        delta = moved_by(state) + dq_g[slot]
        a = float(dq_f[slot] @ dq_f[slot])
        b = 2.0 * float(dq_f[slot] @ delta)
        c = float(delta @ delta) - arc * arc
        if it == 0:
            along = previous if previous is not None else dq_f[slot]
            dlam = float(np.copysign(arc / np.sqrt(a), along @ dq_f[slot]))
        else:
            discriminant = b * b - 4 * a * c
            if discriminant < 0 or a == 0:
                break
            roots = (-b + np.array([-1.0, 1.0]) * np.sqrt(discriminant)) / (2 * a)
            before = moved_by(state)
            turn = [float(before @ (delta + r * dq_f[slot])) for r in roots]
            dlam = float(roots[int(np.argmax(turn))])
        dq = np.zeros(beam.n_dofs)
        dq[free] = dq_g + dlam * dq_f
        lam += dlam
        state = _balance_forces(beam, f, lam, free, state.updated(dq))
    return state, lam, it, False, ratio


def _balance_forces(
    beam: StaticOperator, f: Load, factor: float, free: np.ndarray, state: ExactState
) -> ExactState:
    """The state with its free positions corrected so that the force balances hold
    exactly, its rotations kept (the position correction of the module docstring): at fixed
    rotations the force balances are affine in the positions and in the multipliers of
    the rows that hold positions (``position_multipliers``; those rows are linear in the
    positions), so one solve with their block of the tangent, ``K_uu du = lambda f_u -
    r_u``, satisfies them.  A singular block (positions held by rotations only) leaves the
    state as it is, and so does an operator whose ``balances_positions`` is False (one
    with rows that are not affine in its positions, as a slider's ``xi`` row)."""
    if not getattr(beam, "balances_positions", True):
        return state
    positions = np.union1d(
        _node_positions(free, state), np.intersect1d(free, beam.position_multipliers)
    )
    if positions.size == 0:
        return state
    pts = beam.points(state)
    g = factor * f.vector(state)[positions] - beam.residual(state, pts)[positions]
    try:
        du = _solve(beam.tangent(state, pts, positions), g)
    except (RuntimeError, np.linalg.LinAlgError):
        return state
    dq = np.zeros(beam.n_dofs)
    dq[positions] = du
    return state.updated(dq)
