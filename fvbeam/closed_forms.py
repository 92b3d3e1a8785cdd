"""Closed-form answers used as oracles by the tests and the studies.

Cantilever of length ``L`` clamped at 0, transverse force ``F`` at station ``xi`` (paper
Sec. 5).  Every function returns ``(v_flexural, v_shear, phi)`` at the tip ``L``; the tip
displacement is ``v_flexural + v_shear``.  Where a finite-volume load sits exactly on an
evaluation point it is shared half and half between the two regions, as
:func:`fvbeam.elements.indicator` does.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

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


def timoshenko_transfer(
    omega: float,
    s: float,
    EJ: float = 1.0,
    GA: float = 1.0,
    m: float = 1.0,
    rhoJ: float = 0.0,
    axial: AxialForce | None = None,
) -> np.ndarray:
    """The transfer matrix ``expm(A s)`` (4, 4) of a Timoshenko beam in free vibration at
    ``omega`` over a length ``s``: ``y(s) = expm(A s) y(0)``, ``y = (w, phi, w', phi')``;
    with ``axial`` about the straight state under that axial force.

    Free vibration ``w(s) e^{i omega t}``, ``phi(s) e^{i omega t}`` (transverse displacement,
    section rotation) obeys (Timoshenko 1921; e.g. Han, Benaroya and Wei, J. Sound Vib. 225
    (1999) 935, eqs. 43-44)::

        GA (w'' - phi') + m omega^2 w = 0
        EJ phi'' + GA (w' - phi) + rhoJ omega^2 phi = 0

    a linear system ``y' = A y``.  The shear force is ``GA (w' - phi)``, the moment
    ``EJ phi'``.

    **Under an axial force**, the geometrically exact (Simo-Reissner) beam linearised about
    its straight state of axial strain ``e = -P / EA``
    (:func:`timoshenko_simply_supported_frequencies`), with ``a = 1 + e`` and ``g = a GA +
    P``, the equations are ::

        GA w'' - g phi' + m omega^2 w = 0
        EJ phi'' + g (w' - a phi) + rhoJ omega^2 phi = 0

    whose transverse force is ``GA w' - g phi`` (the spatial force's component normal to
    the undeformed axis) and moment ``EJ phi'``; ``P = 0`` gives Timoshenko's."""
    a, g = _preload(GA, axial)
    A = np.array(
        [
            [0.0, 0.0, 1.0, 0.0],
            [0.0, 0.0, 0.0, 1.0],
            [-m * omega**2 / GA, 0.0, 0.0, g / GA],
            [0.0, (a * g - rhoJ * omega**2) / EJ, -g / EJ, 0.0],
        ]
    )
    return scipy.linalg.expm(A * s)


@dataclass(frozen=True)
class AxialForce:
    """An axial force ``P`` (compressive; negative in tension) on a beam of axial stiffness
    ``EA`` (infinite: inextensible)."""

    P: float
    EA: float = np.inf


def _preload(GA: float, axial: AxialForce | None) -> tuple[float, float]:
    """``a = 1 - P / EA`` and ``g = a GA + P`` of a beam under ``axial``
    (:func:`timoshenko_transfer`; ``1, GA`` without)."""
    if axial is None:
        return 1.0, GA
    a = 1.0 - axial.P / axial.EA
    return a, a * GA + axial.P


def _free(GA: float, axial: AxialForce | None = None) -> np.ndarray:
    """Rows of ``y = (w, phi, w', phi')`` that vanish at a free end (under a dead
    ``axial`` force): the transverse force ``GA w' - g phi`` and the moment ``phi'`` (scaled
    by ``1 / GA`` and ``1 / EJ``; :func:`timoshenko_transfer`)."""
    _, g = _preload(GA, axial)
    return np.array([[0.0, -g / GA, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]])


def timoshenko_cantilever_determinant(
    omega: float,
    L: float = 1.0,
    EJ: float = 1.0,
    GA: float = 1.0,
    m: float = 1.0,
    rhoJ: float = 0.0,
    axial: AxialForce | None = None,
    tip_mass: float = 0.0,
    tip_inertia: float = 0.0,
) -> float:
    """Characteristic function of a clamped-free Timoshenko beam; its roots in ``omega`` are
    the exact natural frequencies (rad/s) of planar bending; with ``axial``, under that dead
    axial tip force (:func:`timoshenko_transfer`); with a ``tip_mass`` (its centre at the
    tip) of rotary inertia ``tip_inertia`` about the tip, whose inertia the end's transverse
    force and moment then carry: ``GA w' - g phi = tip_mass omega^2 w`` and ``EJ phi' =
    tip_inertia omega^2 phi`` (Laura, Pombo and Susemihl, J. Sound Vib. 37 (1974) 161, in
    its Euler-Bernoulli limit ``1 + cos b cosh b + (tip_mass / (m L)) b (cos b sinh b - sin b
    cosh b) = 0`` without ``tip_inertia``, ``b = beta L``).

    Clamped at 0 (``w = phi = 0``) the solution is ``y(s) =`` :func:`timoshenko_transfer`
    ``[0, 0, a, b]``; free at ``L`` the transverse force and the moment ``EJ phi'``
    vanish (a dead force keeps its direction, so its transverse component stays zero).  The
    determinant of that 2x2 system in ``(a, b)`` is the frequency equation
    (equivalent to Huang's closed form, J. Appl. Mech. 28 (1961) 579), scaled here by
    ``1 / (GA EJ)``.  Its Euler-Bernoulli limit (``GA -> inf``, ``rhoJ = 0``) has the roots
    ``omega = (beta L)^2 sqrt(EJ / (m L^4))``, ``beta L = 1.8751, 4.6941, 7.8548``.
    """
    Y = timoshenko_transfer(omega, L, EJ, GA, m, rhoJ, axial)
    end = _free(GA, axial)
    end[0, 0] -= tip_mass * omega**2 / GA
    end[1, 1] -= tip_inertia * omega**2 / EJ
    return float(np.linalg.det(end @ Y[:, 2:]))


def timoshenko_pinned_cantilever_determinant(
    omega: float,
    a: float,
    L: float = 1.0,
    EJ: float = 1.0,
    GA: float = 1.0,
    m: float = 1.0,
    rhoJ: float = 0.0,
) -> float:
    """Characteristic function of a Timoshenko beam clamped at 0, pinned at ``0 < a < L``
    (``w(a) = 0``, rotation free) and free at ``L``.

    From ``y(0) = [0, 0, c, d]``, ``y(a^-) =`` :func:`timoshenko_transfer` ``(a) y(0)``; the
    pin's reaction ``R`` makes the shear jump, rotation and moment continuous:
    ``y(a^+) = y(a^-) + [0, 0, R / GA, 0]``; then ``w(a) = 0`` and the free end's two
    conditions at ``L`` are three equations in ``(c, d, R / GA)``, whose determinant this
    is."""
    Ya = timoshenko_transfer(omega, a, EJ, GA, m, rhoJ)
    Yb = timoshenko_transfer(omega, L - a, EJ, GA, m, rhoJ)
    rows = np.zeros((3, 3))
    rows[0, :2] = Ya[0, 2:]
    free = _free(GA)
    rows[1:, :2] = free @ Yb @ Ya[:, 2:]
    rows[1:, 2] = free @ Yb[:, 2]
    return float(np.linalg.det(rows))


def frequency_roots(
    determinant: Callable[..., float], n: int, step: float, args: tuple = ()
) -> np.ndarray:
    """The ``n`` lowest positive roots of ``determinant(omega, *args)``: sign changes on a grid
    ``step`` apart (which must be finer than the roots' spacing), refined by ``brentq`` to
    ``rtol`` 1e-14."""
    roots: list[float] = []
    a = step
    fa = determinant(a, *args)
    while len(roots) < n:
        b = a + step
        fb = determinant(b, *args)
        if fa * fb < 0:
            roots.append(scipy.optimize.brentq(determinant, a, b, args=args, rtol=1e-14))
        a, fa = b, fb
    return np.array(roots)


def timoshenko_cantilever_frequencies(
    n: int, L: float = 1.0, EJ: float = 1.0, GA: float = 1.0, m: float = 1.0, rhoJ: float = 0.0
) -> np.ndarray:
    """The ``n`` lowest roots of :func:`timoshenko_cantilever_determinant` (rad/s), on a grid
    1/200 of the first Euler-Bernoulli frequency apart (the Timoshenko roots lie below the
    Euler-Bernoulli ones, spaced wider than that; :func:`frequency_roots`)."""
    step = 3.5160 * np.sqrt(EJ / (m * L**4)) / 200
    return frequency_roots(timoshenko_cantilever_determinant, n, step, (L, EJ, GA, m, rhoJ))


def timoshenko_simply_supported_frequencies(
    n: int,
    L: float = 1.0,
    EJ: float = 1.0,
    GA: float = 1.0,
    m: float = 1.0,
    rhoJ: float = 0.0,
    *,
    axial: AxialForce | None = None,
) -> np.ndarray:
    """The ``n`` lowest bending frequencies (rad/s) of a simply supported Timoshenko beam:
    mode ``j`` is ``sin(k x)``, ``k = j pi / L``, whose frequency is the lower root of
    Timoshenko's equation (Han, Benaroya and Wei, "Dynamics of transversely vibrating
    beams using four engineering theories", J. Sound Vib. 225 (1999) 935, simply
    supported)::

        (rhoJ m / GA) omega^4 - (m + (rhoJ + m EJ / GA) k^2) omega^2 + EJ k^4 = 0

    (without rotary inertia ``omega^2 = EJ k^4 / (m (1 + EJ k^2 / GA))``; Euler-Bernoulli
    ``omega = k^2 sqrt(EJ / m)`` as ``GA`` grows).

    **Under an axial force** (``axial``: ``P`` compressive, negative in tension) the
    geometrically exact beam about its straight state; ``NaN`` for a mode the force has
    buckled (``omega^2 <= 0``).  The Simo-Reissner beam (strains ``nu = Lambda^T x' -
    e_1``, ``kappa``; spatial forces ``n = Lambda C nu``, balances ``n' = m x''``, ``m' + x'
    x n = rhoJ phi''``) straight under ``P`` has the axial strain ``e = -P / EA``.  Bending
    in a plane, ``x' = (1 + e) e_1 + w' e_2`` and ``Lambda = exp(phi e_3)``, linearised: the
    shear strain is ``w' - a phi`` (``a = 1 + e``), the transverse spatial force ``GA (w' - a
    phi) - P phi`` and the moment balance's lever term ``(a GA + P) (w' - a phi)``: the
    equations of :func:`timoshenko_transfer`.  With ``w = W sin(k x)``, ``phi = Phi cos(k
    x)`` (hinged ends, no moment), ``(W, Phi)`` solve ::

        [ k^2 GA    -k g         ] [W]           [m   0   ] [W]
        [ -k g      EJ k^2 + a g ] [Phi] = omega^2 [0   rhoJ] [Phi],     g = a GA + P,

    whose determinant, divided by ``GA``, is ::

        (rhoJ m / GA) omega^4 - (k^2 rhoJ + m (EJ k^2 / GA + a (a + P / GA))) omega^2
            + k^2 (EJ k^2 - P (a + P / GA)) = 0,

    Timoshenko's equation at ``P = 0``.  With ``GA, EA -> inf`` and ``rhoJ = 0`` it is
    ``omega^2 = omega_0^2 (1 - P / P_E)``, ``P_E = EJ k^2`` Euler's load, exact for the
    Euler-Bernoulli column (Timoshenko and Gere, "Theory of Elastic Stability", 1961;
    Bokaian, J. Sound Vib. 126 (1989) 49).  With finite ``GA`` the frequency vanishes at
    ``EJ k^2 = P (a + P / GA)``, for ``EA -> inf`` Haringx's load ``P (1 + P / GA) = EJ
    k^2``, the buckling load of the Simo-Reissner beam (Haringx, Philips Res. Rep. 3 (1948)
    401; Atanackovic, "Stability Theory of Elastic Rods", 1997).

    Examples
    --------
    >>> w = timoshenko_simply_supported_frequencies(2, GA=1e12)
    >>> bool(np.allclose(w, [np.pi**2, 4 * np.pi**2]))
    True
    >>> half = AxialForce(np.pi**2 / 2, EA=1e12)  # half Euler's load
    >>> w = timoshenko_simply_supported_frequencies(1, GA=1e12, axial=half)
    >>> bool(np.allclose(w**2, np.pi**4 / 2))
    True
    """
    k = np.arange(1, n + 1) * np.pi / L
    P = 0.0 if axial is None else axial.P
    a = _preload(GA, axial)[0]
    g = a + P / GA  # g / GA
    A = rhoJ * m / GA
    B = k**2 * rhoJ + m * (EJ * k**2 / GA + a * g)
    C = k**2 * (EJ * k**2 - P * g)
    # the lower root of A w^4 - B w^2 + C, written without cancellation (A may be 0)
    omega2 = 2 * C / (B + np.sqrt(B * B - 4 * A * C))
    return np.sqrt(np.where(omega2 > 0, omega2, np.nan))


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
    terms of its remainder series, for every ``x`` and ``t >= 0`` (``docs/dynamics.md``,
    "Moving load").  With ``D_j = kappa_j (1 - r_j^2)``, ``G' = GA - m c^2`` and ``r_j``
    decreasing in ``j``, the terms beyond ``N`` obey::

        |R_j| = GA^2 / ((GA + EJ k^2) G' D_j)
              <= GA / (G' (1 - r^2)) min(1, GA / (EJ k^2)) (1 / (EJ k^4) + 1 / (GA k^2))
        r_j / |D_j| <= r / (1 - r^2) (1 / (EJ k^4) + 1 / (GA k^2)),     r = r_{N+1}

    While the load is on the beam (``t <= L / c``) a term is at most ``|R_j| + r_j / |D_j|``,
    in the free vibration after it at most ``2 r_j / |D_j|``
    (:func:`moving_load_modes`); the larger of the two sums, summed with
    :func:`_power_tail` and times ``2 F / L``.  ``inf`` when ``r_{N+1} >= 1``.
    """
    r = float(_moving_load_modes(np.array(n_modes + 1.0), L, EJ, GA, m, c)[2])
    if r >= 1:
        return np.inf
    N = float(n_modes)
    tail = {p: _power_tail(N, p, L) for p in (2, 4, 6)}
    inverse_kappa = tail[4] / EJ + tail[2] / GA
    quasi_static = min(inverse_kappa, GA * tail[6] / EJ**2 + tail[4] / EJ) / (1 - m * c**2 / GA)
    free = r * inverse_kappa
    return 2 * F / L * (free + max(quasi_static, free)) / (1 - r * r)


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


#: ``|1 - r_j|`` below which a mode is taken at resonance (its limit form).
_RESONANCE = 1e-8


def _check_moving_load(L: float, EJ: float, GA: float, m: float, c: float) -> None:
    if not all(np.isfinite(v) and v > 0 for v in (L, EJ, m, c)) or not GA > m * c**2:
        raise ValueError(
            f"need finite L, EJ, m, c > 0 and GA > m c^2, got L = {L}, EJ = {EJ}, "
            f"GA = {GA}, m = {m}, c = {c}"
        )


def _free_vibration(
    j: np.ndarray, t: np.ndarray, L: float, EJ: float, GA: float, m: float, F: float, c: float
) -> tuple[np.ndarray, np.ndarray]:
    """Modal coordinates and velocities, ``t.shape + j.shape``, after the crossing
    (``t >= L / c``): :func:`moving_load_modes`."""
    k, kappa, r = _moving_load_modes(j, L, EJ, GA, m, c)
    omega, D = np.sqrt(kappa / m), kappa - m * (k * c) ** 2
    T = L / c
    wt, ws = np.multiply.outer(t, omega), np.multiply.outer(t - T, omega)
    sign = np.where(j % 2, -1.0, 1.0)
    near = np.abs(1 - r) < _RESONANCE
    q_T = -F / (L * kappa) * j * np.pi * sign  # the resonant mode's deflection at L / c
    with np.errstate(divide="ignore", invalid="ignore"):
        q = np.where(near, q_T * np.cos(ws), 2 * F / L * r / D * (sign * np.sin(ws) - np.sin(wt)))
        v = np.where(
            near,
            -omega * q_T * np.sin(ws),
            2 * F / L * k * c / D * (sign * np.cos(ws) - np.cos(wt)),
        )
    return q, v


def moving_load_modes(
    j: ArrayLike,
    t: ArrayLike,
    L: float = 1.0,
    EJ: float = 1.0,
    GA: float = np.inf,
    m: float = 1.0,
    F: float = 1.0,
    c: float = 1.0,
) -> tuple[np.ndarray, np.ndarray]:
    """Modal coordinates ``q_j(t)`` and velocities ``q_j'(t)`` of
    ``w = sum_j q_j(t) sin(k_j x)`` (:func:`moving_load_simply_supported`), of shape
    ``t.shape + j.shape``, for every ``t >= 0``.

    With ``k_j = j pi / L``, ``Omega_j = k_j c``, ``omega_j^2 = kappa_j / m``,
    ``r_j = Omega_j / omega_j`` and ``D_j = kappa_j - m Omega_j^2``, the undamped mode
    ``m q'' + kappa q = (2 F / L) sin(Omega t)`` from rest is, while the load is on the beam
    (Fryba 1999, Ch. 1)::

        q_j = (2 F / L) [sin(Omega_j t) - r_j sin(omega_j t)] / D_j,      0 <= t <= T = L / c

    and after it leaves (``Omega_j T = j pi``), the free vibration from the state at ``T``::

        q_j = (2 F / L) (r_j / D_j) [(-1)^j sin(omega_j (t - T)) - sin(omega_j t)],   t >= T

    At resonance (``r_j = 1``) their limits,
    ``(F / (L kappa_j)) (sin w t - w t cos w t)`` and
    ``-(F / (L kappa_j)) j pi (-1)^j cos(w (t - T))``.
    """
    _check_moving_load(L, EJ, GA, m, c)
    j = np.asarray(j, dtype=float)
    t = np.asarray(t, dtype=float)
    if np.any(t < 0) or np.any(j < 1) or np.any(j != np.round(j)):
        raise ValueError("need times t >= 0 and mode numbers j = 1, 2, ...")
    k, kappa, r = _moving_load_modes(j, L, EJ, GA, m, c)
    omega, D = np.sqrt(kappa / m), kappa - m * (k * c) ** 2
    wt, Wt = np.multiply.outer(t, omega), np.multiply.outer(t, k * c)
    near = np.abs(1 - r) < _RESONANCE
    with np.errstate(divide="ignore", invalid="ignore"):
        q = np.where(
            near,
            F / (L * kappa) * (np.sin(wt) - wt * np.cos(wt)),
            2 * F / L * (np.sin(Wt) - r * np.sin(wt)) / D,
        )
        v = np.where(
            near,
            F / (L * m) * t[..., None] * np.sin(wt),
            2 * F / L * k * c * (np.cos(Wt) - np.cos(wt)) / D,
        )
    after = t > L / c
    if np.any(after):
        q[after], v[after] = _free_vibration(j, t[after], L, EJ, GA, m, F, c)
    return q, v


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
    speed ``c``, entering at ``x = 0`` at ``t = 0`` on the beam at rest, and its free
    vibration after the load leaves at ``x = L`` (``t > L / c``).

    Fryba, *Vibration of Solids and Structures under Moving Loads*, 3rd ed. (1999), Ch. 1
    (the series solution for a constant force, undamped), extended to a Timoshenko beam
    without rotary inertia
    (``docs/dynamics.md``, "Moving load"): the modes stay ``sin(k_j x)``, ``k_j = j pi / L``,
    with modal mass ``m L / 2`` and modal stiffness ``kappa_j L / 2``,
    ``kappa_j = EJ k_j^4 / (1 + EJ k_j^2 / GA)``, and ``w = sum_j q_j(t) sin(k_j x)`` with
    the modal coordinates of :func:`moving_load_modes`.

    While the load is on the beam the quasi-static terms decay only like ``j^-2`` (shear);
    their leading part ``2 F sin(k_j c t) / (L G' k_j^2)``, ``G' = GA - m c^2``, is summed in
    closed form, ``F min(x, a) (L - max(x, a)) / (L G')`` with ``a = c t`` (the string's
    Green function), and the series sums the rest.  After the crossing ``a = L`` and that part
    vanishes: the series is the free vibration alone.  Valid for ``c`` below the shear wave
    speed ``sqrt(GA / m)``.

    Parameters
    ----------
    x, t
        Abscissae and times ``t >= 0``, broadcast together.
    n_modes
        Terms kept; by default the fewest whose :func:`moving_load_truncation` bound is at most
        ``rtol`` times the static mid-span deflection ``F L^3 / (48 EJ) + F L / (4 GA)``.
    """
    _check_moving_load(L, EJ, GA, m, c)
    x, t = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(t, dtype=float))
    if np.any(t < 0) or np.any((x < 0) | (x > L)):
        raise ValueError(f"need 0 <= x <= L = {L:g} and times t >= 0")
    if n_modes is None:
        n_modes = moving_load_n_modes(
            rtol * (F * L**3 / (48 * EJ) + F * L / (4 * GA)), L, EJ, GA, m, F, c
        )
    G = GA - m * c**2
    T = L / c
    on = t <= T
    x_on, t_on, x_off, t_off = x[on], t[on], x[~on], t[~on]
    a = c * t_on
    w = np.zeros(x.shape)
    w_on = F / G * np.minimum(x_on, a) * (L - np.maximum(x_on, a)) / L
    w_off = np.zeros(x_off.shape)
    chunk = max(1, 2_000_000 // max(x.size, 1))
    for start in range(1, n_modes + 1, chunk):
        j = np.arange(start, min(start + chunk, n_modes + 1), dtype=float)
        k, kappa, r = _moving_load_modes(j, L, EJ, GA, m, c)
        omega, D = np.sqrt(kappa / m), kappa - m * (k * c) ** 2
        wt, ka = np.multiply.outer(t_on, omega), np.multiply.outer(a, k)
        near = np.abs(1 - r) < _RESONANCE
        with np.errstate(divide="ignore", invalid="ignore"):
            remainder = 1 / ((1 + EJ * k**2 / GA) * (1 - m * c**2 / GA) * D)
            q = np.where(
                near,
                (np.sin(wt) - wt * np.cos(wt)) / (2 * kappa) - np.sin(ka) / (G * k**2),
                np.sin(ka) * remainder - r * np.sin(wt) / D,
            )
        w_on += 2 * F / L * np.einsum("...j,...j->...", q, np.sin(np.multiply.outer(x_on, k)))
        if x_off.size:
            q_off, _ = _free_vibration(j, t_off, L, EJ, GA, m, F, c)
            w_off += np.einsum("...j,...j->...", q_off, np.sin(np.multiply.outer(x_off, k)))
    w[on], w[~on] = w_on, w_off
    return w
