"""Small vector helpers: input 3-vectors, section frames from a tangent and a reference vector."""

from __future__ import annotations

import numpy as np


def vector3(value, name: str) -> np.ndarray:
    """``value`` as a finite 3-vector, or ``ValueError`` naming ``name``."""
    v = np.asarray(value, dtype=float)
    if v.shape != (3,) or not np.all(np.isfinite(v)):
        raise ValueError(f"{name} must be a finite 3-vector, got {value!r}")
    return v


def section_frames(tangents: np.ndarray, up: np.ndarray) -> np.ndarray:
    """Orthonormal section frames ``R = [t, e2, e3]`` (as columns) from tangent vectors.

    ``e3`` is ``up`` with its tangential part removed and ``e2 = e3 x t``, so a beam along x
    with ``up = z`` has the global frame.  Where ``up`` is (nearly) tangent, the global axis
    least aligned with the tangent replaces it.

    Parameters
    ----------
    tangents : (..., 3) array, need not be unit vectors
    up : (3,) array
    """
    t = tangents / np.linalg.norm(tangents, axis=-1, keepdims=True)
    e3 = up - (t @ up)[..., None] * t
    weak = np.linalg.norm(e3, axis=-1) < 1e-6
    if np.any(weak):
        axis = np.eye(3)[np.argmin(np.abs(t[weak]), axis=-1)]
        e3[weak] = axis - np.sum(axis * t[weak], axis=-1, keepdims=True) * t[weak]
    e3 /= np.linalg.norm(e3, axis=-1, keepdims=True)
    e2 = np.cross(e3, t)
    return np.stack([t, e2, e3], axis=-1)
