"""Supports: the dofs of a structure node held fixed."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from fvbeam.names import ENDS, NodeRef, is_index, parse_node, suggest

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
        try:
            return held_dofs(self.kind)
        except ValueError as exc:
            raise ValueError(f"support kind {self.kind!r} at {self.ref!r} {exc}") from None


def held_dofs(kind: str) -> np.ndarray:
    """Local dof indices (0..5) a support of ``kind`` holds: ``clamp`` all six, ``pin`` the
    translations, or the dof names joined by ``+``, each once.  Any other ``kind`` raises
    ``ValueError`` saying what is allowed (a phrase to follow the kind: "must be ...")."""
    if kind == "clamp":
        return np.arange(6)
    if kind == "pin":
        return np.arange(3)
    if not isinstance(kind, str):
        raise ValueError(f"must be a string, got {type(kind).__name__}")
    names = kind.split("+")
    unknown = [n for n in names if n not in DOF_NAMES]
    if unknown:
        raise ValueError(
            f"must be 'clamp', 'pin' or dof names from {' '.join(DOF_NAMES)} joined by "
            f"'+'{suggest(unknown[0], ('clamp', 'pin') + DOF_NAMES)}"
        )
    repeated = sorted({n for n in names if names.count(n) > 1}, key=DOF_NAMES.index)
    if repeated:
        raise ValueError(f"names {', '.join(repeated)} more than once: name each dof once")
    return np.array(sorted(DOF_NAMES.index(n) for n in names))


def complement(n: int, dofs: np.ndarray) -> np.ndarray:
    """The dofs ``0 .. n - 1`` not among ``dofs`` (any order, repeats allowed), increasing:
    a mask, linear in ``n`` (``np.setdiff1d`` sorts and hashes, a second per million dofs)."""
    keep = np.ones(n, dtype=bool)
    keep[np.asarray(dofs, dtype=np.int64)] = False
    return np.flatnonzero(keep)
