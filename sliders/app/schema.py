"""The scene schema: frozen pydantic models of every table a scene may hold (``docs/scenes.md``).

Phase 1 of validation (:func:`sliders.app.scene.parse_scene`): keys, types, finite numbers,
positive stiffnesses and masses, allowed kinds, with a did-you-mean for unknown keys and kinds.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any, Literal, get_args

import numpy as np
from pydantic import (
    AfterValidator,
    BaseModel,
    BeforeValidator,
    ConfigDict,
    Field,
    Strict,
    ValidationInfo,
)

from fvbeam.formulation_names import FormulationName as Formulation
from fvbeam.geometry import inertia3, orthonormal3

NAME_PATTERN = r"^[A-Za-z_][A-Za-z0-9_\-]*$"
#: The CSV tables a run can write (:mod:`sliders.app.tables`).
TableName = Literal["samples", "nodes", "sliders", "internal_forces", "reactions", "modes"]
#: The tables every static study and sweep writes by default (a modes study adds ``modes``).
TABLES = get_args(TableName)[:-1]

Number = Annotated[float, Strict(), Field(allow_inf_nan=False, description="a finite number")]
Positive = Annotated[
    float, Strict(), Field(allow_inf_nan=False, gt=0, description="a finite number > 0")
]
NonNegative = Annotated[
    float, Strict(), Field(allow_inf_nan=False, ge=0, description="a finite number >= 0")
]
Count = Annotated[int, Strict(), Field(ge=1, description="an integer >= 1")]
Flag = Annotated[bool, Strict(), Field(description="true or false")]
Text = Annotated[str, Strict(), Field(description="a string")]
Name = Annotated[
    str,
    Strict(),
    Field(
        pattern=NAME_PATTERN, description=("a name: a letter or _, then letters, digits, _ or -")
    ),
]
NodeRef = Annotated[
    str,
    Strict(),
    Field(
        pattern=NAME_PATTERN[:-1] + r"(\.(start|end))?$",
        description="a node: a body's name, or a beam's end as 'beam.start' or 'beam.end'",
    ),
]
Vec3 = Annotated[
    tuple[Number, ...], Field(min_length=3, max_length=3, description="3 numbers [x, y, z]")
]
Rows3 = Annotated[
    tuple[Vec3, ...], Field(min_length=3, max_length=3, description="3 rows of 3 numbers")
]


def _diagonal(value: Any) -> Any:
    """Three entries that are not all rows stand for a diagonal matrix (a wrong entry is then
    reported at ``[i][i]``)."""
    if (
        isinstance(value, list)
        and len(value) == 3
        and not all(isinstance(v, (list, tuple)) for v in value)
    ):
        return [[value[0], 0.0, 0.0], [0.0, value[1], 0.0], [0.0, 0.0, value[2]]]
    return value


def _inertia(value: tuple) -> tuple:
    inertia3(value, "an inertia")
    return value


def _frame(value: tuple) -> tuple:
    orthonormal3(value, "the axes [e1, e2, e3]")
    return value


Inertia = Annotated[
    Rows3,
    BeforeValidator(_diagonal),
    AfterValidator(_inertia),
    Field(
        description="3 numbers (diagonal) or 3 rows of 3 numbers, symmetric positive semi-definite"
    ),
]
Frame = Annotated[
    Rows3,
    AfterValidator(_frame),
    Field(description="the axes [e1, e2, e3], each 3 numbers, orthonormal"),
]


def _one_name(value: Any) -> Any:
    """A single name stands for a list of one."""
    return [value] if isinstance(value, str) else value


LineRef = Annotated[
    tuple[Name, ...],
    BeforeValidator(_one_name),
    Field(
        min_length=1,
        description="a rigid line's name, or a beam's name or a list of beam "
        "names (a chain, joined end to start)",
    ),
]


def _resolve(path: str, info: ValidationInfo) -> str:
    """A mesh path relative to the scene file's folder, made absolute."""
    base = (info.context or {}).get("base")
    return str((Path(base) / path).resolve()) if base is not None else path


MeshPath = Annotated[
    str,
    Strict(),
    AfterValidator(_resolve),
    Field(description="a mesh file's path (relative to the scene file)"),
]
FilePath = Annotated[
    str,
    Strict(),
    AfterValidator(_resolve),
    Field(description="a file's path (relative to the scene file)"),
]


class Table(BaseModel):
    """A TOML table: unknown keys are errors, values are frozen once validated."""

    model_config = ConfigDict(extra="forbid", frozen=True)


# -- model --------------------------------------------------------------------------------------
class MaterialSpec(Table):
    """A section's material (:class:`fvbeam.shapes.Material`): ``E`` (Pa), exactly one of
    ``nu`` and ``G`` (Pa), ``density`` (kg/m^3)."""

    E: Positive
    nu: Number | None = None
    G: Positive | None = None
    density: Positive | None = None


class TubeShape(Table):
    kind: Literal["tube"]
    outer: Positive
    inner: NonNegative


class CircleShape(Table):
    kind: Literal["circle"]
    diameter: Positive


class RectangleShape(Table):
    kind: Literal["rectangle"]
    width: Positive
    height: Positive


class IShape(Table):
    kind: Literal["I"]
    height: Positive
    width: Positive
    web: Positive
    flange: Positive


ShapeSpec = Annotated[
    TubeShape | CircleShape | RectangleShape | IShape, Field(discriminator="kind")
]


class SectionSpec(Table):
    """``[[section]]``: a beam section, uncoupled: its six stiffnesses
    (``fvbeam.Section.diagonal``) or its ``material`` and ``shape``
    (``fvbeam.Section.from_shape``); exactly one of the two (:mod:`sliders.app.checks`)."""

    name: Name
    EA: Positive | None = None
    GAy: Positive | None = None
    GAz: Positive | None = None
    GJ: Positive | None = None
    EJy: Positive | None = None
    EJz: Positive | None = None
    mass_per_length: Positive | None = None
    inertia: Inertia | None = None
    material: MaterialSpec | None = None
    shape: ShapeSpec | None = None


class StraightSpec(Table):
    """A straight beam from ``start`` to ``end`` in ``elements`` equal elements."""

    start: Vec3
    end: Vec3
    elements: Count


class ArcSpec(Table):
    """A circular arc about ``center`` in the plane normal to z, ``angle0`` to ``angle1``
    (radians)."""

    center: Vec3
    radius: Positive
    angle0: Number
    angle1: Number
    elements: Count


class BeamSpec(Table):
    """``[[beam]]``: one beam; exactly one of ``straight``, ``arc``, ``mesh``."""

    name: Name
    section: Name
    formulation: Formulation | None = None
    straight: StraightSpec | None = None
    arc: ArcSpec | None = None
    mesh: MeshPath | None = None
    up: Vec3 | None = None


class BodySpec(Table):
    """``[[body]]``: a rigid body (``fvbeam.RigidBody``), one six-dof node; ``velocity`` and
    ``angular_velocity``: its node's at the start of a dynamic study (instead of
    ``study.start.velocity``)."""

    name: Name
    position: Vec3
    mass: Positive | None = None
    inertia: Inertia | None = None
    frame: Frame | None = None
    centre: Vec3 = (0.0, 0.0, 0.0)
    velocity: Vec3 | None = None
    angular_velocity: Vec3 | None = None


class TieSpec(Table):
    """``[[tie]]``: two coincident nodes made one."""

    nodes: Annotated[
        tuple[NodeRef, ...], Field(min_length=2, max_length=2, description="two nodes")
    ]


class SupportSpec(Table):
    """``[[support]]``: a node held: ``clamp``, ``pin`` or dof names joined by ``+``."""

    node: NodeRef
    kind: Text = "clamp"


class JointSpec(Table):
    """``[[joint]]``: a joint with finite rotations (exact kinematics) between nodes ``a`` and
    ``b`` (a body, a beam's end, or ``"ground"``): ``spherical``, ``revolute``,
    ``universal``, ``prismatic``, ``fixed`` or rows joined by ``+``; at ``position``
    (default ``b``'s), with axes ``frame`` or ``axis`` (``e1``: a hinge's or a prismatic
    joint's axis) (:mod:`sliders.app.scene_joints`)."""

    kind: Text
    a: NodeRef
    b: NodeRef
    position: Vec3 | None = None
    axis: Vec3 | None = None
    frame: Frame | None = None


class StraightLineSpec(Table):
    kind: Literal["straight"]
    name: Name
    start: Vec3
    end: Vec3
    up: Vec3 = (0.0, 0.0, 1.0)


class ArcLineSpec(Table):
    kind: Literal["arc"]
    name: Name
    center: Vec3
    radius: Positive
    angle0: Number
    angle1: Number


class HelixLineSpec(Table):
    kind: Literal["helix"]
    name: Name
    center: Vec3
    radius: Positive
    pitch: Number
    turns: Positive


class SplineLineSpec(Table):
    kind: Literal["cubic-spline"]
    name: Name
    points: Annotated[tuple[Vec3, ...], Field(min_length=3, description="3 or more points")]
    up: Vec3 = (0.0, 0.0, 1.0)


LineSpec = Annotated[
    StraightLineSpec | ArcLineSpec | HelixLineSpec | SplineLineSpec, Field(discriminator="kind")
]


class FrictionSpec(Table):
    """A slider's bearing friction (``sliders.joints.friction.Friction``): coefficient ``mu``
    and regularisation velocity ``v_eps`` (m/s); stick-slip: the static coefficient
    ``mu_static`` and the Stribeck speed ``v_stribeck`` (m/s)."""

    mu: NonNegative
    v_eps: Positive = 1.0e-3
    mu_static: NonNegative | None = None
    v_stribeck: Positive = 1.0e-2


class SliderSpec(Table):
    """``[[slider]]``: a node sliding on a line (``sliders.joints.slider.Slider``)."""

    name: Name
    kind: Literal["spherical", "classical", "spline"]
    line: LineRef
    body: NodeRef
    offset: Vec3 = (0.0, 0.0, 0.0)
    frame: Frame = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
    smearing: NonNegative = 0.0
    kernel: Literal["box", "hat"] = "box"
    orientation: Literal["section", "slope"] = "section"
    end_stops: Flag = False
    friction: FrictionSpec | None = None


class Wrench(Table):
    """A force and a couple, global axes (N, N m; per unit length for a distributed load)."""

    force: Vec3 = (0.0, 0.0, 0.0)
    moment: Vec3 = (0.0, 0.0, 0.0)


class NodalLoad(Wrench):
    """``[[load]]`` on a node."""

    kind: Literal["nodal"]
    name: Name | None = None
    node: NodeRef


class PointLoad(Wrench):
    """``[[load]]`` at the abscissa ``at`` (m) of a beam, spread by ``smearing``."""

    kind: Literal["point"]
    name: Name | None = None
    beam: Name
    at: NonNegative
    smearing: NonNegative = 0.0
    kernel: Literal["box", "hat"] = "box"


class DistributedLoad(Wrench):
    """``[[load]]`` per unit length on a whole beam."""

    kind: Literal["distributed"]
    name: Name | None = None
    beam: Name


LoadSpec = Annotated[NodalLoad | PointLoad | DistributedLoad, Field(discriminator="kind")]


# -- force elements -----------------------------------------------------------------------------
class StrutLaw(Table):
    """An oleo-pneumatic strut's law (:class:`sliders.forces.laws.Strut`): polytropic gas
    spring, orifice damper, penalty end stops; SI units, compression positive."""

    kind: Literal["strut"]
    area: Positive
    pressure: Positive
    volume: Positive
    exponent: Positive
    ambient: NonNegative = 101_325.0
    compression: NonNegative
    rebound: NonNegative
    stop_stiffness: Positive
    stroke_min: Number = 0.0
    stroke_max: Number


class AxialForceSpec(Table):
    """``[[force]]`` of kind ``axial``: ``law`` along the line between two nodes, of the
    stroke ``extended - |x_b - x_a|`` (:class:`sliders.forces.elements.AxialForce`)."""

    kind: Literal["axial"]
    name: Name
    nodes: Annotated[
        tuple[NodeRef, ...], Field(min_length=2, max_length=2, description="two nodes [a, b]")
    ]
    extended: Positive
    law: StrutLaw


class TyreSpec(Table):
    """``[[force]]`` of kind ``tyre``: a wheel on flat ground (:class:`sliders.forces.
    elements.Tyre`): the axle node's translations, the wheel node's spin."""

    kind: Literal["tyre"]
    name: Name
    axle: NodeRef
    wheel: NodeRef
    radius: Positive
    stiffness: Positive
    damping: NonNegative
    B: Positive
    C: Positive
    D: Positive
    speed_eps: Positive = 0.1
    ground: Vec3 = (0.0, 0.0, 0.0)
    normal: Vec3 = (0.0, 0.0, 1.0)
    forward: Vec3 = (1.0, 0.0, 0.0)


ForceSpec = Annotated[AxialForceSpec | TyreSpec, Field(discriminator="kind")]


# -- drives -------------------------------------------------------------------------------------
class LinearMotion(Table):
    """``start + velocity (t - t0)`` (:class:`sliders.joints.drives.Linear`)."""

    kind: Literal["linear"]
    start: Number
    velocity: Number
    t0: Number = 0.0


class RampMotion(Table):
    """From ``start`` to ``end`` between ``t0`` and ``t1`` (:class:`sliders.joints.drives.Ramp`)."""

    kind: Literal["ramp"]
    start: Number
    end: Number
    t0: Number
    t1: Number
    shape: Literal["linear", "cosine"] = "cosine"


def _integer(value: Any) -> Any:
    """An integer as TOML writes it (``1``, not ``1.0`` nor ``true``), before a ``Literal`` of
    integers compares it (which would take both)."""
    if isinstance(value, bool) or not isinstance(value, int):
        raise ValueError(f"must be an integer, not {type(value).__name__}")
    return value


class TabulatedMotion(Table):
    """Through ``(times, values)`` (:class:`sliders.joints.drives.Tabulated`)."""

    kind: Literal["tabulated"]
    times: Annotated[tuple[Number, ...], Field(min_length=2)]
    values: Annotated[tuple[Number, ...], Field(min_length=2)]
    order: Annotated[Literal[1, 3], BeforeValidator(_integer)] = 1


MotionSpec = Annotated[LinearMotion | RampMotion | TabulatedMotion, Field(discriminator="kind")]


class AbscissaDrive(Table):
    """``[[drive]]`` of a slider's abscissa (m): the body is pushed along its line."""

    kind: Literal["abscissa"]
    slider: Name
    motion: MotionSpec


class DofDriveSpec(Table):
    """``[[drive]]`` of one dof of a node (m or rad from the reference configuration)."""

    kind: Literal["dof"]
    node: NodeRef
    dof: Literal["ux", "uy", "uz", "rx", "ry", "rz"]
    motion: MotionSpec


DriveSpec = Annotated[AbscissaDrive | DofDriveSpec, Field(discriminator="kind")]


# -- study ---------------------------------------------------------------------------------------
class Newton(Table):
    """Newton options (:func:`sliders.solve.statics.newton_many`); ``planar``: a scene that
    lies in a coordinate plane is solved on its in-plane dofs
    (:attr:`sliders.app.model.Model.plane`)."""

    method: Literal["auto", "bordered", "condensed"] = "auto"
    tol: Positive = 1e-8
    max_iterations: Count = 25
    planar: Flag = True


class Solver(Newton):
    """Newton options of the static studies (:meth:`sliders.solve.statics.SliderStatics.solve`);
    ``gravity``: the acceleration of gravity, the weight ``M g`` on the structure with the
    ``mass`` matrix of that kind (:func:`fvbeam.mass.weight`), a dead load that a load-factor
    sweep does not scale."""

    load_steps: Count = 1
    gravity: Vec3 | None = None
    mass: Literal["lumped", "consistent"] = "lumped"


class StaticStudy(Solver):
    kind: Literal["static"]


class LoadFactor(Table):
    """Every load times the value."""

    kind: Literal["load_factor"]


class Translation(Table):
    """The beams and bodies ``move`` translated by the value (m) along ``direction``."""

    kind: Literal["translation"]
    move: Annotated[tuple[Name, ...], Field(min_length=1, description="beam and body names")]
    direction: Vec3


class Abscissa(Table):
    """The abscissa (m) of a slider's body on its line, or of a point load on its beam."""

    kind: Literal["abscissa"]
    of: Name


Parameter = Annotated[LoadFactor | Translation | Abscissa, Field(discriminator="kind")]


class Range(Table):
    """``num`` values evenly spaced from ``start`` to ``stop``, both included."""

    start: Number
    stop: Number
    num: Count


class SweepStudy(Solver):
    kind: Literal["sweep"]
    parameter: Parameter
    values: Annotated[tuple[Number, ...], Field(min_length=1)] | None = None
    range: Range | None = None
    continuation: Flag = True
    stop_on_failure: Flag = False

    def sweep_values(self) -> np.ndarray:
        """The parameter's values, in order."""
        if self.values is not None:
            return np.array(self.values)
        if self.range is None:
            raise ValueError("study: give exactly one of values, range")
        return np.linspace(self.range.start, self.range.stop, self.range.num)


class ModesStudy(SweepStudy):
    """Modes about the static state (:func:`sliders.solve.modes.modes_about`): the ``count``
    lowest, or with ``window = [f_min, f_max]`` (Hz) at most ``count`` in it; ``damping`` the
    beams' stiffness-proportional coefficient (s), as a dynamic study's.  With a
    ``parameter`` (and its ``values`` or ``range``) about every point of that sweep, each
    mode followed from point to point by its shape (MAC); without one, about the scene as
    written."""

    kind: Literal["modes"]  # type: ignore[assignment]
    parameter: Parameter | None = None  # type: ignore[assignment]
    count: Count = 6
    window: tuple[NonNegative, Positive] | None = None
    damping: NonNegative = 0.0


class AdaptiveSpec(Table):
    """Error-controlled steps (:class:`sliders.solve.dynamics.Adaptive`)."""

    rtol: Positive = 1e-4
    atol: NonNegative = 1e-12
    h_min: NonNegative = 0.0
    h_max: Positive | None = None


class CheckpointSpec(Table):
    """Checkpoints of a run of the command (:mod:`sliders.app.checkpoint`): one every
    ``steps`` time steps or ``seconds`` of wall time, whichever comes first (0: not by that
    rule; both 0: none).  The default keeps a short run resumable too (every 500 steps) and
    a long one at most a minute behind."""

    steps: Annotated[int, Strict(), Field(ge=0, description="an integer >= 0")] = 500
    seconds: NonNegative = 60.0


class StartSpec(Table):
    """``[study.start]``: a dynamic study's start from the static equilibrium with
    ``hold``'s nodes clamped (for that solve only: a part the masses alone hold once moving,
    an airframe touching down), then set moving: every node's translations at ``velocity``
    (the dofs the supports and drives hold stay at rest; a body's own ``velocity`` and
    ``angular_velocity`` go first), accelerations zero (a start in balance)."""

    velocity: Vec3 = (0.0, 0.0, 0.0)
    hold: tuple[NodeRef, ...] = ()


class DynamicStudy(Newton):
    """Time integration from the static equilibrium at ``t = 0`` (set moving by ``start``,
    or a saved ``restart`` state) to ``t_end`` (:class:`sliders.solve.dynamics.Dynamics`):
    steps of ``step`` seconds, or ``adaptive`` ones starting there; ``damping`` is the
    stiffness-proportional coefficient (s); ``every``: keep one state in that many for the
    VTU series and renders; ``checkpoint``: how often ``fvslider run`` saves what
    ``--resume`` needs (None: the defaults of :class:`CheckpointSpec`, every minute)."""

    kind: Literal["dynamic"]
    t_end: Positive
    step: Positive
    rho_inf: Annotated[
        float, Strict(), Field(ge=0, le=1, allow_inf_nan=False, description="a number in [0, 1]")
    ] = 0.8
    mass: Literal["lumped", "consistent"] = "lumped"
    damping: NonNegative = 0.0
    gravity: Vec3 | None = None
    adaptive: AdaptiveSpec | None = None
    restart: FilePath | None = None
    every: Count = 1
    checkpoint: CheckpointSpec | None = None
    start: StartSpec | None = None


Study = Annotated[StaticStudy | SweepStudy | ModesStudy | DynamicStudy, Field(discriminator="kind")]


Names = Annotated[tuple[Text, ...], Field(description="a list of names")]


class NodesOutput(Table):
    """``[output.nodes]``: the rows of the ``nodes`` table (``nodes``: a beam's or body's
    name for all its nodes, ``beam.start``, ``beam.end``) and its columns after ``part,
    xi``; None: all."""

    nodes: Names | None = None
    columns: Names | None = None


class SlidersOutput(Table):
    """``[output.sliders]``: the sliders of the ``sliders`` table and its columns after
    ``slider``; None: all."""

    sliders: Names | None = None
    columns: Names | None = None


class ForcesOutput(Table):
    """``[output.internal_forces]``: the beams of the ``internal_forces`` table and its
    columns after ``beam, xi``; None: all."""

    beams: Names | None = None
    columns: Names | None = None


class ReactionsOutput(Table):
    """``[output.reactions]``: the held nodes of the ``reactions`` table and its columns
    after ``node``; None: all."""

    nodes: Names | None = None
    columns: Names | None = None


class ProbeSpec(Table):
    """``[[output.probe]]``: a ``history.csv`` column of a dynamic study, ``value`` of a
    ``node`` (a dof, ``ux`` ... ``rz``, or its rate, ``vx`` ... ``vz``, ``wx`` ... ``wz``), of
    a ``beam`` at the recovery point nearest its abscissa ``at`` (an internal force, ``N``
    ... ``M3``) or of a ``force`` element (``force``, ``stroke``, ``rate`` of an axial one;
    ``Fz``, ``Fx``, ``deflection``, ``slip`` of a tyre) or of a ``slider`` (``force``, the
    magnitude of its reaction's components on ``axes``, all three by default; ``friction``;
    ``couple``) (:mod:`sliders.app.probes`)."""

    name: Name
    node: NodeRef | None = None
    beam: Name | None = None
    force: Name | None = None
    slider: Name | None = None
    at: NonNegative | None = None
    axes: tuple[Literal["x", "y", "z"], ...] | None = None
    value: Text


Column = Annotated[str, Strict(), Field(min_length=1, description="a history.csv column")]
#: A window's end: an event's name (``[[output.event]]``) or a time (s).
Instant = Name | Number


class AttachmentSpec(Table):
    """``[[output.load]]``: the load the rest of the model exerts on a body, its attachment
    load, as ``history.csv`` columns ``NAME.Fx`` ... ``NAME.Mz`` (``components``; default:
    the body's free dofs) (:func:`sliders.app.events.load_probe`)."""

    name: Name
    body: Name
    components: tuple[Literal["Fx", "Fy", "Fz", "Mx", "My", "Mz"], ...] | None = None


class PeakSpec(Table):
    """``[[output.peak]]``: the largest value of a ``history.csv`` column (or of the sum of
    the magnitudes of several) between ``after`` and ``before``, its time and the
    ``concurrent`` columns' values then (:mod:`sliders.app.events`)."""

    name: Name
    of: Column | tuple[Column, ...]
    sign: Literal["magnitude", "positive", "negative"] = "magnitude"
    scale: Number = 1.0
    offset: Number = 0.0
    after: Instant | None = None
    before: Instant | None = None
    concurrent: tuple[Column, ...] = ()
    per: Name | None = None


class EventSpec(Table):
    """``[[output.event]]``: when a force element's ``contact`` begins, a tyre's
    ``lift_off`` and ``spin_up`` (to ``fraction`` of rolling), an axial force's ``stop``
    reached (``compression`` or ``extension``) with its penetration (:mod:`sliders.app.
    events`)."""

    name: Name
    kind: Literal["contact", "lift_off", "spin_up", "stop"]
    force: Name
    fraction: Annotated[
        float, Strict(), Field(gt=0, le=1, allow_inf_nan=False, description="a number in (0, 1]")
    ] = 0.99
    stop: Literal["compression", "extension"] = "compression"


class FrequencySpec(Table):
    """``[[output.frequency]]``: the frequency of a column's oscillation, from its zero
    crossings between ``after`` and ``before`` (:func:`sliders.app.events.frequency`)."""

    name: Name
    of: Column
    after: Instant | None = None
    before: Instant | None = None


class RenderSpec(Table):
    """``[output.render]``: how renders and animations draw (:class:`sliders.app.render.
    Options`): the ``view`` (``auto``: the plane the model lies in, else isometric), the
    ``magnification`` of the elastic displacements (None: automatic), a node to ``follow``
    (everything drawn relative to it), the ``window`` (width, height in pixels) and the
    animation's frames per second ``fps``."""

    view: Literal["auto", "xy", "xz", "yz", "iso"] = "auto"
    magnification: Positive | None = None
    follow: NodeRef | None = None
    window: Annotated[
        tuple[Count, Count], Field(description="two integers >= 1: width and height")
    ] = (1200, 800)
    fps: Positive = 20.0


class Output(Table):
    """``[output]``: the CSV tables to write (:mod:`sliders.app.tables`); ``vtu``: a VTU per
    converged sample and their ``.pvd`` index (:mod:`sliders.app.vtu`); ``png``: pyvista
    renders of the deformed configuration, of the ``last`` converged sample or of ``all``
    (:mod:`sliders.app.render`, needs the ``render`` extra); ``animation``: a dynamic
    study's kept states as ``animation.mp4`` or ``animation.gif``; ``render``: how they
    are drawn (:class:`RenderSpec`).  What to write of them: the
    columns of ``history.csv`` after ``step, t`` (``history``), each table's rows and
    columns, the VTU fields (``vtu_fields``), and ``probe`` columns of ``history.csv``; the
    names are checked against the model (:class:`sliders.app.model.Model`)."""

    csv: tuple[TableName, ...] = TABLES
    vtu: Flag = False
    png: Literal["none", "last", "all"] = "none"
    animation: Literal["none", "mp4", "gif"] = "none"
    render: RenderSpec = RenderSpec()
    history: Names | None = None
    vtu_fields: Names | None = None
    nodes: NodesOutput | None = None
    sliders: SlidersOutput | None = None
    internal_forces: ForcesOutput | None = None
    reactions: ReactionsOutput | None = None
    probe: tuple[ProbeSpec, ...] = ()
    load: tuple[AttachmentSpec, ...] = ()
    peak: tuple[PeakSpec, ...] = ()
    event: tuple[EventSpec, ...] = ()
    frequency: tuple[FrequencySpec, ...] = ()


class Scene(Table):
    """A whole scene: the model's parts, the study and the outputs."""

    title: Text = ""
    kinematics: Literal["exact", "linear", "auto"] = "auto"
    formulation: Formulation = "fv3"
    integration: Literal["reduced", "full"] = "reduced"
    section: tuple[SectionSpec, ...] = ()
    beam: tuple[BeamSpec, ...] = ()
    body: tuple[BodySpec, ...] = ()
    line: tuple[LineSpec, ...] = ()
    tie: tuple[TieSpec, ...] = ()
    support: tuple[SupportSpec, ...] = ()
    joint: tuple[JointSpec, ...] = ()
    slider: tuple[SliderSpec, ...] = ()
    load: tuple[LoadSpec, ...] = ()
    force: tuple[ForceSpec, ...] = ()
    drive: tuple[DriveSpec, ...] = ()
    study: Study
    output: Output = Output()
