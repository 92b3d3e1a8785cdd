"""Large scenes through the command, and the singular-structure diagnosis at their size.

A cantilever of 1e4 fv3 elements (2e4 nodes, 1.2e5 dofs) is well within what the solvers
factorise in linear time; what must not happen on the way is a dense copy of anything the
size of the problem (a dense matrix of its dofs would take 115 GB; LAPACK refuses it).
The diagnosis (:mod:`sliders.solve.diagnosis`) is held to two facts: a clamped cantilever
is regular; a structure with a free part is singular, and the free motions it names are
exactly the free rigid motions of that part (:func:`fvbeam.mechanism.rigid_modes`, named in
any basis alike by :func:`fvbeam.mechanism.motion_phrases`).
"""

from __future__ import annotations

import csv

import numpy as np
import pytest
import scipy.sparse as sp

from fvbeam import Beam, Section, Structure, straight
from fvbeam.closed_forms import cantilever_exact
from fvbeam.mechanism import free_motion_message, motion_phrases, rigid_modes
from fvbeam.support import Support, complement
from sliders.app.cli import main
from sliders.solve.diagnosis import singular_motion
from sliders.solve.mechanism import REMEDY

EPS = np.finfo(float).eps
ELEMENTS = 10_000
L, EJ, GA, F = 10.0, 1.75e6, 8e8, 1e3
#: The equilibrated operator's condition number at 1e4 elements (least singular value
#: 1.4e-13 of the largest, measured by inverse iteration): the forward error of a backward
#: stable solve is within it times eps (Higham, Thm. 7.2).
CONDITION = 1 / 1.4e-13
SECTION = Section.diagonal(EA=2.1e9, GAy=GA, GAz=GA, GJ=1.6e6, EJy=EJ, EJz=EJ)

# the linear solve at scale against the linear closed form: kinematics asked for
SCENE = f"""
kinematics = "linear"
title = "long cantilever"
formulation = "fv3"

[[section]]
name = "steel"
EA = 2.1e9
GAy = {GA}
GAz = {GA}
GJ = 1.6e6
EJy = {EJ}
EJz = {EJ}

[[beam]]
name = "cantilever"
section = "steel"
straight = {{ start = [0.0, 0.0, 0.0], end = [{L}, 0.0, 0.0], elements = {ELEMENTS} }}

[[support]]
node = "cantilever.start"

[[load]]
kind = "nodal"
node = "cantilever.end"
force = [0.0, {F}, 0.0]

[study]
kind = "static"
planar = PLANAR

[output]
csv = ["nodes"]
[output.nodes]
nodes = ["cantilever.end"]
"""


@pytest.mark.parametrize("planar", ["true", "false"])
def test_a_cantilever_of_1e4_elements_runs_through_the_command(tmp_path, planar):
    """``fvslider run`` of the static scene, solved in its plane (half the dofs held) and in
    three dimensions: the tip deflection is Timoshenko's ``F L^3 / (3 EJ) + F L / GA``
    (fv3 is exact at the nodes under end loads), within the condition number times eps."""
    scene = tmp_path / "cantilever.toml"
    scene.write_text(SCENE.replace("PLANAR", planar))
    assert main(["run", str(scene), "--out", str(tmp_path / "out")]) == 0
    with open(tmp_path / "out" / "nodes.csv") as stream:
        (row,) = list(csv.DictReader(stream))
    bending, shear, rotation = cantilever_exact(L, L, EJ, GA, F)
    assert float(row["uy"]) == pytest.approx(bending + shear, rel=CONDITION * EPS)
    assert float(row["rz"]) == pytest.approx(rotation, rel=CONDITION * EPS)


def beams(free_part: bool, elements: int = ELEMENTS) -> tuple[Structure, np.ndarray]:
    """A cantilever of ``elements`` clamped at its start and, with ``free_part``, a second
    beam of as many elements beside it that nothing holds; the structure and its free
    dofs."""
    parts = [Beam(straight((0, 0, 0), (L, 0, 0), elements, 3, name="cantilever"), SECTION, "fv3")]
    if free_part:
        mesh = straight((0, 1, 0), (L, 1, 0), elements, 3, name="piston")
        parts.append(Beam(mesh, SECTION, "fv3"))
    structure = Structure(parts)
    return structure, complement(
        structure.n_dofs, structure.support_dofs([Support("cantilever.start")])
    )


def operator(structure: Structure, free: np.ndarray) -> sp.csr_matrix:
    return structure.tangent(np.zeros(structure.n_dofs)).tocsr()[free][:, free]


def test_a_regular_operator_has_no_free_motion():
    """A clamped cantilever of 100 elements (well conditioned: the equilibrated operator's
    least singular value far above 1e-12 of its largest): none is named."""
    structure, free = beams(free_part=False, elements=100)
    K = operator(structure, free)
    assert singular_motion(K, rigid_modes(structure, free), structure, free, [], REMEDY) is None


def test_a_free_part_is_named_without_a_dense_matrix():
    """The 1e4-element cantilever beside a free beam of as many elements (2.4e5 unknowns: a
    dense copy would take 460 GB): the message names the free beam's six rigid motions,
    as the free rigid motions of the structure are named (the null space found is their
    span)."""
    structure, free = beams(free_part=True)
    K = operator(structure, free)
    rigid = rigid_modes(structure, free)
    assert rigid.k == 6
    expected = free_motion_message(
        "supports and sliders", motion_phrases(rigid, np.eye(rigid.k)), REMEDY
    )
    assert singular_motion(K, rigid, structure, free, [], REMEDY) == expected
    assert "beam 'piston' translating along x, y and z and rotating" in expected


#: The dynamic scene: the static one with a mass (steel, 7850 kg/m^3 on 0.01 m^2) started
#: from its static equilibrium under the tip load, a few steps of 1 ms.
DYNAMIC = SCENE.replace(
    f"EJz = {EJ}\n", f"EJz = {EJ}\nmass_per_length = 78.5\ninertia = [1e-4, 1e-4, 1e-4]\n"
).replace(
    '[study]\nkind = "static"\nplanar = PLANAR\n',
    '[study]\nkind = "dynamic"\nt_end = 0.003\nstep = 0.001\nplanar = true\n',
)


def test_a_dynamic_cantilever_of_1e4_elements_runs_through_the_command(tmp_path):
    """``fvslider run`` of a dynamic study of the 1e4-element cantilever (6e4 unknowns in
    its plane), started from its static equilibrium under the constant tip load: an
    equilibrium is a fixed point of the integrator, so the tip stays at Timoshenko's
    deflection and rotation at every step, within the condition number times eps (the
    step's operator ``K + M / (beta h^2)`` is better conditioned than ``K``)."""
    scene = tmp_path / "cantilever.toml"
    scene.write_text(DYNAMIC)
    assert main(["run", str(scene), "--out", str(tmp_path / "out")]) == 0
    with open(tmp_path / "out" / "nodes.csv") as stream:
        rows = list(csv.DictReader(stream))
    assert [int(row["step"]) for row in rows] == [0, 1, 2, 3]
    bending, shear, rotation = cantilever_exact(L, L, EJ, GA, F)
    for row in rows:
        assert float(row["uy"]) == pytest.approx(bending + shear, rel=CONDITION * EPS)
        assert float(row["rz"]) == pytest.approx(rotation, rel=CONDITION * EPS)
