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

import numba
import numpy as np

from fvbeam.kernel_cache import guard
from sliders.solve.factor import factor_solve
from sliders.solve.newton_kernel import CONVERGED, NewtonProblem, newton

guard(__file__)  # numba's cache of these kernels, consistent with their sources


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
    scheme: tuple,
    mass: tuple,
    damping: tuple,
    problem: NewtonProblem,
    nonlinear: bool,
    times: np.ndarray,
    loads: np.ndarray,
    driven: np.ndarray,
    driven_values: np.ndarray,
    drives: np.ndarray,
    unknown_first: np.ndarray,
    q: np.ndarray,
    v: np.ndarray,
    a: np.ndarray,
    qdd: np.ndarray,
    y: np.ndarray,
    tol: float,
    max_iterations: int,
    Q: np.ndarray,
    V: np.ndarray,
    A: np.ndarray,
    QDD: np.ndarray,
    Y: np.ndarray,
    iterations: np.ndarray,
    violations: np.ndarray,
) -> tuple[int, int, int]:
    """``len(times)`` steps from the state ``q, v, a, qdd`` and the joints' physical unknowns
    ``y`` (module docstring).

    Parameters
    ----------
    scheme
        ``alpha_m, alpha_f, beta, gamma, h, beta_rate, gamma_rate``.
    mass, damping
        ``M`` and ``C`` in compressed rows (``ptr, col, val``).
    problem
        The Newton problem on ``K'`` (:attr:`sliders.solve.newton.CompiledNewton.problem`);
        without joints and force elements (not ``nonlinear``) its first six entries are
        read: ``K'`` and the free dofs and the factors of ``K'`` on them.
    times, loads
        The time at the end of each step, and the external load there (one row per step,
        or one row for all).
    driven, driven_values, drives
        The driven dofs and their values per step; each joint's driven abscissa per step.
    unknown_first
        The first unknown (``xi``) of each joint in ``y``: the others are multipliers.
    tol, max_iterations
        Newton's rule.
    Q, V, A, QDD, Y, iterations, violations
        Per step, the state reached, the Newton iterations and each joint's largest
        constraint violation (:func:`sliders.solve.newton_kernel.newton`).

    Returns
    -------
    The status of the last step taken (``CONVERGED`` when all were), the number of steps
    completed, and the failing joint (or -1).
    """
    alpha_m, alpha_f, beta, gamma, h, beta_rate, gamma_rate = scheme
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
            L_ptr, L_row, L_val, U_ptr, U_row, U_val, perm_r, perm_c = factor
            nf = len(free)
            work[:] = 0.0
            _product(K_ptr, K_col, K_val, start, work)
            rhs, x, scratch = np.empty(nf), np.empty(nf), np.empty(nf)
            for i in range(nf):
                rhs[i] = f[free[i]] - work[free[i]]
            factor_solve(L_ptr, L_row, L_val, U_ptr, U_row, U_val, perm_r, perm_c, rhs, x, scratch)
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
