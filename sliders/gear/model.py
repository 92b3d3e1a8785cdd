"""The telescopic nose landing gear of the paper's Section 7 (issue 14), built from the library.

Frame: x forward, z up, ground ``z = 0``; the strut is vertical, its abscissae measured down
from the attachment at the cylinder's top, ``z_top = R0 + s_ext + L`` (the axle at ``z = R0``
at full extension).  The parts (``docs/landing_gear.md``, "The flexible models"):

* ``airframe``: a rigid body of mass ``m_a`` at the attachment, free in x and z (``uy`` and
  the rotations supported: no pitch), carrying the lift ``(m_a + m_u) g``;
* the cylinder ``C`` on ``[0, L]`` below it, its top node tied to the airframe (clamped), and
  the piston ``P`` on ``[s_ext, s_ext + L]``: light fv3 beams (:data:`LIGHT`) of the tube's
  section, ``n`` elements each; the rigid model scales the section by ``rigid_factor`` (one
  element each);
* two sliders as in the paper's Figures 3-5: ``top`` (the piston's top node slides on ``C``,
  its abscissa is ``s``) and ``bottom`` (the cylinder's bottom node slides on ``P``);
  classical, or spherical;
* ``axle``: a rigid body of mass ``m_u`` tied to the piston's lower end, its spin about the
  strut held (the torque links; no slider kind holds it);
* ``wheel``: a rigid body of spin inertia ``I_w`` about y whose spin alone is free (its
  translations are held: the tyre reads the axle's);
* the strut: an :class:`~sliders.forces.elements.AxialForce` between the cylinder's top and the
  piston's top with ``extended = s_ext``, so that its stroke ``s_ext - |x_P.start -
  x_C.start|`` is the issue's ``S = s_ext - s`` (the chord of the cylinder from its top to
  the piston's head, which is ``s`` while the cylinder is straight);
* the :class:`~sliders.forces.elements.Tyre` between the axle and the wheel;
* gravity on every mass; structural damping ``C = beta K`` with ``beta = 2 zeta / omega_1``
  on the first fore-aft bending mode (:meth:`GearModel.fore_aft_mode`).

:meth:`GearModel.touchdown` is the issue's initial state; :meth:`GearModel.simulate`
integrates it and returns a :class:`~sliders.gear.outputs.GearRun`.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from fvbeam import Beam, RigidBody, Section, Structure, Support, straight
from sliders.forces.elements import AxialForce, Tyre
from sliders.gear.outputs import GearRecorder, GearRun
from sliders.gear.parameters import ISSUE_14, Gear
from sliders.joints.friction import Friction
from sliders.joints.slider import Slider
from sliders.lines.chain import BeamChain
from sliders.solve.dynamics import Dynamics
from sliders.solve.integrator import State
from sliders.solve.statics import SliderStatics

#: The models of issue 14: a rigid leg, and 1, 3 and 5 fv3 elements per tube.
MODELS = ("rigid", "fv3-1", "fv3-3", "fv3-5")
#: The tubes' mass, a fraction of the unsprung mass (both tubes together): light, not
#: massless (:mod:`fvbeam.mass` assembles no mass matrix of a massless section), and taken
#: off the bodies they belong to (the cylinder's off the airframe, the piston's off the axle),
#: so that every rigid motion carries exactly the issue's masses.
LIGHT = 1e-5
#: The direction of the strut's lines from top to bottom, and the slider axes on them.
DOWN = np.array([0.0, 0.0, -1.0])
#: Slider axes ``[e1, e2, e3]`` (columns): ``e1`` along the lines (down), ``e2`` back, ``e3``
#: lateral; the lines' section frame (:func:`fvbeam.geometry.section_frames` with ``up = y``).
FRAME = np.column_stack([DOWN, [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])


def elements(model: str) -> int:
    """Elements per tube of ``model``: one of :data:`MODELS`, or ``fv3-N`` for any ``N >= 1``
    (a finer mesh, for convergence); the rigid leg has one."""
    if model == "rigid":
        return 1
    kind, _, count = model.partition("-")
    if kind != "fv3" or not count.isdigit() or int(count) < 1:
        raise ValueError(f"model must be one of {', '.join(MODELS)} or fv3-N, got {model!r}")
    return int(count)


@dataclass(frozen=True)
class Mode:
    """The first fore-aft bending mode at touchdown: the axle's fore-aft stiffness against
    the airframe ``stiffness`` [N/m] and the mode's circular frequency ``omega`` [rad/s]."""

    stiffness: float
    omega: float

    @property
    def frequency(self) -> float:
        """``omega / (2 pi)`` [Hz]."""
        return self.omega / (2 * np.pi)


class GearModel:
    """Issue 14's gear as a structure, sliders and force elements (module docstring).

    Parameters
    ----------
    model
        ``rigid``, ``fv3-1``, ``fv3-3`` or ``fv3-5``.
    gear
        The parameters (:class:`~sliders.gear.parameters.Gear`).
    slider
        ``classical`` (the paper's Figure 7) or ``spherical``.
    smearing
        Half-width [m] of the sliders' box kernel (:class:`~sliders.joints.slider.Slider`).
    damping_ratio
        ``zeta`` of the first fore-aft bending mode.
    rigid_factor
        The rigid model's section is the tube's times this factor.
    friction
        Bearing friction on both sliders in the dynamics (``mu_b``, ``v_eps`` of ``gear``:
        :class:`~sliders.joints.friction.Friction`); without it, the frictionless gear whose
        friction the outputs post-process.
    strut
        The strut's lower node: ``head`` (the piston's top, ``extended = s_ext``: the gas
        pushes the piston's head, along the cylinder) or ``axle`` (the piston's lower end,
        ``extended = s_ext + L``; for comparison, ``docs/landing_gear.md``).
    """

    def __init__(
        self,
        model: str,
        gear: Gear = ISSUE_14,
        *,
        slider: str = "classical",
        smearing: float = 0.01,
        damping_ratio: float = 0.0175,
        rigid_factor: float = 1e5,
        friction: bool = False,
        strut: str = "head",
    ) -> None:
        self.model, self.gear, self.n_elements = model, gear, elements(model)
        if slider not in ("classical", "spherical"):
            raise ValueError(f"slider must be 'classical' or 'spherical', got {slider!r}")
        if not (np.isfinite(damping_ratio) and 0 <= damping_ratio < 1):
            raise ValueError(f"damping_ratio must be in [0, 1), got {damping_ratio!r}")
        if not (np.isfinite(rigid_factor) and rigid_factor >= 1):
            raise ValueError(f"rigid_factor must be >= 1, got {rigid_factor!r}")
        self.slider_kind, self.smearing, self.damping_ratio = slider, smearing, damping_ratio
        self.rigid_factor = rigid_factor if model == "rigid" else 1.0
        g = gear
        self.top = g.radius + g.extension + g.length
        factor = self.rigid_factor
        #: Each tube's mass [kg] (:data:`LIGHT`).
        self.tube_mass = LIGHT * g.unsprung_mass / 2
        section = Section.diagonal(
            EA=factor * g.EA,
            GAy=factor * g.GA,
            GAz=factor * g.GA,
            GJ=factor * g.GJ,
            EJy=factor * g.EJ,
            EJz=factor * g.EJ,
            mass_per_length=self.tube_mass / g.length,
        )
        top, head, bottom = ([0.0, 0.0, self.top - depth] for depth in (0.0, g.extension, g.length))
        axle = [0.0, 0.0, g.radius]
        cylinder = Beam(straight(top, bottom, self.n_elements, name="C"), section, "fv3")
        piston = Beam(straight(head, axle, self.n_elements, name="P"), section, "fv3")
        bodies = [
            RigidBody("airframe", np.array(top), mass=g.airframe_mass - self.tube_mass),
            RigidBody("axle", np.array(axle), mass=g.unsprung_mass - self.tube_mass),
            RigidBody("wheel", np.array(axle), inertia=np.diag([0.0, g.spin_inertia, 0.0])),
        ]
        self.structure = Structure(
            [cylinder, piston], ties=[("C.start", "airframe"), ("P.end", "axle")], bodies=bodies
        )
        self.supports = [
            Support("airframe", kind="uy+rx+ry+rz"),
            Support("axle", kind="rz"),
            Support("wheel", kind="ux+uy+uz+rx+rz"),
        ]
        self.sliders = [
            Slider(
                slider,
                BeamChain(self.structure, line),
                body,
                frame=FRAME,
                smearing=smearing,
                friction=Friction(g.bearing_mu, g.bearing_v_eps) if friction else None,
                name=name,
            )
            for name, line, body in (("top", "C", "P.start"), ("bottom", "P", "C.end"))
        ]
        if strut not in ("head", "axle"):
            raise ValueError(f"strut must be 'head' or 'axle', got {strut!r}")
        self.strut = AxialForce(
            "C.start",
            "P.start" if strut == "head" else "axle",
            g.strut,
            extended=g.extension + (g.length if strut == "axle" else 0.0),
            name="strut",
        )
        self.tyre = Tyre(
            "axle",
            "wheel",
            radius=g.radius,
            stiffness=g.tyre_stiffness,
            damping=g.tyre_damping,
            B=g.B,
            C=g.C,
            D=g.D,
            speed_eps=g.speed_eps,
            name="tyre",
        )
        self.forces = [self.strut, self.tyre]
        self.lift = self.structure.nodal_load("airframe", (0.0, 0.0, g.lift))
        self.gravity = (0.0, 0.0, -g.gravity)

    def dofs(self, node: str) -> np.ndarray:
        """The six global dofs of ``node`` (a body's name or ``"C.end"`` and the like)."""
        return self.structure.node_dofs(node)

    def _statics(self) -> SliderStatics:
        """The gear hanging from the held airframe, its tyre off the ground (the tyre carries
        nothing at touchdown, and the axle hangs a few micrometres below its reference
        height ``R0``: the tyre element is left out)."""
        return SliderStatics(
            self.structure,
            [Support("airframe"), Support("wheel"), Support("axle", kind="rz")],
            self.sliders,
            forces=[self.strut],
            method="condensed",
        )

    @cached_property
    def loads(self) -> np.ndarray:
        """Lift and gravity (``M g``) as one load vector."""
        g = np.concatenate([self.gravity, np.zeros(3)])
        return self.lift + self.structure.mass("lumped") @ np.tile(g, self.structure.n_nodes)

    @cached_property
    def hanging(self) -> tuple[np.ndarray, list[np.ndarray]]:
        """The gear hanging from the held airframe under gravity and lift, the tyre just off
        the ground: the strut on its extension stop holds the gas preload and the unsprung
        weight (``F_s(S0, 0) = -m_u g``), the tubes strained by it.  Displacements and the
        sliders' unknowns."""
        solution = self._statics().solve(self.loads)
        return solution.q, solution.unknowns

    def touchdown(self) -> State:
        """Issue 14's touchdown: :attr:`hanging` moved rigidly along z so that the axle is at
        ``z = R0`` (the tyre just touching), every part moving at ``sink`` down and
        ``forward`` on, the wheel still; accelerations zero (the hanging state is a
        balance: lift equals the weight, and the tyre carries nothing)."""
        q, unknowns = self.hanging
        q = q.copy()
        axle = self.dofs("axle")
        drop = self.gear.radius - (self.structure.node_position("axle")[2] + q[axle[2]])
        moving = np.setdiff1d(np.arange(self.structure.n_dofs), self.dofs("wheel"))
        translation = moving[moving % 6 < 3]
        z = translation[translation % 6 == 2]
        q[z] += drop
        v = np.zeros(self.structure.n_dofs)
        v[translation[translation % 6 == 0]] = self.gear.forward
        v[z] = -self.gear.sink
        return self.dynamics.state(q, v, 0.0, unknowns)

    def fore_aft_mode(self) -> Mode:
        """The first fore-aft bending mode at touchdown.  The beams are light (:data:`LIGHT`;
        their rotations massless), so the fore-aft motion has two masses, the airframe and
        the axle, joined by the leg's fore-aft stiffness ``k`` at the axle (the airframe held,
        a load there, the sliders at full extension): ``omega^2 = k (1 / m_a + 1 / m_u)``, to
        the tubes' relative mass :data:`LIGHT`."""
        q, unknowns = self.hanging
        statics = self._statics()
        push = 1e3  # N: a tenth of the drag; the response is linear in it
        unit = self.structure.nodal_load("axle", (push, 0.0, 0.0))
        loaded = statics.solve(self.loads + unit, start=(q, unknowns))
        k = push / (loaded.q[self.dofs("axle")[0]] - q[self.dofs("axle")[0]])
        g = self.gear
        return Mode(k, float(np.sqrt(k * (1 / g.airframe_mass + 1 / g.unsprung_mass))))

    @cached_property
    def dynamics(self) -> Dynamics:
        """The time integration (condensed back end, compiled steps), damped ``C = beta K``
        with ``beta = 2 zeta / omega_1`` (:meth:`fore_aft_mode`)."""
        beta = 2 * self.damping_ratio / self.fore_aft_mode().omega if self.damping_ratio else 0.0
        return Dynamics(
            self.structure,
            self.supports,
            self.sliders,
            self.lift,
            forces=self.forces,
            gravity=self.gravity,
            damping=beta,
            method="condensed",
        )

    def simulate(
        self, t_end: float = 0.3, step: float = 1e-4, progress: bool = False, keep: bool = False
    ) -> GearRun:
        """Integrate from :meth:`touchdown` to ``t_end`` in fixed steps of about ``step``
        (generalized-alpha, compiled) and return the outputs
        (:class:`~sliders.gear.outputs.GearRun`; with ``keep``, every state too)."""
        recorder = GearRecorder(self, keep)
        start = self.touchdown()
        clock = time.perf_counter()
        self.dynamics.run(start, t_end, step, recorder=recorder, progress=progress)
        return recorder.result(time.perf_counter() - clock)
