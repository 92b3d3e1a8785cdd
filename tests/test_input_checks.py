"""Misleading or missing input checks: each bad input gives one ValueError naming the argument
(Python) or one problem at its key path (a scene: exit code 2, nothing written), from the one
helper that checks that kind of input on every path."""

import re
import tomllib

import numpy as np
import pytest
from test_limits import FIG1, refused
from test_scenes import SCENES

from fvbeam import Beam, BeamMesh, Section, Structure, Support, arc, from_curve, straight
from fvbeam.geometry import UP_ANGLE
from fvbeam.section import CONDITIONING
from fvbeam.support import held_dofs
from sliders.joints.slider import Slider
from sliders.lines.chain import BeamChain
from sliders.lines.rigid import CubicSpline, StraightLine

SECTION = Section.diagonal(EA=1e3, GAy=1.0, GAz=1.0, GJ=1e3, EJy=1.0, EJz=1.0)


# -- sections -------------------------------------------------------------------------------
def test_an_ill_conditioned_section_states_the_rule_and_names_both_stiffnesses():
    """GA = 1e15 and EJ = 1 are both positive: the section is refused for the ratio 1e-15 of
    its smallest to its largest stiffness, below CONDITIONING = 1e-14."""
    with pytest.raises(ValueError) as info:
        Section.diagonal(EA=1e9, GAy=1e15, GAz=1e15, GJ=1.0, EJy=1.0, EJz=1.0)
    message = str(info.value)
    assert "too ill-conditioned" in message and "positive definite" not in message
    assert "its smallest GJ = 1 is 1e-15 of its largest GAy = 1e+15" in message
    assert f"must exceed {CONDITIONING:g} of its largest" in message


def test_a_coupled_section_names_its_eigenvalues():
    """Eigenvalues 1 +- (1 - 1e-15) of the coupled pair: their ratio is about 5e-16."""
    K = np.diag([1.0, 1.0, 1.0, 1.0, 1.0, 1.0])
    K[4, 5] = K[5, 4] = 1 - 1e-15
    with pytest.raises(ValueError, match=r"smallest eigenvalue .* of its largest eigenvalue 2"):
        Section(K)


def test_a_section_at_the_conditioning_bound_is_accepted():
    """The ratio 1e-13, ten times the bound, passes."""
    section = Section.diagonal(EA=1e13, GAy=1.0, GAz=1.0, GJ=1.0, EJy=1.0, EJz=1.0)
    assert section.stiffness[0, 0] == 1e13


# -- up -------------------------------------------------------------------------------------
def test_up_along_a_straight_beam_is_refused_with_an_axis_that_would_do():
    with pytest.raises(ValueError) as info:
        straight((0, 0, 0), (2, 0, 0), 3, up=(3, 0, 0), name="C")
    message = str(info.value)
    assert message.startswith("C: up = [1.0, 0.0, 0.0] is along the tangent [1.0, 0.0, 0.0]")
    assert "e.g. [0.0, 1.0, 0.0]" in message


def test_up_along_a_curved_element_inside_it_is_found():
    """Two 3-node elements of ``x = sin(pi u / 0.8), z = u``: the interpolated tangent of the
    first (nodes at u = 0, 0.25, 0.5) is linear in X and vertical where its x component
    vanishes, at X = -a_x / b_x (neither an end nor the mid node); ``up = z`` is refused there.
    The tangents all lie in the x-z plane, so an ``up`` tilted out of it by 1e-3 rad crosses
    every one at a sine of at least sin(1e-3), a thousand times UP_ANGLE: it is accepted."""

    def curve(u):
        return np.column_stack([np.sin(np.pi * u / 0.8), 0 * u, u])

    tilted = (0.0, np.sin(1e-3), np.cos(1e-3))
    mesh = from_curve(curve, 2, 3, up=tilted)
    a = mesh.tangent_vectors(np.array([0]), np.array([0.0]))[0]
    b = mesh.tangent_vectors(np.array([0]), np.array([1.0]))[0] - a
    X = -a[0] / b[0]
    assert 0.5 < X < 1
    xi = mesh.abscissae(np.array([0]), np.array([X]))[0]
    with pytest.raises(ValueError, match=rf"along the tangent \[0.0, 0.0, 1.0\] at xi = {xi:.6g}"):
        from_curve(curve, 2, 3, up=(0, 0, 1))
    np.testing.assert_allclose(mesh.up, tilted, rtol=0, atol=1e-16)
    assert np.sin(1e-3) >= 999 * UP_ANGLE


def test_up_along_a_mesh_read_from_points():
    points = [[0, 0, 0], [0, 0, 1], [0, 0, 0.5]]
    with pytest.raises(ValueError, match="up = .* is along the tangent"):
        BeamMesh(points, [[0, 1, 2]])
    assert BeamMesh(points, [[0, 1, 2]], up=(1, 0, 0)).length == pytest.approx(1.0, abs=1e-15)


def test_up_along_rigid_lines():
    with pytest.raises(ValueError, match=r"rail: up = \[0.0, 1.0, 0.0\] is along the tangent"):
        StraightLine((0, 0, 0), (0, 2, 0), up=(0, 1, 0), name="rail")
    with pytest.raises(ValueError, match="up must be a non-zero 3-vector"):
        StraightLine((0, 0, 0), (0, 2, 0), up=(0, 0, 0))
    # a spline through a vertical stretch: its tangent turns through z between the points
    points = [[0, 0, 0], [0, 0, 1], [1, 0, 2], [2, 0, 2]]
    with pytest.raises(ValueError, match="track: up = .* is along the tangent"):
        CubicSpline(points, up=(0, 0, 1), name="track")
    assert CubicSpline(points, up=(0, 1, 0)).length > 0


# -- supports -------------------------------------------------------------------------------
@pytest.mark.parametrize(
    "kind,message",
    [
        ("ux+ux", "names ux more than once"),
        ("rz+ux+rz+ux", "names ux, rz more than once"),
        ("ux+roll", "must be 'clamp', 'pin' or dof names"),
        ("", "must be 'clamp', 'pin' or dof names"),
        ("Clamp", "(did you mean 'clamp'?)"),
    ],
)
def test_support_kinds_hold_each_dof_once(kind, message):
    with pytest.raises(ValueError, match=re.escape(f"support kind {kind!r} at 'C.start' ")):
        Support("C.start", kind=kind)
    with pytest.raises(ValueError) as info:
        held_dofs(kind)
    assert message in str(info.value)


def test_held_dofs_are_sorted_indices():
    assert held_dofs("rz+ux").tolist() == [0, 5]
    assert held_dofs("pin").tolist() == [0, 1, 2]


# -- beams, meshes, loads -------------------------------------------------------------------
def test_beam_checks_the_types_of_its_arguments():
    mesh = straight((0, 0, 0), (1, 0, 0), 2)
    with pytest.raises(ValueError, match=r"section must be a Section .* got dict \{'EA': 1\}"):
        Beam(mesh, {"EA": 1}, "fv3")  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="mesh must be a BeamMesh .* got list"):
        Beam([[0, 0, 0], [1, 0, 0]], SECTION)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="formulation must be a Formulation .* got int"):
        Beam(mesh, SECTION, 3)  # type: ignore[arg-type]


@pytest.mark.parametrize("method", ["internal_forces", "residual", "displacements"])
def test_a_dof_vector_of_the_wrong_size_is_named(method):
    """Two fv3 elements: 5 nodes, 30 dofs."""
    beam = Beam(straight((0, 0, 0), (1, 0, 0), 2), SECTION)
    args = (np.ones(3), 0.5) if method == "displacements" else (np.ones(3),)
    with pytest.raises(ValueError, match=r"q must hold 30 values .* got shape \(3,\)"):
        getattr(beam, method)(*args)


def test_a_global_dof_vector_of_the_wrong_size_is_named():
    """Two beams of one fv3 element, not tied: 2 x 3 nodes, 36 dofs."""
    beams = [
        Beam(straight((0, y, 0), (1, y, 0), 1, name=n), SECTION) for y, n in ((0, "a"), (1, "b"))
    ]
    structure = Structure(beams)
    for call in (lambda: structure.local("b", np.ones(18)), lambda: structure.residual([1.0])):
        with pytest.raises(ValueError, match=r"q must hold 36 values .* got shape"):
            call()
    np.testing.assert_array_equal(structure.local("b", np.arange(36.0)), np.arange(18.0, 36.0))


def test_section_diagonal_names_a_string_stiffness():
    with pytest.raises(ValueError, match="section: EA must be finite and > 0, got '1e9'"):
        Section.diagonal(EA="1e9", GAy=1, GAz=1, GJ=1, EJy=1, EJz=1)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    "call,message",
    [
        (lambda: straight((0, 0), (1, 0), 2), r"start must be a finite 3-vector, got \(0, 0\)"),
        (lambda: straight((0, 0, 0), "end", 2), "end must be a finite 3-vector"),
        (lambda: straight((0, 0, 0), (1, 0, 0), None), "n_elements must be a positive integer"),
        (lambda: straight((0, 0, 0), (1, 0, 0), 2.5), "n_elements must be a positive integer"),
        (lambda: straight((0, 0, 0), (1, 0, 0), "3"), "n_elements must be a positive integer"),
        (lambda: straight((0, 0, 0), (1, 0, 0), np.inf), "n_elements must be a positive integer"),
        (lambda: straight((0, 0, 0), (1, 0, 0), True), "n_elements must be a positive integer"),
        (lambda: arc((0, 0), 1.0, 0.0, 1.0, 2), "center must be a finite 3-vector"),
        (lambda: arc((0, 0, 0), -1.0, 0.0, 1.0, 2), "radius must be finite and > 0"),
        (lambda: arc((0, 0, 0), 1.0, "0", 1.0, 2), "angle0 must be a finite number, got '0'"),
        (lambda: arc((0, 0, 0), 1.0, 1.0, 1.0, 2), "angle0 and angle1 are both 1.0"),
    ],
)
def test_mesh_generators_name_their_bad_argument(call, message):
    with pytest.raises(ValueError, match=message):
        call()


def test_a_point_load_smearing_fits_on_its_beam():
    """A beam of length 2: a smearing (half-width) of 1 fits exactly, 1.0001 does not."""
    beam = Beam(straight((0, 0, 0), (2, 0, 0), 4, name="C"), SECTION)
    f = beam.point_load(1.0, (0, 1, 0), smearing=1.0)
    np.testing.assert_allclose(f.reshape(-1, 6)[:, 1].sum(), 1.0, rtol=1e-14)
    with pytest.raises(
        ValueError, match=r"smearing = 1.0001 m is more than half .* beam 'C' \(2 m\)"
    ):
        beam.point_load(1.0, (0, 1, 0), smearing=1.0001)


def test_a_slider_smearing_fits_on_its_line():
    from fvbeam import RigidBody, Structure

    beam = Beam(straight((0, 0, 0), (0.6, 0, 0), 2, name="C"), SECTION)
    structure = Structure([beam], bodies=[RigidBody("cart", (0.3, 0, 0))])
    chain = BeamChain(structure, "C")
    assert Slider("spherical", chain, "cart", smearing=0.3).smearing == 0.3
    with pytest.raises(ValueError, match=r"more than half the length of line 'C' of slider 'A'"):
        Slider("spherical", chain, "cart", smearing=0.31, name="A")
    with pytest.raises(ValueError, match="smearing must be a finite length >= 0, got -1"):
        Slider("spherical", chain, "cart", smearing=-1, name="A")


# -- the same checks from a scene -----------------------------------------------------------
FIG4 = (SCENES / "fig4_sliding_beams.toml").read_text()
RIGID = (SCENES / "rigid_lines.toml").read_text()


@pytest.mark.parametrize(
    "text,message",
    [
        (
            FIG4.replace('kind = "ux+rx"', 'kind = "ux+ux"'),
            "support[1].kind = 'ux+ux': names ux more than once",
        ),
        (
            FIG4.replace('kind = "clamp"', 'kind = "clmp"'),
            "support[0].kind = 'clmp': must be 'clamp', 'pin' or dof names from ux uy uz rx ry rz"
            " joined by '+' (did you mean 'clamp'?)",
        ),
        (
            FIG4.replace(
                'section = "tube"\nstraight', 'section = "tube"\nup = [2.0, 0.0, 0.0]\nstraight', 1
            ),
            "beam[0]: C: up = [1.0, 0.0, 0.0] is along the tangent [1.0, 0.0, 0.0]",
        ),
        (
            RIGID.replace(
                "end = [1.0, 1.0, 0.0]\n", "end = [1.0, 1.0, 0.0]\nup = [0.0, -1.0, 0.0]\n"
            ),
            "line[0]: rail: up = [0.0, -1.0, 0.0] is along the tangent [0.0, 1.0, 0.0]",
        ),
        (
            FIG4.replace("GAy = 1.1e8", "GAy = 1e15").replace("EJy = 4.1e4", "EJy = 1.0"),
            "section[0]: tube: stiffness is too ill-conditioned: its smallest EJy = 1 is 1e-15 "
            "of its largest GAy = 1e+15",
        ),
        (
            FIG4.replace('body = "P.start"', 'body = "P.start"\nsmearing = 0.31'),
            "slider[0]: smearing = 0.31 m is more than half the length of line 'C' of slider "
            "'A' (0.6 m)",
        ),
        (
            FIG1.replace("at = 1.0", "at = 1.0\nsmearing = 0.6"),
            "load[0].smearing = 0.6: smearing = 0.6 m is more than half the length of beam "
            "'cantilever' (1 m)",
        ),
    ],
    ids=["repeated dof", "unknown kind", "beam up", "line up", "conditioning", "slider", "load"],
)
def test_scene_input_checks(tmp_path, capsys, text, message):
    err = refused(tmp_path, text, capsys)
    assert message in err, err
    assert "invalid scene, 1 problem" in err


@pytest.mark.parametrize(
    "value, path", [([7, "bottom_friction"], "output.peak[0].of[0]"), (7, "output.peak[0].of")]
)
def test_a_value_or_list_is_judged_by_the_shape_given(value, path):
    """A key that takes a column or a list of columns (``output.peak.of``) reports a wrong
    entry of a list at that entry, and a wrong single value at the key: one problem, from the
    branch the scene's shape chose, never both."""
    from test_scenes import problems

    scene = tomllib.loads((SCENES / "landing_gear.toml").read_text())
    scene["output"]["peak"][0]["of"] = value
    found = problems(scene)
    assert [p.path for p in found] == [path]
