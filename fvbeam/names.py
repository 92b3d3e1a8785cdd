"""How the parts of a structure are named: node references, and the did-you-mean of a name.

A node is named as in a scene (``docs/scenes.md``) or by indices:

* ``"C.start"``, ``"C.end"``: an end vertex of the beam named ``C`` (its mesh's ``name``);
* ``"hub"``: the rigid body named ``hub``;
* ``(beam, node)``: ``beam`` a beam's name or its index in the structure, ``node`` a mesh
  node index, ``'start'`` or ``'end'``.

:func:`parse_node` checks the form of a reference; :meth:`fvbeam.structure.Structure.resolve_node`
finds what it names.
"""

from __future__ import annotations

import difflib
from collections.abc import Iterable, Sequence
from typing import Any

import numpy as np

#: A structure node: ``'beam.start'``, ``'beam.end'`` or a body's name, or ``(beam, node)``
#: with ``beam`` a name or an index and ``node`` an index, ``'start'`` or ``'end'``.
NodeRef = str | tuple[int | str, int | str]
#: The named nodes of a beam: its two end vertices.
ENDS = ("start", "end")

_FORMS = (
    "'BEAM.start', 'BEAM.end', a rigid body's name, or (beam, node) with beam a name or an "
    "index and node an index, 'start' or 'end'"
)


def is_index(value: Any) -> bool:
    """``value`` is an integer (a Python or numpy one; not a bool)."""
    return isinstance(value, (int, np.integer)) and not isinstance(value, bool)


def parse_node(ref: Any, owner: str = "") -> str | tuple[int | str, int | str]:
    """The form of a node reference: ``(beam, node)`` for a beam's node (``"C.end"`` gives
    ``("C", "end")``), the name for a body.  Only the form is checked, not that the beam or
    body exists (:meth:`fvbeam.structure.Structure.resolve_node` does).

    Raises ``ValueError`` naming ``ref`` (and the ``owner`` of the reference, if given) when
    it has none of the forms (module docstring).
    """
    where = f"{owner}: " if owner else ""
    if isinstance(ref, str):
        beam, dot, end = ref.rpartition(".")
        if not dot and ref:
            return ref
        if dot and beam and end in ENDS:
            return beam, end
    elif isinstance(ref, (tuple, list)) and len(ref) == 2:
        beam, node = ref
        if not (is_index(beam) or (isinstance(beam, str) and beam)):
            raise ValueError(f"{where}beam {beam!r} of node {ref!r} must be a name or an index")
        if not (is_index(node) or (isinstance(node, str) and node in ENDS)):
            raise ValueError(
                f"{where}node {node!r} of beam {beam!r} is not 'start', 'end' or an index"
            )
        return beam, node
    raise ValueError(f"{where}node reference {ref!r} must be {_FORMS}")


def suggest(word: Any, choices: Iterable[str]) -> str:
    """``" (did you mean 'x'?)"`` for the closest of ``choices`` to ``word``, or ``""``."""
    if not isinstance(word, str):
        return ""
    choices = list(choices)
    same = [c for c in choices if c.lower() == word.lower()]
    close = same or difflib.get_close_matches(word, choices, n=1, cutoff=0.6)
    return f" (did you mean {close[0]!r}?)" if close else ""


def known(names: Sequence[str]) -> str:
    """``names`` listed for a message: ``'a', 'b'``, or ``none``."""
    return ", ".join(repr(n) for n in names) or "none"
