"""The rigid and elastic parts of a motion (:mod:`sliders.app.motion`).

Sources: the definition of the split (a motion that is rigid, group by group and consistent
with the joints, is its own rigid part; a clamp holds all six rigid motions of its group at
the clamp's zero motion) and of lexicographic least squares.  Roundoff: the split is the
residual of least-squares problems solved through the SVD, backward stable, so a consistent
problem leaves a residual below ``m n eps`` times the size of its right-hand side (``m``
rows, ``n`` unknowns; Higham, *Accuracy and Stability of Numerical Algorithms*, Thm. 20.3);
the rigid motion itself is formed with a few more roundings per entry, well inside that.
"""

from __future__ import annotations

import numpy as np
import pytest

from fvbeam import Beam, RigidBody, Section, Structure, Support, straight
from sliders.app.motion import lexicographic_lstsq, rigid_motion
from sliders.app.vtu import structure_size
from sliders.joints.slider import Slider
from sliders.lines.chain import BeamChain
from sliders.lines.rigid import StraightLine

EPS = np.finfo(float).eps
SECTION = Section.diagonal(EA=1e3, GAy=2e2, GAz=2e2, GJ=5.0, EJy=7.0, EJz=7.0)


def rigid(c, theta, X, X0) -> np.ndarray:
    """Nodal dofs ``(c + theta x (X - X0), theta)`` of a rigid motion, one row per point."""
    X = np.atleast_2d(X)
    u = np.asarray(c) + np.cross(theta, X - X0)
    return np.hstack([u, np.broadcast_to(theta, u.shape)])


def frame_cart_and_hub():
    """An L-frame of two tied beams (fv3 and galerkin-p1, no support), a body ``cart`` on
    the frame's first beam (classical slider) and a body ``hub`` on a rigid rail along x
    (classical slider): three groups."""
    a = Beam(straight((0, 0, 0), (1.0, 0, 0), 4, 3), SECTION, "fv3")
    b = Beam(straight((1.0, 0, 0), (1.0, 0.8, 0), 3, 2), SECTION, "galerkin-p1")
    bodies = [RigidBody("cart", (0.4, 0, 0)), RigidBody("hub", (0.3, -0.4, 0.2))]
    structure = Structure([a, b], [((0, "end"), (1, "start"))], bodies)
    rail = StraightLine((0, -0.4, 0.2), (1.0, -0.4, 0.2), name="rail")
    sliders = [
        Slider("classical", BeamChain(structure, [0], "a"), "cart", name="cart"),
        Slider("classical", rail, "hub", name="hub"),
    ]
    return structure, sliders


def test_a_rigid_motion_has_no_elastic_part():
    """The frame moved rigidly (a translation and a small rotation), the cart carried along
    with it and slid 0.25 along its beam (turning with it, as its classical slider holds),
    the hub slid 0.15 along the rail and spun about it; one of the frame's dofs held at its
    rigid value (a drive).  The split finds the whole motion rigid."""
    structure, sliders = frame_cart_and_hub()
    c, theta, X0 = np.array([0.01, -0.02, 0.03]), np.array([1e-3, -2e-3, 3e-3]), np.ones(3)
    q = np.zeros(structure.n_dofs)
    for beam, dofs in zip(structure.beams, structure.dof_maps, strict=True):
        q[dofs] = rigid(c, theta, beam.mesh.points, X0).ravel()
    cart, hub = (structure.bodies[k].position for k in range(2))
    travel = np.array([0.25, 0.0, 0.0])
    carried = rigid(c, theta, cart + travel, X0)[0]
    q[structure.node_dofs("cart")] = carried + np.concatenate([travel, np.zeros(3)])
    q[structure.node_dofs("hub")] = [0.15, 0, 0, 0.02, 0, 0]
    unknowns = [np.array([0.65, 0, 0, 0, 0, 0]), np.array([0.45, 0, 0, 0, 0, 0])]
    held = structure.node_dofs((1, "end"))[:1]
    q_rigid = rigid_motion(structure, q, sliders, unknowns, held)
    # rotations enter the fit times the structure's size; 6 unknowns per group, 3 groups
    ell = structure_size(structure)
    weighted = np.abs(q.reshape(-1, 6) * [1, 1, 1, ell, ell, ell]).max()
    bound = structure.n_dofs * 18 * EPS * weighted
    assert np.abs(q - q_rigid).max() <= bound


def test_a_clamped_group_has_no_rigid_part():
    """A clamp holds the six rigid motions of its group at its own (zero) motion: whatever
    the rest of the beam does is elastic, to the bit (an SVD solve of a zero right-hand
    side is zero)."""
    structure, _ = frame_cart_and_hub()
    held = structure.support_dofs([Support(0, "start")])
    q = np.random.default_rng(5).normal(size=structure.n_dofs)
    q[held] = 0.0
    beams = np.concatenate(structure.dof_maps)
    assert np.all(rigid_motion(structure, q, held=held)[beams] == 0.0)


def test_lexicographic_least_squares():
    """Each level is solved within what the levels before leave free; a level that leaves
    something free gives it the minimum norm (4 eps: SVDs of 1x2 and 2x2 unit problems)."""
    first, second = (np.array([[1.0, 0.0]]), np.array([1.0])), (np.eye(2), np.array([3.0, 2.0]))
    np.testing.assert_allclose(lexicographic_lstsq([first, second], 2), [1, 2], atol=4 * EPS)
    np.testing.assert_allclose(
        lexicographic_lstsq([(np.array([[1.0, 1.0]]), np.array([2.0]))], 2), [1, 1], atol=4 * EPS
    )
    empty = (np.zeros((0, 2)), np.zeros(0))
    np.testing.assert_allclose(lexicographic_lstsq([empty, second], 2), [3, 2], atol=4 * EPS)


def test_bad_held_dofs_are_named():
    structure, _ = frame_cart_and_hub()
    q = np.zeros(structure.n_dofs)
    for held in ([structure.n_dofs], ["ux"], [0.5], [-1]):
        with pytest.raises(ValueError, match=r"held must be global dofs of the structure"):
            rigid_motion(structure, q, held=held)
