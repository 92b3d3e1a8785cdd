"""Planar problems solved on their in-plane dofs (:mod:`sliders.solve.planar`) against the
same problems in three dimensions.

A planar problem's out-of-plane dofs and reactions are exactly zero in three dimensions, so
holding them changes nothing but the arithmetic: the in-plane solution is the same to the
Newton tolerance ``tol`` (both solves stop on it; the test asserts ``10 tol`` of the largest
value) and to roundoff in the linear steps.  A load, a drive or a section that leaves the
plane is refused, named.
"""

from __future__ import annotations

import numpy as np
import pytest
from test_sliders import SECTION, sliding_beams_model

from fvbeam import Beam, Section, Structure, Support, straight
from sliders.joints.drives import Ramp
from sliders.solve.dynamics import Dynamics
from sliders.solve.newton_kernel import NOT_CONVERGED_MESSAGE
from sliders.solve.planar import out_of_plane
from sliders.solve.statics import SliderStatics

TOL = 1e-10


def close(a: np.ndarray, b: np.ndarray) -> None:
    assert np.abs(a - b).max() <= 10 * TOL * max(np.abs(b).max(), 1.0)


@pytest.mark.parametrize("name", ["fv3", "cubic"])
@pytest.mark.parametrize("kind", ["spherical", "classical", "spline"])
def test_sliding_beams_in_their_plane(kind, name) -> None:
    """The sliding beams (the piston's spin held by the plane), a tip force in xy; fv3, and
    cubic chains (whose joints carry the contact compliance's diagonal blocks beside the
    pinned multipliers')."""
    structure, supports, sliders, P = sliding_beams_model(0.37 * 0.6, 3, kind, name)
    f = structure.gather(1, P.nodal_load("end", (40.0, 1.0e3, 0.0), (0.0, 0.0, 5.0)))
    full = SliderStatics(structure, supports, sliders).newton(f, None, TOL, 25)
    planar = SliderStatics(structure, supports, sliders, plane="xy")
    assert planar.free.size < full_free(structure, supports)
    (q, y, _), (q_ref, y_ref, _) = planar.newton(f, None, TOL, 25), full
    close(q, q_ref)
    assert np.all(q[out_of_plane(structure, "xy")] == 0.0)
    for a, b in zip(y, y_ref, strict=True):
        close(a, b)


@pytest.mark.parametrize("warm", [False, True])
def test_a_planar_newton_stopped_short_is_not_called_singular(warm) -> None:
    """The Newton matrix a planar solve factorises holds the pinned multipliers' equations
    ``y_k = 0`` (:func:`sliders.solve.planar.pin`): it is regular where the solve converges,
    and a Newton stopped after one iteration is reported unconverged, as in three dimensions
    (a dynamic step then tries halves).  Without them a pinned multiplier's column lies on
    held dofs only, and the diagnosis would name a free motion along it.  From the default
    start (multipliers zero) and from the converged state under a load three times larger."""
    structure, supports, sliders, P = sliding_beams_model(0.37 * 0.6, 3, "classical", "fv3")
    f = structure.gather(1, P.nodal_load("end", (40.0, 1.0e3, 0.0), (0.0, 0.0, 5.0)))
    for plane in (None, "xy"):
        statics = SliderStatics(structure, supports, sliders, plane=plane)
        q, y, _ = statics.newton(f, None, TOL, 25)
        assert statics._singular(statics.jacobian(q, y)) is None
        outcome = statics.newton(3 * f, (q, y), TOL, 1) if warm else statics.newton(f, None, TOL, 1)
        assert isinstance(outcome, str) and outcome.startswith(NOT_CONVERGED_MESSAGE), outcome


def full_free(structure: Structure, supports: list[Support]) -> int:
    return structure.n_dofs - len(structure.support_dofs(supports))


def test_a_telescope_in_motion_in_its_plane() -> None:
    """Dynamics: the sliding beams with mass, the piston pushed in while a force bends them,
    every step the same in the plane as in three dimensions."""
    section = Section.diagonal(
        EA=1e3,
        GAy=100,
        GAz=100,
        GJ=1.0,
        EJy=1.0,
        EJz=1.0,
        mass_per_length=1.0,
        inertia=np.diag([1e-3] * 3),
    )
    C = Beam(straight((0, 0, 0), (1.0, 0, 0), 2, 3, name="C"), section, "fv3")
    P = Beam(straight((0.3, 0, 0), (1.3, 0, 0), 2, 3, name="P"), section, "fv3")
    structure = Structure([C, P])
    from sliders.joints.slider import Slider
    from sliders.lines.chain import BeamChain

    sliders = [
        Slider("classical", BeamChain(structure, ["C"]), "P.start", name="A"),
        Slider("classical", BeamChain(structure, ["P"]), "C.end", name="B"),
    ]
    from sliders.joints.drives import DofDrive

    drive = DofDrive("P.start", "ux", Ramp(0.0, -0.05, 0.0, 0.5))
    load = structure.nodal_load("P.end", (0.0, 0.2, 0.0))
    runs = []
    for plane, supports in (
        (None, [Support("C.start"), Support("P.start", kind="rx")]),
        ("xy", [Support("C.start")]),
    ):
        d = Dynamics(structure, supports, sliders, load, drives=[drive], plane=plane, tol=TOL)
        runs.append(d.run(d.static_state(), 0.3, 0.01, progress=False))
    close(runs[1].q, runs[0].q)


def test_what_leaves_the_plane_is_named() -> None:
    structure, supports, sliders, P = sliding_beams_model(0.3, 2, "spherical")
    statics = SliderStatics(structure, supports, sliders, plane="xy")
    with pytest.raises(ValueError, match="out of plane xy"):
        statics.solve(structure.gather(1, P.nodal_load("end", (0.0, 1.0, 0.5))))
    tilted = Beam(straight((0, 0, 0), (1, 0.5, 0), 2, 3, name="t"), SECTION, "fv3")
    with pytest.raises(ValueError, match="beam 0 node 1 lies off the plane zx"):
        SliderStatics(Structure([tilted]), [Support("t.start")], [], plane="zx")
    skew = Section(np.eye(6) + 0.1 * np.eye(6, k=1) + 0.1 * np.eye(6, k=-1))
    beam = Beam(straight((0, 0, 0), (1, 0, 0), 2, 3, name="b"), skew, "fv3")
    with pytest.raises(ValueError, match="are coupled: the structure does not deform in plane"):
        SliderStatics(Structure([beam]), [Support("b.start")], [], plane="xy")
