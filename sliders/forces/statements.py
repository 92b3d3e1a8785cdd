"""The force laws, each stated once: its value as its source writes it, nothing else.

Each function returns the law's value from its states and parameters with the arithmetic of
``ops`` (:data:`sliders.joints.arithmetic.NUMPY` here; sympy in
:mod:`sliders.forces.generate`, which differentiates the statement and prints its value
and partial derivatives as numpy code, :mod:`sliders.forces.array_laws`, behind
:mod:`sliders.forces.laws`, and as compiled code, :mod:`sliders.forces.compiled_laws`,
behind the force elements).  Branches are written with
``ops.where`` and strict inequalities, so the derivative at a kink is that of the branch the
inequality selects (the docstrings of :mod:`sliders.forces.laws` say which).

Sources: the gas spring and the orifice damper, Milwitzky and Cook, NACA Report 1154 (1953);
the tyre's slip and Magic Formula, Pacejka, *Tire and Vehicle Dynamics*; regularised
Coulomb and Stribeck friction (``docs/landing_gear.md`` gives every parameter of the gear).
"""

from __future__ import annotations

from typing import Any

from sliders.joints.arithmetic import NUMPY
from sliders.joints.friction import friction_force

__all__ = ["NUMPY"]


def gas_spring(
    S: Any, *, area: Any, pressure: Any, volume: Any, exponent: Any, ambient: Any, ops: Any
) -> Any:
    """``F_gas = A [p0 (V0 / (V0 - A S))^n - p_atm]``: a polytropic gas column (``p V^n``
    constant) compressed by the stroke ``S``."""
    return area * (pressure * (volume / (volume - area * S)) ** exponent - ambient)


def orifice_damper(v: Any, *, compression: Any, rebound: Any, ops: Any) -> Any:
    """``F_d = c v |v|`` with ``c = c_comp`` for ``v > 0`` (compression), else ``c_reb``."""
    return ops.where(v > 0, compression, rebound) * v * ops.abs(v)


def end_stops(S: Any, *, stiffness: Any, lower: Any, upper: Any, ops: Any) -> Any:
    """``k (S - S_min)`` for ``S < S_min``, ``k (S - S_max)`` for ``S > S_max``, else 0."""
    k = stiffness
    return ops.where(S < lower, k * (S - lower), ops.where(S > upper, k * (S - upper), 0.0))


def strut(
    S: Any,
    v: Any,
    *,
    area: Any,
    pressure: Any,
    volume: Any,
    exponent: Any,
    ambient: Any,
    compression: Any,
    rebound: Any,
    stop_stiffness: Any,
    stroke_min: Any,
    stroke_max: Any,
    ops: Any,
) -> Any:
    """The oleo-pneumatic strut: :func:`gas_spring` + :func:`orifice_damper` +
    :func:`end_stops`."""
    gas = gas_spring(
        S,
        area=area,
        pressure=pressure,
        volume=volume,
        exponent=exponent,
        ambient=ambient,
        ops=ops,
    )
    damper = orifice_damper(v, compression=compression, rebound=rebound, ops=ops)
    stop = end_stops(S, stiffness=stop_stiffness, lower=stroke_min, upper=stroke_max, ops=ops)
    return gas + damper + stop


def tyre_radial(d: Any, v: Any, *, stiffness: Any, damping: Any, ops: Any) -> Any:
    """``F_z = k d + c d'`` where the tyre is deflected (``d > 0``) and pushes
    (``k d + c d' > 0``), else 0: a tyre never pulls."""
    push = stiffness * d + damping * v
    return ops.where(ops.both(d > 0, push > 0), push, 0.0)


def slip_ratio(u: Any, w: Any, *, radius: Any, speed_eps: Any, ops: Any) -> Any:
    """``kappa = (u - omega R) / sqrt(u^2 + u_eps^2)``: the longitudinal slip, regularised
    at zero forward speed."""
    return (u - w * radius) / ops.sqrt(u * u + speed_eps * speed_eps)


def friction_curve(kappa: Any, *, B: Any, C: Any, D: Any, ops: Any) -> Any:
    """``mu = D sin(C atan(B kappa))``: Pacejka's Magic Formula without shift or curvature."""
    return D * ops.sin(C * ops.atan(B * kappa))


def tyre_longitudinal(
    u: Any, w: Any, N: Any, *, radius: Any, speed_eps: Any, B: Any, C: Any, D: Any, ops: Any
) -> Any:
    """``F_x = -mu(kappa(u, omega)) F_z``: :func:`friction_curve` of :func:`slip_ratio`."""
    kappa = slip_ratio(u, w, radius=radius, speed_eps=speed_eps, ops=ops)
    return -friction_curve(kappa, B=B, C=C, D=D, ops=ops) * N


def coulomb_friction(v: Any, N: Any, *, mu: Any, v_eps: Any, ops: Any) -> Any:
    """``F = -mu N tanh(v / v_eps)``: Coulomb friction regularised by a hyperbolic tangent
    (:func:`sliders.joints.friction.friction_force` without the Stribeck drop)."""
    return friction_force(v, N, mu=mu, v_eps=v_eps, mu_static=mu, v_stribeck=1.0, ops=ops)


def stribeck_friction(
    v: Any, N: Any, *, mu_static: Any, mu_kinetic: Any, v_stribeck: Any, v_eps: Any, ops: Any
) -> Any:
    """``F = -N g(v) tanh(v / v_eps)``, ``g = mu_k + (mu_s - mu_k) exp(-(v / v_s)^2)``: the
    Stribeck drop from static to kinetic friction
    (:func:`sliders.joints.friction.friction_force`)."""
    return friction_force(
        v, N, mu=mu_kinetic, v_eps=v_eps, mu_static=mu_static, v_stribeck=v_stribeck, ops=ops
    )
