"""Small helpers: input numbers, vectors, inertias and frames, abscissae, section frames from a
tangent and a vector ``up`` (and the check that ``up`` crosses the tangent)."""

from __future__ import annotations

import math
from numbers import Real
from typing import Literal, cast

import numpy as np
from numpy.typing import ArrayLike

#: Smallest sine of the angle between a section frame's ``up`` and the tangent it is made
#: orthogonal to (:func:`section_frames`).  ``e3`` is ``up``'s part across the tangent,
#: ``sin(angle) |up|`` long, so its direction is known to ``eps / sin(angle)``: at ``1e-6`` to
#: about ``2e-10`` rad.  Below, ``up`` points along the centreline and fixes no frame.
UP_ANGLE = 1e-6


def _floats(value: object) -> np.ndarray:
    """``value`` as a float array; NaN when it is not numbers (a string, ragged lists)."""
    if isinstance(value, str):
        return np.full(1, np.nan)
    try:
        return np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        return np.full(1, np.nan)


def number(
    value: object, name: str, bound: Literal["", "> 0", ">= 0"] = "", what: str = ""
) -> float:
    """``value`` as a finite float, also ``> 0`` or ``>= 0`` when ``bound`` says so, or
    ``ValueError`` naming ``name`` and what it must be (``what``, by default "finite and
    BOUND" or "a finite number"); a string or a bool is not a number."""
    real = isinstance(value, Real) and not isinstance(value, bool)
    x = float(cast(Real, value)) if real else math.nan
    if not (math.isfinite(x) and (x > 0 if bound == "> 0" else x >= 0 if bound else True)):
        what = what or (f"finite and {bound}" if bound else "a finite number")
        raise ValueError(f"{name} must be {what}, got {value if real else repr(value)}")
    return x


def vector3(value: ArrayLike, name: str) -> np.ndarray:
    """``value`` as a finite 3-vector, or ``ValueError`` naming ``name``."""
    v = _floats(value)
    # three scalar tests cost a fifth of np.isfinite(v).all() (a sweep moves beams by it)
    if v.shape != (3,) or not (math.isfinite(v[0]) and math.isfinite(v[1]) and math.isfinite(v[2])):
        raise ValueError(f"{name} must be a finite 3-vector, got {value!r}")
    return v


def sized(value: ArrayLike, size: int, name: str, what: str) -> np.ndarray:
    """``value`` as a float vector of ``size`` entries (``what`` they are, for the message),
    or ``ValueError`` naming ``name`` and the shape found."""
    v = _floats(value)
    if v.shape != (size,):
        found = "not numbers" if v.shape == (1,) and np.isnan(v[0]) else f"shape {v.shape}"
        raise ValueError(f"{name} must hold {size} values ({what}), got {found}")
    return v


def wrench(force: ArrayLike, moment: ArrayLike) -> np.ndarray:
    """``[force; moment]`` as a 6-vector from two finite 3-vectors (``ValueError`` naming the
    bad one)."""
    return np.concatenate([vector3(force, "force"), vector3(moment, "moment")])


def inertia3(value: ArrayLike, name: str) -> np.ndarray:
    """``value`` as a finite, symmetric, positive semi-definite 3x3 matrix, or ``ValueError``
    naming ``name``.  Three numbers are the principal values: the diagonal matrix (as in a
    scene).

    Symmetry is checked to 1e-12 of the largest entry and the smallest eigenvalue may be
    negative by 1e-12 of the largest entry: an inertia computed in floating point is symmetric
    and semi-definite to a few ulps of its entries, and any genuine defect is far larger.
    """
    J = np.array(_floats(value))
    if J.shape == (3,):
        J = np.diag(J)
    if J.shape != (3, 3) or not np.all(np.isfinite(J)):
        raise ValueError(f"{name} must be a finite 3x3 matrix or 3 numbers, got {value!r}")
    scale = np.abs(J).max()
    if np.abs(J - J.T).max() > 1e-12 * scale:
        raise ValueError(f"{name} must be symmetric, got {value!r}")
    # the eigenvalues of J / scale: no overflow for entries near the largest float
    eigenvalues = np.linalg.eigvalsh(J / scale) if scale > 0 else np.zeros(3)
    if eigenvalues.min() < -1e-12:
        raise ValueError(
            f"{name} must be positive semi-definite (eigenvalues {scale * eigenvalues})"
        )
    return J


def orthonormal3(value: ArrayLike, name: str) -> np.ndarray:
    """``value`` as an orthonormal 3x3 matrix (``R^T R = I`` to 1e-12), or ``ValueError``
    naming ``name``."""
    R = np.array(value, dtype=float)
    if R.shape != (3, 3) or not np.all(np.isfinite(R)) or np.abs(R.T @ R - np.eye(3)).max() > 1e-12:
        raise ValueError(f"{name} must be an orthonormal 3x3 matrix, got {value!r}")
    return R


def cross(a: np.ndarray, b: np.ndarray, axis: int = -1) -> np.ndarray:
    """``a x b`` along the component ``axis`` (the last, or a leading one counted from 0),
    broadcast: ``np.cross`` without moving axes, several times faster on the small arrays of
    the joint equations and faster on the large ones of the stiffness form."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    out = np.empty(np.broadcast_shapes(a.shape, b.shape))
    x, y, z = ((..., i) if axis == -1 else (slice(None),) * axis + (i,) for i in range(3))
    out[x] = a[y] * b[z] - a[z] * b[y]
    out[y] = a[z] * b[x] - a[x] * b[z]
    out[z] = a[x] * b[y] - a[y] * b[x]
    return out


def skew_matrices(v: np.ndarray) -> np.ndarray:
    """Matrices of ``v x`` for vectors ``v`` of shape (..., 3): shape (..., 3, 3)."""
    out = np.zeros(v.shape + (3,))
    out[..., 0, 1], out[..., 0, 2] = -v[..., 2], v[..., 1]
    out[..., 1, 0], out[..., 1, 2] = v[..., 2], -v[..., 0]
    out[..., 2, 0], out[..., 2, 1] = -v[..., 1], v[..., 0]
    return out


def locate_abscissa(
    xi: np.ndarray | float, breaks: np.ndarray, name: str, what: str
) -> tuple[np.ndarray, np.ndarray]:
    """Interval of ``breaks`` (increasing, from 0) holding each abscissa, and the offset in it.

    An abscissa within ``1e-12`` of the total length outside ``[0, breaks[-1]]`` is taken
    as the nearest end; any other, or a non-finite one, raises ``ValueError`` naming the
    object ``name`` and what it is (``what``, e.g. "the beam").
    """
    xi = np.asarray(xi, dtype=float)
    length = breaks[-1]
    tol = 1e-12 * length
    bad = ~np.isfinite(xi) | (xi < -tol) | (xi > length + tol)
    if np.any(bad):
        value = xi[bad].flat[0] if xi.ndim else float(xi)
        raise ValueError(f"{name}: xi = {value} lies outside {what} [0, {length}]")
    k = np.clip(np.searchsorted(breaks, xi, side="right") - 1, 0, len(breaks) - 2)
    return k, np.clip(xi - breaks[k], 0.0, breaks[k + 1] - breaks[k])


def section_frames(tangents: np.ndarray, up: np.ndarray) -> np.ndarray:
    """Orthonormal section frames ``R = [t, e2, e3]`` (as columns) from tangent vectors.

    ``e3`` is ``up`` with its tangential part removed and ``e2 = e3 x t``, so a beam along x
    with ``up = z`` has the global frame.  ``up`` must cross every tangent: the objects that
    hold an ``up`` check it once, with :func:`check_up`, where they are built.

    Parameters
    ----------
    tangents : (..., 3) array, need not be unit vectors
    up : (3,) array, or (..., 3) broadcast with the tangents
    """
    t = tangents / np.linalg.norm(tangents, axis=-1, keepdims=True)
    up = np.broadcast_to(up, t.shape)
    e3 = up - np.sum(t * up, axis=-1, keepdims=True) * t
    e3 /= np.linalg.norm(e3, axis=-1, keepdims=True)
    e2 = cross(e3, t)
    return np.stack([t, e2, e3], axis=-1)


def norm(v: ArrayLike, axis: int = -1) -> np.ndarray:
    """The Euclidean lengths of the vectors ``v`` along ``axis``, without overflow or
    underflow on the way: each vector scaled by its largest entry before its squares are
    summed (as LAPACK's ``dnrm2``), so that a vector of finite entries gets its length
    whenever that length is a finite float (``np.linalg.norm`` squares first: ``[1e200, 0,
    0]`` has length ``inf`` there, and ``[1e-200, 0, 0]`` length 0)."""
    v = np.asarray(v, dtype=float)
    scale = np.max(np.abs(v), axis=axis, keepdims=True)
    safe = np.where(scale > 0, scale, 1.0)
    with np.errstate(over="ignore"):  # a length beyond the largest float is inf
        return np.squeeze(scale * np.linalg.norm(v / safe, axis=axis, keepdims=True), axis)


def direction(value: ArrayLike, name: str) -> np.ndarray:
    """``value`` as a unit vector: a finite non-zero 3-vector, scaled by its largest entry
    and then normalised (no overflow: ``[0, 0, 1e200]`` is ``[0, 0, 1]``), or ``ValueError``
    naming ``name``."""
    v = vector3(value, name)
    scale = float(np.abs(v).max())
    if not scale > 0:
        raise ValueError(f"{name} must be a non-zero 3-vector, got {value!r}")
    v = v / scale
    return v / float(np.linalg.norm(v))


def check_up(up: np.ndarray, tangents: np.ndarray, xi: np.ndarray, name: str) -> None:
    """``ValueError`` unless the unit vector ``up`` crosses every one of ``tangents`` (n, 3),
    taken at the abscissae ``xi`` (n,) of the object ``name``, at an angle whose sine is at
    least :data:`UP_ANGLE`; the message names the tangent closest to ``up`` and an axis that
    would do.

    A caller checks the tangents where ``up`` comes closest: a centreline's at the ends of
    its pieces and where its part across ``up`` is shortest (:func:`closest_to_up`).
    """
    t = tangents / np.linalg.norm(tangents, axis=-1, keepdims=True)
    sine = np.linalg.norm(cross(t, up), axis=-1)
    k = int(np.argmin(sine))
    if sine[k] < UP_ANGLE:
        axis = np.eye(3)[np.argmin(np.abs(t[k]))]
        raise ValueError(
            f"{name}: up = {np.round(up, 9).tolist()} is along the tangent "
            f"{np.round(t[k], 9).tolist()} at xi = {xi[k]:.6g}; the frame's axis e3 is up "
            f"made orthogonal to the tangent, so up must cross it: give another, "
            f"e.g. {axis.tolist()}"
        )


def closest_to_up(coefficients: np.ndarray, breaks: np.ndarray, up: np.ndarray) -> np.ndarray:
    """Where ``up`` may come closest to a centreline whose tangent is a polynomial on each
    piece: the ``breaks`` and the points where the tangent's part across the unit vector
    ``up`` is stationary in length (shortest, zero where they are parallel, or longest).

    ``coefficients`` (k, m, 3) and ``breaks`` (m + 1,) are the tangent as a
    :class:`scipy.interpolate.PPoly` (highest power first, in the offset from each piece's
    start): a spline's derivative, or ``[slope, start]`` for elements whose tangent is linear
    in their reference coordinate, on ``breaks = 0, 1, ..., m``.  The square of the across
    part is a polynomial of twice the degree on each piece, whose stationary points are the
    real roots of its derivative.
    """
    across = coefficients - np.einsum("kmj,j->km", coefficients, up)[..., None] * up
    k = len(across)
    square = np.zeros((2 * k - 1, across.shape[1]))
    for i in range(k):
        for j in range(k):
            square[i + j] += np.sum(across[i] * across[j], axis=-1)
    if k == 2:  # a linear tangent: a quadratic square, stationary where 2 a s + b = 0
        a, b = square[0], square[1]
        with np.errstate(divide="ignore", invalid="ignore"):
            s = -b / (2 * a)
        inside = (a != 0) & (s >= 0) & (s <= np.diff(breaks))
        return np.concatenate([breaks, breaks[:-1][inside] + s[inside]])
    from scipy.interpolate import PPoly  # only a spline's frames need it

    stationary = PPoly(square, breaks).derivative().roots(discontinuity=False, extrapolate=False)
    return np.concatenate([breaks, stationary[np.isfinite(stationary)]])
