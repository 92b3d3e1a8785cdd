"""The view of a picture: which side the model is seen from, and a camera that frames it.

:func:`choose_view` picks the view from the points a picture draws: the coordinate plane
they lie in (``xy``, ``xz`` or ``yz``, looked at square on), or ``iso`` when they span
all three axes.  An axis counts as flat when the points' extent along it is at most
:data:`FLAT` of their largest extent (a tenth of a percent: not visible in a picture).
A straight line along one axis lies in two planes: along ``z`` it is seen from the side
(``xz``, ``z`` up), along ``x`` or ``y`` from above (``xy``).

:func:`fit_camera` frames given points in a parallel projection (lengths in the image are
proportional to lengths in the model) inside the part of the window :data:`MODEL_REGION`
leaves to the model: the colour bar on the right, the title above and the magnification
below never overlap it.  One camera fitted to every frame of an animation stays fixed.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: The views: the direction of projection (from the camera to the model) and the up direction.
DIRECTIONS: dict[str, tuple[tuple[float, float, float], tuple[float, float, float]]] = {
    "xy": ((0.0, 0.0, -1.0), (0.0, 1.0, 0.0)),
    "xz": ((0.0, 1.0, 0.0), (0.0, 0.0, 1.0)),
    "yz": ((-1.0, 0.0, 0.0), (0.0, 0.0, 1.0)),
    "iso": ((-1.0, 1.0, -1.0), (0.0, 0.0, 1.0)),
}
VIEWS = ("auto", *DIRECTIONS)
#: Relative extent below which an axis counts as flat (module docstring).
FLAT = 1e-3
#: The part of the window the model is fitted in: (left, bottom, right, top), fractions.
MODEL_REGION = (0.04, 0.09, 0.78, 0.88)
#: The plane normal to each flat axis.
PLANE_OF_FLAT_AXIS = {0: "yz", 1: "xz", 2: "xy"}


def check_view(view: str) -> str:
    """``view`` if it is one of :data:`VIEWS`, else ``ValueError`` naming them."""
    if view not in VIEWS:
        raise ValueError(f"view must be one of {', '.join(VIEWS)}, got {view!r}")
    return view


def choose_view(points: np.ndarray) -> str:
    """The view of ``points`` (n, 3) (module docstring): the plane they lie in, ``iso``
    when they span three dimensions."""
    points = np.asarray(points, dtype=float).reshape(-1, 3)
    extent = np.ptp(points, axis=0) if len(points) else np.zeros(3)
    largest = float(extent.max())
    flat = np.flatnonzero(extent <= FLAT * largest) if largest > 0 else np.arange(3)
    if len(flat) == 0:
        return "iso"
    if len(flat) == 1:
        return PLANE_OF_FLAT_AXIS[int(flat[0])]
    if len(flat) == 2 and 2 not in flat:
        return "xz"  # a line along z, seen from the side
    return "xy"


@dataclass(frozen=True)
class Camera:
    """A parallel-projection camera: it looks along ``direction`` at ``focal_point`` with
    ``up`` pointing up; ``parallel_scale`` is half the window's height in model units."""

    focal_point: tuple[float, float, float]
    direction: tuple[float, float, float]
    up: tuple[float, float, float]
    parallel_scale: float

    def position(self, distance: float) -> tuple[float, float, float]:
        """The camera's place, ``distance`` back from the focal point."""
        return tuple(np.asarray(self.focal_point) - distance * np.asarray(self.direction))


def screen_axes(view: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Unit direction of projection ``d``, image right ``r = d x up`` and image up ``u``
    of the view (``xy``, ``xz``, ``yz``, ``iso``)."""
    d, up = (np.asarray(v, dtype=float) for v in DIRECTIONS[view])
    d = d / np.linalg.norm(d)
    r = np.cross(d, up)
    r /= np.linalg.norm(r)
    return d, r, np.cross(r, d)


def fit_camera(
    points: np.ndarray,
    view: str,
    window_size: tuple[int, int],
    region: tuple[float, float, float, float] = MODEL_REGION,
) -> Camera:
    """The camera of ``view`` (not ``auto``) that fits ``points`` (n, 3) into ``region``
    (fractions of the window: left, bottom, right, top) of a window of ``window_size``
    pixels (width, height), centred in it, at one scale for both image axes."""
    d, r, u = screen_axes(view)
    points = np.asarray(points, dtype=float).reshape(-1, 3)
    a, b, depth = points @ r, points @ u, points @ d
    width, height = window_size
    aspect = width / height
    left, bottom, right, top = region
    span_a, span_b = float(np.ptp(a)), float(np.ptp(b))
    scale = max(span_a / (2 * aspect * (right - left)), span_b / (2 * (top - bottom)))
    if scale <= 0:
        scale = max(float(np.abs(points).max()), 1.0)
    # the region's centre at the centre of the points' projection
    centre_a = 0.5 * (a.min() + a.max()) + (0.5 - 0.5 * (left + right)) * 2 * aspect * scale
    centre_b = 0.5 * (b.min() + b.max()) + (0.5 - 0.5 * (bottom + top)) * 2 * scale
    focal = centre_a * r + centre_b * u + 0.5 * (depth.min() + depth.max()) * d
    return Camera(tuple(focal), tuple(d), tuple(u), float(scale))
