"""A scene's kinematics: linear, geometrically exact, or chosen by the linear answer's own
bound on what it neglects (``kinematics = "auto"``, ``docs/scenes.md``).

**The exact path** solves a static study, a load-factor sweep or the states of a modes
study (about the scene or along a load-factor sweep) of beams, rigid bodies, ties,
supports, joints, force elements (:mod:`sliders.app.exact_forces`), loads (nodal,
distributed, point loads between nodes, smeared or not) and gravity with geometrically
exact beams (:class:`fvbeam.exact_structure.ExactStructure`,
:func:`fvbeam.exact_statics.solve_static`; the loads dead, fixed in global axes, their
lever arms on the current configuration: :mod:`sliders.app.dead_loads`), and with
bodies or joints their exact model (:class:`sliders.joints.exact_model.ExactModel`, the
joints of the scene's ``[[joint]]`` tables, :mod:`sliders.app.scene_joints`), and with
sliders on chains (spherical, classical or spline, ``section`` orientation, smeared or
not, with end stops or not) the model with them
(:class:`sliders.joints.exact_slider_model.SlidingModel`).  :func:`unsupported` names the
first scene item it does not carry.

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
from sliders.joints.slider import Slider
from sliders.lines.chain import BeamChain
from sliders.solve.statics import SliderSolution

if TYPE_CHECKING:  # the exact beams are imported where the exact path is taken
    from fvbeam.exact_beam import ExactState
    from fvbeam.exact_loads import DeadLoad
    from fvbeam.exact_structure import ExactStructure
    from sliders.forces.elements import ForceElement
    from sliders.joints.exact_model import ExactModel, Joint, JointedState
    from sliders.joints.exact_slider_model import ExactSlider, SlidingModel, SlidingState

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

    state: ExactState | JointedState | SlidingState = field(kw_only=True)
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
    study = scene.study
    if isinstance(study, DynamicStudy):
        return "study.kind", "a dynamic study"
    item = _slider_unsupported(scene)
    if item is not None:
        return item
    if scene.drive:
        return "drive[0]", "a drive"
    for i, beam in enumerate(scene.beam):
        if (beam.formulation or scene.formulation) == "cubic":
            where = f"beam[{i}].formulation" if beam.formulation else "formulation"
            return where, "the cubic element"
    if isinstance(study, ModesStudy) and study.parameter is None:
        return None
    if isinstance(study, SweepStudy) and not isinstance(study.parameter, LoadFactor):
        return "study.parameter", f"a sweep over {study.parameter.kind}"
    return None


def _slider_unsupported(scene: Scene) -> tuple[str, str] | None:
    """The first slider item the exact path does not carry (it takes spherical, classical
    and spline sliders on chains of beams, ``section`` orientation, with smearing and end
    stops: :mod:`sliders.joints.exact_sliders`), as :func:`unsupported` names it."""
    rigid = {line.name for line in scene.line}
    for i, slider in enumerate(scene.slider):
        if slider.line[0] in rigid:
            return f"slider[{i}].line", "a slider on a rigid line"
        if slider.orientation != "section":
            return f"slider[{i}].orientation", "a slider's 'slope' orientation"
        if slider.friction is not None:
            return f"slider[{i}].friction", "a slider's friction"
    if scene.slider and scene.force:
        return "force[0]", "a force element beside sliders"
    return None


def modes_loads_off_nodes(scene: Scene, structure: Structure) -> tuple[str, str] | None:
    """In a modes study, the first load of ``scene`` between nodes (distributed, gravity, a
    point load off its beam's nodes or smeared), as :func:`unsupported` names it: its lever
    arms follow the configuration (:mod:`fvbeam.exact_loads`), a load stiffness that the
    modes' tangent (:meth:`fvbeam.exact_structure.ExactStructure.tangent`) does not hold."""
    study = scene.study
    if not isinstance(study, ModesStudy):
        return None
    reason = "in a modes study, a load between nodes (its load stiffness is not in the modes)"
    if study.gravity is not None:
        return "study.gravity", reason
    for i, load in enumerate(scene.load):
        if load.kind == "distributed" or (load.kind == "point" and load.smearing > 0):
            return f"load[{i}]", reason
        if load.kind == "point":
            mesh = structure.beams[structure.beam_index(load.beam)].mesh
            if np.abs(mesh.node_abscissae() - load.at).min() > 1e-12 * mesh.length:
                return f"load[{i}].at", reason
    return None


def exact_problems(scene: Scene, structure: Structure) -> list[Problem]:
    """The first scene item the exact path does not carry (:func:`unsupported`,
    :func:`modes_loads_off_nodes`), as a scene problem (with joints, which need the exact
    path, saying so); none when it carries the scene."""
    item = unsupported(scene) or modes_loads_off_nodes(scene, structure)
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
    sliders: list[Slider] = field(default_factory=list)
    forces: list[ForceElement] = field(default_factory=list)
    exact: ExactStructure = field(init=False)
    model: ExactModel | None = field(init=False, default=None)
    sliding: SlidingModel | None = field(init=False, default=None)

    def __post_init__(self) -> None:
        from fvbeam.exact_structure import ExactStructure
        from sliders.joints.exact_model import ExactModel
        from sliders.joints.exact_slider_model import SlidingModel

        if self.joints or self.structure.bodies or self.sliders:
            self.model = ExactModel.on(self.structure, self.joints, "scene", "joint")
            self.exact = self.model.exact
        else:
            self.exact = ExactStructure(self.structure)
        if self.sliders:
            assert self.model is not None
            self.sliding = SlidingModel(
                self.model, [exact_slider(s) for s in self.sliders], "slider"
            )

    def solve(
        self,
        f: np.ndarray | DeadLoad,
        start: ExactState | JointedState | SlidingState | None = None,
    ) -> ExactSolution:
        """Equilibrium under the dead load ``f`` (a vector, or loads between nodes:
        :class:`fvbeam.exact_loads.DeadLoad`) from ``start`` (default the reference, with
        joints the multipliers that balance ``f`` best there:
        :meth:`~sliders.joints.exact_model.ExactModel.balanced`); ``ValueError`` with the
        solver's message when it does not converge, or, with bodies or joints, naming the
        free motion when the tangent at the start is singular
        (:meth:`~sliders.joints.exact_model.ExactModel.free_motion`) and the load has no
        stiffness there to hold it (a weight off its body's node has)."""
        from fvbeam.exact_statics import NotConverged, solve_static
        from sliders.app.exact_forces import WithForces

        # an ExactModel is a StaticOperator over its JointedState (nodes and multipliers)
        operator: Any = self.exact if self.model is None else self.model
        if self.forces:
            operator = WithForces(operator, self.forces, self.structure)
        operator = operator if self.sliding is None else self.sliding
        load: np.ndarray | DeadLoad
        if isinstance(f, np.ndarray):
            load = np.zeros(operator.n_dofs)
            load[: len(f)] = f
        else:
            load = f.padded(operator.n_dofs)
        if self.sliding is not None and start is None:
            start = self.sliding.reference()
        elif self.model is not None:
            if start is None:
                reference = self.model.reference()
                at = load if isinstance(load, np.ndarray) else load.vector(reference)
                start = self.model.balanced(reference, at, self.fixed)
            free = np.setdiff1d(np.arange(self.model.n_dofs), self.fixed)
            motion = self.model.free_motion(cast(Any, start), free)
            # a load's own stiffness (a weight off its body's node) may hold the motion
            stiff = not isinstance(load, np.ndarray) and load.stiffness(start)[free][:, free].nnz
            if motion is not None and not stiff:
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
        jointed = state if self.sliding is None else state.model
        nodes = jointed if self.model is None else jointed.nodes
        internal = operator.residual(state)[: self.exact.n_dofs]
        sliding = self.sliding
        return ExactSolution(
            self.exact.displacements(nodes),
            []
            if sliding is None
            else [sliding.unknowns(state, i) for i in range(len(self.sliders))],
            [result.floor_ratio],
            result.iterations,
            state=state,
            internal=internal,
            forces=self.exact.internal_forces(nodes),
            joints=[] if self.model is None else self.model.reactions(jointed),
        )


def exact_slider(slider: Slider) -> ExactSlider:
    """The slider on the exact path of a scene's (linear) ``slider``, on a chain:
    its kind, line, body, offset, frame, smearing and end stops."""
    from sliders.joints.exact_slider_model import ExactSlider

    line = slider.line
    assert isinstance(line, BeamChain), "unsupported() refuses sliders on rigid lines"
    return ExactSlider(
        slider.kind,
        line.indices,
        slider.body,
        slider.offset,
        slider.frame,
        slider.smearing,
        slider.kernel,
        end_stops=slider.end_stops,
    )
