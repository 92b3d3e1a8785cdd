"""Central finite differences of a force law with a bound on their error.

A law's exact partial derivative is checked against :func:`central_difference`: the derivative
estimated by :func:`scipy.differentiate.derivative` (central differences of order 8 on steps
halved from ``step`` until two successive estimates agree to ``sqrt(eps)`` relative), with the
tolerance

.. math::

    \\tau = 2\\,e_{k} + 64\\,\\epsilon\\,\\frac{\\max|f|}{h_{min}}

where ``e_k`` is scipy's error estimate (the difference of the last two estimates) and
``h_min`` the smallest offset of the last stencil (``x +- h, h/2, h/4, h/8``).  For a function
smooth over the stencil the last estimate's truncation error is ``2^-8`` times the previous
one's, so ``|D_k - f'|`` is about ``e_k / 255``: ``2 e_k`` holds it also before that
asymptotic regime is reached.  The second term bounds the roundoff: the stencil's weights sum
to ``1.69 / h_min`` in magnitude (below 2), and a law's value, tens of floating-point
operations, carries up to 32 ulps of ``|f|`` (its largest at ``x - h, x, x + h``) -- or of
a larger ``scale`` the caller gives, where the law subtracts operands larger than its value
(a slip ratio near zero carries ulps of the speeds it is the difference of).

scipy halves the step up to nine times, so a kink farther from ``x`` than about ``step / 512``
may be resolved (the stencil ends on one side of it).  An estimate that has not settled by then
(``e_k`` above ``1e-6`` of the derivative plus the roundoff term; scipy stops below
``1.5e-8`` when the law is smooth) means a jump, or a kink closer than that: the law is not
differentiable there, and :func:`central_difference` says so rather than return a tolerance
that would accept anything.  A point exactly on a kink is not detected (the symmetric stencil
gives the mean of the one-sided derivatives and settles): check laws away from their kinks.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import ArrayLike
from scipy.differentiate import derivative

#: The order of the central-difference formulas and the stencil's points per side.
ORDER = 8
#: Relative size of an unsettled estimate's error (see the module docstring).
UNSETTLED = 1e-6
EPS = float(np.finfo(float).eps)


def central_difference(
    function: Callable[..., np.ndarray],
    x: ArrayLike,
    step: ArrayLike,
    args: tuple[ArrayLike, ...] = (),
    scale: ArrayLike = 0.0,
) -> tuple[np.ndarray, np.ndarray]:
    """The derivative of an elementwise scalar ``function`` at ``x`` by central differences,
    and the tolerance an exact derivative must meet against it (module docstring).

    Parameters
    ----------
    function : callable
        ``f(x, *args) -> ndarray``, elementwise over ``x`` and ``args`` broadcast together
        (scipy adds a trailing axis of stencil points to ``x`` and one of length 1 to each
        of ``args``).
    x : array_like
        Where to differentiate.
    step : array_like
        The largest offset of the stencil, broadcast with ``x``: small against the scale on
        which ``f`` changes, clear of any kink.
    args : tuple of array_like
        Further arguments of ``function``, held fixed, broadcast with ``x``.
    scale : array_like
        A magnitude whose ulps bound the function's rounding where that exceeds 32 ulps of
        its value (module docstring); the larger of the two is used.

    Returns
    -------
    estimate, tolerance : ndarray
        Of the broadcast shape of ``x`` and ``args``.

    Raises
    ------
    ValueError
        Where the estimate did not settle or met a non-finite value.
    """
    fixed = tuple(np.asarray(a, dtype=float) for a in args)
    shape = np.broadcast_shapes(np.shape(x), *(a.shape for a in fixed))
    x = np.broadcast_to(np.asarray(x, dtype=float), shape)
    h = np.broadcast_to(np.asarray(step, dtype=float), shape)
    fixed = tuple(np.broadcast_to(a, shape) for a in fixed)

    def f(xi: np.ndarray, *others: np.ndarray) -> np.ndarray:
        # scipy wants the shape of xi back, also from a function constant in xi
        return np.broadcast_to(np.asarray(function(xi, *others), dtype=float), xi.shape)

    result = derivative(f, x, args=fixed, initial_step=h, order=ORDER)
    value = np.max([np.abs(f(x + sign * h, *fixed)) for sign in (-1.0, 0.0, 1.0)], axis=0)
    h_min = h / 2.0 ** (result.nit - 1) / 2.0 ** (ORDER // 2 - 1)
    roundoff = 64.0 * EPS * np.maximum(value, scale) / h_min
    unsettled = ~np.isfinite(result.df) | (result.error > UNSETTLED * np.abs(result.df) + roundoff)
    if np.any(unsettled):
        j = np.unravel_index(int(np.argmax(unsettled)), shape)
        raise ValueError(
            f"central differences did not settle at x = {x[j]} (error estimate "
            f"{result.error[j]:.3g} for a derivative {result.df[j]:.6g}): the function is "
            f"not smooth within the step {h[j]:.3g} there"
        )
    return np.asarray(result.df, dtype=float), 2.0 * result.error + roundoff
