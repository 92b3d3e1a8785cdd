"""Supports: the dofs of a structure node held fixed."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from fvbeam.names import ENDS, NodeRef, is_index, parse_node

#: Names of the six nodal dofs, in order.
DOF_NAMES = ("ux", "uy", "uz", "rx", "ry", "rz")


@dataclass(frozen=True)
class Support:
    """A node held fixed: ``clamp`` (all six dofs), ``pin`` (the three translations), or the
    dofs named and joined by ``+`` (from ``ux uy uz rx ry rz``), e.g. ``"ux+rx"``.

    The node is named as in a scene (:mod:`fvbeam.names`), the kind then by keyword:
    ``Support("C.start")``, ``Support("hub", kind="pin")`` (a body is one node);
    or as ``Support(beam, node, kind)`` with ``beam`` a name or an index and ``node`` an
    index, ``'start'`` or ``'end'``: ``Support("C", "start")``, ``Support(0, 3, "pin")``.
    """

    beam: int | str
    node: int | str | None = None
    kind: str = "clamp"

    def __post_init__(self) -> None:
        if isinstance(self.beam, str) and isinstance(self.node, str) and self.node not in ENDS:
            what = "body" if isinstance(parse_node(self.beam), str) else "node"
            single = "a body is a single node" if what == "body" else "the node is named already"
            raise ValueError(
                f"support of {what} {self.beam!r}: {single}, so no node is given "
                f"(got {self.node!r}); write the kind by keyword, "
                f"e.g. Support({self.beam!r}, kind={self.node!r})"
            )
        if is_index(self.beam) and self.node is None:
            raise ValueError(
                f"support of beam {self.beam!r} needs a node (index, 'start' or 'end')"
            )
        parse_node(self.ref, "support")
        self.dofs()

    @classmethod
    def at(cls, ref: NodeRef, kind: str = "clamp") -> "Support":
        """The support of kind ``kind`` at the structure node ``ref`` (any form of
        :mod:`fvbeam.names`): the inverse of :attr:`ref`."""
        return cls(ref, kind=kind) if isinstance(ref, str) else cls(*ref, kind)

    @property
    def ref(self) -> NodeRef:
        """The supported node as a structure node reference."""
        if self.node is None:
            assert isinstance(self.beam, str)  # __post_init__: a beam index comes with a node
            return self.beam
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
