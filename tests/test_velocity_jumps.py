"""Drives that set a mass moving at once from rest: warned of in Python, refused in scenes.

From a state at rest the generalized-alpha update gives a driven dof, after one step ``h``
whose prescribed value is ``q_1``, the velocity ``v_1 = gamma' (q_1 - q_hat)`` with
``q_hat = 0`` and ``gamma' = gamma / (beta h)`` (:mod:`sliders.solve.integrator`): a motion
leaving ``t = 0`` at the rate ``v`` (``q_1 = v h``) ends the first step at
``(gamma / beta) v``, twice ``v`` at ``rho_inf = 0.8``.  That is the jump the check names.
"""

import re
import warnings

import numpy as np
import pytest
from scipy.interpolate import CubicSpline
from test_scenes import SCENES

from fvbeam import Beam, RigidBody, Section, Structure, Support, straight
from sliders.app.cli import main
from sliders.joints.drives import DofDrive, Linear, Ramp, Tabulated, initial_rate
from sliders.joints.slider import Slider
from sliders.lines.chain import BeamChain
from sliders.solve.dynamics import Dynamics
from sliders.solve.jumps import VelocityJumpWarning

EPS = np.finfo(float).eps
UNIT = Section.diagonal(
    EA=1e3, GAy=1, GAz=1, GJ=1e3, EJy=1, EJz=1, mass_per_length=1.0, inertia=(1e-4,) * 3
)


def test_the_initial_rate_is_the_rate_just_after():
    """The right-hand limits of the motions' rates, from their formulas: a linear ramp from
    ``t0`` moves at ``(end - start) / (t1 - t0)``, a cosine one starts at rest, a table at
    its first point moves at its first piece's slope (the spline's derivative there)."""
    assert [initial_rate(Linear(0.2, 0.3, 1.0), t) for t in (0.0, 1.0, 5.0)] == [0.3] * 3
    linear = Ramp(0.0, 2.0, 1.0, 3.0, "linear")
    assert [initial_rate(linear, t) for t in (0.5, 1.0, 2.0, 3.0)] == [0.0, 1.0, 1.0, 0.0]
    cosine = Ramp(0.0, 2.0, 1.0, 3.0)
    assert initial_rate(cosine, 1.0) == 0.0
    assert initial_rate(cosine, 2.0) == cosine(2.0)[1] == pytest.approx(np.pi / 2, rel=EPS)
    table = Tabulated([0, 1, 2], [0, 1, 0.5])
    assert [initial_rate(table, t) for t in (-1.0, 0.0, 1.0, 2.0)] == [0.0, 1.0, -0.5, 0.0]
    spline = Tabulated([0, 1, 2, 4], [0, 1, 0.5, 2], order=3)
    assert initial_rate(spline, 0.0) == float(CubicSpline([0, 1, 2, 4], [0, 1, 0.5, 2])(0, 1))
    assert initial_rate(lambda t: (t, 1.0, 0.0), 0.0) == 1.0  # another kind: its rate


def tip_drive(motion):
    structure = Structure([Beam(straight((0, 0, 0), (1, 0, 0), 2, name="c"), UNIT, "fv3")])
    dynamics = Dynamics(structure, [Support("c.start")], drives=[DofDrive("c.end", "uy", motion)])
    return dynamics, int(structure.node_dofs("c.end")[1])


def test_a_drive_leaving_rest_at_speed_is_warned_of_and_jumps_past_it():
    dynamics, dof = tip_drive(Linear(0.0, 0.5))
    mass = dynamics.M[dof, dof]
    h = 0.01
    with pytest.warns(VelocityJumpWarning) as caught:
        state = dynamics.run(dynamics.static_state(), h, h, progress=False)
    assert str(caught[0].message) == (
        f"the drive of c.end uy starts at 0.5 m/s from rest on a mass of {mass:.4g} kg: the "
        f"first step sets it moving at once ({0.5 * mass * 0.25:.4g} J of kinetic energy from "
        "nowhere): start from rest instead, e.g. with a cosine Ramp (sliders.joints.drives.Ramp)"
    )
    # v_1 = gamma' q_1: a product and a quotient of rounded constants, a few eps
    scheme = dynamics.scheme
    assert state.v[dof] == pytest.approx(scheme.gamma / scheme.beta * 0.5, rel=8 * EPS)


@pytest.mark.parametrize(
    "motion", [Ramp(0.0, 0.5, 0.0, 1.0), Linear(0.0, 0.5)], ids=["cosine ramp", "in motion"]
)
def test_a_start_at_rest_or_a_state_in_motion_is_not_warned_of(motion):
    """A cosine ramp leaves rest at rate zero; a state already moving is taken as it is."""
    dynamics, dof = tip_drive(motion)
    n = dynamics.structure.n_dofs
    if isinstance(motion, Linear):
        v = np.zeros(n)
        v[dof] = 0.5
        start = dynamics.state(np.zeros(n), v)
    else:
        start = dynamics.static_state()
    with warnings.catch_warnings():
        warnings.simplefilter("error", VelocityJumpWarning)
        dynamics.run(start, 0.05, 0.01, progress=False)


def pushed_cart(mass: float):
    """The pushed-body scene's cart (docs/scenes.md) with the given mass, pushed along the
    beam at 0.035 m/s."""
    structure = Structure(
        [Beam(straight((0, 0, 0), (1, 0, 0), 1, name="cantilever"), UNIT, "fv3")],
        bodies=[RigidBody("cart", (0.6, 0, 0), mass=mass)],
    )
    push = Slider(
        "spherical", BeamChain(structure, ["cantilever"]), "cart", drive=Linear(0.6, 0.035)
    )
    supports = [Support("cantilever.start"), Support("cart", kind="rx+ry+rz")]
    load = structure.nodal_load("cart", force=(0, 1, 0))
    return Dynamics(structure, supports, [push], load, method="condensed")


def test_a_pushed_body_jumps_only_with_mass():
    """The mass along the line of a body of mass m at its node is ``l^T (m I) l = m``; a
    massless body (the paper's Figure 2) has nothing to jump."""
    assert pushed_cart(0.0).velocity_jumps(pushed_cart(0.0).static_state()) == []
    heavy = pushed_cart(2.0)
    (jump,) = heavy.velocity_jumps(heavy.static_state())
    assert jump.rate == 0.035 and jump.mass == pytest.approx(2.0, rel=4 * EPS)
    assert jump.energy == pytest.approx(0.5 * 2.0 * 0.035**2, rel=8 * EPS)


HEAVY_CART = (
    "position = [0.6, 0.0, 0.0]     # massless",
    "mass = 2.0\nposition = [0.6, 0.0, 0.0] #",
)
SHORT = ("t_end = 10.0", "t_end = 0.5")
LINEAR_RAMP = (
    "[study]",
    '[[drive]]\nkind = "dof"\nnode = "cantilever.end"\ndof = "uy"\n'
    'motion = { kind = "ramp", start = 0.0, end = 0.01, t0 = 0.0, t1 = 1.0, shape = "linear" }'
    "\n\n[study]",
)


#: A cosine ramp that started before t = 0: it is moving at the start.
MID = Ramp(0.6, 0.95, -1.0, 10.0)
MID_RAMP = (
    'motion = { kind = "linear", start = 0.6, velocity = 0.035 }',
    'motion = { kind = "ramp", start = 0.6, end = 0.95, t0 = -1.0, t1 = 10.0 }',
)


def scene_with(tmp_path, *edits) -> str:
    text = (SCENES / "pushed_body.toml").read_text()
    for old, new in edits:
        assert old in text
        text = text.replace(old, new, 1)
    path = tmp_path / "scene.toml"
    path.write_text(text)
    return text


@pytest.mark.parametrize(
    "edits,where,instead",
    [
        (
            [HEAVY_CART, SHORT],
            "drive[0].motion: the drive of the body of slider 'push' starts at 0.035 m/s from "
            "rest on a mass of 2 kg: the first step sets it moving at once (0.001225 J of "
            "kinetic energy from nowhere)",
            'motion = { kind = "ramp", start = 0.6, end = 0.6175, t0 = 0, t1 = 0.5 }',
        ),
        (
            [HEAVY_CART, SHORT, MID_RAMP],
            "drive[0].motion: the drive of the body of slider 'push' starts at "
            f"{MID(0.0)[1]:.4g} m/s from rest on a mass of 2 kg",
            f'motion = {{ kind = "ramp", start = {MID(0.0)[0]:.6g}, end = {MID(0.5)[0]:.6g}, '
            "t0 = 0, t1 = 0.5 }",
        ),
        (
            [SHORT, LINEAR_RAMP],
            "drive[1].motion: the drive of cantilever.end uy starts at 0.01 m/s from rest",
            'shape = "cosine"',
        ),
    ],
    ids=["linear push of a heavy cart", "cosine ramp already moving", "linear ramp of a tip"],
)
def test_a_scene_refuses_a_jump_and_accepts_the_motion_it_offers(
    edits, where, instead, tmp_path, capsys
):
    """Exit 2 at check and run, nothing written; the motion the message offers (a cosine
    ramp over the study's travel: 0.6 + 0.035 x 0.5 = 0.6175 at t_end = 0.5, or the moving
    ramp's values at 0 and 0.5; a linear ramp's cosine shape) validates and runs."""
    text = scene_with(tmp_path, *edits)
    scene, out = tmp_path / "scene.toml", tmp_path / "out"
    for args in (["check", str(scene)], ["run", str(scene), "--out", str(out)]):
        assert main(args) == 2
        err = capsys.readouterr().err
        assert f"\n  {where}" in err and f"start it at rest instead, e.g. {instead}" in err
        assert sorted(p.name for p in tmp_path.iterdir()) == ["scene.toml"]
    if instead.startswith("motion"):
        fixed = re.sub(r"motion = \{.*\}", instead, text, count=1)
    else:
        fixed = text.replace('shape = "linear"', instead)
    assert fixed != text
    scene.write_text(fixed)
    with warnings.catch_warnings():
        warnings.simplefilter("error", VelocityJumpWarning)
        assert main(["run", str(scene), "--out", str(out)]) == 0
    assert (out / "history.csv").exists()
