"""Compiled per-member work of the condensed Newton step.

:meth:`sliders.solve.condensed.CondensedOperator.step` hands :func:`condensed_step` the joints'
Jacobians as they are stored (:class:`sliders.joints.blocks.SlotJacobian`: the flat ``values`` of
every member, laid out by ``table``) and the cached columns of ``B^{-1}``; per member the
kernel forms and solves the small system of :mod:`sliders.solve.condensed` (module docstring):

    w_c + Y_c u - Phi_c a           = -x_r,c
    Y_z u                           = -z_r
    -C Y_x u + [0, D] u + C Phi a   = -r_y + C x_r

with ``u = [w_c; dy]``, ``Y = B^{-1}[P F; 0]`` and ``C`` read on the slots.  A Jacobian entry
is a force one (``F = [E_c, A]``) in a structure row, an equation one (``C``, ``D``) in an
unknown row.  The structure slots are merged by free dof first: the slots that share a dof
(a node's load, rotation, interpolation and neighbour slots) add their force entries into one
row of ``P F`` and their equation entries into one column of ``C P^T``, and the supported
slots (dof -1) and the zero entries drop out, so ``B^{-1}`` is read only on the distinct dofs
that carry a nonzero entry.  A supported slot in ``c`` has ``w_c = 0`` (its row ``w_c = 0``).
"""

from __future__ import annotations

from typing import NamedTuple

import numba
import numpy as np

from fvbeam.kernel_cache import guard
from fvbeam.scratch import borrowed

guard(__file__)  # numba's cache of these kernels, consistent with their sources


class Columns(NamedTuple):
    """What the condensed step reads of the bordered operator ``B`` (``n`` free dofs, ``k``
    rigid modes)."""

    #: Stored columns of ``B^{-1}`` (as rows, (s, n + k)) and the row of each free dof
    #: (n,) (those of every force dof are stored).
    store: np.ndarray
    column: np.ndarray
    #: The rigid modes (n, k).
    phi: np.ndarray


class Jacobians(NamedTuple):
    """The joints' Jacobians of ``B`` members as they are stored, laid out batch after batch
    (:class:`sliders.solve.condensed._Layout`)."""

    #: Every batch's slot free-dof positions (-1 supported; (k B, t) raveled), Jacobian
    #: ``values`` ((k B, width) raveled) and block ``tables`` ((., 5): first row slot, rows,
    #: first column slot, columns, offset), one batch after the other.
    slots: np.ndarray
    values: np.ndarray
    tables: np.ndarray
    #: Per batch and structure slot, its index among the batch joint's ``c`` slots, or -1.
    c_of: np.ndarray
    #: Per batch (n_batches, 10): joints ``k``, structure slots ``t``, unknowns ``m``, values
    #: ``width``, its offsets into ``slots``, ``values``, ``tables`` (first and last row) and
    #: ``c_of``, and its joints' ``c`` slots.
    batches: np.ndarray
    #: The ``c`` slots of a member, all joints.
    nc: int


class StepScratch(NamedTuple):
    """The views of a condensed step's scratch (:func:`_views`).  A chord step reads what the
    last full step left there."""

    #: The positions of the free dofs among the force and read dofs, those dofs, the ``c``
    #: slots' dofs, the pivots, the counts of force and read dofs.
    where_f: np.ndarray
    where_r: np.ndarray
    fd: np.ndarray
    rd: np.ndarray
    c_dof: np.ndarray
    swaps: np.ndarray
    counts: np.ndarray
    #: ``G = P F``, ``Y``, ``Y^T``, a read row, ``C^T``, ``D``, ``Y_z``.
    G: np.ndarray
    Y: np.ndarray
    Yt: np.ndarray
    read: np.ndarray
    Ct: np.ndarray
    D: np.ndarray
    Y_z: np.ndarray
    #: The small system ``A``, its inverse, right-hand side and row and (reciprocal) column
    #: scales.
    A: np.ndarray
    inverse: np.ndarray
    rhs: np.ndarray
    rows: np.ndarray
    cols: np.ndarray


@numba.njit(inline="never")
def _register(
    dof: int, where: np.ndarray, dofs: np.ndarray, rows: np.ndarray, counts: np.ndarray, kind: int
) -> int:
    """A new free dof appended to the force (``kind`` 0) or read (1) dofs ``dofs``, its row
    of ``rows`` zeroed; returns that row."""
    i = counts[kind]
    where[dof], dofs[i], counts[kind] = i, dof, i + 1
    rows[i] = 0.0
    return i


@numba.njit(inline="never")
def _joint(
    t: int, at: tuple[int, int, int, int, int], table: np.ndarray, jac: Jacobians, v: StepScratch
) -> None:
    """One joint's nonzero Jacobian entries (``jac.values`` from ``v0``, laid out by its
    blocks ``table``: first row slot, rows, first column slot, columns, offset; its ``t``
    slots from ``s0`` in ``jac.slots``) added into the scratch ``v``'s ``G = P F``,
    ``Ct = (C P^T)^T`` and ``D`` (its unknowns from ``y_at``, its ``c`` slots from ``c_at``;
    ``jac.c_of[c0:]`` the index of each structure slot among them), block by block: a block
    of unknown rows and columns goes to ``D``, one of unknown rows and slot columns to ``Ct``
    (a column per free dof), one of slot rows to ``G`` (a row per free dof).  A free dof is
    registered as a force dof ``fd`` or a read dof ``rd`` at its first nonzero entry
    (``counts``: how many of each so far, updated); supported slots drop.  ``at``:
    ``(s0, v0, c0, y_at, c_at)``."""
    s0, v0, c0, y_at, c_at = at
    for block in range(len(table)):
        r0, nr, q0, nq, off = (
            table[block, 0],
            table[block, 1],
            table[block, 2],
            table[block, 3],
            v0 + table[block, 4],
        )
        if r0 >= t and q0 >= t:
            for p in range(nr):
                for q in range(nq):
                    v.D[y_at + r0 - t + p, y_at + q0 - t + q] += jac.values[off + p * nq + q]
        elif r0 >= t:
            for q in range(nq):
                dof = jac.slots[s0 + q0 + q]
                if dof < 0:
                    continue
                i = v.where_r[dof]
                for p in range(nr):
                    value = jac.values[off + p * nq + q]
                    if value == 0.0:
                        continue
                    if i < 0:
                        i = _register(dof, v.where_r, v.rd, v.Ct, v.counts, 1)
                    v.Ct[i, y_at + r0 - t + p] += value
        else:
            for p in range(nr):
                dof = jac.slots[s0 + r0 + p]
                if dof < 0:
                    continue
                i = v.where_f[dof]
                for q in range(nq):
                    value = jac.values[off + p * nq + q]
                    if value == 0.0 or (q0 < t and jac.slots[s0 + q0 + q] < 0):
                        continue
                    if i < 0:
                        i = _register(dof, v.where_f, v.fd, v.G, v.counts, 0)
                    v.G[
                        i, c_at + jac.c_of[c0 + q0 + q] if q0 < t else jac.nc + y_at + q0 - t + q
                    ] += value


@numba.njit(inline="never")
def _gather(b: int, members: int, jac: Jacobians, v: StepScratch) -> None:
    """Member ``b``'s Jacobian entries merged by free dof into the scratch ``v``
    (:func:`_joint`), joints in the order of
    :meth:`sliders.solve.condensed.CondensedOperator.step` (batch after batch, joint ``i`` of
    a batch in its row ``i B + b``), and the free dof of each ``c`` slot (-1 if supported;
    registered as a read dof).  ``counts``: the numbers of force and read dofs."""
    v.counts[0] = v.counts[1] = 0
    v.D[:, :] = 0.0
    y_at = c_at = 0
    for j in range(len(jac.batches)):
        k, t, m, width = jac.batches[j, 0], jac.batches[j, 1], jac.batches[j, 2], jac.batches[j, 3]
        c0, n_c = jac.batches[j, 8], jac.batches[j, 9]
        for i in range(k):
            s0 = jac.batches[j, 4] + (i * members + b) * t
            if n_c:
                for e in range(t):
                    dof = jac.slots[s0 + e]
                    if jac.c_of[c0 + e] >= 0:
                        v.c_dof[c_at + jac.c_of[c0 + e]] = dof
                    if jac.c_of[c0 + e] >= 0 and dof >= 0 and v.where_r[dof] < 0:
                        v.where_r[dof], v.rd[v.counts[1]] = v.counts[1], dof
                        v.Ct[v.counts[1]] = 0.0
                        v.counts[1] += 1
            v0 = jac.batches[j, 5] + (i * members + b) * width
            _joint(
                t,
                (s0, v0, c0, y_at, c_at),
                jac.tables[jac.batches[j, 6] : jac.batches[j, 7]],
                jac,
                v,
            )
            y_at += m
            c_at += n_c


@numba.njit(inline="never")
def _columns(columns: Columns, n: int, v: StepScratch, n_f: int, n_r: int) -> None:
    """The scratch ``v``'s ``Y = B^{-1}[rd, fd] G`` and ``Y_z = B^{-1}[n:, fd] G`` (``n_f``
    force dofs ``fd``, ``n_r`` read dofs ``rd``) from the stored columns of ``B^{-1}``
    (rows of ``columns.store``; ``columns.column``: the row of each free dof), over the
    nonzeros of ``G``.  Each stored column is read once at the read dofs (``read``) and added
    into ``Yt = Y^T`` (contiguous rows), then transposed: every entry sums its terms in the
    order of the force dofs."""
    ncm = v.G.shape[1]
    v.Yt[:, :n_r] = 0.0
    v.Y_z[:, :] = 0.0
    for f in range(n_f):
        at = columns.column[v.fd[f]]
        for r in range(n_r):
            v.read[r] = columns.store[at, v.rd[r]]
        for j in range(ncm):
            g = v.G[f, j]
            if g == 0.0:
                continue
            for r in range(n_r):
                v.Yt[j, r] += v.read[r] * g
            for z in range(v.Y_z.shape[0]):
                v.Y_z[z, j] += columns.store[at, n + z] * g
    for r in range(n_r):
        for j in range(ncm):
            v.Y[r, j] = v.Yt[j, r]


@numba.njit(inline="never")
def _small(base: np.ndarray, r_y: np.ndarray, phi: np.ndarray, v: StepScratch, n_r: int) -> None:
    """One member's small system ``A`` (rows ``c``, rigid, equations; columns ``u_c``,
    ``dy``, rigid amplitudes) and right-hand side ``rhs`` into the scratch ``v`` (module
    docstring; :func:`_small_rhs`), from its base solution ``base = B^{-1}[r_q; 0]``, joint
    residuals ``r_y`` and the ``n_r`` read dofs ``v.rd``."""
    nc, k, m = len(v.c_dof), phi.shape[1], len(r_y)
    ncm = nc + m
    v.A[:, :] = 0.0
    for i in range(nc):
        dof = v.c_dof[i]
        if dof < 0:
            v.A[i, i] = 1.0
            continue
        v.A[i, :ncm] = v.Y[v.where_r[dof]]
        v.A[i, i] += 1.0
        v.A[i, ncm:] = -phi[dof]
    for z in range(k):
        v.A[nc + z, :ncm] = v.Y_z[z]
    for r in range(n_r):
        for y in range(m):
            c = v.Ct[r, y]
            if c == 0.0:
                continue
            row = nc + k + y
            for j in range(ncm):
                v.A[row, j] -= c * v.Y[r, j]
            for z in range(k):
                v.A[row, ncm + z] += c * phi[v.rd[r], z]
    for y in range(m):
        for j in range(m):
            v.A[nc + k + y, nc + j] += v.D[y, j]
    _small_rhs(base, r_y, k, v, n_r)


@numba.njit(inline="never")
def _small_rhs(base: np.ndarray, r_y: np.ndarray, k: int, v: StepScratch, n_r: int) -> None:
    """The right-hand side ``v.rhs`` of the small system (module docstring) with ``k`` rigid
    modes: ``-x_r,c``, ``-z_r`` and ``-r_y + C x_r`` from the base solution ``base =
    B^{-1}[r_q; 0]`` and the joint residuals ``r_y``; the equations' ``C`` (``Ct``, its
    ``n_r`` read dofs ``rd``) and the ``c`` slots' dofs ``c_dof`` as :func:`_gather` left them
    in the scratch ``v``."""
    nc, m = len(v.c_dof), len(r_y)
    n = len(base) - k
    for i in range(nc):
        dof = v.c_dof[i]
        v.rhs[i] = 0.0 if dof < 0 else -base[dof]
    for z in range(k):
        v.rhs[nc + z] = -base[n + z]
    for y in range(m):
        v.rhs[nc + k + y] = 0.0
    for r in range(n_r):
        for y in range(m):
            c = v.Ct[r, y]
            if c != 0.0:
                v.rhs[nc + k + y] += c * base[v.rd[r]]
    for y in range(m):
        v.rhs[nc + k + y] -= r_y[y]


@numba.njit(inline="never")
def _invert(a: np.ndarray, swaps: np.ndarray) -> bool:
    """``a`` replaced by its inverse: Gauss-Jordan elimination with partial pivoting (row
    interchanges, undone on the columns at the end; Higham, Accuracy and Stability of
    Numerical Algorithms, Sec. 14.4); False, and ``a`` undefined, when a pivot is exactly
    zero."""
    n = len(a)
    for k in range(n):
        p, big = k, abs(a[k, k])
        for r in range(k + 1, n):
            if abs(a[r, k]) > big:
                p, big = r, abs(a[r, k])
        if big == 0.0:
            return False
        swaps[k] = p
        if p != k:
            for j in range(n):
                a[p, j], a[k, j] = a[k, j], a[p, j]
        pivot = 1.0 / a[k, k]
        a[k, k] = 1.0
        for j in range(n):
            a[k, j] *= pivot
        for i in range(n):
            factor = a[i, k]
            if i == k or factor == 0.0:
                continue
            a[i, k] = 0.0
            for j in range(n):
                a[i, j] -= factor * a[k, j]
    for k in range(n - 1, -1, -1):
        p = swaps[k]
        if p != k:
            for i in range(n):
                a[i, p], a[i, k] = a[i, k], a[i, p]
    return True


@numba.njit(inline="never")
def _equilibrated_solve(
    A: np.ndarray,
    rhs: np.ndarray,
    threshold: float,
    x: np.ndarray,
    inverse: np.ndarray,
    swaps: np.ndarray,
    rows: np.ndarray,
    cols: np.ndarray,
) -> bool:
    """Solve ``A x = rhs`` after scaling the rows, then the columns, of ``A`` to unit largest
    entries (at least 1e-300); regular when the reciprocal condition number of the scaled
    matrix in the 1-norm, from its exact inverse, is at least ``threshold``.  A singular
    system (exactly, or below the threshold) gives ``x = 0`` and False."""
    n = len(A)
    for i in range(n):
        big = 0.0
        for j in range(n):
            big = max(big, abs(A[i, j]))
        rows[i] = max(big, 1e-300)
    cols[:] = 0.0
    for i in range(n):
        for j in range(n):
            cols[j] = max(cols[j], abs(A[i, j]) / rows[i])
    for j in range(n):
        cols[j] = max(cols[j], 1e-300)
    for j in range(n):
        cols[j] = 1.0 / cols[j]  # reciprocals from here on: a multiply costs less
    for i in range(n):
        scale = 1.0 / rows[i]
        for j in range(n):
            inverse[i, j] = A[i, j] * scale * cols[j]
    norm = _norm_1(inverse, x)
    x[:] = 0.0
    if not _invert(inverse, swaps):
        return False
    if not 1.0 / (norm * _norm_1(inverse, x)) >= threshold:
        x[:] = 0.0
        return False
    _apply_inverse(inverse, rows, cols, rhs, x)
    return True


@numba.njit(inline="never")
def _apply_inverse(
    inverse: np.ndarray, rows: np.ndarray, cols: np.ndarray, rhs: np.ndarray, x: np.ndarray
) -> None:
    """``x = A^{-1} rhs`` from the inverse of the equilibrated ``A`` and its row scales
    ``rows`` and reciprocal column scales ``cols`` (:func:`_equilibrated_solve`)."""
    n = len(inverse)
    for i in range(n):
        total = 0.0
        for j in range(n):
            total += inverse[i, j] * (rhs[j] / rows[j])
        x[i] = total * cols[i]


@numba.njit(inline="never")
def _norm_1(a: np.ndarray, sums: np.ndarray) -> float:
    """The 1-norm of ``a`` (largest column sum of magnitudes; ``sums`` a scratch row)."""
    sums[:] = 0.0
    for i in range(len(a)):
        for j in range(len(a)):
            sums[j] += abs(a[i, j])
    return sums.max()


@numba.njit(cache=True)
def _slot_count(batches: np.ndarray) -> int:
    """The structure slots of a member, all batches (``k t`` each)."""
    size = 0
    for j in range(len(batches)):
        size += batches[j, 0] * batches[j, 1]
    return size


@numba.njit(cache=True)
def step_scratch(
    n: int, batches: np.ndarray, nc: int, m: int, k: int
) -> tuple[np.ndarray, np.ndarray]:
    """The scratch of :func:`condensed_step_into` for ``n`` free dofs, the joints laid out
    by ``batches`` with ``nc`` ``c`` slots and ``m`` unknowns, and ``k`` rigid modes: a float
    and an integer array, the first ``2 n`` integers -1 (no free dof registered yet)."""
    size, ncm = _slot_count(batches), nc + m
    N = ncm + k
    floats = np.empty(3 * size * ncm + size + size * m + m * m + k * ncm + 2 * N * N + 3 * N)
    ints = np.empty(2 * n + 2 * size + nc + N + 2, dtype=np.int64)
    ints[: 2 * n] = -1
    return floats, ints


@numba.njit(inline="always")
def _views(
    n: int, size: int, nc: int, m: int, k: int, floats: np.ndarray, ints: np.ndarray
) -> StepScratch:
    """The arrays of :func:`step_scratch`'s ``floats`` and ``ints`` for ``n`` free dofs,
    ``size`` slots, ``nc`` ``c`` slots, ``m`` unknowns and ``k`` rigid modes, by name
    (:class:`StepScratch`)."""
    ncm = nc + m
    N = ncm + k
    where_f, where_r = borrowed(ints, 0, (n,)), borrowed(ints, n, (n,))
    at = 2 * n
    fd, rd = borrowed(ints, at, (size,)), borrowed(ints, at + size, (size,))
    at += 2 * size
    c_dof, swaps = borrowed(ints, at, (nc,)), borrowed(ints, at + nc, (N,))
    counts = borrowed(ints, at + nc + N, (2,))
    G, Y = borrowed(floats, 0, (size, ncm)), borrowed(floats, size * ncm, (size, ncm))
    at = 2 * size * ncm
    Yt, read = borrowed(floats, at, (ncm, size)), borrowed(floats, at + ncm * size, (size,))
    at += ncm * size + size
    Ct, D = borrowed(floats, at, (size, m)), borrowed(floats, at + size * m, (m, m))
    at += size * m + m * m
    Y_z, A = borrowed(floats, at, (k, ncm)), borrowed(floats, at + k * ncm, (N, N))
    at += k * ncm + N * N
    inverse, rhs = borrowed(floats, at, (N, N)), borrowed(floats, at + N * N, (N,))
    at += N * N + N
    rows, cols = borrowed(floats, at, (N,)), borrowed(floats, at + N, (N,))
    return StepScratch(
        where_f,
        where_r,
        fd,
        rd,
        c_dof,
        swaps,
        counts,
        G,
        Y,
        Yt,
        read,
        Ct,
        D,
        Y_z,
        A,
        inverse,
        rhs,
        rows,
        cols,
    )


@numba.njit(cache=True)
def condensed_step(
    columns: Columns,
    base: np.ndarray,
    r_free: np.ndarray,
    r_y: np.ndarray,
    jac: Jacobians,
    threshold: float,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The small systems of ``B`` members solved (:mod:`sliders.solve.condensed`, module docstring).

    Parameters
    ----------
    columns
        What the step reads of the bordered operator (:class:`Columns`).
    base : (B, n + k)
        ``B^{-1}[r_q; 0]`` per member.
    r_free, r_y : (B, n), (B, m)
        The structure residuals and the joint residuals.
    jac
        The joints' Jacobians and their layout (:class:`Jacobians`).
    threshold : float
        The reciprocal condition number below which a small system is singular.

    Returns
    -------
    ``r_q + P F u`` (B, n), the solutions ``[u_c, dy, a]`` (B, nc + m + k) and which members'
    systems are regular (the solution of the others is zero).  The outputs and the scratch
    of :func:`condensed_step_into`, which does the work, are allocated here.
    """
    members, n = r_free.shape
    m, k = r_y.shape[1], columns.phi.shape[1]
    scratch = step_scratch(n, jac.batches, jac.nc, m, k)
    force = np.empty((members, n))
    z = np.empty((members, jac.nc + m + k))
    regular = np.empty(members, dtype=np.bool_)
    condensed_step_into(columns, base, r_free, r_y, jac, threshold, scratch, (force, z, regular))
    return force, z, regular


@numba.njit(cache=True)
def condensed_step_into(
    columns: Columns,
    base: np.ndarray,
    r_free: np.ndarray,
    r_y: np.ndarray,
    jac: Jacobians,
    threshold: float,
    scratch: tuple[np.ndarray, np.ndarray],
    out: tuple[np.ndarray, np.ndarray, np.ndarray],
) -> None:
    """:func:`condensed_step` into the caller's arrays, without allocating: its outputs
    ``out = (force (B, n), z (B, nc + m + k), regular (B,))`` and its ``scratch``
    (:func:`step_scratch`'s floats and integers: the first ``2 n`` integers, the positions of
    the free dofs among the force and read dofs, are -1 on entry and left so on return), so
    that a Newton loop allocates them once for all its steps."""
    force, z, regular = out
    members, n = r_free.shape
    m, k = r_y.shape[1], columns.phi.shape[1]
    ncm = jac.nc + m
    v = _views(n, _slot_count(jac.batches), jac.nc, m, k, scratch[0], scratch[1])
    force[:, :] = r_free
    z[:, :] = 0.0
    for b in range(members):
        _gather(b, members, jac, v)
        n_f, n_r = v.counts[0], v.counts[1]
        _columns(columns, n, v, n_f, n_r)
        _small(base[b], r_y[b], columns.phi, v, n_r)
        regular[b] = _equilibrated_solve(
            v.A, v.rhs, threshold, z[b], v.inverse, v.swaps, v.rows, v.cols
        )
        _add_forces(v.G, v.fd, n_f, ncm, z[b], force[b])
        for f in range(n_f):
            v.where_f[v.fd[f]] = -1
        for r in range(n_r):
            v.where_r[v.rd[r]] = -1


@numba.njit(cache=True)
def chord_step_into(
    phi: np.ndarray,
    base: np.ndarray,
    r_free: np.ndarray,
    r_y: np.ndarray,
    jac: Jacobians,
    scratch: tuple[np.ndarray, np.ndarray],
    out: tuple[np.ndarray, np.ndarray],
) -> None:
    """The step of one member (``B = 1``) on the small system that :func:`condensed_step_into`
    last formed, inverted and left in its ``scratch`` (a chord step: that system's Jacobian,
    new residuals): ``out = (force, z)``, ``r_q + P F u`` and ``[u_c, dy, a]``, from the
    rigid modes ``phi``, the base solution ``base = B^{-1}[r_q; 0]`` and the residuals
    ``r_free``, ``r_y``, as :func:`condensed_step_into` gives them for that system (``jac``:
    its layout)."""
    force, z = out
    n = r_free.shape[1]
    m, k = r_y.shape[1], phi.shape[1]
    v = _views(n, _slot_count(jac.batches), jac.nc, m, k, scratch[0], scratch[1])
    _small_rhs(base[0], r_y[0], k, v, v.counts[1])
    _apply_inverse(v.inverse, v.rows, v.cols, v.rhs, z[0])
    force[0, :] = r_free[0]
    _add_forces(v.G, v.fd, v.counts[0], jac.nc + m, z[0], force[0])


@numba.njit(inline="never")
def _add_forces(
    G: np.ndarray, fd: np.ndarray, n_f: int, ncm: int, z: np.ndarray, force: np.ndarray
) -> None:
    """``force += P F u``: the rows of ``G = P F`` of the ``n_f`` force dofs ``fd`` times
    ``u``, the first ``ncm`` entries of the small system's solution ``z``."""
    for f in range(n_f):
        total = 0.0
        for j in range(ncm):
            total += G[f, j] * z[j]
        force[fd[f]] += total
