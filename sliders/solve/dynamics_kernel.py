"""Fixed steps of the generalized-alpha scheme, compiled (numba).

:func:`advance` takes ``steps`` steps of size ``h`` from a state, each exactly as
:meth:`sliders.solve.dynamics.Dynamics.step` takes it (:mod:`sliders.solve.integrator`):

1. the prediction ``q^ = q + h v + h^2 (1/2 - beta) a``, ``v^ = v + h (1 - gamma) a``,
   ``qdd^ = (alpha_m a - alpha_f qdd) / (1 - alpha_f)``;
2. the scaled step problem on the operator ``K' = M + (gamma'/beta') C + s K``, ``s = 1/beta'``,
   under ``s (f(t) + M (beta' q^ - qdd^) + C (gamma' q^ - v^))``, from ``q^ + beta h^2 a`` with
   the driven dofs at their values, the multipliers scaled by ``s``: the compiled Newton loop
   (:func:`sliders.solve.newton_kernel.newton`), or without joints one solve;
3. the completion ``v = v^ + gamma' dq``, ``a = dq / (beta h^2)``, ``qdd = qdd^ + beta' dq``
   with ``dq = q - q^``, the multipliers scaled back.

Every step's state is written to the output arrays, so that the caller records them, shows
progress and writes checkpoints between calls; a failing step stops the call with its status
and the index of the step (the caller repeats it in Python for its message).  The loads and
drives of the steps are tabulated by the caller.  ``tests/test_compiled_dynamics.py`` holds
the steps equal to :meth:`Dynamics.step`'s.
"""

from __future__ import annotations

from typing import NamedTuple

import numba
import numpy as np

from fvbeam.kernel_cache import guard
from sliders.solve.factor import factor_solve
from sliders.solve.newton_kernel import CONVERGED, NewtonProblem, newton

guard(__file__)  # numba's cache of these kernels, consistent with their sources


class Stepper(NamedTuple):
    """What does not change from step to step of :func:`advance`."""

    #: ``alpha_m, alpha_f, beta, gamma, h, beta_rate, gamma_rate``.
    scheme: tuple
    #: ``M`` and ``C`` in compressed rows (``ptr, col, val``).
    mass: tuple
    damping: tuple
    #: The Newton problem on ``K'`` (:attr:`sliders.solve.newton.CompiledNewton.problem`);
    #: without joints and force elements (not ``nonlinear``) its first six entries are read:
    #: ``K'`` and the free dofs and the factors of ``K'`` on them.
    problem: NewtonProblem
    nonlinear: bool
    #: The driven dofs; the first unknown (``xi``) of each joint in ``y`` (the others are
    #: multipliers).
    driven: np.ndarray
    unknown_first: np.ndarray
    #: Newton's rule.
    tol: float
    max_iterations: int


class Schedule(NamedTuple):
    """The steps' tabulated inputs, one row per step."""

    #: The time at the end of each step, and the external load there (one row per step, or
    #: one row for all).
    times: np.ndarray
    loads: np.ndarray
    #: The driven dofs' values, and each joint's driven abscissa.
    driven_values: np.ndarray
    drives: np.ndarray


class SchemeState(NamedTuple):
    """A state of the scheme: ``q, v, a, qdd`` (n,) and the joints' physical unknowns ``y``
    (m,); per step of a trajectory, rows of (steps, n) and (steps, m)."""

    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    qdd: np.ndarray
    y: np.ndarray


class Trajectory(NamedTuple):
    """Per step, the state reached, the Newton iterations and each joint's largest
    constraint violation (:func:`sliders.solve.newton_kernel.newton`)."""

    states: SchemeState
    iterations: np.ndarray
    violations: np.ndarray


@numba.njit(cache=True, inline="never")
def _product(
    ptr: np.ndarray, col: np.ndarray, val: np.ndarray, x: np.ndarray, out: np.ndarray
) -> None:
    """``out += A x`` for ``A`` in compressed rows."""
    for i in range(len(out)):
        total = 0.0
        for p in range(ptr[i], ptr[i + 1]):
            total += val[p] * x[col[p]]
        out[i] += total


@numba.njit(cache=True)
def advance(
    stepper: Stepper, schedule: Schedule, state: SchemeState, out: Trajectory
) -> tuple[int, int, int]:
    """``len(schedule.times)`` steps from ``state`` (updated in place; module docstring),
    each step's state and Newton record into ``out``.

    Returns
    -------
    The status of the last step taken (``CONVERGED`` when all were), the number of steps
    completed, and the failing joint (or -1).
    """
    alpha_m, alpha_f, beta, gamma, h, beta_rate, gamma_rate = stepper.scheme
    scheme, mass, damping, problem, nonlinear, driven, unknown_first, tol, max_iterations = stepper
    times, loads, driven_values, drives = schedule
    q, v, a, qdd, y = state
    (Q, V, A, QDD, Y), iterations, violations = out
    M_ptr, M_col, M_val = mass
    C_ptr, C_col, C_val = damping
    n, m = len(q), len(y)
    s = 1.0 / beta_rate
    q_hat, v_hat, qdd_hat = np.empty(n), np.empty(n), np.empty(n)
    work, f = np.empty(n), np.empty(n)
    start = np.empty(n)
    multiplier = np.ones(m, dtype=np.bool_)
    for j in range(len(unknown_first)):
        multiplier[unknown_first[j]] = False
    history = np.zeros(max_iterations + 1)
    ys = np.empty(m)
    for step in range(len(times)):
        for i in range(n):
            q_hat[i] = q[i] + h * v[i] + h * h * (0.5 - beta) * a[i]
            v_hat[i] = v[i] + h * (1 - gamma) * a[i]
            qdd_hat[i] = (alpha_m * a[i] - alpha_f * qdd[i]) / (1 - alpha_f)
        row = loads[step if len(loads) > 1 else 0]
        for i in range(n):
            f[i] = row[i]
            work[i] = beta_rate * q_hat[i] - qdd_hat[i]
        _product(M_ptr, M_col, M_val, work, f)
        for i in range(n):
            work[i] = gamma_rate * q_hat[i] - v_hat[i]
        _product(C_ptr, C_col, C_val, work, f)
        for i in range(n):
            f[i] *= s
            start[i] = q_hat[i] + beta * h * h * a[i]
        for d in range(len(driven)):
            start[driven[d]] = driven_values[step, d]
        for c in range(m):
            ys[c] = y[c] * s if multiplier[c] else y[c]
        if nonlinear:
            status, evaluations, joint = newton(
                problem,
                f,
                start,
                ys,
                drives[step],
                s,
                tol,
                max_iterations,
                history,
                (v_hat, q_hat, gamma_rate),
                violations[step],
            )
            if status != CONVERGED:
                return status, step, joint
            iterations[step] = evaluations - 1
        else:
            K_ptr, K_col, K_val = problem.K_ptr, problem.K_col, problem.K_val
            free, factor = problem.free, problem.factor
            nf = len(free)
            work[:] = 0.0
            _product(K_ptr, K_col, K_val, start, work)
            rhs, x, scratch = np.empty(nf), np.empty(nf), np.empty(nf)
            for i in range(nf):
                rhs[i] = f[free[i]] - work[free[i]]
            factor_solve(factor, rhs, x, scratch)
            for i in range(nf):
                start[free[i]] += x[i]
            iterations[step] = 1
        for i in range(n):
            dq = start[i] - q_hat[i]
            q[i] = start[i]
            v[i] = v_hat[i] + gamma_rate * dq
            a[i] = dq / (beta * h * h)
            qdd[i] = qdd_hat[i] + beta_rate * dq
        back = 1.0 / s
        for c in range(m):
            y[c] = ys[c] * back if multiplier[c] else ys[c]
        Q[step], V[step], A[step], QDD[step], Y[step] = q, v, a, qdd, y
    return CONVERGED, len(times), -1
