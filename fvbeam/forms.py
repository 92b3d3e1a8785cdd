"""scikit-fem forms of the linear 3-D Timoshenko beam (``docs/theory.md``).

Generalised strains in global axes (eq. T1)::

    nu = u' - theta x t,      kappa = theta'

with ``'`` the derivative in arc length and ``t`` the unit tangent.  Internal virtual work
(eq. T3)::

    delta W_int = int ( F . (w' - psi x t) + M . psi' ) ds,   [F; M] = C [nu; kappa]

The forms take three fields at the quadrature points: ``t`` (unit tangent), ``metric``
(ds / d(affine coordinate), 1 on straight beams) and ``C`` (6x6 section stiffness in global
axes).  Test and trial bases may differ (Petrov-Galerkin): the fv test element supplies the
rigid motions of the influence regions, the Galerkin test element the shape functions.
"""

from __future__ import annotations

import numpy as np
from skfem import BilinearForm, LinearForm
from skfem.element import DiscreteField

from fvbeam.geometry import cross


def generalised_strain(field: DiscreteField, t: np.ndarray, metric: np.ndarray) -> np.ndarray:
    """``[u' - theta x t, theta']`` of a 6-component field, shape (6, ...) (eq. T1)."""
    d = field.grad[:, 0] / metric
    rot = cross(np.asarray(field)[3:], t, axis=0)
    return np.concatenate([d[:3] - rot, d[3:]])


@BilinearForm
def internal_work(u, v, w):
    """Internal virtual work density (eq. T3), per unit of the affine element coordinate."""
    t, metric, C = np.asarray(w.t), np.asarray(w.metric), np.asarray(w.C)
    stress = np.einsum("ij...,j...->i...", C, generalised_strain(u, t, metric))
    return np.einsum("i...,i...->...", generalised_strain(v, t, metric), stress) * metric


@LinearForm
def distributed_load(v, w):
    """Virtual work of a force ``f`` and a couple ``m`` per unit length (eq. T5)."""
    v = np.asarray(v)
    work = np.einsum("i...,i...->...", v[:3], np.asarray(w.f)) + np.einsum(
        "i...,i...->...", v[3:], np.asarray(w.m)
    )
    return work * np.asarray(w.metric)


@BilinearForm
def inertia(u, v, w):
    """Kinetic-energy density ``m w.u + psi.(J theta)`` of the translations ``u[:3]`` and
    rotations ``u[3:]``, with ``m`` the mass per length and ``J`` the section inertia per
    length in global axes (3x3 field); per unit of the affine element coordinate."""
    u, v = np.asarray(u), np.asarray(v)
    rotary = np.einsum("ij...,j...->i...", np.asarray(w.J), u[3:])
    work = np.asarray(w.m) * np.einsum("i...,i...->...", v[:3], u[:3]) + np.einsum(
        "i...,i...->...", v[3:], rotary
    )
    return work * np.asarray(w.metric)
