"""The condensed step's compiled kernel against its dense reference, both against the Newton
equations they solve.

:func:`sliders.solve.condensed_kernel.condensed_step` (through
:meth:`sliders.solve.condensed.CondensedOperator.step`) and
:func:`sliders.solve.condensed_reference.condensed_step` on random problems: the stiffness of
two beams with random geometry and sections (a clamped fv3 beam and a free galerkin-p2 one:
a sparse ``K`` with six free rigid modes), of the same beams both clamped (``K`` regular), or
a random sparse symmetric positive definite matrix; joints in two batches (one and two joints
per member) with random Jacobian blocks on a pattern like a slider's (body, turn, load and
rotation slots; ``xi``, ``lambda``, ``mu`` unknowns), a tenth of their entries zero, their
slots on random nodes (supported dofs, and dofs shared by two slots, included); the columns
of ``B^{-1}`` stored at once or computed as the joints need them.

Tolerances (derived).  Both compute ``z = [dq; dy]`` solving the Newton equations
``J z = rhs`` (``J = [K + P E P^T, P A; C P^T, D]`` on the free dofs, assembled here densely
from the joints' blocks), each with a residual ``res = J z - rhs``.  Then
``z_kernel - z_reference = J^{-1} (res_kernel - res_reference)`` exactly, so componentwise
``|z_kernel - z_reference| <= |J^{-1}| (|res_kernel| + |res_reference|)``, the residuals
being evaluated to ``gamma_n (|J| |z| + |rhs|)`` (``n`` the longest row of ``J``; Higham,
Accuracy and Stability of Numerical Algorithms, Sec. 3.5).  The residuals themselves are
round-off: the step solves the small system ``S`` (size ``s``) through its equilibrated
inverse (the kernel; the reference by LU), whose residual is at most ``c_s u kappa(S_e)``
relative to ``|S| |v|`` (Higham, Sec. 14.1, with ``c_s`` a modest multiple of ``s``, taken
``s`` here), and maps it into the Newton equations through ``B``'s backward-stable LU: the
normwise backward error ``|res|_inf / (|J|_inf |z|_inf + |rhs|_inf)`` is at most
``s eps kappa_1(S_e)``, ``S_e`` the equilibrated small system.
"""

import numpy as np
import pytest
import scipy.sparse as sp
from test_sliders import L, sliding_beams_model

from fvbeam import Beam, Section, Structure, Support, straight
from fvbeam.mechanism import rigid_modes, unresisted
from sliders.joints.blocks import SlotJacobian
from sliders.solve import condensed
from sliders.solve import condensed_kernel as kernel
from sliders.solve import condensed_reference as reference
from sliders.solve.condensed import SINGULAR_RCOND, CondensedOperator
from sliders.solve.statics import SliderStatics, newton_many

EPS = np.finfo(float).eps

#: The joints' structure slot groups, unknowns and Jacobian pattern: the shape of a slider's
#: (:class:`sliders.joints.slider.Slider`) with a lever arm (the body rotations read by the
#: body's moment rows: the ``c`` slots) and section rotation dofs.
GROUPS = [("body", 3), ("turn", 3), ("load", 6), ("rotation", 6)]
UNKNOWNS = [("xi", 1), ("lam", 3), ("mu", 2)]
PATTERN = [
    ("body", "lam"),
    ("turn", "lam"),
    ("turn", "turn"),
    ("turn", "mu"),
    ("load", "lam"),
    ("load", "xi"),
    ("rotation", "mu"),
    ("xi", "xi"),
    ("xi", "lam"),
    ("xi", "mu"),
    ("xi", "body"),
    ("xi", "load"),
    ("lam", "body"),
    ("lam", "load"),
    ("lam", "xi"),
    ("mu", "turn"),
    ("mu", "rotation"),
    ("mu", "xi"),
]
M = sum(n for _, n in UNKNOWNS)


class Problem:
    """Two beams with random geometry and sections (nodes of beam 0 clamped at its start,
    beam 1 free unless ``clamp_both``), the condensed operator on their stiffness (or on a
    random sparse SPD matrix of the same size, ``random_K``)."""

    def __init__(self, rng, clamp_both=False, random_K=False):
        def section():
            return Section.diagonal(*(10 ** rng.uniform(-1, 1, 6)))

        def segment(n, npe):
            start = rng.uniform(-1, 1, 3)
            return straight(start, start + rng.uniform(0.5, 2.0, 3), n, npe)

        beams = [
            Beam(segment(3, 3), section(), "fv3"),
            Beam(segment(2, 3), section(), "galerkin-p2"),
        ]
        self.structure = Structure(beams)
        supports = [Support(0, "start")] + ([Support(1, "start")] if clamp_both else [])
        fixed = self.structure.support_dofs(supports)
        self.free = np.setdiff1d(np.arange(self.structure.n_dofs), fixed)
        if random_K:
            n = self.structure.n_dofs
            A = sp.random(n, n, density=0.05, random_state=rng)
            self.K = (A @ A.T + sp.diags(rng.uniform(1.0, 2.0, n))).tocsr()
        else:
            self.K = self.structure.tangent(np.zeros(self.structure.n_dofs)).tocsr()
        self.K_free = self.K[self.free][:, self.free]
        phi = unresisted(rigid_modes(self.structure, self.free), self.K_free).phi
        self.operator = CondensedOperator(self.K, self.free, phi)
        self.K_free = self.K_free.toarray()
        self.position = np.full(self.structure.n_dofs, -1)
        self.position[self.free] = np.arange(len(self.free))
        self.nodes = [dofs[::6] // 6 for dofs in self.structure.dof_maps]

    def slots(self, rng, body_beams, line_beams):
        """One joint's slot positions: the body on a random node of ``body_beams``, the load
        on a random node and the rotation on two random nodes of ``line_beams`` (free-dof
        positions, -1 supported)."""

        def node(beams):
            return rng.choice(np.concatenate([self.nodes[b] for b in beams]))

        body, load = node(body_beams), node(line_beams)
        dofs = [6 * body + np.arange(6), 6 * load + np.arange(6)]
        dofs += [6 * node(line_beams) + np.arange(3, 6) for _ in range(2)]
        return self.position[np.concatenate(dofs)]

    def batches(self, rng, members, body_beams=(1,), line_beams=(0, 1)):
        """Two batches of joints (one, then two per member) with random Jacobians, their
        bodies on nodes of ``body_beams`` (a joint takes at most five of a free part's six
        rigid motions: the three forces and two of the couples of its multipliers),
        their lines on nodes of ``line_beams``."""
        slots, blocks = [], []
        for k in (1, 2):
            J = SlotJacobian(k * members, GROUPS, UNKNOWNS, PATTERN)
            shape = J.values.shape
            J.values[:] = (
                rng.standard_normal(shape)
                * 10 ** rng.uniform(-1, 1, shape)
                * (rng.uniform(size=shape) > 0.1)
            )
            slots.append(
                np.array([self.slots(rng, body_beams, line_beams) for _ in range(k * members)])
            )
            blocks.append(J)
        return slots, blocks


def newton_matrix(K_free, joints):
    """``J = [K + P E P^T, P A; C P^T, D]`` on the free dofs and the joints' unknowns."""
    n, m = len(K_free), sum(len(j.D) for j in joints)
    J = np.zeros((n + m, n + m))
    J[:n, :n] = K_free
    at = n
    for joint in joints:
        P, mj = reference.injection(joint.slots, n), len(joint.D)
        J[:n, :n] += P @ joint.E @ P.T
        J[:n, at : at + mj] = P @ joint.A
        J[at : at + mj, :n] = joint.C @ P.T
        J[at : at + mj, at : at + mj] = joint.D
        at += mj
    return J


def equilibrated_rcond(S):
    """The reciprocal condition number of the equilibrated ``S``, by the reference's own
    definitions."""
    return reference.reciprocal_condition(reference.equilibrated(S)[2])


def check_solutions(operator, K_free, slots, blocks, r_free, r_y, kernel, mine):
    """Kernel and reference regular together; where regular, both solve the Newton
    equations to the backward error ``s eps kappa_1(S_e)`` and agree to the componentwise
    bound (module docstring)."""
    (dq, dy, regular), (dq_r, dy_r, regular_r) = kernel, mine
    np.testing.assert_array_equal(regular, regular_r)
    B = len(r_free)
    for b in np.flatnonzero(regular):
        joints = reference.member_joints(slots, blocks, b, B)
        S = reference.small_system(operator, joints, r_free[b], r_y[b]).S
        J = newton_matrix(K_free, joints)
        rhs = -np.concatenate([r_free[b], r_y[b]])
        z_kernel = np.concatenate([dq[b], dy[b]])
        z_reference = np.concatenate([dq_r[b], dy_r[b]])
        residuals = []
        for z in (z_kernel, z_reference):
            res = J @ z - rhs
            scale = np.abs(J).sum(axis=1).max() * np.abs(z).max() + np.abs(rhs).max()
            assert np.abs(res).max() <= len(S) * EPS / equilibrated_rcond(S) * scale
            n_row = int((J != 0).sum(axis=1).max())
            rounding = n_row * EPS / (1 - n_row * EPS) * (np.abs(J) @ np.abs(z) + np.abs(rhs))
            residuals.append(np.abs(res) + rounding)
        bound = np.abs(np.linalg.inv(J)) @ (residuals[0] + residuals[1])
        assert np.all(np.abs(z_kernel - z_reference) <= bound)


@pytest.mark.parametrize("dense", [True, False], ids=["dense inverse", "cached columns"])
@pytest.mark.parametrize(
    "clamp_both,random_K",
    [(False, False), (True, False), (False, True)],
    ids=["free beam", "both clamped", "random SPD"],
)
def test_kernel_equals_the_reference(dense, clamp_both, random_K, monkeypatch):
    """Six members with their own joints and residuals: the same regular members, and the
    same increments to the derived bound; the free beam keeps its six rigid modes."""
    if not dense:
        monkeypatch.setattr(condensed, "DENSE_LIMIT", 0)
    rng = np.random.default_rng(11 + 2 * clamp_both + random_K)
    problem = Problem(rng, clamp_both, random_K)
    assert problem.operator.n_rigid == (6 if not (clamp_both or random_K) else 0)
    assert problem.operator._dense == dense
    B = 6
    slots, blocks = problem.batches(rng, B)
    r_free = rng.standard_normal((B, problem.operator.n_free)) * 10 ** rng.uniform(-2, 2, (B, 1))
    r_y = rng.standard_normal((B, 3 * M))
    kernel = problem.operator.step(r_free, slots, blocks, r_y)
    mine = reference.condensed_step(problem.operator, r_free, slots, blocks, r_y)
    assert kernel[2].all()
    check_solutions(problem.operator, problem.K_free, slots, blocks, r_free, r_y, kernel, mine)


@pytest.mark.parametrize("dense", [True, False], ids=["dense inverse", "cached columns"])
def test_chord_step_is_the_step_on_the_kept_system(dense, monkeypatch):
    """:func:`~sliders.solve.condensed_kernel.chord_step_into` on the small system that
    ``condensed_step_into`` left in its scratch for one set of residuals, with new
    residuals, is the step ``condensed_step`` takes with those residuals and the same
    Jacobians: the same system, inverse and right-hand side by the same code, so the same
    numbers exactly.  The step on the first residuals differs from it (the residuals
    matter)."""
    if not dense:
        monkeypatch.setattr(condensed, "DENSE_LIMIT", 0)
    rng = np.random.default_rng(17)
    problem = Problem(rng)
    operator = problem.operator
    slots, blocks = problem.batches(rng, 1)
    layout = condensed._Layout(slots, blocks, 1)
    operator._inverse()
    if not dense:
        operator._columns(layout.force_dofs)
    n, k, m = operator.n_free, operator.n_rigid, 3 * M
    columns = kernel.Columns(operator._store, operator._slot, operator.phi)
    first, second = [(rng.standard_normal((1, n)), rng.standard_normal((1, m))) for _ in range(2)]
    scratch = kernel.step_scratch(n, layout.batches, layout.nc, m, k)
    force, z = np.empty((1, n)), np.empty((1, layout.nc + m + k))
    regular = np.empty(1, dtype=bool)
    r_free, r_y = first
    kernel.condensed_step_into(
        columns, operator.solve(r_free), r_free, r_y, layout.jacobians, SINGULAR_RCOND, scratch,
        (force, z, regular),
    )  # fmt: skip
    assert regular[0]
    stepped = force.copy(), z.copy()
    r_free, r_y = second
    chord = np.empty((1, n)), np.empty((1, layout.nc + m + k))
    kernel.chord_step_into(
        operator.phi, operator.solve(r_free), r_free, r_y, layout.jacobians, scratch, chord
    )
    fresh = kernel.condensed_step(
        columns, operator.solve(r_free), r_free, r_y, layout.jacobians, SINGULAR_RCOND
    )
    assert fresh[2][0]
    np.testing.assert_array_equal(chord[0], fresh[0])
    np.testing.assert_array_equal(chord[1], fresh[1])
    assert not np.allclose(stepped[1], fresh[1])


def test_a_free_part_no_joint_holds_is_singular():
    """Joints only on the clamped beam leave the free beam's rigid motions to nothing: the
    Newton matrix is singular (its smallest singular value is zero to roundoff) and both
    the kernel and the reference report every member singular."""
    rng = np.random.default_rng(5)
    problem = Problem(rng)
    B = 3
    slots, blocks = problem.batches(rng, B, body_beams=(0,), line_beams=(0,))
    r_free, r_y = rng.standard_normal((B, problem.operator.n_free)), rng.standard_normal((B, 3 * M))
    kernel = problem.operator.step(r_free, slots, blocks, r_y)
    mine = reference.condensed_step(problem.operator, r_free, slots, blocks, r_y)
    assert not kernel[2].any() and not mine[2].any()
    for b in range(B):
        J = newton_matrix(problem.K_free, reference.member_joints(slots, blocks, b, B))
        sigma = np.linalg.svd(J, compute_uv=False)
        assert sigma[-1] <= len(J) * EPS * sigma[0]


@pytest.mark.parametrize("gap,regular", [(1e-15, False), (1e-4, True)])
def test_the_singular_test_is_the_equilibrated_condition(gap, regular):
    """A joint's second ``mu`` equation made its first times a random factor, plus ``gap``
    times another random row: two rows of the small system differ by ``gap`` relative, so
    its equilibrated reciprocal condition is of order ``gap``: far below
    :data:`SINGULAR_RCOND` for ``gap = 1e-15`` (not exactly singular: no pivot is zero),
    far above for ``1e-4``.  The kernel and the reference decide alike, and agree where
    regular."""
    rng = np.random.default_rng(8)
    problem = Problem(rng)
    B = 2
    slots, blocks = problem.batches(rng, B)
    factor = rng.uniform(0.5, 2.0, B)
    for (rows, _), block in blocks[0].blocks.items():
        if rows == "mu":
            noise = rng.standard_normal(block[:, 0].shape) * np.abs(block[:, 0]).max()
            block[:, 1] = factor[:, None] * block[:, 0] + gap * noise
    r_free, r_y = rng.standard_normal((B, problem.operator.n_free)), rng.standard_normal((B, 3 * M))
    kernel = problem.operator.step(r_free, slots, blocks, r_y)
    mine = reference.condensed_step(problem.operator, r_free, slots, blocks, r_y)
    for b in range(B):
        joints = reference.member_joints(slots, blocks, b, B)
        rcond = equilibrated_rcond(
            reference.small_system(problem.operator, joints, r_free[b], r_y[b]).S
        )
        assert (rcond >= 1e3 * SINGULAR_RCOND) if regular else (rcond <= 1e-3 * SINGULAR_RCOND)
    assert kernel[2].tolist() == mine[2].tolist() == [regular] * B
    check_solutions(problem.operator, problem.K_free, slots, blocks, r_free, r_y, kernel, mine)


@pytest.mark.parametrize("kind", ["spherical", "classical"])
@pytest.mark.parametrize("name", ["fv2", "galerkin-p2"])
def test_kernel_equals_the_reference_on_sliding_beams(kind, name, monkeypatch):
    """Every condensed Newton step of the sliding-beams setup (the piston held only by its
    sliders: four free rigid modes; the joints' real Jacobians and slots), the kernel's
    increments against the reference's on the same arguments, to the derived bound."""
    structure, supports, sliders, P = sliding_beams_model(0.43 * L, 3, kind, name)
    statics = SliderStatics(structure, supports, sliders, method="condensed")
    operator = statics._condensed
    K_free = statics.K[statics.free][:, statics.free].toarray()
    step, calls = CondensedOperator.step, []

    def compared(self, r_free, slots, blocks, r_y):
        kernel = step(self, r_free, slots, blocks, r_y)
        mine = reference.condensed_step(self, r_free, slots, blocks, r_y)
        check_solutions(self, K_free, slots, blocks, r_free, r_y, kernel, mine)
        calls.append(kernel[2].all())
        return kernel

    monkeypatch.setattr(CondensedOperator, "step", compared)
    load = structure.gather(1, P.nodal_load("end", (0, 1.0e3, 0)))
    batches = [s.batch(structure) for s in sliders]
    newton_many([statics], batches, load[None], [None], 1e-8, 25)  # the Python loop's steps
    assert operator.n_rigid == 4 and len(calls) >= 2 and all(calls)
