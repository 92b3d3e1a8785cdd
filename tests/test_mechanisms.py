"""A structure with a free rigid motion is never solved: every path names the motion.

The scenes of issue 12 (the Figure 1 cantilever without its clamp or pinned, the arch on
rollers, the spline slider without its axial support) and the same structures in Python
(``LinearStatics``, ``SliderStatics`` with both back ends, sweeps, ``Dynamics``).  The
expected motions follow from the supports alone (:mod:`fvbeam.mechanism`): a free part keeps
its three translations and three rotations, named about its centre (the mean of its nodes); a
pin at a point leaves the three rotations about that point; ``uy`` held at two points on the
x axis holds ``uy`` and the rotation about z, and leaves the translations along x and z and
the rotations about x and y.  The spline slider holds its body's position across the shaft
and its rotations, not its sliding along the shaft.
"""

import numpy as np
import pytest
from test_scenes import SCENES

from fvbeam import Beam, LinearStatics, RigidBody, Section, Structure, Support, arc, straight
from fvbeam.mechanism import rigid_modes
from sliders.app.cli import main
from sliders.joints.slider import Slider
from sliders.lines.chain import BeamChain
from sliders.solve.dynamics import Dynamics, DynamicsError
from sliders.solve.statics import SliderStatics, solve_many
from sliders.solve.sweep import sweep

EPS = np.finfo(float).eps
UNIT = Section.diagonal(
    EA=1e3, GAy=1, GAz=1, GJ=1e3, EJy=1, EJz=1, mass_per_length=1.0, inertia=(1e-4,) * 3
)
SHAFT = Section.diagonal(
    EA=1e9, GAy=1e8, GAz=1e8, GJ=2e4, EJy=4e4, EJz=4e4, mass_per_length=1.0, inertia=(1e-3,) * 3
)
PREFIX = "singular configuration: the supports leave a rigid-body motion free: "
WITH_SLIDERS = "singular configuration: the supports and sliders leave a rigid-body motion free: "
#: The centre of the arch: the mean of its 17 nodes at angles j pi / 16 on a circle of radius
#: 2, y = 2 cot(pi / 32) / 17 (the sum of sin(j pi / 16), j = 0 ... 16, is cot(pi / 32)).
ARCH_CENTRE = f"(0, {2 / np.tan(np.pi / 32) / 17:.4g}, 0)"
FREE_CANTILEVER = (
    "beam 'cantilever' translating along x, y and z and rotating about x, y and z "
    "through (0.5, 0, 0)"
)
PINNED_CANTILEVER = "beam 'cantilever' rotating about x, y and z through (0, 0, 0)"
ARCH_ON_ROLLERS = (
    f"beam 'arch' translating along x and z and rotating about x and y through {ARCH_CENTRE}"
)
SLIDING_ARM = "beam 'arm' translating along x, slider 'key' sliding along its line"


def edited(tmp_path, name: str, old: str, new: str):
    """The shipped scene ``name`` with ``old`` replaced by ``new``, written in ``tmp_path``."""
    text = (SCENES / f"{name}.toml").read_text()
    assert old in text
    path = tmp_path / f"{name}.toml"
    path.write_text(text.replace(old, new))
    return path


CLAMP = '[[support]]\nnode = "cantilever.start"   # kind = "clamp" by default\n'
SCENE_CASES = {
    "no support": (
        "fig1_cantilever",
        CLAMP,
        "",
        PREFIX + FREE_CANTILEVER,
    ),
    "pinned": (
        "fig1_cantilever",
        CLAMP,
        '[[support]]\nnode = "cantilever.start"\nkind = "pin"\n',
        PREFIX + PINNED_CANTILEVER,
    ),
    "arch on rollers": (
        "arch",
        'kind = "ux+uy+uz+rx"\n\n[[support]]\nnode = "arch.end"\nkind = "pin"',
        'kind = "uy"\n\n[[support]]\nnode = "arch.end"\nkind = "uy"',
        PREFIX + ARCH_ON_ROLLERS,
    ),
    "spline slider free along the shaft": (
        "spline_slider",
        '[[support]]\nnode = "arm.start"\nkind = "ux"\n',
        "",
        WITH_SLIDERS + SLIDING_ARM,
    ),
}


@pytest.mark.parametrize("case", SCENE_CASES)
@pytest.mark.parametrize("command", ["check", "run"])
def test_a_scene_with_a_free_motion_exits_2_naming_it_and_writes_nothing(
    case, command, tmp_path, capsys
):
    name, old, new, message = SCENE_CASES[case]
    scene = edited(tmp_path, name, old, new)
    out = tmp_path / "out"
    args = [command, str(scene)] + (["--out", str(out)] if command == "run" else [])
    assert main(args) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    assert f"\n  support: {message} (hold it with a support, a slider or a drive)" in captured.err
    assert "converged" not in captured.err
    assert sorted(p.name for p in tmp_path.iterdir()) == [scene.name]


def cantilever(supports):
    beam = Beam(straight((0, 0, 0), (1, 0, 0), 1, name="cantilever"), UNIT, "fv3")
    return Structure([beam]), supports


def arch_on_rollers():
    beam = Beam(arc((0, 0, 0), 2.0, 0.0, np.pi, 8, name="arch"), UNIT, "fv3")
    return Structure([beam]), [Support("arch.start", kind="uy"), Support("arch.end", kind="uy")]


STRUCTURES = {
    "no support": (cantilever([]), FREE_CANTILEVER),
    "pinned": (cantilever([Support("cantilever.start", kind="pin")]), PINNED_CANTILEVER),
    "arch on rollers": (arch_on_rollers(), ARCH_ON_ROLLERS),
}


@pytest.mark.parametrize("case", STRUCTURES)
def test_every_static_path_without_sliders_raises_the_named_motion(case):
    (structure, supports), motion = STRUCTURES[case]
    f = structure.nodal_load((0, "end"), force=(0, 1, 0))
    with pytest.raises(ValueError) as linear:
        LinearStatics(structure, supports)
    assert str(linear.value) == f"{PREFIX}{motion} (support more dofs)"
    expected = f"{PREFIX}{motion} (hold it with a support, a slider or a drive)"
    for method in ("bordered", "condensed"):
        with pytest.raises(ValueError) as statics:
            SliderStatics(structure, supports, [], method=method).solve(f)
        assert str(statics.value) == expected
    result = sweep([0.5, 1.0], lambda v: (SliderStatics(structure, supports, []), v * f))
    assert result.failures == [(0.5, expected), (1.0, expected)]
    assert result.solutions == [None, None]


def test_the_static_start_of_a_time_integration_says_what_it_needs():
    """The pinned cantilever has mass: the dynamic operator ``M + c K`` holds its rotations,
    the static start does not.  ``static_state`` names them and what the start needs; a start
    from a given state at rest runs, the tip force turning the beam about the pin (its tip
    moves along +y)."""
    (structure, supports), _ = STRUCTURES["pinned"]
    f = structure.nodal_load((0, "end"), force=(0, 1, 0))
    dynamics = Dynamics(structure, supports, load=f)
    with pytest.raises(DynamicsError) as start:
        dynamics.static_state()
    assert str(start.value) == (
        f"t = 0: {PREFIX}{PINNED_CANTILEVER} (a time integration starts from the static "
        "equilibrium, which needs it held: a support, a slider or a drive; or start from a "
        "given state, Dynamics.state or State.load)"
    )
    state = dynamics.run(dynamics.state(np.zeros(structure.n_dofs)), 0.1, 0.01, progress=False)
    assert state.q[structure.node_dofs((0, "end"))[1]] > 0


def spline_arm(axial: bool):
    """The spline slider scene's shaft and arm, the arm's axial position held or not."""
    shaft = Beam(straight((0, 0, 0), (1, 0, 0), 4, name="shaft"), SHAFT, "fv3")
    arm = Beam(straight((0.37, 0, 0), (0.37, 0.1, 0), 1, name="arm"), SHAFT, "fv3")
    structure = Structure([shaft, arm])
    key = Slider("spline", BeamChain(structure, ["shaft"]), "arm.start", name="key")
    supports = [Support("shaft.start")] + ([Support("arm.start", kind="ux")] if axial else [])
    return structure, supports, key, structure.nodal_load("arm.end", moment=(100, 0, 0))


def test_every_path_with_sliders_raises_the_named_motion():
    """Both back ends (the bordered one reported ``xi lies outside the chain`` before),
    many members at once, a sweep and the static start of a time integration."""
    structure, supports, key, f = spline_arm(axial=False)
    expected = f"{WITH_SLIDERS}{SLIDING_ARM} (hold it with a support, a slider or a drive)"
    for method in ("bordered", "condensed"):
        statics = SliderStatics(structure, supports, [key], method=method)
        with pytest.raises(ValueError) as single:
            statics.solve(f)
        assert str(single.value) == expected
        assert solve_many([statics, statics], [f, 2 * f]) == [expected, expected]
    result = sweep([1.0, 2.0], lambda v: (SliderStatics(structure, supports, [key]), v * f))
    assert result.failures == [(1.0, expected), (2.0, expected)]
    with pytest.raises(DynamicsError, match=f"^t = 0: {WITH_SLIDERS}{SLIDING_ARM} \\(a time"):
        Dynamics(structure, supports, [key], f).static_state()


def test_the_held_arm_still_solves():
    """With its axial support the arm is held: both back ends converge (no false alarm)."""
    structure, supports, key, f = spline_arm(axial=True)
    for method in ("bordered", "condensed"):
        SliderStatics(structure, supports, [key], method=method).solve(f, tol=1e-10)


@pytest.mark.parametrize(
    "supports,count",
    [
        ([], 6),
        ([Support("c.start", kind="pin")], 3),
        ([Support("c.start", kind="uy"), Support("c.end", kind="uy")], 4),
        ([Support("c.start", kind="pin"), Support("c.end", kind="pin")], 1),
        ([Support("c.start")], 0),
    ],
)
def test_the_free_motions_are_the_null_space_of_the_stiffness(supports, count):
    """``rigid_modes`` spans exactly the null space of the stiffness on the free dofs:
    orthonormal (Householder QR: to 10 n eps, Higham Sec. 19.3), zero on the supported dofs,
    ``K phi`` at roundoff (n_row (1 + 2 n_q) eps max|K|, tests/test_condensed.py), and as many
    as the singular values of ``K_ff`` below 1e-10 of the largest, which is 6 minus what the
    supports hold.  The null ones are at roundoff (n eps, 1e-14 of the largest at most); the
    others are at least 3e-6 of it here (a unit cantilever of 4 elements, EJ / EA = 1e-3),
    so the threshold lies in the gap, which the last assertion states."""
    beam = Beam(straight((0, 0, 0), (1, 0, 0), 4, name="c"), UNIT, "fv3")
    structure = Structure([beam])
    free = np.setdiff1d(np.arange(structure.n_dofs), structure.support_dofs(supports))
    modes = rigid_modes(structure, free)
    assert modes.k == count
    n = len(free)
    np.testing.assert_allclose(modes.phi.T @ modes.phi, np.eye(count), atol=10 * n * EPS)
    K = structure.tangent(np.zeros(structure.n_dofs)).tocsr()[free][:, free]
    n_row = int(np.diff(K.indptr).max())
    assert np.abs(K @ modes.phi).max(initial=0.0) <= n_row * 7 * EPS * abs(K).max()
    sigma = np.linalg.svd(K.toarray(), compute_uv=False)
    assert np.sum(sigma <= 1e-10 * sigma[0]) == count
    assert sigma[-count - 1] >= 1e-6 * sigma[0]


def test_a_lone_body_is_a_part_of_its_own():
    """A body tied to nothing keeps its six motions about its own position, whatever holds
    the beam."""
    beam = Beam(straight((0, 0, 0), (1, 0, 0), 2, name="c"), UNIT, "fv3")
    structure = Structure([beam], bodies=[RigidBody("loose", (0, 1, 0))])
    with pytest.raises(ValueError) as info:
        LinearStatics(structure, [Support("c.start")])
    assert str(info.value) == (
        f"{PREFIX}body 'loose' translating along x, y and z and rotating about x, y and z "
        "through (0, 1, 0) (support more dofs)"
    )
