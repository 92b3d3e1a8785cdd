"""Slider joints: a node of the structure slides on a line (paper Secs. 3-4).

The body is a node of the structure (a beam node or a rigid body, six dofs ``u_b, theta_b``,
linear kinematics like the beams) carrying the sliding point at ``offset`` and the slider
axes ``frame`` (columns ``e1, e2, e3``; ``e1`` along the line).  The line is a
:class:`BeamChain` or a rigid line.  Unknowns ``y = [xi, lambda (3), mu_2, mu_3, mu_1]``:
``mu_2, mu_3`` for the classical and spline sliders, ``mu_1`` for the spline slider.  With
``x_b = X_b + offset + u_b + theta_b x offset`` and ``m`` the couple of the orientation
constraints:

=====================  ==================================================  =============
equation               residual                                            paper
=====================  ==================================================  =============
body force             ``+ lambda``                                         eq. 3
body moment            ``+ f_b x lambda + m``, ``f_b = theta_b x offset``   eqs. 3-5
line beams             ``- G(xi) lambda`` (test functions, smeared; T6)     Sec. 4
                       and ``- m`` shared by the nodes (below)
xi                     ``- l . lambda + sum_j mu_j d g_j / d xi``           eqs. 3-5
position               ``x_b - x(xi)`` (plus a compliance: cubic chain)     eq. 1
orientation            ``g_j``                                              Secs. 3.2-3.3
=====================  ==================================================  =============

Two orientation models (``docs/sliders.md`` compares them):

* ``section`` (default; classical and spline): the constraints hold the body's axes to the
  line's *section frame*, the reference frame turned by the section rotation ``theta_L(xi)``
  interpolated linearly between the two nodes around ``xi`` (on a cubic chain: the element's
  own rotation); the couple goes to those nodes with the same weights (consistent virtual
  work).  A correction for the kink that the couple itself puts in the rotation makes the
  constraint second-order accurate (on a cubic chain, exact: ``docs/sliders.md``, "The cubic
  chain").
* ``slope`` (classical only): the paper's eq. (4) on the gradient ``l`` of the interpolated
  centreline, the couple ``m = sum_j mu_j e_bj x l`` carried to the rotation dofs by the
  test functions, as the reference implementation does; first-order accurate, and singular
  when both sliders of the sliding-beams setup fall in one node's region.

Neither routes the couple through ``d l / d q`` as a force dipole on the slope: on
shear-deformable beams the dipole form loses the couple under mesh refinement.

The equations are written in plain numpy, with the paper's numbers, in
:mod:`sliders.joints.equations` (one function per kind and orientation), and compiled in
:mod:`sliders.joints.kernel`, which :meth:`SliderBatch.evaluate` calls for ``B`` members at
once (arrays with a leading member axis, fixed slots per member); both read what
:meth:`SliderBatch.joint_inputs` gathers.  :meth:`Slider.assemble` is the case ``B = 1``.
"""

from __future__ import annotations

import copy
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import cast

import numpy as np

from fvbeam.copies import shallow_copy
from fvbeam.geometry import orthonormal3, vector3
from fvbeam.names import NodeRef, parse_node
from fvbeam.smearing import check_smearing
from fvbeam.structure import Structure
from sliders.joints.blocks import SlotJacobian
from sliders.joints.drives import Motion
from sliders.joints.equations import JointInputs, pattern
from sliders.joints.friction import Friction
from sliders.joints.kernel import GROUPS, joint_equations
from sliders.joints.kernel import KINDS as KERNEL_KINDS
from sliders.joints.stops import end_stops
from sliders.lines.batched import ChainStack, LineRotation, gather
from sliders.lines.chain import BeamChain
from sliders.lines.rigid import RigidLine

KINDS = ("spherical", "classical", "spline")
ORIENTATIONS = ("section", "slope")
UNKNOWNS = ("xi", "lambda_x", "lambda_y", "lambda_z", "mu_2", "mu_3", "mu_1")
#: The number of unknowns of each kind (:attr:`Slider.n_unknowns`).
N_UNKNOWNS = {"spherical": 4, "classical": 6, "spline": 7}


@dataclass
class Slider:
    """A structure node sliding on a line.

    Parameters
    ----------
    kind
        ``spherical``, ``classical`` or ``spline``.
    line
        A :class:`BeamChain` of the same structure, or a rigid line.
    body
        The sliding node, named as in a scene (``"P.start"``, a rigid body's name) or as
        ``(beam, node)`` (:mod:`fvbeam.names`).
    offset
        Sliding point relative to the node, in global axes of the reference configuration.
    frame
        Slider axes ``[e1, e2, e3]`` (columns) in the reference configuration.
    smearing, kernel
        Spread of the reaction force along the line (:mod:`fvbeam.smearing`); the couple of
        the ``section`` orientation is shared linearly between nodes and never jumps.
    orientation
        ``section`` or ``slope`` (module docstring).
    end_stops
        Stops at both ends of the line.  Without them, ``xi`` leaving the line is an error
        naming it; with them, the sliding point rests at the end (``xi`` held there, the
        reaction's tangential part ``l . lambda`` is the stop's force) while the stop pushes,
        and leaves it when the stop would have to pull.
    drive
        A prescribed abscissa ``xi_d(t)`` (:mod:`sliders.joints.drives`): the frictionless
        equation ``l . lambda = 0`` becomes ``xi = xi_d(t)``, and ``l . lambda`` is the force
        pushing the sliding point along the line.  Statics holds ``xi`` at ``xi_d(0)``.
    friction
        Bearing friction along the line (:class:`sliders.joints.friction.Friction`), its
        normal force the joint's transverse reaction: the ``xi`` equation carries it in
        dynamics (:mod:`sliders.joints.friction`), on the condensed back end.
    name
        Label used in error messages.
    """

    kind: str
    line: BeamChain | RigidLine
    body: NodeRef
    offset: np.ndarray = field(default_factory=lambda: np.zeros(3))
    frame: np.ndarray = field(default_factory=lambda: np.eye(3))
    smearing: float = 0.0
    kernel: str = "box"
    orientation: str = "section"
    end_stops: bool = False
    drive: Motion | None = None
    friction: Friction | None = None
    name: str = "slider"

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(
                f"{self.name}: kind must be one of {', '.join(KINDS)}, got {self.kind!r}"
            )
        if self.orientation not in ORIENTATIONS:
            raise ValueError(
                f"{self.name}: orientation must be one of "
                f"{', '.join(ORIENTATIONS)}, got {self.orientation!r}"
            )
        if self.drive is not None and not callable(self.drive):
            raise ValueError(
                f"{self.name}: drive must be a motion (sliders.joints.drives), got {self.drive!r}"
            )
        if self.orientation == "slope" and self.kind != "classical":
            raise ValueError(
                f"{self.name}: orientation 'slope' is the classical slider's "
                f"(paper eq. 4); a {self.kind} slider needs 'section'"
            )
        if self.friction is not None and not isinstance(self.friction, Friction):
            raise ValueError(
                f"{self.name}: friction must be a sliders.joints.friction.Friction, "
                f"got {self.friction!r}"
            )
        if self.friction is not None and self.drive is not None:
            raise ValueError(
                f"{self.name}: a driven slider has no friction (its xi equation is the drive)"
            )
        parse_node(self.body, f"{self.name}: body")
        on = f"line {self.line.name!r} of slider {self.name!r}"
        self.smearing = check_smearing(self.smearing, self.kernel, self.line.length, on)
        self.offset = vector3(self.offset, f"{self.name}: offset")
        self.frame = orthonormal3(self.frame, f"{self.name}: frame")
        self._batch: SliderBatch | None = None

    def moved(self, structure: Structure) -> "Slider":
        """This slider on ``structure``, a moved copy of its line's structure
        (:meth:`fvbeam.structure.Structure.moved`): on a chain, the chain of the same beams
        moved (:meth:`sliders.lines.chain.BeamChain.moved`); a rigid line stays.  Its
        options are taken as they were checked when it was made; a line of another length
        is checked as a new slider's."""
        line = self.line.moved(structure) if isinstance(self.line, BeamChain) else self.line
        if line.length != self.line.length:
            return replace(self, line=line)
        out = shallow_copy(self)
        out.line, out._batch = line, None
        return out

    @property
    def n_unknowns(self) -> int:
        """``xi``, ``lambda``; ``mu_2, mu_3`` for the classical and spline sliders; ``mu_1``
        for the spline slider."""
        return N_UNKNOWNS[self.kind]

    @property
    def unknown_names(self) -> tuple[str, ...]:
        """Names of the joint's unknowns, in order (for messages and outputs)."""
        return UNKNOWNS[: self.n_unknowns]

    def body_dofs(self, structure: Structure) -> np.ndarray:
        """The six global dofs of the body node."""
        return structure.node_dofs(self.body)

    def reference_point(self, structure: Structure) -> np.ndarray:
        """The sliding point in the reference configuration."""
        return structure.node_position(self.body) + self.offset

    def _check_frame(self, xi: float) -> None:
        """The spline slider's constraint is linearised about the line's frame: the slider
        frame must match it at the starting ``xi`` (within 0.1 rad)."""
        R0 = self.line.rotation(xi).R0 if isinstance(self.line, BeamChain) else self.line.at(xi).R
        angle = np.arccos(np.clip((np.trace(self.frame @ R0.T) - 1) / 2, -1.0, 1.0))
        if angle > 0.1:
            raise ValueError(
                f"{self.name}: a spline slider's frame must match the line's frame "
                f"at xi = {xi:.6g} (columns {np.round(R0, 6).tolist()}); it is "
                f"turned {angle:.3g} rad from it"
            )

    def batch(self, structure: Structure) -> SliderBatch:
        """This slider alone as a batch (kept for the last ``structure``)."""
        if self._batch is None or self._batch.structures[0] is not structure:
            self._batch = SliderBatch([self], [structure])
        return self._batch

    def initial_unknowns(self, structure: Structure, q: np.ndarray) -> np.ndarray:
        """``xi`` from projecting the sliding point on the line, multipliers 0."""
        return self.batch(structure).initial_unknowns(q[None])[0]

    def assemble(
        self, structure: Structure, q: np.ndarray, y: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Residual and Jacobian of the joint on the structure dofs it touches: the ``B = 1``
        case of :meth:`SliderBatch.evaluate`, duplicate dofs summed.

        Returns
        -------
        dofs : (t,) global dofs touched, sorted
        r_q : (t,) contribution to the structure residual on them
        r_y : (n_unknowns,) the joint's own equations
        J : (t + n_unknowns, t + n_unknowns) derivative of ``[r_q; r_y]`` in ``[q_t; y]``
        """
        y = np.asarray(y, dtype=float)
        dofs, r, blocks = self.batch(structure).evaluate(q[None], y[None])
        assert blocks is not None  # evaluate returns the Jacobian unless told not to
        dofs, r, J = dofs[0], r[0], blocks.dense()[0]
        unique, where = np.unique(dofs, return_inverse=True)
        t, m, s = len(unique), self.n_unknowns, len(dofs)
        P = np.zeros((s + m, t + m))
        P[np.arange(s), where] = 1.0
        P[s + np.arange(m), t + np.arange(m)] = 1.0
        r = P.T @ r
        return unique, r[:t], r[t:], P.T @ J @ P


def _equations(joint: Slider | SliderBatch) -> tuple:
    """What selects a joint's equations: kind, orientation, smearing, kernel and end stops
    (joints alike in these, placed alike, are evaluated by one batch)."""
    return joint.kind, joint.orientation, joint.smearing, joint.kernel, joint.end_stops


class SliderBatch:
    """``B`` sliders alike (kind, orientation, smearing, offset, frame, end stops), one per
    member of a batch of structures of one topology, on lines of one topology
    (:class:`sliders.lines.batched.ChainStack`, or rigid lines): the joint equations of all members
    at once (module docstring).

    Raises ``ValueError`` naming the first slider that differs from the first one.
    """

    def __init__(self, sliders: Sequence[Slider], structures: Sequence[Structure]) -> None:
        self.sliders, self.structures = list(sliders), list(structures)
        first = self.sliders[0]
        placed = np.all(
            np.stack([s.offset for s in self.sliders]) == first.offset, axis=1
        ) & np.all(np.stack([s.frame for s in self.sliders]) == first.frame, axis=(1, 2))
        for b, s in enumerate(self.sliders[1:], start=1):
            if not (
                _equations(s) == _equations(first)
                and placed[b]
                and (s.drive is None) == (first.drive is None)
                and isinstance(s.line, BeamChain) == isinstance(first.line, BeamChain)
            ):
                raise ValueError(
                    f"{s.name}: slider of member {b} of the batch differs from "
                    "member 0 (kind, orientation, smearing, offset, frame, end "
                    "stops, drive or kind of line)"
                )
        self.kind, self.orientation = first.kind, first.orientation
        self.smearing, self.kernel, self.end_stops = first.smearing, first.kernel, first.end_stops
        self.offset, self.frame, self.n_unknowns = first.offset, first.frame, first.n_unknowns
        self.length = first.line.length
        self.body = np.stack(
            [s.body_dofs(st) for s, st in zip(self.sliders, self.structures, strict=True)]
        )
        self.reference = np.stack(
            [s.reference_point(st) for s, st in zip(self.sliders, self.structures, strict=True)]
        )
        # the members' lines are all chains or all rigid (checked above)
        self.chains = (
            ChainStack(cast(list[BeamChain], [s.line for s in self.sliders]))
            if isinstance(first.line, BeamChain)
            else None
        )
        self.drives = [s.drive for s in self.sliders]
        #: Whether the joints read the lines' section rotation (the ``section`` orientation
        #: of the classical and spline sliders).
        self.section = self.kind != "spherical" and self.orientation == "section"
        #: The Jacobian blocks the joint lays out (:class:`SlotJacobian`): those its kernel
        #: writes (:func:`sliders.joints.equations.pattern`), which :meth:`joint_equations`
        #: checks it holds, once per layout.
        self.pattern = pattern(
            self.kind,
            self.orientation,
            bool(np.any(self.offset)),
            self.section and self.chains is not None,
            self.chains is not None and self.chains.width == 6,
        )

    @classmethod
    def translated(cls, slider: Slider, structure: Structure, shifts: np.ndarray) -> SliderBatch:
        """``slider`` of ``structure`` in ``B`` copies whose beams are moved rigidly by
        ``shifts`` ((B, n_beams, 3), one shift per beam; rigid bodies stay), as if each copy
        were built on :meth:`fvbeam.beam.Beam.translated` beams (same node positions, body
        and lines), without building them: the members share ``slider`` and ``structure``,
        and the template batch :meth:`Slider.batch` (its chain's element frames computed
        once).
        """
        shifts = np.asarray(shifts, dtype=float)
        if shifts.ndim != 3 or shifts.shape[1:] != (len(structure.beams), 3):
            raise ValueError(
                f"{slider.name}: shifts must be (B, {len(structure.beams)}, 3), got {shifts.shape}"
            )
        one, B = slider.batch(structure), len(shifts)
        out = copy.copy(one)
        out.sliders, out.structures, out.drives = [slider] * B, [structure] * B, one.drives * B
        out.body = np.repeat(one.body, B, axis=0)
        node = structure.resolve_node(slider.body)
        moved = np.zeros((B, 3)) if isinstance(node, str) else shifts[:, node[0]]
        out.reference = structure.node_position(slider.body) + moved + slider.offset
        out.chains = one.chains.translated(shifts) if one.chains is not None else None
        return out

    @classmethod
    def joined(cls, batches: Sequence[SliderBatch]) -> SliderBatch:
        """One batch of the members of ``batches``, one batch after the other: the joints of
        a member that are alike (kind, orientation, smearing, offset, frame, end stops, drive,
        unknowns and line length) but sit on different lines of one topology (e.g. on two
        beams of one mesh, :meth:`sliders.lines.batched.ChainStack.joined`) evaluated by one call.
        Raises ``ValueError`` naming the first batch that differs from the first one."""
        first = batches[0]
        for other in batches[1:]:
            if not (
                _equations(other) == _equations(first)
                and other.n_unknowns == first.n_unknowns
                and other.length == first.length
                and np.array_equal(other.offset, first.offset)
                and np.array_equal(other.frame, first.frame)
                and (other.drives[0] is None) == (first.drives[0] is None)
                and other.chains is not None
                and first.chains is not None
            ):
                raise ValueError(
                    f"{other.sliders[0].name}: its joints differ from "
                    f"{first.sliders[0].name}'s (kind, orientation, smearing, "
                    "offset, frame, end stops, drive, length or kind of line)"
                )
        out = copy.copy(first)
        out.sliders = [s for b in batches for s in b.sliders]
        out.structures = [s for b in batches for s in b.structures]
        out.body = np.concatenate([b.body for b in batches])
        out.reference = np.concatenate([b.reference for b in batches])
        out.drives = [d for b in batches for d in b.drives]
        out.chains = ChainStack.joined(cast(list[ChainStack], [b.chains for b in batches]))
        return out

    def __len__(self) -> int:
        return len(self.sliders)

    def subset(self, members: np.ndarray) -> SliderBatch:
        """The batch of the given members only."""
        out = copy.copy(self)
        out.sliders = [self.sliders[b] for b in members]
        out.structures = [self.structures[b] for b in members]
        out.body, out.reference = self.body[members], self.reference[members]
        out.drives = [self.drives[b] for b in members]
        out.chains = self.chains.subset(members) if self.chains is not None else None
        return out

    def _rigid(self) -> list[RigidLine]:
        """The members' lines when they are rigid (``chains`` is None)."""
        return cast(list[RigidLine], [s.line for s in self.sliders])

    def initial_unknowns(self, q: np.ndarray) -> np.ndarray:
        """``xi`` from projecting each member's sliding point on its line (states ``q``,
        (B, n)), multipliers 0: (B, n_unknowns)."""
        points = self.reference + gather(q, self.body[:, :3])
        if self.chains is not None:
            xi = self.chains.project(points, q)
        else:
            xi = np.array([line.project(p) for line, p in zip(self._rigid(), points, strict=True)])
        if self.kind == "spline":
            for s, x in zip(self.sliders, xi, strict=True):
                s._check_frame(float(x))
        return np.column_stack([xi, np.zeros((len(xi), self.n_unknowns - 1))])

    def _line(self, xi: np.ndarray, q: np.ndarray) -> _LineState:
        """The lines' geometry, interpolation and load transfer at ``xi`` (B,)."""
        B = len(xi)
        if self.chains is not None:
            s = self.chains.line_state(
                xi,
                q,
                self.section,
                self.smearing,
                self.kernel,
            )
            interp = s.interpolation
            return _LineState(
                s.x,
                s.l,
                s.l_xi,
                s.l_xixi,
                interp.N,
                interp.dN,
                interp.d2N,
                s.load_dofs,
                s.G,
                s.dG,
                s.contact,
                s.contact_xi,
                s.rotation,
                None,
                s.tangent,
                s.tangent_xi,
                interp.tangent_dofs,
                interp.T,
                interp.T_xi,
            )
        p = [line.at(float(x)) for line, x in zip(self._rigid(), xi, strict=True)]
        x, l, l_xi, l_xixi, R, k, k_xi = (
            np.array([getattr(a, f) for a in p])
            for f in ("x", "l", "l_xi", "l_xixi", "R", "k", "k_xi")
        )
        none, empty = np.zeros((B, 0), dtype=int), np.zeros((B, 3, 0))
        return _LineState(
            x,
            l,
            l_xi,
            l_xixi,
            empty,
            empty,
            empty,
            none,
            np.zeros((B, 0, 6)),
            np.zeros((B, 0, 6)),
            np.zeros((B, 0, 6)),
            np.zeros((B, 0, 6)),
            None,
            (R, k, k_xi),
            l,
            l_xi,
            none,
            empty,
            empty,
        )

    def evaluate(
        self,
        q: np.ndarray,
        y: np.ndarray,
        time: float = 0.0,
        scale: float = 1.0,
        jacobian: bool = True,
    ) -> tuple[np.ndarray, np.ndarray, SlotJacobian | None]:
        """Residuals and Jacobians of the joints of all members (module docstring table).

        ``q`` (B, n): the members' structure states; ``y`` (B, n_unknowns): their joint
        unknowns; ``time``: where the drives are read.  ``scale``: the multipliers in ``y``
        are ``scale`` times the physical ones (the time integrator's scaling,
        :mod:`sliders.solve.dynamics`): every equation is homogeneous in them except the kink
        shift of the section orientation, whose compliance is divided by ``scale``.
        ``jacobian``: False for the residuals alone (a convergence check).

        Each member's local arrays have fixed slots: the body (6), the line's load (k),
        rotation (two nodes' rotations, or their six dofs on a cubic chain; section
        orientation on a chain) and recovered-tangent (3 m) dofs, whose first m are the
        interpolation's (the element's nodes' translations, or their six dofs on a cubic
        chain), then ``xi``, ``lambda`` and the multipliers.  A dof may hold several slots
        (sum them, e.g. :meth:`Slider.assemble`); padded slots carry zeros.  The joint equations are
        :meth:`joint_equations` at :meth:`joint_inputs`; end stops and drives then replace
        the ``xi`` equation where they act.

        Returns
        -------
        dofs : (B, s) global dof of each slot
        r : (B, s + n_unknowns) the structure residual on the slots, then the joint's own
        J : the derivative of ``r`` in ``[q_slots; y]`` by blocks of the slot groups
            ``body``, ``turn`` (the body's rotations), ``load``, ``rotation``, ``interp``,
            ``beside`` (the tangent's other dofs), ``xi``, ``lam``, ``mu``
            (:class:`sliders.joints.blocks.SlotJacobian`); None without ``jacobian``
        """
        dofs, inputs = self.joint_inputs(q, y, scale)
        r, J = self.joint_equations(inputs, jacobian)
        xi = dofs.shape[1]
        if self.end_stops:
            self._end_stop(y[:, 0], y[:, 1:4], inputs.l, xi, r, J)
        if self.drives[0] is not None:
            drives = cast(list[Motion], self.drives)  # all driven or none (checked in __init__)
            r[:, xi] = y[:, 0] - np.array([d(time)[0] for d in drives])
            if J is not None:
                J.unit_row("xi")
        return dofs, r, J

    def joint_inputs(
        self, q: np.ndarray, y: np.ndarray, scale: float = 1.0
    ) -> tuple[np.ndarray, JointInputs]:
        """The global dof of each slot (B, s) and what the joint equations read at the states
        ``q`` (B, n) and unknowns ``y`` (B, n_unknowns): the body's dofs and reference point,
        the lines at ``xi`` (held at the ends with end stops), ``q``, ``y`` and ``scale``
        (:meth:`evaluate`), as :class:`sliders.joints.equations.JointInputs`, the arguments of
        the compiled kernel and of the reference alike."""
        B = len(y)
        xi = np.clip(y[:, 0], 0.0, self.length) if self.end_stops else y[:, 0]
        try:
            line = self._line(xi, q)
        except ValueError as exc:
            raise ValueError(f"slider {self.sliders[0].name!r}: {exc}") from exc
        rot = line.rotation
        rotation_dofs = rot.dofs if rot is not None else np.zeros((B, 0), dtype=np.int64)
        dofs = np.concatenate([self.body, line.load_dofs, rotation_dofs, line.tangent_dofs], axis=1)
        if rot is not None:
            frame = (rot.R0, rot.k0, rot.k0_xi)
            section = (rot.W, rot.W_xi, rot.W_xixi, rot.flex, rot.flex_xi)
        else:
            frame = line.frame or (np.zeros((B, 3, 3)), np.zeros((B, 3)), np.zeros((B, 3)))
            section = (
                np.zeros((B, 3, 0)),
                np.zeros((B, 3, 0)),
                np.zeros((B, 3, 0)),
                np.zeros((B, 3, 3)),
                np.zeros((B, 3, 3)),
            )
        W, W_xi, W_xixi, flex, flex_xi = section
        R0, k0, k0_xi = frame
        inputs = JointInputs(
            self.offset,
            self.frame,
            self.body,
            _c(self.reference),
            _c(q),
            _c(y),
            _c(line.x),
            _c(line.l),
            _c(line.l_xi),
            _c(line.l_xixi),
            _c(line.N),
            _c(line.dN),
            _c(line.d2N),
            _c(line.G),
            _c(line.dG),
            _c(line.tangent),
            _c(line.tangent_xi),
            _c(line.T),
            _c(line.contact),
            _c(line.contact_xi),
            np.ascontiguousarray(rotation_dofs, dtype=np.int64),
            _c(W),
            _c(W_xi),
            _c(W_xixi),
            _c(flex),
            _c(flex_xi),
            _c(R0),
            _c(k0),
            _c(k0_xi),
            float(scale),
        )
        return dofs, inputs

    def joint_equations(
        self, inputs: JointInputs, jacobian: bool = True
    ) -> tuple[np.ndarray, SlotJacobian | None]:
        """The joint equations at ``inputs`` (:meth:`joint_inputs`), compiled
        (:func:`sliders.joints.kernel.joint_equations`): the residuals (B, s + n_unknowns)
        on the slots and the unknowns, and the Jacobian by blocks of :attr:`pattern` (None
        without ``jacobian``).

        Raises ``ValueError`` naming the joint, the block and the pattern when the pattern
        lacks a block the kernel writes at these inputs (:func:`sliders.joints.equations.pattern`
        of the kind, the orientation, the lever arm and the section rotation dofs; checked
        once per layout, :meth:`SlotJacobian.index`).
        """
        B = len(inputs.y)
        at = _Layout(
            inputs.N.shape[2],
            inputs.G.shape[1],
            inputs.rotation_dofs.shape[1],
            inputs.T.shape[2],
            self.n_unknowns,
        )
        writes = pattern(
            self.kind,
            self.orientation,
            bool(inputs.offset.any()),
            inputs.rotation_dofs.shape[1] > 0,
            inputs.contact.shape[1] > 0,
        )
        try:
            J = at.jacobian(B if jacobian else 0, self.pattern)
            index = J.index(GROUPS, writes)
        except ValueError as exc:
            raise ValueError(f"slider {self.sliders[0].name!r}: {exc}") from exc
        r = np.zeros((B, at.t + self.n_unknowns))
        kind = KERNEL_KINDS[self.kind]
        joint_equations(kind, self.orientation == "slope", jacobian, inputs, index, r, J.values)
        return r, J if jacobian else None

    def _end_stop(
        self,
        xi: np.ndarray,
        lam: np.ndarray,
        l: np.ndarray,
        slot: int,
        r: np.ndarray,
        J: SlotJacobian | None,
    ) -> None:
        """Replace the ``xi`` equation (row ``slot`` of ``r``) by ``xi = end`` where the end
        stops hold the members (:func:`sliders.joints.stops.end_stops`)."""
        hit, held = np.zeros(len(xi), dtype=bool), np.zeros(len(xi))
        end_stops(_c(xi), _c(_dot(l, lam)), float(self.length), hit, held)
        r[hit, slot] = held[hit]
        if J is not None:
            J.unit_row("xi", hit)


def _c(a: np.ndarray) -> np.ndarray:
    """``a`` as a C-contiguous float array (one compiled signature of the kernel)."""
    return np.ascontiguousarray(a, dtype=float)


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Row-wise dot products of (B, k) arrays."""
    return np.einsum("bk,bk->b", a, b)


@dataclass(frozen=True)
class _LineState:
    """What the joint needs of the lines at ``xi``, per member (leading axis B): geometry,
    the interpolation's matrices (chains), the load transfer, the position's compliance
    (chains of cubic elements), the section rotation (chains, section orientation) or the
    rigid line's frame ``(R, k, k_xi)``, and the tangent of the frictionless condition with
    its dofs and matrices (chains: the recovered tangent,
    :meth:`sliders.lines.batched.ChainStack.interpolation`, whose first ``m`` dofs are the
    interpolation's; rigid lines: ``l``, no dofs)."""

    x: np.ndarray
    l: np.ndarray
    l_xi: np.ndarray
    l_xixi: np.ndarray
    N: np.ndarray
    dN: np.ndarray
    d2N: np.ndarray
    load_dofs: np.ndarray
    G: np.ndarray
    dG: np.ndarray
    contact: np.ndarray
    contact_xi: np.ndarray
    rotation: LineRotation | None
    frame: tuple[np.ndarray, np.ndarray, np.ndarray] | None
    tangent: np.ndarray
    tangent_xi: np.ndarray
    tangent_dofs: np.ndarray
    T: np.ndarray
    T_xi: np.ndarray


class _Layout:
    """Slots of a member's local arrays: body translations and rotations, the line's
    load, rotation and tangent dofs (the interpolation's are the tangent's first), then
    ``xi``, ``lambda`` and the multipliers ``mu``."""

    def __init__(
        self, n_interp: int, n_load: int, n_rotation: int, n_tangent: int, n_unknowns: int
    ) -> None:
        self.body, self.turn = slice(0, 3), slice(3, 6)
        start = 6
        self.load, start = slice(start, start + n_load), start + n_load
        self.rotation, start = slice(start, start + n_rotation), start + n_rotation
        self.interp = slice(start, start + n_interp)
        self.tangent, start = slice(start, start + n_tangent), start + n_tangent
        self.t = self.xi = start
        self.lam, self.mu = slice(start + 1, start + 4), slice(start + 4, start + n_unknowns)
        self.groups = [
            ("body", 3),
            ("turn", 3),
            ("load", n_load),
            ("rotation", n_rotation),
            ("interp", n_interp),
            ("beside", n_tangent - n_interp),
        ]
        self.own = [("xi", 1), ("lam", 3), ("mu", n_unknowns - 4)]

    def jacobian(self, members: int, pattern: Sequence[tuple[str, str]]) -> SlotJacobian:
        """A zero Jacobian of ``members`` on these slots with the blocks of ``pattern``
        (:attr:`SliderBatch.pattern`; the ``tangent`` slots are ``interp`` and ``beside``,
        the unknowns ``xi``, ``lam`` and ``mu``)."""
        return SlotJacobian(members, self.groups, self.own, pattern)
