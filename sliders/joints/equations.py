"""The slider joint's equations in plain numpy: the reference beside the compiled kernel.

:func:`sliders.joints.kernel.joint_equations` writes the residuals and Jacobian blocks of
``B`` joints entry by entry, in scalar loops that numba compiles; this module writes the same
equations as equations, vectorised over the members, one function per slider kind and
orientation model, each naming the paper's equations (Gualdi, Morandini and Masarati,
Secs. 3-4) it implements:

- :func:`spherical`: the position constraint, eq. (1), and its virtual work, eq. (3) and
  Sec. 4 (a), the part every kind has;
- :func:`classical_section`: plus the classical constraints ``g_2, g_3`` on the line's
  section frame (eq. 4 and Sec. 4 (b), linearised; ``docs/sliders.md``);
- :func:`spline_section`: plus the spline constraint ``g_1`` (eq. 5 and Sec. 4 (c),
  linearised);
- :func:`classical_slope`: plus the classical constraints on the line's gradient, eq. (4).

:func:`joint_reference` picks the function of a kind and orientation.  Every function reads
what :meth:`sliders.joints.slider.SliderBatch.joint_inputs` gathers (:class:`JointInputs`,
the kernel's arguments in its order) and returns the residuals and Jacobian blocks by slot
groups (:class:`Equations`, the groups of :class:`sliders.joints.blocks.SlotJacobian`), so
that the two implementations compare entry by entry (``tests/test_joint_reference.py``).

Notation (member axis first): the body node's displacement ``u_b`` and small rotation
``theta_b``, the sliding point's offset ``f`` and the slider axes ``F = [e_1, e_2, e_3]``
(columns), so ``x_b = X_b + f + u_b + theta_b x f`` and ``e_bj = e_j + theta_b x e_j``; the
unknowns ``y = [xi, lambda, mu]``; the line at ``xi``: ``x``, ``l = x_/xi``, ``l_/xi``,
``l_/xixi``, its interpolation matrix ``N`` (``x = x_0 + N q_interp`` on a chain: the
reference line plus the displacement of the element's dofs) and the test functions read as
a load transfer ``G`` (``(k, 6)``: the load dofs' share of a force and a couple at ``xi``,
theory (T6)); on a chain of cubic elements, the line's compliance at ``xi``: the position
``x + G_uu lambda_L + G_u theta m_L`` under the force ``lambda_L`` and couple ``m_L`` the
line takes there (theory (T13)).  The reference uses arithmetic only (no conversion of
dtype), so it evaluates on any number type numpy holds in an object array.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import NamedTuple

import numpy as np

from sliders.lines.rigid import axial


class JointInputs(NamedTuple):
    """What the joint equations read, for ``B`` members: the arguments of
    :func:`sliders.joints.kernel.joint_equations` in its order (gathered by
    :meth:`sliders.joints.slider.SliderBatch.joint_inputs`).

    ``m`` interpolation dofs, ``k`` load dofs, ``p`` tangent dofs (the first ``m`` the
    interpolation's), ``r`` section-rotation dofs (two nodes' for the ``section`` orientation
    on a chain, else 0), ``c`` contact rows (3 on a chain of cubic elements, else 0).
    """

    #: The sliding point ``f`` on the body node (3,) and the slider axes ``F`` (3, 3), columns.
    offset: np.ndarray
    frame: np.ndarray
    #: The body node's six dofs (B, 6) and the sliding point's reference position ``X_b + f``.
    body: np.ndarray
    reference: np.ndarray
    #: The structure states (B, n) and the joints' unknowns ``[xi, lambda, mu]`` (B, m).
    q: np.ndarray
    y: np.ndarray
    #: The line at ``xi``: ``x``, ``l``, ``l_/xi``, ``l_/xixi`` (B, 3).
    x: np.ndarray
    l: np.ndarray
    l_xi: np.ndarray
    l_xixi: np.ndarray
    #: The interpolation's matrix and its first two ``xi``-derivatives (B, 3, m): ``x`` of the
    #: interpolated dofs.
    N: np.ndarray
    dN: np.ndarray
    d2N: np.ndarray
    #: Load transfer and its ``xi``-derivative (B, k, 6): force columns, then couple columns.
    G: np.ndarray
    dG: np.ndarray
    #: The tangent of the frictionless condition ``l~`` and ``l~_/xi`` (B, 3) and its matrix
    #: on the tangent dofs (B, 3, p).
    tangent: np.ndarray
    tangent_xi: np.ndarray
    T: np.ndarray
    #: The line's position compliance at ``xi``, ``[G_uu, G_u theta]`` (B, c, 6), and its
    #: ``xi``-derivative (theory (T13); ``c = 0`` where the line has none).
    contact: np.ndarray
    contact_xi: np.ndarray
    #: The section rotation ``theta_L = W q_rotation``: its dofs (B, r), matrix and its first
    #: two ``xi``-derivatives (B, 3, r); its compliance ``C_L`` under a couple at ``xi`` (the kink
    #: correction ``kappa C``; the cubic element's ``G_theta theta``) and its derivative
    #: (B, 3, 3).
    rotation_dofs: np.ndarray
    W: np.ndarray
    W_xi: np.ndarray
    W_xixi: np.ndarray
    flex: np.ndarray
    flex_xi: np.ndarray
    #: The line's reference frame ``R_0 = [t_0, ...]`` (B, 3, 3), its curvature ``k_0`` and
    #: ``k_0/xi`` (B, 3): ``R_0/xi = k_0 x R_0``.
    R0: np.ndarray
    k0: np.ndarray
    k0_xi: np.ndarray
    #: The multipliers in ``y`` are ``scale`` times the physical ones (the compliances are
    #: divided by it).
    scale: float


class Equations(NamedTuple):
    """Residuals by row group, (B, size) each (``body``, ``turn``, ``load``, ``rotation``,
    ``xi``, ``lam``, ``mu``; the tangent groups ``interp`` and ``beside`` carry none), and
    Jacobian blocks by ``(row group, column group)``, (B, rows, columns) each."""

    residual: dict[str, np.ndarray]
    jacobian: dict[tuple[str, str], np.ndarray]


def spherical(s: JointInputs) -> Equations:
    """The spherical slider: the position constraint, paper eq. (1),
    ``x_b - x(xi) = 0``, and the virtual work of ``lambda . (x_b - x(xi))``, eq. (3) with the
    deformable line of Sec. 4 (a)::

        delta lambda . (x_b - x)  +  delta x_b . lambda  -  delta q^T dx/dq . lambda
                                  -  delta xi l~ . lambda

    Rows: the body's translations ``+lambda`` and rotations ``(f + theta_b x f) x lambda``,
    the line's load dofs ``-G lambda`` (the test functions at ``xi``, theory (T6)), the
    frictionless condition ``-l~ . lambda`` on the recovered tangent ``l~``
    (``docs/sliders.md``, "Corners of the interpolated chain") and the position constraint.
    On a line with a position compliance (a chain of cubic elements, theory (T13)) the
    constraint reads the line where the force ``lambda`` it takes puts it,
    ``x + G_uu lambda``: a compliance of the constraint rows, never a load.  Every other
    kind adds its orientation constraints to these.
    """
    B = len(s.y)
    u_b, theta_b = _body(s)
    lam = s.y[:, 1:4]
    f_b = np.cross(theta_b, s.offset)  # the offset turned with the body
    arm = s.offset + f_b
    F_lam, dF_lam = s.G[:, :, :3], s.dG[:, :, :3]
    identity = np.broadcast_to(np.eye(3), (B, 3, 3))
    residual = {
        "body": lam,
        "turn": np.cross(arm, lam),
        "load": -np.einsum("bkc,bc->bk", F_lam, lam),
        "xi": -_dot(s.tangent, lam)[:, None],
        "lam": s.reference + u_b + f_b - s.x,
    }
    n_interp = s.N.shape[2]
    tangent = -np.einsum("bc,bcp->bp", lam, s.T)[:, None, :]
    jacobian = {
        ("body", "lam"): identity,
        ("turn", "lam"): _skew(arm),
        # d/d theta_b of (theta_b x f) x lambda = -lambda x (theta_b x f)
        ("turn", "turn"): _skew(lam) @ _skew(s.offset),
        ("load", "xi"): -np.einsum("bkc,bc->bk", dF_lam, lam)[:, :, None],
        ("load", "lam"): -F_lam,
        ("xi", "xi"): -_dot(s.tangent_xi, lam)[:, None, None],
        ("xi", "lam"): -s.tangent[:, None, :],
        ("xi", "interp"): tangent[:, :, :n_interp],
        ("xi", "beside"): tangent[:, :, n_interp:],
        ("lam", "body"): identity,
        ("lam", "turn"): -np.broadcast_to(_skew(s.offset), (B, 3, 3)),
        ("lam", "xi"): -s.l[:, :, None],
        # x = x_0 + N q_interp: d x / d q_interp = N
        ("lam", "interp"): -s.N,
    }
    if s.contact.shape[1]:  # x + G_uu lambda
        G_uu = s.contact[:, :, :3] / s.scale
        residual["lam"] = residual["lam"] - np.einsum("bcd,bd->bc", G_uu, lam)
        jacobian["lam", "lam"] = -G_uu
        rate = np.einsum("bcd,bd->bc", s.contact_xi[:, :, :3] / s.scale, lam)
        jacobian["lam", "xi"] = jacobian["lam", "xi"] - rate[:, :, None]
    return Equations(residual, jacobian)


def classical_section(s: JointInputs) -> Equations:
    """The classical slider on the line's section frame (``section``, the default):
    :func:`spherical` plus ``g_j = 0``, ``j = 2, 3``, with

    ``g_j = e_j . t_0 + (e_j x t_0) . (theta_b - theta_L - kappa C m)``,

    paper eq. (4) with Sec. 4 (b) linearised in the rotations: ``e_bj . t = 0`` for the body's
    axes ``e_bj = e_j + theta_b x e_j`` and the section's axis ``t = t_0 + theta_L x t_0``,
    ``t_0`` the first axis of the line's reference frame ``R_0``; ``kappa C m`` the kink
    correction (``docs/sliders.md``).  Virtual work: :func:`_section`.
    """
    return _sum(spherical(s), _section(s, *_classical_rows(s)))


def spline_section(s: JointInputs) -> Equations:
    """The spline slider: :func:`classical_section` plus ``g_1 = 0`` with

    ``g_1 = t_0 . ax(F R_0^T) + t_0 . (theta_b - theta_L - kappa C m)``,

    paper eq. (5) with Sec. 4 (c) linearised: ``phi . l = 0`` for the relative orientation
    ``phi = ax(R_b R^T)`` of the body ``R_b = (I + theta_b x) F`` and the section
    ``R = (I + theta_L x) R_0``, about ``F ~ R_0`` (the slider checks its frame within 0.1
    rad of the line's).  The multipliers are ``[mu_2, mu_3, mu_1]``.
    """
    classical, spline = _classical_rows(s), _spline_row(s)
    g = [np.concatenate(pair, axis=1) for pair in zip(classical[0], spline[0], strict=True)]
    n = [np.concatenate(pair, axis=1) for pair in zip(classical[1], spline[1], strict=True)]
    return _sum(spherical(s), _section(s, g, n))


def classical_slope(s: JointInputs) -> Equations:
    """The classical slider on the line's gradient (``slope``): :func:`spherical` plus the
    paper's eq. (4), ``g_j = e_bj . l = 0``, ``j = 2, 3``, whose virtual work is

    ``delta mu_j e_bj . l + theta_b_delta . m + delta xi sum_j mu_j e_bj . l_/xi``,

    the couple ``m = sum_j mu_j e_bj x l`` on the body and ``-m`` on the line through the
    couple columns of the test functions ``G`` (as the reference implementation does, not as
    the ``delta q^T dl/dq`` dipole of Sec. 4 (b): ``docs/sliders.md``).
    """
    return _sum(spherical(s), _slope(s))


def _slope(s: JointInputs) -> Equations:
    """The classical constraints on the line's gradient and their virtual work
    (:func:`classical_slope`)."""
    _, theta_b = _body(s)
    mu = s.y[:, 4:6]
    e = s.frame[:, 1:3].T  # e_2, e_3 (rows)
    e_b = e + np.cross(theta_b[:, None, :], e)  # (B, 2, 3)
    couples = np.cross(e_b, s.l[:, None, :])  # e_bj x l
    m = np.einsum("bj,bjc->bc", mu, couples)
    G_m, dG_m = s.G[:, :, 3:], s.dG[:, :, 3:]
    # the couple's derivatives: d(e_bj x l) = (d theta_b x e_j) x l + e_bj x dl, with
    # l = l_0 + dN q_interp and l_/xi = l_0/xi + d2N q_interp
    m_theta = np.einsum("bj,bcd,jde->bce", mu, _skew(s.l), _skew(e))
    m_xi = np.einsum("bj,bjc->bc", mu, np.cross(e_b, s.l_xi[:, None, :]))
    m_mu = np.swapaxes(couples, 1, 2)
    m_interp = np.einsum("bj,bjcd,bdk->bck", mu, _skew(e_b), s.dN)
    turn = {"turn": m_theta, "xi": m_xi[:, :, None], "mu": m_mu, "interp": m_interp}
    load = {key: -G_m @ value for key, value in turn.items()}
    load["xi"] = load["xi"] - np.einsum("bkc,bc->bk", dG_m, m)[:, :, None]
    along = np.einsum("bjc,bc->bj", e_b, s.l_xi)  # e_bj . l_/xi
    residual = {
        "turn": m,
        "load": -np.einsum("bkc,bc->bk", G_m, m),
        "xi": _dot(mu, along)[:, None],
        "mu": np.einsum("bjc,bc->bj", e_b, s.l),
    }
    jacobian = {
        **{("turn", key): value for key, value in turn.items()},
        **{("load", key): value for key, value in load.items()},
        ("xi", "turn"): np.einsum("bj,bjc->bc", mu, np.cross(e, s.l_xi[:, None, :]))[:, None],
        ("xi", "xi"): _dot(mu, np.einsum("bjc,bc->bj", e_b, s.l_xixi))[:, None, None],
        ("xi", "mu"): along[:, None, :],
        ("xi", "interp"): np.einsum("bj,bjc,bck->bk", mu, e_b, s.d2N)[:, None, :],
        ("mu", "turn"): np.cross(e, s.l[:, None, :]),
        ("mu", "xi"): along[:, :, None],
        ("mu", "interp"): np.einsum("bjc,bck->bjk", e_b, s.dN),
    }
    return Equations(residual, jacobian)


#: The reference of each ``(kind, orientation)`` a :class:`sliders.joints.slider.Slider`
#: accepts.
REFERENCES: dict[tuple[str, str], Callable[[JointInputs], Equations]] = {
    ("spherical", "section"): spherical,
    ("classical", "section"): classical_section,
    ("spline", "section"): spline_section,
    ("classical", "slope"): classical_slope,
}


def joint_reference(kind: str, orientation: str, inputs: JointInputs) -> Equations:
    """The equations of a ``kind`` slider with the ``orientation`` model at ``inputs``."""
    try:
        reference = REFERENCES[kind, orientation]
    except KeyError:
        raise ValueError(
            f"no slider equations for kind {kind!r} with orientation {orientation!r}; "
            f"known: {', '.join(map(str, REFERENCES))}"
        ) from None
    return reference(inputs)


def _section(s: JointInputs, g: list[np.ndarray], n: list[np.ndarray]) -> Equations:
    """The orientation constraints on the section frame and their virtual work.

    ``g = [g0, g0_/xi, g0_/xixi]`` (B, J) and ``n = [n, n_/xi, n_/xixi]`` (B, J, 3) define
    ``g_j = g0_j(xi) + n_j(xi) . (theta_b - theta_L - C_L m - G_theta u lambda)``
    (:func:`classical_section`, :func:`spline_section`).  The virtual work of
    ``sum_j mu_j g_j`` without the compliance terms gives the couple ``m = sum_j mu_j n_j``
    on the body, ``-W^T m`` on the dofs that carry ``theta_L = W q_rotation`` and the ``xi``
    row ``sum_j mu_j (g0_j/xi + n_j/xi . (theta_b - theta_L) - n_j . theta_L/xi)``: the
    rotation the couple ``m`` and the force ``lambda`` the line takes at ``xi`` add there,
    ``C_L m + G_theta u lambda`` (the kink correction ``kappa C m``; a cubic element's own,
    theory (T13)), is a compliance of the constraint rows, never a load.  On a line with a
    position compliance the position rows read ``G_u theta m`` too (:func:`spherical`).
    """
    _, theta_b = _body(s)
    lam = s.y[:, 1:4]
    mu = s.y[:, 4:]
    g0, g1, g2 = g
    n0, n1, n2 = n
    nodal = np.take_along_axis(s.q, s.rotation_dofs, axis=1)
    theta_L = np.einsum("bcr,br->bc", s.W, nodal)
    theta_L_xi = np.einsum("bcr,br->bc", s.W_xi, nodal)
    theta_L_xixi = np.einsum("bcr,br->bc", s.W_xixi, nodal)
    C, C_xi = s.flex / s.scale, s.flex_xi / s.scale
    m = np.einsum("bj,bjc->bc", mu, n0)
    m_xi = np.einsum("bj,bjc->bc", mu, n1)
    d = theta_b - theta_L
    shift = np.einsum("bcd,bd->bc", C, m)  # C_L m
    shift_xi = np.einsum("bcd,bd->bc", C_xi, m) + np.einsum("bcd,bd->bc", C, m_xi)
    along = g1 + _rows(n1, d) - _rows(n0, theta_L_xi)  # d g_j / d xi without the shift's
    n0_T = np.swapaxes(n0, 1, 2)
    on_rotation = -(np.einsum("bcr,bc->br", s.W, m_xi) + np.einsum("bcr,bc->br", s.W_xi, m))
    residual = {
        "turn": m,
        "rotation": -np.einsum("bcr,bc->br", s.W, m),
        "xi": _dot(mu, along)[:, None],
    }
    jacobian = {
        ("turn", "xi"): m_xi[:, :, None],
        ("turn", "mu"): n0_T,
        ("rotation", "xi"): on_rotation[:, :, None],
        ("rotation", "mu"): -np.einsum("bcr,bjc->brj", s.W, n0),
        ("xi", "turn"): m_xi[:, None, :],
        ("xi", "rotation"): on_rotation[:, None, :],
        ("xi", "xi"): _dot(
            mu, g2 + _rows(n2, d) - 2 * _rows(n1, theta_L_xi) - _rows(n0, theta_L_xixi)
        )[:, None, None],
        ("xi", "mu"): along[:, None, :],
        ("mu", "turn"): n0,
        ("mu", "rotation"): -np.einsum("bjc,bcr->bjr", n0, s.W),
        ("mu", "mu"): -np.einsum("bic,bcd,bjd->bij", n0, C, n0),
    }
    if s.contact.shape[1]:  # G_theta u lambda in the rotation, G_u theta m in the position
        G_ut, G_ut_xi = s.contact[:, :, 3:] / s.scale, s.contact_xi[:, :, 3:] / s.scale
        shift = shift + np.einsum("bdc,bd->bc", G_ut, lam)
        shift_xi = shift_xi + np.einsum("bdc,bd->bc", G_ut_xi, lam)
        residual["lam"] = -np.einsum("bcd,bd->bc", G_ut, m)
        rate = np.einsum("bcd,bd->bc", G_ut_xi, m) + np.einsum("bcd,bd->bc", G_ut, m_xi)
        jacobian["lam", "xi"] = -rate[:, :, None]
        jacobian["lam", "mu"] = -np.einsum("bcd,bjd->bcj", G_ut, n0)
        jacobian["mu", "lam"] = -np.einsum("bjc,bdc->bjd", n0, G_ut)
    residual["mu"] = g0 + _rows(n0, d - shift)
    jacobian["mu", "xi"] = (along - _rows(n1, shift) - _rows(n0, shift_xi))[:, :, None]
    return Equations(residual, jacobian)


def _classical_rows(s: JointInputs) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """``g0_j = e_j . t_0`` and ``n_j = e_j x t_0`` of the classical constraints (j = 2, 3)
    with their first two ``xi``-derivatives (:func:`_section`)."""
    e = s.frame[:, 1:3].T
    axis = _section_axis(s)
    g = [np.einsum("jc,bc->bj", e, t) for t in axis]
    n = [np.cross(e, t[:, None, :]) for t in axis]
    return g, n


def _spline_row(s: JointInputs) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """``g0_1 = t_0 . ax(F R_0^T)`` and ``n_1 = t_0`` of the spline constraint with their
    first two ``xi``-derivatives (:func:`_section`): ``(F R_0^T)_/xi = -F R_0^T K_0`` with
    ``K_0 = k_0 x`` (as ``R_0/xi = K_0 R_0``)."""
    t0, t1, t2 = _section_axis(s)
    K, K_xi = _skew(s.k0), _skew(s.k0_xi)
    D = s.frame @ np.swapaxes(s.R0, 1, 2)
    D_xi = -D @ K
    D_xixi = -D_xi @ K - D @ K_xi
    a0, a1, a2 = axial(D), axial(D_xi), axial(D_xixi)
    g = [_dot(t0, a0), _dot(t1, a0) + _dot(t0, a1), _dot(t2, a0) + 2 * _dot(t1, a1) + _dot(t0, a2)]
    return [value[:, None] for value in g], [t[:, None, :] for t in (t0, t1, t2)]


def _section_axis(s: JointInputs) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``t_0``, the first axis of the line's reference frame, and its first two
    ``xi``-derivatives: ``t_0/xi = k_0 x t_0``, ``t_0/xixi = k_0/xi x t_0 + k_0 x t_0/xi``."""
    t0 = s.R0[:, :, 0]
    t1 = np.cross(s.k0, t0)
    t2 = np.cross(s.k0_xi, t0) + np.cross(s.k0, t1)
    return t0, t1, t2


def _body(s: JointInputs) -> tuple[np.ndarray, np.ndarray]:
    """The body node's displacement ``u_b`` and rotation ``theta_b`` (B, 3) each."""
    dofs = np.take_along_axis(s.q, s.body, axis=1)
    return dofs[:, :3], dofs[:, 3:]


def _skew(v: np.ndarray) -> np.ndarray:
    """``skew(v)``, the matrix of ``v x``, for vectors (..., 3): (..., 3, 3)."""
    x, y, z = v[..., 0], v[..., 1], v[..., 2]
    zero = 0 * x
    return np.stack(
        [np.stack([zero, -z, y], -1), np.stack([z, zero, -x], -1), np.stack([-y, x, zero], -1)],
        -2,
    )


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise dot products of (B, k) arrays: (B,)."""
    return np.einsum("bk,bk->b", a, b)


def _rows(n: np.ndarray, v: np.ndarray) -> np.ndarray:
    """``n_j . v`` for rows ``n`` (B, J, 3) and vectors ``v`` (B, 3): (B, J)."""
    return np.einsum("bjc,bc->bj", n, v)


def _sum(*parts: Equations) -> Equations:
    """The equations of ``parts`` added, residual by residual and block by block."""
    residual: dict[str, np.ndarray] = {}
    jacobian: dict[tuple[str, str], np.ndarray] = {}
    for part in parts:
        for key, value in part.residual.items():
            residual[key] = residual[key] + value if key in residual else value
        for block, value in part.jacobian.items():
            jacobian[block] = jacobian[block] + value if block in jacobian else value
    return Equations(residual, jacobian)
