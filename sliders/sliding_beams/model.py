"""The sliding-beams setup built once and solved at any piston position (paper Sec. 6).

Cylinder beam C on ``[0, L]`` along x, clamped at 0; piston beam P on ``[s, s + L]``, its
axial translation and its spin about x held at its bottom node (a real strut's gas spring
and torque links; their reactions vanish to first order).  Slider A: P's bottom end node
slides on C.  Slider B: C's top end node slides on P.  A transverse force ``F`` at P's tip.
The paper's values (:data:`PAPER`): ``EJ = 4.1e4 N m^2``, ``GA = 1.1e8 N``, ``L = 0.6 m``;
``EA = 10 GA`` and ``GJ = EJ`` play no role in this bending problem.  The tip stiffness
``k = F / v(s + L)`` normalised by ``EJ / L^3`` is compared with the closed form
(:func:`sliders.sliding_beams.exact.sliding_beams`).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from fvbeam import Beam, Section, Structure, Support, straight
from fvbeam.formulations import formulation as get_formulation
from sliders.joints.slider import Slider
from sliders.lines.chain import BeamChain
from sliders.solve.statics import SliderSolution, SliderStatics, solve_translated

#: The two slider kinds the paper compares on this setup.
KINDS = ("spherical", "classical")
#: The sliders: the beam of the line, its name, the sliding node and the slider's name.
LAYOUT = ((0, "C", (1, "start"), "A"), (1, "P", (0, "end"), "B"))


@dataclass(frozen=True)
class Setup:
    """The tubes' section, the beams' length ``L`` and the tip force ``F``."""

    section: Section
    length: float
    force: float

    @property
    def EJ(self) -> float:
        """Bending stiffness in the plane of the load (``EJz``)."""
        return float(self.section.stiffness[5, 5])

    @property
    def GA(self) -> float:
        """Shear stiffness in the plane of the load (``GAy``)."""
        return float(self.section.stiffness[1, 1])


#: The paper's setup (Sec. 6) with a unit tip force.
PAPER = Setup(
    Section.diagonal(EA=1.1e9, GAy=1.1e8, GAz=1.1e8, GJ=4.1e4, EJy=4.1e4, EJz=4.1e4), 0.6, 1.0
)


class SlidingBeams:
    """The two beams built once; :meth:`stiffness` moves the piston and solves.
    ``smearing`` is a fraction of the element length; ``orientation``: the classical
    sliders' form (:class:`sliders.joints.slider.Slider`).  The piston is the cylinder's beam
    moved (same mesh, section and formulation), so one stiffness is assembled for both."""

    def __init__(
        self,
        formulation: str,
        n_elements: int,
        kind: str,
        smearing: float = 0.0,
        orientation: str = "section",
        setup: Setup = PAPER,
    ) -> None:
        npe = get_formulation(formulation).nodes_per_element
        self.setup = setup
        L = setup.length
        self.cylinder = Beam(
            straight((0, 0, 0), (L, 0, 0), n_elements, npe), setup.section, formulation
        )
        self.kind, self.smearing = kind, smearing * L / n_elements
        self.orientation = orientation if kind == "classical" else "section"
        self.supports = [Support(0, "start"), Support(1, "start", "ux+rx")]
        self._previous: SliderStatics | None = None
        #: The tip load on the structure of :attr:`_previous` and of every structure moved
        #: from it (the same dof numbering).
        self._load = np.zeros(0)
        self.iterations: list[int] = []

    def problem(self, s_over_L: float) -> tuple[SliderStatics, np.ndarray]:
        """The statics (condensed back end) and the tip load with the piston at
        ``s = s_over_L L``; the last position's moved (:meth:`sliders.solve.statics.
        SliderStatics.moved`: its numbering, checked sliders and condensed operator kept,
        and so its tip load)."""
        piston = self.cylinder.translated((s_over_L * self.setup.length, 0, 0))
        previous = self._previous
        if previous is not None:
            self._previous = previous.moved([self.cylinder, piston])
            return self._previous, self._load.copy()
        structure = Structure([self.cylinder, piston])
        self._load = structure.gather(1, piston.nodal_load("end", (0, self.setup.force, 0)))
        sliders = [
            Slider(
                self.kind,
                BeamChain(structure, [k], line),
                body,
                name=name,
                smearing=self.smearing,
                orientation=self.orientation,
            )
            for k, line, body, name in LAYOUT
        ]
        statics = SliderStatics(structure, self.supports, sliders, method="condensed")
        self._previous = statics
        return statics, self._load.copy()

    @cached_property
    def template(self) -> tuple[SliderStatics, np.ndarray]:
        """The problem with the piston on the cylinder (``s = 0``): the statics every
        position's is a translation of (its stiffness assembled and factorised here, once)
        and the tip load; the sliders' batches that every position moves are built here
        too (:meth:`sliders.solve.statics.SliderStatics.prepare_translations`)."""
        statics, load = self.problem(0.0)
        statics.prepare_translations()
        return statics, load

    def shifts(self, stations: np.ndarray) -> np.ndarray:
        """The beams' translations (B, 2, 3) at the stations ``s / L``: the cylinder stays,
        the piston moves along x by ``s``."""
        shifts = np.zeros((len(stations), 2, 3))
        shifts[:, 1, 0] = np.asarray(stations, dtype=float) * self.setup.length
        return shifts

    def solve(self, stations: np.ndarray) -> list[SliderSolution | str]:
        """Every station at once, from the template moved (:func:`sliders.solve.statics.
        solve_translated`): per station its solution or its failure message."""
        statics, f = self.template
        return solve_translated(statics, self.shifts(stations), np.tile(f, (len(stations), 1)))

    def stiffness(self, s_over_L: float) -> float:
        """Normalised tip stiffness ``F L^3 / (EJ v)`` with the piston at ``s = s_over_L L``."""
        statics, f = self.problem(s_over_L)
        solution = statics.solve(f)
        self.iterations.append(solution.iterations)
        return self.tip_stiffness(statics, solution)

    def tip_stiffness(self, statics: SliderStatics, solution: SliderSolution) -> float:
        """``F L^3 / (EJ v)`` from the piston's tip deflection ``v``."""
        structure, L = statics.structure, self.setup.length
        tip = structure.beams[1].displacements(structure.local(1, solution.q), L)[0, 1]
        return self.setup.force / tip * L**3 / self.setup.EJ


def compile_kernels() -> None:
    """Compile the numba kernels of a static solve (joint equations, line state, condensed
    step, test functions at a point), or load them from their cache: two positions of
    each slider kind on one fv3 element (``fvslider compile``; about half a minute the
    first time on a machine, well under a second once cached); and the geometrically exact
    beam's (:mod:`fvbeam.exact_kernel`), by a static solve of one fv3 element."""
    from fvbeam.exact_beam import ExactBeam  # only here: the figures' runs do not need it
    from fvbeam.exact_statics import solve_static

    for kind in KINDS:
        SlidingBeams("fv3", 1, kind).solve(np.array([0.0, 0.01]))
    section = Section.diagonal(EA=1.0, GAy=1.0, GAz=1.0, GJ=1.0, EJy=1.0, EJz=1.0)
    exact = ExactBeam(Beam(straight((0, 0, 0), (1, 0, 0), 1, 3), section, "fv3"))
    load = exact.beam.nodal_load("end", force=(0.0, 0.1, 0.0))
    solve_static(exact, load, exact.beam.node_dofs("start"))
