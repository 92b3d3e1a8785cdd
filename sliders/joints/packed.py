"""The joints of one problem packed into flat arrays, and their equations evaluated compiled.

A Newton step that runs compiled (:mod:`sliders.solve.newton_kernel`) evaluates every joint of
its problem at every iteration.  Passing each joint's dozens of arrays to compiled code costs
more than evaluating it (a call's arguments are checked one by one), so :class:`JointPack`
lays the constant data of all the joints -- their kind and options, the line's arrays and
the joint's slot layout -- into one float array, one integer array and a table of
descriptors, once per problem.  :func:`evaluate_joint` reads one joint's arrays back as views
and does, compiled, what :meth:`sliders.joints.slider.SliderBatch.evaluate` does for one
member in Python:

1. the line at ``xi`` (held at the ends with end stops): on a chain, the compiled line state
   (:func:`sliders.lines.batched_kernel.line_state`; a smeared load transfer by
   :func:`~sliders.lines.batched_kernel.smeared_transfer`, padded to the joint's fixed number
   of load slots; off straight elements, the section frame and curvature of
   :mod:`sliders.lines.rigid_kernel`); on a rigid line, its point, derivatives and frame
   (:func:`sliders.lines.rigid_kernel.line_at`, :func:`~sliders.lines.rigid_kernel.frame_at`);
2. the joint equations (:func:`sliders.joints.kernel.joint_equations`, paper eqs. 1-5,
   Sec. 4) on the joint's slots;
3. the bearing friction's term of the ``xi`` equation (:mod:`sliders.joints.friction`), in
   dynamics, from the velocities of the body and of the line's nodes;
4. an end stop or a drive replacing the ``xi`` equation where it acts.

``tests/test_packed_joints.py`` holds it equal to :meth:`SliderBatch.evaluate`, the
reference, to roundoff, for every kind, orientation, line, smearing, end stop and drive.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import NamedTuple

import numba
import numpy as np

from fvbeam.copies import shallow_copy
from fvbeam.kernel_cache import guard
from fvbeam.pointwise import Smearing
from fvbeam.scratch import borrowed, stack_empty, stack_zeros
from fvbeam.smearing import steps
from fvbeam.structure import Structure
from sliders.joints.blocks import SlotJacobian
from sliders.joints.compiled_laws import friction_at
from sliders.joints.equations import JointInputs, pattern
from sliders.joints.kernel import (
    BESIDE,
    GROUPS,
    INTERP,
    KINDS,
    LAM,
    MU,
    TURN,
    XI,
    joint_equations,
)
from sliders.joints.kernel import BODY as BODY_GROUP
from sliders.joints.slider import Slider, SliderBatch, _equations, _Layout
from sliders.joints.stops import end_stop
from sliders.lines.batched import KERNEL_RULE, ChainStack
from sliders.lines.batched_kernel import (
    Chains,
    line_state,
    line_state_into,
    one_point_state,
    reference_line,
    smeared_transfer,
)
from sliders.lines.chain import BeamChain
from sliders.lines.rigid import RigidLine
from sliders.lines.rigid_kernel import curvature_rate_at, frame_at, line_at

guard(__file__)  # numba's cache of these kernels, consistent with their sources

# The columns of a joint's row of :attr:`JointPack.head` (integers).
KIND, SLOPE, SECTION, CHAIN, SMEARED, BOX, END_STOPS, DRIVEN = range(8)
UNKNOWNS, SLOTS, WIDTH, NPE, LOAD, ROTATION, TANGENT, SHAPE, CURVED, NODE_DOFS = range(8, 18)
FRICTION = 18
HEAD = 19
# The columns of a joint's row of :attr:`JointPack.values` (floats).
SMEARING, LENGTH = range(2)
#: The friction law's columns (:attr:`sliders.joints.friction.Friction.law`).
FRICTION_LAW = slice(2, 6)
#: The blocks the bearing friction's term writes beyond a joint's own (its ``xi`` row reads
#: the body's velocity; the rest of the row is in every joint's pattern).
FRICTION_BLOCKS = (("xi", "body"), ("xi", "turn"))
# The arrays of a joint, in the order of its descriptors (:attr:`JointPack.fields`).
FIELDS = (
    # floats
    "offset",
    "frame",
    "reference",
    "points",
    "breaks",
    "vertex_s",
    "h",
    "lag",
    "regions",
    "ends",
    "stiffness",
    "R0_of",
    "compliance_of",
    "up",
    "beam_compliance",
    "step_r",
    "step_jump",
    "rule_x",
    "rule_w",
    "line_params",
    "line_breaks",
    "grid",
    "grid_points",
    # integers
    "body",
    "member_map",
    "maps",
    "cells",
    "first_element",
    "kinds",
    "straight",
    "start",
    "size",
    "where",
    "grid_dofs",
    "pinned",
)
(
    OFFSET,
    FRAME,
    REFERENCE,
    POINTS,
    BREAKS,
    VERTEX_S,
    H,
    LAG,
    REGIONS,
    ENDS,
    STIFFNESS,
    R0_OF,
    COMPLIANCE_OF,
    UP,
    BEAM_COMPLIANCE,
    STEP_R,
    STEP_JUMP,
    RULE_X,
    RULE_W,
    LINE_PARAMS,
    LINE_BREAKS,
    GRID,
    GRID_POINTS,
    BODY,
    MEMBER_MAP,
    MAPS,
    CELLS,
    FIRST_ELEMENT,
    KINDS_OF,
    STRAIGHT,
    START,
    SIZE,
    WHERE,
    GRID_DOFS,
    PINNED,
) = range(len(FIELDS))
INTEGER_FIELDS = FIELDS.index("body")
#: Sample points of a rigid line where a projection starts (:meth:`sliders.lines.rigid.
#: RigidLine.project`'s grid).
PROJECTION_GRID = 65


class Pool(NamedTuple):
    """A :class:`JointPack`'s arrays as the compiled kernels read them (its attributes)."""

    head: np.ndarray
    values: np.ndarray
    fields: np.ndarray
    floats: np.ndarray
    ints: np.ndarray


class FrictionLine(NamedTuple):
    """The line at ``xi`` as the bearing friction reads it (:func:`_friction`)."""

    #: The interpolation and its ``xi``-derivative (3, m), the recovered tangent's matrix
    #: (3, p), the tangent ``l~`` and ``l~_/xi`` (3,).
    N: np.ndarray
    dN: np.ndarray
    T: np.ndarray
    tangent: np.ndarray
    tangent_xi: np.ndarray


class JointState(NamedTuple):
    """Where :func:`evaluate_joint` evaluates a joint."""

    #: The structure state (n,) and the joint's unknowns ``y`` (m,).
    q: np.ndarray
    y: np.ndarray
    #: ``(v_hat, q_hat, c_v)``: the velocities ``v_hat + c_v (q - q_hat)`` the friction
    #: reads (the integrator's prediction and ``gamma'``; zeros and 0 at rest).
    velocity: tuple[np.ndarray, np.ndarray, float]
    #: The driven abscissa; the multipliers in ``y`` are ``scale`` times the physical ones.
    drive: float
    scale: float


class JointPack:
    """The constant data of ``sliders`` on ``structure``, packed (module docstring);
    ``pinned``: per joint, the unknowns a planar solve pins to zero
    (:func:`sliders.solve.planar.pinned`).

    Attributes
    ----------
    head : (J, HEAD) int64
        Per joint: kind code, slope orientation, section rotation read, line is a chain,
        smeared, box kernel, end stops, driven; unknowns ``m``, structure slots ``t``,
        Jacobian entries ``width``, nodes per element, load / rotation / tangent slots, rigid
        line shape, chain with curved elements, the dofs of a node the chain's
        interpolation reads (3, or 6 with cubic elements), bearing friction.
    values : (J, 6) float64
        Per joint: smearing, line length, the friction law (:attr:`sliders.joints.friction.
        Friction.law`; zero coefficients without friction).
    fields : (J, len(FIELDS), 5) int64
        Per joint and array of :data:`FIELDS`: offset into ``floats`` or ``ints`` and shape
        (up to four dimensions, trailing ones 1).
    floats, ints
        The arrays, raveled one after the other.
    layouts
        Per joint, its slot layout (:class:`sliders.joints.slider._Layout`) and Jacobian
        (:class:`~sliders.joints.blocks.SlotJacobian`, one member), whose ``table`` and
        coupling the condensed step reads.
    """

    def __init__(
        self,
        sliders: Sequence[Slider],
        structure: Structure,
        pinned: Sequence[Sequence[int]] | None = None,
    ) -> None:
        self.sliders = list(sliders)
        pins = list(pinned) if pinned is not None else [()] * len(self.sliders)
        floats: list[np.ndarray] = []
        ints: list[np.ndarray] = []
        sizes = [0, 0]
        J = len(self.sliders)
        self.head = np.zeros((J, HEAD), dtype=np.int64)
        self.values = np.zeros((J, 6))
        self.fields = np.zeros((J, len(FIELDS), 5), dtype=np.int64)
        self.layouts: list[tuple[_Layout, SlotJacobian]] = []
        #: Per joint on a chain, the node of the chain at each projection sample.
        self.grid_nodes: list[np.ndarray] = []
        for j, slider in enumerate(self.sliders):
            arrays, head, layout, jacobian = _joint_arrays(slider, structure, pins[j])
            self.grid_nodes.append(arrays.pop("grid_nodes", np.zeros(0, dtype=int)))
            self.head[j] = head
            law = slider.friction.law if slider.friction else (0.0, 1.0, 0.0, 1.0)
            self.values[j] = slider.smearing, slider.line.length, *law
            self.layouts.append((layout, jacobian))
            for f, name in enumerate(FIELDS):
                integer = f >= INTEGER_FIELDS
                a = np.ascontiguousarray(arrays[name], dtype=np.int64 if integer else float)
                shape = a.shape + (1,) * (4 - a.ndim)
                self.fields[j, f] = (sizes[integer], *shape)
                (ints if integer else floats).append(a.ravel())
                sizes[integer] += a.size
        self.floats = np.concatenate(floats) if floats else np.zeros(0)
        self.ints = np.concatenate(ints) if ints else np.zeros(0, dtype=np.int64)
        self._placement = self._place(self.sliders, structure)

    @property
    def pool(self) -> Pool:
        """The arrays as the compiled kernels read them."""
        return Pool(self.head, self.values, self.fields, self.floats, self.ints)

    def moved(
        self, sliders: Sequence[Slider], structure: Structure, known_moved: bool = False
    ) -> JointPack | None:
        """This pack for ``sliders`` on ``structure`` when they are this pack's moved rigidly
        (a sweep over positions: the same joints on translated copies of the same beams,
        :meth:`fvbeam.beam.Beam.translated`), with only the node positions and the sliding
        points' reference positions read anew (:meth:`_place`); None when they are not
        (build a new pack).  ``known_moved``: the caller made ``structure`` from this
        pack's by :meth:`~fvbeam.structure.Structure.moved` and ``sliders`` from this pack's
        by :meth:`~sliders.joints.slider.Slider.moved` onto it, so they are not compared
        again and the placement fits them."""
        sliders = list(sliders)
        if len(sliders) != len(self.sliders):
            return None
        if not known_moved:
            for new, old in zip(sliders, self.sliders, strict=True):
                if not _moved(new, old):
                    return None
        out = shallow_copy(self)
        out.sliders = sliders
        # moved copies (known_moved) sit on the same bodies and beams of the same numbering
        if not (known_moved or self._placement.fits(structure, sliders)):
            out._placement = self._place(sliders, structure)
        place = out._placement
        out.floats = self.floats.copy()
        out.floats[place.targets] = structure.slot_points().ravel()[place.sources] + place.added
        return out

    def _place(self, sliders: list[Slider], structure: Structure) -> Placement:
        """Where the node positions of ``sliders`` on ``structure`` go in :attr:`floats`:
        each joint's sliding point, its chain's nodes and its projection grid's nodes."""
        targets, sources, added = [], [], []
        for j, slider in enumerate(sliders):
            body = 3 * structure.node_slot(slider.body) + np.arange(3)
            targets.append(self.fields[j, REFERENCE, 0] + np.arange(3))
            sources.append(body)
            added.append(slider.offset)
            if isinstance(slider.line, BeamChain):
                line = slider.line
                nodes = np.concatenate(
                    [
                        structure.node_slot((i, 0)) + np.arange(beam.mesh.n_nodes)
                        for i, beam in zip(line.indices, line.beams, strict=True)
                    ]
                )
                for field, of in ((POINTS, nodes), (GRID_POINTS, nodes[self.grid_nodes[j]])):
                    targets.append(self.fields[j, field, 0] + np.arange(3 * len(of)))
                    sources.append((3 * of[:, None] + np.arange(3)).ravel())
                    added.append(np.zeros(3 * len(of)))
        return Placement(
            structure.dof_maps,
            _holds(sliders),
            np.concatenate(targets + [np.zeros(0, dtype=np.int64)]),
            np.concatenate(sources + [np.zeros(0, dtype=np.int64)]),
            np.concatenate(added + [np.zeros(0)]),
        )

    @property
    def unknowns(self) -> np.ndarray:
        """The number of unknowns of each joint."""
        return self.head[:, UNKNOWNS]

    @property
    def slots(self) -> np.ndarray:
        """The number of structure slots of each joint."""
        return self.head[:, SLOTS]

    @property
    def widths(self) -> np.ndarray:
        """The number of Jacobian entries of each joint."""
        return self.head[:, WIDTH]

    def initial_unknowns(self, q: np.ndarray) -> list[np.ndarray]:
        """Each joint's ``xi`` from projecting its sliding point on its line at the state
        ``q`` (:func:`project`, one compiled call for all joints), multipliers zero; a spline
        slider's frame checked against the line's there."""
        xi = project(self.pool, q)
        out = []
        for slider, x, m in zip(self.sliders, xi, self.unknowns, strict=True):
            if slider.kind == "spline":
                slider._check_frame(float(x))
            out.append(np.concatenate([[x], np.zeros(m - 1)]))
        return out

    def curve(self, j: int, q: np.ndarray, xi: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``x``, ``l``, ``l_/xi`` of joint ``j``'s line at ``xi`` on the state ``q``, compiled
        (:func:`_curve`; on a chain, :meth:`sliders.lines.chain.BeamChain.geometry`)."""
        out = np.empty((3, 3))
        _curve(j, self.pool, q, float(xi), out)
        return out[0], out[1], out[2]

    def violations(self, q: np.ndarray, unknowns: Sequence[np.ndarray], time: float) -> np.ndarray:
        """The largest constraint violation of each joint at the state ``q`` and its physical
        ``unknowns`` (drives read at ``time``), by :func:`violations`: one compiled call for
        all joints."""
        drives = np.array([s.drive(time)[0] if s.drive is not None else 0.0 for s in self.sliders])
        y = np.concatenate([np.asarray(u, dtype=float) for u in unknowns] + [np.zeros(0)])
        return violations(self.pool, q, y, drives)

    def frictions(self, Q: np.ndarray, V: np.ndarray, unknowns: np.ndarray) -> np.ndarray:
        """Each joint's friction force on its body along its line at each state (``Q``,
        ``V`` (k, n); ``unknowns`` (k, m), the joints' physical unknowns side by side): (k, J),
        by :func:`frictions` (one compiled call); zero for a joint without friction."""

        def rows(a: np.ndarray) -> np.ndarray:
            return np.ascontiguousarray(np.atleast_2d(a), dtype=float)

        return frictions(self.pool, rows(Q), rows(V), rows(unknowns))

    def evaluate(
        self,
        j: int,
        q: np.ndarray,
        y: np.ndarray,
        drive: float = 0.0,
        scale: float = 1.0,
        jacobian: bool = True,
        velocity: tuple[np.ndarray, np.ndarray, float] | None = None,
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Joint ``j`` at the state ``q`` (n,) and unknowns ``y``: its slots' global dofs,
        residual (slots, then its own equations) and Jacobian entries (laid out as its
        :class:`~sliders.joints.blocks.SlotJacobian`), by :func:`evaluate_joint`; ``drive``:
        the driven abscissa at this time (read only for a driven joint); ``velocity``:
        ``(v_hat, q_hat, c_v)`` of a dynamic step, which the friction reads (None: at rest)."""
        t, m, width = self.slots[j], self.unknowns[j], self.widths[j]
        dofs = np.zeros(t, dtype=np.int64)
        r, values = np.zeros(t + m), np.zeros(width)
        state = JointState(
            np.ascontiguousarray(q, dtype=float),
            np.ascontiguousarray(y, dtype=float),
            velocity if velocity is not None else (np.zeros(len(q)), np.zeros(len(q)), 0.0),
            float(drive),
            float(scale),
        )
        status = evaluate_joint(j, self.pool, state, jacobian, (dofs, r, values, np.zeros(1)))
        if status == 2:
            raise RuntimeError(f"slider {self.sliders[j].name!r}: more load slots than laid out")
        if status:
            raise ValueError(
                f"slider {self.sliders[j].name!r}: xi = {y[0]:.6g} lies outside its line "
                f"[0, {self.values[j, LENGTH]:.6g}]"
            )
        return dofs, r, values


def _joint_arrays(
    slider: Slider, structure: Structure, pinned: Sequence[int] = ()
) -> tuple[dict, np.ndarray, _Layout, SlotJacobian]:
    """The arrays of :data:`FIELDS` of one joint, its head row, slot layout and Jacobian;
    ``pinned``: the unknowns a planar solve pins to zero (:func:`sliders.solve.planar.
    pinned`), whose rows the layout then holds a diagonal for."""
    batch = SliderBatch([slider], [structure])
    chain = batch.chains
    arrays: dict[str, np.ndarray] = {name: np.zeros(0) for name in FIELDS}
    head = np.zeros(HEAD, dtype=np.int64)
    section = batch.section and chain is not None
    head[KIND], head[SLOPE] = KINDS[batch.kind], batch.orientation == "slope"
    head[SECTION], head[CHAIN] = section, chain is not None
    head[SMEARED], head[BOX] = batch.smearing > 0, batch.kernel == "box"
    head[END_STOPS], head[DRIVEN] = batch.end_stops, batch.drives[0] is not None
    head[UNKNOWNS] = batch.n_unknowns
    head[FRICTION] = slider.friction is not None
    arrays["offset"], arrays["frame"] = batch.offset, batch.frame
    arrays["reference"], arrays["body"] = batch.reference, batch.body
    if chain is not None:
        frames = chain.element_frames()
        npe = chain.npe
        for name in ("member_map", "maps", "cells", "points", "breaks", "vertex_s"):
            arrays[name] = getattr(chain, name if name != "member_map" else "map")
        arrays["first_element"], arrays["h"], arrays["lag"] = (
            chain.first_element,
            chain.h,
            chain.lag,
        )
        arrays["kinds"], arrays["regions"], arrays["ends"] = chain.kinds, chain.regions, chain._ends
        arrays["stiffness"] = chain.stiffness
        arrays["R0_of"], arrays["compliance_of"] = frames.R0, frames.compliance
        arrays["straight"], arrays["up"] = frames.straight[0], chain.up
        arrays["beam_compliance"] = np.stack(chain.compliance)
        head[NPE], head[CURVED], head[NODE_DOFS] = npe, not frames.straight.all(), chain.width
        head[LOAD] = _load_slots(chain, slider.smearing) if slider.smearing > 0 else 6 * npe
        head[ROTATION] = 2 * chain.width if section else 0
        head[TANGENT] = 3 * chain.width * npe
        arrays["step_r"], arrays["step_jump"] = (
            steps(slider.smearing, slider.kernel) if slider.smearing > 0 else (np.zeros(0),) * 2
        )
        arrays["rule_x"], arrays["rule_w"] = KERNEL_RULE
        grid, node = chain._node_grid()
        arrays["grid"], arrays["grid_points"] = grid, chain.points[0, node]
        arrays["grid_nodes"] = node
        arrays["grid_dofs"] = chain._node_dofs()[chain.map[0], node]
    else:
        line = slider.line
        assert isinstance(line, RigidLine)  # a batch's line is a chain or rigid
        head[SHAPE], arrays["line_params"], arrays["line_breaks"] = line.compiled()
        arrays["up"] = np.asarray(line.up, dtype=float)
        arrays["grid"] = np.linspace(0, line.length, PROJECTION_GRID)
        arrays["grid_points"] = np.array([line.derivatives(xi)[0] for xi in arrays["grid"]])
        arrays["grid_dofs"] = np.full((PROJECTION_GRID, 3), -1)
    interp = head[NODE_DOFS] * head[NPE]
    layout = _Layout(interp, head[LOAD], head[ROTATION], head[TANGENT], head[UNKNOWNS])
    arrays["pinned"] = np.asarray(pinned, dtype=np.int64)
    diagonal: tuple[tuple[str, str], ...] = (("lam", "lam"),) if any(k <= 3 for k in pinned) else ()
    diagonal += (("mu", "mu"),) if any(k > 3 for k in pinned) else ()
    diagonal += FRICTION_BLOCKS if slider.friction is not None else ()
    # once each: a cubic chain's joint has the (lam, lam) block already
    jacobian = layout.jacobian(1, tuple(dict.fromkeys(batch.pattern + diagonal)))
    compliant = head[NODE_DOFS] == 6
    writes = pattern(batch.kind, batch.orientation, bool(np.any(batch.offset)), section, compliant)
    writes += FRICTION_BLOCKS if slider.friction is not None else ()
    arrays["start"], arrays["size"], arrays["where"] = jacobian.index(GROUPS, writes)
    head[SLOTS], head[WIDTH] = layout.t, jacobian.values.shape[1]
    return arrays, head, layout, jacobian


def _moved(new: Slider, old: Slider) -> bool:
    """Whether the joint ``new`` is ``old`` moved rigidly: alike in every option, on the same
    rigid line or on a chain of translated copies of ``old``'s beams (they share their
    stiffness and arc lengths, :meth:`fvbeam.beam.Beam.translated`)."""
    if not (
        _equations(new) == _equations(old)
        and (new.drive is None) == (old.drive is None)
        and (new.offset is old.offset or np.array_equal(new.offset, old.offset))
        and (new.frame is old.frame or np.array_equal(new.frame, old.frame))
        and new.friction == old.friction
    ):
        return False
    if isinstance(new.line, BeamChain) and isinstance(old.line, BeamChain):
        return len(new.line.beams) == len(old.line.beams) and all(
            a.stiffness is b.stiffness and a.mesh.vertex_s is b.mesh.vertex_s
            for a, b in zip(new.line.beams, old.line.beams, strict=True)
        )
    return new.line is old.line


def _holds(sliders: list[Slider]) -> list:
    """What a :class:`Placement` reads of its joints besides the structure's numbering:
    each joint's body and line beams."""
    return [(s.body, s.line.indices if isinstance(s.line, BeamChain) else None) for s in sliders]


class Placement(NamedTuple):
    """Where a structure's node positions go in a pack's floats (the entries a rigid move
    changes, :meth:`JointPack.moved`): the structure's node ``numbering`` (dof maps) and
    what each joint ``holds`` (:func:`_holds`) it was made for; the entries ``targets`` of
    the floats and the entries ``sources`` of the structure's raveled
    :meth:`~fvbeam.structure.Structure.slot_points` they are read from, and what is
    ``added`` to each: a joint's offset to its sliding point's entries, zero to the
    others."""

    numbering: list[np.ndarray]
    holds: list
    targets: np.ndarray
    sources: np.ndarray
    added: np.ndarray

    def fits(self, structure: Structure, sliders: list[Slider]) -> bool:
        """Whether this placement places ``sliders`` on ``structure``: the same numbering
        (a moved structure, :meth:`fvbeam.structure.Structure.moved`, keeps it and its
        names) and joints on the same bodies and beams."""
        return structure.dof_maps is self.numbering and _holds(sliders) == self.holds


def _load_slots(chain: ChainStack, smearing: float) -> int:
    """The most load slots a smeared transfer of half-width ``smearing`` fills on ``chain``
    (:func:`sliders.lines.batched_kernel.smeared_transfer`: six per node of the elements the
    kernel reaches): the kernel's support ``2 smearing`` reaches at most
    ``ceil(2 smearing / h_min) + 1`` consecutive elements, each adding ``npe - 1`` nodes."""
    elements = min(int(np.ceil(2 * smearing / chain.h.min())) + 1, chain.h.shape[1])
    return 6 * (elements * (chain.npe - 1) + 1)


@numba.njit(cache=True, inline="always")
def _f1(floats: np.ndarray, d: np.ndarray) -> np.ndarray:
    return borrowed(floats, d[0], (d[1],))


@numba.njit(cache=True, inline="always")
def _f2(floats: np.ndarray, d: np.ndarray) -> np.ndarray:
    return borrowed(floats, d[0], (d[1], d[2]))


@numba.njit(cache=True, inline="always")
def _f3(floats: np.ndarray, d: np.ndarray) -> np.ndarray:
    return borrowed(floats, d[0], (d[1], d[2], d[3]))


@numba.njit(cache=True, inline="always")
def _f4(floats: np.ndarray, d: np.ndarray) -> np.ndarray:
    return borrowed(floats, d[0], (d[1], d[2], d[3], d[4]))


@numba.njit(cache=True, inline="never")
def _own_transfer(n_load: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A joint's own ``load_dofs`` (1, n_load) and ``G``, ``dG`` (1, n_load, 6), zero (where
    the line state's transfer does not have its shape)."""
    return (
        np.zeros((1, n_load), np.int64),
        np.zeros((1, n_load, 6)),
        np.zeros((1, n_load, 6)),
    )


@numba.njit(cache=True, inline="always")
def _own_rotation(n_rot: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """A joint's own ``rotation_dofs`` (1, n_rot) and ``W``, ``W_xi``, ``W_xixi``
    (1, 3, n_rot), zero (a joint that reads no section rotation of its line), on the stack
    of the kernel this is inlined into (:mod:`fvbeam.scratch`; two nodes of six dofs)."""
    return (
        stack_zeros(12, (1, n_rot), np.int64),
        stack_zeros(36, (1, 3, n_rot), np.float64),
        stack_zeros(36, (1, 3, n_rot), np.float64),
        stack_zeros(36, (1, 3, n_rot), np.float64),
    )


@numba.njit(cache=True, inline="always")
def _own_section() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A joint's own section frame ``R0`` and compliances ``flex``, ``flex_xi`` (1, 3, 3),
    zero until computed (a curved element, a rigid line) or unread (no section), on the
    stack of the kernel this is inlined into."""
    return (
        stack_zeros(9, (1, 3, 3), np.float64),
        stack_zeros(9, (1, 3, 3), np.float64),
        stack_zeros(9, (1, 3, 3), np.float64),
    )


@numba.njit(cache=True, inline="always")
def _chains(hd: np.ndarray, d: np.ndarray, floats: np.ndarray, ints: np.ndarray) -> Chains:
    """A chain joint's line as the line kernels read it, viewed in the pack's pools."""
    return Chains(
        _f1(ints, d[MEMBER_MAP]),
        _f4(ints, d[MAPS]),
        _f2(ints, d[CELLS]),
        _f3(floats, d[POINTS]),
        _f2(floats, d[BREAKS]),
        _f2(floats, d[VERTEX_S]),
        _f1(ints, d[FIRST_ELEMENT]),
        _f2(floats, d[H]),
        _f1(floats, d[LAG]),
        _f1(ints, d[KINDS_OF]),
        _f2(floats, d[REGIONS]),
        _f2(floats, d[ENDS]),
        _f2(floats, d[STIFFNESS]),
        hd[NODE_DOFS],
        _f4(floats, d[R0_OF]),
        _f4(floats, d[COMPLIANCE_OF]),
    )


@numba.njit(cache=True, inline="never")
def _unit_row(start: np.ndarray, size: np.ndarray, where: np.ndarray, values: np.ndarray) -> None:
    """The ``xi`` row of the Jacobian replaced by the unit derivative in ``xi`` (an equation
    ``xi - value``; :meth:`sliders.joints.blocks.SlotJacobian.unit_row`)."""
    for g in range(len(size)):
        o = where[XI, g]
        if o >= 0:
            for c in range(size[g]):
                values[o + c] = 0.0
    values[where[XI, XI]] = 1.0


@numba.njit(cache=True)
def evaluate_joint(
    j: int,
    pool: Pool,
    state: JointState,
    jacobian: bool,
    out: tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray],
) -> int:
    """Joint ``j`` of a :class:`JointPack` (its ``pool``) at ``state``: the global dof of each
    slot into ``dofs`` (t,), the residual into ``r`` (t + m,) and, with ``jacobian``, the
    Jacobian entries into ``values`` (width,) of ``out = (dofs, r, values, friction)``, all
    overwritten (module docstring); a joint with friction writes its force on the body along
    the line, ``F`` of :mod:`sliders.joints.friction` (physical when ``scale`` is 1), into
    ``friction`` (1,).  Returns 0, or 1 when ``xi`` lies off the line (without end stops),
    nothing written then."""
    dofs, r, values, friction = out
    hd, d = pool.head[j], pool.fields[j]
    smearing, length = pool.values[j, 0], pool.values[j, 1]
    kind, m, t, npe = hd[KIND], hd[UNKNOWNS], hd[SLOTS], hd[NPE]
    n_load, n_rot, width = hd[LOAD], hd[ROTATION], hd[NODE_DOFS]
    xi_raw = state.y[0]
    xi = min(max(xi_raw, 0.0), length) if hd[END_STOPS] else xi_raw
    # within 1e-12 of the length beyond an end is at the end (fvbeam.geometry.locate_abscissa)
    tie = 1e-12 * length
    if not (-tie <= xi <= length + tie):
        return 1
    start, size, where = _f1(pool.ints, d[START]), _f1(pool.ints, d[SIZE]), _f2(pool.ints, d[WHERE])
    body = _f2(pool.ints, d[BODY])
    xs = stack_empty(1, (1,), np.float64)
    xs[0] = xi
    qb = borrowed(state.q, 0, (1, len(state.q)))
    yb = borrowed(state.y, 0, (1, m))
    # the joint's line geometry, on the stack (fvbeam.scratch)
    x, l = stack_zeros(3, (1, 3), np.float64), stack_zeros(3, (1, 3), np.float64)
    l_xi, l_xixi = stack_zeros(3, (1, 3), np.float64), stack_zeros(3, (1, 3), np.float64)
    tangent, tangent_xi = stack_zeros(3, (1, 3), np.float64), stack_zeros(3, (1, 3), np.float64)
    k0, k0_xi = stack_zeros(3, (1, 3), np.float64), stack_zeros(3, (1, 3), np.float64)
    # each array below is bound once on every path: on a chain, to the line state's own
    # where it has the joint's shape (a point transfer, a straight element's section), else
    # to one made for the joint
    if hd[CHAIN]:
        chains = _chains(hd, d, pool.floats, pool.ints)
        line = one_point_state(npe, width, True, not hd[SMEARED], hd[SECTION] != 0)
        line_state_into(xs, qb, chains, True, not hd[SMEARED], hd[SECTION] != 0, line)
        beam, element, X, geometry = line.beam, line.element, line.X, line.geometry
        N, dN, d2N, T = line.N, line.dN, line.d2N, line.T
        tangent_flat = line.tangent_dofs
        x[0], l[0], l_xi[0], l_xixi[0] = (
            geometry[0, 0],
            geometry[0, 1],
            geometry[0, 2],
            geometry[0, 3],
        )
        tangent[0], tangent_xi[0] = geometry[0, 4], geometry[0, 5]
        contact, contact_xi = line.contact, line.contact_xi
        if hd[SMEARED]:
            kernel = Smearing(
                smearing,
                hd[BOX] != 0,
                _f1(pool.floats, d[STEP_R]),
                _f1(pool.floats, d[STEP_JUMP]),
                _f1(pool.floats, d[RULE_X]),
                _f1(pool.floats, d[RULE_W]),
            )
            sd, sG, sdG = smeared_transfer(xs, kernel, chains)
            k = sd.shape[1]
            if k > n_load:
                return 2
            load_dofs, G, dG = _own_transfer(n_load)
            load_dofs[0, :k] = sd[0]
            load_dofs[0, k:] = sd[0, k - 1]
            G[0, :k], dG[0, :k] = sG[0], sdG[0]
        else:
            load_dofs, G, dG = line.load_dofs, line.G, line.dG
        if hd[SECTION]:
            rotation_dofs, W, W_xi, W_xixi = line.rotation_dofs, line.W, line.W_xi, line.W_xixi
            e = element[0]
            if _f1(pool.ints, d[STRAIGHT])[e]:
                R0, flex, flex_xi = line.R0, line.flex, line.flex_xi
            else:  # curved: Lagrange 3-node elements only (a cubic element is straight)
                R0, flex, flex_xi = _own_section()
                nodes = np.empty((1, npe, 3))
                for a in range(npe):
                    nodes[0, a] = chains.points[0, chains.cells[e, a]]
                l0, l0_xi = reference_line(nodes, chains.h[0, e : e + 1], X)
                up = _f2(pool.floats, d[UP])[e]
                frame_at(l0[0], l0_xi[0], up, R0[0], k0[0])
                curvature_rate_at(l0[0], l0_xi[0], stack_zeros(3, (3,), np.float64), up, k0_xi[0])
                C = R0[0] @ _f3(pool.floats, d[BEAM_COMPLIANCE])[beam[0]] @ R0[0].T
                flex[0], flex_xi[0] = line.kink[0] * C, line.kink_xi[0] * C
        else:
            rotation_dofs, W, W_xi, W_xixi = _own_rotation(n_rot)
            R0, flex, flex_xi = _own_section()
    else:
        load_dofs, G, dG = _own_transfer(n_load)
        rotation_dofs, W, W_xi, W_xixi = _own_rotation(n_rot)
        R0, flex, flex_xi = _own_section()
        # a rigid line's empty interpolation and contact rows
        contact = contact_xi = stack_empty(1, (1, 0, 6), np.float64)
        derivatives = stack_empty(12, (4, 3), np.float64)
        at = min(max(xi, 0.0), length)  # a rigid line is read at the end (RigidLine.at)
        line_at(
            hd[SHAPE],
            _f1(pool.floats, d[LINE_PARAMS]),
            _f1(pool.floats, d[LINE_BREAKS]),
            at,
            derivatives,
        )
        x[0], l[0], l_xi[0], l_xixi[0] = (
            derivatives[0],
            derivatives[1],
            derivatives[2],
            derivatives[3],
        )
        tangent[0], tangent_xi[0] = l[0], l_xi[0]
        up = _f1(pool.floats, d[UP])
        frame_at(l[0], l_xi[0], up, R0[0], k0[0])
        curvature_rate_at(l[0], l_xi[0], l_xixi[0], up, k0_xi[0])
        N = dN = d2N = T = stack_empty(1, (1, 3, 0), np.float64)
        tangent_flat = stack_empty(1, (1, 0), np.int64)
    at = 0
    for c in range(6):
        dofs[at + c] = body[0, c]
    at = 6
    for c in range(n_load):
        dofs[at + c] = load_dofs[0, c]
    at += n_load
    for c in range(n_rot):
        dofs[at + c] = rotation_dofs[0, c]
    at += n_rot
    for c in range(tangent_flat.shape[1]):
        dofs[at + c] = tangent_flat[0, c]
    rb, vb = borrowed(r, 0, (1, t + m)), borrowed(values, 0, (1, len(values)))
    rb[:] = 0.0
    vb[:] = 0.0
    inputs = JointInputs(
        _f1(pool.floats, d[OFFSET]),
        _f2(pool.floats, d[FRAME]),
        body,
        _f2(pool.floats, d[REFERENCE]),
        qb,
        yb,
        x,
        l,
        l_xi,
        l_xixi,
        N,
        dN,
        d2N,
        G,
        dG,
        tangent,
        tangent_xi,
        T,
        contact,
        contact_xi,
        rotation_dofs,
        W,
        W_xi,
        W_xixi,
        flex,
        flex_xi,
        R0,
        k0,
        k0_xi,
        state.scale,
    )
    joint_equations(kind, hd[SLOPE] != 0, jacobian, inputs, (start, size, where), rb, vb)
    if hd[FRICTION]:
        friction[0] = _friction(
            pool.values[j, FRICTION_LAW],
            state,
            (dofs, _f1(pool.floats, d[OFFSET]), 6 + n_load + n_rot),
            FrictionLine(N[0], dN[0], T[0], tangent[0], tangent_xi[0]),
            jacobian,
            (start, size, where),
            (r, vb),
        )
    if hd[END_STOPS]:
        hit, held = end_stop(
            xi_raw, l[0, 0] * state.y[1] + l[0, 1] * state.y[2] + l[0, 2] * state.y[3], length
        )
        if hit:
            r[t] = held
            if jacobian:
                _unit_row(start, size, where, values)
    if hd[DRIVEN]:
        r[t] = state.y[0] - state.drive
        if jacobian:
            _unit_row(start, size, where, values)
    for k in _f1(pool.ints, d[PINNED]):
        r[t + k] = state.y[k]
        if jacobian:
            _pin(k, size, where, values)
    return 0


@numba.njit(cache=True, inline="never")
def _friction(
    law: np.ndarray,
    state: JointState,
    slots: tuple[np.ndarray, np.ndarray, int],
    line: FrictionLine,
    jacobian: bool,
    index: tuple[np.ndarray, np.ndarray, np.ndarray],
    out: tuple[np.ndarray, np.ndarray],
) -> float:
    """The bearing friction's term ``e`` of the ``xi`` equation (:func:`sliders.joints.
    compiled_laws.friction_at`) added to ``r``, and with ``jacobian`` its derivatives to
    ``values`` (1, width), of ``out = (r, values)``; returns the friction force ``F``.
    ``law``: ``mu, v_eps, mu_static, v_stribeck`` (:attr:`sliders.joints.friction.Friction.
    law`); ``slots``: each slot's dof, the sliding point's offset ``f`` and the first
    interpolation slot; ``index``: the layout's ``(start, size, where)``
    (:func:`sliders.joints.kernel.joint_equations`).  Through what it reads:

    * the recovered tangent ``l~ = T q + l~_0`` (its ``xi`` derivative ``l~_/xi``; ``T`` on the
      ``interp`` and ``beside`` slots);
    * the multipliers ``lambda = y[1:4]``;
    * the sliding velocity ``w = u_b' + theta_b' x f + ... - N q'`` of the body's point
      (``u_b + theta_b x f`` with ``f`` the offset, as the position constraint reads it) relative
      to the line's material point at ``xi`` (``N`` on the ``interp`` slots; zero on a rigid
      line), with ``q' = v_hat + c_v (q - q_hat)``: ``dw/dq = c_v dw/dq'``, and
      ``dw/dxi = -N_/xi q'``.
    """
    q, y, (v_hat, q_hat, c_v) = state.q, state.y, state.velocity
    dofs, offset, interp = slots
    N, dN, T, tangent, tangent_xi = line
    start, _, where = index
    r, values = out
    t = start[XI]
    w, line_xi = np.zeros(3), np.zeros(3)
    for c in range(3):
        b, turn = dofs[c], dofs[3 + c]
        w[c] += v_hat[b] + c_v * (q[b] - q_hat[b])
        rate = v_hat[turn] + c_v * (q[turn] - q_hat[turn])
        w[(c + 1) % 3] -= rate * offset[(c + 2) % 3]  # theta' x f: e_c x f per component
        w[(c + 2) % 3] += rate * offset[(c + 1) % 3]
    for col in range(N.shape[1]):
        dof = dofs[interp + col]
        rate = v_hat[dof] + c_v * (q[dof] - q_hat[dof])
        for c in range(3):
            w[c] -= N[c, col] * rate
            line_xi[c] -= dN[c, col] * rate
    d_l, d_w, d_lam = np.zeros(3), np.zeros(3), np.zeros(3)
    mu, v_eps, mu_static, v_stribeck = law
    e, force = friction_at(tangent, w, y[1:4], mu, v_eps, mu_static, v_stribeck, d_l, d_w, d_lam)
    r[t] += e
    if not jacobian:
        return force
    o = where[XI, XI]
    for c in range(3):
        values[0, o] += d_l[c] * tangent_xi[c] + d_w[c] * line_xi[c]
        values[0, where[XI, LAM] + c] += d_lam[c]
        values[0, where[XI, BODY_GROUP] + c] += c_v * d_w[c]
        # d (d_w . (theta' x f)) / d theta' = f x d_w
        values[0, where[XI, TURN] + c] += c_v * (
            offset[(c + 1) % 3] * d_w[(c + 2) % 3] - offset[(c + 2) % 3] * d_w[(c + 1) % 3]
        )
    n_interp = N.shape[1]
    for col in range(T.shape[1]):
        s = d_l[0] * T[0, col] + d_l[1] * T[1, col] + d_l[2] * T[2, col]
        if col < n_interp:
            s -= c_v * (d_w[0] * N[0, col] + d_w[1] * N[1, col] + d_w[2] * N[2, col])
            values[0, where[XI, INTERP] + col] += s
        else:
            values[0, where[XI, BESIDE] + col - n_interp] += s
    return force


@numba.njit(cache=True, inline="never")
def _pin(k: int, size: np.ndarray, where: np.ndarray, values: np.ndarray) -> None:
    """The row of unknown ``k`` (a multiplier: ``lambda`` for 1-3, ``mu`` after) replaced by
    the unit derivative in itself (the equation ``y_k = 0`` of a planar solve,
    :mod:`sliders.solve.planar`)."""
    group, row = (LAM, k - 1) if k <= 3 else (MU, k - 4)
    for g in range(len(size)):
        o = where[group, g]
        if o >= 0:
            for c in range(size[g]):
                values[o + row * size[g] + c] = 0.0
    values[where[group, group] + row * size[group] + row] = 1.0


@numba.njit(cache=True)
def violations(pool: Pool, q: np.ndarray, y: np.ndarray, drives: np.ndarray) -> np.ndarray:
    """The largest position and orientation constraint violation of each joint of a
    :class:`JointPack` at the state ``q`` and the joints' physical unknowns ``y`` side by side
    (``|x_b - x(xi)|`` and ``|g_j|``: the residual rows after the ``xi`` equation); NaN for a
    joint whose ``xi`` lies off its line."""
    head = pool.head
    J = len(head)
    out = np.empty(J)
    at = 0
    rest = (np.zeros(len(q)), np.zeros(len(q)), 0.0)  # the friction's row is not read here
    scratch = np.zeros(1)
    for j in range(J):
        t, m = head[j, SLOTS], head[j, UNKNOWNS]
        dofs, r, values = np.zeros(t, np.int64), np.zeros(t + m), np.zeros(0)
        state = JointState(q, y[at : at + m], rest, drives[j], 1.0)
        status = evaluate_joint(j, pool, state, False, (dofs, r, values, scratch))
        worst = np.nan if status else 0.0
        if not status:
            for c in range(t + 1, t + m):
                worst = max(worst, abs(r[c]))
        out[j] = worst
        at += m
    return out


@numba.njit(cache=True)
def frictions(pool: Pool, Q: np.ndarray, V: np.ndarray, Y: np.ndarray) -> np.ndarray:
    """Each joint's friction force ``F`` on its body along its line (:mod:`sliders.joints.
    friction`; zero without friction) at each of ``k`` states: displacements ``Q`` and
    velocities ``V`` (k, n), the joints' physical unknowns side by side ``Y`` (k, m); (k, J),
    NaN for a joint whose ``xi`` lies off its line."""
    head = pool.head
    J = len(head)
    out = np.zeros((len(Q), J))
    force = np.zeros(1)
    for k in range(len(Q)):
        at = 0
        for j in range(J):
            t, m = head[j, SLOTS], head[j, UNKNOWNS]
            if head[j, FRICTION]:
                dofs, r = np.zeros(t, np.int64), np.zeros(t + m)
                state = JointState(Q[k], Y[k, at : at + m], (V[k], Q[k], 0.0), 0.0, 1.0)
                status = evaluate_joint(j, pool, state, False, (dofs, r, np.zeros(0), force))
                out[k, j] = np.nan if status else force[0]
            at += m
    return out


@numba.njit(cache=True, inline="never")
def _curve(j: int, pool: Pool, q: np.ndarray, xi: float, out: np.ndarray) -> None:
    """``x``, ``l``, ``l_/xi`` (3, 3) of joint ``j``'s line at ``xi`` on the state ``q``."""
    hd, d, floats, ints = pool.head[j], pool.fields[j], pool.floats, pool.ints
    if hd[CHAIN]:
        geometry = line_state(
            np.full(1, xi), q.reshape((1, len(q))), _chains(hd, d, floats, ints), True, False, False
        ).geometry
        for r in range(3):
            out[r] = geometry[0, r]
    else:
        derivatives = np.empty((4, 3))
        line_at(
            hd[SHAPE], _f1(floats, d[LINE_PARAMS]), _f1(floats, d[LINE_BREAKS]), xi, derivatives
        )
        for r in range(3):
            out[r] = derivatives[r]


@numba.njit(cache=True)
def project(pool: Pool, q: np.ndarray) -> np.ndarray:
    """Each joint's ``xi`` that projects its sliding point on its line at the state ``q``:
    :func:`sliders.lines.rigid.project` (the reference, which the chains' and the rigid
    lines' ``project`` call), one joint at a time: Newton on ``l . (x - p) = 0`` from the
    sample closest to ``p`` (a chain's nodes, a rigid line's 65 points), each step clipped
    to the line, until a step is below ``1e-14`` of the length (at most 50)."""
    head, values_of, fields, floats, ints = pool
    J = len(head)
    out = np.empty(J)
    geometry = np.empty((3, 3))
    for j in range(J):
        d = fields[j]
        length = values_of[j, 1]
        body, reference = _f2(ints, d[BODY]), _f2(floats, d[REFERENCE])
        point = np.empty(3)
        for c in range(3):
            point[c] = reference[0, c] + q[body[0, c]]
        grid, points, dofs = (
            _f1(floats, d[GRID]),
            _f2(floats, d[GRID_POINTS]),
            _f2(ints, d[GRID_DOFS]),
        )
        best, closest = 0, np.inf
        for g in range(len(grid)):
            distance = 0.0
            for c in range(3):
                moved = points[g, c] + (q[dofs[g, c]] if dofs[g, c] >= 0 else 0.0)
                distance += (moved - point[c]) ** 2
            if distance < closest:
                best, closest = g, distance
        xi = grid[best]
        for _ in range(50):
            _curve(j, pool, q, xi, geometry)
            slope, along = 0.0, 0.0
            for c in range(3):
                gap = geometry[0, c] - point[c]
                slope += geometry[1, c] * geometry[1, c] + geometry[2, c] * gap
                along += geometry[1, c] * gap
            step = -along / slope if slope > 0 else 0.0
            xi = min(max(xi + step, 0.0), length)
            if abs(step) <= 1e-14 * max(length, 1.0):
                break
        out[j] = xi
    return out
