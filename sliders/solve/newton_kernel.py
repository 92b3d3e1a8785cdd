"""The condensed Newton loop of one problem, compiled (numba).

:func:`newton` is :func:`sliders.solve.statics.newton_many` for one member on the condensed
back end (:mod:`sliders.solve.condensed`), every iteration in compiled code: the residual
``r_q = A q - f`` of the operator ``A`` (the stiffness, or the time integrator's
``M + c_v C + s K``), the joints' residuals and Jacobians (:func:`sliders.joints.packed.
evaluate_joint`), the small system on the slots the joints touch
(:func:`sliders.solve.condensed_kernel.condensed_step_into`, its scratch allocated once
per solve) and the increments
``dq = -B^{-1}[r_q + P F u; 0] + Phi a`` with the bordered operator ``B`` factorised once
(:func:`sliders.solve.factor.factor_solve` for ``B^{-1}[r_q; 0]``).  The columns of
``B^{-1}`` at the dofs that carry joint forces are computed when first needed and kept
(:func:`_ensure_columns`); the forces ``P F u`` act on those dofs only, so their part of the
increment is a sum of those columns, without a second solve.

The convergence rule and the residual history are :func:`sliders.solve.statics.converged`'s
and ``newton_many``'s: a member converges when every increment is below ``tol`` of its
scale, and its residual is evaluated once more.  So is the iteration policy: after a
regular Newton step the residual is evaluated without the Jacobian, and below ``tol``
(scaled as the history's) the step only confirms convergence, so it is taken on the small
system of that Newton step, whose inverse is in the step's scratch (a chord step,
:func:`sliders.solve.condensed_kernel.chord_step_into`: one solve with ``B`` and a product
with that inverse, no Jacobian, no new columns); above ``tol`` the Jacobian is evaluated at
the state (with the residual again) and the step is Newton's.  Near the solution the chord
increment differs from Newton's by ``O(|dJ| |r|)``, far below ``tol``.
``tests/test_compiled_newton.py`` holds the loop equal to ``newton_many`` on the same
problems.

Status codes returned: :data:`CONVERGED`, :data:`SINGULAR` (a small system below the
condition threshold: the caller names the free motion), :data:`NOT_CONVERGED`,
:data:`OFF_LINE` (a joint's ``xi`` left its line; the caller names it) and
:data:`OVERFLOW` (more load slots than a joint was laid out for: a bug).
"""

from __future__ import annotations

from typing import NamedTuple

import numba
import numpy as np

from fvbeam.kernel_cache import guard
from fvbeam.scratch import borrowed, stack_empty
from sliders.forces.kernel import evaluate_element
from sliders.joints.packed import JointState, Pool, evaluate_joint
from sliders.solve.condensed_kernel import (
    Columns,
    Jacobians,
    chord_step_into,
    condensed_step_into,
    step_scratch,
)
from sliders.solve.factor import Factors, factor_solve

guard(__file__)  # numba's cache of these kernels, consistent with their sources

CONVERGED, SINGULAR, NOT_CONVERGED, OFF_LINE, OVERFLOW = range(5)


class NewtonProblem(NamedTuple):
    """What :func:`newton` reads of a problem and does not change between its solves
    (:attr:`sliders.solve.newton.CompiledNewton.problem`)."""

    #: The operator ``A`` (n, n) in compressed rows.
    K_ptr: np.ndarray
    K_col: np.ndarray
    K_val: np.ndarray
    #: The free dofs (nf,) and the position of every dof among them (-1: held).
    free: np.ndarray
    position: np.ndarray
    #: The arrays of :class:`sliders.solve.factor.Factor` of the bordered operator
    #: ``B = [A_ff, s Phi; s Phi^T, 0]``, and the rigid modes ``Phi`` (nf, k) the operator
    #: does not resist.
    factor: Factors
    phi: np.ndarray
    #: The cache of columns of ``B^{-1}`` (:func:`_ensure_columns`), kept between calls:
    #: the columns (as rows), each free dof's row (-1: not stored), the rows in use (1,).
    store: np.ndarray
    column: np.ndarray
    filled: np.ndarray
    #: The joints (:class:`sliders.joints.packed.JointPack`).
    joints: Pool
    #: The force elements (:mod:`sliders.forces.elements`): their kinds, slots (E, 6) and
    #: packed constants (element ``e``'s from ``element_offsets[e]`` to
    #: ``element_offsets[e + 1]``), evaluated by :func:`sliders.forces.kernel.evaluate_element`.
    element_kind: np.ndarray
    element_slots: np.ndarray
    element_values: np.ndarray
    element_offsets: np.ndarray
    #: The layout for the condensed step of the joints and then the elements (one batch
    #: each, :func:`sliders.solve.condensed_kernel.condensed_step`), and the slots (into
    #: their slots side by side) that carry forces.
    tables: np.ndarray
    c_of: np.ndarray
    batches: np.ndarray
    force_slots: np.ndarray
    nc: int
    #: The reciprocal condition number below which a small system is singular.
    threshold: float
    #: The displacement increment that counts as converged whatever ``tol``
    #: (:func:`sliders.solve.statics.converged`).
    resolution: float


class Evaluated(NamedTuple):
    """What :func:`_evaluate` writes: each slot's dof (t,), the joints' residuals on their
    slots and unknowns (t + m,), the Jacobian entries (width,), the residual ``R`` (n,), its
    free rows (1, nf) and the joints' equations (1, m), and each joint's largest constraint
    violation (J,)."""

    dofs: np.ndarray
    r_joint: np.ndarray
    values: np.ndarray
    R: np.ndarray
    r_free: np.ndarray
    r_y: np.ndarray
    violation: np.ndarray


#: How the message of a Newton loop that did not converge begins (unless a diagnosis names
#: a free motion first; :class:`sliders.solve.dynamics.NotConverged`).
NOT_CONVERGED_MESSAGE = "Newton did not converge"


@numba.njit(cache=True, inline="never")
def residual(
    K_ptr: np.ndarray,
    K_col: np.ndarray,
    K_val: np.ndarray,
    q: np.ndarray,
    f: np.ndarray,
    R: np.ndarray,
) -> None:
    """``R = A q - f`` for the operator ``A`` in compressed rows."""
    for i in range(len(f)):
        total = -f[i]
        for p in range(K_ptr[i], K_ptr[i + 1]):
            total += K_val[p] * q[K_col[p]]
        R[i] = total


@numba.njit(cache=True, inline="never")
def _ensure_columns(
    dofs: np.ndarray,
    store: np.ndarray,
    column: np.ndarray,
    count: np.ndarray,
    factor: Factors,
    unit: np.ndarray,
    scratch: np.ndarray,
) -> None:
    """The columns ``B^{-1}[e_d; 0]`` of the free dofs ``dofs`` (-1: held, skipped) stored
    as rows of ``store`` (``column``: the row of each free dof, -1 if not stored; ``count``:
    rows in use).  A column is solved once and kept; when the missing ones do not fit, the
    store is emptied first (it holds at least the columns of one iteration)."""
    missing = 0
    for d in dofs:
        if d >= 0 and column[d] < 0:
            missing += 1
    if missing == 0:
        return
    if count[0] + missing > len(store):
        column[:] = -1
        count[0] = 0
    for d in dofs:
        if d >= 0 and column[d] < 0:
            unit[:] = 0.0
            unit[d] = 1.0
            row = count[0]
            factor_solve(factor, unit, store[row], scratch)
            column[d] = row
            count[0] = row + 1


@numba.njit(cache=True, inline="never")
def _evaluate(
    problem: NewtonProblem,
    q: np.ndarray,
    f: np.ndarray,
    y: np.ndarray,
    drives: np.ndarray,
    scale: float,
    velocity: tuple,
    jacobian: bool,
    done: bool,
    out: Evaluated,
) -> tuple[int, int, float]:
    """The residual at ``q``, ``y`` (:func:`newton`'s arguments): ``R = A q - f`` with the
    joints' and force elements' forces added (``r_free`` its free rows, ``r_y`` the joints'
    equations), each slot's dof into ``dofs`` and, with ``jacobian``, the Jacobian entries
    into ``values``; when ``done``, each joint's largest constraint violation into
    ``violation``.  Returns the status (0, :data:`OFF_LINE` or :data:`OVERFLOW`), the joint
    that failed (or -1) and the largest entry of the residual."""
    v_hat, q_hat, c_v = velocity
    head, batches, element_kind = problem.joints.head, problem.batches, problem.element_kind
    element_slots, element_values = problem.element_slots, problem.element_values
    element_offsets = problem.element_offsets
    dofs, r_joint, values, R = out.dofs, out.r_joint, out.values, out.R
    r_free, r_y, violation = out.r_free, out.r_y, out.violation
    J, E = len(head), len(element_kind)
    friction = stack_empty(1, (1,), np.float64)  # a joint's friction force, not read here
    q_e, v_e = stack_empty(6, (6,), np.float64), stack_empty(6, (6,), np.float64)
    r_e, J_e = stack_empty(6, (6,), np.float64), stack_empty(36, (6, 6), np.float64)
    residual(problem.K_ptr, problem.K_col, problem.K_val, q, f, R)
    s0, v0, y0 = 0, 0, 0
    for j in range(J):
        t, mj, wj = batches[j, 1], batches[j, 2], batches[j, 3]
        status = evaluate_joint(
            j,
            problem.joints,
            JointState(q, borrowed(y, y0, (mj,)), velocity, drives[j], scale),
            jacobian,
            (
                borrowed(dofs, s0, (t,)),
                borrowed(r_joint, s0 + y0, (t + mj,)),
                borrowed(values, v0, (wj,)),
                friction,
            ),
        )
        if status:
            return (OFF_LINE if status == 1 else OVERFLOW), j, 0.0
        for s in range(t):
            R[dofs[s0 + s]] += r_joint[s0 + y0 + s]
        for c in range(mj):
            r_y[0, y0 + c] = r_joint[s0 + y0 + t + c]
        if done:
            worst = 0.0
            for c in range(1, mj):
                worst = max(worst, abs(r_y[0, y0 + c]))
            violation[j] = worst
        s0 += t
        v0 += wj
        y0 += mj
    for e in range(E):
        for c in range(6):
            dof = element_slots[e, c]
            dofs[s0 + c] = dof
            q_e[c] = q[dof]
            v_e[c] = v_hat[dof] + c_v * (q[dof] - q_hat[dof])
        evaluate_element(
            element_kind[e],
            element_values[element_offsets[e] : element_offsets[e + 1]],
            q_e,
            v_e,
            c_v,
            scale,
            r_e,
            J_e,
        )
        for c in range(6):
            R[dofs[s0 + c]] += r_e[c]
            for d in range(6):
                values[v0 + 6 * c + d] = J_e[c, d]
        s0 += 6
        v0 += 36
    measure = 0.0
    for i in range(len(problem.free)):
        r_free[0, i] = R[problem.free[i]]
        measure = max(measure, abs(r_free[0, i]))
    for c in range(r_y.shape[1]):
        measure = max(measure, abs(r_y[0, c]))
    return 0, -1, measure


@numba.njit(cache=True)
def newton(
    problem: NewtonProblem,
    f: np.ndarray,
    q: np.ndarray,
    y: np.ndarray,
    drives: np.ndarray,
    scale: float,
    tol: float,
    max_iterations: int,
    history: np.ndarray,
    velocity: tuple,
    violation: np.ndarray,
) -> tuple[int, int, int]:
    """Newton on one member from ``q``, ``y`` (updated in place) under the load ``f``.

    Parameters
    ----------
    problem
        What does not change between solves (:class:`NewtonProblem`).
    f, q, y
        The load (n,), the state (n,) and the joints' unknowns side by side.
    drives, scale
        Each joint's driven abscissa at this time; the scaling of the multipliers.
    tol, max_iterations
        :func:`sliders.solve.statics.converged`'s rule.
    history
        (max_iterations + 1,): the scaled residual of each evaluation.
    velocity
        ``(v_hat, q_hat, c_v)``: the velocities ``v = v_hat + c_v (q - q_hat)`` the force
        elements and the sliders' friction read (the integrator's prediction and ``gamma'``;
        zeros and 0 in statics).
    violation
        (J,): each joint's largest position and orientation constraint violation at the
        converged state (the residual rows after its ``xi`` equation), written on
        convergence (:meth:`sliders.solve.dynamics.Dynamics.joint_residuals`).

    Returns
    -------
    The status (module docstring), the number of residual evaluations written to
    ``history``, and the joint that failed (:data:`OFF_LINE`, :data:`OVERFLOW`) or -1.
    """
    free, position, factor, phi = problem.free, problem.position, problem.factor, problem.phi
    store, column, count = problem.store, problem.column, problem.filled
    tables, c_of, batches, nc = problem.tables, problem.c_of, problem.batches, problem.nc
    force_slots, threshold, resolution = problem.force_slots, problem.threshold, problem.resolution
    head, joint_values, element_kind = (
        problem.joints.head,
        problem.joints.values,
        problem.element_kind,
    )
    n, nf, k = len(q), len(free), phi.shape[1]
    J, E = len(head), len(element_kind)
    m = len(y)
    t_all = 0
    width = 0
    for j in range(J + E):
        t_all += batches[j, 1]
        width += batches[j, 3]
    dofs = np.zeros(t_all, np.int64)
    slots = np.zeros(t_all, np.int64)
    r_joint = np.zeros(t_all + m)
    values = np.zeros(width)
    R = np.zeros(n)
    r_free = np.zeros((1, nf))
    r_y = np.zeros((1, m))
    evaluated = Evaluated(dofs, r_joint, values, R, r_free, r_y, violation)
    rhs, solution, scratch = np.zeros(nf + k), np.zeros((1, nf + k)), np.zeros(nf + k)
    added = np.zeros(nf, np.bool_)
    first = np.zeros(J, np.int64)
    at = 0
    for j in range(J):
        first[j] = at
        at += batches[j, 2]
    lengths = joint_values[:, 1]
    # the condensed step's outputs and scratch, for every step of this solve
    step = step_scratch(nf, batches, nc, m, k)
    columns, jac = Columns(store, column, phi), Jacobians(slots, values, tables, c_of, batches, nc)
    force, z = np.empty((1, nf)), np.empty((1, nc + m + k))
    regular = np.empty(1, np.bool_)
    load_scale = 1e-300
    for i in range(n):
        load_scale = max(load_scale, abs(f[i]))
    reach = 0.0
    for i in range(n):
        reach = max(reach, abs(q[i]))
    done = False
    kept = False  # the last step was a regular Newton step: its small system is in scratch
    for iteration in range(max_iterations + 1):
        # after a Newton step the residual comes first: below tol the step only confirms
        # convergence and is taken on the kept system (a chord step), else the Jacobian is
        # evaluated at the state (the residual with it, again) and the step is Newton's
        jacobian = not (done or kept)
        while True:
            status, joint, measure = _evaluate(
                problem, q, f, y, drives, scale, velocity, jacobian, done, evaluated
            )
            if status:
                return status, iteration, joint
            if jacobian or done or measure / load_scale <= tol or iteration == max_iterations:
                break
            jacobian = True
        history[iteration] = measure / load_scale
        if done:
            return CONVERGED, iteration + 1, -1
        if iteration == max_iterations:
            break
        chord = not jacobian
        if not chord:  # the slots of this Jacobian (a chord step keeps the kept system's)
            for s in range(t_all):
                slots[s] = position[dofs[s]]
            _ensure_columns(slots[force_slots], store, column, count, factor, rhs, scratch)
        rhs[:nf] = r_free[0]
        rhs[nf:] = 0.0
        factor_solve(factor, rhs, solution[0], scratch)
        if chord:
            chord_step_into(phi, solution, r_free, r_y, jac, step, (force, z))
            kept = False  # a chord step follows a Newton step only
        else:
            condensed_step_into(
                columns, solution, r_free, r_y, jac, threshold, step, (force, z, regular)
            )
            kept = True  # regular, else the check below returns
        if not regular[0]:
            return SINGULAR, iteration + 1, -1
        # B^{-1}[r_q + P F u; 0] = B^{-1}[r_q; 0] + sum_d (P F u)_d B^{-1}[e_d; 0]: the joint
        # forces act on the force dofs only, whose columns are stored
        for s in force_slots:
            d = slots[s]
            if d >= 0 and not added[d]:
                added[d] = True
                extra = force[0, d] - r_free[0, d]
                if extra != 0.0:
                    stored = store[column[d]]
                    for i in range(nf + k):
                        solution[0, i] += extra * stored[i]
        for s in force_slots:
            if slots[s] >= 0:
                added[slots[s]] = False
        step_q = 0.0
        for i in range(nf):
            dq = -solution[0, i]
            for a in range(k):
                dq += phi[i, a] * z[0, nc + m + a]
            q[free[i]] += dq
            step_q = max(step_q, abs(dq))
        for i in range(n):
            reach = max(reach, abs(q[i]))
        reach = max(reach, step_q)
        force_scale = load_scale
        for j in range(J):
            for c in range(first[j] + 1, first[j] + batches[j, 2]):
                force_scale = max(force_scale, abs(y[c] + z[0, nc + c]))
        ok = step_q <= max(tol * reach, resolution)
        for j in range(J):
            ok = ok and abs(z[0, nc + first[j]]) <= tol * lengths[j]
        step_multipliers = 0.0
        for j in range(J):
            for c in range(first[j] + 1, first[j] + batches[j, 2]):
                step_multipliers = max(step_multipliers, abs(z[0, nc + c]))
        for c in range(m):
            y[c] += z[0, nc + c]
        done = ok and step_multipliers <= tol * force_scale
    return NOT_CONVERGED, max_iterations + 1, -1
