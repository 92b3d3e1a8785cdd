"""Natural frequencies of simply supported beams against the closed forms, every
formulation (fvbeam.modes, fvbeam.closed_forms.timoshenko_simply_supported_frequencies).

Bending in the x-y plane of a beam of length 1 pinned at both ends, EJ = m = 1, the three
lowest modes; two regimes: Timoshenko (``s^2 = EJ / (GA L^2) = 0.01``, rotary inertia
``rhoJ = 1e-3`` per length) and Euler-Bernoulli (``GA = 1e6``, no rotary inertia: the lumped
rotations are massless).

Tolerance sources:

* The closed form's Euler-Bernoulli limit: ``omega^2 = k^4 / (1 + k^2 / GA)``, so it lies
  below ``k^2`` by ``k^2 / (2 GA)`` relatively, to leading order; the bound is twice that.
* Mesh convergence: the observed order ``log2(e_n / e_2n)`` on n, 2n, 4n elements within
  0.5 of the expected one, and the finest error below ``e_2n / 2^(p - 0.5)``, as the
  cantilever's (``tests/test_modes.py``); n = 16 for order 2 (on 8 elements the third
  mode is not yet asymptotic: fv3 2.66), n = 8 for order 4 (on 64 elements the first
  mode's error, 1e-10, meets the rounding of a stiffness whose shear is 1e6 times its
  bending).  Expected orders, measured on n = 8 to 64 and
  explained: 2 for fv2, fv3 and galerkin-p1 (the lumped masses are quadratures exact for
  linear fields only; fv2 is galerkin-p1 with one-point stiffness, equal to round-off),
  2p = 4 for galerkin-p2 (Strang and Fix, "An Analysis of the Finite Element Method",
  Sec. 6.3); cubic 4 in the Euler-Bernoulli regime, where its Hermite deflection is the
  whole kinematics, and 2 with shear and rotary inertia, where the rotation's
  interpolation carries the rotary inertia (measured 2.00 to 2.06).
"""

import numpy as np
import pytest

from fvbeam import Beam, Section, Support, closed_forms, formulation, straight
from fvbeam.modes import natural_frequencies

REGIMES = {"timoshenko": (100.0, 1e-3), "euler-bernoulli": (1e6, 0.0)}
#: Axial and torsional stiffness (their modes far above the bending ones) and bending.
STIFFNESS = {"EA": 1e5, "GJ": 1e2, "EJy": 1.0, "EJz": 1.0}
CASES = [
    ("fv2", "lumped", {"timoshenko": 2, "euler-bernoulli": 2}),
    ("fv3", "lumped", {"timoshenko": 2, "euler-bernoulli": 2}),
    ("galerkin-p1", "lumped", {"timoshenko": 2, "euler-bernoulli": 2}),
    ("galerkin-p1", "consistent", {"timoshenko": 2, "euler-bernoulli": 2}),
    ("galerkin-p2", "lumped", {"timoshenko": 4, "euler-bernoulli": 4}),
    ("galerkin-p2", "consistent", {"timoshenko": 4, "euler-bernoulli": 4}),
    ("cubic", "lumped", {"timoshenko": 2, "euler-bernoulli": 4}),
    ("cubic", "consistent", {"timoshenko": 2, "euler-bernoulli": 4}),
]


def frequencies(name: str, kind: str, n: int, GA: float, rhoJ: float) -> np.ndarray:
    inertia = np.diag([2e-3, rhoJ, rhoJ])
    section = Section.diagonal(GAy=GA, GAz=GA, mass_per_length=1.0, inertia=inertia, **STIFFNESS)
    mesh = straight((0, 0, 0), (1, 0, 0), n, formulation(name).nodes_per_element)
    beam = Beam(mesh, section, name)
    supports = [Support(0, k, "ux+uz+rx+ry") for k in range(mesh.n_nodes)]
    supports += [Support(0, "start", "uy"), Support(0, "end", "uy")]
    return natural_frequencies(beam, supports, 3, kind).omega


def test_the_closed_form_has_the_euler_bernoulli_limit():
    GA = 1e6
    k = np.pi * np.arange(1, 4)
    omega = closed_forms.timoshenko_simply_supported_frequencies(3, GA=GA)
    assert np.all(omega < k**2)
    assert np.all(1 - omega / k**2 < 2 * k**2 / (2 * GA))


@pytest.mark.parametrize("regime", REGIMES)
@pytest.mark.parametrize("name,kind,orders", CASES)
def test_simply_supported_frequencies_converge_at_the_expected_order(name, kind, orders, regime):
    GA, rhoJ = REGIMES[regime]
    order = orders[regime]
    exact = closed_forms.timoshenko_simply_supported_frequencies(3, GA=GA, rhoJ=rhoJ)
    n = 16 if order == 2 else 8
    errors = [np.abs(frequencies(name, kind, k * n, GA, rhoJ) / exact - 1) for k in (1, 2, 4)]
    for coarse, fine in zip(errors, errors[1:], strict=False):
        observed = np.log2(coarse / fine)
        assert np.all(np.abs(observed - order) < 0.5), observed
    assert np.all(errors[2] < errors[1] / 2 ** (order - 0.5))
