"""Loads and forces beside the joints: a load moving along a chain
(:mod:`sliders.forces.moving_load`), and the force laws of a landing gear (issue 14): gas
spring, orifice damper, end stops, the strut, tyre, slip and friction, user laws; each law
returns its value and partial derivatives (:mod:`sliders.forces.laws`,
:mod:`sliders.forces.user`), checked by central differences (:mod:`sliders.forces.differences`).

A public name's module is imported on its first use (PEP 562), so that a scene without a
moving load or a user law imports neither (nor scipy's differentiation)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from fvbeam.lazy import lazy_names

if TYPE_CHECKING:
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
    from sliders.forces.moving_load import MovingLoad
    from sliders.forces.user import UserLaw

__all__ = [
    "MovingLoad",
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

#: Each public name's module.
_MODULES = {name: "sliders.forces.laws" for name in __all__} | {
    "MovingLoad": "sliders.forces.moving_load",
    "UserLaw": "sliders.forces.user",
}

__getattr__, __dir__ = lazy_names(__name__, _MODULES, globals())
