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
* its derivative along a direction ``w``, :func:`left_jacobian_derivative`, and, for the
  second variations of Galerkin beams, the derivatives of ``J(psi)^T y`` along ``psi``
  (:func:`transposed_jacobian_derivative`) and of that along ``psi`` again
  (:func:`transposed_jacobian_second_derivative`), written with
  ``alpha = a'/t, beta = b'/t, gamma = alpha'/t, delta = beta'/t``.

Nodal rotations are updated on the manifold by a spatial increment: ``R <- exp(d phi) R``
(:func:`update`).
"""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation

from fvbeam.geometry import skew_matrices

#: Angle below which ``gamma`` and ``delta`` (module docstring) are read from their series
#: (to ``t^6``): the first neglected term is below ``1.4e-9 t^8 < 4e-13`` there, and the
#: closed forms, which lose about ``eps / t^6`` to cancellation, below ``1e-12`` above
#: (measured against the series to ``t^22``).
SECOND_SERIES = 0.35
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
    """``a, b, c, alpha, beta`` of the module docstring at angles ``t``."""
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


def _second_coefficients(t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``gamma = alpha'/t`` and ``delta = beta'/t`` (module docstring) at angles ``t``."""
    small = t < SECOND_SERIES
    s = np.where(small, 1.0, t)
    t2 = t * t
    sin, cos = np.sin(s), np.cos(s)
    alpha = (s * sin - 2 * (1 - cos)) / s**4
    beta = ((1 - cos) * s - 3 * (s - sin)) / s**5
    gamma = np.where(
        small,
        1 / 90 - t2 / 1680 + t2 * t2 / 75600 - t2**3 / 5987520,
        ((s * cos - sin) / s**4 - 4 * alpha / s) / s,
    )
    delta = np.where(
        small,
        1 / 630 - t2 / 15120 + t2 * t2 / 831600 - t2**3 / 77837760,
        ((s * sin - 2 * (1 - cos)) / s**5 - 5 * beta / s) / s,
    )
    return gamma, delta


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


def transposed_jacobian_derivative(psi: np.ndarray, y: np.ndarray) -> np.ndarray:
    """``L`` (..., 3, 3) with ``d/de J(psi + e w)^T y = L w`` at 0::

    L = a skew(y) - b skew(psi) skew(y) - b skew(skew(psi) y)
        + ((-alpha skew(psi) + beta skew(psi)^2) y) psi^T
    """
    a, b, _, alpha, beta = _coefficients(np.linalg.norm(psi, axis=-1))
    S, Y = skew_matrices(psi), skew_matrices(y)
    Sy = np.einsum("...ij,...j->...i", S, y)
    SSy = np.einsum("...ij,...j->...i", S, Sy)
    tail = -alpha[..., None] * Sy + beta[..., None] * SSy
    return (
        a[..., None, None] * Y
        - b[..., None, None] * (S @ Y + skew_matrices(Sy))
        + tail[..., :, None] * psi[..., None, :]
    )


def transposed_jacobian_second_derivative(
    psi: np.ndarray, y: np.ndarray, w: np.ndarray
) -> np.ndarray:
    """``d/de [transposed_jacobian_derivative(psi + e x, y) w]`` at 0 as a matrix in ``x``
    (..., 3, 3): the second derivative of ``J(psi)^T y`` along ``w`` and ``x``."""
    a, b, _, alpha, beta = _coefficients(np.linalg.norm(psi, axis=-1))
    gamma, delta = _second_coefficients(np.linalg.norm(psi, axis=-1))
    S, Y, W = skew_matrices(psi), skew_matrices(y), skew_matrices(w)
    Sy = np.einsum("...ij,...j->...i", S, y)
    SSy = np.einsum("...ij,...j->...i", S, Sy)
    Yw = np.einsum("...ij,...j->...i", Y, w)
    SYw = np.einsum("...ij,...j->...i", S, Yw)
    Syw = np.einsum("...ij,...j->...i", skew_matrices(Sy), w)
    dot = np.einsum("...i,...i->...", psi, w)[..., None, None]

    def outer(u: np.ndarray, v: np.ndarray) -> np.ndarray:
        return u[..., :, None] * v[..., None, :]

    x = lambda c: c[..., None, None]  # noqa: E731 - a coefficient broadcast over 3x3
    return (
        outer(x(alpha)[..., 0] * Yw - x(beta)[..., 0] * SYw - x(beta)[..., 0] * Syw, psi)
        + x(b) * skew_matrices(Yw)
        - x(b) * (W @ Y)
        + dot
        * (
            outer(-x(gamma)[..., 0] * Sy + x(delta)[..., 0] * SSy, psi)
            + x(alpha) * Y
            - x(beta) * (skew_matrices(Sy) + S @ Y)
        )
        + outer(-x(alpha)[..., 0] * Sy + x(beta)[..., 0] * SSy, w)
    )
