"""Joints between nodes with finite rotations: each law stated once, its derivatives derived.

A joint holds two points, one on node ``a`` and one on node ``b`` (a beam node or a rigid
body of an exact model, :mod:`sliders.joints.exact_model`; or the ground, which does not
move).  Each node has a position ``x`` and a rotation ``R`` (the identity in the reference
configuration); the joint's point sits at the offsets ``p_a``, ``p_b`` from the nodes and
carries the frames ``F_a``, ``F_b`` (orthonormal, columns ``[e_1, e_2, e_3]``), all in the
nodes' reference axes.  In the current configuration the frames are ``D_a = R_a F_a``,
``D_b = R_b F_b`` (columns ``d_ai``, ``d_bi``) and the gap between the points is

    g = (x_b + R_b p_b) - (x_a + R_a p_a).

**Rows.**  A joint is a choice of the six rows (:func:`rows`)::

    ux, uy, uz:   d_ai . g = 0            (the points coincide along e_i of frame a)
    rx:           d_a2 . d_b3 = 0
    ry:           d_a1 . d_b3 = 0         (axis directions orthogonal)
    rz:           d_a1 . d_b2 = 0

In the reference configuration (``F_a = F_b``, the points at one place) every row is zero;
to first order the rotation rows are ``-theta_1, theta_2, -theta_3``, the components of the
relative rotation ``theta_b - theta_a`` in frame ``a``, and the position rows the components
of the gap: the linear joint's rows.  The kinds (:data:`KINDS`) choose:

* ``spherical``: ``ux uy uz``, the points coincide;
* ``revolute`` (a hinge about ``e_1``): plus ``ry rz``, the axis ``d_a1`` stays orthogonal
  to ``d_b2`` and ``d_b3``, i.e. along ``d_b1``, at any angle of the hinge;
* ``universal`` (Cardan): plus ``rx``, the cross's pins ``d_a2`` (on ``a``) and ``d_b3``
  (on ``b``) stay orthogonal, the two shafts along ``e_1``;
* ``prismatic`` (sliding along ``e_1``): ``uy uz rx ry rz``;
* ``fixed``: all six.

Any other choice is written as the rows' names joined by ``+`` (``"uy+rz"``, a support
that holds a point on an inclined line and its rotation about ``e_3``): a support is a
joint to the ground, in any frame.

**Multipliers and reactions.**  With the multipliers ``lambda`` of the rows ``c``, the
joint's virtual work is ``lambda . delta c``; its contribution to the nodes' balances
``r(q) = f`` is ``B^T lambda`` with ``B = dc/dq`` on the nodes' spatial increments
``[du, dphi]`` (``dx = du``, ``dR = skew(dphi) R``), and to the tangent the *geometric
stiffness* ``H = d(B^T lambda)/dq`` at fixed ``lambda``: the multipliers times the rows'
second variation.  ``B^T lambda`` on node ``b`` is the load the joint carries from ``b``: on
a node held only by the joint, it balances the node's load.  Nothing but the rows is written
by hand: :func:`derive` runs :func:`rows` on dual numbers (:mod:`sliders.joints.dual`)
nested twice, a virtual variation ``eta`` inside a change of state ``epsilon``, each seeded
as ``x + epsilon du``, ``(I + epsilon skew(dphi)) R``; the first order in ``eta`` is ``B``
and ``B^T lambda``, the mixed order ``eta epsilon`` is ``H``, which is exactly Newton's
tangent for the update ``R <- exp(dphi) R`` (the exponential's second-order term has no
mixed part).  The same seeding on sympy symbols writes the rows' generated form
(:mod:`sliders.joints.exact_generate` writes :mod:`sliders.joints.exact_rows`), which
:func:`derive_many` runs over many joints at once and the models use; :func:`derive` is the
reference it is held to.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from fvbeam.geometry import orthonormal3, skew_matrices, vector3
from sliders.joints.dual import gradients, seeded, values
from sliders.joints.exact_rows import ROW_FUNCTIONS

#: The six rows a joint may hold, in order (module docstring).
ROWS = ("ux", "uy", "uz", "rx", "ry", "rz")
#: The axes of frame ``a`` and frame ``b`` whose directions stay orthogonal, per rotation row.
ORTHOGONAL = {"rx": (1, 2), "ry": (0, 2), "rz": (0, 1)}
#: The rows written in generated form (:mod:`sliders.joints.exact_rows`), and each row as one
#: of them on the frames' columns in another order: ``ux`` reads ``d_a1``, so ``uy`` is
#: ``ux`` with frame ``a``'s columns ``(2, 1, 3)``; ``rx`` reads ``d_a2, d_b3``, so ``ry`` is
#: ``rx`` with frame ``a``'s ``(2, 1, 3)``.  (row, frame a's columns, frame b's columns).
GENERATED = ("ux", "rx")
AS_GENERATED = {
    "ux": ("ux", (0, 1, 2), (0, 1, 2)),
    "uy": ("ux", (1, 0, 2), (0, 1, 2)),
    "uz": ("ux", (2, 1, 0), (0, 1, 2)),
    "rx": ("rx", (0, 1, 2), (0, 1, 2)),
    "ry": ("rx", (1, 0, 2), (0, 1, 2)),
    "rz": ("rx", (1, 0, 2), (0, 2, 1)),
}
#: The rows of each kind of joint.
KINDS = {
    "spherical": "ux+uy+uz",
    "revolute": "ux+uy+uz+ry+rz",
    "universal": "ux+uy+uz+rx",
    "prismatic": "uy+uz+rx+ry+rz",
    "fixed": "ux+uy+uz+rx+ry+rz",
}


def selected_rows(kind: str, label: str) -> tuple[str, ...]:
    """The rows (in :data:`ROWS` order) of a kind of :data:`KINDS` or of rows joined by
    ``+``; ``ValueError`` naming ``label`` and the offending word."""
    if not isinstance(kind, str) or not kind:
        raise ValueError(f"{label}: kind must be one of {', '.join(KINDS)} or rows joined by +")
    words = KINDS.get(kind, kind).split("+")
    for word in words:
        if word not in ROWS:
            raise ValueError(
                f"{label}: {word!r} is neither a kind of joint ({', '.join(KINDS)}) nor a "
                f"row ({' '.join(ROWS)})"
            )
    if len(set(words)) != len(words):
        raise ValueError(f"{label}: a row is named twice in {kind!r}")
    return tuple(row for row in ROWS if row in words)


@dataclass(frozen=True)
class JointLaw:
    """A joint's geometry: its rows (:data:`ROWS`), the offsets ``p_a``, ``p_b`` (3,) and
    frames ``F_a``, ``F_b`` (3, 3, columns) of its point in the nodes' reference axes."""

    rows: tuple[str, ...]
    offset_a: np.ndarray
    offset_b: np.ndarray
    frame_a: np.ndarray
    frame_b: np.ndarray

    @classmethod
    def at(
        cls,
        kind: str,
        position: ArrayLike,
        frame: ArrayLike,
        node_a: ArrayLike,
        node_b: ArrayLike,
        label: str = "joint",
    ) -> JointLaw:
        """The joint of ``kind`` (:func:`selected_rows`) at ``position`` with the frame
        ``frame`` (columns, global axes) in the reference configuration, between nodes whose
        reference positions are ``node_a`` and ``node_b`` (the ground: the position itself)."""
        point = vector3(position, f"{label}: position")
        F = orthonormal3(frame, f"{label}: frame")
        a, b = vector3(node_a, f"{label}: node a"), vector3(node_b, f"{label}: node b")
        return cls(selected_rows(kind, label), point - a, point - b, F, F.copy())


class Derived(NamedTuple):
    """A joint's rows at a state and what :func:`derive` derives from them: the rows ``c``
    (m,), ``B = dc/dq`` (m, 12) on ``[du_a, dphi_a, du_b, dphi_b]``, the geometric stiffness
    ``H = d(B^T lambda)/dq`` (12, 12)."""

    rows: np.ndarray
    jacobian: np.ndarray
    stiffness: np.ndarray


def rows(law: JointLaw, x_a: Any, R_a: Any, x_b: Any, R_b: Any) -> np.ndarray:
    """The joint's rows (module docstring) at node positions ``x`` (3,) and rotations ``R``
    (3, 3): ``d_ai . g`` for the position rows, ``d_ai . d_bj`` for the rotation rows.
    Arithmetic only (numbers or the duals of :func:`derive`)."""
    D_a, D_b = R_a @ law.frame_a, R_b @ law.frame_b
    gap = (x_b + R_b @ law.offset_b) - (x_a + R_a @ law.offset_a)
    out = []
    for row in law.rows:
        if row in ORTHOGONAL:
            i, j = ORTHOGONAL[row]
            out.append(D_a[:, i] @ D_b[:, j])
        else:
            out.append(D_a[:, ROWS.index(row)] @ gap)
    return np.array(out, dtype=object)


def _varied(x: np.ndarray, R: np.ndarray, first: int) -> tuple[np.ndarray, np.ndarray]:
    """``x`` and ``R`` as duals of a change of state ``epsilon`` holding duals of a
    variation ``eta``, both in the directions ``first .. first + 5``: ``[du, dphi]``."""
    unit = np.eye(3)
    turns = skew_matrices(unit)  # skew(e_k)
    x_e = seeded(x, {first + k: unit[k] for k in range(3)})
    R_e = seeded(R, {first + 3 + k: turns[k] @ R for k in range(3)})
    x_n = seeded(x_e, {first + k: unit[k] for k in range(3)})
    R_n = seeded(R_e, {first + 3 + k: turns[k] @ R_e for k in range(3)})
    return x_n, R_n


def derive(
    law: JointLaw,
    x_a: np.ndarray,
    R_a: np.ndarray,
    x_b: np.ndarray,
    R_b: np.ndarray,
    multipliers: np.ndarray,
    moving: tuple[bool, bool] = (True, True),
) -> Derived:
    """The rows, their Jacobian and the geometric stiffness of the multipliers (module
    docstring) at the nodes' states; a node that is not ``moving`` is the ground (its
    columns stay zero)."""
    ends = []
    for k, (x, R) in enumerate(((x_a, R_a), (x_b, R_b))):
        x, R = np.asarray(x, dtype=float), np.asarray(R, dtype=float)
        ends.append(_varied(x, R, 6 * k) if moving[k] else (x, R))
    (xa, Ra), (xb, Rb) = ends
    c = rows(law, xa, Ra, xb, Rb)
    work = np.array([sum(float(m) * r for m, r in zip(multipliers, c, strict=True))])
    return Derived(
        values(values(c)).astype(float),
        values(gradients(c, 12)).astype(float),
        gradients(gradients(work, 12)[0], 12).astype(float),
    )


def derive_many(
    laws: Sequence[JointLaw],
    x_a: np.ndarray,
    R_a: np.ndarray,
    x_b: np.ndarray,
    R_b: np.ndarray,
    multipliers: Sequence[np.ndarray],
    moving: np.ndarray,
) -> list[Derived]:
    """:func:`derive` of many joints at once, by the rows' generated form
    (:mod:`sliders.joints.exact_rows`, written from :func:`rows` by
    :mod:`sliders.joints.exact_generate`): each row name evaluated over every joint that
    holds it.  ``x_a``, ``x_b`` (J, 3), ``R_a``, ``R_b`` (J, 3, 3) the ends' states,
    ``multipliers`` each joint's, ``moving`` (J, 2) whether each end is a node (else the
    ground: its columns are zero)."""
    J = len(laws)
    values = [np.zeros(len(law.rows)) for law in laws]
    jacobians = [np.zeros((len(law.rows), 12)) for law in laws]
    stiffness = np.zeros((J, 12, 12))
    nodes = [x_a, R_a.reshape(J, 9), x_b, R_b.reshape(J, 9)]
    offsets = [np.array([law.offset_a for law in laws]), np.array([law.offset_b for law in laws])]
    frames = [np.array([law.frame_a for law in laws]), np.array([law.frame_b for law in laws])]
    for name, (generated, columns_a, columns_b) in AS_GENERATED.items():
        pairs = [(j, law.rows.index(name)) for j, law in enumerate(laws) if name in law.rows]
        if not pairs:
            continue
        joints = [j for j, _ in pairs]
        turned = [
            F[joints][:, :, list(c)] for F, c in zip(frames, (columns_a, columns_b), strict=True)
        ]
        fields = [f[joints] for f in nodes + offsets] + [F.reshape(-1, 9) for F in turned]
        B, H = np.zeros((12, len(pairs))), np.zeros((12, 12, len(pairs)))
        value = ROW_FUNCTIONS[generated](np.hstack(fields).T, B, H)  # inputs (48, n)
        for n, (j, k) in enumerate(pairs):
            values[j][k] = value[n]
            jacobians[j][k] = B[:, n]
            stiffness[j] += multipliers[j][k] * H[:, :, n]
    held = np.repeat(~np.asarray(moving, dtype=bool), 6, axis=1)  # (J, 12) ground columns
    out = []
    for j in range(J):
        jacobians[j][:, held[j]] = 0.0
        stiffness[j][held[j]] = 0.0
        stiffness[j][:, held[j]] = 0.0
        out.append(Derived(values[j], jacobians[j], stiffness[j]))
    return out
