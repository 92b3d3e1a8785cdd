"""Rigid lines and line frames at one abscissa, compiled (numba).

The compiled twins of :mod:`sliders.lines.rigid`, for the compiled Newton step
(:mod:`sliders.joints.packed`): a rigid line's point and derivatives at ``xi``
(:func:`line_at`) and the frame ``R = [t, e2, e3]`` with its curvature ``k = ax(R_/xi R^T)``
and ``k_/xi`` (:func:`frame_at`, :func:`curvature_rate_at`).  Every rigid line is one of two
shapes, given by a parameter row (:meth:`sliders.lines.rigid.RigidLine.compiled`):

``POLYNOMIAL``
    piecewise cubic in ``xi``: ``x = sum_j c_j (xi - s_p)^(3 - j)`` on piece ``p``
    (a straight line is one piece, a cubic spline one per chord);
``HELICAL``
    ``x = c + [r cos a, r sin a, rise (a - a0)]`` with ``a = a0 + w xi`` (a circular arc has
    ``rise = 0``, a helix ``a0 = 0``).

The references are the numpy functions of :mod:`sliders.lines.rigid` (``derivatives``,
:func:`~sliders.lines.rigid.frame_and_curvature`, :func:`~sliders.lines.rigid.curvature_rate`);
``tests/test_rigid_kernel.py`` holds the two equal to roundoff.
"""

from __future__ import annotations

import numba
import numpy as np

from fvbeam.kernel_cache import guard

guard(__file__)  # numba's cache of these kernels, consistent with their sources

POLYNOMIAL, HELICAL = 0, 1


@numba.njit(cache=True, inline="never")
def line_at(shape: int, params: np.ndarray, breaks: np.ndarray, xi: float, out: np.ndarray) -> None:
    """``x, x', x'', x'''`` (4, 3) of a rigid line at ``xi`` into ``out``.

    ``POLYNOMIAL``: ``breaks`` (P + 1,) the pieces' starts and the end, ``params`` (P, 4, 3)
    raveled, the coefficients of ``(xi - s_p)^3, ^2, ^1, ^0`` (scipy's ``PPoly.c`` order).
    ``HELICAL``: ``params`` = ``[c_x, c_y, c_z, r, rise, a0, w]``."""
    if shape == POLYNOMIAL:
        n = len(breaks) - 1
        p = 0
        while p < n - 1 and breaks[p + 1] <= xi:
            p += 1
        d = xi - breaks[p]
        base = 12 * p
        for c in range(3):
            c3, c2 = params[base + c], params[base + 3 + c]
            c1, c0 = params[base + 6 + c], params[base + 9 + c]
            out[0, c] = ((c3 * d + c2) * d + c1) * d + c0
            out[1, c] = (3 * c3 * d + 2 * c2) * d + c1
            out[2, c] = 6 * c3 * d + 2 * c2
            out[3, c] = 6 * c3
        return
    r, rise, a0, w = params[3], params[4], params[5], params[6]
    a = a0 + w * xi
    co, si = np.cos(a), np.sin(a)
    out[0, 0], out[0, 1], out[0, 2] = (
        params[0] + r * co,
        params[1] + r * si,
        params[2] + rise * (a - a0),
    )
    out[1, 0], out[1, 1], out[1, 2] = -w * r * si, w * r * co, w * rise
    out[2, 0], out[2, 1], out[2, 2] = -w * w * r * co, -w * w * r * si, 0.0
    out[3, 0], out[3, 1], out[3, 2] = w**3 * r * si, -(w**3) * r * co, 0.0


@numba.njit(cache=True, inline="never")
def _cross(a: np.ndarray, b: np.ndarray, out: np.ndarray) -> None:
    out[0] = a[1] * b[2] - a[2] * b[1]
    out[1] = a[2] * b[0] - a[0] * b[2]
    out[2] = a[0] * b[1] - a[1] * b[0]


@numba.njit(cache=True, inline="never")
def frame_at(l: np.ndarray, l_xi: np.ndarray, up: np.ndarray, R: np.ndarray, k: np.ndarray) -> None:
    """The frame ``R = [t, e2, e3]`` (columns) from the direction ``l`` and ``up``, and its
    curvature ``k = ax(R_/xi R^T)`` from ``l_/xi`` (:func:`sliders.lines.rigid.
    frame_and_curvature`): ``t = l/|l|``, ``e3 = n/|n|`` with ``n = up - (up . t) t``,
    ``e2 = e3 x t``, differentiated by the chain rule."""
    norm_l = np.sqrt(l[0] ** 2 + l[1] ** 2 + l[2] ** 2)
    t, t_xi = l / norm_l, np.empty(3)
    dot = t[0] * l_xi[0] + t[1] * l_xi[1] + t[2] * l_xi[2]
    for c in range(3):
        t_xi[c] = (l_xi[c] - dot * t[c]) / norm_l
    up_t = up[0] * t[0] + up[1] * t[1] + up[2] * t[2]
    up_txi = up[0] * t_xi[0] + up[1] * t_xi[1] + up[2] * t_xi[2]
    n = up - up_t * t
    norm_n = np.sqrt(n[0] ** 2 + n[1] ** 2 + n[2] ** 2)
    e3 = n / norm_n
    n_xi = -up_txi * t - up_t * t_xi
    e3_n = e3[0] * n_xi[0] + e3[1] * n_xi[1] + e3[2] * n_xi[2]
    e3_xi = (n_xi - e3_n * e3) / norm_n
    e2, e2_xi, scratch = np.empty(3), np.empty(3), np.empty(3)
    _cross(e3, t, e2)
    _cross(e3_xi, t, e2_xi)
    _cross(e3, t_xi, scratch)
    e2_xi += scratch
    R_xi = np.empty((3, 3))
    for c in range(3):
        R[c, 0], R[c, 1], R[c, 2] = t[c], e2[c], e3[c]
        R_xi[c, 0], R_xi[c, 1], R_xi[c, 2] = t_xi[c], e2_xi[c], e3_xi[c]
    W = R_xi @ R.T
    k[0] = 0.5 * (W[2, 1] - W[1, 2])
    k[1] = 0.5 * (W[0, 2] - W[2, 0])
    k[2] = 0.5 * (W[1, 0] - W[0, 1])


@numba.njit(cache=True, inline="never")
def curvature_rate_at(
    l: np.ndarray, l_xi: np.ndarray, l_xixi: np.ndarray, up: np.ndarray, k_xi: np.ndarray
) -> None:
    """``k_/xi`` (:func:`sliders.lines.rigid.curvature_rate`): the central difference of
    :func:`frame_at` over ``xi +- d``, ``d = 1e-4 / |l_/xi|``, the direction carried by its
    Taylor expansion; zero on a straight part (``|l_/xi| <= 1e-12 |l|``)."""
    scale = np.sqrt(l_xi[0] ** 2 + l_xi[1] ** 2 + l_xi[2] ** 2)
    if not scale > 1e-12 * np.sqrt(l[0] ** 2 + l[1] ** 2 + l[2] ** 2):
        k_xi[:] = 0.0
        return
    d = 1e-4 / scale
    R, ahead, behind = np.empty((3, 3)), np.empty(3), np.empty(3)
    frame_at(l + d * l_xi + 0.5 * d * d * l_xixi, l_xi + d * l_xixi, up, R, ahead)
    frame_at(l - d * l_xi + 0.5 * d * d * l_xixi, l_xi - d * l_xixi, up, R, behind)
    for c in range(3):
        k_xi[c] = (ahead[c] - behind[c]) / (2 * d)
