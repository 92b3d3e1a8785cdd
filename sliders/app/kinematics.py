"""A scene's kinematics: linear, geometrically exact, or chosen by the linear answer's own
bound on what it neglects (``kinematics = "auto"``, ``docs/scenes.md``).

**The exact path** solves a static study, a load-factor sweep or the states of a modes
study (about the scene or along a load-factor sweep) of beams, rigid bodies, ties,
supports, joints and nodal loads (and point loads at a node, unsmeared) with
geometrically exact beams (:class:`fvbeam.exact_structure.ExactStructure`,
:func:`fvbeam.exact_statics.solve_static`; the loads dead, fixed in global axes), and with
bodies or joints their exact model (:class:`sliders.joints.exact_model.ExactModel`, the
joints of the scene's ``[[joint]]`` tables, :mod:`sliders.app.scene_joints`).  The bodies'
masses play no part (no gravity on this path).  :func:`unsupported` names the first scene item it
does not carry.

**The bound** (:func:`neglected`).  Linear kinematics writes the strains as
``nu = u' - theta x t`` and ``kappa = theta'``; the exact ones
(:mod:`fvbeam.exact_beam`) with ``Lambda = exp(theta)`` are, to second order in the rotation,

    nu = Lambda^T (t + u') - t = nu_lin - theta x nu_lin - theta x (theta x t) / 2 + O(theta^3),
    kappa = J(theta)^T theta' = kappa_lin - theta x kappa_lin / 2 + O(theta^3),

so the neglected terms are second order: ``|nu - nu_lin| <= theta (theta / 2 + eps)`` with
``theta`` the largest rotation at the beams' nodes and ``eps`` the largest strain
``|nu_lin|``.  A body tied to a beam shares its node's rotation; a body on no beam (a wheel
spinning about its axle) moves rigidly, strains nothing and does not enter ``theta``:
linear kinematics is exact for its rotation about one fixed axis, and does not bound a
free body turning about several.  Integrated
along a path from a support, they move a point by at most ``ell theta (theta / 2 + eps)``,
``ell`` the path's length (bounded here by the beams' total length), and the loads' lever
arms by as much.  Relative to the largest displacement ``u`` of the linear answer,

    eta = ell theta (theta / 2 + eps) / u

bounds the relative difference between the linear and the exact answers at leading order
(first order in ``theta``, since ``u`` is).  ``"auto"`` keeps the linear answer when ``eta``
is at most the study's ``tol`` and solves exactly otherwise; ``"linear"`` warns when ``eta``
is above it.  The bound is that of the rotation and strain: a compressive axial force near
buckling amplifies a small rotation, which it does not see.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, cast

import numpy as np

from fvbeam.beam import InternalForces
from fvbeam.structure import Structure
from sliders.app.errors import Problem
from sliders.app.schema import DynamicStudy, LoadFactor, ModesStudy, Scene, SweepStudy
from sliders.solve.statics import SliderSolution

if TYPE_CHECKING:  # the exact beams are imported where the exact path is taken
    from fvbeam.exact_beam import ExactState
    from fvbeam.exact_structure import ExactStructure
    from sliders.joints.exact_model import ExactModel, Joint, JointedState

#: The scene key's values.
KINDS = ("exact", "linear", "auto")


@dataclass
class ExactSolution(SliderSolution):
    """A static solution with exact kinematics: ``q`` each node's displacement and rotation
    vector (:meth:`fvbeam.exact_structure.ExactStructure.displacements`), the ``state``
    itself, the internal force vector ``internal`` (``r(q)`` and the joints' ``B^T
    lambda``: its reactions), each beam's section ``forces`` at its recovery points and each
    joint's share ``B^T lambda`` of its nodes' balances
    (:meth:`sliders.joints.exact_model.ExactModel.reactions`)."""

    state: ExactState | JointedState = field(kw_only=True)
    internal: np.ndarray = field(kw_only=True)
    forces: list[InternalForces] = field(kw_only=True)
    joints: list[np.ndarray] = field(kw_only=True, default_factory=list)


@dataclass(frozen=True)
class Bound:
    """The linear answer's bound on its neglected terms (module docstring): its largest
    ``rotation`` (rad), ``strain`` and ``displacement`` (m), the ``length`` of the longest
    path (m) and ``eta``, the bound relative to the displacement."""

    rotation: float
    strain: float
    displacement: float
    length: float
    eta: float

    def describe(self) -> str:
        return (
            f"largest rotation {self.rotation:.3g} rad and strain {self.strain:.3g} bound the "
            f"neglected terms by {self.eta:.3g} of the largest displacement"
        )


def unsupported(scene: Scene) -> tuple[str, str] | None:
    """The first item of ``scene`` the exact path does not carry, as ``(key path,
    reason)``, or None."""
    parts = {"slider": "a slider", "force": "a force element"}
    for what, items in zip(parts, (scene.slider, scene.force), strict=True):
        if items:
            return f"{what}[0]", parts[what]
    if scene.drive:
        return "drive[0]", "a drive"
    for i, beam in enumerate(scene.beam):
        if (beam.formulation or scene.formulation) == "cubic":
            where = f"beam[{i}].formulation" if beam.formulation else "formulation"
            return where, "the cubic element"
    for i, load in enumerate(scene.load):
        if load.kind == "distributed":
            return f"load[{i}]", "a distributed load"
        if load.kind == "point" and load.smearing > 0:
            return f"load[{i}].smearing", "a smeared point load"
    study = scene.study
    if isinstance(study, DynamicStudy):
        return "study.kind", "a dynamic study"
    if study.gravity is not None:
        return "study.gravity", "gravity (a distributed load)"
    if isinstance(study, ModesStudy) and study.parameter is None:
        return None
    if isinstance(study, SweepStudy) and not isinstance(study.parameter, LoadFactor):
        return "study.parameter", f"a sweep over {study.parameter.kind}"
    return None


def point_loads_off_nodes(scene: Scene, structure: Structure) -> tuple[str, str] | None:
    """The first point load of ``scene`` that is not at a node of its beam (the exact path
    takes a point load at a node as that node's load), as :func:`unsupported` names it."""
    for i, load in enumerate(scene.load):
        if load.kind != "point":
            continue
        mesh = structure.beams[structure.beam_index(load.beam)].mesh
        gap = np.abs(mesh.node_abscissae() - load.at).min()
        if gap > 1e-12 * mesh.length:
            return f"load[{i}].at", "a point load between nodes"
    return None


def exact_problems(scene: Scene, structure: Structure) -> list[Problem]:
    """The first scene item the exact path does not carry (:func:`unsupported`,
    :func:`point_loads_off_nodes`), as a scene problem (with joints, which need the exact
    path, saying so); none when it carries the scene."""
    item = unsupported(scene) or point_loads_off_nodes(scene, structure)
    if item is None:
        return []
    path, reason = item
    if scene.joint:  # no other path: joints are exact only
        return [Problem(path, f"{reason}: exact kinematics, which joints need, does not carry it")]
    return [Problem(path, f"{reason}: exact kinematics does not carry it ('auto', 'linear' do)")]


def neglected(structure: Structure, q: np.ndarray) -> Bound:
    """The bound of a linear answer ``q`` on its neglected terms (module docstring): the
    largest rotation at the beams' nodes, the largest nodal displacement, and the largest
    strain ``|nu|`` at the beams' recovery points (their section forces,
    :attr:`fvbeam.beam.Beam.recovery`, through the section's compliance)."""
    d = q.reshape(-1, 6)
    on_beams = np.concatenate([np.zeros(0, int), *(m[::6] // 6 for m in structure.dof_maps)])
    rotation = float(np.linalg.norm(d[on_beams, 3:], axis=1).max(initial=0.0))
    displacement = float(np.linalg.norm(d[:, :3], axis=1).max(initial=0.0))
    strain, length = 0.0, 0.0
    for beam, dofs in zip(structure.beams, structure.dof_maps, strict=True):
        forces = (beam.recovery @ q[dofs]).reshape(-1, 6)
        nu = np.linalg.solve(beam.section.stiffness, forces.T)[:3]
        strain = max(strain, float(np.linalg.norm(nu, axis=0).max(initial=0.0)))
        length += beam.mesh.length
    eta = length * rotation * (rotation / 2 + strain) / displacement if displacement > 0 else 0.0
    return Bound(rotation, strain, displacement, length, eta)


@dataclass
class ExactPath:
    """The exact statics of a model's structure, supports and joints, built once for a
    study: the structure's :class:`~fvbeam.exact_structure.ExactStructure`, or with bodies or
    joints its :class:`~sliders.joints.exact_model.ExactModel`."""

    structure: Structure
    fixed: np.ndarray
    max_iterations: int = 25
    load_steps: int = 1
    joints: list[Joint] = field(default_factory=list)
    exact: ExactStructure = field(init=False)
    model: ExactModel | None = field(init=False, default=None)

    def __post_init__(self) -> None:
        from fvbeam.exact_structure import ExactStructure
        from sliders.joints.exact_model import ExactModel

        if self.joints or self.structure.bodies:
            self.model = ExactModel.on(self.structure, self.joints, "scene", "joint")
            self.exact = self.model.exact
        else:
            self.exact = ExactStructure(self.structure)

    def solve(self, f: np.ndarray, start: ExactState | JointedState | None = None) -> ExactSolution:
        """Equilibrium under the dead load ``f`` from ``start`` (default the reference, with
        joints the multipliers that balance ``f`` best there:
        :meth:`~sliders.joints.exact_model.ExactModel.balanced`); ``ValueError`` with the
        solver's message when it does not converge, or, with bodies or joints, naming the
        free motion when the tangent at the start is singular
        (:meth:`~sliders.joints.exact_model.ExactModel.free_motion`)."""
        from fvbeam.exact_statics import NotConverged, solve_static

        # an ExactModel is a StaticOperator over its JointedState (nodes and multipliers)
        operator: Any = self.exact if self.model is None else self.model
        load = np.zeros(operator.n_dofs)
        load[: len(f)] = f
        if self.model is not None:
            if start is None:
                start = self.model.balanced(self.model.reference(), load, self.fixed)
            free = np.setdiff1d(np.arange(self.model.n_dofs), self.fixed)
            motion = self.model.free_motion(cast(Any, start), free)
            if motion is not None:
                raise ValueError(f"exact kinematics: at the start, {motion}")
        try:
            result = solve_static(
                operator,
                load,
                self.fixed,
                state=cast(Any, start),
                max_iterations=self.max_iterations,
                first_step=1.0 / self.load_steps,
            )
        except NotConverged as exc:
            raise ValueError(f"exact kinematics: {exc}") from None
        state: Any = result.state
        nodes = state if self.model is None else state.nodes
        internal = operator.residual(state)[: self.exact.n_dofs]
        return ExactSolution(
            self.exact.displacements(nodes),
            [],
            [result.floor_ratio],
            result.iterations,
            state=state,
            internal=internal,
            forces=self.exact.internal_forces(nodes),
            joints=[] if self.model is None else self.model.reactions(state),
        )
