"""The force laws of :mod:`sliders.forces.statements` on arrays (generated).

Written by ``python -m sliders.forces.generate`` from the laws' one statement (sympy traces
each law and differentiates it); ``tests/test_force_statements.py`` checks that regenerating
changes nothing.  :mod:`sliders.forces.laws` checks the inputs and calls these.
"""

# ruff: noqa
# mypy: ignore-errors

import numpy


def gas_spring(stroke, area, pressure, volume, exponent, ambient):
    """:func:`sliders.forces.statements.gas_spring` and its derivatives: ``(value, d/dstroke)``."""
    t0 = (-area*stroke + volume)**(-1.0)
    t1 = (t0*volume)**exponent
    return area*(-ambient + pressure*t1), area**2*exponent*pressure*t0*t1


def orifice_damper(rate, compression, rebound):
    """:func:`sliders.forces.statements.orifice_damper` and its derivatives: ``(value, d/drate)``."""
    t0 = numpy.select([numpy.greater(rate, 0),True], [compression,rebound], default=numpy.nan)
    t1 = t0*abs(rate)
    return rate*t1, rate*t0*numpy.sign(rate) + t1


def end_stops(stroke, stiffness, lower, upper):
    """:func:`sliders.forces.statements.end_stops` and its derivatives: ``(value, d/dstroke)``."""
    t0 = numpy.greater(lower, stroke)
    t1 = numpy.greater(stroke, upper)
    return numpy.select([t0,True], [stiffness*(-lower + stroke),numpy.select([t1,True], [stiffness*(stroke - upper),0.0], default=numpy.nan)], default=numpy.nan), numpy.select([t0,True], [stiffness,numpy.select([t1,True], [stiffness,0], default=numpy.nan)], default=numpy.nan)


def tyre_radial(deflection, rate, stiffness, damping):
    """:func:`sliders.forces.statements.tyre_radial` and its derivatives: ``(value, d/ddeflection, d/drate)``."""
    t0 = damping*rate + deflection*stiffness
    t1 = numpy.logical_and(numpy.greater(deflection, 0), numpy.greater(t0, 0))
    return numpy.select([t1,True], [t0,0.0], default=numpy.nan), numpy.select([t1,True], [stiffness,0], default=numpy.nan), numpy.select([t1,True], [damping,0], default=numpy.nan)


def slip_ratio(forward_speed, spin, radius, speed_eps):
    """:func:`sliders.forces.statements.slip_ratio` and its derivatives: ``(value, d/dforward_speed, d/dspin)``."""
    t0 = forward_speed**2 + speed_eps**2
    t1 = 1/numpy.sqrt(t0)
    t2 = forward_speed - radius*spin
    return t1*t2, -forward_speed*t2/t0**(3/2) + t1, -radius*t1


def friction_curve(kappa, B, C, D):
    """:func:`sliders.forces.statements.friction_curve` and its derivatives: ``(value, d/dkappa)``."""
    t0 = C*numpy.arctan(B*kappa)
    return D*numpy.sin(t0), B*C*D*numpy.cos(t0)/(B**2*kappa**2 + 1)


def tyre_longitudinal(forward_speed, spin, normal, radius, speed_eps, B, C, D):
    """:func:`sliders.forces.statements.tyre_longitudinal` and its derivatives: ``(value, d/dforward_speed, d/dspin, d/dnormal)``."""
    t0 = forward_speed - radius*spin
    t1 = forward_speed**2 + speed_eps**2
    t2 = 1/numpy.sqrt(t1)
    t3 = B*t2
    t4 = C*numpy.arctan(t0*t3)
    t5 = D*numpy.sin(t4)
    t6 = C*D*normal*numpy.cos(t4)/(B**2*t0**2/t1 + 1)
    return -normal*t5, -t6*(-B*forward_speed*t0/t1**(3/2) + B*t2), radius*t3*t6, -t5


def coulomb_friction(velocity, normal, mu, v_eps):
    """:func:`sliders.forces.statements.coulomb_friction` and its derivatives: ``(value, d/dvelocity, d/dnormal)``."""
    t0 = v_eps**(-1.0)
    t1 = numpy.tanh(t0*velocity)
    t2 = mu*t1
    return -normal*t2, -mu*normal*t0*(1 - t1**2), -t2


def stribeck_friction(velocity, normal, mu_static, mu_kinetic, v_stribeck, v_eps):
    """:func:`sliders.forces.statements.stribeck_friction` and its derivatives: ``(value, d/dvelocity, d/dnormal)``."""
    t0 = v_stribeck**(-2.0)
    t1 = (-mu_kinetic + mu_static)*numpy.exp(-t0*velocity**2)
    t2 = mu_kinetic + t1
    t3 = v_eps**(-1.0)
    t4 = numpy.tanh(t3*velocity)
    t5 = t2*t4
    return -normal*t5, 2*normal*t0*t1*t4*velocity - normal*t2*t3*(1 - t4**2), -t5
