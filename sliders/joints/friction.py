"""Coulomb friction along a slider's line, its normal force the joint's transverse reaction.

The paper's future work (Sec. 7): a bearing's friction ``mu N`` opposing the sliding, ``N``
the reaction across the line.  With the reaction ``lambda`` (the joint's multipliers, the
force on the body being ``-lambda``), the line's tangent ``t = l~ / |l~|`` (the recovered
tangent of the frictionless condition) and the sliding velocity of the body's point relative
to the line's material point under it, ``v_rel = t . w``, ``w = v_point - v_line(xi)``:

.. math::

    N = |\\lambda - (t \\cdot \\lambda) t|, \\qquad
    F = -\\mu N \\tanh(v_{rel} / v_\\epsilon)

(:func:`sliders.forces.laws.coulomb_friction`, regularised: a viscous law below
``v_eps``); with stick-slip, ``mu`` is the Stribeck curve ``g(v) = mu_k + (mu_s - mu_k)
exp(-(v / v_s)^2)`` falling from the static ``mu_s`` to the kinetic ``mu = mu_k``
(:func:`sliders.forces.laws.stribeck_friction`): ``F = -N phi(v_rel)``, ``phi = g tanh``.

``F`` pushes the body along ``t``; the line takes ``-F`` through the reaction, which the
joint's ``xi`` equation makes carry it: the frictionless ``-l~ . lambda = 0``
becomes ``-l~ . lambda - |l~| F = 0`` (the virtual work of a force between body and line
along the line, ``F |l~| delta xi``).  Its term in that equation and the term's partial
derivatives in ``l~``, ``w`` and ``lambda`` are :func:`friction_term` (the statement) and
:func:`sliders.joints.compiled_laws.friction_at` (compiled, generated from it by
:mod:`sliders.joints.generate`);
:mod:`sliders.joints.packed` carries them through the
line's dependence on ``xi`` and on the dofs, the velocities on the dofs by the integrator's
``gamma'``.  The friction's power ``F v_rel <= 0`` is what it dissipates.

Couples of the classical and spline sliders make no friction here: a bearing's couple is a
pair of forces whose size depends on the bearing's length, which the joint does not know.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from sliders.joints.arithmetic import NUMPY


@dataclass(frozen=True)
class Friction:
    """A slider's bearing friction: coefficient ``mu`` (``>= 0``; the kinetic one with
    stick-slip) and regularisation velocity ``v_eps`` [m/s] (``> 0``; the law is viscous, of
    coefficient ``mu N / v_eps``, below it: :func:`sliders.forces.laws.coulomb_friction`);
    stick-slip: a static coefficient ``mu_static >= mu`` and the Stribeck speed
    ``v_stribeck`` [m/s] over which the friction falls from it to ``mu``
    (:func:`sliders.forces.laws.stribeck_friction`).  It acts in dynamics; statics, at
    rest, sees none (``tanh 0 = 0``)."""

    mu: float
    v_eps: float = 1.0e-3
    mu_static: float | None = None
    v_stribeck: float = 1.0e-2

    def __post_init__(self) -> None:
        if not (math.isfinite(self.mu) and self.mu >= 0):
            raise ValueError(f"friction mu must be a finite number >= 0, got {self.mu!r}")
        if not (math.isfinite(self.v_eps) and self.v_eps > 0):
            raise ValueError(f"friction v_eps must be a finite number > 0, got {self.v_eps!r}")
        if self.mu_static is not None and not (
            math.isfinite(self.mu_static) and self.mu_static >= self.mu
        ):
            raise ValueError(
                f"friction mu_static must be a finite number >= mu ({self.mu}), "
                f"got {self.mu_static!r}"
            )
        if not (math.isfinite(self.v_stribeck) and self.v_stribeck > 0):
            raise ValueError(
                f"friction v_stribeck must be a finite number > 0, got {self.v_stribeck!r}"
            )

    @property
    def law(self) -> tuple[float, float, float, float]:
        """``mu, v_eps, mu_static, v_stribeck`` as :func:`friction_term` takes them
        (``mu_static = mu`` without stick-slip)."""
        static = self.mu if self.mu_static is None else self.mu_static
        return self.mu, self.v_eps, static, self.v_stribeck


def friction_force(
    v: Any, N: Any, *, mu: Any, v_eps: Any, mu_static: Any, v_stribeck: Any, ops: Any = NUMPY
) -> Any:
    """The friction law: ``F = -N phi(v)``, ``phi = g(v) tanh(v / v_eps)`` with the Stribeck
    curve ``g = mu + (mu_static - mu) exp(-(v / v_stribeck)^2)`` (``g = mu`` when
    ``mu_static = mu``: Coulomb's law, regularised), at the sliding speed ``v`` under the
    normal force ``N``; the arithmetic ``ops`` (:mod:`sliders.joints.arithmetic`)."""
    g = mu + (mu_static - mu) * ops.exp(-((v / v_stribeck) ** 2))
    return -N * g * ops.tanh(v / v_eps)


def friction_term(
    l: Any,
    w: Any,
    lam: Any,
    mu: Any,
    v_eps: Any,
    mu_static: Any = None,
    v_stribeck: Any = 1.0,
    ops: Any = NUMPY,
) -> tuple[Any, Any]:
    """The friction's term ``e = -|l| F`` of the ``xi`` equation (module docstring) and the
    friction force ``F`` (:func:`friction_force` of the sliding speed ``s = t . w`` and the
    transverse reaction ``N = |lambda - (t . lambda) t|``, ``t = l / |l|``; ``mu_static``
    None: ``mu``), 3-vectors ``l``, ``w``, ``lambda``.  Without a transverse reaction
    (``N = 0``) the term is 0 and so are its derivatives (the one-sided ones of ``N``).
    Its partial derivatives, compiled, are generated from this statement
    (:func:`sliders.joints.compiled_laws.friction_at`)."""
    static = mu if mu_static is None else mu_static
    L = ops.sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2])
    t = [l[c] / L for c in range(3)]
    along = t[0] * lam[0] + t[1] * lam[1] + t[2] * lam[2]
    across = [lam[c] - along * t[c] for c in range(3)]
    N = ops.sqrt(across[0] * across[0] + across[1] * across[1] + across[2] * across[2])
    s = t[0] * w[0] + t[1] * w[1] + t[2] * w[2]
    F = friction_force(s, N, mu=mu, v_eps=v_eps, mu_static=static, v_stribeck=v_stribeck, ops=ops)
    return ops.where(N > 0, -L * F, 0.0), F
