"""Rigid bodies: structure nodes with six dofs that belong to no beam."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from fvbeam.geometry import inertia3, orthonormal3, skew_matrices, vector3


@dataclass(frozen=True, eq=False)
class RigidBody:
    """A rigid body: one node of a :class:`~fvbeam.structure.Structure` with the six dofs
    ``ux uy uz rx ry rz`` (small displacement and rotation of the node, linear kinematics like
    the beams), attached to the rest only through ties, supports and joints.

    Parameters
    ----------
    name
        Unique name in its structure; ties, supports and sliders refer to the body by it.
    position
        The node in the reference configuration, global axes.
    mass
        Mass, >= 0 (stored for dynamics; statics does not use it).
    inertia
        3x3 inertia about the centre of mass in global axes, symmetric positive
        semi-definite (stored for dynamics).
    frame
        Optional body axes (columns), an orthonormal 3x3 matrix.
    centre
        Centre of mass relative to the node, global axes (default: at the node).
    """

    name: str
    position: np.ndarray
    mass: float = 0.0
    inertia: np.ndarray = field(default_factory=lambda: np.zeros((3, 3)))
    frame: np.ndarray | None = None
    centre: np.ndarray = field(default_factory=lambda: np.zeros(3))

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name:
            raise ValueError(f"a rigid body's name must be a non-empty string, got {self.name!r}")
        label = f"body {self.name!r}"
        try:
            mass = float(self.mass)
        except (TypeError, ValueError):
            mass = np.nan
        if not (np.isfinite(mass) and mass >= 0):
            raise ValueError(f"{label}: mass must be finite and >= 0, got {self.mass!r}")
        values = {
            "position": vector3(self.position, f"{label}: position").copy(),
            "mass": mass,
            "inertia": inertia3(self.inertia, f"{label}: inertia"),
            "centre": vector3(self.centre, f"{label}: centre").copy(),
        }
        if self.frame is not None:
            values["frame"] = orthonormal3(self.frame, f"{label}: frame")
        for key, value in values.items():
            if isinstance(value, np.ndarray):
                value.setflags(write=False)
            object.__setattr__(self, key, value)

    def mass_matrix(self) -> np.ndarray:
        """6x6 mass matrix on the node's ``[u, theta]``: the centre of mass moves with
        ``u + theta x c``, so ``T = m |u' + theta' x c|^2 / 2 + theta' . J theta' / 2`` gives
        ``[[m I, -m S], [m S, J - m S S]]`` with ``S = skew(c)``."""
        S = skew_matrices(self.centre)
        return np.block(
            [
                [self.mass * np.eye(3), -self.mass * S],
                [self.mass * S, self.inertia - self.mass * S @ S],
            ]
        )
