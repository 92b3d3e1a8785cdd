"""The force laws of :mod:`sliders.forces.laws` at one point, compiled (numba).

The compiled Newton step evaluates force elements at every iteration
(:mod:`sliders.forces.kernel`), so each law has a scalar twin here, with its parameters in a
row of floats in the order its ``PARAMETERS`` entry lists.  The laws of
:mod:`sliders.forces.laws` are the references (they check their inputs; these do not: the
elements check them once, where they are built); ``tests/test_laws_kernel.py`` holds each twin
equal to its reference to roundoff.  Every function returns the value and its partial
derivatives in the order of its state arguments.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from fvbeam.kernel_cache import guard

guard(__file__)  # numba's cache of these kernels, consistent with their sources

#: The parameter rows of the laws, by name (:mod:`sliders.forces.laws` keyword arguments).
PARAMETERS = {
    "strut": (
        "area",
        "pressure",
        "volume",
        "exponent",
        "ambient",
        "compression",
        "rebound",
        "stop_stiffness",
        "stroke_min",
        "stroke_max",
    ),
    "tyre": ("radius", "stiffness", "damping", "B", "C", "D", "speed_eps"),
    "coulomb": ("mu", "v_eps"),
}


@numba.njit(cache=True, inline="never")
def strut(p: np.ndarray, stroke: float, rate: float) -> tuple[float, float, float]:
    """:class:`sliders.forces.laws.Strut`: gas spring, orifice damper and end stops,
    ``(F_s, dF_s/dS, dF_s/dS')``; ``p``: ``PARAMETERS["strut"]``."""
    A, p0, V0, n, p_atm = p[0], p[1], p[2], p[3], p[4]
    gas = V0 - A * stroke
    ratio = (V0 / gas) ** n
    force = A * (p0 * ratio - p_atm)
    d_stroke = n * A * A * p0 * ratio / gas
    c = p[5] if rate > 0 else p[6]
    force += c * rate * abs(rate)
    d_rate = 2.0 * c * abs(rate)
    k, low, high = p[7], p[8], p[9]
    if stroke < low:
        force += k * (stroke - low)
        d_stroke += k
    elif stroke > high:
        force += k * (stroke - high)
        d_stroke += k
    return force, d_stroke, d_rate


@numba.njit(cache=True, inline="never")
def tyre_radial(p: np.ndarray, deflection: float, rate: float) -> tuple[float, float, float]:
    """:func:`sliders.forces.laws.tyre_radial`: ``(F_z, dF_z/dd, dF_z/dd')``."""
    k, c = p[1], p[2]
    push = k * deflection + c * rate
    if deflection > 0 and push > 0:
        return push, k, c
    return 0.0, 0.0, 0.0


@numba.njit(cache=True, inline="never")
def tyre_longitudinal(
    p: np.ndarray, forward_speed: float, spin: float, normal: float
) -> tuple[float, float, float, float]:
    """:func:`sliders.forces.laws.tyre_longitudinal`: ``F_x = -mu(kappa) F_z`` with the
    slip :func:`~sliders.forces.laws.slip_ratio` and the Magic Formula
    :func:`~sliders.forces.laws.friction_curve`: ``(F_x, dF_x/du, dF_x/domega, dF_x/dF_z)``."""
    R, B, C, D, eps = p[0], p[3], p[4], p[5], p[6]
    u, w = forward_speed, spin
    scale = math.sqrt(u * u + eps * eps)
    kappa = (u - w * R) / scale
    k_u = 1.0 / scale - kappa * u / (scale * scale)
    k_w = -R / scale
    angle = C * math.atan(B * kappa)
    mu = D * math.sin(angle)
    mu_k = D * C * B * math.cos(angle) / (1.0 + (B * kappa) ** 2)
    return -mu * normal, -mu_k * k_u * normal, -mu_k * k_w * normal, -mu


@numba.njit(cache=True, inline="never")
def coulomb(p: np.ndarray, velocity: float, normal: float) -> tuple[float, float, float]:
    """:func:`sliders.forces.laws.coulomb_friction`: ``(F, dF/dv, dF/dN)``."""
    mu, eps = p[0], p[1]
    t = math.tanh(velocity / eps)
    return -mu * normal * t, -mu * normal * (1.0 - t * t) / eps, -mu * t
