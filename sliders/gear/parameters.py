"""Issue 14's nose landing gear: every parameter in one place (``docs/landing_gear.md`` gives
each value's reason and its typical range).

The Figure 7 models (:mod:`sliders.gear.model`) and the independent rigid reference
(``studies/landing_gear_ode.py``) both read :class:`Gear`, so that they differ in their
equations only.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from sliders.forces.laws import Strut


@dataclass(frozen=True)
class Gear:
    """Issue 14's nose gear (``docs/landing_gear.md`` gives each value's reason).

    Masses [kg], lengths [m], speeds [m/s]; ``length`` is each tube's ``L``, ``extension``
    the piston-top abscissa ``s_ext`` at full extension; ``EA``, ``GA``, ``GJ``, ``EJ`` [N,
    N m^2] each tube's section (a 54 x 4 mm steel tube; shear and bending alike in both
    planes); ``radius``, ``spin_inertia`` and the
    tyre's ``tyre_stiffness``, ``tyre_damping``, ``B``, ``C``, ``D``, ``speed_eps`` as in
    :func:`sliders.forces.laws.tyre_radial` and :func:`~sliders.forces.laws.tyre_longitudinal`;
    ``sink`` and ``forward`` the touchdown speeds; ``bearing_mu`` the sliders' friction
    coefficient (paper Sec. 7), ``bearing_v_eps`` its regularisation speed.
    """

    airframe_mass: float = 300.0
    unsprung_mass: float = 12.0
    gravity: float = 9.81
    length: float = 0.6
    extension: float = 0.45
    EA: float = 1.3e8
    GA: float = 1.1e8
    GJ: float = 3.2e4
    EJ: float = 4.1e4
    strut: Strut = field(
        default_factory=lambda: Strut(
            area=1.6e-3,
            pressure=4.1e5,
            volume=2.8e-4,
            exponent=1.3,
            compression=5000.0,
            rebound=20000.0,
            stop_stiffness=1e8,
            stroke_max=0.16,
        )
    )
    radius: float = 0.22
    spin_inertia: float = 0.15
    tyre_stiffness: float = 2.5e5
    tyre_damping: float = 250.0
    B: float = 10.0
    C: float = 1.65
    D: float = 0.8
    speed_eps: float = 0.1
    sink: float = 2.8
    forward: float = 40.0
    bearing_mu: float = 0.02
    bearing_v_eps: float = 1e-3

    @property
    def mass(self) -> float:
        """``M = m_a + m_u``, the mass the ground's longitudinal force accelerates."""
        return self.airframe_mass + self.unsprung_mass

    @property
    def lift(self) -> float:
        """The constant lift ``(m_a + m_u) g`` on the airframe [N]."""
        return self.mass * self.gravity


#: Issue 14's gear, as ``Gear()`` (a default argument).
ISSUE_14 = Gear()
