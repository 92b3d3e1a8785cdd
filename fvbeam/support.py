"""Supports: the dofs of a structure node held fixed, and how a node is named."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: Names of the six nodal dofs, in order.
DOF_NAMES = ("ux", "uy", "uz", "rx", "ry", "rz")


#: A structure node: ``(beam index, node)`` (node: index, ``'start'`` or ``'end'``) or the
#: name of a rigid body.
NodeRef = tuple[int, int | str] | str


@dataclass(frozen=True)
class Support:
    """A node held fixed: ``clamp`` (all six dofs), ``pin`` (the three translations), or the
    dofs named and joined by ``+`` (from ``ux uy uz rx ry rz``), e.g. ``"ux+rx"``.

    ``Support(beam, node, kind)`` holds a beam node; ``Support("hub", kind=...)`` holds the
    rigid body named ``hub`` (a body is one node, so it takes no ``node``).
    """

    beam: int | str
    node: int | str | None = None
    kind: str = "clamp"

    def __post_init__(self) -> None:
        if isinstance(self.beam, str) and self.node is not None:
            raise ValueError(
                f"support of body {self.beam!r}: a body is a single node, so no "
                f"node is given (got {self.node!r}); write the kind by keyword, "
                f"e.g. Support({self.beam!r}, kind='pin')"
            )
        if not isinstance(self.beam, str) and self.node is None:
            raise ValueError(
                f"support of beam {self.beam!r} needs a node (index, 'start' or 'end')"
            )
        self.dofs()

    @classmethod
    def at(cls, ref: NodeRef, kind: str = "clamp") -> "Support":
        """The support of kind ``kind`` at the structure node ``ref`` (``(beam, node)`` or a
        body name): the inverse of :attr:`ref`."""
        return cls(ref, kind=kind) if isinstance(ref, str) else cls(*ref, kind)

    @property
    def ref(self) -> NodeRef:
        """The supported node as a structure node reference."""
        if isinstance(self.beam, str):
            return self.beam
        assert self.node is not None  # __post_init__: a beam index comes with a node
        return self.beam, self.node

    def dofs(self) -> np.ndarray:
        """Local dof indices (0..5) the support holds."""
        if self.kind == "clamp":
            return np.arange(6)
        if self.kind == "pin":
            return np.arange(3)
        names = self.kind.split("+")
        unknown = [n for n in names if n not in DOF_NAMES]
        if unknown or not names:
            raise ValueError(
                f"support kind must be 'clamp', 'pin' or dof names from "
                f"{' '.join(DOF_NAMES)} joined by '+', got {self.kind!r}"
            )
        return np.array(sorted({DOF_NAMES.index(n) for n in names}))
