"""Small helpers: input 3-vectors, inertias and frames, abscissae, section frames from a tangent
and a vector."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike


def _floats(value: object) -> np.ndarray:
    """``value`` as a float array; NaN when it is not numbers (a string, ragged lists)."""
    if isinstance(value, str):
        return np.full(1, np.nan)
    try:
        return np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        return np.full(1, np.nan)


def vector3(value: ArrayLike, name: str) -> np.ndarray:
    """``value`` as a finite 3-vector, or ``ValueError`` naming ``name``."""
    v = _floats(value)
    if v.shape != (3,) or not np.all(np.isfinite(v)):
        raise ValueError(f"{name} must be a finite 3-vector, got {value!r}")
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
    if np.linalg.eigvalsh(J).min() < -1e-12 * scale:
        raise ValueError(
            f"{name} must be positive semi-definite (eigenvalues {np.linalg.eigvalsh(J)})"
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
    with ``up = z`` has the global frame.  Where ``up`` is (nearly) tangent, the global axis
    least aligned with the tangent replaces it.

    Parameters
    ----------
    tangents : (..., 3) array, need not be unit vectors
    up : (3,) array, or (..., 3) broadcast with the tangents
    """
    t = tangents / np.linalg.norm(tangents, axis=-1, keepdims=True)
    up = np.broadcast_to(up, t.shape)
    e3 = up - np.sum(t * up, axis=-1, keepdims=True) * t
    weak = np.linalg.norm(e3, axis=-1) < 1e-6
    if np.any(weak):
        axis = np.eye(3)[np.argmin(np.abs(t[weak]), axis=-1)]
        e3[weak] = axis - np.sum(axis * t[weak], axis=-1, keepdims=True) * t[weak]
    e3 /= np.linalg.norm(e3, axis=-1, keepdims=True)
    e2 = cross(e3, t)
    return np.stack([t, e2, e3], axis=-1)
