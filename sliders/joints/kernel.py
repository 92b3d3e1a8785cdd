"""The slider joint's equations, compiled: residuals and Jacobian blocks of ``B`` members.

:meth:`sliders.joints.slider.SliderBatch.joint_inputs` gathers what the joints need (the line
state at ``xi``, the body's displacements, the unknowns:
:class:`sliders.joints.equations.JointInputs`) and
:meth:`~sliders.joints.slider.SliderBatch.joint_equations` calls :func:`joint_equations`,
which writes, member by member, the residual on the slots and the Jacobian blocks of the
joint's pattern (:class:`sliders.joints.blocks.SlotJacobian`: one flat array, ``where[row
group, column group]`` the offset of a block, -1 where it is not in the pattern).

Nothing here states a law.  Each member's point quantities (the body point, the line at
``xi``, the multipliers: :data:`sliders.joints.compiled_laws.POINT`) go to the law of its
kind and orientation, generated from its one statement in :mod:`sliders.joints.equations`
(:mod:`sliders.joints.compiled_laws`), which returns the point rows and their derivatives in
the point quantities.  This kernel then does what
:func:`sliders.joints.equations.scatter` and :func:`~sliders.joints.equations.derive` do on
dual numbers, once for every kind: it puts the rows on the slots (the load through the test
functions ``G``, the section couple through ``W^T``) and chains the derivatives through the
line's maps (``x`` moves with ``xi`` by ``l`` and with the interpolated dofs by ``N``, ``l`` by
``l_/xi`` and ``dN``, ..., ``G`` and ``W`` with ``xi`` by ``G_/xi`` and ``W_/xi``).
``tests/test_joint_reference.py`` holds it to :func:`sliders.joints.equations.joint_reference`
entry by entry.

The kernel writes the blocks ``where`` lays out, which hold the law's sparsity
(:func:`sliders.joints.equations.pattern`, read off the law's derivative; checked once per
layout by :meth:`sliders.joints.blocks.SlotJacobian.index`).

Slot groups, in this order (their first slot ``start`` and ``size``): ``body`` (3), ``turn``
(3, the body's rotations), ``load``, ``rotation``, ``interp``, ``beside``, then the joint's
unknowns ``xi`` (1), ``lam`` (3), ``mu``.  The line's interpolation, recovered tangent and
section rotation are matrices on their slots (``N``, ``T``, ``W``: the Lagrange ``N_a I`` on the
translations, or a cubic element's functions on all six dofs of its nodes); on a cubic chain
the constraint rows read the line's compliance at the contact too (``contact``, theory T13).
"""

from __future__ import annotations

import numba
import numpy as np

from fvbeam.kernel_cache import guard
from fvbeam.scratch import stack_empty
from sliders.joints.compiled_laws import AT_CONSTANT, AT_POINT, AT_ROW, CODES, law

guard(__file__)  # numba's cache of these kernels, consistent with their sources

BODY, TURN, LOAD, ROTATION, INTERP, BESIDE, XI, LAM, MU = range(9)
#: Group names in the order of the indices above (:class:`sliders.joints.blocks.SlotJacobian`).
GROUPS = ("body", "turn", "load", "rotation", "interp", "beside", "xi", "lam", "mu")
KINDS = {"spherical": 0, "classical": 1, "spline": 2}
#: The compiled law of each kind code (:data:`KINDS`) on the ``section`` orientation, and
#: the classical slider's on the ``slope`` orientation.
_SECTION = (
    CODES["spherical", "section"],
    CODES["classical", "section"],
    CODES["spline", "section"],
)
_SLOPE = CODES["classical", "slope"]
# The point quantities' places (sliders.joints.compiled_laws.POINT) and sizes.
_U, _THETA, _X, _L, _L_XI = (AT_POINT[k] for k in ("u", "theta", "x", "l", "l_xi"))
_TANGENT, _THETA_L, _THETA_L_XI = (AT_POINT[k] for k in ("tangent", "theta_L", "theta_L_xi"))
_FLEX, _CONTACT, _R0, _K0 = (AT_POINT[k] for k in ("flex", "contact", "R0", "k0"))
_LAM, _MU = AT_POINT["lam"], AT_POINT["mu"]
_POINTS = _MU + 3
_OFFSET, _FRAME, _REFERENCE, _SCALE = (
    AT_CONSTANT[k] for k in ("offset", "frame", "reference", "scale")
)
# The rows' places (sliders.joints.compiled_laws.ROWS).
_FORCE, _COUPLE, _LINE_LOAD = AT_ROW["body_force"], AT_ROW["body_couple"], AT_ROW["line_load"]
_SECTION_COUPLE, _XI_ROW = AT_ROW["section_couple"], AT_ROW["xi"]
_POSITION, _ORIENTATION = AT_ROW["position"], AT_ROW["orientation"]
_ROWS = _ORIENTATION + 3


@numba.njit(cache=True)
def joint_equations(kind, slope, jacobian, point, index, r, values):
    """Residuals ``r`` (B, t + m) and Jacobian blocks ``values`` (B, size) of ``B`` joints.

    Parameters
    ----------
    kind, slope
        :data:`KINDS` code; ``slope``: the ``slope`` orientation (else ``section``).
    jacobian
        Whether to write ``values`` (else the residuals only).
    point
        What the joints read: :class:`sliders.joints.equations.JointInputs`.
    index
        ``(start, size, where)``: the first slot and size of each group (9,), the block
        offsets (9, 9), -1 outside the pattern (which must hold every block of
        :func:`sliders.joints.equations.pattern`).
    r, values
        Zero outputs, written here.
    """
    start, size, where = index
    code = _SLOPE if slope else _SECTION[kind]
    n_mu = size[MU]
    # stack space as literals (numba's need), checked against the layouts' sizes
    p = stack_empty(69, (_POINTS,), np.float64)
    rate = stack_empty(69, (_POINTS,), np.float64)  # the point quantities' xi-rates
    c = stack_empty(16, (_SCALE + 1,), np.float64)
    rows = stack_empty(22, (_ROWS,), np.float64)
    jac = stack_empty(1518, (_ROWS, _POINTS), np.float64)
    widest = max(size[BODY], size[ROTATION], size[INTERP], size[BESIDE], 3)
    chained = np.empty((_ROWS, widest))  # every row's derivative in one column group
    for i in range(3):
        c[_OFFSET + i] = point.offset[i]
        for e in range(3):
            c[_FRAME + 3 * i + e] = point.frame[i, e]
    c[_SCALE] = point.scale
    # the column groups the pattern writes, the same for every member
    columns = stack_empty(8, (8,), np.int64)
    n_columns = 0
    for column in (BODY, TURN, ROTATION, INTERP, BESIDE, XI, LAM, MU):
        if size[column] > 0 and np.any(where[:, column] >= 0):
            columns[n_columns] = column
            n_columns += 1
    for b in range(len(point.y)):
        _point_quantities(point, b, p, rate)
        for i in range(3):
            c[_REFERENCE + i] = point.reference[b, i]
        jac[:, :] = 0.0
        law(code, p, c, rows, jac)
        _scatter_rows(point, b, rows, n_mu, start, r)
        if not jacobian:
            continue
        for column in columns[:n_columns]:
            _chain(point, b, jac, rate, column, size[column], chained)
            _scatter_blocks(point, b, rows, chained, column, n_mu, index, values)


@numba.njit(cache=True)
def _point_quantities(point, b, p, rate):
    """Member ``b``'s point quantities ``p`` (:data:`sliders.joints.compiled_laws.POINT`) and
    their ``xi``-rates ``rate``: ``x`` by ``l``, ``l`` by ``l_/xi``, ``l_/xi`` by ``l_/xixi``,
    ``l~`` by ``l~_/xi``, ``theta_L = W q`` by ``W_/xi q``, ``theta_L/xi`` by ``W_/xixi q``,
    ``C_L`` and the contact compliance by theirs, ``R_0`` by ``k_0 x R_0``, ``k_0`` by
    ``k_0/xi``; the body's dofs and the multipliers do not move with ``xi``."""
    q, y, W, W_xi, W_xixi = point.q, point.y, point.W, point.W_xi, point.W_xixi
    p[:] = 0.0
    rate[:] = 0.0
    for i in range(3):
        p[_U + i] = q[b, point.body[b, i]]
        p[_THETA + i] = q[b, point.body[b, 3 + i]]
        p[_X + i], rate[_X + i] = point.x[b, i], point.l[b, i]
        p[_L + i], rate[_L + i] = point.l[b, i], point.l_xi[b, i]
        p[_L_XI + i], rate[_L_XI + i] = point.l_xi[b, i], point.l_xixi[b, i]
        p[_TANGENT + i], rate[_TANGENT + i] = point.tangent[b, i], point.tangent_xi[b, i]
        p[_K0 + i], rate[_K0 + i] = point.k0[b, i], point.k0_xi[b, i]
        p[_LAM + i] = y[b, 1 + i]
        for a in range(W.shape[2]):
            dof = q[b, point.rotation_dofs[b, a]]
            p[_THETA_L + i] += W[b, i, a] * dof
            rate[_THETA_L + i] += W_xi[b, i, a] * dof
            p[_THETA_L_XI + i] += W_xi[b, i, a] * dof
            rate[_THETA_L_XI + i] += W_xixi[b, i, a] * dof
        k0 = point.k0[b]
        for e in range(3):
            p[_FLEX + 3 * i + e] = point.flex[b, i, e]
            rate[_FLEX + 3 * i + e] = point.flex_xi[b, i, e]
            p[_R0 + 3 * i + e] = point.R0[b, i, e]
            # (k_0 x R_0)_ie, row i of skew(k_0) times column e of R_0
            i1, i2 = (i + 1) % 3, (i + 2) % 3
            rate[_R0 + 3 * i + e] = k0[i1] * point.R0[b, i2, e] - k0[i2] * point.R0[b, i1, e]
    for i in range(point.contact.shape[1]):
        for e in range(6):
            p[_CONTACT + 6 * i + e] = point.contact[b, i, e]
            rate[_CONTACT + 6 * i + e] = point.contact_xi[b, i, e]
    for j in range(y.shape[1] - 4):
        p[_MU + j] = y[b, 4 + j]


@numba.njit(cache=True)
def _scatter_rows(point, b, rows, n_mu, start, r):
    """Member ``b``'s point rows on its slots (:func:`sliders.joints.equations.scatter`): the
    body's force and couple, the line load through ``G``, the section couple through
    ``W^T``, the ``xi``, position and orientation rows as they are."""
    G, W = point.G, point.W
    for i in range(3):
        r[b, start[BODY] + i] += rows[_FORCE + i]
        r[b, start[TURN] + i] += rows[_COUPLE + i]
        r[b, start[LAM] + i] += rows[_POSITION + i]
    for k in range(G.shape[1]):
        for e in range(6):
            r[b, start[LOAD] + k] += G[b, k, e] * rows[_LINE_LOAD + e]
    for a in range(W.shape[2]):
        for i in range(3):
            r[b, start[ROTATION] + a] += W[b, i, a] * rows[_SECTION_COUPLE + i]
    r[b, start[XI]] += rows[_XI_ROW]
    for j in range(n_mu):
        r[b, start[MU] + j] += rows[_ORIENTATION + j]


@numba.njit(cache=True)
def _chain(point, b, jac, rate, column, width, out):
    """Every point row's derivative in the dofs of one column group, ``out[:, :width]``: the
    law's derivatives ``jac`` in the point quantities times theirs in the group's dofs (the
    body's and the multipliers' own, ``W`` and ``W_/xi`` on the rotation dofs, ``N``, ``dN``,
    ``d2N`` and ``T`` on the interpolated dofs, ``T`` beside them, the ``xi``-rates)."""
    out[:, :width] = 0.0
    m = point.N.shape[2]
    for i in range(jac.shape[0]):
        for j in range(width):
            s = 0.0
            if column == BODY:
                s = jac[i, _U + j]
            elif column == TURN:
                s = jac[i, _THETA + j]
            elif column == LAM:
                s = jac[i, _LAM + j]
            elif column == MU:
                s = jac[i, _MU + j]
            elif column == XI:
                for a in range(_POINTS):
                    s += jac[i, a] * rate[a]
            elif column == ROTATION:
                for e in range(3):
                    s += jac[i, _THETA_L + e] * point.W[b, e, j]
                    s += jac[i, _THETA_L_XI + e] * point.W_xi[b, e, j]
            elif column == INTERP:
                for e in range(3):
                    s += jac[i, _X + e] * point.N[b, e, j] + jac[i, _L + e] * point.dN[b, e, j]
                    s += jac[i, _L_XI + e] * point.d2N[b, e, j]
                    s += jac[i, _TANGENT + e] * point.T[b, e, j]
            else:  # BESIDE
                for e in range(3):
                    s += jac[i, _TANGENT + e] * point.T[b, e, m + j]
            out[i, j] = s


@numba.njit(cache=True)
def _scatter_blocks(point, b, rows, chained, column, n_mu, index, values):
    """Member ``b``'s Jacobian blocks in one column group: the rows' derivatives ``chained``
    put on the row groups as :func:`_scatter_rows` puts the rows (the load through ``G`` and
    the section couple through ``W^T``, plus ``G_/xi`` and ``W_/xi^T`` of the rows in the
    ``xi`` column), written where the pattern has a block."""
    start, size, where = index
    G, W = point.G, point.W
    width = size[column]
    for row, first, count in (
        (BODY, _FORCE, 3),
        (TURN, _COUPLE, 3),
        (XI, _XI_ROW, 1),
        (LAM, _POSITION, 3),
        (MU, _ORIENTATION, n_mu),
    ):
        at = where[row, column]
        if at >= 0:
            for i in range(count):
                for j in range(width):
                    values[b, at + i * width + j] += chained[first + i, j]
    at = where[LOAD, column]
    if at >= 0:
        for k in range(G.shape[1]):
            for j in range(width):
                s = 0.0
                for e in range(6):
                    s += G[b, k, e] * chained[_LINE_LOAD + e, j]
                    if column == XI:
                        s += point.dG[b, k, e] * rows[_LINE_LOAD + e]
                values[b, at + k * width + j] += s
    at = where[ROTATION, column]
    if at >= 0:
        for a in range(W.shape[2]):
            for j in range(width):
                s = 0.0
                for e in range(3):
                    s += W[b, e, a] * chained[_SECTION_COUPLE + e, j]
                    if column == XI:
                        s += point.W_xi[b, e, a] * rows[_SECTION_COUPLE + e]
                values[b, at + a * width + j] += s
