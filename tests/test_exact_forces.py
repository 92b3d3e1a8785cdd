"""Force elements on the exact path (sliders.app.exact_forces): the tangent of an exact
structure with a strut against central differences of its residual at a random finite
configuration.

Tolerance: central differences with step ``e = 1e-7`` on the spatial increments: truncation
``e^2`` times the third derivatives (the beam's stiffness ``1e3`` over lengths of ``0.25``,
the strut's ``1e3`` N over ``0.1`` m: ``1e-14 * 1e6 ~ 1e-8`` of the largest entry), rounding
``eps |r| / e`` (``|r| ~ 1e3``: ``2e-6``, ``1e-8`` of the largest entry ``~1e5``); ``1e-6``
of the largest entry bounds both.
"""

import numpy as np
from test_exact_loads import central_differences

from fvbeam import Beam, RigidBody, Section, Structure, rotations, straight
from fvbeam.exact_beam import ExactState
from fvbeam.exact_structure import ExactStructure
from sliders.app.exact_forces import WithForces
from sliders.forces.elements import AxialForce
from sliders.forces.laws import Strut


def test_tangent_with_a_strut_matches_finite_differences():
    section = Section.diagonal(EA=1e5, GAy=1e5, GAz=1e5, GJ=1e3, EJy=1e3, EJz=1e3)
    beam = Beam(straight((0, 0, 0), (1, 0, 0), 4, 3, name="rod"), section, "fv3")
    structure = Structure([beam], [], [RigidBody("anchor", np.array([1.4, 0.2, 0.1]))])
    law = Strut(1.6e-3, 4.1e5, 2.8e-4, 1.3, 5000.0, 20000.0, 1e8, 0.16)
    strut = AxialForce("rod.end", "anchor", law, 0.5, "strut")
    operator = WithForces(ExactStructure(structure), [strut], structure)
    rng = np.random.default_rng(3)
    reference = operator.reference()
    n = len(reference.x)
    state = ExactState(
        reference.x + 0.02 * rng.standard_normal((n, 3)),
        rotations.exp_map(0.5 * rng.standard_normal((n, 3))),
    )
    K = operator.tangent(state).toarray()
    fd = central_differences(operator.residual, state, 1e-7)
    np.testing.assert_allclose(K, fd, rtol=0, atol=1e-6 * np.abs(fd).max())
    slots = strut.slots(structure)
    assert (
        np.abs(
            K[np.ix_(slots, slots)]
            - ExactStructure(structure).tangent(state).toarray()[np.ix_(slots, slots)]
        ).max()
        > 1e-3 * np.abs(fd).max()
    )  # the strut's share is there
