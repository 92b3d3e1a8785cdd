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
derivatives in ``l~``, ``w`` and ``lambda`` are :func:`friction_term` (numpy, the reference)
and :func:`friction_at` (compiled); :mod:`sliders.joints.packed` carries them through the
line's dependence on ``xi`` and on the dofs, the velocities on the dofs by the integrator's
``gamma'``.  The friction's power ``F v_rel <= 0`` is what it dissipates.

Couples of the classical and spline sliders make no friction here: a bearing's couple is a
pair of forces whose size depends on the bearing's length, which the joint does not know.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numba
import numpy as np

from fvbeam.kernel_cache import guard

guard(__file__)  # numba's cache of these kernels, consistent with their sources


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


def friction_term(
    l: np.ndarray,
    w: np.ndarray,
    lam: np.ndarray,
    mu: float,
    v_eps: float,
    mu_static: float | None = None,
    v_stribeck: float = 1.0,
) -> tuple[float, np.ndarray, np.ndarray, np.ndarray, float]:
    """The friction's term ``e = -|l| F = |l| N phi(s)`` of the ``xi`` equation (module
    docstring), ``s = t . w``, ``phi = g tanh(s / v_eps)`` with the Stribeck curve ``g``
    (``g = mu`` when ``mu_static`` is None or ``mu``), its partial derivatives in ``l``,
    ``w`` and ``lambda`` (each (3,)), and the friction force ``F``, written as the equations
    read: with ``P = I - t t`` (``dt/dl = P / |l|``) and ``dN/dt = -(t . lambda) lambda / N``,

        de/dl = N phi t + phi P dN/dt + N phi'(s) P w,
        de/dw = |l| N phi'(s) t,        de/dlambda = |l| phi (lambda - (t . lambda) t) / N.
    """
    static = mu if mu_static is None else mu_static
    L = np.linalg.norm(l)
    t = l / L
    across = lam - (t @ lam) * t
    N = np.linalg.norm(across)
    s = t @ w
    tau = np.tanh(s / v_eps)
    drop = (static - mu) * np.exp(-((s / v_stribeck) ** 2))
    g, g_s = mu + drop, -2.0 * s * drop / v_stribeck**2
    phi, phi_s = g * tau, g_s * tau + g * (1.0 - tau * tau) / v_eps
    P = np.eye(3) - np.outer(t, t)
    dN_dt = -(t @ lam) * lam / N if N > 0 else np.zeros(3)
    d_l = N * phi * t + phi * (P @ dN_dt) + N * phi_s * (P @ w)
    d_w = L * N * phi_s * t
    d_lam = L * phi * across / N if N > 0 else np.zeros(3)
    return L * N * phi, d_l, d_w, d_lam, -N * phi


@numba.njit(cache=True, inline="never")
def friction_at(
    l: np.ndarray,
    w: np.ndarray,
    lam: np.ndarray,
    mu: float,
    v_eps: float,
    mu_static: float,
    v_stribeck: float,
    d_l: np.ndarray,
    d_w: np.ndarray,
    d_lam: np.ndarray,
) -> tuple[float, float]:
    """:func:`friction_term` compiled: returns ``e`` and ``F``, the partials into ``d_l``,
    ``d_w``, ``d_lam`` (3,)."""
    L = np.sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2])
    t = l / L
    along = t[0] * lam[0] + t[1] * lam[1] + t[2] * lam[2]
    across = lam - along * t
    N = np.sqrt(across[0] ** 2 + across[1] ** 2 + across[2] ** 2)
    slide = t[0] * w[0] + t[1] * w[1] + t[2] * w[2]
    tau = np.tanh(slide / v_eps)
    drop = (mu_static - mu) * np.exp(-((slide / v_stribeck) ** 2))
    g = mu + drop
    phi = g * tau
    phi_s = -2.0 * slide * drop / (v_stribeck * v_stribeck) * tau + g * (1.0 - tau * tau) / v_eps
    for c in range(3):
        dN_dt = -along * lam[c] / N if N > 0 else 0.0
        d_w[c] = L * N * phi_s * t[c]
        d_lam[c] = L * phi * across[c] / N if N > 0 else 0.0
        d_l[c] = N * phi * t[c] + N * phi_s * (w[c] - slide * t[c]) + phi * dN_dt
    # the projection P = I - t t of d N / d t: remove its component along t
    dot = 0.0
    for c in range(3):
        dot += t[c] * (-along * lam[c] / N if N > 0 else 0.0)
    for c in range(3):
        d_l[c] -= phi * dot * t[c]
    return L * N * phi, -N * phi
