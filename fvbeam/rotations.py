"""Finite rotations: the rotation vector, its exponential map and tangent operators.

A rotation is a matrix ``R`` of SO(3); a rotation vector ``psi`` (angle ``|psi|`` about the
axis ``psi / |psi|``) stands for ``R = exp(skew(psi))`` (Rodrigues).  The exponential and its
inverse (the principal logarithm, ``|psi| <= pi``) are scipy's
(:class:`scipy.spatial.transform.Rotation`).  The tangent operators are written with

    a(t) = (1 - cos t) / t^2,    b(t) = (t - sin t) / t^3,    t = |psi|,

and their series below :data:`SERIES` (where the closed forms lose digits to cancellation):

* the left Jacobian ``J(psi) = I + a skew(psi) + b skew(psi)^2``: a variation ``d psi``
  turns ``exp(psi)`` by the *spatial* rotation ``J(psi) d psi``,
  ``d exp(psi) = skew(J(psi) d psi) exp(psi)``; the right Jacobian is ``J(psi)^T = J(-psi)``,
  ``exp(psi)^T d exp(psi) = skew(J(psi)^T d psi)`` (the material one);
* its inverse ``J(psi)^-1 = I - skew(psi) / 2 + c skew(psi)^2`` with
  ``c(t) = (1 - t sin t / (2 (1 - cos t))) / t^2``;
* its derivative along a direction ``w``, :func:`left_jacobian_derivative`.

Nodal rotations are updated on the manifold by a spatial increment: ``R <- exp(d phi) R``
(:func:`update`).
"""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

from fvbeam.geometry import skew_matrices

#: Angle below which the coefficients ``a, b, c`` and their derivatives are read from their
#: Taylor series: there the first neglected term is below ``t^6 / 10^4 < 2e-12`` of the
#: leading one, and the closed forms, which lose ``eps / t^2`` to cancellation, are used
#: above, where ``eps / t^2 < 1e-13``.
SERIES = 0.05


def exp_map(psi: np.ndarray) -> np.ndarray:
    """``exp(skew(psi))`` of rotation vectors ``psi`` (..., 3), shape (..., 3, 3)."""
    psi = np.asarray(psi, dtype=float)
    flat = Rotation.from_rotvec(psi.reshape(-1, 3)).as_matrix()
    return flat.reshape(psi.shape[:-1] + (3, 3))


def log_map(R: np.ndarray) -> np.ndarray:
    """The principal rotation vector (``|psi| <= pi``) of rotations ``R`` (..., 3, 3)."""
    R = np.asarray(R, dtype=float)
    flat = Rotation.from_matrix(R.reshape(-1, 3, 3)).as_rotvec()
    return flat.reshape(R.shape[:-2] + (3,))


def update(R: np.ndarray, dphi: np.ndarray) -> np.ndarray:
    """Rotations ``R`` (..., 3, 3) turned by the spatial increments ``dphi`` (..., 3):
    ``exp(skew(dphi)) R``."""
    return exp_map(dphi) @ R


def _coefficients(t: np.ndarray) -> tuple[np.ndarray, ...]:
    """``a, b, c`` of the module docstring and ``a'/t, b'/t`` at angles ``t``."""
    small = t < SERIES
    s = np.where(small, 1.0, t)  # any angle where the series is used
    t2 = t * t
    sin, cos = np.sin(s), np.cos(s)
    a = np.where(small, 0.5 - t2 / 24 + t2 * t2 / 720, (1 - cos) / s**2)
    b = np.where(small, 1 / 6 - t2 / 120 + t2 * t2 / 5040, (s - sin) / s**3)
    c = np.where(small, 1 / 12 + t2 / 720 + t2 * t2 / 30240, (1 - s * sin / (2 * (1 - cos))) / s**2)
    da = np.where(small, -1 / 12 + t2 / 180 - t2 * t2 / 6720, (s * sin - 2 * (1 - cos)) / s**4)
    db = np.where(
        small, -1 / 60 + t2 / 1260 - t2 * t2 / 60480, ((1 - cos) * s - 3 * (s - sin)) / s**5
    )
    return a, b, c, da, db


def left_jacobian(psi: np.ndarray) -> np.ndarray:
    """``J(psi) = I + a skew(psi) + b skew(psi)^2`` (..., 3, 3), the spatial tangent of the
    exponential map."""
    a, b, *_ = _coefficients(np.linalg.norm(psi, axis=-1))
    S = skew_matrices(psi)
    return np.eye(3) + a[..., None, None] * S + b[..., None, None] * (S @ S)


def inverse_left_jacobian(psi: np.ndarray) -> np.ndarray:
    """``J(psi)^-1 = I - skew(psi) / 2 + c skew(psi)^2`` (..., 3, 3): the variation of the
    rotation vector of a rotation turned by a spatial ``d theta`` is ``J^-1 d theta``
    (``|psi| < 2 pi``)."""
    _, _, c, *_ = _coefficients(np.linalg.norm(psi, axis=-1))
    S = skew_matrices(psi)
    return np.eye(3) - 0.5 * S + c[..., None, None] * (S @ S)


def left_jacobian_derivative(psi: np.ndarray, w: np.ndarray) -> np.ndarray:
    """The derivative of :func:`left_jacobian` along ``w``, ``d/de J(psi + e w)`` at 0
    (..., 3, 3)::

        a skew(w) + b (skew(w) skew(psi) + skew(psi) skew(w))
            + (psi . w) (a'/t skew(psi) + b'/t skew(psi)^2)
    """
    a, b, _, da, db = _coefficients(np.linalg.norm(psi, axis=-1))
    S, W = skew_matrices(psi), skew_matrices(w)
    dot = np.einsum("...i,...i->...", psi, w)
    return (
        a[..., None, None] * W
        + b[..., None, None] * (W @ S + S @ W)
        + (dot * da)[..., None, None] * S
        + (dot * db)[..., None, None] * (S @ S)
    )
