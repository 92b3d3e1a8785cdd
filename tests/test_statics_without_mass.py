"""Statics never assembles a mass matrix (issue 13: skip what a scene does not need).

Every mass matrix is assembled by :func:`fvbeam.mass.lumped` or :func:`fvbeam.mass.consistent`
(through ``Beam.mass``) and gathered by ``Structure.mass``; the tests replace the three with a
function that fails, check that the replacement does catch a mass assembly, and run the
static solvers and static scenes, whose sections carry mass.
"""

import numpy as np
import pytest
from test_scenes import SCENES

from fvbeam import Beam, LinearStatics, Section, Structure, Support, mass, straight
from sliders.app.model import Model
from sliders.app.run import run
from sliders.app.scene import load_scene
from sliders.joints.slider import Slider
from sliders.lines.chain import BeamChain
from sliders.lines.rigid import CircularArc
from sliders.solve.statics import SliderStatics

SECTION = Section.diagonal(
    EA=1e3, GAy=5.0, GAz=5.0, GJ=1.5, EJy=2.0, EJz=2.0, mass_per_length=3.0, inertia=(1, 1, 1)
)


class MassAssembled(AssertionError):
    pass


@pytest.fixture
def no_mass(monkeypatch):
    """Any mass assembly raises :class:`MassAssembled`."""

    def fail(*args, **kwargs):
        raise MassAssembled("a static solve assembled a mass matrix")

    for kind in mass.KINDS:
        monkeypatch.setattr(mass, kind, fail)
    monkeypatch.setattr(Structure, "mass", fail)


def test_the_guard_catches_a_mass_assembly(no_mass):
    beam = Beam(straight((0, 0, 0), (1, 0, 0), 3), SECTION, "fv3")
    with pytest.raises(MassAssembled):
        beam.mass("lumped")
    with pytest.raises(MassAssembled):
        Structure([beam]).mass()


def test_linear_statics_assembles_no_mass(no_mass):
    beam = Beam(straight((0, 0, 0), (1, 0, 0), 4), SECTION, "galerkin-p2")
    statics = LinearStatics(beam, [Support(0, "start")])
    q = statics.solve(beam.point_load(1.0, force=(0, 1, 0)))
    assert q[beam.node_dofs("end")][1] > 0


@pytest.mark.parametrize("method", ["bordered", "condensed"])
def test_slider_statics_assembles_no_mass(no_mass, method):
    """A beam's tip on a rigid arc, and the paper's two beams joined by two sliders."""
    beam = Beam(straight((0, 0, 0), (1, 0, 0), 4, 3), SECTION, "fv3")
    structure = Structure([beam])
    arc = CircularArc((1, -2, 0), 2.0, np.pi / 2 - 0.3, np.pi / 2 + 0.3)
    frame = np.column_stack([[-1, 0, 0], [0, 1, 0], [0, 0, -1]]).astype(float)
    slider = Slider("classical", arc, (0, "end"), frame=frame, name="tip")
    statics = SliderStatics(structure, [Support(0, "start")], [slider], method=method)
    f = structure.gather(0, beam.nodal_load("end", force=(3.0, 1.0e3, 2.0e2)))
    assert np.all(np.isfinite(statics.solve(f).q))

    C = Beam(straight((0, 0, 0), (1, 0, 0), 3, 3), SECTION, "fv3")
    P = Beam(straight((0.4, 0, 0), (1.4, 0, 0), 3, 3), SECTION, "fv3")
    structure = Structure([C, P])
    sliders = [
        Slider("spherical", BeamChain(structure, [0], "C"), (1, "start"), name="A"),
        Slider("spherical", BeamChain(structure, [1], "P"), (0, "end"), name="B"),
    ]
    supports = [Support(0, "start"), Support(1, "start", "ux+rx")]
    statics = SliderStatics(structure, supports, sliders, method=method)
    tip = structure.gather(1, P.nodal_load("end", force=(0, 1.0, 0)))
    assert np.all(np.isfinite(statics.solve(tip).q))


@pytest.mark.parametrize("scene", ["arch", "carriage_on_chain", "fig4_sliding_beams"])
def test_static_scenes_assemble_no_mass(no_mass, scene):
    """A static study and two sweeps (sliders on a chain, the paper's setup, condensed)."""
    results = run(Model(load_scene(SCENES / f"{scene}.toml")), progress=False)
    assert results.samples and all(sample.error is None for sample in results.samples)
