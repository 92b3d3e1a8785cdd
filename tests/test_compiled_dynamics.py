"""Compiled fixed steps (:mod:`sliders.solve.dynamics_kernel`, what :meth:`Dynamics.run`
takes) against :meth:`Dynamics.step`, the reference, step by step.

The two evaluate the same prediction, step problem and completion; they differ in the order
of a few sums (the structure residual, the sparse products) and in the solve's triangular
sweeps (compiled against SuperLU's), so each step's state differs by the roundoff of a solve
with the step operator, ``~ cond(K') eps |q|``, and the joints' Newton loops stop on the
same rule at the same iteration (asserted).  With joints, the step's Newton matrix is the
operator bordered by the joints' equations, and its condition ``cond(J)`` (measured at the
start) bounds the roundoff of the increments, multipliers included.  Over ``N`` steps of a
scheme whose spectral radius is at most 1, these differences add at most linearly: the test
allows ``100 N cond eps`` relative to the largest value (a wrong term of the step is of the
size of the step's change, some ten orders above).
"""

from __future__ import annotations

import numpy as np
import pytest
from test_dynamics import MASS, SECTION, R, bead, bead_start, cantilever

from fvbeam import Beam, RigidBody, Structure, Support, straight
from sliders.joints.drives import DofDrive, Linear, Ramp
from sliders.joints.slider import Slider
from sliders.lines.chain import BeamChain
from sliders.solve.dynamics import Dynamics
from sliders.solve.integrator import State

EPS = np.finfo(float).eps


class Trace:
    """Every recorded state (:class:`sliders.solve.dynamics.Recorder`)."""

    def __init__(self) -> None:
        self.states: list[State] = []

    def start(self, dynamics: Dynamics, state: State) -> None:
        self.states = []

    def record(self, dynamics: Dynamics, new: State, old: State) -> None:
        self.states.append(new)

    def close(self) -> None:
        pass


def assert_steps_agree(d: Dynamics, start: State, h: float, steps: int, path: float = 0.0) -> None:
    """``steps`` compiled steps (:meth:`Dynamics.run`) against :meth:`Dynamics.step`;
    ``path``: a bound on the multipliers' difference per step from a line evaluated by
    other floating-point functions on the two paths (see :func:`test_a_bead_on_a_wire`)."""
    trace = Trace()
    d.run(start, start.t + steps * h, h, recorder=trace, progress=False)
    assert len(trace.states) == steps
    solver = d._solver(h)
    if d.sliders:
        scale = 1.0 / d.scheme.rates(h)[0]
        unknowns = [np.concatenate([y[:1], scale * y[1:]]) for y in start.unknowns]
        matrix = solver.jacobian(start.q, unknowns).toarray()
    else:
        matrix = d.operator(h)[d.free][:, d.free].toarray()
    bound = 100 * steps * np.linalg.cond(matrix) * EPS
    state = start
    for compiled in trace.states:
        state = d.step(state, h)
        assert compiled.iterations == state.iterations
        assert compiled.t == state.t
        scale = max(np.abs(state.q).max(), 1e-300)
        for a, b in ((compiled.q, state.q), (compiled.v, state.v), (compiled.qdd, state.qdd)):
            assert np.abs(a - b).max() <= bound * max(np.abs(b).max(), scale / h**2)
        for a, b in zip(compiled.unknowns, state.unknowns, strict=True):
            assert np.abs(a - b).max() <= bound * max(np.abs(b).max(), 1.0) + steps * path


@pytest.mark.parametrize("mass", ["lumped", "consistent"])
def test_a_damped_cantilever_with_gravity_and_a_driven_tip(mass) -> None:
    """No joints: one solve per step; damping, gravity and a dof drive."""
    structure, supports = cantilever("galerkin-p2" if mass == "consistent" else "fv3", 4)
    drive = DofDrive((0, "end"), "uz", Ramp(0.0, 0.01, 0.0, 0.3))
    d = Dynamics(
        structure, supports, mass=mass, damping=1e-3, gravity=(0, -9.81, 0), drives=[drive]
    )
    assert_steps_agree(d, d.static_state(), 0.01, 60)


@pytest.mark.parametrize("smearing", [0.0, 0.05])
def test_a_body_driven_across_an_element(smearing) -> None:
    """The Figure 2 arrangement: a massless body driven along a damped cantilever, one
    slider, point and smeared reaction."""
    structure, supports = cantilever("fv3", 2)
    structure = Structure(structure.beams, bodies=[RigidBody("body", (0.3, 0, 0), mass=0.0)])
    slider = Slider(
        "spherical",
        BeamChain(structure, [0]),
        "body",
        drive=Linear(0.3, 0.5),
        smearing=smearing,
        name="body",
    )
    d = Dynamics(
        structure,
        supports + [Support("body", kind="rx+ry+rz")],
        [slider],
        structure.nodal_load("body", (0, 1.0, 0)),
        damping=2e-3,
        method="condensed",
    )
    assert_steps_agree(d, d.static_state(), 0.02, 50)


def test_a_bead_on_a_wire() -> None:
    """A massive body on a rigid arc under gravity, from a moving start.  The arc's point is
    a cosine and a sine, evaluated by numpy on one path and by the compiled code's libm on
    the other, within an ulp each: the sliding point's path differs by ``2 eps R`` per step,
    which the reaction, ``m qdd``, turns into ``beta' m 2 eps R`` (``beta' = qdd / dq``, the
    scheme's ``4 / h^2`` in order) on top of the solves' roundoff."""
    structure, slider, supports = bead()
    d = Dynamics(structure, supports, [slider], gravity=(0, -1.0, 0), method="condensed")
    h = 0.01
    path = d.scheme.rates(h)[0] * MASS * 2 * EPS * R
    assert_steps_agree(d, bead_start(structure.n_dofs), h, 80, path)


@pytest.mark.parametrize("kind", ["spherical", "classical"])
def test_two_beams_sliding_in_each_other(kind) -> None:
    """The sliding beams with mass: the piston held only by its sliders, pushed in by a
    cosine ramp on its base while a transverse force acts at its tip."""
    C = Beam(straight((0, 0, 0), (1.0, 0, 0), 2, 3, name="C"), SECTION, "fv3")
    P = Beam(straight((0.3, 0, 0), (1.3, 0, 0), 2, 3, name="P"), SECTION, "fv3")
    structure = Structure([C, P])
    sliders = [
        Slider(kind, BeamChain(structure, ["C"]), "P.start", name="A"),
        Slider(kind, BeamChain(structure, ["P"]), "C.end", name="B"),
    ]
    supports = [Support("C.start")]
    drive = DofDrive((1, "start"), "ux", Ramp(0.0, -0.05, 0.0, 0.5))
    d = Dynamics(
        structure,
        supports + [Support("P.start", kind="rx")],
        sliders,
        structure.gather(1, P.nodal_load("end", (0, 0.2, 0.1))),
        drives=[drive],
        method="condensed",
    )
    assert_steps_agree(d, d.static_state(), 0.01, 40)
