"""Closed-form answers used as oracles by the tests and the studies.

Cantilever of length ``L`` clamped at 0, transverse force ``F`` at station ``xi`` (paper
Sec. 5).  Every function returns ``(v_flexural, v_shear, phi)`` at the tip ``L``; the tip
displacement is ``v_flexural + v_shear``.  Where a finite-volume load sits exactly on an
evaluation point it is shared half and half between the two regions, as
:func:`fvbeam.elements.indicator` does.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg
import scipy.optimize

from fvbeam.elements import TIE


def _step(x: np.ndarray, L: float = 1.0) -> np.ndarray:
    """Heaviside step, 1/2 within the library's tie band (``elements.TIE`` element lengths)."""
    tie = np.abs(x) <= TIE * L
    return np.where(tie, 0.5, np.where(x > 0, 1.0, 0.0))


def cantilever_exact(xi, L: float = 1.0, EJ: float = 1.0, GA: float = 1.0, F: float = 1.0):
    """Timoshenko cantilever, force at ``xi`` (paper Sec. 5.1)."""
    xi = np.asarray(xi, dtype=float)
    return F * xi**2 * (3 * L - xi) / (6 * EJ), F * xi / GA, F * xi**2 / (2 * EJ)


def cantilever_fv2(xi, L: float = 1.0, EJ: float = 1.0, GA: float = 1.0, F: float = 1.0):
    """One 2-node finite-volume element (paper Sec. 5.2)."""
    xi = np.asarray(xi, dtype=float)
    step = _step(xi - L / 2, L)
    return (F * L**2 / (2 * EJ) * (xi - L / 2) * step, F * L / GA * step,
            F * L / EJ * np.maximum(xi - L / 2, 0.0))


def cantilever_fv3(xi, L: float = 1.0, EJ: float = 1.0, GA: float = 1.0, F: float = 1.0):
    """One 3-node finite-volume element (paper Sec. 5.3; ``docs/theory.md`` for a < xi < b).

    With the evaluation points ``a, b = L (1 -+ 1/sqrt(3)) / 2``:

    * ``xi < a``: the load is on the clamped node, nothing moves;
    * ``a < xi < b``: ``v = F [L b (xi - a) / (2 EJ) + L / (2 GA)]``,
      ``phi = F L (xi - a) / (2 EJ)`` (eq. T9);
    * ``xi > b``: ``v = F [L^2 (3 xi - L) / (6 EJ) + L / GA]``, ``phi = F L (xi - L/2) / EJ``.
    """
    xi = np.asarray(xi, dtype=float)
    a, b = L * (1 - 1 / np.sqrt(3)) / 2, L * (1 + 1 / np.sqrt(3)) / 2
    on_mid = _step(xi - a, L) - _step(xi - b, L)
    on_tip = _step(xi - b, L)
    flex = (on_mid * F * L * b * (xi - a) / (2 * EJ)
            + on_tip * F * L**2 * (3 * xi - L) / (6 * EJ))
    shear = on_mid * F * L / (2 * GA) + on_tip * F * L / GA
    phi = on_mid * F * L * (xi - a) / (2 * EJ) + on_tip * F * L * (xi - L / 2) / EJ
    return flex, shear, phi


def cantilever_internal_forces(zeta, xi: float, F: float = 1.0):
    """Exact shear and bending moment at ``zeta`` for a force at ``xi`` (paper Sec. 5.1)."""
    zeta = np.asarray(zeta, dtype=float)
    return F * _step(xi - zeta), F * np.maximum(xi - zeta, 0.0)


def quarter_circle_tip(R: float, P: float, GJ: float, EJ_radial: float, GA_normal: float):
    """Out-of-plane tip deflection of a quarter-circle cantilever under a tip force ``P``.

    Castigliano on the statically determinate arc (angle alpha from the clamp): torque
    ``P R (1 - sin alpha)``, bending about the radial axis ``P R cos alpha``, shear ``P``::

        delta = P R^3 [(3 pi / 4 - 2) / GJ + (pi / 4) / EJ_radial] + P R pi / (2 GA_normal)
    """
    return (P * R**3 * ((3 * np.pi / 4 - 2) / GJ + (np.pi / 4) / EJ_radial)
            + P * R * np.pi / (2 * GA_normal))


def timoshenko_cantilever_determinant(omega: float, L: float = 1.0, EJ: float = 1.0,
                                      GA: float = 1.0, m: float = 1.0,
                                      rhoJ: float = 0.0) -> float:
    """Characteristic function of a clamped-free Timoshenko beam; its roots in ``omega`` are
    the exact natural frequencies (rad/s) of planar bending.

    Free vibration ``w(s) e^{i omega t}``, ``phi(s) e^{i omega t}`` (transverse displacement,
    section rotation) obeys (Timoshenko 1921; e.g. Han, Benaroya and Wei, J. Sound Vib. 225
    (1999) 935, eqs. 43-44)::

        GA (w'' - phi') + m omega^2 w = 0
        EJ phi'' + GA (w' - phi) + rhoJ omega^2 phi = 0

    a linear system ``y' = A y`` in ``y = (w, phi, w', phi')``.  Clamped at 0 (``w = phi = 0``)
    the solution is ``y(s) = expm(A s) [0, 0, a, b]``; free at ``L`` the shear
    ``GA (w' - phi)`` and the moment ``EJ phi'`` vanish.  The determinant of that 2x2 system in
    ``(a, b)`` is the frequency equation (equivalent to Huang's closed form, J. Appl. Mech. 28
    (1961) 579), scaled here by ``1 / (GA EJ)``.  Its Euler-Bernoulli limit (``GA -> inf``,
    ``rhoJ = 0``) has the roots ``omega = (beta L)^2 sqrt(EJ / (m L^4))``,
    ``beta L = 1.8751, 4.6941, 7.8548``.
    """
    A = np.array([[0.0, 0.0, 1.0, 0.0],
                  [0.0, 0.0, 0.0, 1.0],
                  [-m * omega**2 / GA, 0.0, 0.0, 1.0],
                  [0.0, (GA - rhoJ * omega**2) / EJ, -GA / EJ, 0.0]])
    Y = scipy.linalg.expm(A * L)
    free = np.array([[0.0, -1.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]]) @ Y[:, 2:]
    return float(np.linalg.det(free))


def timoshenko_cantilever_frequencies(n: int, L: float = 1.0, EJ: float = 1.0, GA: float = 1.0,
                                      m: float = 1.0, rhoJ: float = 0.0) -> np.ndarray:
    """The ``n`` lowest roots of :func:`timoshenko_cantilever_determinant` (rad/s): sign
    changes on a grid 1/200 of the first Euler-Bernoulli frequency apart (the Timoshenko roots
    lie below the Euler-Bernoulli ones, spaced wider than that), refined by ``brentq`` to
    ``rtol`` 1e-14."""
    step = 3.5160 * np.sqrt(EJ / (m * L**4)) / 200
    roots: list[float] = []
    a = step
    fa = timoshenko_cantilever_determinant(a, L, EJ, GA, m, rhoJ)
    while len(roots) < n:
        b = a + step
        fb = timoshenko_cantilever_determinant(b, L, EJ, GA, m, rhoJ)
        if fa * fb < 0:
            roots.append(scipy.optimize.brentq(timoshenko_cantilever_determinant, a, b,
                                               args=(L, EJ, GA, m, rhoJ), rtol=1e-14))
        a, fa = b, fb
    return np.array(roots)
