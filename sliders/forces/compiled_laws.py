"""The force laws of :mod:`sliders.forces.statements`, compiled (generated).

Written by ``python -m sliders.forces.generate`` from the laws' one statement (sympy traces
each law and differentiates it); ``tests/test_force_statements.py`` checks that regenerating
changes nothing.  Each function reads its parameters in a row of floats, in the order its
:data:`PARAMETERS` entry lists (the force elements check them once, where they are built),
and returns the value and its partial derivatives in the order of its state arguments.
"""

# ruff: noqa

import math

import numba

from fvbeam.kernel_cache import guard

guard(__file__)  # numba's cache of these kernels, consistent with their sources

#: The parameter rows of the laws, by name (:mod:`sliders.forces.laws` keyword arguments).
PARAMETERS = {'strut': ('area', 'pressure', 'volume', 'exponent', 'ambient', 'compression', 'rebound', 'stop_stiffness', 'stroke_min', 'stroke_max'), 'tyre': ('radius', 'stiffness', 'damping', 'B', 'C', 'D', 'speed_eps')}


@numba.njit(cache=True, inline="never")
def strut(p, stroke, rate):
    """:func:`sliders.forces.statements.strut` at one point, ``p``: ``PARAMETERS["strut"]``; returns ``(value, d/dstroke, d/drate)``."""
    t0 = 1/(-p[0]*stroke + p[2])
    t1 = p[1]*(p[2]*t0)**p[3]
    t2 = ((p[5]) if (rate > 0) else (p[6]))
    t3 = t2*abs(rate)
    t4 = -stroke
    t5 = (p[8] > stroke)
    t6 = (p[9] < stroke)
    return p[0]*(-p[4] + t1) + rate*t3 + ((p[7]*(-p[8] - t4)) if t5 else (((p[7]*(-p[9] - t4)) if t6 else (0.0)))), p[0]**2*p[3]*t0*t1 + ((p[7]) if t5 else (((p[7]) if t6 else (0)))), rate*t2*(0.0 if rate == 0 else math.copysign(1, rate)) + t3


@numba.njit(cache=True, inline="never")
def tyre_radial(p, deflection, rate):
    """:func:`sliders.forces.statements.tyre_radial` at one point, ``p``: ``PARAMETERS["tyre"]``; returns ``(value, d/ddeflection, d/drate)``."""
    t0 = deflection*p[1] + p[2]*rate
    t1 = (deflection > 0) and (t0 > 0)
    return ((t0) if t1 else (0.0)), ((p[1]) if t1 else (0)), ((p[2]) if t1 else (0))


@numba.njit(cache=True, inline="never")
def tyre_longitudinal(p, forward_speed, spin, normal):
    """:func:`sliders.forces.statements.tyre_longitudinal` at one point, ``p``: ``PARAMETERS["tyre"]``; returns ``(value, d/dforward_speed, d/dspin, d/dnormal)``."""
    t0 = forward_speed - p[0]*spin
    t1 = forward_speed**2 + p[6]**2
    t2 = 1/math.sqrt(t1)
    t3 = p[3]*t2
    t4 = p[4]*math.atan(t0*t3)
    t5 = p[5]*math.sin(t4)
    t6 = normal*p[4]*p[5]*math.cos(t4)/(p[3]**2*t0**2/t1 + 1)
    return -normal*t5, -t6*(-forward_speed*p[3]*t0/t1**(3/2) + p[3]*t2), p[0]*t3*t6, -t5
