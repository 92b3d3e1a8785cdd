"""The slider joint's laws, each written once, at a point, as the paper writes it.

A law reads the body's sliding point (:class:`BodyPoint`), the line at ``xi``
(:class:`LinePoint`) and the joint's multipliers (:class:`Unknowns`), and returns its
residual at the point (:class:`PointRows`): the force and couple on the body, the load on
the line at ``xi``, the couple on the line's section rotation, the ``xi`` row and the
constraint rows.  One function per slider kind and orientation model, each naming the
paper's equations (Gualdi, Morandini and Masarati, Secs. 3-4) it implements:

- :func:`spherical`: the position constraint, eq. (1), and its virtual work, eq. (3) and
  Sec. 4 (a), the part every kind has;
- :func:`classical_section`: plus the classical constraints ``g_2, g_3`` on the line's
  section frame (eq. 4 and Sec. 4 (b), linearised; ``docs/sliders.md``);
- :func:`spline_section`: plus the spline constraint ``g_1`` (eq. 5 and Sec. 4 (c),
  linearised);
- :func:`classical_slope`: plus the classical constraints on the line's gradient, eq. (4).

Nothing else is written by hand.  :func:`scatter` puts a law's point rows on the joint's
slot groups through the line's maps (the load transfer ``G``, the rotation map ``W``), the
same routine for every kind; :func:`derive` runs law and scatter on dual numbers
(:mod:`sliders.joints.dual`) seeded through the line's maps and their ``xi``-derivatives,
which gives the exact Jacobian by blocks of slot groups (:class:`Equations`);
:func:`pattern` reads the blocks a law writes off that derivative.  The compiled form of
each law and of its derivatives is generated from the same function
(:mod:`sliders.joints.generate` writes :mod:`sliders.joints.compiled_laws`), and
:func:`joint_reference` is the reference the compiled kernel
(:func:`sliders.joints.kernel.joint_equations`, which the solvers run) is held to, entry by
entry, on every kind, orientation and line (``tests/test_joint_reference.py``).  Every
function reads what :meth:`sliders.joints.slider.SliderBatch.joint_inputs` gathers
(:class:`JointInputs`, the kernel's arguments in its order).

Notation: the body node's displacement ``u_b`` and small rotation ``theta_b``, the sliding
point's offset ``f`` and the slider axes ``F = [e_1, e_2, e_3]`` (columns), so
``x_b = X_b + f + u_b + theta_b x f`` and ``e_bj = e_j + theta_b x e_j``; the unknowns
``y = [xi, lambda, mu]``; the line at ``xi``: ``x``, ``l = x_/xi``, ``l_/xi``, ``l_/xixi``,
its interpolation matrix ``N`` (``x = x_0 + N q_interp`` on a chain: the reference line plus
the displacement of the element's dofs) and the test functions read as a load transfer
``G`` (``(k, 6)``: the load dofs' share of a force and a couple at ``xi``, theory (T6)); on a
chain of cubic elements, the line's compliance at ``xi``: the position
``x + G_uu lambda_L + G_u theta m_L`` under the force ``lambda_L`` and couple ``m_L`` the
line takes there (theory (T13)).  The laws use arithmetic only (no conversion of dtype), so
they evaluate on any number type numpy holds in an object array: dual numbers, and the
round-off carrying numbers of the tests.
"""

from __future__ import annotations

from collections.abc import Callable
from functools import cache
from typing import Any, NamedTuple

import numpy as np

from sliders.joints.dual import gradients, seeded, values
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


class BodyPoint(NamedTuple):
    """The body's sliding point: the offset ``f`` (3,) on the body node and the slider axes
    ``F = [e_1, e_2, e_3]`` (3, 3, columns), the point's reference position ``X_b + f`` (3,),
    the node's displacement ``u_b`` and small rotation ``theta_b`` (3,) each."""

    offset: np.ndarray
    frame: np.ndarray
    reference: np.ndarray
    u: np.ndarray
    theta: np.ndarray


class LinePoint(NamedTuple):
    """The line at ``xi``: the position ``x``, the tangent ``l = x_/xi`` and ``l_/xi`` (3,);
    the recovered tangent ``l~`` of the frictionless condition (3,); the load transfer ``G``
    (k, 6: the load dofs' share of a force, then of a couple, at ``xi``, theory (T6)); the
    section rotation ``theta_L`` and ``theta_L/xi`` (3,) with its map ``W`` (3, r) onto the
    rotation dofs and its compliance ``C_L`` under a couple (3, 3); the position compliance
    ``[G_uu, G_u theta]`` (c, 6; theory (T13), ``c = 0`` where the line has none); the
    reference frame ``R_0 = [t_0, ...]`` (3, 3) and its curvature ``k_0`` (3,),
    ``R_0/xi = k_0 x R_0``."""

    x: np.ndarray
    l: np.ndarray
    l_xi: np.ndarray
    tangent: np.ndarray
    G: np.ndarray
    theta: np.ndarray
    theta_xi: np.ndarray
    W: np.ndarray
    flex: np.ndarray
    contact: np.ndarray
    R0: np.ndarray
    k0: np.ndarray


class Unknowns(NamedTuple):
    """The joint's multipliers: ``lambda`` (3,) and ``mu`` (J,), ``scale`` times the
    physical ones (the compliances are divided by it)."""

    lam: np.ndarray
    mu: np.ndarray
    scale: float


class PointRows(NamedTuple):
    """A law's residual at the point: the force and couple on the body (3,) each, the load
    ``[force; couple]`` on the line at ``xi`` (6,), the couple on the line's section
    rotation (3,), the ``xi`` row, the position constraint rows (3,) and the orientation
    constraint rows (J,)."""

    body_force: Any
    body_couple: Any
    line_load: Any
    section_couple: Any
    xi: Any
    position: Any
    orientation: Any


def spherical(body: BodyPoint, line: LinePoint, y: Unknowns) -> PointRows:
    """The spherical slider: the position constraint, paper eq. (1), ``x_b - x(xi) = 0``
    with ``x_b = X_b + f + u_b + theta_b x f``, and the virtual work of
    ``lambda . (x_b - x(xi))``, eq. (3) with the deformable line of Sec. 4 (a)::

        delta lambda . (x_b - x)  +  delta x_b . lambda  -  delta q^T dx/dq . lambda
                                  -  delta xi l~ . lambda

    the force ``lambda`` and couple ``(f + theta_b x f) x lambda`` on the body, ``-lambda``
    on the line at ``xi`` (through the test functions, theory (T6)) and the frictionless
    condition ``-l~ . lambda`` on the recovered tangent ``l~`` (``docs/sliders.md``,
    "Corners of the interpolated chain").  On a line with a position compliance (a chain of
    cubic elements, theory (T13)) the constraint reads the line where the force ``lambda``
    it takes puts it, ``x + G_uu lambda``: a compliance of the constraint rows, never a
    load.  Every other kind adds its orientation constraints to these.
    """
    turned = np.cross(body.theta, body.offset)  # the offset turned with the body
    position = body.reference + body.u + turned - line.x
    if len(line.contact):  # x + G_uu lambda
        position = position - line.contact[:, :3] @ y.lam / y.scale
    zero = 0 * y.lam
    return PointRows(
        body_force=y.lam,
        body_couple=np.cross(body.offset + turned, y.lam),
        line_load=np.concatenate([-y.lam, zero]),
        section_couple=zero,
        xi=-(line.tangent @ y.lam),
        position=position,
        orientation=np.zeros(0, dtype=object),
    )


def classical_section(body: BodyPoint, line: LinePoint, y: Unknowns) -> PointRows:
    """The classical slider on the line's section frame (``section``, the default):
    :func:`spherical` plus ``g_j = 0``, ``j = 2, 3``, with

    ``g_j = e_j . t_0 + (e_j x t_0) . (theta_b - theta_L - kappa C m)``,

    paper eq. (4) with Sec. 4 (b) linearised in the rotations: ``e_bj . t = 0`` for the body's
    axes ``e_bj = e_j + theta_b x e_j`` and the section's axis ``t = t_0 + theta_L x t_0``,
    ``t_0`` the first axis of the line's reference frame ``R_0``; ``kappa C m`` the kink
    correction (``docs/sliders.md``).  Virtual work: :func:`_section`.
    """
    return _sum(spherical(body, line, y), _section(body, line, y, _classical_rows(body, line)))


def spline_section(body: BodyPoint, line: LinePoint, y: Unknowns) -> PointRows:
    """The spline slider: :func:`classical_section` plus ``g_1 = 0`` with

    ``g_1 = t_0 . ax(F R_0^T) + t_0 . (theta_b - theta_L - kappa C m)``,

    paper eq. (5) with Sec. 4 (c) linearised: ``phi . l = 0`` for the relative orientation
    ``phi = ax(R_b R^T)`` of the body ``R_b = (I + theta_b x) F`` and the section
    ``R = (I + theta_L x) R_0``, about ``F ~ R_0`` (the slider checks its frame within 0.1
    rad of the line's).  The multipliers are ``[mu_2, mu_3, mu_1]``.
    """
    classical, spline = _classical_rows(body, line), _spline_row(body, line)
    rows = tuple(np.concatenate(pair) for pair in zip(classical, spline, strict=True))
    return _sum(spherical(body, line, y), _section(body, line, y, rows))


def classical_slope(body: BodyPoint, line: LinePoint, y: Unknowns) -> PointRows:
    """The classical slider on the line's gradient (``slope``): :func:`spherical` plus the
    paper's eq. (4), ``g_j = e_bj . l = 0``, ``j = 2, 3``, whose virtual work is

    ``delta mu_j e_bj . l + theta_b_delta . m + delta xi sum_j mu_j e_bj . l_/xi``,

    the couple ``m = sum_j mu_j e_bj x l`` on the body and ``-m`` on the line through the
    couple columns of the test functions ``G`` (as the reference implementation does, not as
    the ``delta q^T dl/dq`` dipole of Sec. 4 (b): ``docs/sliders.md``).
    """
    e = body.frame[:, 1:3].T  # e_2, e_3 (rows)
    e_b = e + np.cross(body.theta, e)
    m = y.mu @ np.cross(e_b, line.l)
    slope = PointRows(
        body_force=0 * m,
        body_couple=m,
        line_load=np.concatenate([0 * m, -m]),
        section_couple=0 * m,
        xi=y.mu @ (e_b @ line.l_xi),
        position=0 * m,
        orientation=e_b @ line.l,
    )
    return _sum(spherical(body, line, y), slope)


def _section(
    body: BodyPoint, line: LinePoint, y: Unknowns, rows: tuple[np.ndarray, ...]
) -> PointRows:
    """The orientation constraints on the section frame and their virtual work.

    ``rows = (g0, g0_/xi, n, n_/xi)``, (J,) and (J, 3), define
    ``g_j = g0_j(xi) + n_j(xi) . (theta_b - theta_L - C_L m - G_theta u lambda)``
    (:func:`classical_section`, :func:`spline_section`).  The virtual work of
    ``sum_j mu_j g_j`` without the compliance terms gives the couple ``m = sum_j mu_j n_j``
    on the body, ``-m`` on the section rotation (``-W^T m`` on the dofs that carry
    ``theta_L = W q_rotation``) and the ``xi`` row
    ``sum_j mu_j (g0_j/xi + n_j/xi . (theta_b - theta_L) - n_j . theta_L/xi)``: the
    rotation the couple ``m`` and the force ``lambda`` the line takes at ``xi`` add there,
    ``C_L m + G_theta u lambda`` (the kink correction ``kappa C m``; a cubic element's own,
    theory (T13)), is a compliance of the constraint rows, never a load.  On a line with a
    position compliance the position rows read ``G_u theta m`` too (:func:`spherical`).
    """
    g0, g1, n0, n1 = rows
    m = y.mu @ n0
    d = body.theta - line.theta
    shift = line.flex @ m / y.scale  # C_L m
    position = 0 * m
    if len(line.contact):  # G_theta u lambda in the rotation, G_u theta m in the position
        shift = shift + y.lam @ line.contact[:, 3:] / y.scale
        position = -(line.contact[:, 3:] @ m) / y.scale
    along = g1 + n1 @ d - n0 @ line.theta_xi  # d g_j / d xi without the shift's
    return PointRows(
        body_force=0 * m,
        body_couple=m,
        line_load=np.concatenate([0 * m, 0 * m]),
        section_couple=-m,
        xi=y.mu @ along,
        position=position,
        orientation=g0 + n0 @ (d - shift),
    )


def _classical_rows(body: BodyPoint, line: LinePoint) -> tuple[np.ndarray, ...]:
    """``g0_j = e_j . t_0`` and ``n_j = e_j x t_0`` of the classical constraints (j = 2, 3)
    with their ``xi``-derivatives (``t_0/xi = k_0 x t_0``; :func:`_section`)."""
    e = body.frame[:, 1:3].T
    t0, t1 = _section_axis(line)
    return e @ t0, e @ t1, np.cross(e, t0), np.cross(e, t1)


def _spline_row(body: BodyPoint, line: LinePoint) -> tuple[np.ndarray, ...]:
    """``g0_1 = t_0 . ax(F R_0^T)`` and ``n_1 = t_0`` of the spline constraint with their
    ``xi``-derivatives (:func:`_section`): ``(F R_0^T)_/xi = -F R_0^T K_0`` with
    ``K_0 = k_0 x`` (as ``R_0/xi = K_0 R_0``)."""
    t0, t1 = _section_axis(line)
    D = body.frame @ line.R0.T
    D_xi = -D @ _skew(line.k0)
    a0, a1 = axial(D), axial(D_xi)
    return np.array([t0 @ a0]), np.array([t1 @ a0 + t0 @ a1]), t0[None], t1[None]


def _section_axis(line: LinePoint) -> tuple[np.ndarray, np.ndarray]:
    """``t_0``, the first axis of the line's reference frame, and ``t_0/xi = k_0 x t_0``."""
    t0 = line.R0[:, 0]
    return t0, np.cross(line.k0, t0)


def _sum(*parts: PointRows) -> PointRows:
    """The rows of ``parts`` added, the orientation rows of each kind one after the other."""
    first, *rest = parts
    for part in rest:
        added = [a + b for a, b in zip(first[:-1], part[:-1], strict=True)]
        orientation = np.concatenate([first.orientation, part.orientation])
        first = PointRows._make([*added, orientation])
    return first


#: The law of each ``(kind, orientation)`` a :class:`sliders.joints.slider.Slider` accepts.
LAWS: dict[tuple[str, str], Callable[[BodyPoint, LinePoint, Unknowns], PointRows]] = {
    ("spherical", "section"): spherical,
    ("classical", "section"): classical_section,
    ("spline", "section"): spline_section,
    ("classical", "slope"): classical_slope,
}


def law_of(kind: str, orientation: str) -> Callable[[BodyPoint, LinePoint, Unknowns], PointRows]:
    """The point law of a ``kind`` slider with the ``orientation`` model."""
    try:
        return LAWS[kind, orientation]
    except KeyError:
        raise ValueError(
            f"no slider equations for kind {kind!r} with orientation {orientation!r}; "
            f"known: {', '.join(map(str, LAWS))}"
        ) from None


def scatter(rows: PointRows, line: LinePoint) -> dict[str, Any]:
    """A point law's rows on the joint's row groups: the body's force and couple on its
    translations and rotations, the load on the line at ``xi`` through the test functions
    (``G [force; couple]``, theory (T6)), the section couple through the rotation's map
    (``W^T m``), and the ``xi``, position and orientation rows as they are."""
    return {
        "body": rows.body_force,
        "turn": rows.body_couple,
        "load": line.G @ rows.line_load,
        "rotation": line.W.T @ rows.section_couple,
        "xi": np.array([rows.xi]),
        "lam": rows.position,
        "mu": rows.orientation,
    }


#: The joint's row groups (:func:`scatter`) and its column groups, in the slot order of
#: :class:`sliders.joints.blocks.SlotJacobian` (``load`` carries no column: no law reads
#: the load dofs but through the line's maps).
ROWS = ("body", "turn", "load", "rotation", "xi", "lam", "mu")
#: Every slot group, in slot order.
SLOTS = ("body", "turn", "load", "rotation", "interp", "beside", "xi", "lam", "mu")
COLUMNS = ("body", "turn", "rotation", "interp", "beside", "xi", "lam", "mu")


@cache
def pattern(
    kind: str, orientation: str, lever: bool, rotation: bool, compliant: bool = False
) -> tuple[tuple[str, str], ...]:
    """The Jacobian blocks a ``kind`` slider with the ``orientation`` model writes: its law's
    sparsity, read off the law's derivative (:func:`derive`) at random inputs on small groups
    (two load, two interpolated, one beside dof), with the sliding point off the node
    (``lever``), the line's section rotation dofs (``rotation``) and a position compliance
    (``compliant``: a chain of cubic elements) where asked; in slot order.  A block the law
    does not read is exactly zero there (a dual carries only the directions it depends on);
    one it reads is zero at random inputs with probability zero."""
    rng = np.random.default_rng(0)
    J = {"spherical": 0, "classical": 2, "spline": 3}[kind]
    r, c = (2 if rotation else 0), (3 if compliant else 0)

    def draw(*shape: int) -> np.ndarray:
        return rng.uniform(-1.0, 1.0, shape)

    inputs = JointInputs(
        offset=draw(3) if lever else np.zeros(3),
        frame=draw(3, 3),
        body=np.arange(6)[None],
        reference=draw(1, 3),
        q=draw(1, 6 + r),
        y=draw(1, 4 + J),
        x=draw(1, 3),
        l=draw(1, 3),
        l_xi=draw(1, 3),
        l_xixi=draw(1, 3),
        N=draw(1, 3, 2),
        dN=draw(1, 3, 2),
        d2N=draw(1, 3, 2),
        G=draw(1, 2, 6),
        dG=draw(1, 2, 6),
        tangent=draw(1, 3),
        tangent_xi=draw(1, 3),
        T=draw(1, 3, 3),
        contact=draw(1, c, 6),
        contact_xi=draw(1, c, 6),
        rotation_dofs=6 + np.arange(r)[None],
        W=draw(1, 3, r),
        W_xi=draw(1, 3, r),
        W_xixi=draw(1, 3, r),
        flex=draw(1, 3, 3),
        flex_xi=draw(1, 3, 3),
        R0=draw(1, 3, 3),
        k0=draw(1, 3),
        k0_xi=draw(1, 3),
        scale=1.0,
    )
    blocks = derive(law_of(kind, orientation), inputs).jacobian
    order = {group: i for i, group in enumerate(SLOTS)}
    written = [key for key, block in blocks.items() if np.any(block != 0)]
    return tuple(sorted(written, key=lambda key: (order[key[0]], order[key[1]])))


def joint_reference(kind: str, orientation: str, inputs: JointInputs) -> Equations:
    """The residuals and Jacobian blocks of a ``kind`` slider with the ``orientation`` model
    at ``inputs``: its point law (:data:`LAWS`) scattered onto the slots (:func:`scatter`),
    differentiated by dual numbers (:func:`derive`)."""
    return derive(law_of(kind, orientation), inputs)


def derive(law: Callable[[BodyPoint, LinePoint, Unknowns], PointRows], s: JointInputs) -> Equations:
    """A point law's residuals and its exact Jacobian at the inputs of ``B`` members.

    Each member's point quantities are seeded as duals (:mod:`sliders.joints.dual`) in the
    joint's column groups through the line's maps: ``x`` moves with ``xi`` by ``l`` and with
    the interpolated dofs by ``N``, ``l`` by ``l_/xi`` and ``dN``, ``l_/xi`` by ``l_/xixi``
    and ``d2N``, ``l~`` by ``l~_/xi`` and ``T`` (interpolated and beside dofs), ``G`` by
    ``G_/xi``, ``W`` by ``W_/xi`` (and ``W_/xi`` by ``W_/xixi``, ``theta_L/xi = W_/xi
    q_rotation``), ``C_L`` and the contact compliance by theirs, ``R_0`` by ``k_0 x R_0`` and
    ``k_0`` by ``k_0/xi``; the body's ``u_b``, ``theta_b``, the rotation dofs and the
    multipliers are their own columns.  The law run on them and scattered gives each row's
    value and gradient: the chain rule through the line's maps is the seeding, written once
    for every kind.
    """
    B = len(s.y)
    m, p, r = s.N.shape[2], s.T.shape[2], s.W.shape[2]
    J = s.y.shape[1] - 4
    sizes = dict(zip(COLUMNS, (3, 3, r, m, p - m, 1, 3, J), strict=True))
    seed = _Seeds(sizes)
    at, n = seed.at, seed.n
    residual: dict[str, list[np.ndarray]] = {g: [] for g in ROWS}
    jacobian: dict[str, list[np.ndarray]] = {g: [] for g in ROWS}
    for b in range(B):
        nodal = np.take(s.q[b], s.body[b])
        q_rot = seed.own("rotation", np.take(s.q[b], s.rotation_dofs[b]))
        T = s.T[b]
        W = seed.moving(s.W[b], s.W_xi[b])
        W_xi = seed.moving(s.W_xi[b], s.W_xixi[b])
        line = LinePoint(
            x=seed.moving(s.x[b], s.l[b], interp=s.N[b]),
            l=seed.moving(s.l[b], s.l_xi[b], interp=s.dN[b]),
            l_xi=seed.moving(s.l_xi[b], s.l_xixi[b], interp=s.d2N[b]),
            tangent=seed.moving(s.tangent[b], s.tangent_xi[b], interp=T[:, :m], beside=T[:, m:]),
            G=seed.moving(s.G[b], s.dG[b]),
            theta=W @ q_rot,
            theta_xi=W_xi @ q_rot,
            W=W,
            flex=seed.moving(s.flex[b], s.flex_xi[b]),
            contact=seed.moving(s.contact[b], s.contact_xi[b]),
            R0=seed.moving(s.R0[b], _skew(s.k0[b]) @ s.R0[b]),
            k0=seed.moving(s.k0[b], s.k0_xi[b]),
        )
        body = BodyPoint(
            offset=s.offset,
            frame=s.frame,
            reference=s.reference[b],
            u=seed.own("body", nodal[:3]),
            theta=seed.own("turn", nodal[3:]),
        )
        y = Unknowns(seed.own("lam", s.y[b, 1:4]), seed.own("mu", s.y[b, 4:]), s.scale)
        for group, rows in scatter(law(body, line, y), line).items():
            rows = np.asarray(rows, dtype=object).reshape(-1)
            residual[group].append(values(rows))
            jacobian[group].append(gradients(rows, n))
    equations = Equations({}, {})
    for group in ROWS:
        rows = np.array(residual[group], dtype=object).reshape(B, -1)
        if not rows.shape[1]:
            continue
        equations.residual[group] = _numbers(rows)
        grad = np.array(jacobian[group], dtype=object).reshape(B, rows.shape[1], n)
        for column in COLUMNS:
            if sizes[column]:
                block = grad[:, :, at[column] : at[column] + sizes[column]]
                equations.jacobian[group, column] = _numbers(block)
    return equations


class _Seeds:
    """Duals in the joint's columns (:data:`COLUMNS`, of ``sizes``) for :func:`derive`."""

    def __init__(self, sizes: dict[str, int]) -> None:
        self.at, self.n = self.layout(sizes)

    @staticmethod
    def layout(sizes: dict[str, int]) -> tuple[dict[str, int], int]:
        """The first column of each group and the number of columns."""
        first = np.cumsum([0, *sizes.values()]).tolist()
        return dict(zip(sizes, first[:-1], strict=True)), first[-1]

    def _columns(self, group: str, a: np.ndarray) -> dict[int, np.ndarray]:
        """The derivative ``a`` (its last axis the group's columns) by column index."""
        return {self.at[group] + j: a[..., j] for j in range(np.shape(a)[-1])}

    def own(self, group: str, value: np.ndarray) -> np.ndarray:
        """``value`` (the group's size) seeded as the group's own columns."""
        return seeded(value, self._columns(group, np.eye(len(value), dtype=value.dtype)))

    def moving(self, value: np.ndarray, rate: np.ndarray, **maps: np.ndarray) -> np.ndarray:
        """A line quantity ``value`` whose ``xi``-derivative is ``rate`` and whose derivatives
        in the dofs of the groups ``maps`` names are theirs (last axis the group's columns)."""
        directions = {self.at["xi"]: rate}
        for group, a in maps.items():
            directions.update(self._columns(group, a))
        return seeded(value, directions)


def _numbers(a: np.ndarray) -> np.ndarray:
    """An object array of floats as a float array; of any other number type, as it is."""
    try:
        return a.astype(float) if all(isinstance(e, float | int) for e in a.flat) else a
    except TypeError:
        return a


def _skew(v: np.ndarray) -> np.ndarray:
    """``skew(v)``, the matrix of ``v x``, for a 3-vector of any number type."""
    zero = 0 * v[0]
    return np.array([[zero, -v[2], v[1]], [v[2], zero, -v[0]], [-v[1], v[0], zero]], dtype=object)
