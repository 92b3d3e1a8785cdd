"""Modes about a solved static state: frequencies, damping ratios and mode shapes.

The structure with its supports, sliders and force elements, linearised about a converged
state ``(q, y)`` of :class:`~sliders.solve.statics.SliderStatics`, vibrates as::

    M q'' + C q' + (K + E) q + A y = 0,      C_y q + D y = 0

with ``[K + E, A; C_y, D]`` the Newton matrix of the statics at the state
(:meth:`~sliders.solve.statics.SliderStatics.jacobian`: the beams' stiffness on the free dofs
bordered by each slider's Jacobian in its unknowns ``y``, the abscissa and the multipliers)
plus the force elements' stiffness ``dr/dq`` at rest, ``M`` the structure's mass (the
sliders' unknowns carry none), ``C`` the stiffness-proportional damping ``damping K`` of the
beams (as in :class:`~sliders.solve.dynamics.Dynamics`) plus the force elements' ``dr/dv``.

The massless unknowns ``y`` are eliminated, so that the pencil left is regular on the
motions the sliders allow and has no root of the constraints (the bordered pencil's
infinite eigenvalues are defective, index 2, and rounding moves them by ``u^(1/2)`` of the
largest inverse eigenvalue, where they were told from the modes only by a threshold).
Slider by slider (its rows touch its own unknowns only), the block ``D``, its rows and
columns equilibrated (each row of ``[C_y D]`` and column of ``[A; D]`` to a largest entry of
1), is split by its singular value decomposition ``D = U S V^T``:

* the part of ``S`` above :data:`RIGID` (``sqrt(u)`` of the largest) is regular: its
  unknowns (the abscissa, a multiplier along the frictionless tangent, a multiplier of a
  compliant line: a chain of cubic elements, the kink correction of a section orientation)
  follow the structure, ``y_1 = -S_1^-1 U_1^T C_y q``, and add ``-A V_1 S_1^-1 U_1^T C_y``
  to the stiffness (static condensation).  Below ``sqrt(u)`` a compliance is taken as
  rigid: that changes the problem by less than its own size, whereas condensing it would
  lift rounding errors by its inverse, so ``sqrt(u)`` is where the two errors meet;
* the rest are constraints ``G q = 0`` (``G = U_2^T C_y``) with reactions ``B y_2``
  (``B = A V_2``): the sliders' rigid connections.

Then ``q = Z w`` on a basis ``Z`` of the null space of ``G`` and the rows are taken with a
basis ``Y`` of the null space of ``B^T`` (which takes out the reactions), both by
:func:`fvbeam.null_space.null_basis` (one dof per constraint eliminated, the master-slave
way: the rows touch a few dofs each, so ``Z`` and ``Y`` are the identity but on those):
``Y^T (K + E) Z``, ``Y^T M Z`` and ``Y^T C Z``, the same sparsity as the structure's.  The
finite-volume stiffness is unsymmetric and a slider's load transfer is not its
interpolation, so ``Y`` is not ``Z``.  The pencil is solved by
:func:`fvbeam.modes.lowest_modes` (one sparse LU per state, shift-invert).

Real modes when the damping is absent or proportional (``C = damping (K + E)`` on the
reduced unknowns: no force element, and no stiffness of the sliders' own, which about an
unloaded state they have none; each mode's ratio is then ``damping omega / 2``), complex
modes otherwise, whose eigenvalue ``s`` gives the natural frequency ``|s|`` and the damping
ratio ``-Re s / |s|``; overdamped (non-oscillating) roots are not returned.

**Preloaded modes.**  With linear beams, about a loaded state the modes take the beams'
unloaded stiffness (no geometric stiffness of the preload; the sliders' terms in their
multipliers are kept), which :func:`modes_about` says in a warning.  Given a
:class:`Preload`, a state of the geometrically exact beams
(:class:`fvbeam.exact_structure.ExactStructure`), ``K`` is their tangent there, material and
geometric stiffness of the preload (:meth:`~fvbeam.exact_structure.ExactStructure.tangent`;
the loads are dead, so they add none), and ``M`` their mass with the rotary inertia turned
to the current sections (:meth:`~fvbeam.exact_structure.ExactStructure.mass`), both in the
tangent's spatial increments ``[du, dphi]``; the beams' damping is ``damping`` times that
tangent.  No warning then.  With rigid bodies and joints
(:class:`sliders.joints.exact_model.ExactModel`, :meth:`Preload.of_model`) the joints' rows
``B`` at the converged state join the sliders' constraints (``G`` gains the rows ``B``,
the reactions the columns ``B^T``: one reduction by :func:`fvbeam.null_space.null_basis`),
their geometric stiffness ``sum H_j`` (the rows' second derivatives times the converged
multipliers) joins the stiffness, not the damping, and each body's mass is turned whole by
its rotation (:meth:`fvbeam.exact_bodies.ExactBodies.mass`, exact off its centre of
mass).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import scipy.sparse as sp
from scipy.optimize import linear_sum_assignment

from fvbeam.modes import lowest_modes
from fvbeam.null_space import null_basis
from sliders.forces.kernel import evaluate_element
from sliders.solve.mechanism import joint_parts
from sliders.solve.statics import SliderSolution, SliderStatics

if TYPE_CHECKING:  # the exact beams are imported by whoever built the state
    from fvbeam.exact_beam import ExactState
    from fvbeam.exact_structure import ExactStructure
    from sliders.joints.exact_model import ExactModel, JointedState

#: The warning of a state under load (module docstring).
PRELOAD_WARNING = (
    "modes about a loaded state take the beams' linear, unloaded stiffness: the geometric "
    "stiffness of the preload is not included"
)


@dataclass(frozen=True)
class Preload:
    """A state of geometrically exact beams, with bodies and joints, to take the modes
    about (module docstring): ``stiffness`` the beams' tangent and ``mass`` the mass there,
    ``joints`` the joints' geometric stiffness ``sum H_j`` and ``rows`` their constraint rows
    ``B`` (one per row of the joints), all on the structure's dofs."""

    stiffness: sp.csr_matrix
    mass: sp.csr_matrix
    joints: sp.csr_matrix | None = None
    rows: sp.csr_matrix | None = None

    @classmethod
    def at(cls, exact: ExactStructure, state: ExactState, mass: str = "lumped") -> Preload:
        """The tangent and the mass of ``exact`` at ``state`` (``mass`` ``lumped`` or
        ``consistent``)."""
        return cls(sp.csr_matrix(exact.tangent(state)), exact.mass(state, mass))

    @classmethod
    def of_model(cls, model: ExactModel, state: JointedState, mass: str = "lumped") -> Preload:
        """The beams' tangent, the mass (the bodies' turned whole,
        :meth:`fvbeam.exact_bodies.ExactBodies.mass`), the joints' geometric stiffness and
        their rows of the exact ``model`` at its converged ``state`` (the blocks of its
        bordered tangent ``[K + sum H, B^T; B, 0]``,
        :meth:`~sliders.joints.exact_model.ExactModel.joint_blocks`)."""
        points = model.points(state)
        joints, rows = model.joint_blocks(state, points)
        joints.eliminate_zeros()  # the reduction reads the columns the rows touch
        rows.eliminate_zeros()
        beams = sp.csr_matrix(model.exact.tangent(state.nodes, points.parts))
        return cls(beams, model.exact.mass(state.nodes, mass), joints, rows)


@dataclass(frozen=True)
class StateModes:
    """Modes about a state, by ascending frequency.

    Attributes
    ----------
    omega
        (k,) natural frequencies, rad/s (of a damped mode ``|s|``).
    damping_ratio
        (k,) damping ratios (``-Re s / |s|``; 0 without damping).
    shapes
        (n_dofs, k) mode shapes on the structure's dofs, zero at the supports: real modes
        scaled to unit modal mass ``phi^T M phi = 1``, complex ones to a largest entry of 1.
    """

    omega: np.ndarray
    damping_ratio: np.ndarray
    shapes: np.ndarray

    @property
    def hertz(self) -> np.ndarray:
        """Natural frequencies in Hz, ``omega / 2 pi``."""
        return self.omega / (2 * np.pi)

    @property
    def complex(self) -> bool:
        """Whether the shapes are complex (non-proportional damping)."""
        return bool(np.iscomplexobj(self.shapes))


def _force_blocks(statics: SliderStatics, q: np.ndarray) -> tuple[sp.coo_matrix, sp.coo_matrix]:
    """The force elements' stiffness ``dr/dq`` and damping ``dr/dv`` at ``q`` and rest, on the
    free dofs (:func:`sliders.forces.kernel.evaluate_element` at ``c_v = 0`` and ``1``)."""
    nf = len(statics.free)
    position = np.full(statics.structure.n_dofs, -1)
    position[statics.free] = np.arange(nf)
    rows, cols, k_vals, c_vals = [], [], [], []
    r, J0, J1, rest = np.empty(6), np.empty((6, 6)), np.empty((6, 6)), np.zeros(6)
    for element in statics.forces:
        slots = element.slots(statics.structure)
        p, at = element.packed(statics.structure), np.ascontiguousarray(q[slots])
        evaluate_element(element.kind, p, at, rest, 0.0, 1.0, r, J0)
        evaluate_element(element.kind, p, at, rest, 1.0, 1.0, r, J1)
        index = position[slots]
        keep = index >= 0
        rr, cc = np.meshgrid(index[keep], index[keep], indexing="ij")
        rows.append(rr.ravel())
        cols.append(cc.ravel())
        k_vals.append(J0[np.ix_(keep, keep)].ravel())
        c_vals.append((J1 - J0)[np.ix_(keep, keep)].ravel())
    if not rows:
        empty = sp.coo_matrix((nf, nf))
        return empty, empty
    rc = (np.concatenate(rows), np.concatenate(cols))
    return (
        sp.coo_matrix((np.concatenate(k_vals), rc), shape=(nf, nf)),
        sp.coo_matrix((np.concatenate(c_vals), rc), shape=(nf, nf)),
    )


@dataclass(frozen=True)
class Reduction:
    """The linearised problem on the motions the constraints leave free (module docstring):
    ``K``, ``M``, ``C`` on the reduced unknowns ``w`` (``q_free = Z w``), whether the
    damping is proportional, ``C = damping K``, and the positions of the reduced rows and
    columns in the structure's banded order (:attr:`fvbeam.structure.Structure.dof_rank`
    of the free dofs they keep), for the sparse LU."""

    K: sp.csc_matrix
    M: sp.csc_matrix
    C: sp.csc_matrix
    Z: sp.csc_matrix
    proportional: bool
    ranks: tuple[np.ndarray, np.ndarray]


#: Singular values of a slider's equilibrated multiplier block below this part of the
#: largest are constraints, not compliances (module docstring): ``sqrt(u)``.
RIGID = float(np.sqrt(np.finfo(float).eps / 2))


def _joint_blocks(
    statics: SliderStatics, q: np.ndarray, unknowns: list[np.ndarray]
) -> tuple[sp.coo_matrix, sp.coo_matrix, sp.coo_matrix]:
    """The sliders' stiffness on the free dofs (their ``dr/dq`` and the compliant part of
    their unknowns condensed), their constraint rows ``G`` and their multipliers' columns
    ``B`` (module docstring), all on the free dofs."""
    nf = len(statics.free)
    position = np.full(statics.structure.n_dofs, -1)
    position[statics.free] = np.arange(nf)
    stiffness: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []
    rows: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []
    columns: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []
    count = 0
    for dofs, _, _, J in joint_parts(statics.structure, statics.sliders, q, unknowns):
        t = len(dofs)
        index = position[dofs]
        keep = index >= 0
        index = index[keep]
        A, C = J[:t, t:][keep], J[t:, :t][:, keep]
        D = J[t:, t:]
        K = J[:t, :t][np.ix_(keep, keep)]
        # equilibrate: each row of [C D] and each column of [A; D] to a largest entry of 1
        rho = _largest(np.hstack([C, D]), axis=1)
        gamma = _largest(np.vstack([A, D]), axis=0)
        U, s, Vt = np.linalg.svd(D / rho[:, None] / gamma[None, :])
        rank = int(np.sum(s > RIGID * s[0])) if s.size and s[0] > 0 else 0
        C_u = U.T @ (C / rho[:, None])
        A_v = (A / gamma[None, :]) @ Vt.T
        K = K - A_v[:, :rank] @ (C_u[:rank] / s[:rank, None])
        stiffness.append(_block(index, index, K))
        constraints = np.arange(count, count + len(s) - rank)
        rows.append(_block(constraints, index, C_u[rank:]))
        columns.append(_block(index, constraints, A_v[:, rank:]))
        count += len(s) - rank
    return (
        _assembled(stiffness, (nf, nf)),
        _assembled(rows, (count, nf)),
        _assembled(columns, (nf, count)),
    )


def _largest(a: np.ndarray, axis: int) -> np.ndarray:
    """The largest magnitude along ``axis``, 1 where all are zero."""
    m = np.abs(a).max(axis=axis) if a.size else np.zeros(a.shape[1 - axis])
    return np.where(m > 0, m, 1.0)


def _block(
    rows: np.ndarray, cols: np.ndarray, values: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A dense block's entries as ``(rows, cols, values)``."""
    rr, cc = np.meshgrid(rows, cols, indexing="ij")
    return rr.ravel(), cc.ravel(), values.ravel()


def _assembled(blocks: list, shape: tuple[int, int]) -> sp.coo_matrix:
    """A sparse matrix of the ``(rows, cols, values)`` blocks (repeated entries summed)."""
    if not blocks:
        return sp.coo_matrix(shape)
    rows, cols, values = (np.concatenate(parts) for parts in zip(*blocks, strict=True))
    return sp.coo_matrix((values, (rows, cols)), shape=shape)


def reduction(
    statics: SliderStatics,
    solution: SliderSolution,
    mass: str = "lumped",
    damping: float = 0.0,
    preload: Preload | None = None,
) -> Reduction:
    """The linearised problem about ``solution`` on the motions its sliders leave free
    (module docstring; ``mass``, ``damping`` and ``preload`` as in :func:`modes_about`).

    Raises
    ------
    ValueError
        Constraint rows and multiplier columns of different ranks (redundant constraints
        whose reactions the state does not determine).
    """
    q = solution.q
    free = statics.free
    K_j, G, B = _joint_blocks(statics, q, list(solution.unknowns))
    K_f, C_f = _force_blocks(statics, q)
    if preload is not None and preload.rows is not None and preload.joints is not None:
        rows_free = preload.rows[:, free]
        G, B = sp.vstack([G, rows_free]), sp.hstack([B, rows_free.T])
        K_j = K_j + preload.joints[free][:, free]
    extra = (K_j + K_f).tocsr()
    extra.eliminate_zeros()
    C_f = C_f.tocsr()
    C_f.eliminate_zeros()
    Z, columns = null_basis(G)
    Y, rows = null_basis(B.T)
    if Z.shape[1] != Y.shape[1]:
        raise ValueError(
            f"the sliders' constraints have rank {len(free) - Z.shape[1]} but their reactions "
            f"rank {len(free) - Y.shape[1]}: redundant constraints the state cannot resolve"
        )
    if preload is None:
        K_free, M_all = statics.K_free.tocsr(), statics.structure.mass(mass)
    else:
        K_free, M_all = preload.stiffness[free][:, free].tocsr(), preload.mass
    Yt = Y.T.tocsr()
    K = (Yt @ (K_free + extra) @ Z).tocsc()
    M = (Yt @ M_all.tocsr()[free][:, free] @ Z).tocsc()
    C = (Yt @ (damping * K_free + C_f) @ Z).tocsc()
    C.eliminate_zeros()
    proportional = C.nnz == 0 or (C_f.nnz == 0 and extra.nnz == 0)
    rank = statics.structure.dof_rank[free]
    return Reduction(K, M, C, Z, proportional, (rank[rows], rank[columns]))


def modes_about(
    statics: SliderStatics,
    solution: SliderSolution,
    count: int,
    *,
    mass: str = "lumped",
    damping: float = 0.0,
    window: tuple[float, float] | None = None,
    preload: Preload | None = None,
) -> StateModes:
    """The ``count`` lowest modes about the state ``solution`` of ``statics`` (module
    docstring).

    Parameters
    ----------
    statics
        The problem (3-D: a planar one's joints are pinned out of its plane, which its
        sliders' rows do not express).
    solution
        A converged state of it.
    count
        Number of modes, ``>= 1``.
    mass
        ``lumped`` or ``consistent`` (:meth:`fvbeam.structure.Structure.mass`).
    damping
        Stiffness-proportional coefficient (s) of the beams' damping, ``>= 0``.
    window
        ``(f_min, f_max)`` in Hz: the modes of frequency in the window (at most ``count``,
        the lowest from ``f_min`` on); None: the ``count`` lowest.
    preload
        The exact beams' tangent and mass at the state (:meth:`Preload.at`): the modes
        with the geometric stiffness of the preload; None: the linear beams' (with a warning
        about a loaded state).

    Raises
    ------
    ValueError
        A bad argument, a planar problem, redundant constraints, or a state whose
        linearised stiffness is singular.
    """
    if not (isinstance(count, (int, np.integer)) and count >= 1):
        raise ValueError(f"count must be an integer >= 1, got {count!r}")
    if not (np.isfinite(damping) and damping >= 0):
        raise ValueError(f"damping must be a finite coefficient >= 0, got {damping!r}")
    if window is not None and not (0 <= window[0] < window[1]):
        raise ValueError(f"window must be (f_min, f_max) with 0 <= f_min < f_max, got {window}")
    if statics.plane is not None:
        raise ValueError("modes are solved on the 3-D problem: build its statics without plane")
    if preload is None and np.any(solution.q != 0):
        warnings.warn(PRELOAD_WARNING, UserWarning, stacklevel=2)
    problem = reduction(statics, solution, mass, damping, preload)
    shift = 0.0 if window is None else (2 * np.pi * window[0]) ** 2
    wanted = count if window is None else 2 * count
    try:
        damping_matrix = None if problem.proportional else problem.C
        spectrum = lowest_modes(problem.K, problem.M, wanted, damping_matrix, shift, problem.ranks)
    except RuntimeError as exc:  # splu: exactly singular
        raise ValueError(f"the linearised problem is singular at the state: {exc}") from exc
    if problem.proportional:
        if spectrum.s.size and spectrum.s.min() <= 0:
            raise ValueError(
                "the linearised stiffness is not positive at the state (omega^2 = "
                f"{spectrum.s.min():.6g}): a motion the supports and sliders leave free, "
                "or a buckled state"
            )
        omega = np.sqrt(spectrum.s)
        zeta = damping * omega / 2
    else:
        s = spectrum.s
        omega, zeta = np.abs(s), -s.real / np.abs(s)
    order = np.argsort(omega)
    if window is not None:
        low, high = 2 * np.pi * np.asarray(window)
        order = order[(omega[order] >= low * (1 - 1e-12)) & (omega[order] <= high)]
    order = order[:count]
    M_all = statics.structure.mass(mass) if preload is None else preload.mass
    M_free = M_all.tocsr()[statics.free][:, statics.free]
    vectors = _normalised(problem.Z @ spectrum.vectors[:, order], M_free)
    shapes = np.zeros((statics.structure.n_dofs, len(order)), dtype=vectors.dtype)
    shapes[statics.free] = vectors
    return StateModes(omega[order], zeta[order], shapes)


def _normalised(vectors: np.ndarray, M: sp.spmatrix) -> np.ndarray:
    """Real vectors to unit modal mass, complex ones to a largest entry of 1; either with its
    largest entry positive (a sign, or a phase, fixed for the tables)."""
    if np.iscomplexobj(vectors):
        peak = vectors[np.abs(vectors).argmax(axis=0), np.arange(vectors.shape[1])]
        return vectors / peak
    vectors = vectors / np.sqrt(np.einsum("ik,ik->k", vectors, M @ vectors))
    peak = vectors[np.abs(vectors).argmax(axis=0), np.arange(vectors.shape[1])]
    return vectors * np.sign(peak)


def mac(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The modal assurance criterion of every shape of ``a`` (n, ka) with every shape of
    ``b`` (n, kb): ``|a^H b|^2 / ((a^H a)(b^H b))`` (Allemang, "The modal assurance
    criterion", Proc. IMAC 21, 2003), 1 for shapes equal up to a factor, 0 for orthogonal
    ones."""
    cross = np.abs(a.conj().T @ b) ** 2
    norms = np.outer(np.sum(np.abs(a) ** 2, axis=0), np.sum(np.abs(b) ** 2, axis=0))
    return cross / np.where(norms > 0, norms, 1.0)


def follow(previous: np.ndarray, current: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Number the ``current`` shapes (n, k) after the ``previous`` ones (n, k'), numbered by
    their columns, that they resemble: the assignment of largest total MAC
    (:func:`scipy.optimize.linear_sum_assignment`), so that a mode keeps its number where
    frequencies cross.  Returns each current shape's number (k,) (the shapes left over when
    ``k > k'`` take ``k'``, ``k' + 1``, ... in their order) and its MAC to the previous shape
    of that number (NaN for those left over)."""
    table = mac(previous, current)
    rows, cols = linear_sum_assignment(table, maximize=True)
    k = current.shape[1]
    number, values = np.full(k, -1), np.full(k, np.nan)
    number[cols], values[cols] = rows, table[rows, cols]
    left = number < 0
    number[left] = previous.shape[1] + np.arange(int(left.sum()))
    return number, values
