"""Sliders on lines of exact beams: each law stated once, its derivatives derived.

The paper's slider (Gualdi, Morandini and Masarati, Secs. 3-4) with finite rotations.  The
body is a node of an exact model (position ``x_b``, rotation ``R_b``) carrying the sliding
point at the offset ``f`` and the slider axes ``F = [e_1, e_2, e_3]`` (columns), both in the
node's reference axes: the point is ``x_b + R_b f`` and the body's axes are ``E = R_b F``,
columns ``e_bj``.  The line at ``xi`` (:mod:`sliders.lines.exact_line`) has the position
``x(xi)``, the gradient ``l = x_/xi``, the section frame ``D(xi) = Lambda(xi) R_0(xi)`` with
axis ``t = D e_1`` and the curvature ``k = ax(D_/xi D^T)``.  The joint's unknowns are
``[xi, lambda, mu]``, ``mu = [mu_2, mu_3]`` for the classical slider, ``[mu_2, mu_3, mu_1]``
for the spline slider (the linear slider's order).

**Rows** (:func:`rows`), the constraints ``c`` at a point of the line ``(x_L, D_L)``::

    spherical:  x_b + R_b f - x_L = 0                              (eq. 1)
    classical:  + e_b2 . t = 0,  e_b3 . t = 0           (eq. 4 on the section's axis, Sec. 4 b)
    spline:     + ax(R_Delta) . t = 0,  R_Delta = E D_L^T       (eq. 5, Sec. 4 c)

**Virtual work** ``delta (y . c)`` (eqs. 3-5 and Sec. 4 (a)-(c)): the line's point varies
by ``delta x_L`` and its section frame with the rotations of the two nodes that turn it,
``delta theta_L = ax(delta D_L D_L^T)`` (the ``Gamma delta theta`` of Sec. 4, through the
interpolation of :func:`sliders.lines.exact_line.section_frame`), and with ``xi`` by
``l delta xi`` and ``k delta xi``.  So the derivative of ``y . c`` gives the force and couple
on the body, the force ``f_L`` on the line's point (which the line's test functions carry to
its nodes: :func:`sliders.lines.exact_line.transfer`), the couple on the two nodes (the
interpolation's own virtual work: to first order the linear slider's ``(1 - s, s)`` shares,
which never jump) and the ``xi`` row, with ``m_L`` the couple on the section,

    f_L . l + m_L . k = 0,

for the spherical slider ``-lambda . l`` (eq. 3), and for the orientation constraints the
couple's work through the line's curvature: ``-m . k`` with ``m = sum_j mu_j (e_bj x t)``
(plus the spline's ``-mu_1 k . R_Delta^T t`` and ``ax``'s own), the term that makes the
*configurational force* of a bent line.  In the reference configuration the rows and their
derivatives are the linear slider's (:mod:`sliders.joints.equations`, ``section``
orientation): ``tests/test_exact_sliders.py`` holds them equal at first order.

**Kink correction** (classical and spline): as on linear lines (:mod:`sliders.joints.
equations`, ``docs/sliders.md``), the couple ``M`` the line takes at ``xi`` turns its
section there off the nodes' interpolation by ``kappa C M`` (the linear chain's
``flex``, turned with the section): the rows read ``D_L`` turned by ``cay(kappa C M)``, a
compliance of the rows, never a load; the ``xi`` row carries half its rate,
``M . kappa_/xi C M / 2`` (the change with ``xi`` of the compliance's energy), which makes
the configurational force of a bent rod independent of where ``xi`` sits in its node span
(``docs/exact_sliders.md``).

**Derivation.**  Nothing but :func:`rows` and the line's interpolation is written by hand:
:func:`derive` runs them on dual numbers nested twice, as
:func:`sliders.joints.exact_laws.derive` does: an outer change of state ``epsilon`` in the
joint's columns (the body's and the line's nodes' ``[du, dphi]``, seeded as ``x + epsilon du``,
``(I + epsilon skew(dphi)) R``, and ``xi`` through the line's rates, and the multipliers),
and an inner virtual variation ``eta`` (:data:`VIRTUAL`) of the body, of the line's point
(``x_L`` by ``delta x_L`` and ``l delta xi``) and of the two nodes' rotations and the
section's weight and reference frame along ``xi`` (``D_L`` recomputed from them).  The
first order in ``eta`` of ``y . c`` is the joint's loads and
``xi`` row; their order ``epsilon`` (and that of ``c``) is Newton's tangent, geometric
stiffness included.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from fvbeam.geometry import skew_matrices
from sliders.joints.dual import Dual, gradients, seeded, values
from sliders.lines.exact_line import (
    LineSite,
    axial,
    cayley,
    position,
    section_frame,
    skew,
    transfer,
)

#: The slider kinds built on exact lines and their orientation rows.
KINDS = {"spherical": 0, "classical": 2, "spline": 3}
#: The virtual variation's directions (:func:`derive`): the body's ``[du, dphi]`` (0-5), the
#: line point's ``du`` (6-8), the rotations of the two nodes that turn the section (9-14),
#: ``xi`` (15).
VIRTUAL = 16


@dataclass(frozen=True)
class SliderPoint:
    """A slider's body point: its ``kind`` (:data:`KINDS`), the offset ``f`` (3,) and the
    slider axes ``F`` (3, 3, columns) in the body node's reference axes."""

    kind: str
    offset: np.ndarray
    frame: np.ndarray

    @property
    def n_unknowns(self) -> int:
        """``xi``, ``lambda`` (3) and the orientation multipliers."""
        return 4 + KINDS[self.kind]


def rows(point: SliderPoint, x_b: Any, R_b: Any, x_L: Any, D_L: Any) -> np.ndarray:
    """The slider's constraints (module docstring) at the body node ``x_b``, ``R_b`` and the
    line's point ``x_L`` with its section frame ``D_L``.  Arithmetic only."""
    out = list(x_b + R_b @ point.offset - x_L)
    if point.kind == "spherical":
        return np.array(out, dtype=object)
    E = R_b @ point.frame
    t = D_L[:, 0]
    out += [E[:, 1] @ t, E[:, 2] @ t]
    if point.kind == "spline":
        out.append(axial(E @ D_L.T) @ t)
    return np.array(out, dtype=object)


class SliderDerived(NamedTuple):
    """A slider's residual and tangent on its local columns: the body's six dofs, then each
    of ``nodes`` six (the line's), then ``xi``, ``lambda``, ``mu``.  Rows likewise: the loads
    on the body and the line's nodes, the ``xi`` row, the constraints.  ``load`` the force
    and couple on the line's point (6,), ``arms`` the line's ``l`` and ``k`` (for the
    residual's round-off floor), ``along`` the frictionless ``xi`` row's value
    ``f_L . l + m_L . k`` (zero unless driven: then the force the drive holds the contact
    with, along the line)."""

    nodes: np.ndarray
    residual: np.ndarray
    tangent: np.ndarray
    load: np.ndarray
    arms: np.ndarray
    along: float


def _state(x: np.ndarray, R: np.ndarray, first: int) -> tuple[np.ndarray, np.ndarray]:
    """A node's ``x`` and ``R`` as duals of a change of state in the directions
    ``first .. first + 5``: ``[du, dphi]``."""
    unit = np.eye(3)
    x_e = seeded(x, {first + k: unit[k] for k in range(3)})
    R_e = seeded(R, {first + 3 + k: skew_matrices(unit)[k] @ R for k in range(3)})
    return x_e, R_e


def _varied(x: Any, R: Any, first: int) -> tuple:
    """``x`` (unless None) and ``R`` as duals of a virtual variation: ``x`` in
    ``first .. first + 2``, ``R`` by ``skew(e_k) R`` in ``first + 3 .. first + 5``."""
    unit, turns = np.eye(3), skew_matrices(np.eye(3))
    dR = {first + 3 + k: turns[k] @ R for k in range(3)}
    x_v = None if x is None else seeded(x, {first + k: unit[k] for k in range(3)})
    return x_v, seeded(R, dR)


def derive(
    point: SliderPoint,
    site: LineSite,
    x: np.ndarray,
    R: np.ndarray,
    body: int,
    y: np.ndarray,
    X: np.ndarray,
    held: float | None = None,
) -> SliderDerived:
    """The slider's residual and tangent (module docstring) at the nodes' positions ``x``
    (n, 3) and rotations ``R`` (n, 3, 3), ``body`` the body's node, ``y`` the joint's
    unknowns ``[xi, lambda, mu]`` (the line's ``site`` read at ``xi``), ``X`` (n, 3) the
    nodes' reference positions.  A driven slider's abscissa is ``held``: its ``xi`` row is
    ``xi - held`` (the frictionless row's value, ``f_L . l + m_L . k``, is then the drive's
    force along the line), as on linear lines."""
    nodes = site.touched
    if body in set(nodes.tolist()):
        raise ValueError("a slider's body may not be a node of its own line")
    n_line = len(nodes)
    at_xi = 6 + 6 * n_line
    n_y = len(y)
    n = at_xi + n_y  # xi is the first unknown
    slot = {int(node): 6 + 6 * i for i, node in enumerate(nodes)}
    x_b, R_b = _state(x[body], R[body], 0)
    x_n = {int(a): _state(x[a], R[a], slot[int(a)]) for a in nodes}

    def along(value: np.ndarray, rate: np.ndarray) -> np.ndarray:
        return seeded(value, {at_xi: rate})

    N, dN = along(site.N, site.dN), along(site.dN, site.d2N)
    x_L, l = position(np.array([x_n[int(a)][0] for a in site.nodes]), N, dN)
    s = along(np.array([site.s]), np.array([site.s_xi]))[0]
    R0 = along(site.R0, np.asarray(skew(site.k0) @ site.R0, dtype=float))
    k0 = along(site.k0, site.k0_xi)
    # the multipliers change with the state, not with the virtual variation
    mult = [
        Dual(m, {})
        for m in seeded(y[1:], {at_xi + 1 + j: np.eye(n_y - 1)[j] for j in range(n_y - 1)})
    ]
    # the virtual variation (VIRTUAL): the body, the line's point, the two nodes that turn
    # the section, xi (the point along l, the section's weight and reference frame)
    xb_v, Rb_v = _varied(x_b, R_b, 0)
    xL_v = seeded(x_L, {**{6 + k: np.eye(3)[k] for k in range(3)}, 15: l})
    pair = [_varied(None, x_n[int(a)][1], 6 + 3 * j)[1] for j, a in enumerate(site.pair)]
    D_L, k = section_frame(
        pair[0],
        pair[1],
        seeded(np.array([s]), {15: np.array([site.s_xi])})[0],
        site.s_xi,
        seeded(R0, {15: skew(k0) @ R0}),
        k0,
    )
    c = rows(point, xb_v, Rb_v, xL_v, D_L)
    virtual = _virtual(mult, c)
    if point.kind != "spherical":  # the kink correction at the couple the line takes
        couple = -(virtual[9:12] + virtual[12:15])  # exerted on the line: minus its load
        Lam = values(D_L) @ R0.T  # Lambda, as duals of the change of state
        flex = along(site.flex, site.flex_xi)
        kink = Lam @ flex @ Lam.T @ couple
        # along xi, half the compliance's rate: the xi row of its energy m . C m / 2
        rate = 0.5 * (Lam @ along(site.flex_xi, site.flex_xixi) @ Lam.T @ couple)
        D_L = cayley(seeded(kink, {15: rate})) @ D_L
        c = rows(point, xb_v, Rb_v, xL_v, D_L)
        virtual = _virtual(mult, c)
    load = virtual[6:9]
    G = along(site.G[:, :3], site.G_xi[:, :3])
    X_nodes = {int(a): X[a] for a in nodes}
    moved = x_L - along(site.X, site.l0)
    line_load = transfer(site, G, load, moved, {a: v[0] for a, v in x_n.items()}, X_nodes)
    residual = np.full(n, 0.0, dtype=object)
    residual[:6] = virtual[:6]
    for i, dof in enumerate(site.load_dofs):
        j = slot[int(dof) // 6] + int(dof) % 6
        residual[j] = residual[j] + line_load[i]
    for j, a in enumerate(site.pair):
        at = slot[int(a)] + 3
        for m in range(3):
            residual[at + m] = residual[at + m] + virtual[9 + 3 * j + m]
    residual[at_xi] = virtual[15] if held is None else Dual(y[0], {at_xi: 1.0}) - held
    residual[at_xi + 1 :] = values(c)
    couple = virtual[9:12] + virtual[12:15]
    return SliderDerived(
        nodes,
        values(residual).astype(float),
        gradients(residual, n).astype(float),
        _number(np.concatenate([load, couple])),
        np.concatenate([_number(l), _number(values(k))]),
        float(_number(np.array([virtual[15]]))[0]),
    )


def _virtual(mult: list, c: np.ndarray) -> np.ndarray:
    """The order ``eta`` of ``y . c`` (:data:`VIRTUAL` duals of the change of state)."""
    work = sum(m * r for m, r in zip(mult, c, strict=True))
    return gradients(np.array([work], dtype=object), VIRTUAL)[0]


def _number(a: np.ndarray) -> np.ndarray:
    """The values of duals as floats."""
    return np.array([e.value if isinstance(e, Dual) else e for e in a], dtype=float)
