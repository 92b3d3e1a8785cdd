"""Force elements on the exact path: a scene's ``[[force]]`` elements in statics between the
nodes of geometrically exact beams and bodies.

In statics (velocities zero) an element's force depends on its nodes' positions only, and
on their current positions exactly: an axial element acts along the current line between
its nodes (``S = extended - |x_b - x_a|``), a tyre on the axle's current height above the
ground (its longitudinal force, of the slip of speeds that are zero, vanishes).  So
:func:`sliders.forces.kernel.evaluate_element`, read with the nodes' displacements
``x - X`` on its translation slots, gives the exact residual ``r = -force`` and its
Jacobian; the translation increments of the exact path are the displacements' own
(``x <- x + du``), so the Jacobian is the tangent's share as it stands.  A tyre's wheel
rotation slots take no force in statics (no spin).

:class:`WithForces` adds them to an exact operator (an
:class:`~fvbeam.exact_structure.ExactStructure` or an
:class:`~sliders.joints.exact_model.ExactModel`): a
:class:`~fvbeam.exact_statics.StaticOperator` as those are.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
import scipy.sparse as sp

from fvbeam.structure import Structure
from sliders.forces.elements import ForceElement
from sliders.forces.kernel import evaluate_element


class WithForces:
    """The exact ``operator`` with the static force elements ``forces`` of ``structure``
    (module docstring); everything else is the operator's."""

    def __init__(self, operator: Any, forces: Sequence[ForceElement], structure: Structure):
        self.operator = operator
        self.n_dofs: int = operator.n_dofs
        self.position_multipliers: np.ndarray = operator.position_multipliers
        self._X = operator.reference().x.copy()
        self._elements = [
            (f.kind, f.packed(structure), f.slots(structure).astype(np.int64)) for f in forces
        ]

    @property
    def name(self) -> str:
        return str(self.operator.name)

    def reference(self) -> Any:
        return self.operator.reference()

    def points(self, state: Any) -> Any:
        return self.operator.points(state)

    def _evaluated(self, state: Any) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """Each element's slots, residual (6,) and Jacobian (6, 6) at ``state``."""
        u = (state.x - self._X).ravel()
        out = []
        for kind, packed, slots in self._elements:
            q = np.zeros(6)
            translations = slots % 6 < 3
            q[translations] = u[(slots // 6 * 3 + slots % 6)[translations]]
            r, J = np.zeros(6), np.zeros((6, 6))
            evaluate_element(kind, packed, q, np.zeros(6), 0.0, 1.0, r, J)
            out.append((slots, r, J))
        return out

    def residual(self, state: Any, pts: Any = None) -> np.ndarray:
        """The operator's residual and the elements' ``r = -force``."""
        out = np.array(self.operator.residual(state, pts), dtype=float)
        for slots, r, _ in self._evaluated(state):
            np.add.at(out, slots, r)
        return out

    def residual_floor(self, state: Any, pts: Any = None) -> np.ndarray:
        """The operator's floor and the elements' forces (their rounding is ``eps`` times
        them)."""
        out = np.array(self.operator.residual_floor(state, pts), dtype=float)
        for slots, r, _ in self._evaluated(state):
            np.add.at(out, slots, np.abs(r))
        return out

    def tangent(self, state: Any, pts: Any = None, keep: Any = None) -> sp.csc_matrix:
        """The operator's tangent and the elements' Jacobians, on the dofs ``keep``."""
        rows, cols, vals = [], [], []
        for slots, _, J in self._evaluated(state):
            rows.append(np.repeat(slots, 6))
            cols.append(np.tile(slots, 6))
            vals.append(J.ravel())
        if not vals:
            return sp.csc_matrix(self.operator.tangent(state, pts, keep))
        K = sp.csr_matrix(
            (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
            shape=(self.n_dofs, self.n_dofs),
        )
        if keep is not None:
            K = K[keep][:, keep]
        return sp.csc_matrix(self.operator.tangent(state, pts, keep) + K)
