"""Exact models with sliders: an :class:`~sliders.joints.exact_model.ExactModel` whose nodes
also slide on lines of its exact beams.

Each :class:`ExactSlider` puts a node of the model (a beam node or a rigid body) on a chain
of the model's beams (:class:`~sliders.lines.exact_line.ExactChain`) with the laws of
:mod:`sliders.joints.exact_sliders`; its unknowns ``[xi, lambda, mu]`` follow the joints'
multipliers.  The problem is the model's with the sliders' loads added to the nodes'
balances and their ``xi`` and constraint rows appended::

    r(q) + sum_j B_j^T lambda_j + sum_s p_s(q, y_s) = f,    c_j(q) = 0,
    xi row_s(q, y_s) = 0,                                    c_s(q, xi_s) = 0,

``p_s`` the slider's loads on its body and on its line's nodes; its tangent is the model's
bordered tangent with each slider's block (derived: :func:`sliders.joints.exact_sliders.
derive`).  :class:`SlidingModel` has the operator interface of
:func:`fvbeam.exact_statics.solve_static`, without the solver's position correction: a
slider's ``xi`` row, ``-lambda . l + ...``, is bilinear in its multipliers and the line's
positions, and a correction of the positions and multipliers at fixed ``xi`` leaves it off
by their rounding times its large derivatives, which Newton alone removes.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from fvbeam.names import NodeRef
from sliders.joints.exact_model import ExactModel, JointedState, ModelPoints
from sliders.joints.exact_sliders import KINDS, SliderDerived, SliderPoint, derive
from sliders.lines.exact_line import ExactChain

EPS = float(np.finfo(float).eps)


@dataclass(frozen=True)
class ExactSlider:
    """A node sliding on a chain of exact beams.

    Parameters
    ----------
    kind
        ``spherical``, ``classical`` or ``spline`` (:mod:`sliders.joints.exact_sliders`).
    line
        The chain's beams, by name or index, joined end to start (a beam's name alone for
        one beam).
    body
        The sliding node (:mod:`fvbeam.names`): a beam node or a rigid body.
    offset
        The sliding point from the node, global axes of the reference configuration.
    frame
        The slider axes ``[e_1, e_2, e_3]`` (columns) in the reference configuration.
    smearing, kernel
        The spread of the load on the line (:mod:`fvbeam.smearing`), as on linear chains.
    xi
        The starting abscissa (default: the drive's, else the reference line's point closest
        to the sliding point).
    drive
        The abscissa a drive holds (statics: a drive's value at the start), or None: the
        frictionless slider.
    end_stops
        Stops at both ends of the line: the sliding point rests at an end (``xi`` held
        there, the frictionless row's value the stop's force) while the stop pushes, and
        leaves it when the stop would pull (:meth:`SlidingModel.stopped`).
    """

    kind: str
    line: str | int | Sequence[str | int]
    body: NodeRef
    offset: np.ndarray = field(default_factory=lambda: np.zeros(3))
    frame: np.ndarray = field(default_factory=lambda: np.eye(3))
    smearing: float = 0.0
    kernel: str = "box"
    xi: float | None = None
    drive: float | None = None
    end_stops: bool = False


@dataclass(frozen=True)
class SlidingState:
    """A state of a :class:`SlidingModel`: the model's, and the sliders' unknowns."""

    model: JointedState
    unknowns: np.ndarray

    @property
    def x(self) -> np.ndarray:
        """The nodes' positions (n, 3)."""
        return self.model.x

    @property
    def R(self) -> np.ndarray:
        """The nodes' rotations (n, 3, 3)."""
        return self.model.R

    def updated(self, dq: np.ndarray) -> SlidingState:
        """The state moved by ``dq``: the model's part, then the sliders' increments added."""
        n = len(dq) - len(self.unknowns)
        return SlidingState(self.model.updated(dq[:n]), self.unknowns + dq[n:])


@dataclass(frozen=True)
class SlidingPoints:
    """What a state evaluates to: the model's points, each slider's residual and tangent."""

    model: ModelPoints
    sliders: list[SliderDerived]


class SlidingModel:
    """An exact model with sliders (module docstring); ``sliders[i]`` named ``key[i]`` in
    messages."""

    def __init__(
        self, model: ExactModel, sliders: Sequence[ExactSlider], key: str = "sliders"
    ) -> None:
        self.model, self.sliders, self.key = model, list(sliders), key
        self.name = model.name
        structure = model.structure
        self.chains: list[ExactChain] = []
        self.laws: list[SliderPoint] = []
        self.bodies: list[int] = []
        self.slices: list[slice] = []
        start = model.n_dofs
        for i, slider in enumerate(self.sliders):
            label = f"{self.name}: {key}[{i}]"
            if slider.kind not in KINDS:
                raise ValueError(
                    f"{label}: kind must be one of {', '.join(KINDS)}, got {slider.kind!r}"
                )
            try:
                chain = ExactChain(structure, slider.line, slider.smearing, slider.kernel)
                body = model._node(slider.body, "body")
            except ValueError as error:
                raise ValueError(f"{label}: {error}") from None
            if body < 0:
                raise ValueError(f"{label}: the body must be a node, not the ground")
            point = SliderPoint(
                slider.kind,
                np.asarray(slider.offset, dtype=float),
                np.asarray(slider.frame, dtype=float),
            )
            self.chains.append(chain)
            self.laws.append(point)
            self.bodies.append(body)
            self.slices.append(slice(start, start + point.n_unknowns))
            start += point.n_unknowns
        self.n_dofs = start
        self.n_nodes = model.n_nodes
        self.position_multipliers = model.position_multipliers
        #: No position correction (:func:`fvbeam.exact_statics._balance_forces`): a
        #: slider's ``xi`` row is bilinear in its multipliers and the line's positions.
        self.balances_positions = False
        self._X = model.exact.reference().x

    def reference(self) -> SlidingState:
        """The model's reference, each slider at its ``xi`` (given, or the reference line's
        point closest to the sliding point), zero multipliers."""
        unknowns = []
        for slider, chain, point, body in zip(
            self.sliders, self.chains, self.laws, self.bodies, strict=True
        ):
            xi = slider.drive if slider.xi is None else slider.xi
            xi = chain.project(self._X[body] + point.offset) if xi is None else xi
            unknowns.append(np.concatenate([[float(xi)], np.zeros(point.n_unknowns - 1)]))
        values = np.concatenate(unknowns) if unknowns else np.zeros(0)
        return SlidingState(self.model.reference(), values)

    def unknowns(self, state: SlidingState, i: int) -> np.ndarray:
        """Slider ``i``'s unknowns ``[xi, lambda, mu]`` at ``state``."""
        where = self.slices[i]
        n = self.model.n_dofs
        return state.unknowns[where.start - n : where.stop - n]

    def points(self, state: SlidingState) -> SlidingPoints:
        """The model's points and each slider's residual and tangent."""
        derived = []
        for i, (chain, point, body) in enumerate(
            zip(self.chains, self.laws, self.bodies, strict=True)
        ):
            y = self.unknowns(state, i)
            slider, at = self.sliders[i], y[0]
            if slider.end_stops and slider.drive is None:
                at = min(max(at, 0.0), chain.length)  # a stop holds xi on the line
            try:
                site = chain.at(at)
            except ValueError as error:
                raise ValueError(f"{self.name}: {self.key}[{i}]: {error}") from None
            d = derive(point, site, state.x, state.R, body, y, self._X, slider.drive)
            if at != y[0] or (slider.end_stops and self.stopped(chain, at, d.along)):
                d = derive(point, site, state.x, state.R, body, y, self._X, at)
            derived.append(d)
        return SlidingPoints(self.model.points(state.model), derived)

    @staticmethod
    def stopped(chain: ExactChain, xi: float, along: float) -> bool:
        """Whether an end stop holds a sliding point at ``xi``: at an end of the line, the
        frictionless row's value ``along`` (``d (y . c) / d xi``) pushing it out, i.e. the
        stop's multiplier non-negative (``-along`` at the far end, where ``xi <= L``;
        ``along`` at the start, where ``xi >= 0``: Karush-Kuhn-Tucker)."""
        if xi >= chain.length:
            return along <= 0.0
        if xi <= 0.0:
            return along >= 0.0
        return False

    def _dofs(self, i: int, derived: SliderDerived) -> np.ndarray:
        """The model's dofs of slider ``i``'s local columns (:class:`SliderDerived`)."""
        nodes = np.concatenate([[self.bodies[i]], derived.nodes])
        where = self.slices[i]
        return np.concatenate(
            [(6 * nodes[:, None] + np.arange(6)).ravel(), np.arange(where.start, where.stop)]
        )

    def residual(self, state: SlidingState, pts: SlidingPoints | None = None) -> np.ndarray:
        """The model's residual with the sliders' loads, then their rows."""
        pts = self.points(state) if pts is None else pts
        out = np.zeros(self.n_dofs)
        out[: self.model.n_dofs] = self.model.residual(state.model, pts.model)
        for i, derived in enumerate(pts.sliders):
            np.add.at(out, self._dofs(i, derived), derived.residual)
        return out

    def residual_floor(self, state: SlidingState, pts: SlidingPoints | None = None) -> np.ndarray:
        """A bound on each residual in units of its rounding: the model's; on a slider's
        loads and rows, the sizes of their terms: ``|load|`` spread as the load is
        (``|J| |y|`` over the multipliers' columns), on the ``xi`` row plus ``|f_L| |l| +
        |m_L| |k|``, on a constraint row ``|B|`` times the nodes' coordinates' sizes (as
        :meth:`~sliders.joints.exact_model.ExactModel.residual_floor`) plus its value; on
        every row, the sizes of its derivatives times the unknowns' (``|J| [|x|, 1, |y|]``,
        ``|xi|`` among ``|y|``:
        the rounding of the state the row reads)."""
        pts = self.points(state) if pts is None else pts
        out = np.zeros(self.n_dofs)
        out[: self.model.n_dofs] = self.model.residual_floor(state.model, pts.model)
        size = np.maximum(np.linalg.norm(state.x, axis=1), 1.0)
        for i, derived in enumerate(pts.sliders):
            dofs = self._dofs(i, derived)
            n_y = self.slices[i].stop - self.slices[i].start
            y = np.abs(self.unknowns(state, i))
            J = np.abs(derived.tangent)
            nodes = len(dofs) - n_y
            scale = np.concatenate(
                [np.where(np.arange(nodes) % 6 < 3, size[dofs[:nodes] // 6], 1.0), y]
            )
            floor = J @ scale + np.abs(derived.residual)
            load = np.abs(derived.load)
            floor[nodes] = load[:3] @ np.abs(derived.arms[:3]) + load[3:] @ np.abs(derived.arms[3:])
            np.add.at(out, dofs, floor)
        return out

    def tangent(
        self, state: SlidingState, pts: SlidingPoints | None = None, keep: np.ndarray | None = None
    ) -> sp.csc_matrix:
        """The model's bordered tangent with each slider's block; with ``keep`` (sorted
        dofs), its rows and columns on those only."""
        pts = self.points(state) if pts is None else pts
        K = sp.block_diag(
            [
                self.model.tangent(state.model, pts.model),
                sp.csc_matrix((self.n_dofs - self.model.n_dofs,) * 2),
            ],
            format="coo",
        )
        rows, cols, vals = [K.row], [K.col], [K.data]
        for i, derived in enumerate(pts.sliders):
            dofs = self._dofs(i, derived)
            rows.append(np.repeat(dofs, len(dofs)))
            cols.append(np.tile(dofs, len(dofs)))
            vals.append(derived.tangent.ravel())
        full = sp.coo_matrix(
            (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
            shape=(self.n_dofs, self.n_dofs),
        ).tocsc()
        return full if keep is None else full[keep][:, keep].tocsc()
