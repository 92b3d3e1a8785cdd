"""Point, smeared and distributed loads against conservation laws and the kernel closed forms.

Tolerances: every identity here is exact up to roundoff in sums of O(10) terms of order one,
so 1e-12 (absolute, loads of order one) is ~1e3 machine epsilons.
"""

import numpy as np
import pytest

from fvbeam import Beam, Section, arc, straight
from fvbeam.elements import evaluation_points

EXACT = 1e-12
SECTION = Section.diagonal(EA=10.0, GAy=2.0, GAz=3.0, GJ=1.0, EJy=1.5, EJz=0.8)
FORMULATIONS = [("fv2", 2), ("fv3", 3), ("galerkin-p1", 2), ("galerkin-p2", 3), ("cubic", 2)]
F = np.array([0.3, -1.2, 0.7])
M = np.array([0.1, 0.4, -0.5])


def oblique_beam(name, npe, n=4):
    direction = np.array([1.0, 2.0, -0.5])
    return Beam(straight((0.5, -1, 2), np.array([0.5, -1, 2]) + direction, n, npe), SECTION, name)


def resultants(beam, f):
    """Total force, and total moment about the origin, of a nodal load vector."""
    nodal = f.reshape(-1, 6)
    force = nodal[:, :3].sum(axis=0)
    moment = (nodal[:, 3:] + np.cross(beam.mesh.points, nodal[:, :3])).sum(axis=0)
    return force, moment


@pytest.mark.parametrize("name,npe", FORMULATIONS)
@pytest.mark.parametrize("smearing,kernel", [(0.0, "box"), (0.05, "box"), (0.05, "hat")])
@pytest.mark.parametrize("fraction", [0.0, 0.13, 0.5, 0.77, 1.0])
def test_point_load_keeps_force_and_moment(name, npe, smearing, kernel, fraction):
    """Virtual work of a rigid motion: the test functions reproduce rigid motions (fv: by
    construction, Galerkin: partition of unity and linear completeness on a straight beam,
    cubic: rigid motions are homogeneous solutions of the beam, docs/theory.md Sec. 9),
    so the nodal loads have the resultant F and moment x(xi) x F + M of the applied load."""
    beam = oblique_beam(name, npe)
    xi = fraction * beam.mesh.length
    f = beam.point_load(xi, F, M, smearing=smearing * beam.mesh.length, kernel=kernel)
    force, moment = resultants(beam, f)
    e, X = beam.mesh.locate(xi)
    x = beam.mesh.positions(e, X)
    np.testing.assert_allclose(force, F, atol=EXACT)
    if smearing == 0 or 0.05 < fraction < 0.95:
        np.testing.assert_allclose(moment, np.cross(x, F) + M, atol=EXACT)


@pytest.mark.parametrize("npe", [2, 3])
@pytest.mark.parametrize("kernel", ["box", "hat"])
def test_smeared_shares_across_an_evaluation_point(npe, kernel):
    """Share of the downstream node as the load crosses an evaluation point p: the box kernel
    gives the ramp 1/2 + d/(2 eps) (the reference implementation's weights), the hat kernel
    its integral 1/2 + d/eps - d|d|/(2 eps^2), d = xi - p."""
    n, eps = 3, 0.02
    beam = Beam(straight((0, 0, 0), (1, 0, 0), n, npe), SECTION, f"fv{npe}")
    p = (1 + evaluation_points(npe)[-1]) / n  # last evaluation point of element 1
    downstream = 2  # vertex 2 closes element 1
    for d in np.linspace(-eps, eps, 9):
        f = beam.point_load(p + d, (0, 1, 0), smearing=eps, kernel=kernel).reshape(-1, 6)
        expected = (
            0.5 + d / (2 * eps) if kernel == "box" else 0.5 + d / eps - d * abs(d) / (2 * eps**2)
        )
        assert f[downstream, 1] == pytest.approx(expected, abs=EXACT)


@pytest.mark.parametrize("npe", [2, 3])
def test_smearing_makes_the_load_continuous_in_xi(npe):
    """Without smearing the load jumps by F at an evaluation point; with the box kernel the
    load vector is Lipschitz in xi with constant |F| / (2 eps) per node (ramp slope)."""
    beam = Beam(straight((0, 0, 0), (1, 0, 0), 2, npe), SECTION, f"fv{npe}")
    p = evaluation_points(npe)[0] / 2
    delta = 1e-7
    jump0 = np.abs(beam.point_load(p + delta, (0, 1, 0)) - beam.point_load(p - delta, (0, 1, 0)))
    assert jump0.reshape(-1, 6)[:, 1].max() == pytest.approx(1.0, abs=EXACT)
    eps = 0.01
    jump = np.abs(
        beam.point_load(p + delta, (0, 1, 0), smearing=eps)
        - beam.point_load(p - delta, (0, 1, 0), smearing=eps)
    )
    lever = 1.0  # moments carry the force times a lever arm shorter than the beam
    assert jump.max() <= 2 * delta / (2 * eps) * (1 + lever) + EXACT


@pytest.mark.parametrize("name,npe", FORMULATIONS)
def test_smearing_inside_one_region_changes_nothing_on_a_straight_beam(name, npe):
    """A symmetric kernel on a straight beam, away from region boundaries, has the same
    virtual work as the point load against rigid motions (fv) and linear shape functions
    (galerkin-p1); quadratic P2 and cubic shape functions see the kernel's second moment
    instead."""
    beam = oblique_beam(name, npe, n=2)
    xi = 0.3 * beam.mesh.length if npe == 3 else 0.1 * beam.mesh.length
    f0 = beam.point_load(xi, F, M)
    f1 = beam.point_load(xi, F, M, smearing=0.01 * beam.mesh.length, kernel="hat")
    if name in ("galerkin-p2", "cubic"):
        assert np.abs(f1 - f0).max() > 0
    else:
        np.testing.assert_allclose(f1, f0, atol=EXACT)


@pytest.mark.parametrize("kernel", ["box", "hat"])
def test_kernel_cut_by_the_beam_end_keeps_the_whole_load(kernel):
    beam = Beam(straight((0, 0, 0), (1, 0, 0), 3, 3), SECTION, "fv3")
    for xi in (0.0, 0.01, 0.99, 1.0):
        force, _ = resultants(beam, beam.point_load(xi, F, smearing=0.05, kernel=kernel))
        np.testing.assert_allclose(force, F, atol=EXACT)


@pytest.mark.parametrize("name,npe", FORMULATIONS)
def test_distributed_load_resultant_on_a_curved_beam(name, npe):
    """A linearly varying load q(xi) = q0 + q1 xi along a quarter circle: the nodal forces sum
    to its integral q0 L + q1 L^2 / 2 up to the quadrature of the interpolated arc, whose
    length converges at O(h^4) (relative error of the length itself is the bound)."""
    beam = Beam(arc((0, 0, 0), 1.0, 0.0, np.pi / 2, 16, npe), SECTION, name)
    L = beam.mesh.length
    q0, q1 = np.array([0.0, 0.0, 1.0]), np.array([0.5, 0.0, -0.2])
    f = beam.distributed_load(force=lambda xi: q0 + np.outer(xi, q1))
    force, _ = resultants(beam, f)
    np.testing.assert_allclose(force, q0 * L + q1 * L**2 / 2, rtol=1e-9, atol=1e-9)


def test_bad_loads_name_the_item():
    beam = Beam(straight((0, 0, 0), (1, 0, 0), 2, 3), SECTION, "fv3")
    with pytest.raises(ValueError, match="smearing"):
        beam.point_load(0.5, F, smearing=-0.1)
    with pytest.raises(ValueError, match="kernel"):
        beam.point_load(0.5, F, smearing=0.1, kernel="gauss")
    with pytest.raises(ValueError, match="force"):
        beam.point_load(0.5, (np.nan, 0, 0))
    with pytest.raises(ValueError, match="moment"):
        beam.point_load(0.5, F, moment=(1, 2))
    with pytest.raises(ValueError, match="xi"):
        beam.point_load(1.2, F)
    with pytest.raises(ValueError, match="distributed load 'f'"):
        beam.distributed_load(force=lambda xi: np.full((len(xi), 3), np.inf))


@pytest.mark.parametrize("name,npe", FORMULATIONS)
def test_nodal_load_at_a_vertex_equals_the_point_load_there(name, npe):
    """Every formulation's test functions are 1 at their own vertex and 0 at the others (the
    fv region of a vertex contains it, with zero lever arm; the cubic element's functions
    take unit nodal values), so both loads coincide."""
    beam = oblique_beam(name, npe)
    vertex = 2
    xi = beam.mesh.vertex_s[vertex]
    np.testing.assert_allclose(beam.nodal_load(vertex, F, M), beam.point_load(xi, F, M), atol=EXACT)
    with pytest.raises(ValueError, match="node 99"):
        beam.nodal_load(99, F)
