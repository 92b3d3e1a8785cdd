"""The compiled force laws (:mod:`sliders.forces.compiled_laws`) against their references
(:mod:`sliders.forces.laws`), to roundoff.

Both are printed from the same differentiated statements (:mod:`sliders.forces.statements`,
``python -m sliders.forces.generate``): the same closed forms in the same order of
operations, except that the references sum the strut's three parts after evaluating each:
every value and derivative agrees within a few ulp of the largest term it sums (bound
``8 eps`` of it).
"""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from sliders.forces import compiled_laws as kernel
from sliders.forces import laws

EPS = np.finfo(float).eps
GEAR = dict(area=1.6e-3, pressure=4.1e5, volume=2.8e-4, exponent=1.3)
STRUT = laws.Strut(**GEAR, compression=5000.0, rebound=20000.0, stop_stiffness=1e8, stroke_max=0.16)
TYRE = dict(radius=0.22, stiffness=2.5e5, damping=250.0, B=10.0, C=1.65, D=0.8, speed_eps=0.1)


def row(name: str, values: dict) -> np.ndarray:
    return np.array([values[key] for key in kernel.PARAMETERS[name]], dtype=float)


def close(got: tuple, expected: tuple, scale: float) -> None:
    for a, b in zip(got, expected, strict=True):
        assert abs(a - float(b)) <= 8 * EPS * max(scale, abs(float(b)))


@settings(max_examples=200, deadline=None, derandomize=True)
@given(st.floats(-1e-3, 0.17), st.floats(-5.0, 5.0))
def test_strut(stroke: float, rate: float) -> None:
    p = row("strut", {**vars(STRUT), "ambient": STRUT.ambient})
    expected = STRUT(stroke, rate)
    gas = STRUT.gas(stroke)[0]
    stop = STRUT.stops(stroke)[0]
    scale = abs(float(gas)) + abs(float(stop)) + 2e4 * rate * rate
    close(kernel.strut(p, stroke, rate), expected, scale)


@settings(max_examples=200, deadline=None, derandomize=True)
@given(st.floats(-0.05, 0.1), st.floats(-5.0, 5.0), st.floats(-5.0, 45.0), st.floats(-50, 250))
def test_tyre(deflection: float, rate: float, forward: float, spin: float) -> None:
    p = row("tyre", TYRE)
    radial = laws.tyre_radial(deflection, rate, stiffness=TYRE["stiffness"], damping=250.0)
    close(kernel.tyre_radial(p, deflection, rate), radial, abs(float(radial[0])))
    normal = float(radial[0])
    expected = laws.tyre_longitudinal(
        forward,
        spin,
        normal,
        radius=0.22,
        B=10.0,
        C=1.65,
        D=0.8,
        speed_eps=0.1,
    )
    got = kernel.tyre_longitudinal(p, forward, spin, normal)
    for a, b in zip(got, expected, strict=True):
        assert abs(a - float(b)) <= 64 * EPS * max(abs(float(b)), 1.0) * max(normal, 1.0)
