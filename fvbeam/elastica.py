"""Closed forms of large-deflection statics of inextensible, unshearable rods (oracles of the
geometrically exact beam, :mod:`fvbeam.exact_beam`).

* :func:`tip_loaded_cantilever`: the elastica of a cantilever under a dead tip force normal
  to its straight reference, by elliptic integrals (Bisshopp and Drucker, Q. Appl. Math. 3
  (1945) 272; tabulated by Mattiasson, IJNME 17 (1981) 145).
* :func:`rolled_cantilever`: a cantilever under an end couple bends into a circular arc of
  radius ``EJ / M``.
* :func:`twisted_cantilever`: a straight rod of isotropic bending stiffness and any torsional
  stiffness under a dead end couple in any direction: a helix (Kirchhoff), with bending and
  twist coupled by the couple's turning with the section.
* :func:`heavy_cantilever`: the elastica of a cantilever under its own weight, a uniform
  dead load normal to its straight reference (Frisch-Fay, "Flexible Bars", Butterworths
  1962, Ch. 4), by collocation (scipy's ``solve_bvp``) to ``1e-10``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.integrate
import scipy.optimize
from scipy.special import ellipe, ellipeinc, ellipk, ellipkinc

from fvbeam.rotations import exp_map


@dataclass(frozen=True)
class ElasticaTip:
    """The tip of the tip-loaded elastica, in units of the length: ``shortening`` (along the
    reference axis), ``deflection`` (along the load) and the tip ``rotation`` (rad)."""

    shortening: float
    deflection: float
    rotation: float


def tip_loaded_cantilever(load: float) -> ElasticaTip:
    """The elastica of a cantilever under a dead tip force normal to it, at the load
    parameter ``load = P L^2 / EJ > 0``.

    With the tip rotation ``theta0``, ``k^2 = (1 + sin theta0) / 2`` and
    ``sin phi1 = 1 / (k sqrt 2)``, the moment balance ``EJ theta'' = -P cos theta`` integrates
    to (``K, F, E`` the complete and incomplete elliptic integrals of the first and second
    kind, modulus ``k``)::

        sqrt(load) = K(k) - F(phi1, k)
        deflection / L = 1 - 2 (E(k) - E(phi1, k)) / sqrt(load)
        shortening / L = 1 - sqrt(2 sin theta0 / load)

    ``theta0`` is the root of the first in ``(0, pi/2)`` (Brent).  At ``load = 10``:

    >>> tip = tip_loaded_cantilever(10.0)
    >>> round(tip.shortening, 5), round(tip.deflection, 5)
    (0.555, 0.81061)
    """
    if not load > 0:
        raise ValueError(f"load P L^2 / EJ must be > 0, got {load!r}")

    def modulus(theta0: float) -> tuple[float, float]:
        m = (1 + np.sin(theta0)) / 2  # k^2
        return m, float(np.arcsin(1 / np.sqrt(2 * m)))

    def balance(theta0: float) -> float:
        m, phi1 = modulus(theta0)
        return float(ellipk(m) - ellipkinc(phi1, m)) - np.sqrt(load)

    theta0 = scipy.optimize.brentq(balance, 1e-12, np.pi / 2 - 1e-12, xtol=1e-15, rtol=1e-15)
    m, phi1 = modulus(theta0)
    deflection = 1 - 2 * float(ellipe(m) - ellipeinc(phi1, m)) / np.sqrt(load)
    shortening = 1 - np.sqrt(2 * np.sin(theta0) / load)
    return ElasticaTip(float(shortening), float(deflection), float(theta0))


def rolled_cantilever(moment: float, length: float = 1.0, EJ: float = 1.0) -> np.ndarray:
    """Tip position ``(x, y)`` of a cantilever along ``x`` from the origin under an end couple
    ``moment`` about ``z``: the arc of radius ``rho = EJ / moment``,
    ``(rho sin(L / rho), rho (1 - cos(L / rho)))``; at ``moment = 2 pi EJ / L`` the tip is
    back at the root.

    >>> np.round(rolled_cantilever(2 * np.pi), 12) + 0.0
    array([0., 0.])
    """
    angle = moment * length / EJ
    if angle == 0:
        return np.array([length, 0.0])
    rho = EJ / moment
    return np.array([rho * np.sin(angle), rho * (1 - np.cos(angle))])


def twisted_cantilever(
    moment: np.ndarray, length: float, EJ: float, GJ: float
) -> tuple[np.ndarray, np.ndarray]:
    """Tip position (from the root) and rotation of a straight rod along ``x`` (section axes
    the global ones), clamped at the root, bending stiffness ``EJ`` about both section axes and
    torsional stiffness ``GJ``, under a dead end couple ``moment`` (global).

    No force acts, so the internal couple is ``moment`` everywhere and the material curvature
    is ``kappa = C^-1 Lambda^T M`` with ``C = diag(GJ, EJ, EJ)``; its solution is
    ``Lambda(s) = exp(s M / EJ) exp(s b e1)`` with ``b = M . e1 (1/GJ - 1/EJ)`` (the section
    turns about the couple at the rate ``|M| / EJ`` and twists about its own axis at ``b``),
    and the centreline ``x' = Lambda e1 = exp(s M / EJ) e1``, a helix about ``M``::

        x(L) = (n . e1) n L + sin(w L) / w e_p + (1 - cos(w L)) / w (n x e_p)

    with ``w = |M| / EJ``, ``n = M / |M|``, ``e_p = e1 - (n . e1) n``.
    """
    M = np.asarray(moment, dtype=float)
    e1 = np.array([1.0, 0.0, 0.0])
    w = float(np.linalg.norm(M)) / EJ
    n = M / np.linalg.norm(M)
    ep = e1 - (n @ e1) * n
    tip = (n @ e1) * n * length + np.sin(w * length) / w * ep
    tip += (1 - np.cos(w * length)) / w * np.cross(n, ep)
    b = M[0] * (1 / GJ - 1 / EJ)
    rotation = exp_map(length * M / EJ) @ exp_map(length * b * e1)
    return tip, rotation


def heavy_cantilever(load: float) -> ElasticaTip:
    """The elastica of a cantilever under a uniform dead load ``w`` per length normal to its
    straight reference (its own weight), at the load parameter ``load = w L^3 / EJ > 0``
    (Frisch-Fay, "Flexible Bars" (1962), Ch. 4: the heavy cantilever), in units of ``L``.

    With the arc length ``s``, the section's turn ``theta`` (counterclockwise, the load
    along ``-y``), the moment at ``s`` is the load beyond it about it,
    ``EJ theta' = -w int_s^L (x(t) - x(s)) dt``, so ``EJ theta'' = w (L - s) cos theta``,
    with ``theta(0) = 0`` (clamped) and ``theta'(L) = 0`` (free); ``x' = cos theta``,
    ``y' = sin theta``.  Solved by scipy's collocation ``solve_bvp`` to a residual of
    ``1e-10`` on 200 to 10^5 nodes, from the small-deflection solution.
    """
    if not load > 0:
        raise ValueError(f"load must be > 0, got {load!r}")

    def rhs(s: np.ndarray, y: np.ndarray) -> np.ndarray:
        theta, dtheta = y[0], y[1]
        return np.vstack([dtheta, load * (1 - s) * np.cos(theta), np.cos(theta), np.sin(theta)])

    def ends(a: np.ndarray, b: np.ndarray) -> np.ndarray:
        return np.array([a[0], b[1], a[2], a[3]])

    s = np.linspace(0.0, 1.0, 200)
    theta = load * ((1 - s) ** 3 - 1) / 6  # the linear beam's, theta' = -w (L - s)^2 / 2 EJ
    guess = np.vstack([theta, -load * (1 - s) ** 2 / 2, s, np.zeros_like(s)])
    solution = scipy.integrate.solve_bvp(rhs, ends, s, guess, tol=1e-10, max_nodes=100_000)
    if not solution.success:
        raise RuntimeError(f"heavy cantilever at load {load}: {solution.message}")
    theta, _, x, y = solution.y[:, -1]
    return ElasticaTip(1.0 - x, -y, -theta)
