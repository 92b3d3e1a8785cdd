"""Probes: extra ``history.csv`` columns, one value of each recorded state.

A probe is either a function of the state and the dynamics, or a :class:`LinearProbe`: a
value linear in the displacements ``q``, given by its weights on the global dofs.  The
recorder evaluates all the linear ones of a step with one product
(:class:`sliders.app.history.Recorder`).  A scene's probes (``[[output.probe]]``,
``docs/scenes.md``) are linear: a node's displacement or rotation (:func:`node_probe`), or an
internal force at a beam's recovery point (:func:`force_probe`: a row of the beam's recovery
map, :attr:`fvbeam.beam.Beam.recovery`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp

from fvbeam.names import NodeRef, suggest
from fvbeam.structure import Structure
from fvbeam.support import DOF_NAMES
from sliders.app.state_tables import FORCE_NAMES
from sliders.forces.elements import ForceElement

if TYPE_CHECKING:
    from sliders.solve.dynamics import Dynamics
    from sliders.solve.integrator import State


@dataclass(frozen=True)
class LinearProbe:
    """A value linear in the displacements: ``weights @ q``, ``weights`` a ``(1, n_dofs)``
    sparse row on the global dofs."""

    weights: sp.csr_matrix


#: The rates of a node's dofs (:data:`fvbeam.support.DOF_NAMES`): velocity and angular
#: velocity, global axes.
VELOCITY_NAMES = ("vx", "vy", "vz", "wx", "wy", "wz")

#: A probe: a function of the state and the dynamics, or linear in ``q``.
Probe = Callable[["State", "Dynamics"], float] | LinearProbe


def node_probe(structure: Structure, node: NodeRef, dof: str) -> LinearProbe:
    """The dof ``dof`` (``ux`` ... ``rz``) of ``node`` (a body's name, ``BEAM.start``,
    ``BEAM.end``, or ``(beam, node)``)."""
    if dof not in DOF_NAMES:
        raise ValueError(
            f"dof {dof!r}: must be one of {', '.join(DOF_NAMES)}{suggest(dof, DOF_NAMES)}"
        )
    column = structure.node_dofs(node)[DOF_NAMES.index(dof)]
    return LinearProbe(sp.csr_matrix(([1.0], ([0], [column])), shape=(1, structure.n_dofs)))


def force_probe(structure: Structure, beam: int | str, at: float, force: str) -> LinearProbe:
    """The internal force ``force`` (:data:`sliders.app.state_tables.FORCE_NAMES`, section
    frame) at the recovery point of ``beam`` nearest the abscissa ``at``."""
    if force not in FORCE_NAMES:
        raise ValueError(
            f"force {force!r}: must be one of {', '.join(FORCE_NAMES)}{suggest(force, FORCE_NAMES)}"
        )
    index = structure.beam_index(beam)
    part = structure.beams[index]
    point = int(np.argmin(np.abs(part.recovery_abscissae - at)))
    row = part.recovery[6 * point + FORCE_NAMES.index(force)].tocoo()
    columns = structure.dof_maps[index][row.col]
    return LinearProbe(
        sp.csr_matrix((row.data, (np.zeros_like(columns), columns)), shape=(1, structure.n_dofs))
    )


def velocity_probe(structure: Structure, node: NodeRef, rate: str) -> Probe:
    """The rate ``rate`` (:data:`VELOCITY_NAMES`: ``vx`` ... ``wz``) of ``node``'s dofs."""
    if rate not in VELOCITY_NAMES:
        raise ValueError(
            f"velocity {rate!r}: must be one of {', '.join(VELOCITY_NAMES)}"
            f"{suggest(rate, VELOCITY_NAMES)}"
        )
    column = int(structure.node_dofs(node)[VELOCITY_NAMES.index(rate)])

    def probe(state: State, dynamics: Dynamics) -> float:
        return float(state.v[column])

    return probe


class ElementOutputs:
    """A force element's outputs (:meth:`sliders.forces.elements.ForceElement.outputs`) at
    the last state asked for: the probes of one element evaluate it once per state."""

    def __init__(self, element: ForceElement) -> None:
        self.element = element
        self.state: State | None = None
        self.values: dict[str, np.ndarray] = {}

    def __call__(self, state: State, dynamics: Dynamics) -> dict[str, np.ndarray]:
        if state is not self.state:
            self.values = self.element.outputs(dynamics.structure, state.q, state.v)
            self.state = state
        return self.values


def element_probe(element: ForceElement, value: str, shared: ElementOutputs | None = None) -> Probe:
    """The output ``value`` of a force element (its ``OUTPUTS``:
    :meth:`sliders.forces.elements.ForceElement.outputs`) at the state; ``shared``: the
    element's outputs shared with its other probes."""
    if value not in element.OUTPUTS:
        raise ValueError(
            f"{element.name}: value {value!r} must be one of {', '.join(element.OUTPUTS)}"
            f"{suggest(value, element.OUTPUTS)}"
        )
    outputs = shared if shared is not None else ElementOutputs(element)

    def probe(state: State, dynamics: Dynamics) -> float:
        return float(outputs(state, dynamics)[value])

    return probe
