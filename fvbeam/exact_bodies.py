"""Rigid bodies with finite rotations, for the statics of exact models.

Each body is a node with a position ``x`` and a rotation ``R`` (the identity in the
reference configuration, where the body's axes are its :class:`~fvbeam.body.RigidBody`'s
``frame``), updated on the manifold as the nodes of an exact beam are
(:class:`~fvbeam.exact_beam.ExactState`): by spatial increments ``[du, dphi]`` in global
axes, ``x <- x + du``, ``R <- exp(dphi) R``.  A body has no internal forces: its balance is
the loads on its node and what the joints holding it carry (:mod:`sliders.joints.exact_model`),
so its residual and its tangent are zero.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import scipy.sparse as sp

from fvbeam.body import RigidBody
from fvbeam.exact_beam import ExactState


class ExactBodies:
    """Rigid bodies as nodes with finite rotations (module docstring), in the order given;
    the operator interface of :class:`~fvbeam.exact_beam.ExactBeam` (six dofs per body)."""

    def __init__(self, bodies: Sequence[RigidBody]) -> None:
        self.bodies = list(bodies)
        self.n_dofs = 6 * len(self.bodies)

    def reference(self) -> ExactState:
        """The bodies' positions, identity rotations."""
        x = np.array([body.position for body in self.bodies], dtype=float).reshape(-1, 3)
        return ExactState(x, np.broadcast_to(np.eye(3), (len(self.bodies), 3, 3)))

    def points(self, state: ExactState) -> None:
        """Nothing to evaluate: a body has no internal forces."""

    def residual(self, state: ExactState, pts: None = None) -> np.ndarray:
        """Zero: a body's balance is its loads and its joints'."""
        return np.zeros(self.n_dofs)

    def residual_floor(self, state: ExactState, pts: None = None) -> np.ndarray:
        """Zero: no internal terms to round."""
        return np.zeros(self.n_dofs)

    def tangent(
        self, state: ExactState, pts: None = None, keep: np.ndarray | None = None
    ) -> sp.csc_matrix:
        """Zero (on the dofs ``keep``, when given)."""
        size = self.n_dofs if keep is None else len(keep)
        return sp.csc_matrix((size, size))

    def mass(self, state: ExactState) -> np.ndarray:
        """Each body's 6x6 mass about ``state`` (k, 6, 6), in the spatial increments
        ``[du, dphi]`` of its node, at rest.

        The body turned by ``R`` carries its centre of mass at ``x + R c`` and its inertia
        about it ``R J R^T`` (``c``, ``J`` the :class:`~fvbeam.body.RigidBody`'s, reference
        axes).  An increment moves the centre by ``du + dphi x (R c)`` and turns the body
        by ``dphi`` (spatial), so its kinetic energy at rest is ``T = m |du' + dphi' x
        (R c)|^2 / 2 + dphi' . (R J R^T) dphi' / 2``: the reference mass
        (:meth:`~fvbeam.body.RigidBody.mass_matrix`) with ``c`` and ``J`` turned,
        ``[[m I, -m S], [m S, R J R^T - m S S]]``, ``S = skew(R c) = R skew(c) R^T``, which is
        ``T M_0 T^T`` with ``T = diag(R, R)``: both blocks turn, the translations' too,
        where a beam node's lumped mass, without coupling, turns only its rotation block.
        """
        T = np.zeros((len(self.bodies), 6, 6))
        T[:, :3, :3] = T[:, 3:, 3:] = state.R
        M0 = np.array([body.mass_matrix() for body in self.bodies]).reshape(-1, 6, 6)
        return T @ M0 @ T.transpose(0, 2, 1)
