"""Off-screen pyvista pictures of a deformed structure with its sliders: PNG renders
(:func:`render`) and MP4 or GIF animations (:func:`animate`).

What is drawn (:mod:`sliders.app.shapes` gives the sizes):

* the deformed beams, each a tube of its section's size, coloured by the bending-moment
  magnitude ``|(M2, M3)|`` (section axes) interpolated linearly in ``xi`` between the
  beam's recovery points (held constant beyond the first and last); the outer beam of a
  telescope translucent, so the inner one shows through it;
* the undeformed beams, carried by their rigid motion, as translucent grey tubes;
* sliders as red spheres at their contact points on the deformed lines; rigid bodies as
  dark cubes; a tyre's wheel as a disc with its tyre and a mark that turns with its spin,
  and the ground it rolls on;
* the rigid lines the sliders run on as thin dark rails, and each axial force element (a
  strut, a spring-damper) as an orange coil spring between its nodes.

Each part is a named actor of the plotter (:data:`ACTORS` gives the names), so a picture's
parts can be counted.

Every point is drawn at ``X + u_R + m (u - u_R)``: its reference position, the rigid part
``u_R`` of its displacement at true size and the elastic part magnified ``m`` times.  Given
the held dofs, ``u_R`` is the rigid motion of :func:`sliders.app.motion.rigid_motion` (a
body's travel along its line, a drive's motion, a free part's mean motion), so sliding
bodies and driven parts stay at their true places, on their magnified lines; without them
it is zero and the whole displacement is magnified.  By default ``m`` draws the largest
elastic displacement as :data:`AUTO_FRACTION` of the structure's size: the deformation is
seen, and the mechanism is not hidden by it.  ``m`` is written in the picture.  With
``follow``, everything is drawn relative to that node: its drawn displacement is taken off
every point (a camera riding with an airframe).

The view (:mod:`sliders.app.view`) is by default the plane the drawn points lie in, or an
isometric one; the camera is a parallel projection fitted to everything drawn, leaving the
right of the image to the colour bar, the top to the title and the bottom to the
magnification.  An animation fits one camera, one magnification and one colour range to all
its frames, and writes the time in each frame's title.

pyvista is imported only when a picture is made.  Without a display, VTK renders through EGL
(Mesa's software rasteriser; the Makefile installs Debian's ``libegl1 libegl-mesa0
libgl1-mesa-dri``): the pictures then set ``VTK_DEFAULT_OPENGL_WINDOW`` to
``vtkEGLRenderWindow`` unless it is set already, which skips VTK's failing attempt at X11.
Animations are written through imageio (with its own ffmpeg for MP4: the ``render`` extra).
"""

from __future__ import annotations

import ctypes.util
import os
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from fvbeam.beam import InternalForces
from fvbeam.io import write_atomic
from fvbeam.names import NodeRef
from fvbeam.structure import Structure
from sliders.app.schema import RenderSpec
from sliders.app.shapes import (
    COIL_FACTOR,
    HUB_FACTOR,
    HUB_WIDTH,
    RAIL_FACTOR,
    TYRE_WIDTH,
    WIRE_FACTOR,
    Ground,
    TubeSizes,
    Wheel,
    axial_forces,
    coil,
    ground_under,
    line_points,
    rigid_lines,
    tube_sizes,
    tyres,
    wheel,
)
from sliders.app.state_tables import contact_point
from sliders.app.view import Camera, check_view, choose_view, fit_camera
from sliders.app.vtu import Frame, check_solution, rigid_part, structure_size, tube_radii
from sliders.forces.elements import ForceElement
from sliders.joints.slider import Slider

#: Samples per element along the tube (a 3-node element is a parabola; 8 chords keep
#: its sag below 1/256 of the element's bow, invisible at tube scale).
SAMPLES_PER_ELEMENT = 8
#: Automatic magnification: the largest elastic displacement drawn as this fraction of the
#: structure's size.
AUTO_FRACTION = 0.1
#: Marker sizes relative to the largest tube radius.
SPHERE_FACTOR, CUBE_FACTOR = 1.6, 3.0
BAR_TITLE = "bending moment [N m]"
#: The colour bar: left, bottom, width and height, fractions of the window (right of
#: :data:`sliders.app.view.MODEL_REGION`).
BAR_BOX = (0.82, 0.14, 0.1, 0.72)
#: The colour bar's title and label font sizes in a window 1200 pixels wide (scaled with
#: the width, so the bar's title keeps within its box).
BAR_FONT = (20, 18)
#: The title's largest font size and the share of the window's width it may take.
TITLE_FONT, TITLE_WIDTH = 22, 0.94
#: Opacity of the outer beam of a telescope and of the undeformed ghost.
OUTER_OPACITY, GHOST_OPACITY = 0.35, 0.2
#: Animations: the formats and the frame rate.
FORMATS = ("mp4", "gif")
FPS = 20
#: The names of the actors a picture draws, ``{k}`` the part's index: beams and their ghosts
#: by the beam's, rigid lines by their order among the sliders' lines, force elements by
#: their order among the axial ones, wheels and grounds by the tyre's.
ACTORS = (
    "beam {k}",
    "ghost {k}",
    "sliders",
    "bodies",
    "rigid line {k}",
    "force element {k}",
    "tyre {k}",
    "hub {k}",
    "spin mark {k}",
    "ground {k}",
)


def headless_defaults() -> None:
    """Choose VTK's EGL window when there is no display and libEGL can be found (and the
    user has not chosen a window class)."""
    if os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"):
        return
    if ctypes.util.find_library("EGL"):
        os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")


def magnification_for(
    structure: Structure, elastic: np.ndarray, magnification: float | None
) -> float:
    """``magnification``, checked, or by default the factor drawing the largest nodal
    elastic displacement as ``AUTO_FRACTION`` of the structure's size, and 1 when it is
    visible as it is (at least that fraction, a large deflection) or nothing deforms."""
    if magnification is None:
        largest = float(np.abs(elastic.reshape(-1, 6)[:, :3]).max()) if elastic.size else 0.0
        if largest <= 0:
            return 1.0
        return max(1.0, AUTO_FRACTION * structure_size(structure) / largest)
    if not (
        isinstance(magnification, (int, float)) and np.isfinite(magnification) and magnification > 0
    ):
        raise ValueError(f"magnification must be a positive number, got {magnification!r}")
    return float(magnification)


def beam_samples(
    structure: Structure,
    q: np.ndarray,
    rigid: np.ndarray,
    section_forces: Sequence[InternalForces] | None = None,
) -> list[tuple[np.ndarray, ...]]:
    """Per beam, at the ends of ``SAMPLES_PER_ELEMENT`` chords per element (each point
    once, element vertices among them): reference points (n, 3), the displacement (n, 3)
    and its rigid part (n, 3) (``q`` and its rigid part ``rigid`` interpolated as the beam
    interpolates them), and the bending-moment magnitude (n,) (of ``section_forces`` when
    given)."""
    out: list[tuple[np.ndarray, ...]] = []
    X = np.arange(SAMPLES_PER_ELEMENT) / SAMPLES_PER_ELEMENT
    for b, (beam, dofs) in enumerate(zip(structure.beams, structure.dof_maps, strict=True)):
        mesh, q_beam = beam.mesh, q[dofs]
        e = np.append(np.repeat(np.arange(mesh.n_elements), len(X)), mesh.n_elements - 1)
        Xe = np.append(np.tile(X, mesh.n_elements), 1.0)
        xi = mesh.abscissae(e, Xe)
        forces = beam.internal_forces(q_beam) if section_forces is None else section_forces[b]
        bending = np.linalg.norm(forces.moment[:, 1:], axis=1)
        out.append(
            (
                mesh.positions(e, Xe),
                beam.displacements(q_beam, xi)[:, :3],
                beam.displacements(rigid[dofs], xi)[:, :3],
                np.interp(xi, forces.xi, bending),
            )
        )
    return out


@dataclass(frozen=True)
class Drawing:
    """Where a picture draws everything, ``X + u_R + m (u - u_R)`` (module docstring):
    ``beams``, per beam the sample points of :func:`beam_samples` and their bending moment;
    ``ghosts``, the same points undeformed, ``X + u_R``; ``sliders``, the contact points
    (k, 3); ``bodies``, the body nodes (k, 3) (not the tyres' wheels); ``wheels``, the
    tyres' wheels on their drawn axles; ``grounds``, the tyres' ground (empty until
    :func:`with_grounds`); ``rails``, the points of each rigid line the sliders run on;
    ``springs``, the drawn end points (2, 3) of each axial force element."""

    beams: list[tuple[np.ndarray, np.ndarray]]
    ghosts: list[np.ndarray]
    sliders: np.ndarray
    bodies: np.ndarray
    wheels: list[Wheel] = field(default_factory=list)
    grounds: list[Ground] = field(default_factory=list)
    #: The displacement taken off every point (``follow``), zero without it.
    shift: np.ndarray = field(default_factory=lambda: np.zeros(3))
    rails: list[np.ndarray] = field(default_factory=list)
    springs: list[np.ndarray] = field(default_factory=list)

    def points(self) -> np.ndarray:
        """Every drawn centre point (beams, sliders, bodies, wheel centres, rigid lines,
        force elements' ends), (n, 3)."""
        return np.vstack(
            [p for p, _ in self.beams]
            + [self.sliders, self.bodies, np.zeros((0, 3))]
            + [w.centre[None] for w in self.wheels]
            + self.rails
            + self.springs
        )


def place(X: np.ndarray, u: np.ndarray, u_rigid: np.ndarray, scale: float) -> np.ndarray:
    """The drawn point ``X + u_R + scale (u - u_R)``."""
    return X + u_rigid + scale * (u - u_rigid)


def drawing(
    structure: Structure,
    q: np.ndarray,
    sliders: Sequence[Slider],
    unknowns: Sequence[np.ndarray],
    rigid: np.ndarray,
    scale: float,
    forces: Sequence[ForceElement] = (),
    follow: NodeRef | None = None,
    section_forces: Sequence[InternalForces] | None = None,
) -> Drawing:
    """The :class:`Drawing` of the state ``q`` with rigid part ``rigid``, the elastic part
    magnified ``scale`` times; the tyres among ``forces`` as wheels; relative to the node
    ``follow`` when given; the beams coloured by ``section_forces`` when given (else the
    linear map of ``q``)."""
    shift = np.zeros(3)
    if follow is not None:
        dofs = structure.node_dofs(follow)[:3]
        shift = place(np.zeros(3), q[dofs], rigid[dofs], scale)
    samples = beam_samples(structure, q, rigid, section_forces)
    contact = []
    for slider, y in zip(sliders, unknowns, strict=True):
        x, u = contact_point(slider, q, y)
        contact.append(place(x, u, contact_point(slider, rigid, y)[1], scale) - shift)
    wheels = tyres(forces)
    hidden = {structure.node_dofs(t.wheel)[0] for t in wheels}
    bodies, drawn_wheels = [], []
    for body in structure.bodies:
        dofs = structure.node_dofs(body.name)[:3]
        if dofs[0] not in hidden:
            bodies.append(place(body.position, q[dofs], rigid[dofs], scale) - shift)

    def node(ref: NodeRef) -> np.ndarray:
        dofs = structure.node_dofs(ref)[:3]
        return place(structure.node_position(ref), q[dofs], rigid[dofs], scale) - shift

    for tyre in wheels:
        drawn_wheels.append(wheel(tyre, structure, q, node(tyre.axle), shift))
    return Drawing(
        [(place(X, u, u_R, scale) - shift, bending) for X, u, u_R, bending in samples],
        [X + u_R - shift for X, _, u_R, _ in samples],
        np.array(contact).reshape(-1, 3),
        np.array(bodies).reshape(-1, 3),
        drawn_wheels,
        [],
        shift,
        [line_points(line) - shift for line in rigid_lines(sliders)],
        [np.stack([node(f.a), node(f.b)]) for f in axial_forces(forces)],
    )


def polyline(pv, points: np.ndarray):
    """One pyvista polyline through ``points`` (a tube along it has no inner caps)."""
    return pv.PolyData(points, lines=np.concatenate([[len(points)], np.arange(len(points))]))


@dataclass(frozen=True)
class Style:
    """What stays the same in every frame of a picture: the tube ``sizes``, the
    magnification ``scale``, the colour range ``clim`` of the bending moment, the ``view``
    and the ``camera``, the ``window_size`` and whether the ``scalar_bar`` shows, and
    whether displacements are split (``held`` given: the rigid part at true size)."""

    sizes: TubeSizes
    scale: float
    clim: tuple[float, float]
    view: str
    camera: Camera
    window_size: tuple[int, int]
    scalar_bar: bool
    split: bool


@dataclass(frozen=True)
class Options:
    """How to draw: ``view`` (``auto``, ``xy``, ``xz``, ``yz``, ``iso``:
    :mod:`sliders.app.view`), ``magnification`` (None: automatic), ``radius`` (None: each
    beam's section size, :mod:`sliders.app.shapes`; or one value, or one per beam),
    ``follow`` (a node everything is drawn relative to), ``window_size`` (width, height in
    pixels), ``scalar_bar`` (the colour bar of the bending moment)."""

    view: str = "auto"
    magnification: float | None = None
    radius: float | Sequence[float] | None = None
    follow: NodeRef | None = None
    window_size: tuple[int, int] = (1200, 800)
    scalar_bar: bool = True

    @classmethod
    def of(cls, spec: RenderSpec) -> Options:
        """The options a scene's ``[output.render]`` asks for."""
        return cls(spec.view, spec.magnification, None, spec.follow, spec.window)


def _sizes(frame: Frame, radius: float | Sequence[float] | None) -> TubeSizes:
    structure = frame.structure
    if radius is None:
        return tube_sizes(structure, frame.sliders, structure_size(structure))
    radii, marker = tube_radii(structure, radius)
    return TubeSizes(radii, np.zeros(len(radii), dtype=bool), marker)


def _bounds(drawings: Sequence[Drawing], sizes: TubeSizes) -> np.ndarray:
    """The corners (8, 3) of the box holding everything the drawings draw, with the tubes'
    and markers' sizes around their points."""
    pad = max(CUBE_FACTOR * sizes.marker, SPHERE_FACTOR * sizes.marker)
    low, high = np.full(3, np.inf), np.full(3, -np.inf)
    for d in drawings:
        parts = [d.points() - pad, d.points() + pad]
        parts += [w.centre[None] + s * w.radius for w in d.wheels for s in (-1, 1)]
        parts += [g.corners() for g in d.grounds]
        stacked = np.vstack(parts)
        low, high = np.minimum(low, stacked.min(axis=0)), np.maximum(high, stacked.max(axis=0))
    corners = np.stack([low, high])
    return np.array(
        [[corners[i, 0], corners[j, 1], corners[k, 2]] for i, j, k in np.ndindex(2, 2, 2)]
    )


def with_grounds(
    drawings: Sequence[Drawing], frame: Frame, forces: Sequence[ForceElement]
) -> list[Drawing]:
    """The ``drawings`` with the ground of each tyre, under everything any of them draws."""
    points = np.vstack([d.points() for d in drawings])
    size = structure_size(frame.structure)
    out = []
    for d in drawings:
        grounds = [ground_under(t, points, size, d.shift) for t in tyres(forces)]
        out.append(replace(d, grounds=grounds))
    return out


def prepare(
    frames: Sequence[Frame], forces: Sequence[ForceElement], options: Options
) -> tuple[Style, list[Drawing]]:
    """The :class:`Style` fitted to all ``frames`` and their :class:`Drawing`\\ s: one
    magnification, colour range, view and camera for all."""
    if not frames:
        raise ValueError("there are no frames to draw")
    check_view(options.view)
    first = frames[0]
    checked = [check_solution(f.structure, f.q, f.sliders, f.unknowns) for f in frames]
    sizes = _sizes(first, options.radius)
    rigids = [
        rigid_part(f.structure, q, f.sliders, ys, f.held)
        for f, (q, ys) in zip(frames, checked, strict=True)
    ]
    elastic = np.concatenate([q - r for (q, _), r in zip(checked, rigids, strict=True)])
    scale = magnification_for(first.structure, elastic, options.magnification)
    if options.follow is not None:
        first.structure.node_dofs(options.follow)  # ValueError naming an unknown node
    drawings = [
        drawing(f.structure, q, f.sliders, ys, r, scale, forces, options.follow, f.section_forces)
        for f, (q, ys), r in zip(frames, checked, rigids, strict=True)
    ]
    view = options.view
    if view == "auto":
        view = choose_view(np.vstack([d.points() for d in drawings]))
    drawings = with_grounds(drawings, first, forces)
    bending = [float(b.max()) for d in drawings for _, b in d.beams if len(b)]
    clim = (0.0, max(bending + [1e-300]))
    camera = fit_camera(_bounds(drawings, sizes), view, options.window_size)
    style = Style(
        sizes,
        scale,
        clim,
        view,
        camera,
        options.window_size,
        options.scalar_bar,
        first.held is not None,
    )
    return style, drawings


class Canvas:
    """An off-screen pyvista plotter drawing one :class:`Drawing` after another in one
    :class:`Style`: the camera, the colour bar and the magnification note are set once, the
    parts and the title each frame (:meth:`show`)."""

    def __init__(self, style: Style) -> None:
        headless_defaults()
        import pyvista as pv

        self.pv, self.style = pv, style
        self.plotter = pv.Plotter(off_screen=True, window_size=list(style.window_size))
        self.actors: list[Any] = []
        self.bar_added = False
        plotter = self.plotter
        plotter.set_background("white")
        width, height = style.window_size
        what = "elastic displacements" if style.split else "displacements"
        note = pv.Text(f"{what} x {style.scale:.3g}, view {style.view}", position=(10, 8))
        note.prop.font_size, note.prop.color = max(8, round(16 * width / 1200)), "black"
        plotter.add_actor(note)
        self.title = pv.Text("", position=(width // 2, height - 10))
        self.title.prop.color = "black"
        self.title.prop.SetJustificationToCentered()
        self.title.prop.SetVerticalJustificationToTop()
        plotter.add_actor(self.title)
        camera, c = plotter.camera, style.camera
        distance = 10.0 * c.parallel_scale
        plotter.camera_position = [c.position(distance), c.focal_point, c.up]
        camera.parallel_projection = True
        camera.parallel_scale = c.parallel_scale

    def show(self, drawn: Drawing, title: str) -> None:
        """Replace the parts by those of ``drawn`` and the title by ``title``."""
        pv, plotter, style = self.pv, self.plotter, self.style
        for actor in self.actors:
            plotter.remove_actor(actor, render=False)
        self.actors = []
        sizes = style.sizes
        for k, (ghost, (points, bending), r, outer) in enumerate(
            zip(drawn.ghosts, drawn.beams, sizes.radii, sizes.translucent, strict=True)
        ):
            self._add(
                f"ghost {k}",
                polyline(pv, ghost).tube(radius=r, n_sides=24),
                color="grey",
                opacity=GHOST_OPACITY,
            )
            line = polyline(pv, points)
            line.point_data[BAR_TITLE] = bending
            self._add(
                f"beam {k}",
                line.tube(radius=r, n_sides=24),
                cmap="viridis",
                clim=list(style.clim),
                scalars=BAR_TITLE,
                show_scalar_bar=False,
                opacity=OUTER_OPACITY if outer else 1.0,
            )
            if style.scalar_bar and not self.bar_added:
                self._scalar_bar()
        for k, rail in enumerate(drawn.rails):
            self._add(
                f"rigid line {k}",
                polyline(pv, rail).tube(radius=RAIL_FACTOR * sizes.marker, n_sides=16),
                color="#404040",
            )
        radius = COIL_FACTOR * sizes.marker
        for k, (a, b) in enumerate(drawn.springs):
            self._add(
                f"force element {k}",
                polyline(pv, coil(a, b, radius)).tube(radius=WIRE_FACTOR * radius, n_sides=12),
                color="#e07000",
            )
        if len(drawn.sliders):
            sphere = pv.Sphere(radius=SPHERE_FACTOR * sizes.marker)
            self._add(
                "sliders",
                pv.PolyData(drawn.sliders).glyph(geom=sphere, scale=False, orient=False),
                color="red",
            )
        if len(drawn.bodies):
            edge = CUBE_FACTOR * sizes.marker
            cube = pv.Cube(x_length=edge, y_length=edge, z_length=edge)
            self._add(
                "bodies",
                pv.PolyData(drawn.bodies).glyph(geom=cube, scale=False, orient=False),
                color="#333333",
            )
        for k, w in enumerate(drawn.wheels):
            tyre = pv.Cylinder(
                center=w.centre,
                direction=w.axis,
                radius=w.radius,
                height=TYRE_WIDTH * w.radius,
                resolution=90,
            ).clip(normal=w.normal, origin=w.ground, invert=False)
            hub = pv.Cylinder(
                center=w.centre,
                direction=w.axis,
                radius=HUB_FACTOR * w.radius,
                height=HUB_WIDTH * w.radius,
                resolution=60,
            )
            mark = pv.Cylinder(
                center=w.mark(), direction=w.axis, radius=0.08 * w.radius, height=w.radius
            )
            self._add(f"tyre {k}", tyre, color="#202020")
            self._add(f"hub {k}", hub, color="#b0b0b0")
            self._add(f"spin mark {k}", mark, color="white")
        for k, g in enumerate(drawn.grounds):
            across = np.cross(g.normal, g.forward)
            box = pv.Box(bounds=(-0.5, 0.5, -0.5, 0.5, -1.0, 0.0))
            box.points = (
                g.centre
                + np.outer(box.points[:, 0] * g.length, g.forward)
                + np.outer(box.points[:, 1] * g.width, across)
                + np.outer(box.points[:, 2] * g.thickness, g.normal)
            )
            self._add(f"ground {k}", box, color="#c8b48c")
        self._title(title)
        plotter.renderer.ResetCameraClippingRange()

    def _add(self, name: str, mesh, **kwargs) -> None:
        """Add ``mesh`` as the actor ``name`` (one of :data:`ACTORS`)."""
        self.actors.append(self.plotter.add_mesh(mesh, name=name, reset_camera=False, **kwargs))

    def parts(self) -> list[str]:
        """The names of the parts drawn now (:data:`ACTORS`), in drawing order."""
        return [a.name for a in self.actors]

    def _scalar_bar(self) -> None:
        left, bottom, width, height = BAR_BOX
        bar = self.plotter.add_scalar_bar(
            BAR_TITLE.replace(" [", "\n["),
            mapper=self.actors[-1].mapper,
            vertical=True,
            position_x=left,
            position_y=bottom,
            width=width,
            height=height,
            fmt="%.3g",
            color="black",
            title_font_size=self._font(BAR_FONT[0]),
            label_font_size=self._font(BAR_FONT[1]),
            n_labels=6,
        )
        # the top label reaches half its height above the bar: the title clears it
        bar.SetVerticalTitleSeparation(self._font(BAR_FONT[1]))
        self.bar_added = True

    def _font(self, size: int) -> int:
        """A font size for a 1200 pixels wide window, scaled to this window's width (at
        least 8)."""
        return max(8, round(size * self.style.window_size[0] / 1200))

    def _title(self, title: str) -> None:
        """Set the title at the largest font (up to :data:`TITLE_FONT`) whose width is at
        most :data:`TITLE_WIDTH` of the window's."""
        self.title.input = title
        width = self.style.window_size[0]
        size = TITLE_FONT
        while size > 6:
            self.title.prop.font_size = size
            if self.title_box()[1] - self.title_box()[0] <= TITLE_WIDTH * width:
                break
            size -= 1

    def title_box(self) -> tuple[float, float, float, float]:
        """The title's box in pixels: x0, x1, y0, y1."""
        box = [0.0] * 4
        self.title.GetBoundingBox(self.plotter.renderer, box)
        return (box[0], box[1], box[2], box[3])

    def screenshot(self, path: Path) -> None:
        self.plotter.screenshot(str(path))

    def close(self) -> None:
        self.plotter.close()


def render(
    path: str | Path,
    structure: Structure,
    q: np.ndarray,
    sliders: Sequence[Slider] = (),
    unknowns: Sequence[np.ndarray] = (),
    magnification: float | None = None,
    title: str = "",
    radius: float | Sequence[float] | None = None,
    view: str = "auto",
    window_size: tuple[int, int] = (1200, 800),
    scalar_bar: bool = True,
    held: ArrayLike | None = None,
    forces: Sequence[ForceElement] = (),
    follow: NodeRef | None = None,
    section_forces: Sequence[InternalForces] | None = None,
) -> float:
    """Render the deformed configuration to the PNG file ``path`` (atomically).

    Parameters
    ----------
    path
        Output ``.png``.
    structure, q, sliders, unknowns
        As :func:`sliders.app.vtu.to_meshio`.
    magnification, radius, view, window_size, scalar_bar, follow
        As :class:`Options`.
    title
        Text at the top of the image.
    held
        The global dofs the supports and dof drives hold, for the rigid part of the motion
        (:func:`sliders.app.vtu.rigid_part`); ``None``: no rigid part, the whole
        displacement magnified.
    forces
        The force elements: their tyres are drawn as wheels on their ground.
    section_forces
        Each beam's section forces, for the colours, when they are not the linear map of
        ``q`` (exact kinematics; :class:`sliders.app.vtu.Frame`).

    Returns
    -------
    float
        The magnification used (also written in the image).
    """
    path = Path(path)
    if path.suffix != ".png":
        raise ValueError(f"path {str(path)!r} must end in .png")
    options = Options(view, magnification, radius, follow, window_size, scalar_bar)
    frame = Frame(0.0, structure, q, sliders, unknowns, held, section_forces)
    style, (drawn,) = prepare([frame], forces, options)
    canvas = Canvas(style)
    try:
        canvas.show(drawn, title)
        write_atomic(path, canvas.screenshot)
    finally:
        canvas.close()
    return style.scale


def render_frame(
    path: str | Path,
    frame: Frame,
    title: str,
    forces: Sequence[ForceElement] = (),
    options: Options = Options(),
) -> float:
    """:func:`render` of ``frame`` (its state and held dofs) with the view, magnification,
    window and followed node of ``options``; returns the magnification used."""
    return render(
        path,
        frame.structure,
        frame.q,
        frame.sliders,
        frame.unknowns,
        options.magnification,
        title,
        view=options.view,
        window_size=options.window_size,
        held=frame.held,
        forces=forces,
        follow=options.follow,
        section_forces=frame.section_forces,
    )


@dataclass
class Animation:
    """What :func:`animate` drew: the ``style`` and, per frame as the plotter had them when
    the frame was written, the ``cameras`` (position, focal point, up, parallel scale), the
    colour ``ranges`` of every coloured part and the ``titles``."""

    style: Style
    cameras: list[tuple] = field(default_factory=list)
    ranges: list[list[tuple[float, float]]] = field(default_factory=list)
    titles: list[str] = field(default_factory=list)


def animate(
    path: str | Path,
    frames: Sequence[Frame],
    title: str = "",
    forces: Sequence[ForceElement] = (),
    options: Options = Options(),
    fps: float = FPS,
    progress: bool = False,
) -> Animation:
    """Write ``frames`` as the animation ``path`` (``.mp4`` or ``.gif``, atomically), one
    camera, magnification and colour range over them all, ``"{title}: t = ... s"`` above
    each.

    Parameters
    ----------
    path
        Output ``.mp4`` (H.264 through imageio's ffmpeg) or ``.gif``.
    frames
        The states, in order (:meth:`sliders.app.run_dynamic.DynamicRun.frames`, or
        :meth:`sliders.app.vtu.Frame.of` of each state).
    title
        Text before the time in each frame's title.
    forces
        The force elements: their tyres are drawn as wheels on their ground.
    options
        How to draw (:class:`Options`).
    fps
        Frames per second.
    progress
        A progress bar of the frames (on a terminal).
    """
    from tqdm.auto import tqdm

    path = Path(path)
    kind = path.suffix.lstrip(".")
    if kind not in FORMATS:
        raise ValueError(f"path {str(path)!r} must end in .mp4 or .gif")
    if not (isinstance(fps, (int, float)) and np.isfinite(fps) and fps > 0):
        raise ValueError(f"fps must be a positive number, got {fps!r}")
    style, drawings = prepare(frames, forces, options)
    record = Animation(style)

    def write(tmp: Path) -> None:
        canvas = Canvas(style)
        try:
            if kind == "gif":
                canvas.plotter.open_gif(str(tmp), fps=fps)
            else:
                canvas.plotter.open_movie(str(tmp), framerate=fps, quality=7)
            steps = zip(frames, drawings, strict=True)
            for frame, drawn in tqdm(
                steps, total=len(frames), desc="animation", unit="frame", disable=not progress
            ):
                text = f"{title or 'scene'}: t = {frame.time:.4g} s"
                canvas.show(drawn, text)
                canvas.plotter.write_frame()
                camera = canvas.plotter.camera
                record.cameras.append((*canvas.plotter.camera_position, camera.parallel_scale))
                record.ranges.append(
                    [
                        tuple(a.mapper.scalar_range)
                        for a in canvas.actors
                        if a.mapper.scalar_visibility
                    ]
                )
                record.titles.append(text)
        finally:
            canvas.close()

    write_atomic(path, write)
    return record
