"""Force laws of a landing gear: value and partial derivatives, vectorised over arrays.

Every law is a pure function of its state arguments (numpy arrays, broadcast together) and of
keyword parameters, and returns the force followed by its partial derivatives in the order of
the state arguments, for the Newton step that evaluates force elements (its Jacobian) and for
reference integrations.  Parameters are checked on every call (a few scalar tests), states must
be finite; bad input raises one ``ValueError`` naming the law and the offending item.

The laws and their sources (``docs/landing_gear.md`` gives every parameter of the gear):

* :func:`gas_spring`: polytropic air spring of an oleo-pneumatic strut (Milwitzky and Cook,
  NACA Report 1154, 1953; Currey, *Aircraft Landing Gear Design*, 1988);
* :func:`orifice_damper`: quadratic orifice damping with separate compression and rebound
  coefficients (NACA Report 1154: ``rho A_h^3 S'^2 / (2 C_d^2 A_n^2)``);
* :func:`end_stops`: penalty end stops of the stroke;
* :class:`Strut`: their sum, the strut law of issue 14;
* :func:`tyre_radial`: a unilateral spring-damper tyre that never pulls;
* :func:`slip_ratio`, :func:`friction_curve`, :func:`tyre_longitudinal`: longitudinal slip and
  Pacejka's Magic Formula without shift or curvature (Pacejka, *Tire and Vehicle Dynamics*);
* :func:`coulomb_friction`, :func:`stribeck_friction`: regularised dry friction.

Where a law has a kink (an end stop, the tyre leaving the ground or unloading), the derivative
returned is that of the branch holding at the point, the branch being chosen by the strict
inequality written in the law's docstring; at the kink itself this is one of the one-sided
derivatives, and the docstring says which.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from fvbeam.geometry import number
from sliders.forces import array_laws

#: Standard sea-level atmospheric pressure [Pa], the default back pressure of :func:`gas_spring`.
P_ATM = 101_325.0


def state(value: ArrayLike, law: str, name: str) -> np.ndarray:
    """``value`` as a float array of finite numbers, or ``ValueError`` naming ``law`` and
    ``name``."""
    try:
        x = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{law}: {name} must be finite numbers, got {value!r}") from None
    if not np.isfinite(x).all():
        bad = x[~np.isfinite(x)].ravel()[0]
        raise ValueError(f"{law}: {name} must be finite, got {bad}")
    return x


#: What a law returns: its value followed by its partial derivatives, one per state argument.
Law = tuple[np.ndarray, ...]


def broadcast(*arrays: np.ndarray) -> Law:
    """The arrays (each a law's own result, not an input) broadcast to one shape."""
    shapes = [np.shape(a) for a in arrays]
    if all(shape == shapes[0] for shape in shapes):
        return tuple(np.asarray(a, dtype=float) for a in arrays)
    shape = np.broadcast_shapes(*shapes)
    return tuple(np.array(np.broadcast_to(a, shape), dtype=float) for a in arrays)


def gas_spring(
    stroke: ArrayLike,
    *,
    area: float,
    pressure: float,
    volume: float,
    exponent: float,
    ambient: float = P_ATM,
) -> Law:
    """Polytropic gas spring: the force of a gas column compressed by a piston.

    .. math::

        F_{gas}(S) = A \\left[p_0 \\left(\\frac{V_0}{V_0 - A S}\\right)^n - p_{atm}\\right],
        \\qquad
        \\frac{dF_{gas}}{dS} = \\frac{n A^2 p_0}{V_0 - A S}
                              \\left(\\frac{V_0}{V_0 - A S}\\right)^n

    (Milwitzky and Cook, NACA Report 1154, eq. for the pneumatic force; ``p V^n`` constant).
    Compression ``S`` positive; ``S < 0`` (beyond full extension) expands the gas.

    Parameters
    ----------
    stroke : array_like
        ``S`` [m], below the gas column's length ``V0 / A``.
    area : float
        ``A`` [m^2], the pneumatic area.
    pressure : float
        ``p0`` [Pa], absolute gas pressure at ``S = 0``.
    volume : float
        ``V0`` [m^3], gas volume at ``S = 0``.
    exponent : float
        ``n``, the polytropic index (1 isothermal, 1.4 adiabatic).
    ambient : float
        ``p_atm`` [Pa], the pressure on the piston's other side.

    Returns
    -------
    force, d_stroke : ndarray
        ``F_gas`` [N] and ``dF_gas/dS`` [N/m].

    Raises
    ------
    ValueError
        A parameter not positive (``ambient`` may be 0), or a stroke that reaches ``V0 / A``
        (no gas volume left).

    Examples
    --------
    The preload at full extension is ``A (p0 - p_atm)``:

    >>> force, slope = gas_spring(0.0, area=1.6e-3, pressure=4.1e5, volume=2.8e-4, exponent=1.3)
    >>> round(float(force), 2)
    493.88
    """
    law = "gas spring"
    A = number(area, f"{law}: area", "> 0")
    p0 = number(pressure, f"{law}: pressure", "> 0")
    V0 = number(volume, f"{law}: volume", "> 0")
    n = number(exponent, f"{law}: exponent", "> 0")
    p_atm = number(ambient, f"{law}: ambient", ">= 0")
    S = state(stroke, law, "stroke")
    gas = V0 - A * S
    if np.any(gas <= 0):
        worst = float(np.max(S))
        raise ValueError(
            f"{law}: stroke {worst} m leaves no gas (it must stay below the gas column's length "
            f"V0 / A = {V0 / A} m)"
        )
    return broadcast(*array_laws.gas_spring(S, A, p0, V0, n, p_atm))


def gas_spring_energy(
    stroke: ArrayLike,
    *,
    area: float,
    pressure: float,
    volume: float,
    exponent: float,
    ambient: float = P_ATM,
) -> np.ndarray:
    """The work done on the gas spring from ``S = 0`` to ``S`` (its potential energy), the
    integral of :func:`gas_spring`'s force:

    .. math::

        E_{gas}(S) = \\int_0^S F_{gas}\\,dS
                   = \\frac{p_0 V_0^n}{n - 1}\\left[(V_0 - A S)^{1-n} - V_0^{1-n}\\right]
                     - p_{atm} A S \\qquad (n \\ne 1),

    and ``p0 V0 ln(V0 / (V0 - A S)) - p_atm A S`` for ``n = 1``, evaluated as
    ``p0 V0 expm1((n - 1) L) / (n - 1)`` with ``L = -log1p(-A S / V0)`` so that small strokes
    lose no digits to cancellation.  Same parameters and errors as :func:`gas_spring`; returns
    the energy [J].
    """
    # gas_spring checks every input and the gas volume; its force is not needed here.
    gas_spring(stroke, area=area, pressure=pressure, volume=volume, exponent=exponent)
    A, p0, V0, n = float(area), float(pressure), float(volume), float(exponent)
    S = np.asarray(stroke, dtype=float)
    # -log(1 - A S / V0) and (1 - A S / V0)^(1-n) - 1 without the cancellation at small S
    log_ratio = -np.log1p(-A * S / V0)
    if n == 1.0:
        return p0 * V0 * log_ratio - float(ambient) * A * S
    return p0 * V0 / (n - 1.0) * np.expm1((n - 1.0) * log_ratio) - float(ambient) * A * S


def orifice_damper(rate: ArrayLike, *, compression: float, rebound: float) -> Law:
    """Quadratic orifice damper with separate compression and rebound coefficients.

    .. math::

        F_d(\\dot S) = c(\\dot S)\\,\\dot S\\,|\\dot S|, \\qquad
        c = c_{comp}\\ (\\dot S > 0), \\quad c_{reb}\\ (\\dot S \\le 0), \\qquad
        \\frac{dF_d}{d\\dot S} = 2\\,c(\\dot S)\\,|\\dot S|

    (NACA Report 1154: the orifice force ``rho A_h^3 S'^2 / (2 C_d^2 A_n^2)``, opposing the
    flow).  The force and its derivative are continuous at ``S' = 0`` (both vanish there), so
    the coefficient's switch leaves the law once continuously differentiable.

    Parameters
    ----------
    rate : array_like
        ``S'`` [m/s], the stroke rate, positive in compression.
    compression, rebound : float
        ``c_comp``, ``c_reb`` [N s^2/m^2], both ``>= 0``.

    Returns
    -------
    force, d_rate : ndarray
        ``F_d`` [N] (compression positive) and ``dF_d/dS'`` [N s/m].
    """
    law = "orifice damper"
    c_comp = number(compression, f"{law}: compression", ">= 0")
    c_reb = number(rebound, f"{law}: rebound", ">= 0")
    v = state(rate, law, "rate")
    return broadcast(*array_laws.orifice_damper(v, c_comp, c_reb))


def _stop_bounds(law: str, stiffness: float, lower: float, upper: float) -> tuple[float, ...]:
    k = number(stiffness, f"{law}: stiffness", "> 0")
    low = number(lower, f"{law}: lower")
    high = number(upper, f"{law}: upper")
    if not low < high:
        raise ValueError(f"{law}: lower ({low}) must be below upper ({high})")
    return k, low, high


def end_stops(stroke: ArrayLike, *, stiffness: float, lower: float, upper: float) -> Law:
    """Penalty end stops of a stroke.

    .. math::

        F_{stop}(S) = \\begin{cases} k (S - S_{min}) & S < S_{min} \\\\
                                     0 & S_{min} \\le S \\le S_{max} \\\\
                                     k (S - S_{max}) & S > S_{max} \\end{cases}

    Compression positive: beyond the extension stop the force is negative (it pulls the strut
    back in), beyond the bottoming stop positive.  The derivative is ``k`` on the stops and 0
    between; at ``S = S_min`` or ``S_max`` exactly it is 0, the one-sided derivative from the
    free range.

    Parameters
    ----------
    stroke : array_like
        ``S`` [m].
    stiffness : float
        ``k`` [N/m], ``> 0``.
    lower, upper : float
        ``S_min < S_max`` [m].

    Returns
    -------
    force, d_stroke : ndarray
        ``F_stop`` [N] and ``dF_stop/dS`` [N/m].
    """
    law = "end stops"
    k, low, high = _stop_bounds(law, stiffness, lower, upper)
    S = state(stroke, law, "stroke")
    return broadcast(*array_laws.end_stops(S, k, low, high))


def end_stops_energy(
    stroke: ArrayLike, *, stiffness: float, lower: float, upper: float
) -> np.ndarray:
    """The penalty stops' potential energy, ``k (S - S_min)^2 / 2`` below ``S_min``,
    ``k (S - S_max)^2 / 2`` above ``S_max``, 0 between (the integral of :func:`end_stops`'s
    force from the free range); same parameters and errors."""
    force, _ = end_stops(stroke, stiffness=stiffness, lower=lower, upper=upper)
    return 0.5 * force * force / float(stiffness)


@dataclass(frozen=True)
class Strut:
    """The oleo-pneumatic strut of issue 14: gas spring, orifice damper and end stops.

    .. math::

        F_s(S, \\dot S) = A\\left[p_0 \\left(\\frac{V_0}{V_0 - A S}\\right)^n - p_{atm}\\right]
                         + c(\\dot S)\\,\\dot S\\,|\\dot S| + F_{stop}(S)

    with :func:`gas_spring`, :func:`orifice_damper` and :func:`end_stops` (``S_min = 0``, the
    full extension, by default).  Compression positive: the force pushes the two parts apart.
    Calling it returns ``(F_s, dF_s/dS, dF_s/dS')``; :meth:`energy` the stored energy.
    """

    area: float
    pressure: float
    volume: float
    exponent: float
    compression: float
    rebound: float
    stop_stiffness: float
    stroke_max: float
    stroke_min: float = 0.0
    ambient: float = P_ATM

    def __post_init__(self) -> None:
        # Each law checks its own parameters: evaluate them once at both stops (the gas spring
        # refuses a bottoming stop beyond its gas column).
        self([self.stroke_min, self.stroke_max], 0.0)

    def gas(self, stroke: ArrayLike) -> Law:
        """:func:`gas_spring` with this strut's parameters."""
        return gas_spring(
            stroke,
            area=self.area,
            pressure=self.pressure,
            volume=self.volume,
            exponent=self.exponent,
            ambient=self.ambient,
        )

    def stops(self, stroke: ArrayLike) -> Law:
        """:func:`end_stops` with this strut's parameters."""
        return end_stops(
            stroke, stiffness=self.stop_stiffness, lower=self.stroke_min, upper=self.stroke_max
        )

    def __call__(self, stroke: ArrayLike, rate: ArrayLike) -> Law:
        """``F_s`` [N], ``dF_s/dS`` [N/m] and ``dF_s/dS'`` [N s/m] at stroke ``S`` and its rate."""
        gas, d_gas = self.gas(stroke)
        stop, d_stop = self.stops(stroke)
        damper, d_rate = orifice_damper(rate, compression=self.compression, rebound=self.rebound)
        return broadcast(gas + stop + damper, d_gas + d_stop, d_rate)

    def energy(self, stroke: ArrayLike) -> np.ndarray:
        """The energy stored at stroke ``S`` [J]: :func:`gas_spring_energy` plus
        :func:`end_stops_energy` (zero at ``S = 0``)."""
        return gas_spring_energy(
            stroke,
            area=self.area,
            pressure=self.pressure,
            volume=self.volume,
            exponent=self.exponent,
            ambient=self.ambient,
        ) + end_stops_energy(
            stroke, stiffness=self.stop_stiffness, lower=self.stroke_min, upper=self.stroke_max
        )


def tyre_radial(deflection: ArrayLike, rate: ArrayLike, *, stiffness: float, damping: float) -> Law:
    """Unilateral radial tyre force: a spring-damper in compression that never pulls.

    .. math::

        F_z = \\begin{cases} \\max(0,\\ k_t d + c_t \\dot d) & d > 0 \\\\ 0 & d \\le 0
              \\end{cases}

    with the deflection ``d = R_0 - z_{axle}`` and its rate ``d' = -z_axle'`` (issue 14 writes
    ``k_t d - c_t z_axle'``).  The derivatives are ``(k_t, c_t)`` where ``d > 0`` and
    ``k_t d + c_t d' > 0`` (strictly), and ``(0, 0)`` elsewhere: at the unloading kink
    ``k_t d + c_t d' = 0`` this is the one-sided derivative from the unloaded side.  At ``d = 0``
    the force jumps from 0 to ``max(0, c_t d')`` (the damper's share at first contact); the law
    is discontinuous there and no derivative represents the jump.

    Parameters
    ----------
    deflection : array_like
        ``d`` [m], positive in contact.
    rate : array_like
        ``d'`` [m/s], positive while the tyre is being compressed.
    stiffness : float
        ``k_t`` [N/m], ``> 0``.
    damping : float
        ``c_t`` [N s/m], ``>= 0``.

    Returns
    -------
    force, d_deflection, d_rate : ndarray
        ``F_z`` [N] (upward on the axle), ``dF_z/dd`` [N/m], ``dF_z/dd'`` [N s/m].
    """
    law = "tyre radial force"
    k = number(stiffness, f"{law}: stiffness", "> 0")
    c = number(damping, f"{law}: damping", ">= 0")
    d = state(deflection, law, "deflection")
    v = state(rate, law, "rate")
    return broadcast(*array_laws.tyre_radial(d, v, k, c))


def tyre_energy(deflection: ArrayLike, *, stiffness: float) -> np.ndarray:
    """The tyre spring's energy ``k_t d^2 / 2`` for ``d > 0``, else 0 [J]: the conservative part
    of :func:`tyre_radial` (the rest of its work, ``(F_z - k_t d) d'``, is dissipated)."""
    law = "tyre energy"
    k = number(stiffness, f"{law}: stiffness", "> 0")
    d = state(deflection, law, "deflection")
    return np.where(d > 0, 0.5 * k * d * d, 0.0)


def slip_ratio(
    forward_speed: ArrayLike, spin: ArrayLike, *, radius: float, speed_eps: float
) -> Law:
    """Longitudinal slip ratio of a wheel, regularised at zero forward speed.

    .. math::

        \\kappa = \\frac{u - \\omega R_0}{\\sqrt{u^2 + u_\\epsilon^2}}, \\qquad
        \\frac{\\partial\\kappa}{\\partial u} = \\frac{1}{\\sqrt{u^2 + u_\\epsilon^2}}
            - \\frac{(u - \\omega R_0)\\,u}{(u^2 + u_\\epsilon^2)^{3/2}}, \\qquad
        \\frac{\\partial\\kappa}{\\partial\\omega} = -\\frac{R_0}{\\sqrt{u^2 + u_\\epsilon^2}}

    Issue 14's ``kappa = (u - omega R0) / u`` has a pole at ``u = 0``.  The denominator here
    is ``|u|`` made smooth: for ``|u| >> u_eps`` it is ``|u| (1 + u_eps^2 / (2 u^2) + ...)``,
    so ``kappa`` equals the issue's for ``u > 0`` to a relative ``u_eps^2 / (2 u^2)``
    (3e-6 at 40 m/s with ``u_eps = 0.1`` m/s), and for ``u < 0`` it keeps the sign that makes
    the friction oppose the sliding.  At ``u = 0`` a spinning wheel has the finite slip
    ``-omega R0 / u_eps`` (it saturates the friction curve: full sliding), a still one none.

    Parameters
    ----------
    forward_speed : array_like
        ``u`` [m/s], the axle's speed along the ground.
    spin : array_like
        ``omega`` [rad/s], positive when rolling forward.
    radius : float
        ``R0`` [m], the rolling radius, ``> 0``.
    speed_eps : float
        ``u_eps`` [m/s], ``> 0``.

    Returns
    -------
    kappa, d_forward_speed, d_spin : ndarray
    """
    return broadcast(*array_laws.slip_ratio(*_slip(forward_speed, spin, radius, speed_eps)))


def _slip(
    forward_speed: ArrayLike, spin: ArrayLike, radius: float, speed_eps: float
) -> tuple[np.ndarray, np.ndarray, float, float]:
    """The checked states and parameters of :func:`slip_ratio`: ``u, omega, R0, u_eps``."""
    law = "slip ratio"
    R = number(radius, f"{law}: radius", "> 0")
    eps = number(speed_eps, f"{law}: speed_eps", "> 0")
    return state(forward_speed, law, "forward speed"), state(spin, law, "spin"), R, eps


def friction_curve(kappa: ArrayLike, *, B: float, C: float, D: float) -> Law:
    """Friction coefficient against slip: Pacejka's Magic Formula without shift or curvature.

    .. math::

        \\mu(\\kappa) = D \\sin(C \\arctan(B\\kappa)), \\qquad
        \\frac{d\\mu}{d\\kappa} = \\frac{D\\,C\\,B \\cos(C \\arctan(B\\kappa))}{1 + B^2\\kappa^2}

    (Pacejka, *Tire and Vehicle Dynamics*, the Magic Formula with ``E = 0``).  The peak ``D``
    is at ``kappa = tan(pi / (2 C)) / B`` for ``C > 1``; as ``kappa -> oo`` the curve tends to
    ``D sin(C pi / 2)``; the slope at zero slip is ``B C D``.

    Parameters
    ----------
    kappa : array_like
        Slip ratio (:func:`slip_ratio`).
    B, C, D : float
        Stiffness, shape and peak factors, each ``> 0``.

    Returns
    -------
    mu, d_kappa : ndarray
    """
    k = state(kappa, "friction curve", "kappa")
    return broadcast(*array_laws.friction_curve(k, *_curve(B, C, D)))


def _curve(B: float, C: float, D: float) -> tuple[float, float, float]:
    """The checked parameters of :func:`friction_curve`."""
    law = "friction curve"
    return (
        number(B, f"{law}: B", "> 0"),
        number(C, f"{law}: C", "> 0"),
        number(D, f"{law}: D", "> 0"),
    )


def _normal(normal: ArrayLike, law: str) -> np.ndarray:
    N = state(normal, law, "normal force")
    if np.any(N < 0):
        raise ValueError(f"{law}: normal force must be >= 0, got {float(np.min(N))}")
    return N


def tyre_longitudinal(
    forward_speed: ArrayLike,
    spin: ArrayLike,
    normal: ArrayLike,
    *,
    radius: float,
    B: float,
    C: float,
    D: float,
    speed_eps: float,
) -> Law:
    """Longitudinal tyre force from the slip ratio through the friction curve.

    .. math::

        F_x = -\\mu(\\kappa(u, \\omega))\\,F_z, \\qquad
        \\frac{\\partial F_x}{\\partial u} = -\\mu'\\,\\kappa_{,u}\\,F_z, \\quad
        \\frac{\\partial F_x}{\\partial \\omega} = -\\mu'\\,\\kappa_{,\\omega}\\,F_z, \\quad
        \\frac{\\partial F_x}{\\partial F_z} = -\\mu

    with :func:`slip_ratio` and :func:`friction_curve` (issue 14).  Forward positive: a wheel
    slower than the ground (``kappa > 0``) is dragged back.  The spin moment on the wheel is
    ``-F_x R0`` (the issue's ``I_w omega' = -F_x R0``).

    Parameters
    ----------
    forward_speed, spin : array_like
        ``u`` [m/s], ``omega`` [rad/s].
    normal : array_like
        ``F_z`` [N], ``>= 0`` (:func:`tyre_radial`).
    radius, B, C, D, speed_eps : float
        As in :func:`slip_ratio` and :func:`friction_curve`.

    Returns
    -------
    force, d_forward_speed, d_spin, d_normal : ndarray
    """
    N = _normal(normal, "tyre longitudinal force")
    u, w, R, eps = _slip(forward_speed, spin, radius, speed_eps)
    return broadcast(*array_laws.tyre_longitudinal(u, w, N, R, eps, *_curve(B, C, D)))


def coulomb_friction(velocity: ArrayLike, normal: ArrayLike, *, mu: float, v_eps: float) -> Law:
    """Coulomb friction regularised by a hyperbolic tangent.

    .. math::

        F = -\\mu N \\tanh(v / v_\\epsilon), \\qquad
        \\frac{\\partial F}{\\partial v} = -\\frac{\\mu N}{v_\\epsilon}
            \\left(1 - \\tanh^2(v / v_\\epsilon)\\right), \\qquad
        \\frac{\\partial F}{\\partial N} = -\\mu \\tanh(v / v_\\epsilon)

    The sign function of Coulomb's law is replaced by ``tanh``, smooth and odd: the force is
    ``mu N`` opposing the sliding to a relative ``2 exp(-2 |v| / v_eps)`` once ``|v|`` exceeds a
    few ``v_eps``, and a viscous damper of coefficient ``mu N / v_eps`` through zero (so it
    cannot hold a part still against a load: the part creeps at ``v_eps load / (mu N)``).  Its
    power ``F v`` is never positive, so the friction always dissipates.

    Parameters
    ----------
    velocity : array_like
        ``v`` [m/s], the sliding velocity of the part the force acts on, relative to the other.
    normal : array_like
        ``N`` [N], ``>= 0``, the normal force pressing the parts together.
    mu : float
        Friction coefficient, ``>= 0``.
    v_eps : float
        Regularisation velocity [m/s], ``> 0``.

    Returns
    -------
    force, d_velocity, d_normal : ndarray
    """
    law = "coulomb friction"
    m = number(mu, f"{law}: mu", ">= 0")
    eps = number(v_eps, f"{law}: v_eps", "> 0")
    v = state(velocity, law, "velocity")
    N = _normal(normal, law)
    return broadcast(*array_laws.coulomb_friction(v, N, m, eps))


def stribeck_friction(
    velocity: ArrayLike,
    normal: ArrayLike,
    *,
    mu_static: float,
    mu_kinetic: float,
    v_stribeck: float,
    v_eps: float,
) -> Law:
    """Regularised friction with a Stribeck drop from static to kinetic friction (stick-slip).

    .. math::

        F = -N\\,g(v) \\tanh(v / v_\\epsilon), \\qquad
        g(v) = \\mu_k + (\\mu_s - \\mu_k)\\,e^{-(v / v_s)^2}

    with ``dF/dv = -N [g' tanh + g (1 - tanh^2) / v_eps]``, ``g' = -2 v (mu_s - mu_k)
    exp(-(v/v_s)^2) / v_s^2``, and ``dF/dN = -g tanh``.  The friction falls from about
    ``mu_s N`` at low sliding speed to ``mu_k N``: this negative slope is what drives
    stick-slip oscillations of a part pulled through a spring.  It is a *regularised* stick:
    below ``v_eps`` the law is a stiff viscous damper (as :func:`coulomb_friction`), not a
    locked contact, so a "stuck" part creeps slowly instead of holding exactly.  With
    ``mu_static = mu_kinetic`` it is :func:`coulomb_friction`.

    Parameters
    ----------
    velocity, normal : array_like
        As in :func:`coulomb_friction`.
    mu_static, mu_kinetic : float
        ``mu_s >= mu_k >= 0``.
    v_stribeck : float
        ``v_s`` [m/s], ``> 0``, the speed over which the friction drops.
    v_eps : float
        Regularisation velocity [m/s], ``> 0``.

    Returns
    -------
    force, d_velocity, d_normal : ndarray
    """
    law = "stribeck friction"
    mu_s = number(mu_static, f"{law}: mu_static", ">= 0")
    mu_k = number(mu_kinetic, f"{law}: mu_kinetic", ">= 0")
    if mu_s < mu_k:
        raise ValueError(f"{law}: mu_static ({mu_s}) must be >= mu_kinetic ({mu_k})")
    v_s = number(v_stribeck, f"{law}: v_stribeck", "> 0")
    v = state(velocity, law, "velocity")
    N = _normal(normal, law)
    eps = number(v_eps, f"{law}: v_eps", "> 0")
    return broadcast(*array_laws.stribeck_friction(v, N, mu_s, mu_k, v_s, eps))
