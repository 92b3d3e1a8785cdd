"""Modes about a preloaded exact state: the geometric stiffness of an axial force
(sliders.solve.modes.Preload, fvbeam.exact_structure.ExactStructure.mass, the modes study with
``kinematics = "exact"``).

A column of length 1 along x (EJ = 1 about z, 4 about y, so the lowest bending is in the
x-y plane; GA = 100, EA = 1e4, m = 1, rotary inertia 1e-3 about z), under a dead axial tip
force ``P`` (compressive; negative in tension).

Tolerance sources:

* Mesh convergence against the exact frequency equations of the linearised Simo-Reissner
  beam (:func:`fvbeam.closed_forms.timoshenko_simply_supported_frequencies` with an
  ``AxialForce``, the hinged
  column; :func:`fvbeam.closed_forms.timoshenko_cantilever_determinant` with an ``AxialForce``,
  the cantilever under a dead tip force): the observed order ``log2(e_n / e_2n)`` on n, 2n, 4n
  elements (``MESHES``) within 0.5 of 2 and the finest error below ``e_2n / 2^1.5``, as
  the unloaded beams' (``tests/test_simply_supported_modes.py``: fv2 and fv3 with the
  lumped mass are second order; measured here 1.95 to 2.29).
* The closed form's limits: at ``P = 0`` it is Timoshenko's equation, both backward stable
  roots of one quadratic (``1e-13``, a few ``u``); its Euler-Bernoulli limit
  ``omega^2 = omega_0^2 (1 - P / P_E)`` (``GA = EA = 1e8``, no rotary inertia) differs by
  the shear and the axial strain's relative terms ``EJ k^2 / GA + P / GA + P / EA`` at
  leading order (the closed form's docstring: ``c``, ``g`` and ``a`` expanded); the bound is
  twice their sum.
* The linear limit: at ``P = 0`` the exact tangent is the linear stiffness and the state's
  rotations the identity, so the modes are today's linear ones to the eigen solvers'
  backward error (``EIGEN``, 1e-9: condition numbers below 1e6, ``u = 2.2e-16``).
* Frame invariance of the mass: the lumped mass turned by a rigid rotation is the mass of the
  turned beam, entry by entry, to round-off (1e-14 of its largest entry).
"""

import csv
import tomllib

import numpy as np
import pytest

from fvbeam import Beam, Section, Structure, Support, closed_forms, formulation, straight
from fvbeam.closed_forms import AxialForce
from fvbeam.exact_beam import ExactState
from fvbeam.exact_statics import solve_static
from fvbeam.exact_structure import ExactStructure
from sliders.app.cli import main
from sliders.app.model import Model
from sliders.app.run import run
from sliders.app.scene import parse_scene
from sliders.solve.modes import PRELOAD_WARNING, Preload, modes_about
from sliders.solve.statics import SliderSolution, SliderStatics

EIGEN = 1e-9
FREQUENCIES = closed_forms.timoshenko_simply_supported_frequencies
EJ, GA, EA, M, RHO_J = 1.0, 100.0, 1e4, 1.0, 1e-3
#: Haringx's buckling load of the hinged column (closed form's docstring), about 9.02.
P_H = (np.sqrt(1 + 4 * EJ * np.pi**2 / GA) - 1) * GA / 2


def section() -> Section:
    return Section.diagonal(
        EA=EA,
        GAy=GA,
        GAz=GA,
        GJ=1e2,
        EJy=4 * EJ,
        EJz=EJ,
        mass_per_length=M,
        inertia=np.diag([5 * RHO_J, 4 * RHO_J, RHO_J]),
    )


#: Supports: hinged (pinned at 0 with the twist held, on a roller along x at 1) and clamped.
SUPPORTS = {
    "hinged": [Support(0, "start", "ux+uy+uz+rx"), Support(0, "end", "uy+uz")],
    "clamped": [Support(0, "start")],
}


#: Meshes of the convergence study: fv3 from 4 elements (already asymptotic: order 2.29 from
#: 4 to 8); on 32 fv3 elements the exact statics of the bar needs tens of load steps.
MESHES = {"fv2": (8, 16, 32), "fv3": (4, 8, 16)}


def column(name: str, n: int, P: float, held: str) -> tuple[SliderStatics, SliderSolution, Preload]:
    """The column of ``n`` elements under ``P``: its statics, its exact state as a solution
    and the preload there."""
    mesh = straight((0, 0, 0), (1, 0, 0), n, formulation(name).nodes_per_element)
    structure = Structure([Beam(mesh, section(), name)])
    statics = SliderStatics(structure, SUPPORTS[held], [])
    exact = ExactStructure(structure)
    f = structure.nodal_load("beam.end", (-P, 0.0, 0.0))
    state = solve_static(exact, f, structure.support_dofs(SUPPORTS[held])).state
    solution = SliderSolution(exact.displacements(state), [], [0.0])
    return statics, solution, Preload.at(exact, state)


def first(name: str, n: int, P: float, held: str) -> float:
    statics, solution, preload = column(name, n, P, held)
    return float(modes_about(statics, solution, 1, preload=preload).omega[0])


def assert_second_order(errors: list[float]) -> None:
    for coarse, fine in zip(errors, errors[1:], strict=False):
        assert abs(np.log2(coarse / fine) - 2) < 0.5, np.log2(coarse / fine)
    assert errors[2] < errors[1] / 2**1.5


def test_the_closed_form_has_timoshenkos_and_eulers_limits():
    unloaded = FREQUENCIES(3, GA=GA, rhoJ=RHO_J, axial=AxialForce(0.0, EA))
    timoshenko = FREQUENCIES(3, GA=GA, rhoJ=RHO_J)
    np.testing.assert_allclose(unloaded, timoshenko, rtol=1e-13)
    stiff = 1e8
    k = np.pi * np.arange(1, 4)
    for P in (-20.0, -5.0, 2.0, 6.0, 9.0):
        omega = FREQUENCIES(3, GA=stiff, axial=AxialForce(P, stiff))
        euler = k**4 * (1 - P / k**2)  # omega_0^2 (1 - P / P_E), P_E = EJ k^2
        bound = 2 * (k**2 / stiff + abs(P) / stiff + abs(P) / stiff)
        np.testing.assert_allclose(omega**2 / euler - 1, 0.0, atol=bound.max())
    # with shear the first frequency vanishes at Haringx's load
    below, above = (
        FREQUENCIES(1, GA=GA, rhoJ=RHO_J, axial=AxialForce(P))[0]
        for P in (P_H * (1 - 1e-6), P_H * (1 + 1e-6))
    )
    assert below > 0 and np.isnan(above)


@pytest.mark.parametrize("name", ["fv2", "fv3"])
@pytest.mark.parametrize("P", [0.6 * P_H, -20.0])
def test_a_hinged_column_under_an_axial_force_has_the_preloaded_frequency(name, P):
    exact = FREQUENCIES(1, GA=GA, m=M, rhoJ=RHO_J, axial=AxialForce(P, EA))[0]
    errors = [abs(first(name, n, P, "hinged") / exact - 1) for n in MESHES[name]]
    assert_second_order(errors)
    unloaded = FREQUENCIES(1, GA=GA, rhoJ=RHO_J)[0]
    # compression lowers the frequency, tension raises it (string stiffening)
    assert (exact < unloaded) == (P > 0)


def test_a_cantilever_under_a_dead_tip_force_has_its_preloaded_frequency():
    P = 1.5  # below the cantilever's buckling load, about pi^2 / 4
    args = (1.0, EJ, GA, M, RHO_J, AxialForce(P, EA))
    exact = closed_forms.frequency_roots(
        closed_forms.timoshenko_cantilever_determinant, 1, 0.01, args
    )[0]
    unloaded = closed_forms.timoshenko_cantilever_frequencies(1, GA=GA, rhoJ=RHO_J)[0]
    assert 0 < exact < unloaded
    errors = [abs(first("fv2", n, P, "clamped") / exact - 1) for n in (8, 16, 32)]
    assert_second_order(errors)


def test_without_load_the_modes_are_the_linear_ones():
    statics, solution, preload = column("fv2", 8, 0.0, "hinged")
    exact = modes_about(statics, solution, 6, preload=preload)
    linear = modes_about(statics, statics.solve(np.zeros(statics.structure.n_dofs)), 6)
    np.testing.assert_allclose(exact.omega, linear.omega, rtol=EIGEN)


@pytest.mark.parametrize("name,n", [("fv2", 1000), ("fv3", 64)])
def test_a_fine_columns_exact_state_converges_in_one_load_step(name, n):
    """The straight state is one Newton iteration: at fixed rotations the force balances are
    affine in the positions, and the position correction satisfies them
    (:mod:`fvbeam.exact_statics`); its residual is then at the round-off of the positions,
    ``eps |x_a|`` differenced over an element, which the floor states."""
    mesh = straight((0, 0, 0), (1, 0, 0), n, formulation(name).nodes_per_element)
    structure = Structure([Beam(mesh, section(), name)])
    f = structure.nodal_load("beam.end", (-0.6 * P_H, 0.0, 0.0))
    fixed = structure.support_dofs(SUPPORTS["hinged"])
    result = solve_static(ExactStructure(structure), f, fixed)
    assert result.attempts == 1 and result.floor_ratio < 1


def test_a_column_beyond_its_buckling_load_is_named_buckled():
    statics, solution, preload = column("fv2", 8, 1.2 * P_H, "hinged")
    with pytest.raises(ValueError, match="buckled state"):
        modes_about(statics, solution, 1, preload=preload)


def test_the_mass_turns_with_the_sections():
    quarter = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # x to y
    along_x = Structure([Beam(straight((0, 0, 0), (1, 0, 0), 4, 2), section(), "fv2")])
    along_y = Structure([Beam(straight((0, 0, 0), (0, 1, 0), 4, 2), section(), "fv2")])
    exact = ExactStructure(along_x)
    reference = exact.reference()
    n = len(reference.x)
    turned = ExactState(reference.x @ quarter.T, np.broadcast_to(quarter, (n, 3, 3)))
    M_turned, M_y = exact.mass(turned).toarray(), along_y.mass().toarray()
    np.testing.assert_allclose(M_turned, M_y, atol=1e-14 * abs(M_y).max())
    assert not np.allclose(exact.mass(reference).toarray(), M_y)


SCENE = """
title = "column"
formulation = "fv2"
kinematics = "exact"

[[section]]
name = "rod"
EA = 1e4
GAy = 100.0
GAz = 100.0
GJ = 100.0
EJy = 4.0
EJz = 1.0
mass_per_length = 1.0
inertia = [5e-3, 4e-3, 1e-3]

[[beam]]
name = "rod"
section = "rod"
straight = { start = [0.0, 0.0, 0.0], end = [1.0, 0.0, 0.0], elements = 16 }

[[support]]
node = "rod.start"
kind = "ux+uy+uz+rx"

[[support]]
node = "rod.end"
kind = "uy+uz"

[[load]]
kind = "nodal"
node = "rod.end"
force = [-5.0, 0.0, 0.0]

[study]
kind = "modes"
count = 2
"""


def test_a_modes_study_with_exact_kinematics_takes_the_preload(tmp_path):
    data = tomllib.loads(SCENE)
    results = run(Model(parse_scene(data, tmp_path, "column.toml")), progress=False)
    assert results.kinematics.startswith("kinematics: exact")
    assert results.modes is not None
    omega = results.modes[0].modes.omega
    statics, solution, preload = column("fv2", 16, 5.0, "hinged")
    np.testing.assert_allclose(omega, modes_about(statics, solution, 2, preload=preload).omega)
    # auto takes the loaded state exact (its bound sees no rotation: the column is straight)
    data["kinematics"] = "auto"
    auto = run(Model(parse_scene(data, tmp_path, "column.toml")), progress=False)
    assert auto.kinematics.startswith("kinematics: exact (auto: modes about a loaded state")
    assert auto.modes is not None
    np.testing.assert_array_equal(auto.modes[0].modes.omega, omega)
    # linear kinematics keeps the unloaded stiffness, and says so
    data["kinematics"] = "linear"
    with pytest.warns(UserWarning, match="geometric stiffness"):
        linear = run(Model(parse_scene(data, tmp_path, "column.toml")), progress=False)
    assert linear.modes is not None and linear.modes[0].modes.omega[0] > omega[0] * 1.1
    assert "not included" in PRELOAD_WARNING


def test_a_load_factor_sweep_follows_the_modes_towards_the_buckling_load(tmp_path):
    values = (0.0, 0.5, 1.0, 1.5)  # P = 5 value, up to 0.83 of the buckling load
    sweep = f'parameter = {{ kind = "load_factor" }}\nvalues = {list(values)}\n'
    path = tmp_path / "column.toml"
    path.write_text(SCENE.replace("count = 2\n", "count = 2\n" + sweep))
    assert main(["run", str(path), "--out", str(tmp_path / "out")]) == 0
    with open(tmp_path / "out" / "modes.csv", newline="") as handle:
        rows = [r for r in csv.DictReader(handle) if r["mode"] == "1"]
    hertz = np.array([float(r["frequency_hz"]) for r in rows])
    expected = [first("fv2", 16, 5.0 * v, "hinged") / (2 * np.pi) for v in values]
    np.testing.assert_allclose(hertz, expected, rtol=EIGEN)
    assert np.all(np.diff(hertz) < 0)
    # the hinged column's first shape is sin(pi x) under any axial force (closed form):
    # the discrete shapes differ by O(h^2), their MAC from 1 by its square
    assert all(float(r["mac"]) > 1 - (1 / 16) ** 4 for r in rows[1:])
