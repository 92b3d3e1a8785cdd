"""Scene sections from material and shape, and gravity in static studies: a section written
with its geometry and the same section written as its numbers give the same model and
results; each bad section is named; a cantilever under its own weight against the closed
form ``q L^4 / (8 EJ) + q L^2 / (2 GA)``.  The scenes ask for linear kinematics: these are the
linear model's closed forms and its lumped weight (the exact path's weight, a distributed
load on the current configuration, is tested in ``tests/test_exact_loads.py``)."""

import math
import tomllib

import numpy as np
import pytest
from test_condensed import agreement_bound
from test_scenes import SCENES, problems

from fvbeam import Section
from fvbeam.shapes import Material, Tube
from sliders.app.model import Model
from sliders.app.run import run
from sliders.app.scene import load_scene, parse_scene

EPS = np.finfo(float).eps
STEEL = {"E": 210e9, "nu": 0.3, "density": 7850.0}
TUBE = {"kind": "tube", "outer": 0.06, "inner": 0.05}
L = 2.0


def cantilever(section: dict, form: str = "fv3", elements: int = 4, **study) -> dict:
    """A cantilever along x, its tip loaded along every axis (tension, two shears, torsion):
    every stiffness of the section acts."""
    return {
        "kinematics": "linear",
        "formulation": form,
        "section": [{"name": "s", **section}],
        "beam": [
            {
                "name": "arm",
                "section": "s",
                "straight": {"start": [0.0, 0.0, 0.0], "end": [L, 0.0, 0.0], "elements": elements},
            }
        ],
        "support": [{"node": "arm.start"}],
        "load": [
            {
                "kind": "nodal",
                "node": "arm.end",
                "force": [1e3, 200.0, -300.0],
                "moment": [50.0, 0.0, 0.0],
            }
        ],
        "study": {"kind": "static", **study},
    }


def numbers_toml(section: Section) -> str:
    """The section as a scene's numbers, each float written as its repr (read back exactly)."""
    keys = ("EA", "GAy", "GAz", "GJ", "EJy", "EJz")
    lines = [f"{k} = {float(v)!r}" for k, v in zip(keys, section.stiffness.diagonal(), strict=True)]
    lines.append(f"mass_per_length = {float(section.mass_per_length)!r}")
    lines.append(f"inertia = {[float(x) for x in section.inertia.diagonal()]!r}")
    return "\n".join(lines)


def test_geometry_and_its_numbers_give_the_same_model_and_results():
    """The section from material and shape, and the scene that writes its stiffnesses, mass
    and inertia as numbers: the same section bit for bit, so the same solution bit for bit,
    with and without gravity."""
    python = Section.from_shape(Material(**STEEL), Tube(outer=0.06, inner=0.05))
    numbers = tomllib.loads(numbers_toml(python))
    for study in ({}, {"gravity": [0.0, 0.0, -9.81]}):
        geometric = Model(parse_scene(cantilever({"material": STEEL, "shape": TUBE}, **study)))
        written = Model(parse_scene(cantilever(numbers, **study)))
        a, b = geometric.beams[0].section, written.beams[0].section
        np.testing.assert_array_equal(a.stiffness, python.stiffness)
        np.testing.assert_array_equal(a.stiffness, b.stiffness)
        np.testing.assert_array_equal(a.inertia, b.inertia)
        assert a.mass_per_length == b.mass_per_length
        (first,), (second,) = run(geometric, False).samples, run(written, False).samples
        np.testing.assert_array_equal(first.load, second.load)
        np.testing.assert_array_equal(first.solution.q, second.solution.q)


@pytest.mark.parametrize(
    "section, where, message",
    [
        (
            {"material": STEEL, "shape": TUBE, "EA": 1.0},
            "section[0]",
            "not both (found EA, material, shape)",
        ),
        ({}, "section[0]", "give its six stiffnesses (EA, GAy, GAz, GJ, EJy, EJz), or its"),
        (
            {"EA": 1.0, "GAy": 1.0, "GAz": 1.0, "GJ": 1.0, "EJy": 1.0},
            "section[0].EJz",
            "missing: give all six stiffnesses, or material and shape instead",
        ),
        ({"material": STEEL}, "section[0].shape", "missing: a section's material needs its shape"),
        (
            {"material": STEEL, "shape": TUBE, "mass_per_length": 2.0},
            "section[0].mass_per_length",
            "follows from material.density and the shape: leave it out",
        ),
        (
            {"material": {"E": 210e9, "nu": 0.3, "G": 80e9}, "shape": TUBE},
            "section[0].material",
            "give exactly one of nu, G",
        ),
        (
            {"material": STEEL, "shape": {"kind": "tube", "outer": 0.05, "inner": 0.06}},
            "section[0]",
            "shape.inner must be less than shape.outer = 0.05, got 0.06",
        ),
    ],
)
def test_a_bad_section_is_named(section, where, message):
    found = {p.path: p.message for p in problems(cantilever(section))}
    assert where in found and message in found[where], found


def test_a_shape_of_unknown_kind_names_the_kinds():
    with pytest.raises(ValueError, match=r"section\[0\]\.shape\.kind = 'square'"):
        parse_scene(cantilever({"material": STEEL, "shape": {"kind": "square", "side": 1.0}}))


def test_a_dynamic_study_needs_the_density():
    scene = cantilever({"material": {"E": 210e9, "nu": 0.3}, "shape": TUBE})
    scene["study"] = {"kind": "dynamic", "t_end": 0.01, "step": 0.001}
    (problem,) = problems(scene)
    assert problem.path == "section[0].material.density"
    assert problem.message == "a dynamic study needs the mass of every beam's section"


def test_gravity_on_nothing_with_a_mass_is_named():
    """Named where the mass is missing, the section's density (no body has a mass)."""
    scene = cantilever({"material": {"E": 210e9, "nu": 0.3}, "shape": TUBE}, gravity=[0, 0, -9.81])
    (problem,) = problems(scene)
    assert problem.path == "section[0].material.density" and "weigh nothing" in problem.message


def own_weight(form: str, elements: int, mass: str):
    """The tip deflection of the steel tube cantilever under its own weight alone, its closed
    form (Timoshenko: bending q L^4 / (8 EJ), shear q L^2 / (2 GA)), the sample and the tip's
    uz dof."""
    scene = cantilever({"material": STEEL, "shape": TUBE}, form, elements)
    scene["load"] = []
    scene["study"].update(gravity=[0.0, 0.0, -9.81], mass=mass)
    (sample,) = run(Model(parse_scene(scene)), False).samples
    section = sample.statics.structure.beams[0].section
    EJ, GA = section.stiffness[4, 4], section.stiffness[2, 2]
    q = section.mass_per_length * 9.81
    tip = sample.statics.structure.node_dofs("arm.end")[2]
    return -sample.solution.q[tip], q * L**4 / (8 * EJ) + q * L**2 / (2 * GA), sample, tip


@pytest.mark.parametrize("form, mass", [("cubic", "consistent"), ("galerkin-p2", "lumped")])
@pytest.mark.parametrize("elements", [1, 3])
def test_own_weight_of_a_cantilever_is_the_closed_form(form, mass, elements):
    """The weight M g on the cubic element's consistent mass is its consistent load, and the
    P2 element's lumped mass gives its shape functions' load: their nodal values are exact
    for any load (the homogeneous solutions lie in their trial spaces), so the tip deflection
    is the closed form to the solve's round-off bound (tests/test_condensed.py) plus the
    closed form's own rounding (8 eps)."""
    got, exact, sample, tip = own_weight(form, elements, mass)
    statics, solution = sample.statics, sample.solution
    bound = agreement_bound(statics, solution, solution, sample.load)
    where = np.searchsorted(statics.free, tip)
    assert abs(got - exact) <= bound[where] + 8 * EPS * exact


def test_own_weight_on_fv3_converges_at_second_order():
    """fv3's lumped mass puts each region's weight at its node, without the end regions'
    couple about their nodes (fvbeam.mass, next test), so its deflection converges as h^2
    (where its own distributed load is exact): each halving of h divides the error by 4, to
    1 % (the next term of the error, O(h^4), is 1/16 of the first by 2 elements)."""
    errors = []
    for n in (2, 4, 8):
        got, exact, _, _ = own_weight("fv3", n, "lumped")
        errors.append(abs(got / exact - 1))
    orders = [math.log2(a / b) for a, b in zip(errors[:-1], errors[1:], strict=True)]
    assert all(abs(p - 2) <= 0.01 for p in orders), orders
    # docs/scenes.md quotes the errors with 4 and 8 elements
    assert (round(100 * errors[1], 2), round(100 * errors[2], 2)) == (0.56, 0.14)


@pytest.mark.parametrize("form", ["fv2", "fv3"])
def test_the_weight_of_a_finite_volume_beam_is_its_regions_weight(form):
    """M g with fv's lumped mass gives each node its region's weight: the forces of the
    distributed load m g on the test functions (the same integrals of the region
    indicators, to round-off), and no couple, where the distributed load has the end
    regions' couples about the end nodes (and only those)."""
    _, _, sample, _ = own_weight(form, 5, "lumped")
    structure = sample.statics.structure
    beam = structure.beams[0]
    q = beam.section.mass_per_length * 9.81
    distributed = structure.gather(0, beam.distributed_load((0.0, 0.0, -q))).reshape(-1, 6)
    weight = sample.load.reshape(-1, 6)
    np.testing.assert_allclose(weight[:, :3], distributed[:, :3], rtol=0, atol=4 * EPS * q * L)
    assert not weight[:, 3:].any()
    ends = [structure.node_slot(f"arm.{end}") for end in ("start", "end")]
    assert np.all(np.abs(np.delete(distributed[:, 3:], ends, axis=0)) <= 4 * EPS * q * L**2)
    assert np.all(np.abs(distributed[ends, 4]) > 0)


def test_a_load_factor_sweep_keeps_the_weight():
    """Gravity is a dead load: a load-factor sweep scales the [[load]]s only, so at factor 0
    the solution is the weight's alone and at 1 the weight's plus the load's (linear)."""
    weighted = cantilever({"material": STEEL, "shape": TUBE}, gravity=[0.0, 0.0, -9.81])
    weighted["study"].update(kind="sweep", parameter={"kind": "load_factor"}, values=[0.0, 1.0])
    zero, one = run(Model(parse_scene(weighted)), False).samples
    alone = cantilever({"material": STEEL, "shape": TUBE}, gravity=[0.0, 0.0, -9.81])
    alone["load"] = []
    (weight,) = run(Model(parse_scene(alone)), False).samples
    loaded = run(Model(parse_scene(cantilever({"material": STEEL, "shape": TUBE}))), False)
    np.testing.assert_array_equal(zero.load, weight.load)
    np.testing.assert_array_equal(one.load, weight.load + loaded.samples[0].load)
    scale = np.abs(one.solution.q).max()
    np.testing.assert_allclose(zero.solution.q, weight.solution.q, rtol=0, atol=1e-12 * scale)


def test_a_body_weighs_at_its_centre_of_mass():
    """A body at the tip of a massless cantilever, its centre of mass 0.5 m beyond the node
    along x: the weight m g at the tip and the couple of its arm, m g 0.5 about -y... so the
    tip rotation ry is m g (L^2 / (2 EJ) + 0.5 L / EJ) (a tip force and a tip couple)."""
    section = {"material": {"E": 210e9, "nu": 0.3}, "shape": TUBE}
    scene = cantilever(section, "cubic", 2, gravity=[0.0, 0.0, -9.81])
    scene["load"] = []
    scene["body"] = [
        {"name": "payload", "position": [L, 0.0, 0.0], "mass": 10.0, "centre": [0.5, 0.0, 0.0]}
    ]
    scene["tie"] = [{"nodes": ["arm.end", "payload"]}]
    (sample,) = run(Model(parse_scene(scene)), False).samples
    structure = sample.statics.structure
    EJ = structure.beams[0].section.stiffness[4, 4]
    W = 10.0 * 9.81
    dofs = structure.node_dofs("payload")
    np.testing.assert_allclose(sample.load[dofs], [0, 0, -W, 0, W * 0.5, 0], rtol=4 * EPS, atol=0)
    ry = sample.solution.q[dofs[4]]
    expected = W * L**2 / (2 * EJ) + W * 0.5 * L / EJ
    assert ry == pytest.approx(expected, rel=1e-10)


def test_the_shipped_tube_cantilever_is_the_closed_form():
    """studies/scenes/tube_cantilever.toml: the tip deflection under the weight and the tip
    load P is (q L^4 / 8 + P L^3 / 3) / EJ + (q L^2 / 2 + P L) / GA (cubic elements,
    consistent mass: exact at the nodes, as above), to the solve's round-off bound."""
    (sample,) = run(Model(load_scene(SCENES / "tube_cantilever.toml")), False).samples
    structure = sample.statics.structure
    section = structure.beams[0].section
    EJ, GA = section.stiffness[4, 4], section.stiffness[2, 2]
    q, P = section.mass_per_length * 9.81, 100.0
    exact = (q * L**4 / 8 + P * L**3 / 3) / EJ + (q * L**2 / 2 + P * L) / GA
    tip = structure.node_dofs("arm.end")[2]
    bound = agreement_bound(sample.statics, sample.solution, sample.solution, sample.load)
    got = -sample.solution.q[tip]
    assert abs(got - exact) <= bound[np.searchsorted(sample.statics.free, tip)] + 8 * EPS * exact


def test_a_consistent_weight_on_finite_volume_beams_is_named():
    scene = cantilever({"material": STEEL, "shape": TUBE}, gravity=[0, 0, -9.81], mass="consistent")
    (problem,) = problems(scene)
    assert problem.path == "study.mass" and "take the lumped mass only" in problem.message
