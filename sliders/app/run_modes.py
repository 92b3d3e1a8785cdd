"""A modes study: the modes about the static state of every sample, followed along a sweep.

:func:`modes_of` takes the samples of a run (:func:`sliders.app.run.run`: the scene as
written, or every point of the sweep) and solves the modes about each converged one
(:func:`sliders.solve.modes.modes_about`, one factorisation per sample).  Along a sweep each
mode keeps its number from point to point by its shape: the modes of a point are numbered
as those of the previous point they resemble most (:func:`sliders.solve.modes.follow`, the
largest total MAC), so a number names one mode where frequencies cross.  A sample solved
with exact kinematics (:class:`sliders.app.kinematics.ExactSolution`) has its modes about
its exact state, with the geometric stiffness of the preload, and with bodies or joints
those of its exact model, the joints' rows and geometric stiffness
(:class:`sliders.solve.modes.Preload`); a linear one about a loaded state warns that it is
left out.

Outputs (:func:`write_modes`, into the run's new output directory, which replaces the old one
whole): ``modes.csv`` (:data:`MODES_COLUMNS`), the shapes as a VTU
series per sample (``modes_NNNNNN/modes_NNNNNN.pvd``, one state per mode, its number as the
time: ParaView steps through the modes, and Warp By Vector shows each), each mode drawn
over the sample's state (:func:`over_state`: with exact kinematics its rotation increments
composed with the state's rotations) at the scale :func:`mode_scale`, and along a sweep
``campbell.png``, the frequencies against the parameter, one curve per mode number (with
matplotlib, the ``plot`` extra); with ``output.animation``, each mode of the first converged
sample as ``mode_NN.mp4`` or ``mode_NN.gif`` (:func:`mode_frames`: one period, one camera,
magnification and colour range; pyvista, the ``render`` extra); with ``output.png``, each
mode of the rendered samples (the last converged, or all) at its peak, over the state, as
``render_NNNNNN_mode_NN.png``.
"""

from __future__ import annotations

import csv
import importlib.util
import warnings
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Protocol

import numpy as np

from fvbeam.rotations import exp_map, log_map
from fvbeam.structure import Structure
from fvbeam.support import complement
from sliders.app.kinematics import ExactSolution
from sliders.app.schema import ModesStudy
from sliders.app.state_tables import cell
from sliders.app.vtu import Frame, structure_size, write_series
from sliders.solve.modes import PRELOAD_WARNING, Preload, StateModes, follow, modes_about
from sliders.solve.statics import SliderSolution, SliderStatics

if TYPE_CHECKING:
    from fvbeam.exact_structure import ExactStructure
    from sliders.joints.exact_model import ExactModel, Joint

#: The columns of ``modes.csv``: a row per converged sample and mode.
MODES_COLUMNS = ("sample", "value", "mode", "frequency_hz", "damping_ratio", "mac")
#: The frames of one period of a mode's animation.
MODE_FRAMES = 24
#: A mode is drawn over its state with its largest translation this part of the
#: structure's size, or its largest rotation this many radians (:func:`mode_scale`): the
#: renders' automatic magnification (:data:`sliders.app.render.AUTO_FRACTION`), so they
#: draw it as it is.
MODE_FRACTION = 0.1
#: What writes an animation: ``(path, frames, title)`` (:func:`sliders.app.render.animate`
#: with the scene's force elements and render options).
Animator = Callable[[Path, Sequence[Frame], str], object]
#: What writes a picture: ``(path, frame, title)`` (:func:`sliders.app.render.render` with
#: the scene's force elements and render options).
Painter = Callable[[Path, Frame, str], object]


class Solved(Protocol):
    """What the modes read of a sample (:class:`sliders.app.run.Sample`)."""

    @property
    def index(self) -> int: ...

    @property
    def value(self) -> float | None: ...

    @property
    def statics(self) -> SliderStatics | None: ...

    @property
    def solution(self) -> SliderSolution | None: ...


@dataclass(frozen=True)
class SampleModes:
    """The modes about one converged sample: ``number`` (k,) each mode's number (from 1,
    followed along a sweep) and ``mac`` (k,) its MAC to the previous sample's mode of that
    number (NaN at the first sample, or for a mode new at this one); or the ``error`` that
    stopped its eigen solve."""

    sample: Solved
    modes: StateModes | None
    number: np.ndarray
    mac: np.ndarray
    error: str | None = None


def modes_of(
    samples: Sequence[Solved],
    study: ModesStudy,
    progress: bool = True,
    joints: Sequence[Joint] = (),
) -> list[SampleModes]:
    """The modes of ``study`` about every converged one of ``samples``, in order (module
    docstring), an exact sample's with the scene's ``joints``
    (:func:`sliders.app.scene_joints.joints`); a tqdm progress bar on a terminal; the
    preload warning (:data:`~sliders.solve.modes.PRELOAD_WARNING`) once for the run."""
    from tqdm import tqdm

    # the exact beams, or exact model, of each structure, built once
    exact: dict[int, ExactStructure | ExactModel] = {}

    def preload(statics: SliderStatics, solution: SliderSolution) -> Preload | None:
        """The preload at an exact sample's state: the exact beams' tangent and mass, with
        bodies or joints their exact model's (:meth:`Preload.of_model`); None for a linear
        sample, or one with sliders on exact lines (their modes take the linear stiffness,
        with the preload warning)."""
        from fvbeam.exact_structure import ExactStructure
        from sliders.joints.exact_model import ExactModel, JointedState
        from sliders.joints.exact_slider_model import SlidingState

        if not isinstance(solution, ExactSolution) or isinstance(solution.state, SlidingState):
            return None
        structure = statics.structure
        state = solution.state
        if isinstance(state, JointedState):
            model = exact.get(id(structure))
            if not isinstance(model, ExactModel):
                model = exact[id(structure)] = ExactModel.on(structure, joints, "scene", "joint")
            return Preload.of_model(model, state, study.mass)
        beams = exact.get(id(structure))
        if not isinstance(beams, ExactStructure):
            beams = exact[id(structure)] = ExactStructure(structure)
        return Preload.at(beams, state, study.mass)

    out: list[SampleModes] = []
    previous: np.ndarray | None = None  # the last shapes, one column per mode number
    loaded = False
    samples = [s for s in samples if s.solution is not None]
    for sample in tqdm(samples, disable=None if progress else True, desc="modes"):
        assert sample.statics is not None and sample.solution is not None
        try:
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                modes = modes_about(
                    sample.statics,
                    sample.solution,
                    study.count,
                    mass=study.mass,
                    damping=study.damping,
                    window=study.window,
                    preload=preload(sample.statics, sample.solution),
                )
            loaded = loaded or any(PRELOAD_WARNING in str(w.message) for w in caught)
        except ValueError as exc:
            out.append(SampleModes(sample, None, np.zeros(0, int), np.zeros(0), str(exc)))
            continue
        k = len(modes.omega)
        if previous is None:
            number, mac = np.arange(k), np.full(k, np.nan)
        else:
            number, mac = follow(previous, modes.shapes)
        out.append(SampleModes(sample, modes, number + 1, mac))
        width = max(number.max() + 1 if k else 0, 0 if previous is None else previous.shape[1])
        shapes = np.zeros((modes.shapes.shape[0], width), dtype=modes.shapes.dtype)
        if previous is not None:  # a number missing here keeps its last shape
            shapes[:, : previous.shape[1]] = previous
        shapes[:, number] = modes.shapes
        previous = shapes
    if loaded:
        warnings.warn(PRELOAD_WARNING, UserWarning, stacklevel=2)
    return out


def _rows(found: list[SampleModes]) -> Iterator[list[str]]:
    for entry in found:
        if entry.modes is None:
            continue
        order = np.argsort(entry.number)
        for j in order:
            yield [
                cell(v)
                for v in (
                    entry.sample.index,
                    entry.sample.value,
                    int(entry.number[j]),
                    float(entry.modes.hertz[j]),
                    float(entry.modes.damping_ratio[j]),
                    None if np.isnan(entry.mac[j]) else float(entry.mac[j]),
                )
            ]


def write_modes(
    found: list[SampleModes],
    directory: Path,
    table: bool,
    sweep: bool,
    animation: tuple[str, Animator] | None = None,
    pictures: tuple[set[int], Painter] | None = None,
) -> None:
    """Write ``modes.csv`` (when ``table``), the shapes' VTU series, for a ``sweep``
    ``campbell.png``, with ``animation`` (its format, ``mp4`` or ``gif``, and what
    writes it) each mode of the first converged sample animated, and with ``pictures``
    (the indices of the samples to render and what renders) each of their modes at its
    peak, into ``directory`` (module docstring)."""
    if table:
        with open(directory / "modes.csv", "w", newline="") as handle:
            writer = csv.writer(handle)
            writer.writerow(MODES_COLUMNS)
            writer.writerows(_rows(found))
    for entry in found:
        if entry.modes is not None and len(entry.number):
            series = directory / f"modes_{entry.sample.index:06d}"
            write_series(series, _frames(entry))
    if sweep and importlib.util.find_spec("matplotlib") is not None:
        _campbell(found, directory / "campbell.png")
    solved = [entry for entry in found if entry.modes is not None and len(entry.number)]
    if animation is not None and solved:
        kind, animate = animation
        entry = solved[0]
        assert entry.modes is not None
        for j in np.argsort(entry.number):
            number, hertz = int(entry.number[j]), float(entry.modes.hertz[j])
            title = f"mode {number} ({hertz:.4g} Hz)"
            animate(directory / f"mode_{number:02d}.{kind}", mode_frames(entry, j), title)
    if pictures is not None:
        indices, paint = pictures
        for entry in solved:
            if entry.sample.index not in indices:
                continue
            assert entry.modes is not None
            for j in np.argsort(entry.number):
                number, hertz = int(entry.number[j]), float(entry.modes.hertz[j])
                name = f"render_{entry.sample.index:06d}_mode_{number:02d}.png"
                paint(
                    directory / name, mode_frames(entry, j, 1)[0], f"mode {number} ({hertz:.4g} Hz)"
                )


def mode_scale(structure: Structure, shape: np.ndarray) -> float:
    """The factor drawing a mode ``shape`` (its dofs, real or complex) at
    :data:`MODE_FRACTION`: its largest nodal translation that part of the structure's size
    (:func:`sliders.app.vtu.structure_size`), or its largest rotation that many radians,
    whichever is reached first; 1 for a zero shape."""
    d = np.abs(shape).reshape(-1, 6)
    size = structure_size(structure)
    largest = max(
        float(d[:, :3].max(initial=0.0)) / size if size > 0 else 0.0,
        float(d[:, 3:].max(initial=0.0)),
    )
    return MODE_FRACTION / largest if largest > 0 else 1.0


def over_state(solution: SliderSolution, increment: np.ndarray) -> np.ndarray:
    """The displacement (the structure's dofs) of the sample's state moved by the mode's
    ``increment`` (real, its dofs): with exact kinematics
    (:class:`~sliders.app.kinematics.ExactSolution`) each node at ``x + du`` turned to
    ``exp(dphi) R`` (the rotation increment a spatial rotation vector composed with the
    state's rotation ``R``; written as the rotation vector ``log(exp(dphi) R)``), else
    the linear state's ``q + increment``."""
    q = solution.q + increment
    if isinstance(solution, ExactSolution):
        d = q.reshape(-1, 6)
        d[:, 3:] = log_map(exp_map(increment.reshape(-1, 6)[:, 3:]) @ solution.state.R)
    return q


def mode_frames(entry: SampleModes, j: int, count: int = MODE_FRAMES) -> list[Frame]:
    """One period of mode ``j`` (its column) over the sample's state in ``count`` frames:
    the state moved by ``a Re(phi e^{i 2 pi k / count})`` (:func:`over_state`) at ``t = k /
    (count f)``, ``phi`` the shape, ``a`` its :func:`mode_scale` and ``f`` its frequency (a
    real mode swings as ``phi cos``; a damped, complex one shows the phases of its parts),
    the sliders at their abscissae."""
    statics, solution, modes = entry.sample.statics, entry.sample.solution, entry.modes
    assert statics is not None and solution is not None and modes is not None
    held = complement(statics.structure.n_dofs, statics.free)
    shape, hertz = modes.shapes[:, j], float(modes.hertz[j])
    scale = mode_scale(statics.structure, shape)
    period = 1.0 / hertz if hertz > 0 else 1.0
    return [
        Frame(
            k * period / count,
            statics.structure,
            over_state(solution, scale * (shape * np.exp(2j * np.pi * k / count)).real),
            statics.sliders,
            solution.unknowns,
            held,
        )
        for k in range(count)
    ]


def _frames(entry: SampleModes) -> Iterator[Frame]:
    """One state per mode, by number: the sample's state moved by the shape's real part at
    its :func:`mode_scale` (:func:`over_state`; sliders at their abscissae)."""
    statics, solution, modes = entry.sample.statics, entry.sample.solution, entry.modes
    assert statics is not None and solution is not None and modes is not None
    held = complement(statics.structure.n_dofs, statics.free)
    for j in np.argsort(entry.number):
        shape = modes.shapes[:, j]
        yield Frame(
            float(entry.number[j]),
            statics.structure,
            over_state(solution, mode_scale(statics.structure, shape) * shape.real),
            statics.sliders,
            solution.unknowns,
            held,
        )


def _campbell(found: list[SampleModes], path: Path) -> None:
    """The frequencies against the sweep's parameter, one line per mode number, as a PNG at
    ``path`` (inside the run's new output directory, which replaces the old one whole)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    curves: dict[int, list[tuple[float, float]]] = {}
    for entry in found:
        if entry.modes is None:
            continue
        for n, f in zip(entry.number, entry.modes.hertz, strict=True):
            curves.setdefault(int(n), []).append((float(entry.sample.value or 0.0), float(f)))
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for n, points in sorted(curves.items()):
        x, y = np.array(points).T
        ax.plot(x, y, marker=".", label=f"mode {n}")
    ax.set_xlabel("parameter")
    ax.set_ylabel("frequency (Hz)")
    ax.legend(fontsize="small", ncol=2)
    ax.grid(True, alpha=0.3)
    fig.savefig(path, dpi=120, bbox_inches="tight")
    plt.close(fig)
