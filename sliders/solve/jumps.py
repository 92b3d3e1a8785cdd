"""Velocity jumps: drives that start a body with mass moving at once.

A drive prescribes a motion (:mod:`sliders.joints.drives`); the time integrator
(:mod:`sliders.solve.dynamics`) takes the state it starts from as it is.  From a state at rest
(every velocity zero: the static start of a time integration) a motion that leaves the start
with a rate ``v`` (:func:`sliders.joints.drives.initial_rate`: a ``Linear`` motion, a linear
ramp or a table starting at once) sets what it drives to that speed within the first step: the
step's accelerations are of order ``v / h``, the driving force of order ``m v / h`` (an
impulse ``m v``), and the kinetic energy ``m v^2 / 2`` appears from nowhere (no work of the
loads supplies it).  ``m`` is the mass the drive moves: the mass matrix's entry on a driven
dof, or ``l^T M_b l`` for a slider's abscissa, ``M_b`` the mass on the body node's
translations and ``l`` the line's unit tangent there.  Nothing happens with no mass there: a
massless body pushed along a beam (the paper's Figure 2) starts as the motion says.

:func:`velocity_jumps` lists the jumps of a start; :meth:`sliders.solve.dynamics.Dynamics.run`
warns of them (:class:`VelocityJumpWarning`), and a scene refuses them
(:class:`sliders.app.model.Model`).  A state in motion (a restart) is taken as the motion
that led to it left it: its velocities are not compared.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from fvbeam.structure import Structure
from fvbeam.support import DOF_NAMES
from sliders.joints.drives import DofDrive, initial_rate
from sliders.joints.slider import Slider
from sliders.solve.integrator import State
from sliders.solve.mechanism import joint_parts


class VelocityJumpWarning(UserWarning):
    """A drive starts a body with mass moving at once (:func:`velocity_jumps`)."""


@dataclass(frozen=True)
class VelocityJump:
    """A drive (``drive``: a :class:`~sliders.joints.drives.DofDrive`, or the
    :class:`~sliders.joints.slider.Slider` whose abscissa is driven) that leaves a state at
    rest with the ``rate`` (m/s, or rad/s for a rotation) on the ``mass`` it moves (kg, or
    kg m^2)."""

    drive: DofDrive | Slider
    rate: float
    mass: float

    @property
    def energy(self) -> float:
        """The kinetic energy the first step gives the driven mass: ``m v^2 / 2`` (J)."""
        return 0.5 * self.mass * self.rate**2

    def __str__(self) -> str:
        if isinstance(self.drive, Slider):
            what, unit, inertia = f"the body of slider '{self.drive.name}'", "m/s", "kg"
        else:
            what = f"{self.drive.node} {self.drive.dof}"
            unit, inertia = ("m/s", "kg") if self.drive.dof.startswith("u") else ("rad/s", "kg m^2")
        return (
            f"the drive of {what} starts at {self.rate:.4g} {unit} from rest on a mass of "
            f"{self.mass:.4g} {inertia}: the first step sets it moving at once "
            f"({self.energy:.4g} J of kinetic energy from nowhere)"
        )


def velocity_jumps(
    structure: Structure,
    M: sp.spmatrix,
    drives: Sequence[DofDrive],
    sliders: Sequence[Slider],
    state: State,
) -> list[VelocityJump]:
    """The drives that jump a mass from rest at ``state`` (module docstring): none unless
    every velocity of ``state`` is zero; then every dof drive (``drives``) and slider drive
    (the ``sliders`` with one) whose motion leaves ``state.t`` with a nonzero rate on a
    nonzero mass (``M``: the structure's mass matrix)."""
    if np.any(state.v):
        return []
    M = sp.csr_matrix(M)
    jumps = []
    for drive in drives:
        rate = initial_rate(drive.motion, state.t)
        dof = int(structure.node_dofs(drive.node)[DOF_NAMES.index(drive.dof)])
        if rate and M[dof, dof] > 0:
            jumps.append(VelocityJump(drive, rate, float(M[dof, dof])))
    for slider, y in zip(sliders, state.unknowns, strict=True):
        if slider.drive is None:
            continue
        rate = initial_rate(slider.drive, state.t)
        if not rate:
            continue
        ((dofs, _, _, J),) = joint_parts(structure, [slider], state.q, [y])
        t = len(dofs)
        tangent = -J[t + 1 : t + 4, t]  # the position rows x_b - x(xi), their xi column
        tangent = tangent / np.linalg.norm(tangent)
        body = slider.body_dofs(structure)[:3]
        mass = float(tangent @ M[body][:, body].toarray() @ tangent)
        if mass > 0:
            jumps.append(VelocityJump(slider, rate, mass))
    return jumps
