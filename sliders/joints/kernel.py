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
from sliders.joints.compiled_laws import (
    AT_CONSTANT,
    AT_POINT,
    AT_ROW,
    CODES,
    DERIVATIVE_OF,
    DERIVATIVE_ROW,
    DERIVATIVES,
    POINT,
    ROWS,
    law,
)

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
#: How each point quantity moves with the dofs besides ``xi`` (:func:`_chain`): as one dof of
#: its own group (the body's displacement and rotation, the multipliers), through a line map
#: on the interpolated dofs (``x`` by ``N``, ``l`` by ``dN``, ``l_/xi`` by ``d2N``, ``l~`` by
#: ``T``, which reaches the dofs beside them too) or on the rotation dofs (``theta_L`` by
#: ``W``, ``theta_L/xi`` by ``W_/xi``), or with ``xi`` alone.
_OWN, _BY_N, _BY_DN, _BY_D2N, _BY_T, _BY_W, _BY_W_XI, _XI_ONLY = range(8)
_WAYS = {
    "u": (_OWN, BODY),
    "theta": (_OWN, TURN),
    "x": (_BY_N, INTERP),
    "l": (_BY_DN, INTERP),
    "l_xi": (_BY_D2N, INTERP),
    "tangent": (_BY_T, INTERP),
    "theta_L": (_BY_W, ROTATION),
    "theta_L_xi": (_BY_W_XI, ROTATION),
    "lam": (_OWN, LAM),
    "mu": (_OWN, MU),
}
_WAY = np.full(_POINTS, _XI_ONLY)
_OWN_GROUP = np.full(_POINTS, -1)
_COMPONENT = np.zeros(_POINTS, dtype=np.int64)
for _name, _size in POINT:
    _at = AT_POINT[_name]
    _COMPONENT[_at : _at + _size] = np.arange(_size)
    _WAY[_at : _at + _size], _OWN_GROUP[_at : _at + _size] = _WAYS.get(_name, (_XI_ONLY, -1))
#: The row group of each point row (:data:`sliders.joints.compiled_laws.ROWS`) and its
#: component there.
_ROW_GROUPS = {
    "body_force": BODY,
    "body_couple": TURN,
    "line_load": LOAD,
    "section_couple": ROTATION,
    "xi": XI,
    "position": LAM,
    "orientation": MU,
}
_ROW_GROUP = np.zeros(_ROWS, dtype=np.int64)
_ROW_COMPONENT = np.zeros(_ROWS, dtype=np.int64)
for _name, _size in ROWS:
    _at = AT_ROW[_name]
    _ROW_GROUP[_at : _at + _size] = _ROW_GROUPS[_name]
    _ROW_COMPONENT[_at : _at + _size] = np.arange(_size)


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
    d = stack_empty(256, (DERIVATIVE_ROW.shape[1],), np.float64)
    for i in range(3):
        c[_OFFSET + i] = point.offset[i]
        for e in range(3):
            c[_FRAME + 3 * i + e] = point.frame[i, e]
    c[_SCALE] = point.scale
    for b in range(len(point.y)):
        _point_quantities(point, b, p, rate)
        for i in range(3):
            c[_REFERENCE + i] = point.reference[b, i]
        law(code, p, c, rows, d)
        _scatter_rows(point, b, rows, n_mu, start, r)
        if jacobian:
            _chain(point, b, code, d, rate, rows, index, values)


@numba.njit(cache=True, inline="always")
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


@numba.njit(cache=True, inline="always")
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


@numba.njit(cache=True, inline="always")
def _chain(point, b, code, d, rate, rows, index, values):
    """Member ``b``'s Jacobian blocks: each nonzero derivative ``d`` of a point row in a point
    quantity (:data:`sliders.joints.compiled_laws.DERIVATIVE_ROW`, ``DERIVATIVE_OF``) times
    that quantity's derivatives in the dofs (:data:`_WAYS`: the body's and the multipliers'
    own, ``N``, ``dN``, ``d2N`` and ``T`` on the interpolated dofs, ``T`` beside them, ``W``
    and ``W_/xi`` on the rotation dofs; in ``xi`` its rate), put on the row groups as
    :func:`_scatter_rows` puts the row, where the pattern has the block: the line load's and
    the section couple's rows gathered first (``through``), then put through ``G`` and
    ``W^T`` with the ``xi``-derivatives of those maps, ``G_/xi`` and ``W_/xi^T``."""
    start, size, where = index
    G, W, W_xi, T = point.G, point.W, point.W_xi, point.T
    N, dN, d2N = point.N, point.dN, point.d2N
    m, beside, rotation = size[INTERP], size[BESIDE], size[ROTATION]
    # the columns of every group side by side from ``first`` (the load is no column)
    first = stack_empty(10, (10,), np.int64)
    first[0] = 0
    for group in range(9):
        first[group + 1] = first[group] + (size[group] if group != LOAD else 0)
    # the line load's six rows and the section couple's three, in every column
    through = stack_empty(1152, (9, first[9]), np.float64)  # 9 rows, 128 columns
    for i in range(9):
        for j in range(first[9]):
            through[i, j] = 0.0
    row_of, of = DERIVATIVE_ROW[code], DERIVATIVE_OF[code]
    for k in range(DERIVATIVES[code]):
        i, a, v = row_of[k], of[k], d[k]
        way, e = _WAY[a], _COMPONENT[a]
        group, r = _ROW_GROUP[i], _ROW_COMPONENT[i]
        if group == LOAD or group == ROTATION:
            h = r if group == LOAD else 6 + r
            if way == _OWN:
                through[h, first[_OWN_GROUP[a]] + e] += v
            else:
                through[h, first[XI]] += v * rate[a]
            if way == _BY_W or way == _BY_W_XI:
                for j in range(rotation):
                    slope = W[b, e, j] if way == _BY_W else W_xi[b, e, j]
                    through[h, first[ROTATION] + j] += v * slope
            elif way == _BY_T:
                for j in range(beside):
                    through[h, first[BESIDE] + j] += v * T[b, e, m + j]
            if way == _BY_N or way == _BY_DN or way == _BY_D2N or way == _BY_T:
                M = N if way == _BY_N else dN if way == _BY_DN else d2N if way == _BY_D2N else T
                for j in range(m):
                    through[h, first[INTERP] + j] += v * M[b, e, j]
            continue
        # a row put as it is: straight into its blocks
        if way == _OWN:
            column = _OWN_GROUP[a]
            at = where[group, column]
            if at >= 0:
                values[b, at + r * size[column] + e] += v
            continue
        at = where[group, XI]
        if at >= 0:
            values[b, at + r] += v * rate[a]
        if way == _BY_W or way == _BY_W_XI:
            at = where[group, ROTATION]
            if at >= 0:
                for j in range(rotation):
                    slope = W[b, e, j] if way == _BY_W else W_xi[b, e, j]
                    values[b, at + r * rotation + j] += v * slope
        elif way == _BY_T:
            at = where[group, BESIDE]
            if at >= 0:
                for j in range(beside):
                    values[b, at + r * beside + j] += v * T[b, e, m + j]
        if way == _BY_N or way == _BY_DN or way == _BY_D2N or way == _BY_T:
            at = where[group, INTERP]
            if at >= 0:
                M = N if way == _BY_N else dN if way == _BY_DN else d2N if way == _BY_D2N else T
                for j in range(m):
                    values[b, at + r * m + j] += v * M[b, e, j]
    # the gathered rows through G and W^T, skipping a zero factor (the maps' sparsity)
    for column in (BODY, TURN, ROTATION, INTERP, BESIDE, XI, LAM, MU):
        width, j0 = size[column], first[column]
        at = where[LOAD, column]
        if at >= 0:
            for e in range(6):
                for q in range(G.shape[1]):
                    g = G[b, q, e]
                    if g != 0.0:
                        for j in range(width):
                            values[b, at + q * width + j] += g * through[e, j0 + j]
                    if column == XI:
                        values[b, at + q] += point.dG[b, q, e] * rows[_LINE_LOAD + e]
        at = where[ROTATION, column]
        if at >= 0:
            for e in range(3):
                for q in range(W.shape[2]):
                    w = W[b, e, q]
                    for j in range(width):
                        values[b, at + q * width + j] += w * through[6 + e, j0 + j]
                    if column == XI:
                        values[b, at + q] += W_xi[b, e, q] * rows[_SECTION_COUPLE + e]
