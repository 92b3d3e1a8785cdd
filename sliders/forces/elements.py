"""Force elements: forces between nodes and on the ground that the Newton step evaluates.

An element acts on a few structure dofs (its *slots*) with a force that depends on their
displacements and velocities through a law of :mod:`sliders.forces.laws`; the Newton step
adds its residual and its Jacobian ``dr/dq + c_v dr/dv`` (``c_v = dv/dq``, the integrator's
``gamma'``; zero in statics) to the problem, as it adds a joint's, on the compiled path
(:mod:`sliders.forces.kernel`) and the Python one alike.  The residual of the structure is
``K q - f + r``: an element's ``r`` is minus the force it exerts.

:class:`AxialForce`
    a force along the current line between two nodes, from a law of the stroke
    ``S = extended - |x_b - x_a|`` (compression positive) and its rate: a strut between its
    attachment and its axle, a spring-damper;
:class:`Tyre`
    a wheel on flat ground: the unilateral radial force of the axle's height above the ground
    and its rate, and the longitudinal force of the slip between the axle's forward speed and
    the wheel's spin (the spin moment goes to the wheel).

Each element checks its parameters where it is built and packs them
(:meth:`ForceElement.packed`) for the compiled kernel.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

from fvbeam.geometry import direction, number, vector3
from fvbeam.names import NodeRef, parse_node
from fvbeam.structure import Structure
from sliders.forces import laws
from sliders.forces.compiled_laws import PARAMETERS

AXIAL, TYRE = range(2)


class ForceElement:
    """What the Newton step reads of an element: its kind, slots and packed parameters;
    and what it reports (:meth:`outputs`, named by :attr:`OUTPUTS`)."""

    name: str
    kind: int
    #: The names of :meth:`outputs`.
    OUTPUTS: tuple[str, ...] = ()

    def outputs(self, structure: Structure, q: np.ndarray, v: np.ndarray) -> dict[str, np.ndarray]:
        """The element's forces and states at displacements ``q`` and velocities ``v`` (the
        global dofs on the last axis; leading axes, such as time steps, broadcast)."""
        raise NotImplementedError

    def slots(self, structure: Structure) -> np.ndarray:
        """The global dofs the element acts on."""
        raise NotImplementedError

    def packed(self, structure: Structure) -> np.ndarray:
        """The element's constants as the compiled kernel reads them
        (:func:`sliders.forces.kernel.evaluate_element`)."""
        raise NotImplementedError


@dataclass
class AxialForce(ForceElement):
    """``law(S, S')`` along the line from node ``a`` to node ``b``: ``S = extended - |x_b -
    x_a|`` is the stroke, compression positive, and the force pushes the nodes apart when
    positive.  ``law``: a :class:`sliders.forces.laws.Strut`."""

    a: NodeRef
    b: NodeRef
    law: laws.Strut
    extended: float
    name: str = "axial force"
    kind: int = field(default=AXIAL, init=False)

    def __post_init__(self) -> None:
        parse_node(self.a, f"{self.name}: a")
        parse_node(self.b, f"{self.name}: b")
        if not isinstance(self.law, laws.Strut):
            raise ValueError(f"{self.name}: law must be a sliders.forces.laws.Strut")
        self.extended = number(self.extended, f"{self.name}: extended", "> 0")

    OUTPUTS = ("force", "stroke", "rate")

    def slots(self, structure: Structure) -> np.ndarray:
        return np.concatenate(
            [structure.node_dofs(self.a)[:3], structure.node_dofs(self.b)[:3]]
        ).astype(np.int64)

    def outputs(self, structure: Structure, q: np.ndarray, v: np.ndarray) -> dict[str, np.ndarray]:
        """``force`` (the law's, compression positive), ``stroke`` ``S`` and its ``rate``."""
        a, b = structure.node_dofs(self.a)[:3], structure.node_dofs(self.b)[:3]
        d = structure.node_position(self.b) - structure.node_position(self.a)
        d = d + np.asarray(q)[..., b] - np.asarray(q)[..., a]
        length = np.linalg.norm(d, axis=-1)
        rate = -np.sum(d * (np.asarray(v)[..., b] - np.asarray(v)[..., a]), axis=-1) / length
        stroke = self.extended - length
        return {"force": self.law(stroke, rate)[0], "stroke": stroke, "rate": rate}

    def packed(self, structure: Structure) -> np.ndarray:
        law = {**vars(self.law), "ambient": self.law.ambient}
        return np.concatenate(
            [
                structure.node_position(self.a),
                structure.node_position(self.b),
                [self.extended],
                [law[key] for key in PARAMETERS["strut"]],
            ]
        )


@dataclass
class Tyre(ForceElement):
    """A wheel of rolling ``radius`` on the ground plane through ``ground`` with upward
    ``normal``, rolling along ``forward``: the axle is node ``axle`` (its translations), the
    wheel node ``wheel`` (a rigid body whose rotation about ``normal x forward`` is the spin).

    Radial force (:func:`sliders.forces.laws.tyre_radial`) of the deflection
    ``d = radius - (x_axle - ground) . normal`` and its rate, along ``normal`` on the axle;
    longitudinal force (:func:`sliders.forces.laws.tyre_longitudinal`) of the axle's speed
    ``u = v_axle . forward`` and the spin ``omega``, along ``forward`` on the axle; the spin
    moment ``-radius F_x`` about the axis on the wheel."""

    axle: NodeRef
    wheel: NodeRef
    radius: float
    stiffness: float
    damping: float
    B: float
    C: float
    D: float
    speed_eps: float = 0.1
    ground: ArrayLike = (0.0, 0.0, 0.0)
    normal: ArrayLike = (0.0, 0.0, 1.0)
    forward: ArrayLike = (1.0, 0.0, 0.0)
    name: str = "tyre"
    kind: int = field(default=TYRE, init=False)

    def __post_init__(self) -> None:
        parse_node(self.axle, f"{self.name}: axle")
        parse_node(self.wheel, f"{self.name}: wheel")
        self.ground = vector3(self.ground, f"{self.name}: ground")
        self.normal = direction(self.normal, f"{self.name}: normal")
        self.forward = direction(self.forward, f"{self.name}: forward")
        if abs(float(np.dot(self.normal, self.forward))) > 1e-12:
            raise ValueError(f"{self.name}: forward must be normal to the ground's normal")
        laws.tyre_longitudinal(  # the laws check their parameters
            0.0,
            0.0,
            0.0,
            radius=self.radius,
            B=self.B,
            C=self.C,
            D=self.D,
            speed_eps=self.speed_eps,
        )
        laws.tyre_radial(0.0, 0.0, stiffness=self.stiffness, damping=self.damping)

    OUTPUTS = ("Fz", "Fx", "deflection", "slip", "forward_speed", "spin")

    @property
    def axis(self) -> np.ndarray:
        """The wheel's axle direction ``normal x forward``."""
        return np.cross(np.asarray(self.normal, dtype=float), np.asarray(self.forward, dtype=float))

    def outputs(self, structure: Structure, q: np.ndarray, v: np.ndarray) -> dict[str, np.ndarray]:
        """The radial force ``Fz`` and the longitudinal ``Fx`` (forward positive) on the axle,
        the ``deflection`` ``d``, the ``slip`` ratio, the axle's ``forward_speed`` ``u`` and
        the wheel's ``spin`` ``omega``."""
        axle, wheel = structure.node_dofs(self.axle)[:3], structure.node_dofs(self.wheel)[3:]
        q, v = np.asarray(q), np.asarray(v)
        normal, forward = np.asarray(self.normal), np.asarray(self.forward)
        x = structure.node_position(self.axle) + q[..., axle] - np.asarray(self.ground)
        deflection = self.radius - x @ normal
        vertical = laws.tyre_radial(
            deflection, -(v[..., axle] @ normal), stiffness=self.stiffness, damping=self.damping
        )[0]
        u, spin = v[..., axle] @ forward, v[..., wheel] @ self.axis
        tyre = {"radius": self.radius, "speed_eps": self.speed_eps}
        longitudinal = laws.tyre_longitudinal(
            u, spin, vertical, B=self.B, C=self.C, D=self.D, **tyre
        )[0]
        return {
            "Fz": vertical,
            "Fx": longitudinal,
            "deflection": deflection,
            "slip": laws.slip_ratio(u, spin, **tyre)[0],
            "forward_speed": u,
            "spin": spin,
        }

    def slots(self, structure: Structure) -> np.ndarray:
        return np.concatenate(
            [structure.node_dofs(self.axle)[:3], structure.node_dofs(self.wheel)[3:]]
        ).astype(np.int64)

    def packed(self, structure: Structure) -> np.ndarray:
        values = {key: getattr(self, key) for key in PARAMETERS["tyre"]}
        return np.concatenate(
            [
                structure.node_position(self.axle),
                np.asarray(self.ground, dtype=float),
                np.asarray(self.normal, dtype=float),
                np.asarray(self.forward, dtype=float),
                self.axis,
                [values[key] for key in PARAMETERS["tyre"]],
            ]
        )
