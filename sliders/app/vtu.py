"""VTU snapshots of a solved structure with its sliders, and ParaView ``.pvd`` series.

One VTU (written with meshio) holds, as points in the *reference* configuration:

=================  ============================================  ======================
points             what                                          cells (block)
=================  ============================================  ======================
beam nodes         every beam's mesh nodes, beam after beam       ``line`` / ``line3``
                   (vertices, then mid nodes, as in the mesh)     per beam, mesh order
evaluation points  every beam's recovery points (fv: evaluation   ``vertex``
                   points; Galerkin: Gauss points)
sliders            each slider's contact point on its line        ``vertex``
rigid bodies       each body's node                               ``vertex``
=================  ============================================  ======================

Point data: ``displacement`` and ``rotation`` (N, 3) (a rotation vector; its matrix
``exp(skew(rotation))`` as ``rotation_matrix``, (N, 9) row by row: with exact kinematics the
node's finite rotation, :mod:`sliders.app.kinematics`) from ``q`` through the structure's dof
maps (beam nodes: their dofs; evaluation points: the beam's trial interpolation; sliders:
the line's displacement at ``xi`` and the body's rotation; bodies: their dofs), so that the
reference points warped by ``displacement`` (ParaView's *Warp By Vector*, scale 1) are the
deformed configuration, sliders on their deformed lines; ``rigid_displacement`` (N, 3), the
same maps applied to the rigid part ``q_R`` of the motion (:func:`sliders.app.motion.rigid_motion`:
the sliding travel, a drive's motion, a free part's mean motion), and
``elastic_displacement = displacement - rigid_displacement``.  Warped by
``rigid_displacement`` at scale 1 and then by ``elastic_displacement`` at any scale ``m``,
the points are the picture :mod:`sliders.app.render` draws: sliding bodies and driven parts
at their true places, the deformation magnified ``m`` times, sliders on their lines.  Without
the held dofs (``held=None``) the rigid part is zero.  ``radius`` (N,): by default each
beam's drawn radius (:func:`sliders.app.shapes.tube_sizes`: its section's size, the inner
tube of a telescope thinner than the outer), the one a render gives its tube, on its nodes
and recovery points; sliders and bodies carry the largest.  ParaView's *Tube* filter draws
the beams at their size with *Vary Radius* "By Absolute Scalar" on ``radius``.

Cell data, one value per cell of every block (meshio needs every name on every block; a
value that does not apply is NaN, or -1 for integers):

* ``part``: 0 beam element, 1 evaluation point, 2 slider, 3 rigid body (VTU readers merge
  consecutive blocks of one cell type, so this, not the block, tells them apart);
* ``id``: the beam's, slider's or body's index in ``structure.beams``, ``sliders``,
  ``structure.bodies``;
* ``element``: the element in its beam (beam elements, evaluation points);
* ``xi``: abscissa of an evaluation point along its beam, or a slider's along its line;
* ``force``, ``moment`` (section axes: axial, two shears; torsion, two bending moments) and
  ``force_global``, ``moment_global`` (global axes): the internal forces at an evaluation
  point (:meth:`fvbeam.beam.Beam.internal_forces`);
* ``reaction``: a slider's ``lambda``; ``couple``: the couple ``m`` of its orientation
  constraints (zero for a spherical slider).  Both as they enter the body's residual
  (:mod:`sliders.joints.slider`): the joint pushes the body with ``-lambda, -m`` and the line with
  ``+lambda, +m``.
"""

from __future__ import annotations

import os
import xml.etree.ElementTree as ET
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Protocol, cast

import numpy as np
from numpy.typing import ArrayLike

from fvbeam.beam import InternalForces
from fvbeam.io import replace_directory, write_atomic
from fvbeam.names import suggest
from fvbeam.structure import Structure
from fvbeam.support import complement
from sliders.app.motion import rigid_motion
from sliders.app.shapes import tube_sizes
from sliders.app.state_tables import contact_point
from sliders.joints.slider import Slider
from sliders.lines.chain import BeamChain

if TYPE_CHECKING:  # meshio is imported where a VTU is made
    import meshio

#: Values of the ``part`` cell field.
PARTS = {"beam": 0, "evaluation point": 1, "slider": 2, "body": 3}
FLOAT_CELL_FIELDS = {
    "xi": 1,
    "force": 3,
    "moment": 3,
    "force_global": 3,
    "moment_global": 3,
    "reaction": 3,
    "couple": 3,
}
INT_CELL_FIELDS = ("part", "id", "element")
#: The fields a VTU may be asked for (``fields``); ``radius``, ``part``, ``id``, ``element``
#: and ``xi`` are always written.
FIELDS = (
    "displacement",
    "rigid_displacement",
    "elastic_displacement",
    "rotation",
    "rotation_matrix",
    "force",
    "moment",
    "force_global",
    "moment_global",
    "reaction",
    "couple",
)
ALWAYS = ("radius", *INT_CELL_FIELDS, "xi")


def check_fields(fields: Sequence[str] | None) -> set[str]:
    """The VTU fields asked for (None: all), or ``ValueError`` naming an unknown one."""
    if fields is None:
        return set(FIELDS)
    for i, name in enumerate(fields):
        if name not in FIELDS:
            raise ValueError(
                f"fields[{i}] = {name!r}: must be one of {', '.join(FIELDS)}{suggest(name, FIELDS)}"
            )
    return set(fields)


def structure_size(structure: Structure) -> float:
    """Diagonal of the bounding box of the beams' nodes and the bodies, reference
    configuration."""
    points = np.vstack(
        [beam.mesh.points for beam in structure.beams]
        + [body.position[None, :] for body in structure.bodies]
    )
    return float(np.linalg.norm(np.ptp(points, axis=0)))


def tube_radii(
    structure: Structure, radius: float | Sequence[float] | None, sliders: Sequence[Slider] = ()
) -> tuple[np.ndarray, float]:
    """One tube radius per beam, and the radius of the vertex markers (the largest).

    ``radius``: one value for all, one per beam, or ``None`` for each beam's drawn radius
    with the ``sliders`` (:func:`sliders.app.shapes.tube_sizes`).
    """
    n = len(structure.beams)
    if radius is None:
        size = structure_size(structure)
        if size == 0:
            raise ValueError(
                "radius: the structure has no extent, so there is no default radius; give one"
            )
        sizes = tube_sizes(structure, sliders, size)
        return sizes.radii, sizes.marker
    try:
        values = np.array(radius, dtype=float, ndmin=1)
    except (TypeError, ValueError):
        values = np.array([np.nan])
    if values.size == 1:
        values = np.full(max(n, 1), values[0])
    if values.shape != (max(n, 1),) or not np.all(np.isfinite(values)) or np.any(values <= 0):
        raise ValueError(
            f"radius must be one positive number or one per beam ({n}), got {radius!r}"
        )
    return values[:n], float(values.max())


def check_solution(
    structure: Structure, q: np.ndarray, sliders: Sequence[Slider], unknowns: Sequence[np.ndarray]
) -> tuple[np.ndarray, list[np.ndarray]]:
    """``q`` and the sliders' unknowns as float arrays; ``ValueError`` naming the item whose
    size or values do not fit."""
    q = np.asarray(q, dtype=float)
    if q.shape != (structure.n_dofs,) or not np.all(np.isfinite(q)):
        raise ValueError(
            f"q must be {structure.n_dofs} finite values (the structure's dofs), "
            f"got shape {q.shape}"
        )
    if len(unknowns) != len(sliders):
        raise ValueError(f"unknowns: {len(unknowns)} arrays for {len(sliders)} sliders")
    ys = []
    for i, (slider, given) in enumerate(zip(sliders, unknowns, strict=True)):
        try:
            y = np.asarray(given, dtype=float)
        except (TypeError, ValueError):
            y = np.full(0, np.nan)
        if y.shape != (slider.n_unknowns,) or not np.all(np.isfinite(y)):
            raise ValueError(
                f"unknowns[{i}] (slider {slider.name!r}): expected "
                f"{slider.n_unknowns} finite values "
                f"({', '.join(slider.unknown_names)}), got {given!r}"
            )
        ys.append(y)
    return q, ys


def slider_couple(slider: Slider, structure: Structure, q: np.ndarray, y: np.ndarray) -> np.ndarray:
    """The couple ``m`` of the slider's orientation constraints, as it enters the body's
    residual (zero for a spherical slider).

    ``m`` is linear in the multipliers ``mu``, so it is read off the joint's exact Jacobian:
    ``m = (d r_body_rotation / d mu) mu``.  That column holds ``m`` alone unless the body
    is a node of its own line, which is refused.
    """
    if slider.kind == "spherical":
        return np.zeros(3)
    body = slider.body_dofs(structure)
    if (
        isinstance(slider.line, BeamChain)
        and np.isin(
            body, np.concatenate([structure.dof_maps[b] for b in slider.line.indices])
        ).any()
    ):
        raise ValueError(
            f"slider {slider.name!r}: its body is a node of its own line {slider.line.name!r}"
        )
    dofs, _, _, J = slider.assemble(structure, q, y)
    turn = np.searchsorted(dofs, body[3:])
    return J[turn, len(dofs) + 4 :] @ y[4:]


def rigid_part(
    structure: Structure,
    q: np.ndarray,
    sliders: Sequence[Slider],
    unknowns: Sequence[np.ndarray],
    held: ArrayLike | None,
) -> np.ndarray:
    """The rigid part of ``q`` (:func:`sliders.app.motion.rigid_motion`), or zero without
    the held dofs (``held=None``)."""
    if held is None:
        return np.zeros_like(q)
    return rigid_motion(structure, q, sliders, unknowns, held)


class _Blocks:
    """Points, point data, cell blocks and cell data, gathered block by block."""

    def __init__(self) -> None:
        self.points: list[np.ndarray] = []
        self.displacement: list[np.ndarray] = []
        self.rotation: list[np.ndarray] = []
        self.radius: list[np.ndarray] = []
        self.rigid: list[np.ndarray] = []
        self.cells: list[tuple[str, np.ndarray]] = []
        self.data: dict[str, list[np.ndarray]] = {
            name: [] for name in (*INT_CELL_FIELDS, *FLOAT_CELL_FIELDS)
        }
        self.n_points = 0

    def add(
        self,
        kind: str,
        connectivity: np.ndarray,
        points: np.ndarray,
        motion: np.ndarray,
        rigid: np.ndarray,
        radius: ArrayLike,
        **cell_data: ArrayLike,
    ) -> None:
        """One cell block; ``connectivity`` indexes ``points``; ``motion`` (n, 6) and its
        rigid part's displacement ``rigid`` (n, 3); ``cell_data`` any subset of the cell
        fields (the rest are filled)."""
        n_cells = len(connectivity)
        self.cells.append((kind, connectivity + self.n_points))
        self.points.append(points)
        self.displacement.append(motion[:, :3])
        self.rotation.append(motion[:, 3:])
        self.rigid.append(rigid)
        self.radius.append(np.broadcast_to(radius, (len(points),)))
        self.n_points += len(points)
        for name in INT_CELL_FIELDS:
            self.data[name].append(
                np.broadcast_to(cell_data.get(name, -1), (n_cells,)).astype(np.int64)
            )
        for name, width in FLOAT_CELL_FIELDS.items():
            shape = (n_cells,) if width == 1 else (n_cells, width)
            self.data[name].append(
                np.broadcast_to(cell_data.get(name, np.nan), shape).astype(float)
            )

    def mesh(self, fields: set[str]) -> meshio.Mesh:
        """The mesh with the ``fields`` asked for, and those always written."""
        displacement, rigid = np.vstack(self.displacement), np.vstack(self.rigid)
        point_data = {
            "displacement": displacement,
            "rigid_displacement": rigid,
            "elastic_displacement": displacement - rigid,
            "rotation": np.vstack(self.rotation),
            "radius": np.concatenate(self.radius),
        }
        if "rotation_matrix" in fields:
            from fvbeam.rotations import exp_map

            point_data["rotation_matrix"] = exp_map(point_data["rotation"]).reshape(-1, 9)
        import meshio

        keep = fields | set(ALWAYS)
        return meshio.Mesh(
            np.vstack(self.points),
            self.cells,
            point_data={k: v for k, v in point_data.items() if k in keep},
            cell_data={k: v for k, v in self.data.items() if k in keep},
        )


def to_meshio(
    structure: Structure | System,
    q: np.ndarray | Solution,
    sliders: Sequence[Slider] = (),
    unknowns: Sequence[np.ndarray] = (),
    radius: float | Sequence[float] | None = None,
    held: ArrayLike | None = None,
    fields: Sequence[str] | None = None,
    section_forces: Sequence[InternalForces] | None = None,
) -> meshio.Mesh:
    """The solved structure as a meshio mesh (layout and fields: module docstring).

    ``to_meshio(statics, solution)`` takes them from a solved system (:meth:`Frame.of`: a
    ``SliderStatics`` and its ``SliderSolution``, a ``Dynamics`` or ``Model`` and a
    ``State``), ``radius`` then by keyword.

    Parameters
    ----------
    structure
        Beams and rigid bodies.
    q
        Global displacements, ``(structure.n_dofs,)``.
    sliders, unknowns
        The sliders and their unknowns ``[xi, lambda, mu...]`` in the same order
        (:class:`sliders.solve.statics.SliderSolution` ``.unknowns``).
    radius
        Tube radius: one value, one per beam, or ``None`` for each beam's drawn radius
        (:func:`sliders.app.shapes.tube_sizes`); sliders and bodies carry the largest.
    held
        The global dofs the supports and dof drives hold, for the rigid part of the motion
        (:func:`rigid_part`); ``None``: no rigid part.
    fields
        The fields to write (:data:`FIELDS`; None: all), besides ``radius``, ``part``,
        ``id``, ``element`` and ``xi``: what none of them needs is not computed (the rigid
        part of the motion, the internal forces, the sliders' couples).
    section_forces
        Each beam's section forces at its recovery points when they are not the linear
        map of ``q`` (a state of exact kinematics, :mod:`sliders.app.kinematics`).
    """
    structure, q, sliders, unknowns, held = _solved(structure, q, sliders, unknowns, held)
    q, ys = check_solution(structure, q, sliders, unknowns)
    asked = check_fields(fields)
    radii, marker = tube_radii(structure, radius, sliders)
    split = bool(asked & {"rigid_displacement", "elastic_displacement"})
    q_rigid = rigid_part(structure, q, sliders, ys, held) if split else np.zeros_like(q)
    forces_asked = bool(asked & {"force", "moment", "force_global", "moment_global"})
    blocks = _Blocks()
    for b, (beam, dofs, r) in enumerate(
        zip(structure.beams, structure.dof_maps, radii, strict=True)
    ):
        mesh, q_beam, rigid_beam = beam.mesh, q[dofs], q_rigid[dofs]
        kind = "line" if mesh.nodes_per_element == 2 else "line3"
        blocks.add(
            kind,
            mesh.cells,
            mesh.points,
            q_beam.reshape(-1, 6),
            rigid_beam.reshape(-1, 6)[:, :3],
            r,
            part=PARTS["beam"],
            id=b,
            element=np.arange(mesh.n_elements),
        )
        xi = beam.recovery_abscissae
        e, X = mesh.locate(xi)
        forces = None
        if forces_asked:
            forces = beam.internal_forces(q_beam) if section_forces is None else section_forces[b]
        blocks.add(
            "vertex",
            np.arange(len(e))[:, None],
            mesh.positions(e, X),
            beam.displacements(q_beam, xi),
            beam.displacements(rigid_beam, xi)[:, :3],
            r,
            part=PARTS["evaluation point"],
            id=b,
            element=e,
            xi=xi,
            **(
                {}
                if forces is None
                else dict(
                    force=forces.force,
                    moment=forces.moment,
                    force_global=forces.force_global,
                    moment_global=forces.moment_global,
                )
            ),
        )
    if sliders:
        contact = [contact_point(s, q, y) for s, y in zip(sliders, ys, strict=True)]
        motion = np.array(
            [
                np.concatenate([u, q[s.body_dofs(structure)[3:]]])
                for s, (_, u) in zip(sliders, contact, strict=True)
            ]
        )
        blocks.add(
            "vertex",
            np.arange(len(sliders))[:, None],
            np.array([x for x, _ in contact]),
            motion,
            np.array([contact_point(s, q_rigid, y)[1] for s, y in zip(sliders, ys, strict=True)]),
            marker,
            part=PARTS["slider"],
            id=np.arange(len(sliders)),
            xi=np.array([y[0] for y in ys]),
            reaction=np.array([y[1:4] for y in ys]),
            couple=np.array(
                [slider_couple(s, structure, q, y) for s, y in zip(sliders, ys, strict=True)]
                if "couple" in asked
                else np.nan
            ),
        )
    if structure.bodies:
        blocks.add(
            "vertex",
            np.arange(len(structure.bodies))[:, None],
            np.array([body.position for body in structure.bodies]),
            np.array([q[structure.node_dofs(body.name)] for body in structure.bodies]),
            np.array([q_rigid[structure.node_dofs(body.name)[:3]] for body in structure.bodies]),
            marker,
            part=PARTS["body"],
            id=np.arange(len(structure.bodies)),
        )
    return blocks.mesh(asked)


def write_vtu(
    path: str | Path,
    structure: Structure | System,
    q: np.ndarray | Solution,
    sliders: Sequence[Slider] = (),
    unknowns: Sequence[np.ndarray] = (),
    radius: float | Sequence[float] | None = None,
    held: ArrayLike | None = None,
    fields: Sequence[str] | None = None,
    section_forces: Sequence[InternalForces] | None = None,
) -> None:
    """Write the solved structure to the VTU file ``path`` atomically
    (:func:`fvbeam.io.write_atomic`); arguments as :func:`to_meshio`, e.g.
    ``write_vtu(path, statics, solution)``."""
    path = Path(path)
    if path.suffix != ".vtu":
        raise ValueError(f"path {str(path)!r} must end in .vtu")
    import meshio

    mesh = to_meshio(structure, q, sliders, unknowns, radius, held, fields, section_forces)
    write_atomic(path, lambda tmp: meshio.write(tmp, mesh, file_format="vtu"))


def write_pvd(path: str | Path, steps: Sequence[tuple[float, str | Path]]) -> None:
    """Write a ParaView collection ``path`` (``.pvd``) listing ``steps`` = ``[(time,
    vtu_path)]`` atomically.

    Each ``vtu_path`` (absolute or relative to the working directory, as any path) must
    exist; the index names it relative to the ``.pvd``'s directory, so the two move
    together.  Times must be finite and distinct (ParaView shows one data set per time).
    """
    path = Path(path)
    if path.suffix != ".pvd":
        raise ValueError(f"path {str(path)!r} must end in .pvd")
    root = ET.Element("VTKFile", type="Collection", version="0.1", byte_order="LittleEndian")
    collection = ET.SubElement(root, "Collection")
    seen: dict[float, int] = {}
    for i, step in enumerate(steps):
        if not (isinstance(step, (tuple, list)) and len(step) == 2):
            raise ValueError(f"steps[{i}] must be (time, vtu_path), got {step!r}")
        time, file = step
        try:
            time = float(time)
        except (TypeError, ValueError):
            time = np.nan
        if not np.isfinite(time):
            raise ValueError(f"steps[{i}]: time must be a finite number, got {step[0]!r}")
        if time in seen:
            raise ValueError(f"steps[{i}]: time {time!r} repeats steps[{seen[time]}]")
        seen[time] = i
        if not Path(file).is_file():
            raise ValueError(f"steps[{i}]: file {str(file)!r} does not exist")
        relative = Path(os.path.relpath(Path(file).resolve(), path.parent.resolve()))
        ET.SubElement(
            collection, "DataSet", timestep=repr(time), group="", part="0", file=relative.as_posix()
        )
    tree = ET.ElementTree(root)
    ET.indent(tree)
    write_atomic(path, lambda tmp: tree.write(tmp, encoding="utf-8", xml_declaration=True))


class System(Protocol):
    """A solved system's parts: ``SliderStatics``, ``Dynamics``, ``Model``."""

    @property
    def structure(self) -> Structure: ...
    @property
    def sliders(self) -> Sequence[Slider]: ...


class Solution(Protocol):
    """A solution's values: ``SliderSolution``, a dynamics ``State``."""

    @property
    def q(self) -> np.ndarray: ...
    @property
    def unknowns(self) -> Sequence[np.ndarray]: ...


@dataclass(frozen=True)
class Frame:
    """One output step of a series: the time (or swept parameter) and the solved structure
    with its sliders and held dofs (arguments of :func:`to_meshio`)."""

    time: float
    structure: Structure
    q: np.ndarray
    sliders: Sequence[Slider] = ()
    unknowns: Sequence[np.ndarray] = ()
    held: ArrayLike | None = None
    #: Each beam's section forces when they are not the linear map of ``q`` (exact
    #: kinematics: the solution's ``forces``).
    section_forces: Sequence[InternalForces] | None = None

    @classmethod
    def of(
        cls,
        system: System,
        solution: Solution,
        time: float | None = None,
        held: ArrayLike | None = None,
    ) -> Frame:
        """The frame of ``solution`` (its ``q`` and ``unknowns``: a ``SliderSolution``, a
        dynamics ``State``) of ``system`` (its ``structure`` and ``sliders``: a
        ``SliderStatics``, a ``Dynamics``, a scene's ``Model``), at ``time`` (default: the
        solution's ``t``, else 0).  ``held``: the dofs the supports and dof drives hold
        (default: those not in ``system.free``, for a ``SliderStatics`` or a ``Dynamics``;
        ``None`` for a system without ``free``: no rigid part)."""
        for given, what, names in (
            (system, "system", ("structure", "sliders")),
            (solution, "solution", ("q", "unknowns")),
        ):
            if not all(hasattr(given, name) for name in names):
                raise ValueError(
                    f"the {what} must have {' and '.join(names)} (got {type(given).__name__})"
                )
        if time is None:
            time = getattr(solution, "t", 0.0)
        free = getattr(system, "free", None)
        if held is None and free is not None:
            held = complement(system.structure.n_dofs, free)
        return cls(
            float(time),
            system.structure,
            solution.q,
            system.sliders,
            solution.unknowns,
            held,
            getattr(solution, "forces", None),
        )


def _solved(
    structure: Structure | System,
    q: np.ndarray | Solution,
    sliders: Sequence[Slider],
    unknowns: Sequence[np.ndarray],
    held: ArrayLike | None,
) -> tuple[Structure, np.ndarray, Sequence[Slider], Sequence[np.ndarray], ArrayLike | None]:
    """The arguments of :func:`to_meshio` given either way: as they are, or a system and its
    solution (:meth:`Frame.of`, which finds the held dofs of a system that has ``free``)
    with nothing after them but ``held``."""
    if isinstance(structure, Structure):
        return structure, cast(np.ndarray, q), sliders, unknowns, held
    if not (isinstance(sliders, Sequence) and isinstance(unknowns, Sequence)) or (
        len(sliders) or len(unknowns)
    ):
        raise ValueError(
            "given a solved system and its solution, the sliders and their unknowns are "
            "theirs: pass nothing after the solution (the radius by keyword)"
        )
    frame = Frame.of(structure, cast(Solution, q), held=held)
    return frame.structure, frame.q, frame.sliders, frame.unknowns, frame.held


def write_series(
    directory: str | Path,
    frames: Iterable[Frame],
    radius: float | Sequence[float] | None = None,
    fields: Sequence[str] | None = None,
) -> Path:
    """Write a whole series: ``directory/NAME.pvd`` (``NAME`` the directory's name) and one
    ``directory/step_NNNNNN.vtu`` per frame, in frame order, with the ``fields`` asked for
    (:func:`to_meshio`).

    The files are written into a new temporary directory, which then takes the place of
    ``directory`` as a whole (:func:`fvbeam.io.replace_directory`): an error or an
    interruption while frames are computed or written leaves the previous series untouched,
    and a re-run never leaves a mix of old and new files.  ``frames`` may be a generator
    (the frames are written as they come).  Returns the ``.pvd`` path.
    """
    directory = Path(directory)
    index = directory / f"{directory.name}.pvd"
    check_fields(fields)

    def write(tmp: Path) -> None:
        steps = []
        for k, frame in enumerate(frames):
            if not isinstance(frame, Frame):
                raise ValueError(f"frames[{k}] must be a Frame, got {type(frame).__name__}")
            file = tmp / f"step_{k:06d}.vtu"
            write_vtu(
                file,
                frame.structure,
                frame.q,
                frame.sliders,
                frame.unknowns,
                radius,
                frame.held,
                fields,
                frame.section_forces,
            )
            steps.append((frame.time, file))
        write_pvd(tmp / index.name, steps)

    replace_directory(directory, write)
    return index
