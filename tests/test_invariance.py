"""Frame invariance, the curved quarter-circle cantilever, and structures of several beams."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import block_diag
from scipy.spatial.transform import Rotation

from fvbeam import Beam, LinearStatics, Section, Structure, Support, arc, closed_forms, straight

EPS = np.finfo(float).eps
NODES = {"fv2": 2, "fv3": 3, "galerkin-p1": 2, "galerkin-p2": 3}


def _roundoff_tol(statics: LinearStatics, q: np.ndarray, ops: float) -> float:
    """Forward-error bound of the solve: cond(K_ff) x (ops x eps) x ||q||.

    ``ops`` bounds the relative perturbation, in units of eps, of the assembled stiffness and
    load (a few products of rotation matrices per entry for a rotated beam).
    """
    Kff = statics.K[statics.free][:, statics.free].toarray()
    return np.linalg.cond(Kff) * ops * EPS * np.linalg.norm(q)


# ---------------------------------------------------------------------------------------
# frame invariance
# ---------------------------------------------------------------------------------------
SECTION = Section.diagonal(EA=7.0, GAy=2.0, GAz=3.0, GJ=1.5, EJy=1.2, EJz=0.8)
L = 2.0
Q = Rotation.random(random_state=2024).as_matrix()
F = np.array([0.3, -1.1, 0.7])
M = np.array([0.4, 0.2, -0.5])
STATIONS = L * np.array([0.0, 0.2, 0.5, 0.63, 0.8, 1.0])


def _cantilever(form: str, rotation: np.ndarray):
    mesh = straight((0, 0, 0), rotation @ [L, 0, 0], 3, NODES[form], up=rotation @ [0, 0, 1])
    beam = Beam(mesh, SECTION, form)
    statics = LinearStatics(beam, [Support(0, "start")])
    q = statics.solve(beam.point_load(0.63 * L, force=rotation @ F, moment=rotation @ M))
    return beam, statics, q


@pytest.mark.parametrize("form", sorted(NODES))
def test_cantilever_is_frame_invariant(form):
    ref, _, q_ref = _cantilever(form, np.eye(3))
    rot, statics, q_rot = _cantilever(form, Q)
    # the reference solution must engage every stiffness: all six components non-zero
    d_ref = ref.displacements(q_ref, STATIONS)
    assert np.all(np.abs(d_ref[-1]) > 1e-3 * np.abs(d_ref).max())
    # roundoff: cond(K) x (~1e2 operations per entry to rotate the geometry and loads) x eps
    tol = _roundoff_tol(statics, q_rot, 1e2)
    assert tol < 1e-10 * np.abs(d_ref).max()  # and the bound itself is a roundoff level
    np.testing.assert_allclose(
        rot.displacements(q_rot, STATIONS), d_ref @ block_diag(Q, Q).T, rtol=0, atol=tol
    )
    # internal forces in the section frame do not see the rotation
    f_ref, f_rot = ref.internal_forces(q_ref), rot.internal_forces(q_rot)
    # same stations: arc length of the rotated chord, roundoff ~ 1e2 eps x L
    np.testing.assert_allclose(f_rot.xi, f_ref.xi, rtol=0, atol=1e2 * EPS * L)
    scale = max(np.abs(f_ref.force).max(), np.abs(f_ref.moment).max())
    # stresses = C x strains: the displacement bound relative to |q|, times the stress scale
    rel = tol / np.linalg.norm(q_rot)
    np.testing.assert_allclose(f_rot.force, f_ref.force, rtol=0, atol=rel * scale)
    np.testing.assert_allclose(f_rot.moment, f_ref.moment, rtol=0, atol=rel * scale)
    # global-axis internal forces rotate with the beam
    np.testing.assert_allclose(
        f_rot.force_global, f_ref.force_global @ Q.T, rtol=0, atol=rel * scale
    )
    np.testing.assert_allclose(
        f_rot.moment_global, f_ref.moment_global @ Q.T, rtol=0, atol=rel * scale
    )


# ---------------------------------------------------------------------------------------
# curved beam: quarter-circle cantilever under an out-of-plane tip force
# ---------------------------------------------------------------------------------------
R, P = 1.7, 0.9
# Out of plane, the arc works in torsion (GJ), bending about the in-plane normal e2 (EJy)
# and shear along e3 = z (GAz).  EA, GAy, EJz differ from them by large factors, so a swapped
# mapping (EJz for EJy, GAy for GAz) would change the answer by a factor ~3 (checked below).
ARC_STIFFNESS = dict(EA=50.0, GAy=20.0, GAz=3.0, GJ=1.5, EJy=1.2, EJz=9.0)
EXACT = closed_forms.quarter_circle_tip(
    R, P, ARC_STIFFNESS["GJ"], ARC_STIFFNESS["EJy"], ARC_STIFFNESS["GAz"]
)
NS = (2, 4, 8, 16)


def _quarter_circle(form: str, n: int):
    mesh = arc((0, 0, 0), R, 0.0, np.pi / 2, n, 3)
    beam = Beam(mesh, Section.diagonal(**ARC_STIFFNESS), form)
    statics = LinearStatics(beam, [Support(0, "start")])
    q = statics.solve(beam.point_load(mesh.length, force=(0, 0, P)))
    return beam, statics, q


def test_quarter_circle_oracle_discriminates_the_axes():
    wrong = closed_forms.quarter_circle_tip(
        R, P, ARC_STIFFNESS["GJ"], ARC_STIFFNESS["EJz"], ARC_STIFFNESS["GAy"]
    )
    assert abs(wrong - EXACT) > 0.5 * EXACT


@pytest.mark.parametrize("form", ["fv3", "galerkin-p2"])
def test_quarter_circle_tip_converges_at_order_4(form):
    err = []
    for n in NS:
        beam, statics, q = _quarter_circle(form, n)
        tip = beam.displacements(q, beam.mesh.length)[0]
        # planar arc, diagonal section, out-of-plane load: the in-plane problem (ux, uy, thz)
        # is decoupled and unloaded, so it stays zero to roundoff
        tol = _roundoff_tol(statics, q, 1e2)
        assert np.all(np.abs(q.reshape(-1, 6)[:, [0, 1, 5]]) <= tol)
        err.append(abs(tip[2] - EXACT) / EXACT)
    err = np.array(err)
    order = np.log2(err[:-1] / err[1:])
    # quadratic interpolation of the circle: geometric error O(h^4); for a tip load on a
    # straight beam both formulations are exact, so the geometry sets the rate
    assert np.all(np.abs(order - 4) < 0.5), (err, order)
    # O(h^4) from the coarsest error: err(16) ~ err(2) / 8^4 = 1.75e-3 / 4096 = 4.3e-7
    assert err[-1] < 1e-6, err


# ---------------------------------------------------------------------------------------
# several beams
# ---------------------------------------------------------------------------------------
def test_two_tied_beams_equal_one_beam():
    d = np.array([1.0, 2.0, -0.5]) / np.linalg.norm([1.0, 2.0, -0.5])
    up = (0.0, 0.0, 1.0)
    one = Beam(straight((0, 0, 0), L * d, 6, 3, up=up), SECTION, "fv3")
    a = Beam(straight((0, 0, 0), L / 2 * d, 3, 3, up=up), SECTION, "fv3")
    b = Beam(straight(L / 2 * d, L * d, 3, 3, up=up), SECTION, "fv3")
    structure = Structure([a, b], ties=[(0, "end", 1, "start")])
    assert structure.n_nodes == one.mesh.n_nodes  # the tie merged the two end nodes
    s_one = LinearStatics(one, [Support(0, "start")])
    s_two = LinearStatics(structure, [Support(0, "start")])
    stations = np.linspace(0.0, L, 9)
    for xi in (L, 0.3 * L):  # load on the second / on the first beam
        q1 = s_one.solve(one.point_load(xi, F, M))
        if xi > L / 2:
            f = structure.gather(1, b.point_load(xi - L / 2, F, M))
        else:
            f = structure.gather(0, a.point_load(xi, F, M))
        q2 = s_two.solve(f)
        # roundoff of two solves of the same equations, differently numbered
        tol = 2 * _roundoff_tol(s_one, q1, 1e2)
        u1 = one.displacements(q1, stations)
        u2 = np.vstack(
            [
                a.displacements(structure.local(0, q2), stations[stations <= L / 2]),
                b.displacements(structure.local(1, q2), stations[stations > L / 2] - L / 2),
            ]
        )
        assert np.abs(u1).max() > 0.1
        np.testing.assert_allclose(u2, u1, rtol=0, atol=tol)
