"""The compiled joint kernel against its numpy reference, and the contract of its pattern.

:func:`sliders.joints.kernel.joint_equations` (the laws generated from their statement,
chained through the line's maps in compiled code) and :mod:`sliders.joints.equations` (the
paper's laws, their Jacobian derived by dual numbers) read the same inputs
(:meth:`SliderBatch.joint_inputs`) and must give the same residuals and Jacobian blocks up to
roundoff, for every slider kind, both orientation models, beam chains
(fv2, fv3, galerkin-p2, cubic, whose line has a compliance at the contact; smeared and not)
and rigid lines (an arc, a helix), with the sliding
point on the node and off it (the lever arm, which the pattern distinguishes), on chains
with and without the section rotation dofs (the other option of the pattern).

Tolerance: every entry is a polynomial in the inputs, and both implementations evaluate its
terms in floating point, grouped and ordered differently.  A computed expression lies within
``gamma_n A`` of its exact value (Higham, *Accuracy and Stability of Numerical Algorithms*,
Sec. 3.3, to first order), ``gamma_n = n eps / (1 - n eps)``, where ``A`` is the expression
evaluated with every operand and every operation in absolute value (the sum of the absolute
values of its terms) and ``n`` the number of roundings along its longest chain.  ``A`` is
the same for any grouping of the same terms (sums and products of non-negative numbers
regroup exactly), so the two implementations agree within ``2 gamma_n A``.  The test carries
``A`` and ``n`` beside each value through the reference (:class:`Running`, on object arrays)
and takes ``n`` twice the reference's deepest chain, for the kernel's other grouping.  A
wrong term is of the size of the terms themselves (``A``), some 13 orders above the bound.
"""

import dataclasses
from itertools import product

import numpy as np
import pytest
from test_sliders import SECTION, sliding_beams_model

from fvbeam import Beam, Structure, straight
from sliders.joints.blocks import SlotJacobian
from sliders.joints.equations import Equations, JointInputs, joint_reference
from sliders.joints.kernel import GROUPS
from sliders.joints.slider import Slider, SliderBatch
from sliders.lines.rigid import CircularArc, Helix

EPS = np.finfo(float).eps
#: The slider kinds with their orientation models.
JOINTS = [
    ("spherical", "section"),
    ("classical", "section"),
    ("spline", "section"),
    ("classical", "slope"),
]
#: Lines: beam chains (formulation, smearing as a fraction of the element) and rigid lines.
LINES = ["fv3", "fv3 smeared", "fv2", "galerkin-p2", "cubic", "cubic smeared", "arc", "helix"]
OFFSETS = {"on the node": np.zeros(3), "off the node": np.array([0.02, -0.05, 0.03])}
MEMBERS = 3


class Running:
    """A float with the absolute sum ``size`` of the terms it was computed from and the
    number ``depth`` of roundings along its longest chain (module docstring)."""

    __slots__ = ("value", "size", "depth")

    def __init__(self, value: float, size: float, depth: int) -> None:
        self.value, self.size, self.depth = value, size, depth

    @staticmethod
    def of(x: "Running | float") -> "Running":
        return x if isinstance(x, Running) else Running(float(x), abs(float(x)), 0)

    def _join(self, other, value, size):
        return Running(value, size, max(self.depth, Running.of(other).depth) + 1)

    def __add__(self, other):
        if not isinstance(other, NUMBERS):  # a dual number of them: its own arithmetic
            return NotImplemented
        o = Running.of(other)
        return self._join(o, self.value + o.value, self.size + o.size)

    def __sub__(self, other):
        if not isinstance(other, NUMBERS):
            return NotImplemented
        o = Running.of(other)
        return self._join(o, self.value - o.value, self.size + o.size)

    def __mul__(self, other):
        if not isinstance(other, NUMBERS):
            return NotImplemented
        o = Running.of(other)
        return self._join(o, self.value * o.value, self.size * o.size)

    def __truediv__(self, other):
        if not isinstance(other, NUMBERS):
            return NotImplemented
        o = Running.of(other)
        return self._join(o, self.value / o.value, self.size / abs(o.value))

    def __rsub__(self, other):
        return Running.of(other) - self

    def __neg__(self):
        return Running(-self.value, self.size, self.depth)

    __radd__ = __add__
    __rmul__ = __mul__


#: What :class:`Running` computes with (anything else, a dual, brings its own arithmetic).
NUMBERS = (Running, int, float)


def running(inputs: JointInputs) -> JointInputs:
    """The inputs as :class:`Running` numbers (exact: size the absolute value, no rounding);
    the dof maps stay integers."""
    to_running = np.vectorize(lambda x: Running(float(x), abs(float(x)), 0), otypes=[object])
    return JointInputs(*(a if np.asarray(a).dtype.kind == "i" else to_running(a) for a in inputs))


def roundoff_bounds(kind: str, orientation: str, inputs: JointInputs) -> Equations:
    """``2 gamma_n A`` for every residual and Jacobian entry (module docstring)."""
    evaluated = joint_reference(kind, orientation, running(inputs))
    size = np.vectorize(lambda e: Running.of(e).size, otypes=[float])
    depth = np.vectorize(lambda e: Running.of(e).depth, otypes=[int])
    parts = list(evaluated.residual.values()) + list(evaluated.jacobian.values())
    n = 2 * max(int(depth(np.asarray(p)).max(initial=0)) for p in parts)
    gamma = n * EPS / (1 - n * EPS)
    return Equations(
        {k: 2 * gamma * size(np.asarray(v)) for k, v in evaluated.residual.items()},
        {k: 2 * gamma * size(np.asarray(v)) for k, v in evaluated.jacobian.items()},
    )


def kernel_equations(r: np.ndarray, J: SlotJacobian) -> Equations:
    """The kernel's output by slot groups."""
    start, size, _ = J.index(GROUPS)
    residual = {g: r[:, s : s + n] for g, s, n in zip(GROUPS, start, size, strict=True)}
    return Equations(residual, dict(J.blocks))


def assert_equal_to_roundoff(kernel: Equations, reference: Equations, bound: Equations):
    """Every residual and block of the kernel within the bound of the reference's (zero
    where one of them has none: then exactly zero unless the other is within its bound)."""
    for group, value in kernel.residual.items():
        expected = reference.residual.get(group, np.zeros_like(value))
        allowed = bound.residual.get(group, 0.0)
        assert np.all(np.abs(value - expected) <= allowed), group
    for key in set(kernel.jacobian) | set(reference.jacobian):
        value = kernel.jacobian.get(key)
        expected = reference.jacobian.get(key)
        value = np.zeros_like(expected) if value is None else value
        expected = np.zeros_like(value) if expected is None else expected
        error = np.abs(value - np.broadcast_to(expected, value.shape))
        assert np.all(error <= bound.jacobian.get(key, 0.0)), (key, error.max())


def batch_of(kind: str, orientation: str, line: str, offset: np.ndarray) -> SliderBatch:
    """``MEMBERS`` copies of slider A of the sliding-beams setup (the piston's bottom on the
    cylinder, three elements per beam), or of a beam's tip sliding on a rigid line."""
    if line in ("arc", "helix"):
        beam = Beam(straight((0, 0, 0), (1, 0, 0), 4, 3), SECTION, "fv3")
        structure = Structure([beam])
        rigid = (
            CircularArc((1, -2, 0), 2.0, np.pi / 2 - 0.3, np.pi / 2 + 0.3)
            if line == "arc"
            else Helix((0.1, 0.2, -0.3), 0.8, 0.5, 1.5)
        )
        slider = Slider(kind, rigid, (0, "end"), orientation=orientation, name="tip")
    else:
        formulation, smearing = line.split()[0], 0.02 if "smeared" in line else 0.0
        structure, _, sliders, _ = sliding_beams_model(
            0.3, 3, kind, formulation, smearing, orientation=orientation
        )
        slider = sliders[0]
    slider = dataclasses.replace(slider, offset=offset)
    return SliderBatch([slider] * MEMBERS, [structure] * MEMBERS)


def random_state(batch: SliderBatch, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Displacements ~1e-3, ``xi`` inside the line, multipliers ~1."""
    q = rng.standard_normal((MEMBERS, batch.structures[0].n_dofs)) * 1e-3
    y = rng.standard_normal((MEMBERS, batch.n_unknowns))
    y[:, 0] = rng.uniform(0.1, 0.9, MEMBERS) * batch.length
    return q, y


CASES = [
    pytest.param(kind, orientation, line, offset, id=f"{kind}-{orientation}-{line}-{where}")
    for (kind, orientation), line, (where, offset) in product(JOINTS, LINES, OFFSETS.items())
]


@pytest.mark.parametrize("kind,orientation,line,offset", CASES)
def test_kernel_equals_reference_on_random_states(kind, orientation, line, offset):
    """The joint evaluated as the solvers do (:meth:`SliderBatch.evaluate`, the pattern of the
    joint) at random states, against the reference at the inputs the batch gathers, with the
    multipliers at scale 1 and 3 (the time integrator's scaling)."""
    batch = batch_of(kind, orientation, line, offset)
    rng = np.random.default_rng(11)
    q, y = random_state(batch, rng)
    for scale in (1.0, 3.0):
        _, r, J = batch.evaluate(q, y, scale=scale)
        _, inputs = batch.joint_inputs(q, y, scale)
        assert_equal_to_roundoff(
            kernel_equations(r, J),
            joint_reference(kind, orientation, inputs),
            roundoff_bounds(kind, orientation, inputs),
        )


@pytest.mark.parametrize("kind,orientation,line,offset", CASES)
def test_kernel_equals_reference_on_random_inputs_and_writes_its_reach(
    kind, orientation, line, offset
):
    """Every input drawn at random (the line state too: curvature, compliances and
    ``l_/xixi`` that the states above leave zero on straight chains), on the shapes and dof
    maps of the batch, the kernel writing into a Jacobian with every block: it writes exactly
    the blocks of the law's pattern (:func:`sliders.joints.equations.pattern`: nothing else,
    and each somewhere nonzero with the sliding point off the node) and equals the reference
    to roundoff."""
    batch = batch_of(kind, orientation, line, offset)
    rng = np.random.default_rng(5)
    _, inputs = batch.joint_inputs(*random_state(batch, rng))
    drawn = JointInputs(
        *(a if np.asarray(a).dtype.kind == "i" else rng.uniform(-1, 1, np.shape(a)) for a in inputs)
    )
    # the offset decides the lever arm's blocks: drawn only off the node
    drawn = drawn._replace(offset=drawn.offset if np.any(offset) else offset, scale=1.7)
    writes = batch.pattern
    batch.pattern = tuple(product(GROUPS, GROUPS))
    r, J = batch.joint_equations(drawn)
    kernel = kernel_equations(r, J)
    for (rows, cols), block in kernel.jacobian.items():
        if (rows, cols) not in writes:
            assert np.all(block == 0), (rows, cols)
        elif np.any(offset):  # on the node, (turn, lam) = skew(f + theta_b x f) is zero
            assert block.size == 0 or np.any(block != 0), (rows, cols)
    assert_equal_to_roundoff(
        kernel,
        joint_reference(kind, orientation, drawn),
        roundoff_bounds(kind, orientation, drawn),
    )


@pytest.mark.parametrize(
    "kind,orientation,line",
    [
        ("spherical", "section", "arc"),
        ("classical", "section", "fv3"),
        ("spline", "section", "galerkin-p2"),
        ("classical", "slope", "fv3 smeared"),
    ],
)
def test_a_pattern_without_a_block_the_kernel_writes_is_an_error(kind, orientation, line):
    """Dropping any one block the kernel writes from the joint's pattern is a ValueError
    naming the joint, the block and the pattern, raised before the compiled kernel runs
    (with and without the Jacobian), where the block's offset would have been -1."""
    batch = batch_of(kind, orientation, line, OFFSETS["off the node"])
    q, y = random_state(batch, np.random.default_rng(2))
    writes = batch.pattern
    for block in writes:
        batch.pattern = tuple(b for b in writes if b != block)
        for jacobian in (True, False):
            with pytest.raises(ValueError) as error:
                batch.evaluate(q, y, jacobian=jacobian)
            message = str(error.value)
            assert message.startswith(f"slider {batch.sliders[0].name!r}: ")
            assert f"block ({block[0]}, {block[1]})" in message
            assert str(list(batch.pattern)) in message


def test_inputs_the_pattern_was_not_laid_out_for_are_an_error():
    """The check follows what the kernel will write at the inputs it is given: a joint laid
    out on the node (no lever-arm blocks) handed a sliding point off the node."""
    batch = batch_of("classical", "section", "fv3", OFFSETS["on the node"])
    _, inputs = batch.joint_inputs(*random_state(batch, np.random.default_rng(6)))
    off = inputs._replace(offset=OFFSETS["off the node"])
    with pytest.raises(ValueError, match=r"slider 'A': the kernel writes block \(turn, turn\)"):
        batch.joint_equations(off)


def test_a_pattern_naming_an_unknown_group_is_an_error():
    """A block of a group that is not among the joint's slots: ValueError naming the joint,
    the block, the pattern and the groups there are."""
    batch = batch_of("classical", "section", "fv3", OFFSETS["on the node"])
    q, y = random_state(batch, np.random.default_rng(3))
    batch.pattern = batch.pattern + (("turn", "torque"),)
    with pytest.raises(ValueError, match=r"slider 'A': block \(turn, torque\) of the pattern") as e:
        batch.evaluate(q, y)
    assert "body, turn, load, rotation, interp, beside, xi, lam, mu" in str(e.value)


def test_writing_a_block_outside_the_pattern_is_an_error():
    """The numpy side of the contract: a block the joint does not declare (``(xi, body)``:
    the ``xi`` equation does not read the body's translations) is a ValueError naming it and
    the pattern."""
    batch = batch_of("spherical", "section", "fv3", OFFSETS["on the node"])
    _, _, J = batch.evaluate(*random_state(batch, np.random.default_rng(4)))
    with pytest.raises(ValueError, match=r"block \(xi, body\) is not in the joint's pattern \["):
        J.block("xi", "body")


def test_the_reference_of_an_unknown_slider_is_an_error():
    """A kind and orientation with no equations (the slope form is the classical slider's)
    is a ValueError naming both."""
    batch = batch_of("spherical", "section", "arc", OFFSETS["on the node"])
    _, inputs = batch.joint_inputs(*random_state(batch, np.random.default_rng(7)))
    with pytest.raises(ValueError, match="no slider equations for kind 'spherical' with "):
        joint_reference("spherical", "slope", inputs)
