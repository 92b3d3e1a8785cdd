"""A joint's Jacobian on its slots, kept by blocks of slot groups in one flat array.

A joint (:meth:`sliders.joints.slider.SliderBatch.evaluate`) writes its residual on fixed *slots*:
groups of structure dofs (the body's translations and rotations, the line's load, rotation
and tangent dofs) followed by groups of its own unknowns (``xi``, ``lambda``, ``mu``).  Its
Jacobian is mostly structurally zero: 63 x 63 per member for a classical joint on fv3 with a
few hundred entries that are not.  :class:`SlotJacobian` keeps only the blocks (row group,
column group) of a *pattern* the joint declares, so the pattern is known from the groups
without reading the values.  The blocks lie one after the other in one ``(B, size)`` array
(``values``), described by ``table`` (one row per block: first row slot, rows, first column
slot, columns, offset of its row-major entries), which the compiled kernels read and write
directly (:mod:`sliders.joints.kernel`, :mod:`sliders.solve.condensed_kernel`); ``blocks`` holds
numpy views of the same entries.  The dense matrix (:meth:`SlotJacobian.dense`) is assembled
from the blocks for the bordered back end, :meth:`sliders.joints.slider.Slider.assemble` and the
finite-difference tests.
"""

from __future__ import annotations

import copy
from collections.abc import Sequence
from functools import lru_cache

import numpy as np


class SlotJacobian:
    """Derivative of ``[r_q(slots); r_y]`` in ``[q(slots); y]`` for ``B`` members, by blocks.

    ``structure`` and ``unknowns``: the ordered ``(name, size)`` slot groups of the structure
    dofs and of the joint's unknowns; the dense matrix has them in that order, rows and
    columns alike.  ``pattern``: the ``(row group, column group)`` blocks that may be
    nonzero, each stored once, zero to start with.  A block of a group that is not among the
    slots, and writing a block outside the pattern (:meth:`block`; a kernel's blocks,
    :meth:`index`), are errors (``ValueError`` naming the block and the pattern).
    """

    def __init__(
        self,
        members: int,
        structure: Sequence[tuple[str, int]],
        unknowns: Sequence[tuple[str, int]],
        pattern: Sequence[tuple[str, str]],
    ) -> None:
        self.members = members
        self.structure = [name for name, _ in structure]
        self.unknowns = [name for name, _ in unknowns]
        self._key = (tuple(structure) + tuple(unknowns), tuple(pattern), len(self.structure))
        self.size, self.at, self.n, self.pattern, self.table = _layout(*self._key[:2])
        self._views(np.zeros((members, int(self.table[:, 1] @ self.table[:, 3]))))

    def _views(self, values: np.ndarray) -> None:
        """Keep ``values`` (B, size); its block views are made when first asked for."""
        self.values = values
        self._blocks: dict[tuple[str, str], np.ndarray] | None = None

    @property
    def blocks(self) -> dict[tuple[str, str], np.ndarray]:
        """The (B, rows, cols) view of each block of the pattern, by ``(rows, cols)``."""
        if self._blocks is None:
            values = self.values
            self._blocks = {
                key: values[:, o : o + nr * nc].reshape(len(values), nr, nc)
                for key, (_, nr, _, nc, o) in zip(self.pattern, self.table, strict=True)
            }
        return self._blocks

    def index(
        self, groups: Sequence[str], writes: Sequence[tuple[str, str]] = ()
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """For a kernel: the first slot and size of each of ``groups`` (g,), and the
        offset of block ``(groups[i], groups[j])`` in ``values`` at ``[i, j]`` (g, g), -1
        where it is not in the pattern.  ``writes``: the blocks the kernel writes, which
        must all have an offset (``ValueError`` naming the first that has none and the
        pattern, checked once per layout)."""
        return _index(*self._key[:2], tuple(groups), tuple(writes))

    def block(self, rows: str, cols: str) -> np.ndarray:
        """The (B, rows, cols) block of the pattern (a view, to write into)."""
        try:
            return self.blocks[rows, cols]
        except KeyError:
            raise ValueError(
                f"block ({rows}, {cols}) is not in the joint's pattern {self.pattern}"
            ) from None

    def unit_row(self, row: str, members: np.ndarray | slice = slice(None)) -> None:
        """Replace the derivatives of the one-row group ``row`` of the given ``members`` by
        the unit derivative in its own unknown (an equation ``y_row - value``)."""
        for (rows, _), block in self.blocks.items():
            if rows == row:
                block[members] = 0.0
        self.block(row, row)[members, 0, 0] = 1.0

    def subset(self, members: np.ndarray | slice) -> SlotJacobian:
        """The Jacobian of the given members only."""
        out = copy.copy(self)
        out._views(self.values[members])
        out.members = len(out.values)
        return out

    def coupling(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The structure slots of the groups with a block in a structure row (``c``: the
        displacements the slot forces depend on), of the groups with a block in their rows
        (the slots that carry forces), and the index of each structure slot among the ``c``
        slots (-1 for the others): the pattern of the equations, whatever the values, once
        per layout."""
        return _coupling(*self._key)

    def dense(self) -> np.ndarray:
        """The whole (B, n, n) matrix on the slots."""
        out = np.zeros((self.members, self.n, self.n))
        for (r, c), block in self.blocks.items():
            out[:, self.at[r], self.at[c]] = block
        return out


@lru_cache(maxsize=64)
def _layout(
    groups: tuple[tuple[str, int], ...], pattern: tuple[tuple[str, str], ...]
) -> tuple[dict, dict, int, list, np.ndarray]:
    """Sizes and slots of the ``groups``, their number, the pattern without repeats and its
    table (:class:`SlotJacobian`), once per layout."""
    size, at, start = {}, {}, 0
    for name, n in groups:
        size[name], at[name] = n, slice(start, start + n)
        start += n
    blocks = list(dict.fromkeys(pattern))
    for r, c in blocks:
        if r not in at or c not in at:
            raise ValueError(
                f"block ({r}, {c}) of the pattern {blocks} names a group that is not among "
                f"the slots ({', '.join(at)})"
            )
    rows, offset = [], 0
    for r, c in blocks:
        rows.append((at[r].start, size[r], at[c].start, size[c], offset))
        offset += size[r] * size[c]
    return size, at, start, blocks, np.array(rows, dtype=np.int64).reshape(-1, 5)


@lru_cache(maxsize=64)
def _index(
    groups: tuple[tuple[str, int], ...],
    pattern: tuple[tuple[str, str], ...],
    names: tuple[str, ...],
    writes: tuple[tuple[str, str], ...],
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:meth:`SlotJacobian.index` of the groups ``names`` for a kernel that ``writes`` those
    blocks, read from :func:`_layout`, once per layout."""
    size, at, _, blocks, table = _layout(groups, pattern)
    where = np.full((len(names), len(names)), -1, dtype=np.int64)
    for (r, c), row in zip(blocks, table, strict=True):
        where[names.index(r), names.index(c)] = row[4]
    for r, c in writes:
        if r not in names or c not in names or where[names.index(r), names.index(c)] < 0:
            raise ValueError(
                f"the kernel writes block ({r}, {c}), which is not in the pattern {blocks}"
            )
    return (
        np.array([at[g].start for g in names], dtype=np.int64),
        np.array([size[g] for g in names], dtype=np.int64),
        where,
    )


@lru_cache(maxsize=64)
def _coupling(
    groups: tuple[tuple[str, int], ...], pattern: tuple[tuple[str, str], ...], n_structure: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:meth:`SlotJacobian.coupling`, once per layout."""
    _, at, _, _, _ = _layout(groups, pattern)
    names = [name for name, _ in groups[:n_structure]]
    read = {c for r, c in pattern if r in names}
    rows = {r for r, _ in pattern}

    def slots(chosen: list[str]) -> np.ndarray:
        return np.concatenate(
            [np.arange(at[g].start, at[g].stop) for g in chosen] + [np.zeros(0, dtype=np.int64)]
        ).astype(np.int64)

    c = slots([g for g in names if g in read])
    index = np.full(sum(n for _, n in groups[:n_structure]), -1, dtype=np.int64)
    index[c] = np.arange(len(c))
    return c, slots([g for g in names if g in rows]), index
