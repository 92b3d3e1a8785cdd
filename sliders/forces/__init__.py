"""Force laws of a landing gear (issue 14): gas spring, orifice damper, end stops, the strut,
tyre, slip and friction, user laws; each returns its value and partial derivatives
(:mod:`sliders.forces.laws`, :mod:`sliders.forces.user`), checked by central differences
(:mod:`sliders.forces.differences`)."""

from sliders.forces.laws import (
    Strut,
    coulomb_friction,
    end_stops,
    friction_curve,
    gas_spring,
    orifice_damper,
    slip_ratio,
    stribeck_friction,
    tyre_longitudinal,
    tyre_radial,
)
from sliders.forces.user import UserLaw

__all__ = [
    "Strut",
    "UserLaw",
    "coulomb_friction",
    "end_stops",
    "friction_curve",
    "gas_spring",
    "orifice_damper",
    "slip_ratio",
    "stribeck_friction",
    "tyre_longitudinal",
    "tyre_radial",
]
