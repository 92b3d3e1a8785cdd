"""Off-screen pyvista render of a deformed structure with its sliders.

The deformed beams are drawn as a tube coloured by the bending-moment magnitude
``|(M2, M3)|`` (section axes), interpolated linearly in ``xi`` between the beam's recovery
points (held constant beyond the first and last); the undeformed beams, carried by their
rigid motion, as a translucent grey tube; sliders as red spheres at their contact points on
the deformed lines; rigid bodies as dark cubes.

Every point is drawn at ``X + u_R + m (u - u_R)``: its reference position, the rigid part
``u_R`` of its displacement at true size and the elastic part magnified ``m`` times (the
factor is shown in the image).  Given the held dofs, ``u_R`` is the rigid motion of
:func:`sliders.app.motion.rigid_motion` (a body's travel along its line, a drive's motion),
so sliding bodies and driven parts stay at their true places, on their magnified lines;
without them it is zero and the whole displacement is magnified.

pyvista is imported only when a render is made.  Without a display, VTK renders through EGL
(Mesa's software rasteriser; the Makefile installs Debian's ``libegl1 libegl-mesa0
libgl1-mesa-dri``): :func:`render` then sets ``VTK_DEFAULT_OPENGL_WINDOW`` to
``vtkEGLRenderWindow`` unless it is set already, which skips VTK's failing attempt at X11.
"""

from __future__ import annotations

import ctypes.util
import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from fvbeam.io import write_atomic
from fvbeam.structure import Structure
from sliders.app.state_tables import contact_point
from sliders.app.vtu import check_solution, rigid_part, structure_size, tube_radii
from sliders.joints.slider import Slider

#: Samples per element along the tube (a 3-node element is a parabola; 8 chords keep
#: its sag below 1/256 of the element's bow, invisible at tube scale).
SAMPLES_PER_ELEMENT = 8
#: Automatic magnification: the largest displacement drawn as this fraction of the
#: structure's size.
AUTO_FRACTION = 0.1
VIEWS = ("xy", "xz", "yz", "iso")
#: Marker sizes relative to the tube radius.
SPHERE_FACTOR, CUBE_FACTOR = 2.5, 3.0
BAR_TITLE = "bending moment [N m]"
#: The demo's tube radii (cylinder, piston) per unit structure size: the piston thinner,
#: inside the cylinder, so that the coincident stretch of the two beams does not flicker.
DEMO_RADII = np.array([0.012, 0.007])


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
    elastic displacement as ``AUTO_FRACTION`` of the structure's size (1 when nothing
    deforms)."""
    if magnification is None:
        largest = float(np.abs(elastic.reshape(-1, 6)[:, :3]).max()) if elastic.size else 0.0
        return AUTO_FRACTION * structure_size(structure) / largest if largest > 0 else 1.0
    if not (
        isinstance(magnification, (int, float)) and np.isfinite(magnification) and magnification > 0
    ):
        raise ValueError(f"magnification must be a positive number, got {magnification!r}")
    return float(magnification)


def beam_samples(
    structure: Structure, q: np.ndarray, rigid: np.ndarray
) -> list[tuple[np.ndarray, ...]]:
    """Per beam, at the ends of ``SAMPLES_PER_ELEMENT`` chords per element (each point
    once, element vertices among them): reference points (n, 3), the displacement (n, 3)
    and its rigid part (n, 3) (``q`` and its rigid part ``rigid`` interpolated as the beam
    interpolates them), and the bending-moment magnitude (n,)."""
    out: list[tuple[np.ndarray, ...]] = []
    X = np.arange(SAMPLES_PER_ELEMENT) / SAMPLES_PER_ELEMENT
    for beam, dofs in zip(structure.beams, structure.dof_maps, strict=True):
        mesh, q_beam = beam.mesh, q[dofs]
        e = np.append(np.repeat(np.arange(mesh.n_elements), len(X)), mesh.n_elements - 1)
        Xe = np.append(np.tile(X, mesh.n_elements), 1.0)
        xi = mesh.abscissae(e, Xe)
        forces = beam.internal_forces(q_beam)
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
    """Where :func:`render` draws everything, ``X + u_R + m (u - u_R)`` (module
    docstring): ``beams``, per beam the sample points of :func:`beam_samples` and their
    bending moment; ``ghosts``, the same points undeformed, ``X + u_R``; ``sliders``, the
    contact points (k, 3); ``bodies``, the body nodes (k, 3)."""

    beams: list[tuple[np.ndarray, np.ndarray]]
    ghosts: list[np.ndarray]
    sliders: np.ndarray
    bodies: np.ndarray


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
) -> Drawing:
    """The :class:`Drawing` of the state ``q`` with rigid part ``rigid``, the elastic part
    magnified ``scale`` times."""
    samples = beam_samples(structure, q, rigid)
    contact = []
    for slider, y in zip(sliders, unknowns, strict=True):
        x, u = contact_point(slider, q, y)
        contact.append(place(x, u, contact_point(slider, rigid, y)[1], scale))
    bodies = []
    for body in structure.bodies:
        dofs = structure.node_dofs(body.name)[:3]
        bodies.append(place(body.position, q[dofs], rigid[dofs], scale))
    return Drawing(
        [(place(X, u, u_R, scale), bending) for X, u, u_R, bending in samples],
        [X + u_R for X, _, u_R, _ in samples],
        np.array(contact).reshape(-1, 3),
        np.array(bodies).reshape(-1, 3),
    )


def polyline(pv, points: np.ndarray):
    """One pyvista polyline through ``points`` (a tube along it has no inner caps)."""
    return pv.PolyData(points, lines=np.concatenate([[len(points)], np.arange(len(points))]))


def render(
    path: str | Path,
    structure: Structure,
    q: np.ndarray,
    sliders: Sequence[Slider] = (),
    unknowns: Sequence[np.ndarray] = (),
    magnification: float | None = None,
    title: str = "",
    radius: float | Sequence[float] | None = None,
    view: str = "xy",
    window_size: tuple[int, int] = (1200, 600),
    scalar_bar: bool = True,
    held: ArrayLike | None = None,
) -> float:
    """Render the deformed configuration to the PNG file ``path`` (atomically).

    Parameters
    ----------
    path
        Output ``.png``.
    structure, q, sliders, unknowns, radius
        As :func:`sliders.app.vtu.to_meshio` (``radius``: the tube's).
    magnification
        Scale of the elastic displacements; ``None`` for automatic
        (:func:`magnification_for`).
    title
        Text at the top of the image.
    view
        Camera: ``xy``, ``xz``, ``yz`` (looking down the third axis) or ``iso``.
    window_size
        Image width and height in pixels.
    scalar_bar
        Show the colour bar of the bending moment.
    held
        The global dofs the supports and dof drives hold, for the rigid part of the motion
        (:func:`sliders.app.vtu.rigid_part`); ``None``: no rigid part, the whole
        displacement magnified.

    Returns
    -------
    float
        The magnification used (also written in the image).
    """
    path = Path(path)
    if path.suffix != ".png":
        raise ValueError(f"path {str(path)!r} must end in .png")
    if view not in VIEWS:
        raise ValueError(f"view must be one of {', '.join(VIEWS)}, got {view!r}")
    q, ys = check_solution(structure, q, sliders, unknowns)
    radii, marker = tube_radii(structure, radius)
    rigid = rigid_part(structure, q, sliders, ys, held)
    scale = magnification_for(structure, q - rigid, magnification)
    drawn = drawing(structure, q, sliders, ys, rigid, scale)
    headless_defaults()
    import pyvista as pv

    plotter = pv.Plotter(off_screen=True, window_size=list(window_size))
    try:
        plotter.set_background("white")
        if drawn.beams:
            clim = [0.0, max(max(float(b.max()) for _, b in drawn.beams), 1e-300)]
            for ghost, (points, bending), r in zip(drawn.ghosts, drawn.beams, radii, strict=True):
                plotter.add_mesh(
                    polyline(pv, ghost).tube(radius=r, n_sides=24), color="grey", opacity=0.25
                )
                line = polyline(pv, points)
                line.point_data[BAR_TITLE] = bending
                plotter.add_mesh(
                    line.tube(radius=r, n_sides=24),
                    cmap="viridis",
                    clim=clim,
                    scalars=BAR_TITLE,
                    show_scalar_bar=scalar_bar,
                    scalar_bar_args={"color": "black"},
                )
        if len(drawn.sliders):
            plotter.add_mesh(
                pv.PolyData(drawn.sliders).glyph(
                    geom=pv.Sphere(radius=SPHERE_FACTOR * marker), scale=False, orient=False
                ),
                color="red",
            )
        if len(drawn.bodies):
            edge = CUBE_FACTOR * marker
            plotter.add_mesh(
                pv.PolyData(drawn.bodies).glyph(
                    geom=pv.Cube(x_length=edge, y_length=edge, z_length=edge),
                    scale=False,
                    orient=False,
                ),
                color="#333333",
            )
        plotter.add_text(title, position="upper_edge", font_size=14, color="black")
        plotter.add_text(
            f"{'displacements' if held is None else 'elastic displacements'} x {scale:.3g}",
            position="lower_left",
            font_size=10,
            color="black",
        )
        {
            "xy": plotter.view_xy,
            "xz": plotter.view_xz,
            "yz": plotter.view_yz,
            "iso": plotter.view_isometric,
        }[view]()
        write_atomic(path, lambda tmp: plotter.screenshot(str(tmp)))
    finally:
        plotter.close()
    return scale
