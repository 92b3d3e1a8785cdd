"""The packed, compiled joints (:mod:`sliders.joints.packed`) against the reference
:meth:`SliderBatch.evaluate`: the same residuals and Jacobians on the same dofs.

Both run the same compiled line-state and joint kernels on the same inputs; they differ in
how they gather them (the packed joint pads a smeared load transfer to a fixed number of
slots, whose extra rows are zero) and, off straight elements, in the 3 x 3 products of the
section frame (numpy against numba).  Slots are merged by dof before comparing (a dof may
hold several slots).  Tolerance: the 3 x 3 products round within ``3 eps`` of their terms, a
rotation entry of magnitude at most 1 multiplying compliances and multipliers, so every
entry agrees within ``16 eps`` of the largest magnitude of the residual or Jacobian: a wrong
term is of that magnitude, 15 orders above.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from test_joint_reference import JOINTS, LINES, OFFSETS, batch_of, random_state
from test_sliders import SECTION

from fvbeam import Beam, Structure, arc
from sliders.joints.drives import Linear
from sliders.joints.packed import JointPack
from sliders.joints.slider import Slider, SliderBatch
from sliders.lines.chain import BeamChain

EPS = np.finfo(float).eps


def merged(dofs: np.ndarray, r: np.ndarray, J: np.ndarray) -> tuple[np.ndarray, ...]:
    """Residual and Jacobian with the slots of each dof summed (:meth:`Slider.assemble`)."""
    unique, where = np.unique(dofs, return_inverse=True)
    s, t, m = len(dofs), len(unique), len(r) - len(dofs)
    P = np.zeros((s + m, t + m))
    P[np.arange(s), where] = 1.0
    P[s + np.arange(m), t + np.arange(m)] = 1.0
    return unique, P.T @ r, P.T @ J @ P


def assert_same_joint(batch: SliderBatch, q: np.ndarray, y: np.ndarray, **options) -> None:
    """The packed joint of the batch's first member against the batch's evaluation of it."""
    slider, structure = batch.sliders[0], batch.structures[0]
    time, drive = options.pop("time", 0.0), options.pop("drive", 0.0)
    dofs, r, J = batch.subset(np.array([0])).evaluate(q[None], y[None], time, **options)
    reference = merged(dofs[0], r[0], J.dense()[0])
    pack = JointPack([slider], structure)
    p_dofs, p_r, values = pack.evaluate(0, q, y, drive, **options)
    layout, jacobian = pack.layouts[0]
    jacobian._views(values[None])
    packed = merged(p_dofs, p_r, jacobian.dense()[0])
    assert np.array_equal(packed[0], reference[0])
    for got, expected in zip(packed[1:], reference[1:], strict=True):
        assert np.abs(got - expected).max() <= 16 * EPS * max(np.abs(expected).max(), 1.0)


@pytest.mark.parametrize("offset", list(OFFSETS))
@pytest.mark.parametrize("line", LINES)
@pytest.mark.parametrize("kind,orientation", JOINTS)
def test_packed_joint_equals_the_batch(kind, orientation, line, offset) -> None:
    """Every kind and orientation on fv2, fv3 (point and smeared), galerkin-p2 chains and
    rigid lines (arc, helix), on the node and off it, at random states and both multiplier
    scales."""
    batch = batch_of(kind, orientation, line, OFFSETS[offset])
    rng = np.random.default_rng(3)
    q, y = random_state(batch, rng)
    for scale in (1.0, 3.0):
        assert_same_joint(batch, q[0], y[0], scale=scale)


@pytest.mark.parametrize("kind", ["spherical", "classical", "spline"])
@pytest.mark.parametrize("smearing", [0.0, 0.05])
def test_packed_joint_on_a_curved_chain(kind, smearing) -> None:
    """A body on an arched chain of two beams (curved elements: the section frame and its
    curvature computed at ``xi``), across the beams' junction."""
    a = Beam(arc((0, 0, 0), 1.0, 0.0, 0.8, 3, 3, name="a"), SECTION, "fv3")
    b = Beam(arc((0, 0, 0), 1.0, 0.8, 1.6, 2, 3, name="b"), SECTION, "fv3")
    tip = Beam(arc((0, 0, 0), 1.0, 0.3, 0.35, 1, 3, name="tip"), SECTION, "fv3")
    structure = Structure([a, b, tip], ties=[("a.end", "b.start")])
    line = BeamChain(structure, ["a", "b"], "arch")
    slider = Slider(kind, line, "tip.end", smearing=smearing, name="s")
    batch = SliderBatch([slider], [structure])
    rng = np.random.default_rng(8)
    for xi in (0.2, 0.79, 0.8, 1.3):
        q = rng.standard_normal(structure.n_dofs) * 1e-3
        y = rng.standard_normal(slider.n_unknowns)
        y[0] = xi
        assert_same_joint(batch, q, y)


@pytest.mark.parametrize("xi,lam", [(-0.01, 1.0), (0.0, -1.0), (0.0, 1.0), (0.6, 1.0), (0.7, 1.0)])
def test_end_stops_and_drives(xi, lam) -> None:
    """End stops (beyond an end, at an end pushing and not pushing) and a driven abscissa
    replace the ``xi`` equation alike."""
    batch = batch_of("classical", "section", "fv3", OFFSETS["on the node"])
    slider = batch.sliders[0]
    q, y = random_state(batch, np.random.default_rng(4))
    y = y[0].copy()
    y[0], y[1:4] = xi, lam * np.array([1.0, 0.3, -0.2])
    stopped = SliderBatch([dataclasses.replace(slider, end_stops=True)], batch.structures[:1])
    assert_same_joint(stopped, q[0], y)
    motion = Linear(0.1, 0.25)
    driven = SliderBatch([dataclasses.replace(slider, drive=motion)], batch.structures[:1])
    y[0] = min(max(xi, 0.05), 0.55)
    assert_same_joint(driven, q[0], y, time=0.7, drive=motion(0.7)[0])


def test_an_abscissa_off_the_line_is_named() -> None:
    """Off its line without end stops: the packed joint's error names the slider."""
    batch = batch_of("spherical", "section", "fv3", OFFSETS["on the node"])
    q, y = random_state(batch, np.random.default_rng(5))
    y[0, 0] = -0.1
    pack = JointPack(batch.sliders[:1], batch.structures[0])
    with pytest.raises(ValueError, match="slider 'A': xi = -0.1 lies outside its line"):
        pack.evaluate(0, q[0], y[0])


@pytest.mark.parametrize("line", LINES)
def test_projection_equals_the_batch(line) -> None:
    """The compiled projection (:func:`sliders.joints.packed.project`) against the batch's
    (:meth:`SliderBatch.initial_unknowns`, numpy around the same line kernels): the same
    Newton steps from the same sample, so the same ``xi`` to a few ulp of the line's length,
    on a deformed state; and on the state moved rigidly (:meth:`JointPack.moved`)."""
    batch = batch_of("spherical", "section", line, OFFSETS["off the node"])
    slider, structure = batch.sliders[0], batch.structures[0]
    q = np.random.default_rng(9).standard_normal(structure.n_dofs) * 1e-3
    pack = JointPack([slider], structure)
    reference = batch.subset(np.array([0])).initial_unknowns(q[None])[0]
    (packed,) = pack.initial_unknowns(q)
    assert np.abs(packed - reference).max() <= 8 * EPS * slider.line.length


def test_curve_equals_the_chain_geometry() -> None:
    """:meth:`JointPack.curve` (compiled) against :meth:`BeamChain.geometry` (numpy around the
    same line kernels) on the arched chain, across the junction, on a deformed state: the
    same ``x, l`` to a few ulp of their scale, and ``l_/xi`` (the second derivatives of the
    quadratic shape functions, whose magnitudes sum to 16 / h^2, times the node positions) to
    a few ulp of ``16 |x| / h^2`` on the shortest element."""
    a = Beam(arc((0, 0, 0), 1.0, 0.0, 0.8, 3, 3, name="a"), SECTION, "fv3")
    b = Beam(arc((0, 0, 0), 1.0, 0.8, 1.6, 2, 3, name="b"), SECTION, "fv3")
    tip = Beam(arc((0, 0, 0), 1.0, 0.3, 0.35, 1, 3, name="tip"), SECTION, "fv3")
    structure = Structure([a, b, tip], ties=[("a.end", "b.start")])
    slider = Slider("spherical", BeamChain(structure, ["a", "b"], "arch"), "tip.end", name="s")
    pack = JointPack([slider], structure)
    q = np.random.default_rng(10).standard_normal(structure.n_dofs) * 1e-3
    h = min(np.diff(beam.mesh.vertex_s).min() for beam in (a, b))
    for xi in (0.0, 0.2, 0.8, 1.3, slider.line.length):
        compiled = np.array(pack.curve(0, q, xi))
        reference = np.array(slider.line.geometry(xi, q)[:3])
        scale = np.abs(reference[:2]).max(axis=1)
        bound = 8 * EPS * np.array([scale[0], scale[1], 16 * scale[0] / h**2])
        assert np.all(np.abs(compiled - reference).max(axis=1) <= bound)
