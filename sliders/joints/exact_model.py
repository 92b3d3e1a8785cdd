"""Exact models: geometrically exact beams and rigid bodies held by joints with finite rotations.

The nodes are a :class:`~fvbeam.structure.Structure`'s, on its numbering: its beams'
(:class:`~fvbeam.exact_beam.ExactBeam`) in beam order, then its bodies'
(:class:`~fvbeam.exact_bodies.ExactBodies`), tied nodes one node
(:class:`~fvbeam.exact_structure.ExactStructure`), and named as there (``"C.end"``,
``(0, 3)``, ``"hub"``); ``"ground"`` is the fixed frame.  Each
:class:`Joint` adds its rows ``c`` (:mod:`sliders.joints.exact_laws`) and as many multipliers
``lambda``, after the nodes' dofs.  The problem is

    r(q) + sum_j B_j^T lambda_j = f,        c_j(q) = 0,

``r`` the beams' internal forces, ``B_j = dc_j/dq`` on the nodes' spatial increments, ``f``
dead nodal loads (zero on the multipliers).  Its tangent borders the beams' (material and
geometric) with the joints' rows and adds their geometric stiffness ``H_j``::

    [ K + sum_j H_j   B^T ]
    [ B               0   ]

:class:`ExactModel` has the operator interface of an exact beam (``reference``, ``points``,
``residual``, ``residual_floor``, ``tangent``, ``n_dofs``, and a state with ``updated``), so
:func:`fvbeam.exact_statics.solve_static` solves it: ``fixed`` clamps nodes' dofs in global
axes, a support in any other frame is a joint to ``"ground"``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from numpy.typing import ArrayLike

from fvbeam.body import RigidBody
from fvbeam.exact_beam import ExactBeam, ExactState, PointState
from fvbeam.exact_structure import ExactStructure
from fvbeam.geometry import direction, section_frames
from fvbeam.names import NodeRef
from fvbeam.structure import Structure
from sliders.joints.exact_laws import Derived, JointLaw, derive_many

#: The name of the fixed frame in a joint's ends.
GROUND = "ground"
#: The most free dofs :meth:`ExactModel.free_motion` diagnoses (a dense SVD).
DIAGNOSED = 3000
EPS = float(np.finfo(float).eps)


@dataclass(frozen=True)
class Joint:
    """A joint between nodes ``a`` and ``b`` of an exact model (either may be ``"ground"``).

    Parameters
    ----------
    kind
        ``spherical``, ``revolute``, ``universal``, ``prismatic``, ``fixed``, or rows joined
        by ``+`` (``ux uy uz rx ry rz``): :mod:`sliders.joints.exact_laws`.
    a, b
        Node references (:mod:`fvbeam.names`) or ``"ground"``.  The position rows are the
        gap's components in ``a``'s frame.
    position
        The joint's point in the reference configuration, global axes (default: node ``b``'s
        position, or ``a``'s when ``b`` is the ground).
    frame
        The joint's axes in the reference configuration, columns ``[e_1, e_2, e_3]`` in
        global axes (default the identity): a hinge turns about ``e_1``, a prismatic joint
        slides along it.
    axis
        Instead of ``frame``: ``e_1``, with ``e_3`` the global ``z`` axis made orthogonal to
        it (``y`` for an axis within 26 degrees of ``z``) and ``e_2 = e_3 x e_1``, as a
        straight beam's section axes.
    """

    kind: str
    a: NodeRef
    b: NodeRef
    position: ArrayLike | None = None
    frame: ArrayLike | None = None
    axis: ArrayLike | None = None

    def axes(self, label: str) -> np.ndarray:
        """The joint's frame (columns) from ``frame`` or ``axis``; ``ValueError`` naming
        ``label`` when both are given."""
        if self.axis is None:
            return np.eye(3) if self.frame is None else np.asarray(self.frame)
        if self.frame is not None:
            raise ValueError(f"{label}: give a frame or an axis, not both")
        e1 = direction(self.axis, f"{label}: axis")
        up = np.array([0.0, 1.0, 0.0]) if abs(e1[2]) > 0.9 else np.array([0.0, 0.0, 1.0])
        return section_frames(e1, up)


@dataclass(frozen=True)
class JointedState:
    """A state of an exact model: its nodes' positions and rotations, the joints'
    multipliers."""

    nodes: ExactState
    multipliers: np.ndarray

    @property
    def x(self) -> np.ndarray:
        """The nodes' positions (n, 3)."""
        return self.nodes.x

    @property
    def R(self) -> np.ndarray:
        """The nodes' rotations (n, 3, 3)."""
        return self.nodes.R

    def updated(self, dq: np.ndarray) -> JointedState:
        """The state moved by ``dq``: the nodes' ``[du, dphi]`` on the manifold, then the
        multipliers' increments added."""
        n = 6 * len(self.nodes.x)
        return JointedState(self.nodes.updated(dq[:n]), self.multipliers + dq[n:])


@dataclass(frozen=True)
class ModelPoints:
    """What a state evaluates to: each beam's points, each joint's rows and derivatives
    (:func:`sliders.joints.exact_laws.derive_many`)."""

    parts: list[PointState]
    joints: list[Derived]


class ExactModel:
    """Exact beams and rigid bodies held by joints (module docstring).

    Parameters
    ----------
    beams
        The geometrically exact beams.
    bodies
        The rigid bodies, with finite rotations (:mod:`fvbeam.exact_bodies`).
    joints
        The joints, each named in errors as ``joints[i]``.
    name
        The model's name in messages.
    ties
        Nodes joined rigidly, as :class:`~fvbeam.structure.Structure` takes them: tied
        nodes are one node (:class:`~fvbeam.exact_structure.ExactStructure`).
    """

    def __init__(
        self,
        beams: Sequence[ExactBeam] = (),
        bodies: Sequence[RigidBody] = (),
        joints: Sequence[Joint] = (),
        name: str = "model",
        ties: Sequence[tuple] = (),
    ) -> None:
        for i, beam in enumerate(beams):
            if not isinstance(beam, ExactBeam):
                raise ValueError(
                    f"{name}: beams[{i}] must be an ExactBeam (ExactBeam(beam)), "
                    f"got {type(beam).__name__}"
                )
        self._build(Structure([b.beam for b in beams], ties, bodies), joints, name)

    @classmethod
    def on(
        cls,
        structure: Structure,
        joints: Sequence[Joint] = (),
        name: str = "model",
        key: str = "joints",
    ) -> ExactModel:
        """The exact model of ``structure``'s beams, ties and bodies, on its node numbering
        (:class:`~fvbeam.exact_structure.ExactStructure`), held by ``joints``, each named
        ``key[i]`` in messages."""
        model = cls.__new__(cls)
        model._build(structure, joints, name, key)
        return model

    def _build(
        self, structure: Structure, joints: Sequence[Joint], name: str, key: str = "joints"
    ) -> None:
        self.name = name
        self.key = key
        if any(body.name == GROUND for body in structure.bodies):
            raise ValueError(f"{name}: a rigid body may not be named {GROUND!r} (the fixed frame)")
        self.structure = structure
        self.exact = ExactStructure(structure)
        self.n_nodes = structure.n_nodes
        self.joints = list(joints)
        self.laws: list[JointLaw] = []
        #: Each joint's nodes (-1 for the ground), its reference point (where the ground
        #: holds it) and its multipliers' slice.
        self.ends: list[tuple[int, int]] = []
        self.anchors: list[np.ndarray] = []
        self.slices: list[slice] = []
        reference = self.exact.reference()
        start = 6 * self.n_nodes
        for i, joint in enumerate(self.joints):
            label = f"{name}: {key}[{i}]"
            ends = tuple(
                self._node(ref, f"{label}: {side}")
                for side, ref in (("a", joint.a), ("b", joint.b))
            )
            if ends == (-1, -1):
                raise ValueError(f"{label}: both ends are the ground")
            if ends[0] == ends[1]:
                raise ValueError(f"{label}: both ends are the same node")
            default = reference.x[ends[1]] if ends[1] >= 0 else reference.x[ends[0]]
            point = default if joint.position is None else joint.position
            at = [point if k < 0 else reference.x[k] for k in ends]
            law = JointLaw.at(joint.kind, point, joint.axes(label), at[0], at[1], label)
            self.laws.append(law)
            self.ends.append((int(ends[0]), int(ends[1])))
            self.anchors.append(law.offset_a + at[0])
            self.slices.append(slice(start, start + len(law.rows)))
            start += len(law.rows)
        self.n_dofs = start
        #: The multipliers of the rows that hold positions (:class:`~fvbeam.exact_statics.
        #: StaticOperator`).
        self.position_multipliers = np.array(
            [
                where.start + k
                for law, where in zip(self.laws, self.slices, strict=True)
                for k, row in enumerate(law.rows)
                if row.startswith("u")
            ],
            dtype=np.int64,
        )

    def _node(self, ref: NodeRef, label: str) -> int:
        """The node a reference names, -1 for the ground; ``ValueError`` naming ``label``."""
        if isinstance(ref, str) and ref == GROUND:
            return -1
        try:
            return int(self.structure.node_dofs(ref)[0]) // 6
        except ValueError as error:
            raise ValueError(f"{label}: {error}") from None

    def reference(self) -> JointedState:
        """The structure's reference configuration, zero multipliers."""
        return JointedState(self.exact.reference(), np.zeros(self.n_dofs - 6 * self.n_nodes))

    def _ends(
        self, i: int, nodes: ExactState
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Joint ``i``'s ends' positions and rotations ``x_a, R_a, x_b, R_b``: a node's, or
        the ground's (the joint's reference point, the identity)."""
        a, b = (
            (nodes.x[node], nodes.R[node]) if node >= 0 else (self.anchors[i], np.eye(3))
            for node in self.ends[i]
        )
        return a[0], a[1], b[0], b[1]

    def points(self, state: JointedState) -> ModelPoints:
        """Each beam's points and each joint's rows, Jacobian and geometric stiffness."""
        parts = self.exact.points(state.nodes)
        ends = [self._ends(i, state.nodes) for i in range(len(self.laws))]
        x_a, R_a, x_b, R_b = (
            np.array([e[k] for e in ends]).reshape((-1,) + shape)
            for k, shape in enumerate(((3,), (3, 3), (3,), (3, 3)))
        )
        joints = derive_many(
            self.laws,
            x_a,
            R_a,
            x_b,
            R_b,
            [self._multipliers(state, where) for where in self.slices],
            np.array(self.ends).reshape(-1, 2) >= 0,
        )
        return ModelPoints(parts, joints)

    def _columns(self, ends: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
        """The model's dofs of a joint's twelve columns that move, and which columns."""
        cols = np.concatenate([6 * node + np.arange(6) for node in ends])
        moving = np.repeat(np.array(ends) >= 0, 6)
        return cols[moving], np.flatnonzero(moving)

    def _multipliers(self, state: JointedState, where: slice) -> np.ndarray:
        n = 6 * self.n_nodes
        return state.multipliers[where.start - n : where.stop - n]

    def residual(self, state: JointedState, pts: ModelPoints | None = None) -> np.ndarray:
        """The nodes' balances ``r + sum B^T lambda`` and the joints' rows ``c``."""
        pts = self.points(state) if pts is None else pts
        out = np.concatenate(
            [self.exact.residual(state.nodes, pts.parts), np.zeros(self.n_dofs - 6 * self.n_nodes)]
        )
        for derived, ends, where in zip(pts.joints, self.ends, self.slices, strict=True):
            dofs, cols = self._columns(ends)
            out[dofs] += derived.jacobian[:, cols].T @ self._multipliers(state, where)
            out[where] = derived.rows
        return out

    def residual_floor(self, state: JointedState, pts: ModelPoints | None = None) -> np.ndarray:
        """A bound on each residual in units of its rounding: the parts' own; for the joints'
        terms ``|B|^T |lambda|`` on the nodes and, on a row, ``|B|`` times the nodes'
        coordinates' sizes (``|x|`` on the translation columns, 1 on the rotation ones): the
        terms of ``d_ai . g`` are the gap's ends, those of ``d_ai . d_bj`` unit vectors'."""
        pts = self.points(state) if pts is None else pts
        out = np.concatenate(
            [
                self.exact.residual_floor(state.nodes, pts.parts),
                np.zeros(self.n_dofs - 6 * self.n_nodes),
            ]
        )
        size = np.repeat(
            np.column_stack([np.linalg.norm(state.nodes.x, axis=1), np.ones(self.n_nodes)]),
            3,
            axis=1,
        ).ravel()
        for derived, ends, where in zip(pts.joints, self.ends, self.slices, strict=True):
            dofs, cols = self._columns(ends)
            B = np.abs(derived.jacobian[:, cols])
            out[dofs] += B.T @ np.abs(self._multipliers(state, where))
            out[where] = B @ np.maximum(size[dofs], 1.0) + np.abs(derived.rows)
        return out

    def tangent(
        self, state: JointedState, pts: ModelPoints | None = None, keep: np.ndarray | None = None
    ) -> sp.csc_matrix:
        """The bordered tangent (module docstring); with ``keep`` (sorted dofs), its rows and
        columns on those only."""
        pts = self.points(state) if pts is None else pts
        H, B = self.joint_blocks(state, pts)
        K = self.exact.tangent(state.nodes, pts.parts)
        zero = sp.csr_matrix((B.shape[0], B.shape[0]))
        full = sp.bmat([[K + H, B.T], [B, zero]], format="csc")
        return full if keep is None else full[keep][:, keep].tocsc()

    def joint_blocks(
        self, state: JointedState, pts: ModelPoints | None = None
    ) -> tuple[sp.csr_matrix, sp.csr_matrix]:
        """The joints' geometric stiffness ``sum_j H_j`` (on the nodes' dofs) and their rows
        ``B`` (one per multiplier, on the nodes' dofs) at ``state``: the blocks of the
        bordered tangent (module docstring)."""
        pts = self.points(state) if pts is None else pts
        n = 6 * self.n_nodes
        h_rows, h_cols, h_vals = [np.zeros(0, int)], [np.zeros(0, int)], [np.zeros(0)]
        b_rows, b_cols, b_vals = [np.zeros(0, int)], [np.zeros(0, int)], [np.zeros(0)]
        for derived, ends, where in zip(pts.joints, self.ends, self.slices, strict=True):
            dofs, columns = self._columns(ends)
            mult = np.arange(where.start, where.stop) - n
            h_rows.append(np.repeat(dofs, len(dofs)))
            h_cols.append(np.tile(dofs, len(dofs)))
            h_vals.append(derived.stiffness[np.ix_(columns, columns)].ravel())
            b_rows.append(np.repeat(mult, len(dofs)))
            b_cols.append(np.tile(dofs, len(mult)))
            b_vals.append(derived.jacobian[:, columns].ravel())
        H = sp.coo_matrix(
            (np.concatenate(h_vals), (np.concatenate(h_rows), np.concatenate(h_cols))),
            shape=(n, n),
        )
        B = sp.coo_matrix(
            (np.concatenate(b_vals), (np.concatenate(b_rows), np.concatenate(b_cols))),
            shape=(self.n_dofs - n, n),
        )
        return H.tocsr(), B.tocsr()

    def reactions(self, state: JointedState) -> list[np.ndarray]:
        """Each joint's share of its nodes' balances, ``B^T lambda``, as ``[force, couple]``
        on node ``a`` and on node ``b`` (2, 6; zero on the ground): the loads the joint
        carries from its nodes, couples about the nodes."""
        pts = self.points(state)
        out = []
        for derived, where in zip(pts.joints, self.slices, strict=True):
            out.append((derived.jacobian.T @ self._multipliers(state, where)).reshape(2, 6))
        return out

    def balanced(
        self, state: JointedState, load: np.ndarray, fixed: ArrayLike = ()
    ) -> JointedState:
        """``state`` with the multipliers that balance ``load`` (the nodes' six dofs each)
        best, least squares of ``r + B^T lambda = f`` on the dofs not ``fixed``: a start for
        a mechanism that only its load holds (at zero multipliers nothing resists its free
        motion, and Newton's first tangent is singular)."""
        n = 6 * self.n_nodes
        free = np.setdiff1d(np.arange(n), np.asarray(fixed, dtype=int))
        zero = JointedState(state.nodes, np.zeros_like(state.multipliers))
        gap = (np.asarray(load, dtype=float)[:n] - self.residual(zero)[:n])[free]
        columns = self.tangent(zero)[:n, n:].toarray()[free]
        multipliers = np.linalg.lstsq(columns, gap, rcond=None)[0]
        return JointedState(state.nodes, multipliers)

    def free_motion(self, state: JointedState, free: np.ndarray) -> str | None:
        """What nothing resists at ``state`` when the bordered tangent on the dofs ``free``
        is singular (its smallest singular value within ``n eps`` of its largest, numpy's
        rank test), else None: the null vector's largest node dofs (at least a tenth of its
        largest, :meth:`fvbeam.structure.Structure.dof_name`) and the joints at their nodes,
        or, when the null vector is mostly multipliers, the joint whose rows repeat what
        others hold.  None too above :data:`DIAGNOSED` free dofs (a dense SVD)."""
        if len(free) > DIAGNOSED:
            return None
        _, s, Vt = np.linalg.svd(self.tangent(state, keep=free).toarray())
        if s[-1] > len(free) * EPS * s[0]:
            return None
        v = np.zeros(self.n_dofs)
        v[free] = Vt[-1]
        n = 6 * self.n_nodes
        if np.linalg.norm(v[:n]) < np.linalg.norm(v[n:]):
            k = int(np.argmax(np.abs(v[n:]))) + n
            i = next(j for j, where in enumerate(self.slices) if where.start <= k < where.stop)
            return (
                f"the rows of {self.key}[{i}] ({self.joints[i].kind}) repeat what other "
                "joints or supports hold (a singular tangent)"
            )
        size = np.abs(v[:n])
        dofs = [int(d) for d in np.argsort(-size)[:3] if size[d] >= 0.1 * size.max()]
        nodes = {d // 6 for d in dofs}
        at = [
            f"{self.key}[{i}] ({joint.kind})"
            for i, (joint, ends) in enumerate(zip(self.joints, self.ends, strict=True))
            if nodes & set(ends)
        ]
        where = f"left free by {', '.join(at)}" if at else "held by no joint or support"
        return (
            f"a free motion nothing resists (a singular tangent): mostly "
            f"{', '.join(self.structure.dof_name(d) for d in dofs)}, {where}"
        )
