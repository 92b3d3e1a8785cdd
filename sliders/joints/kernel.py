"""The slider joint's equations, compiled: residuals and Jacobian blocks of ``B`` members.

:meth:`sliders.joints.slider.SliderBatch.joint_inputs` gathers what the joints need (the line
state at ``xi``, the body's displacements, the unknowns:
:class:`sliders.joints.equations.JointInputs`) and
:meth:`~sliders.joints.slider.SliderBatch.joint_equations` calls :func:`joint_equations`,
which writes, member by member, the residual on the slots and the Jacobian blocks of the
joint's pattern (:class:`sliders.joints.blocks.SlotJacobian`: one flat array, ``where[row
group, column group]`` the offset of a block, -1 where it is not in the pattern).  The
equations are those of :mod:`sliders.joints.equations`, which writes them in plain numpy with
the paper's numbers (eqs. 1-5, Sec. 4), one function per kind and orientation model
(``section``: the section frame, ``docs/sliders.md``; ``slope``: paper eq. 4);
``tests/test_joint_reference.py`` holds the two equal to roundoff.

The kernel writes exactly the blocks of the law's sparsity
(:func:`sliders.joints.equations.pattern`, read off the law's derivative): the pattern a
joint lays out, which :meth:`sliders.joints.blocks.SlotJacobian.index` checks once per layout
(a block written outside the pattern would land at offset -1).

Slot groups, in this order (their first slot ``start`` and ``size``): ``body`` (3), ``turn``
(3, the body's rotations), ``load``, ``rotation``, ``interp``, ``beside``, then the joint's
unknowns ``xi`` (1), ``lam`` (3), ``mu``.  The line's interpolation, recovered tangent and
section rotation are matrices on their slots (``N``, ``T``, ``W``: the Lagrange ``N_a I`` on the
translations, or a cubic element's functions on all six dofs of its nodes); on a cubic chain
the constraint rows read the line's compliance at the contact too (``contact``, theory T13,
the blocks ``(lam, lam)``, ``(lam, mu)``, ``(mu, lam)``).
"""

from __future__ import annotations

import numba
import numpy as np

from fvbeam.kernel_cache import guard
from fvbeam.scratch import stack_empty, stack_matrix3, stack_vector3

guard(__file__)  # numba's cache of these kernels, consistent with their sources

BODY, TURN, LOAD, ROTATION, INTERP, BESIDE, XI, LAM, MU = range(9)
#: Group names in the order of the indices above (:class:`sliders.joints.blocks.SlotJacobian`).
GROUPS = ("body", "turn", "load", "rotation", "interp", "beside", "xi", "lam", "mu")
KINDS = {"spherical": 0, "classical": 1, "spline": 2}
ORIENTATIONS = {"section": 0, "slope": 1}


@numba.njit(cache=True)
def _add(values, b, where, size, R, C, i, j, v):
    """Add ``v`` to entry ``(i, j)`` of block ``(R, C)`` of member ``b``."""
    values[b, where[R, C] + i * size[C] + j] += v


@numba.njit(cache=True)
def _cross(a, b, out):
    """``out = a x b`` for 3-vectors."""
    out[0] = a[1] * b[2] - a[2] * b[1]
    out[1] = a[2] * b[0] - a[0] * b[2]
    out[2] = a[0] * b[1] - a[1] * b[0]


@numba.njit(cache=True)
def _dot(a, b):
    """``a . b`` for 3-vectors."""
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


@numba.njit(cache=True)
def _skew(v, out):
    """``out = skew(v)``, the matrix of ``v x``."""
    out[0, 0], out[0, 1], out[0, 2] = 0.0, -v[2], v[1]
    out[1, 0], out[1, 1], out[1, 2] = v[2], 0.0, -v[0]
    out[2, 0], out[2, 1], out[2, 2] = -v[1], v[0], 0.0


@numba.njit(cache=True)
def _axial(A, out):
    """``out = ax(A)``, the vector of the skew-symmetric part of ``A``."""
    out[0] = 0.5 * (A[2, 1] - A[1, 2])
    out[1] = 0.5 * (A[0, 2] - A[2, 0])
    out[2] = 0.5 * (A[1, 0] - A[0, 1])


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
    offset, frame, body, reference, q, y = (
        point.offset,
        point.frame,
        point.body,
        point.reference,
        point.q,
        point.y,
    )
    x, l, N, G, dG, T = point.x, point.l, point.N, point.G, point.dG, point.T
    tangent, tangent_xi, contact, contact_xi, scale = (
        point.tangent,
        point.tangent_xi,
        point.contact,
        point.contact_xi,
        point.scale,
    )
    B = len(y)
    t = start[XI]
    lam = stack_vector3()
    arm = stack_vector3()
    v = stack_vector3()
    S1 = stack_matrix3()
    S2 = stack_matrix3()
    theta = stack_vector3()
    axes = stack_empty(6, (2, 3), np.float64)
    for j in range(2):
        for c in range(3):
            axes[j, c] = frame[c, j + 1]
    lever = offset[0] != 0.0 or offset[1] != 0.0 or offset[2] != 0.0
    compliant = contact.shape[1] > 0
    n_load, n_tangent, n_interp = G.shape[1], T.shape[2], N.shape[2]
    for b in range(B):
        for c in range(3):
            lam[c] = y[b, 1 + c]
            theta[c] = q[b, body[b, 3 + c]]
        _cross(theta, offset, v)  # f_b
        for c in range(3):
            arm[c] = offset[c] + v[c]
            # body force (eq. 3) and position constraint (eq. 1)
            r[b, c] += lam[c]
            r[b, t + 1 + c] = reference[b, c] + q[b, body[b, c]] + v[c] - x[b, c]
            if compliant:  # the line where the force it takes puts it (theory T13)
                for e in range(3):
                    r[b, t + 1 + c] -= contact[b, c, e] / scale * lam[e]
        _cross(arm, lam, v)
        for c in range(3):
            r[b, 3 + c] += v[c]  # body moment (eq. 3)
        for k in range(n_load):  # the force on the line (Sec. 4, eq. T6)
            r[b, start[LOAD] + k] -= G[b, k, 0] * lam[0] + G[b, k, 1] * lam[1] + G[b, k, 2] * lam[2]
        r[b, t] = -(tangent[b, 0] * lam[0] + tangent[b, 1] * lam[1] + tangent[b, 2] * lam[2])
        if jacobian:
            _skew(arm, S1)
            for i in range(3):
                for c in range(3):
                    _add(values, b, where, size, BODY, LAM, i, c, 1.0 if i == c else 0.0)
                    _add(values, b, where, size, LAM, BODY, i, c, 1.0 if i == c else 0.0)
                    if lever:  # skew(f + theta_b x f), zero on the node
                        _add(values, b, where, size, TURN, LAM, i, c, S1[i, c])
                _add(values, b, where, size, LAM, XI, i, 0, -l[b, i])
                _add(values, b, where, size, XI, LAM, 0, i, -tangent[b, i])
            if compliant:
                for i in range(3):
                    s = 0.0
                    for c in range(3):
                        s += contact_xi[b, i, c] * lam[c]
                        _add(values, b, where, size, LAM, LAM, i, c, -contact[b, i, c] / scale)
                    _add(values, b, where, size, LAM, XI, i, 0, -s / scale)
            if lever:
                _skew(lam, S1)
                _skew(offset, S2)
                for i in range(3):
                    for c in range(3):
                        s = 0.0
                        for e in range(3):
                            s += S1[i, e] * S2[e, c]
                        _add(values, b, where, size, TURN, TURN, i, c, s)
                        _add(values, b, where, size, LAM, TURN, i, c, -S2[i, c])
            for k in range(n_load):
                s = 0.0
                for c in range(3):
                    s += dG[b, k, c] * lam[c]
                    _add(values, b, where, size, LOAD, LAM, k, c, -G[b, k, c])
                _add(values, b, where, size, LOAD, XI, k, 0, -s)
            _add(
                values,
                b,
                where,
                size,
                XI,
                XI,
                0,
                0,
                -(
                    tangent_xi[b, 0] * lam[0]
                    + tangent_xi[b, 1] * lam[1]
                    + tangent_xi[b, 2] * lam[2]
                ),
            )
            for col in range(n_tangent):
                s = -(T[b, 0, col] * lam[0] + T[b, 1, col] * lam[1] + T[b, 2, col] * lam[2])
                if col < n_interp:
                    _add(values, b, where, size, XI, INTERP, 0, col, s)
                else:
                    _add(values, b, where, size, XI, BESIDE, 0, col - n_interp, s)
            for col in range(n_interp):
                for c in range(3):
                    _add(values, b, where, size, LAM, INTERP, c, col, -N[b, c, col])
    if kind != 0 and slope:
        _slope(jacobian, axes, point, index, r, values)
    elif kind != 0:
        _section(kind, jacobian, axes, point, index, r, values)


@numba.njit(cache=True)
def _matvec(A, v, out):
    """``out = A v`` for a 3x3 ``A``."""
    for i in range(3):
        out[i] = A[i, 0] * v[0] + A[i, 1] * v[1] + A[i, 2] * v[2]


@numba.njit(cache=True)
def _matmul(A, B, out):
    """``out = A B`` for 3x3 matrices."""
    for i in range(3):
        for j in range(3):
            out[i, j] = A[i, 0] * B[0, j] + A[i, 1] * B[1, j] + A[i, 2] * B[2, j]


@numba.njit(cache=True)
def _section(kind, jacobian, axes, point, index, r, values):
    """Orientation constraints on the line's section frame, linear in the rotations.

    ``g_j = g0_j(xi) + n_j(xi) . (theta_b - theta_L)``: classical (``j = 2, 3``)
    ``g0 = e_j . t0``, ``n = e_j x t0``; spline (``j = 1``) ``g0 = t0 . ax(F R0^T)``,
    ``n = t0`` -- eqs. (4), (5) and Sec. 4 linearised, with ``R0 = [t0, ...]`` the line's
    reference frame, ``t1, t2`` the first two ``xi``-derivatives of ``t0`` and ``F`` the
    slider frame.  The virtual work of ``sum mu_j g_j`` gives the couple ``m = sum mu_j n_j``
    on the body, ``-W^T m`` on the dofs that carry ``theta_L = W q_rotation`` and the ``xi``
    row.  The constraint reads ``theta_L`` plus ``C_L m`` (``flex``: the exact rotation at a
    couple lies off the interpolation of its nodal values by that much, ``docs/sliders.md``)
    and, on a line with a position compliance, ``G_theta u lambda`` (``contact``, whose
    position rows then read ``G_u theta m``; theory T13).  ``axes``: ``e_2, e_3`` (rows);
    ``point``, ``index``, ``r``, ``values``: as :func:`joint_equations`.
    """
    start, size, where = index
    frame, body, q, y, contact, contact_xi = (
        point.frame,
        point.body,
        point.q,
        point.y,
        point.contact,
        point.contact_xi,
    )
    rotation_dofs, W, W_xi, W_xixi = point.rotation_dofs, point.W, point.W_xi, point.W_xixi
    flex, flex_xi, R0, k0, k0_xi, scale = (
        point.flex,
        point.flex_xi,
        point.R0,
        point.k0,
        point.k0_xi,
        point.scale,
    )
    t = start[XI]
    n_mu = size[MU]
    n_w = W.shape[2]
    compliant = contact.shape[1] > 0
    mu = stack_empty(3, (n_mu,), np.float64)
    lam = stack_vector3()
    theta, theta_L = stack_vector3(), stack_vector3()
    theta_L_xi, theta_L_xixi = stack_vector3(), stack_vector3()
    t0, t1, t2 = stack_vector3(), stack_vector3(), stack_vector3()
    v, d = stack_vector3(), stack_vector3()
    m, m_xi, shift = stack_vector3(), stack_vector3(), stack_vector3()
    rate, Cn = stack_vector3(), stack_vector3()
    a0, a1, a2 = stack_vector3(), stack_vector3(), stack_vector3()
    # rows j of n_i: axes_j x t_i (classical), then t_i (spline); g_i likewise
    n0, n1, n2 = (
        stack_empty(9, (n_mu, 3), np.float64),
        stack_empty(9, (n_mu, 3), np.float64),
        stack_empty(9, (n_mu, 3), np.float64),
    )
    g0, g1, g2, along = (
        stack_empty(3, (n_mu,), np.float64),
        stack_empty(3, (n_mu,), np.float64),
        stack_empty(3, (n_mu,), np.float64),
        stack_empty(3, (n_mu,), np.float64),
    )
    R0T, F, K = stack_matrix3(), stack_matrix3(), stack_matrix3()
    dF, ddF, P = stack_matrix3(), stack_matrix3(), stack_matrix3()
    C, C_xi = stack_matrix3(), stack_matrix3()
    for b in range(len(y)):
        for j in range(n_mu):
            mu[j] = y[b, 4 + j]
        for c in range(3):
            lam[c] = y[b, 1 + c]
            theta[c] = q[b, body[b, 3 + c]]
            theta_L[c] = 0.0
            theta_L_xi[c] = 0.0
            theta_L_xixi[c] = 0.0
            for a in range(n_w):
                value = q[b, rotation_dofs[b, a]]
                theta_L[c] += W[b, c, a] * value
                theta_L_xi[c] += W_xi[b, c, a] * value
                theta_L_xixi[c] += W_xixi[b, c, a] * value
            t0[c] = R0[b, c, 0]
        _cross(k0[b], t0, t1)
        _cross(k0_xi[b], t0, t2)
        _cross(k0[b], t1, v)
        for c in range(3):
            t2[c] += v[c]
        for j in range(2):
            _cross(axes[j], t0, n0[j])
            _cross(axes[j], t1, n1[j])
            _cross(axes[j], t2, n2[j])
            g0[j], g1[j], g2[j] = _dot(t0, axes[j]), _dot(t1, axes[j]), _dot(t2, axes[j])
        if kind == 2:
            for i in range(3):
                for c in range(3):
                    R0T[i, c] = R0[b, c, i]
            _matmul(frame, R0T, F)
            _skew(k0[b], K)
            _matmul(F, K, dF)
            dF *= -1.0
            _matmul(dF, K, ddF)
            _skew(k0_xi[b], K)
            _matmul(F, K, P)
            for i in range(3):
                for c in range(3):
                    ddF[i, c] = -ddF[i, c] - P[i, c]
            _axial(F, a0)
            _axial(dF, a1)
            _axial(ddF, a2)
            for c in range(3):
                n0[2, c], n1[2, c], n2[2, c] = t0[c], t1[c], t2[c]
            g0[2] = _dot(t0, a0)
            g1[2] = _dot(t1, a0) + _dot(t0, a1)
            g2[2] = _dot(t2, a0) + 2 * _dot(t1, a1) + _dot(t0, a2)
        for c in range(3):
            d[c] = theta[c] - theta_L[c]
            m[c] = 0.0
            m_xi[c] = 0.0
            for j in range(n_mu):
                m[c] += mu[j] * n0[j, c]
                m_xi[c] += mu[j] * n1[j, c]
            for i in range(3):
                C[c, i] = flex[b, c, i] / scale
                C_xi[c, i] = flex_xi[b, c, i] / scale
        # shift = C_L m (+ G_theta u lambda), rate its xi-derivative at fixed multipliers
        _matvec(C, m, shift)
        _matvec(C_xi, m, rate)
        _matvec(C, m_xi, v)
        for c in range(3):
            rate[c] += v[c]
            if compliant:
                for e in range(3):
                    shift[c] += contact[b, e, 3 + c] / scale * lam[e]
                    rate[c] += contact_xi[b, e, 3 + c] / scale * lam[e]
                    # the position rows: - G_u theta m
                    r[b, t + 1 + c] -= contact[b, c, 3 + e] / scale * m[e]
        for j in range(n_mu):
            along[j] = g1[j] + _dot(n1[j], d) - _dot(n0[j], theta_L_xi)
            r[b, t] += mu[j] * along[j]
            r[b, t + 4 + j] = g0[j] + _dot(n0[j], d) - _dot(n0[j], shift)
        for c in range(3):
            r[b, 3 + c] += m[c]
        for a in range(n_w):
            r[b, start[ROTATION] + a] -= W[b, 0, a] * m[0] + W[b, 1, a] * m[1] + W[b, 2, a] * m[2]
        if not jacobian:
            continue
        s = 0.0
        for j in range(n_mu):
            s += mu[j] * (
                g2[j] + _dot(n2[j], d) - 2 * _dot(n1[j], theta_L_xi) - _dot(n0[j], theta_L_xixi)
            )
        _add(values, b, where, size, XI, XI, 0, 0, s)
        for c in range(3):
            _add(values, b, where, size, TURN, XI, c, 0, m_xi[c])
            _add(values, b, where, size, XI, TURN, 0, c, m_xi[c])
        for a in range(n_w):
            s = 0.0
            for c in range(3):
                s -= W_xi[b, c, a] * m[c] + W[b, c, a] * m_xi[c]
            _add(values, b, where, size, ROTATION, XI, a, 0, s)
            _add(values, b, where, size, XI, ROTATION, 0, a, s)
        if compliant:
            for c in range(3):
                s = 0.0
                for e in range(3):
                    s += (contact_xi[b, c, 3 + e] * m[e] + contact[b, c, 3 + e] * m_xi[e]) / scale
                _add(values, b, where, size, LAM, XI, c, 0, -s)
        for j in range(n_mu):
            _add(values, b, where, size, XI, MU, 0, j, along[j])
            _add(
                values,
                b,
                where,
                size,
                MU,
                XI,
                j,
                0,
                along[j] - _dot(n1[j], shift) - _dot(n0[j], rate),
            )
            _matvec(C, n0[j], Cn)
            for i in range(n_mu):
                _add(values, b, where, size, MU, MU, i, j, -_dot(n0[i], Cn))
            for c in range(3):
                _add(values, b, where, size, TURN, MU, c, j, n0[j, c])
                _add(values, b, where, size, MU, TURN, j, c, n0[j, c])
            for a in range(n_w):
                s = -(W[b, 0, a] * n0[j, 0] + W[b, 1, a] * n0[j, 1] + W[b, 2, a] * n0[j, 2])
                _add(values, b, where, size, ROTATION, MU, a, j, s)
                _add(values, b, where, size, MU, ROTATION, j, a, s)
            if compliant:
                for c in range(3):
                    s = 0.0
                    for e in range(3):
                        s += contact[b, c, 3 + e] * n0[j, e]
                    _add(values, b, where, size, LAM, MU, c, j, -s / scale)
                    _add(values, b, where, size, MU, LAM, j, c, -s / scale)


@numba.njit(cache=True)
def _slope(jacobian, axes, point, index, r, values):
    """The classical slider on the line's gradient, ``e_bj . l = 0`` (paper eq. 4): the
    couple ``m = sum mu_j e_bj x l`` on the body, carried to the line's rotation dofs by the
    test functions (the rotational columns of ``G``).  Arguments as :func:`_section`."""
    start, size, where = index
    body, q, y, l, l_xi, l_xixi = point.body, point.q, point.y, point.l, point.l_xi, point.l_xixi
    dN, d2N, G, dG = point.dN, point.d2N, point.G, point.dG
    t = start[XI]
    n_load, n_interp = G.shape[1], dN.shape[2]
    theta, m, v, w = stack_vector3(), stack_vector3(), stack_vector3(), stack_vector3()
    e_b = stack_empty(6, (2, 3), np.float64)
    L, E0, E, dm_dtheta = stack_matrix3(), stack_matrix3(), stack_matrix3(), stack_matrix3()
    dm_dxi, dm_dmu = stack_vector3(), stack_vector3()
    for b in range(len(y)):
        for c in range(3):
            theta[c] = q[b, body[b, 3 + c]]
            m[c] = 0.0
        for j in range(2):
            _cross(theta, axes[j], v)
            for c in range(3):
                e_b[j, c] = axes[j, c] + v[c]
            _cross(e_b[j], l[b], v)
            for c in range(3):
                m[c] += y[b, 4 + j] * v[c]
        for c in range(3):
            r[b, 3 + c] += m[c]
        for k in range(n_load):
            s = 0.0
            for c in range(3):
                s += G[b, k, 3 + c] * m[c]
            r[b, start[LOAD] + k] -= s
            if jacobian:
                s = 0.0
                for c in range(3):
                    s += dG[b, k, 3 + c] * m[c]
                _add(values, b, where, size, LOAD, XI, k, 0, -s)
        for j in range(2):
            e, e0, mu_j = e_b[j], axes[j], y[b, 4 + j]
            r[b, t] += mu_j * _dot(e, l_xi[b])
            r[b, t + 4 + j] = _dot(e, l[b])
            if not jacobian:
                continue
            _skew(l[b], L)
            _skew(e0, E0)
            _skew(e, E)
            _matmul(L, E0, dm_dtheta)
            dm_dtheta *= mu_j
            _cross(e, l_xi[b], dm_dxi)
            _cross(e, l[b], dm_dmu)
            for i in range(3):
                dm_dxi[i] *= mu_j
            for i in range(3):
                _add(values, b, where, size, TURN, XI, i, 0, dm_dxi[i])
                _add(values, b, where, size, TURN, MU, i, j, dm_dmu[i])
                for c in range(3):
                    _add(values, b, where, size, TURN, TURN, i, c, dm_dtheta[i, c])
            # d m / d q_interp = mu_j e_bj x dN (l = l_0 + dN q_interp)
            for col in range(n_interp):
                for c in range(3):
                    v[c] = dN[b, c, col]
                _matvec(E, v, w)
                for i in range(3):
                    _add(values, b, where, size, TURN, INTERP, i, col, mu_j * w[i])
                for k in range(n_load):
                    g = G[b, k, 3:]
                    _add(values, b, where, size, LOAD, INTERP, k, col, -mu_j * _dot(g, w))
                d2 = d2N[b, 0, col] * e[0] + d2N[b, 1, col] * e[1] + d2N[b, 2, col] * e[2]
                _add(values, b, where, size, XI, INTERP, 0, col, mu_j * d2)
                _add(values, b, where, size, MU, INTERP, j, col, _dot(e, v))
            for k in range(n_load):
                g = G[b, k, 3:]
                _add(values, b, where, size, LOAD, XI, k, 0, -_dot(g, dm_dxi))
                _add(values, b, where, size, LOAD, MU, k, j, -_dot(g, dm_dmu))
                for c in range(3):
                    _add(
                        values,
                        b,
                        where,
                        size,
                        LOAD,
                        TURN,
                        k,
                        c,
                        -(g[0] * dm_dtheta[0, c] + g[1] * dm_dtheta[1, c] + g[2] * dm_dtheta[2, c]),
                    )
            _cross(e0, l_xi[b], v)
            for c in range(3):
                _add(values, b, where, size, XI, TURN, 0, c, mu_j * v[c])
            _add(values, b, where, size, XI, XI, 0, 0, mu_j * _dot(e, l_xixi[b]))
            _add(values, b, where, size, XI, MU, 0, j, _dot(e, l_xi[b]))
            _cross(e0, l[b], v)
            for c in range(3):
                _add(values, b, where, size, MU, TURN, j, c, v[c])
            _add(values, b, where, size, MU, XI, j, 0, _dot(e, l_xi[b]))
