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
from numpy.typing import ArrayLike

from fvbeam.pointwise import TIE

#: The tip response of a cantilever: flexural and shear parts of the displacement, rotation.
Tip = tuple[np.ndarray, np.ndarray, np.ndarray]


def _step(x: np.ndarray, L: float = 1.0) -> np.ndarray:
    """Heaviside step, 1/2 within the library's tie band (``pointwise.TIE`` element lengths)."""
    tie = np.abs(x) <= TIE * L
    return np.where(tie, 0.5, np.where(x > 0, 1.0, 0.0))


def cantilever_exact(
    xi: ArrayLike, L: float = 1.0, EJ: float = 1.0, GA: float = 1.0, F: float = 1.0
) -> Tip:
    """Timoshenko cantilever, force at ``xi`` (paper Sec. 5.1).

    At the tip, ``F L^3 / (3 EJ)``, ``F L / GA`` and ``F L^2 / (2 EJ)``:

    >>> print(*cantilever_exact(1.0))
    0.3333333333333333 1.0 0.5
    """
    xi = np.asarray(xi, dtype=float)
    return F * xi**2 * (3 * L - xi) / (6 * EJ), F * xi / GA, F * xi**2 / (2 * EJ)


def cantilever_fv2(
    xi: ArrayLike, L: float = 1.0, EJ: float = 1.0, GA: float = 1.0, F: float = 1.0
) -> Tip:
    """One 2-node finite-volume element (paper Sec. 5.2).

    At the tip, ``F L^3 / (4 EJ)``: the element bends only beyond its evaluation point
    ``L / 2``; the shear part and the rotation are exact:

    >>> print(*cantilever_fv2(1.0))
    0.25 1.0 0.5
    """
    xi = np.asarray(xi, dtype=float)
    step = _step(xi - L / 2, L)
    return (
        F * L**2 / (2 * EJ) * (xi - L / 2) * step,
        F * L / GA * step,
        F * L / EJ * np.maximum(xi - L / 2, 0.0),
    )


def cantilever_fv3(
    xi: ArrayLike, L: float = 1.0, EJ: float = 1.0, GA: float = 1.0, F: float = 1.0
) -> Tip:
    """One 3-node finite-volume element (paper Sec. 5.3; ``docs/theory.md`` for a < xi < b).

    With the evaluation points ``a, b = L (1 -+ 1/sqrt(3)) / 2``:

    * ``xi < a``: the load is on the clamped node, nothing moves;
    * ``a < xi < b``: ``v = F [L b (xi - a) / (2 EJ) + L / (2 GA)]``,
      ``phi = F L (xi - a) / (2 EJ)`` (eq. T9);
    * ``xi > b``: ``v = F [L^2 (3 xi - L) / (6 EJ) + L / GA]``, ``phi = F L (xi - L/2) / EJ``.

    At the tip, the exact response (:func:`cantilever_exact`):

    >>> print(*cantilever_fv3(1.0))
    0.3333333333333333 1.0 0.5
    """
    xi = np.asarray(xi, dtype=float)
    a, b = L * (1 - 1 / np.sqrt(3)) / 2, L * (1 + 1 / np.sqrt(3)) / 2
    on_mid = _step(xi - a, L) - _step(xi - b, L)
    on_tip = _step(xi - b, L)
    flex = on_mid * F * L * b * (xi - a) / (2 * EJ) + on_tip * F * L**2 * (3 * xi - L) / (6 * EJ)
    shear = on_mid * F * L / (2 * GA) + on_tip * F * L / GA
    phi = on_mid * F * L * (xi - a) / (2 * EJ) + on_tip * F * L * (xi - L / 2) / EJ
    return flex, shear, phi


def cantilever_end_loads(
    s: ArrayLike,
    L: float = 1.0,
    EJ: float = 1.0,
    GA: float = 1.0,
    F: float = 1.0,
    C: float = 0.0,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Deflection, rotation, shear force and bending moment at ``s`` of a Timoshenko
    cantilever clamped at 0 under a tip force ``F`` and a tip couple ``C`` in one bending
    plane (rotation positive from the beam's axis towards the deflection).

    The shear ``S = F`` and the moment ``M = F (L - s) + C`` are statically determinate; the
    rotation integrates ``M / EJ`` from the clamp and the deflection ``theta + S / GA``::

        theta = F (2 L s - s^2) / (2 EJ) + C s / EJ
        v     = F s^2 (3 L - s) / (6 EJ) + F s / GA + C s^2 / (2 EJ)

    At the tip with ``C = 0``, :func:`cantilever_exact` at ``xi = L``:

    >>> v, theta, S, M = cantilever_end_loads(1.0)
    >>> print(v, theta, S, M)
    1.3333333333333333 0.5 1.0 0.0
    """
    s = np.asarray(s, dtype=float)
    theta = F * (2 * L * s - s**2) / (2 * EJ) + C * s / EJ
    v = F * s**2 * (3 * L - s) / (6 * EJ) + F * s / GA + C * s**2 / (2 * EJ)
    return v, theta, np.full(s.shape, float(F)), F * (L - s) + C


def cantilever_internal_forces(
    zeta: ArrayLike, xi: float, F: float = 1.0
) -> tuple[np.ndarray, np.ndarray]:
    """Exact shear and bending moment at ``zeta`` for a force at ``xi`` (paper Sec. 5.1)."""
    zeta = np.asarray(zeta, dtype=float)
    return F * _step(xi - zeta), F * np.maximum(xi - zeta, 0.0)


def quarter_circle_tip(R: float, P: float, GJ: float, EJ_radial: float, GA_normal: float) -> float:
    """Out-of-plane tip deflection of a quarter-circle cantilever under a tip force ``P``.

    Castigliano on the statically determinate arc (angle alpha from the clamp): torque
    ``P R (1 - sin alpha)``, bending about the radial axis ``P R cos alpha``, shear ``P``::

        delta = P R^3 [(3 pi / 4 - 2) / GJ + (pi / 4) / EJ_radial] + P R pi / (2 GA_normal)
    """
    return P * R**3 * ((3 * np.pi / 4 - 2) / GJ + (np.pi / 4) / EJ_radial) + P * R * np.pi / (
        2 * GA_normal
    )


def timoshenko_cantilever_determinant(
    omega: float,
    L: float = 1.0,
    EJ: float = 1.0,
    GA: float = 1.0,
    m: float = 1.0,
    rhoJ: float = 0.0,
) -> float:
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
    A = np.array(
        [
            [0.0, 0.0, 1.0, 0.0],
            [0.0, 0.0, 0.0, 1.0],
            [-m * omega**2 / GA, 0.0, 0.0, 1.0],
            [0.0, (GA - rhoJ * omega**2) / EJ, -GA / EJ, 0.0],
        ]
    )
    Y = scipy.linalg.expm(A * L)
    free = np.array([[0.0, -1.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]]) @ Y[:, 2:]
    return float(np.linalg.det(free))


def timoshenko_cantilever_frequencies(
    n: int, L: float = 1.0, EJ: float = 1.0, GA: float = 1.0, m: float = 1.0, rhoJ: float = 0.0
) -> np.ndarray:
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
            roots.append(
                scipy.optimize.brentq(
                    timoshenko_cantilever_determinant, a, b, args=(L, EJ, GA, m, rhoJ), rtol=1e-14
                )
            )
        a, fa = b, fb
    return np.array(roots)


def simply_supported_point_load(
    x: ArrayLike, a: ArrayLike, L: float = 1.0, EJ: float = 1.0, GA: float = np.inf, F: float = 1.0
) -> np.ndarray:
    """Static deflection of a simply supported Timoshenko beam under a force ``F`` at ``a``.

    Bending (e.g. Timoshenko and Gere, *Mechanics of Materials*, App. G) plus the shear
    deflection of the piecewise-constant shear force ``F b / L`` (``x < a``), with
    ``b = L - a``; for ``x > a`` the mirror image ``x -> L - x``, ``a -> L - a``::

        w(x) = F b x (L^2 - b^2 - x^2) / (6 EJ L) + F b x / (GA L),    0 <= x <= a

    At mid-span under a mid-span force, ``F L^3 / (48 EJ) + F L / (4 GA) = 1/48 + 1/4``:

    >>> print(f"{simply_supported_point_load(0.5, 0.5, GA=1.0):.10f}")
    0.2708333333
    """
    x, a = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(a, dtype=float))
    left = x <= a
    xx, bb = np.where(left, x, L - x), np.where(left, L - a, a)
    return F * bb * xx * ((L**2 - bb**2 - xx**2) / (6 * EJ * L) + 1 / (GA * L))


def _moving_load_modes(
    j: np.ndarray, L: float, EJ: float, GA: float, m: float, c: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Wavenumbers ``k_j``, modal stiffness per length ``kappa_j`` and ``r_j = Omega_j /
    omega_j`` of a simply supported Timoshenko beam without rotary inertia."""
    k = j * np.pi / L
    kappa = 1.0 / (1.0 / (EJ * k**4) + 1.0 / (GA * k**2))
    return k, kappa, k * c * np.sqrt(m / kappa)


def _power_tail(N: float, p: int, L: float) -> float:
    """``sum_{j > N} k_j^-p <= (L / pi)^p N^(1-p) / (p - 1)`` (``k_j = j pi / L``)."""
    return (L / np.pi) ** p * N ** (1 - p) / (p - 1)


def moving_load_truncation(
    n_modes: int, L: float, EJ: float, GA: float, m: float, F: float, c: float
) -> float:
    """Bound on ``|w - w_N|`` of :func:`moving_load_simply_supported` kept to ``N = n_modes``
    terms of its remainder series, for every ``x`` and ``0 <= t <= L / c``
    (``docs/dynamics.md``, "Moving load").  With ``D_j = kappa_j (1 - r_j^2)``,
    ``G' = GA - m c^2`` and ``r_j`` decreasing in ``j``, the terms beyond ``N`` obey::

        |R_j| = GA^2 / ((GA + EJ k^2) G' D_j)
              <= GA / (G' (1 - r^2)) min(1, GA / (EJ k^2)) (1 / (EJ k^4) + 1 / (GA k^2))
        r_j / |D_j| <= r / (1 - r^2) (1 / (EJ k^4) + 1 / (GA k^2)),     r = r_{N+1}

    summed with :func:`_power_tail` and times ``2 F / L``.  ``inf`` when ``r_{N+1} >= 1``.
    """
    r = float(_moving_load_modes(np.array(n_modes + 1.0), L, EJ, GA, m, c)[2])
    if r >= 1:
        return np.inf
    N = float(n_modes)
    tail = {p: _power_tail(N, p, L) for p in (2, 4, 6)}
    inverse_kappa = tail[4] / EJ + tail[2] / GA
    quasi_static = min(inverse_kappa, GA * tail[6] / EJ**2 + tail[4] / EJ) / (1 - m * c**2 / GA)
    return 2 * F / L * (quasi_static + r * inverse_kappa) / (1 - r * r)


def moving_load_n_modes(
    tol: float, L: float, EJ: float, GA: float, m: float, F: float, c: float
) -> int:
    """The fewest modes whose :func:`moving_load_truncation` bound is at most ``tol``."""
    if not (tol > 0 and np.sqrt(m / GA) * c < 1):
        raise ValueError(
            f"need tol > 0 and a speed c = {c:g} below the shear wave speed "
            f"sqrt(GA / m) = {np.sqrt(GA / m):g}, got tol = {tol:g}"
        )
    low, high = 0, 1
    while moving_load_truncation(high, L, EJ, GA, m, F, c) > tol:
        low, high = high, 2 * high
    while high - low > 1:
        middle = (low + high) // 2
        if moving_load_truncation(middle, L, EJ, GA, m, F, c) > tol:
            low = middle
        else:
            high = middle
    return high


def moving_load_simply_supported(
    x: ArrayLike,
    t: ArrayLike,
    L: float = 1.0,
    EJ: float = 1.0,
    GA: float = np.inf,
    m: float = 1.0,
    F: float = 1.0,
    c: float = 1.0,
    n_modes: int | None = None,
    rtol: float = 1e-8,
) -> np.ndarray:
    """Deflection ``w(x, t)`` of a simply supported beam crossed by a constant force ``F`` at
    speed ``c``, entering at ``x = 0`` at ``t = 0`` on the beam at rest.

    Fryba, *Vibration of Solids and Structures under Moving Loads*, 3rd ed. (1999), Ch. 1
    (the series solution for a constant force, undamped), extended to a Timoshenko beam
    without rotary inertia
    (``docs/dynamics.md``, "Moving load"): the modes stay ``sin(k_j x)``, ``k_j = j pi / L``,
    with modal mass ``m L / 2`` and modal stiffness ``kappa_j L / 2``,
    ``kappa_j = EJ k_j^4 / (1 + EJ k_j^2 / GA)``::

        w = sum_j q_j(t) sin(k_j x),
        q_j = 2 F / (L m) [sin(Omega_j t) - r_j sin(omega_j t)] / (omega_j^2 - Omega_j^2),
        omega_j^2 = kappa_j / m,   Omega_j = k_j c,   r_j = Omega_j / omega_j

    (at resonance, ``r_j = 1``, its limit ``2 F / (L m) (sin w t - w t cos w t) / (2 w^2)``).
    The quasi-static terms decay only like ``j^-2`` (shear); their leading part
    ``2 F sin(k_j c t) / (L G' k_j^2)``, ``G' = GA - m c^2``, is summed in closed form,
    ``F min(x, a) (L - max(x, a)) / (L G')`` with ``a = c t`` (the string's Green function),
    and the series sums the rest.  Valid while the load is on the beam, ``0 <= t <= L / c``,
    for ``c`` below the shear wave speed ``sqrt(GA / m)``.

    Parameters
    ----------
    x, t
        Abscissae and times, broadcast together.
    n_modes
        Terms kept; by default the fewest whose :func:`moving_load_truncation` bound is at most
        ``rtol`` times the static mid-span deflection ``F L^3 / (48 EJ) + F L / (4 GA)``.
    """
    if not all(np.isfinite(v) and v > 0 for v in (L, EJ, m, c)) or not GA > m * c**2:
        raise ValueError(
            f"need finite L, EJ, m, c > 0 and GA > m c^2, got L = {L}, EJ = {EJ}, "
            f"GA = {GA}, m = {m}, c = {c}"
        )
    x, t = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(t, dtype=float))
    if np.any(t < 0) or np.any(t > L / c * (1 + 1e-12)) or np.any((x < 0) | (x > L)):
        raise ValueError(
            f"need 0 <= x <= L = {L:g} and 0 <= t <= L / c = {L / c:g} (the load on the beam)"
        )
    if n_modes is None:
        n_modes = moving_load_n_modes(
            rtol * (F * L**3 / (48 * EJ) + F * L / (4 * GA)), L, EJ, GA, m, F, c
        )
    G = GA - m * c**2
    a = np.minimum(c * t, L)
    w = F / G * np.minimum(x, a) * (L - np.maximum(x, a)) / L
    chunk = max(1, 2_000_000 // max(x.size, 1))
    for start in range(1, n_modes + 1, chunk):
        j = np.arange(start, min(start + chunk, n_modes + 1), dtype=float)
        k, kappa, r = _moving_load_modes(j, L, EJ, GA, m, c)
        omega, D = np.sqrt(kappa / m), kappa - m * (k * c) ** 2
        wt, ka = np.multiply.outer(t, omega), np.multiply.outer(a, k)
        near = np.abs(1 - r) < 1e-8
        with np.errstate(divide="ignore", invalid="ignore"):
            remainder = 1 / ((1 + EJ * k**2 / GA) * (1 - m * c**2 / GA) * D)
            q = np.where(
                near,
                (np.sin(wt) - wt * np.cos(wt)) / (2 * kappa) - np.sin(ka) / (G * k**2),
                np.sin(ka) * remainder - r * np.sin(wt) / D,
            )
        w += 2 * F / L * np.einsum("...j,...j->...", q, np.sin(np.multiply.outer(x, k)))
    return w
