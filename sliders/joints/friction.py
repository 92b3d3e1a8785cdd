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
``v_eps``).  ``F`` pushes the body along ``t``; the line takes ``-F`` through the reaction,
which the joint's ``xi`` equation makes carry it: the frictionless ``-l~ . lambda = 0``
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


@dataclass(frozen=True)
class Friction:
    """A slider's bearing friction: coefficient ``mu`` (``>= 0``) and regularisation
    velocity ``v_eps`` [m/s] (``> 0``; the law is viscous, of coefficient ``mu N / v_eps``,
    below it: :func:`sliders.forces.laws.coulomb_friction`).  It acts in dynamics; statics,
    at rest, sees none (``tanh 0 = 0``)."""

    mu: float
    v_eps: float = 1.0e-3

    def __post_init__(self) -> None:
        if not (math.isfinite(self.mu) and self.mu >= 0):
            raise ValueError(f"friction mu must be a finite number >= 0, got {self.mu!r}")
        if not (math.isfinite(self.v_eps) and self.v_eps > 0):
            raise ValueError(f"friction v_eps must be a finite number > 0, got {self.v_eps!r}")


def friction_term(
    l: np.ndarray, w: np.ndarray, lam: np.ndarray, mu: float, v_eps: float
) -> tuple[float, np.ndarray, np.ndarray, np.ndarray, float]:
    """The friction's term ``e = -|l| F = mu |l| N tanh(t . w / v_eps)`` of the ``xi``
    equation (module docstring) and its partial derivatives in ``l``, ``w`` and ``lambda``
    (each (3,)), and the friction force ``F``, written as the equations read."""
    L = np.linalg.norm(l)
    t = l / L
    across = lam - (t @ lam) * t
    N = np.linalg.norm(across)
    tau = np.tanh(t @ w / v_eps)
    sech2 = 1.0 - tau * tau
    e = mu * L * N * tau
    P = np.eye(3) - np.outer(t, t)  # d t / d l = P / L
    dN_dt = -(t @ lam) * lam / N if N > 0 else np.zeros(3)
    d_l = mu * (N * tau * t + tau * (P @ dN_dt) + N * sech2 / v_eps * (P @ w))
    d_w = mu * L * N * sech2 / v_eps * t
    d_lam = mu * L * tau * across / N if N > 0 else np.zeros(3)
    return e, d_l, d_w, d_lam, -mu * N * tau


@numba.njit(cache=True, inline="never")
def friction_at(
    l: np.ndarray,
    w: np.ndarray,
    lam: np.ndarray,
    mu: float,
    v_eps: float,
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
    sech2 = 1.0 - tau * tau
    for c in range(3):
        dN_dt = -along * lam[c] / N if N > 0 else 0.0
        d_w[c] = mu * L * N * sech2 / v_eps * t[c]
        d_lam[c] = mu * L * tau * across[c] / N if N > 0 else 0.0
        d_l[c] = mu * (N * tau * t[c] + N * sech2 / v_eps * (w[c] - slide * t[c]))
        d_l[c] += mu * tau * dN_dt
    # the projection P = I - t t of d N / d t: remove its component along t
    dot = 0.0
    for c in range(3):
        dot += t[c] * (-along * lam[c] / N if N > 0 else 0.0)
    for c in range(3):
        d_l[c] -= mu * tau * dot * t[c]
    return mu * L * N * tau, -mu * N * tau
