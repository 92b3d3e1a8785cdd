"""Static equilibrium of a structure with sliders: Newton-Raphson on linear beams.

The beams are linear (stiffness ``K`` assembled once); the sliders touch a few dofs ``T`` and
add their own unknowns ``y``.  Each Newton step solves::

    (K + E) dq + A dy = -r_q,      C dq + D dy = -r_y

with ``E, A, C, D`` the sliders' Jacobian blocks on ``T`` and ``y`` (free dofs only; the
supports are eliminated).  Two linear-algebra back ends share one Newton loop:

``bordered``
    factorises the whole bordered matrix at every step.  ``K`` alone may be singular (a
    piston held only by its sliders is a free body until the sliders are added); the
    bordered matrix is regular as soon as the sliders hold it.
``condensed``
    factorises ``K``, bordered by the free parts' rigid motions, once per structure and
    support set, and solves a small dense system on ``T``, ``y`` and the rigid amplitudes
    per step (:mod:`sliders.solve.condensed`).

:func:`newton_many` is the Newton loop, for independent members of one shape at once
(:func:`solve_many`; the condensed steps of all members are one stacked solve); a single
solve is its one-member case.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from numpy.typing import ArrayLike

from fvbeam.beam import Beam
from fvbeam.body import RigidBody
from fvbeam.copies import shallow_copy
from fvbeam.mechanism import (
    RigidModes,
    node_positions,
    rigid_modes,
    unresisted,
)
from fvbeam.structure import Structure
from fvbeam.support import Support, complement
from sliders.forces.elements import ForceElement
from sliders.joints.slider import Slider, SliderBatch
from sliders.solve.condensed import CondensedOperator
from sliders.solve.diagnosis import equilibration, singular_motion
from sliders.solve.mechanism import (
    MASSLESS_REMEDY,
    REMEDY,
    free_motion,
    joint_parts,
    member_parts,
)
from sliders.solve.newton import ColumnStorageError, CompiledNewton
from sliders.solve.newton_kernel import NOT_CONVERGED_MESSAGE
from sliders.solve.planar import check, check_load, moved_in_plane, out_of_plane, pin, pinned

METHODS = ("auto", "bordered", "condensed")


@dataclass
class SliderSolution:
    """Displacements ``q``, each slider's unknowns ``[xi, lambda, (mu_2, mu_3)]``, the
    residual norms of the Newton iterations of the last load step (forces scaled by that
    step's load), and the Newton iterations of every load step."""

    q: np.ndarray
    unknowns: list[np.ndarray]
    residuals: list[float]
    step_iterations: list[int] = field(default_factory=list)

    @property
    def iterations(self) -> int:
        """Newton iterations over all load steps."""
        return sum(self.step_iterations)


class SliderStatics:
    """Equilibrium of ``structure`` held by ``supports`` and ``sliders``.

    ``reuse``: a previous instance on beams with the same stiffness objects, dof maps and
    supports (e.g. the same beams translated, :meth:`fvbeam.beam.Beam.translated`), whose
    assembled stiffness (and, for the condensed back end, factorisation and cached columns)
    is then taken as it is; a sweep over positions builds it once.  ``method``: the
    linear-algebra back end, ``bordered`` or ``condensed`` (module docstring), or ``auto``
    (the default: ``condensed`` where it applies, :meth:`_automatic`); :attr:`method` is the
    one taken.  ``plane``: ``xy``, ``yz`` or ``zx`` for a planar problem, solved on its
    in-plane dofs (:mod:`sliders.solve.planar`; ``ValueError`` naming what is not planar).
    ``operator``:
    a matrix that takes the place of the stiffness (the time integrator's
    ``M + c_v C + c_q K``, :mod:`sliders.solve.dynamics`); default the structure's stiffness.

    A solve never returns a solution of a singular system: the rigid motions that the
    supports leave free (:attr:`rigid`) must be held by the sliders, which every start with
    zero multipliers checks (:mod:`sliders.solve.mechanism`), and a singular Newton step ends
    the solve with the free motion named (:meth:`_diagnose`).
    """

    K: sp.csr_matrix
    free: np.ndarray
    _K_free: sp.coo_matrix | None
    _position: np.ndarray
    _condensed: CondensedOperator | None
    _fixed: np.ndarray
    _held: np.ndarray | None

    def __init__(
        self,
        structure: Structure,
        supports: Sequence[Support],
        sliders: Sequence[Slider],
        reuse: "SliderStatics | None" = None,
        method: str = "auto",
        operator: sp.spmatrix | None = None,
        forces: Sequence[ForceElement] = (),
        plane: str | None = None,
    ) -> None:
        if method not in METHODS:
            raise ValueError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
        self.structure, self.sliders, self.method = structure, list(sliders), method
        self.forces = list(forces)
        self._stiffness = operator is None
        self._rigid: RigidModes | None = None
        self._compiled: CompiledNewton | None = None
        names = [s.name for s in self.sliders]
        if len(set(names)) != len(names):
            raise ValueError(f"slider names must be unique, got {names}")
        self.plane = plane
        self._supports = list(supports)
        moved = reuse is not None and reuse._same_supports(structure, self._supports, plane)
        if reuse is not None and moved:  # the same nodes held: a structure moved
            fixed, self._held = reuse._fixed, reuse._held
        else:
            fixed = structure.support_dofs(supports)
            self._held = out_of_plane(structure, plane) if plane is not None else None
            if self._held is not None:  # a planar solve holds the out-of-plane dofs
                fixed = np.union1d(fixed, self._held)
        self._fixed = fixed
        if reuse is not None and operator is None and reuse._same_operator(structure, fixed):
            self.K, self.free, self._K_free = reuse.K, reuse.free, reuse._K_free
            self._position, self._condensed = reuse._position, reuse._condensed
        else:
            reuse = None
            self.K = (
                structure.tangent(np.zeros(structure.n_dofs)) if operator is None else operator
            ).tocsr()
            self.free = complement(structure.n_dofs, fixed)
            self._position = np.full(structure.n_dofs, -1)
            self._position[self.free] = np.arange(len(self.free))
            self._K_free = None
            self._condensed = None
        if plane is not None:  # a reused operator's coupling was checked where it was built
            check(
                structure,
                self.sliders,
                plane,
                [self.K] if reuse is None else [],
                reuse.sliders if reuse is not None and moved else (),
            )
        self._auto = method == "auto"
        if method == "auto":
            method = self.method = self._automatic()
        if method == "condensed" and self._condensed is None:
            self._condensed = CondensedOperator(self.K, self.free, self.rigid.phi)
        if reuse is not None and reuse._compiled is not None and method == reuse.method:
            self._compiled = reuse._compiled.moved(self)

    def moved(self, beams: Sequence[Beam], bodies: Sequence[RigidBody] = ()) -> SliderStatics:
        """This problem with its beams and bodies replaced by ``beams`` and ``bodies``, each
        the one it replaces moved rigidly (:meth:`fvbeam.structure.Structure.moved`, which
        checks them): the sliders moved with them (:meth:`sliders.joints.slider.Slider.
        moved`), the supports, back end, operator, factorisation and cached columns kept (a
        rigid translation changes none of them), the compiled loop's joints moved
        (:meth:`sliders.solve.newton.CompiledNewton.moved`).  What
        ``SliderStatics(structure.moved(...), supports, moved sliders, reuse=self)`` builds,
        without checking again what the move keeps by construction; a planar problem's
        sliders are checked in its plane again unless the move keeps every node's
        coordinate along the normal (:func:`sliders.solve.planar.moved_in_plane`).  A sweep
        over positions moves each point's problem from the last."""
        structure = self.structure.moved(beams, bodies)
        sliders = [slider.moved(structure) for slider in self.sliders]
        if self.plane is not None and not moved_in_plane(self.structure, structure, self.plane):
            check(structure, sliders, self.plane, [], self.sliders)
        out = shallow_copy(self)
        out.structure, out.sliders, out._rigid = structure, sliders, None
        if self._compiled is not None:
            out._compiled = self._compiled.moved(out, known_moved=True)
        return out

    def _automatic(self) -> str:
        """The back end ``auto`` takes: ``condensed`` (the compiled Newton loop on a
        factorisation kept for the problem's life) when the operator bordered by the free
        parts' rigid motions is regular, else ``bordered``, which lets the sliders hold a
        mechanism that is no rigid motion of a part; ``bordered`` without sliders (one linear
        solve).  A problem too large for the condensed columns
        (:class:`~sliders.solve.newton.ColumnStorageError`) turns ``bordered`` at its first
        solve."""
        if not (self.sliders or self.forces):
            return "bordered"
        if self._condensed is None:
            try:
                self._condensed = CondensedOperator(self.K, self.free, self.rigid.phi)
            except ValueError:
                return "bordered"
        return "condensed"

    @property
    def K_free(self) -> sp.coo_matrix:
        """The operator on the free dofs, taken out when first asked for (the bordered back
        end and the free motions of the time integrator's operator read it; the condensed
        one takes it out itself); a problem that reuses this one's operator takes it too
        once it is out."""
        if self._K_free is None:
            self._K_free = self.K[self.free][:, self.free].tocoo()
        return self._K_free

    @property
    def rigid(self) -> RigidModes:
        """The rigid motions that the supports leave free and the operator does not resist
        (:func:`fvbeam.mechanism.rigid_modes`; of the time integrator's operator, those of
        the massless parts, :func:`fvbeam.mechanism.unresisted`), computed when first
        asked for."""
        if self._rigid is None:
            modes = rigid_modes(self.structure, self.free)
            self._rigid = modes if self._stiffness else unresisted(modes, self.K_free)
        return self._rigid

    @property
    def remedy(self) -> str:
        """What would hold a free motion, in the messages: a support, a slider or a drive
        (and on the time integrator's operator, whose free motions are the massless
        parts', a mass)."""
        return REMEDY if self._stiffness else MASSLESS_REMEDY

    def free_motion(
        self, q: np.ndarray, unknowns: Sequence[np.ndarray], remedy: str | None = None
    ) -> str | None:
        """The message naming the rigid motions that neither the supports nor the sliders
        hold at the state ``q``, ``unknowns`` (multipliers zero: a start from rest), or None
        (:func:`sliders.solve.mechanism.free_motion`; ``remedy``: what would hold them,
        default :attr:`remedy`)."""
        parts = joint_parts(self.structure, self.sliders, q, unknowns)
        return free_motion(self.rigid, self._position, parts, self.sliders, remedy or self.remedy)

    def _same_supports(
        self, structure: Structure, supports: list[Support], plane: str | None
    ) -> bool:
        """Whether ``supports`` hold the dofs this problem's supports hold, known without
        locating them again: the same supports and plane on a structure sharing this one's
        node numbering (:meth:`fvbeam.structure.Structure.moved`)."""
        return (
            structure.dof_maps is self.structure.dof_maps
            and plane == self.plane
            and supports == self._supports
        )

    def _same_operator(self, structure: Structure, fixed: np.ndarray) -> bool:
        old = self.structure
        return (
            len(old.beams) == len(structure.beams)
            and all(
                a.stiffness is b.stiffness for a, b in zip(old.beams, structure.beams, strict=True)
            )
            and (
                structure.dof_maps is old.dof_maps
                or all(
                    np.array_equal(a, b)
                    for a, b in zip(old.dof_maps, structure.dof_maps, strict=True)
                )
            )
            and structure.n_dofs == old.n_dofs
            and (fixed is self._fixed or np.array_equal(fixed, self._fixed))
        )

    def initial_unknowns(self, q: np.ndarray) -> list[np.ndarray]:
        return [s.initial_unknowns(self.structure, q) for s in self.sliders]

    def prepare_translations(self) -> None:
        """Build what :func:`solve_translated` moves to every position, once: each slider's
        one-member batch (:meth:`~sliders.joints.slider.Slider.batch`) and its chain's element
        frames (:meth:`~sliders.lines.batched.ChainStack.element_frames`; a translation keeps
        them).  Part of a template's setup; without it the first :func:`solve_translated`
        builds them."""
        for slider in self.sliders:
            batch = slider.batch(self.structure)
            if batch.chains is not None:
                batch.chains.element_frames()

    def solve(
        self,
        f: np.ndarray,
        start: tuple[np.ndarray, list[np.ndarray]] | None = None,
        tol: float = 1e-8,
        max_iterations: int = 25,
        load_steps: int = 1,
    ) -> SliderSolution:
        """Newton-Raphson from ``start`` (default: no displacement, projected ``xi``).

        ``load_steps``: the load is applied in that many equal increments, each solved from
        the previous one's converged state.  Converged when the increments fall below
        ``tol`` relative to their scale: ``q`` to its largest entry, ``xi`` to its line's
        length, multipliers to the largest of them and of the load.  (The scale of ``q`` is
        the largest displacement the solve has met, so a solution at rest, ``q = 0``, still
        converges.)  Raises ``ValueError`` naming the free motion when the system is
        singular, or the last residual when Newton does not converge (with the load step,
        when there are several).
        """
        f = np.asarray(f, dtype=float)
        if f.shape != (self.structure.n_dofs,) or not np.isfinite(f).all():
            raise ValueError(f"load vector must be finite with {self.structure.n_dofs} rows")
        if self.plane is not None:
            check_load(self.structure, f, self.plane, held=self._held)
        if not (isinstance(load_steps, (int, np.integer)) and load_steps >= 1):
            raise ValueError(f"load_steps must be a positive integer, got {load_steps!r}")
        state, counts = start, []
        for k in range(1, load_steps + 1):
            try:
                load = f if load_steps == 1 else f * (k / load_steps)
                q, ys, residuals = self._newton(load, state, tol, max_iterations)
            except ValueError as exc:
                if load_steps == 1:
                    raise
                raise ValueError(f"load step {k} of {load_steps}: {exc}") from exc
            counts.append(len(residuals) - 1)
            state = (q, ys)
        return SliderSolution(q, ys, residuals, counts)

    def _newton(
        self,
        f: np.ndarray,
        start: tuple[np.ndarray, list[np.ndarray]] | None,
        tol: float,
        max_iterations: int,
    ) -> tuple[np.ndarray, list, list[float]]:
        """One Newton solve: converged ``q``, slider unknowns and residual history (the
        ``B = 1`` case of :func:`newton_many`); ``ValueError`` with its diagnostic.  Without
        sliders the problem is linear: one solve on the free dofs."""
        if not (self.sliders or self.forces):
            return self._linear(f)
        outcome = self.newton(f, start, tol, max_iterations)
        if isinstance(outcome, str):
            raise ValueError(outcome)
        return outcome

    def newton(
        self,
        f: np.ndarray,
        start: tuple[np.ndarray, list[np.ndarray]] | None,
        tol: float,
        max_iterations: int,
        time: float = 0.0,
        scale: float = 1.0,
        velocity: tuple[np.ndarray, np.ndarray, float] | None = None,
    ) -> tuple[np.ndarray, list, list[float]] | str:
        """One Newton solve under the load ``f`` from ``start`` (default: no displacement,
        projected ``xi``), drives read at ``time``, multipliers scaled by ``scale``: the
        converged ``q``, slider unknowns and scaled residual history, or the message of the
        failure.  ``velocity``: ``(v_hat, q_hat, c_v)``, the velocities the force elements
        read (None: at rest).  The condensed back end runs the compiled loop
        (:class:`sliders.solve.newton.CompiledNewton`), the bordered one
        :func:`newton_many` (for one member)."""
        if self.method == "condensed" and self._auto:
            try:
                _ = self.compiled
            except ColumnStorageError:  # too large for the columns: auto takes bordered
                self.method = "bordered"
        if self.method == "condensed":
            if start is None:  # the projection compiled, for every joint at once
                q = np.zeros(self.structure.n_dofs)
                start = (q, self.compiled.pack.initial_unknowns(q))
            q0, unknowns = start
            return self.compiled.solve(f, q0, unknowns, tol, max_iterations, time, scale, velocity)
        if self.forces or self.plane is not None:
            raise ValueError(
                "force elements and planar solves run on the condensed back end (method "
                "'condensed' or 'auto')"
            )
        rubbing = [s.name for s in self.sliders if s.friction is not None]
        if rubbing and velocity is not None:
            raise ValueError(
                f"slider {rubbing[0]!r}: slider friction runs on the condensed back end "
                "(method 'condensed' or 'auto')"
            )
        batches = [s.batch(self.structure) for s in self.sliders]
        return newton_many([self], batches, f[None], [start], tol, max_iterations, time, scale)[0]

    @property
    def compiled(self) -> CompiledNewton:
        """The compiled Newton loop of this problem (condensed back end), built when first
        asked for."""
        if self._compiled is None:
            condensed = self._condensed
            if condensed is None:
                raise ValueError("the compiled Newton step runs on the condensed back end")
            self._compiled = CompiledNewton(
                self.structure,
                self.sliders,
                self.K,
                self.free,
                condensed.factor,
                condensed.phi,
                self,
                self.forces,
                [pinned(s, self.plane) for s in self.sliders] if self.plane else None,
            )
        return self._compiled

    def _linear(self, f: np.ndarray) -> tuple[np.ndarray, list, list[float]]:
        """``K q = f`` on the free dofs (a structure without sliders: the bordered step with
        no borders, from rest), with the residual history ``[1, |K q - f| / |f|]``;
        ``ValueError`` naming the rigid motions the supports leave free, if any."""
        step = self._bordered_step(-f, np.zeros(0), [], cold=True)
        if step is None:
            raise ValueError(self._diagnose([], "the stiffness has no finite solution", cold=True))
        q = step[0]
        scale = max(np.abs(f).max(), 1e-300)
        return q, [], [1.0, float(np.abs((self.K @ q - f)[self.free]).max() / scale)]

    def jacobian(self, q: np.ndarray, unknowns: Sequence[np.ndarray]) -> sp.csc_matrix:
        """The Newton matrix at ``q`` and the sliders' ``unknowns``: rows and columns are the
        free dofs (in order) followed by each slider's unknowns."""
        return self._bordered(joint_parts(self.structure, self.sliders, q, unknowns))

    def _bordered(self, parts: list) -> sp.csc_matrix:
        """The bordered matrix on the free dofs and slider unknowns (a dof held by several
        slots sums them); in a planar solve with the pinned multipliers' equations
        (:func:`sliders.solve.planar.pin`), as the condensed back end solves it."""
        nf = len(self.free)
        rows, cols, vals = [self.K_free.row], [self.K_free.col], [self.K_free.data]
        offset = nf
        for j, (dofs, _, ry, J) in enumerate(parts):
            if self.plane is not None:
                J = pin(J, len(dofs), pinned(self.sliders[j], self.plane))
            index = np.concatenate([self._position[dofs], offset + np.arange(len(ry))])
            keep = index >= 0
            rr, cc = np.meshgrid(index[keep], index[keep], indexing="ij")
            rows.append(rr.ravel())
            cols.append(cc.ravel())
            vals.append(J[np.ix_(keep, keep)].ravel())
            offset += len(ry)
        return sp.csc_matrix(
            (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
            shape=(offset, offset),
        )

    def _bordered_step(
        self, r_q: np.ndarray, r_y: np.ndarray, parts: list, cold: bool = False
    ) -> tuple[np.ndarray, np.ndarray] | None:
        """Newton increments from the factorised bordered system of the joints' ``parts``
        (their Jacobians; a chord step's are an iteration old) under the residuals ``r_q``
        and ``r_y`` (the joints', side by side, at the state); None if it is singular:
        a factor with a zero pivot, a matrix singular to working precision
        (:func:`rcond_estimate` of the equilibrated matrix below :data:`NUMERICALLY_SINGULAR`),
        increments that are not finite, or,
        at a ``cold`` state (multipliers zero), a rigid motion that the supports and sliders
        leave free (:func:`sliders.solve.mechanism.free_motion`)."""
        if cold and free_motion(self.rigid, self._position, parts, self.sliders, self.remedy):
            return None
        S = self._bordered(parts)
        try:
            lu = spla.splu(S)
        except RuntimeError:
            return None
        if rcond_estimate(S, lu) < NUMERICALLY_SINGULAR:
            return None
        z = lu.solve(-np.concatenate([r_q[self.free], r_y]))
        if not np.all(np.isfinite(z)):
            return None
        dq = np.zeros_like(r_q)
        dq[self.free] = z[: len(self.free)]
        return dq, z[len(self.free) :]

    def _steps(
        self,
        members: Sequence[SliderStatics],
        R: np.ndarray,
        parts: list,
        r_y: np.ndarray,
        stacked: list,
        cold: np.ndarray,
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Newton increments ``dq`` (B, n), ``dy`` (B, m) of ``members`` (this one's
        operator; their residuals ``R`` (B, n), ``r_y`` and the joints' slot arrays
        ``parts``, per slider, and ``stacked``, per evaluated batch, :func:`_evaluate`), and
        which are regular.  ``cold``: the members whose multipliers are zero (the bordered
        step checks their free motions; the condensed one's test of its small system is
        exact, :mod:`sliders.solve.condensed`)."""
        B = len(R)
        dq, dy = np.zeros_like(R), np.zeros_like(r_y)
        if self.method == "bordered":
            regular = np.zeros(B, dtype=bool)
            for b, member in enumerate(members):
                step = member._bordered_step(R[b], r_y[b], member_parts(parts, b), bool(cold[b]))
                if step is not None:
                    (dq[b], dy[b]), regular[b] = step, True
            return dq, dy, regular
        assert self._condensed is not None  # __init__ builds it for the condensed back end
        dq_free, dy, regular = self._condensed.step(
            R[:, self.free],
            [self._position[d] for d, _, _ in stacked],
            [J for _, _, J in stacked],
            r_y,
        )
        dq[:, self.free] = dq_free
        return dq, dy, regular

    def _diagnose(self, parts: list, fallback: str, cold: bool) -> str:
        """Why the Newton matrix at ``parts`` is singular: at a ``cold`` state (multipliers
        zero) the rigid motions that the supports and sliders leave free
        (:func:`sliders.solve.mechanism.free_motion`), else the null vector of the bordered
        matrix (:meth:`_singular`); ``fallback`` when neither finds it singular."""
        found = cold and free_motion(self.rigid, self._position, parts, self.sliders, self.remedy)
        return found or self._singular(self._bordered(parts)) or fallback

    def _singular(self, S: sp.spmatrix) -> str | None:
        """The free motion of the bordered matrix ``S`` if it is singular to round-off, None
        when it is regular (:func:`sliders.solve.diagnosis.singular_motion`: no dense copy)."""
        return singular_motion(S, self.rigid, self.structure, self.free, self.sliders, self.remedy)


#: Below this reciprocal condition number a matrix is singular to working precision
#: (``kappa u >= 1``, ``u`` the unit roundoff: Higham, *Accuracy and Stability of Numerical
#: Algorithms*, Sec. 1.6): a matrix singular in exact arithmetic that rounding left with a
#: small pivot reads 1e-18 to 1e-28 here, a regular mesh of 1e4 elements about 1e-13.
NUMERICALLY_SINGULAR = float(np.finfo(float).eps)


def rcond_estimate(S: sp.spmatrix, lu: spla.SuperLU) -> float:
    """The reciprocal 1-norm condition number of ``S`` once its rows and then its columns are
    scaled to a largest entry of 1 (``A = D_r S D_c``; the scaling a stiffness bordered by
    unit constraint rows needs: :func:`sliders.solve.diagnosis.equilibration`), estimated from
    ``S``'s factorisation ``lu``: ``1 / (|A|_1 |A^-1|_1)``, with ``|A^-1|_1`` by Hager's
    estimator (Higham, *Accuracy and Stability of Numerical Algorithms*, Sec. 15.3; scipy's
    ``onenormest`` with one column, which is deterministic), a few solves with ``lu``.

    A configuration that roundoff leaves with a small nonzero pivot reads 1e-18 and below;
    the regular sliding-beams problems read 1e-6 to 1e-7."""
    rows, cols = equilibration(S)
    A = sp.diags(1.0 / rows) @ sp.csr_matrix(S) @ sp.diags(1.0 / cols)
    inverse = spla.LinearOperator(
        S.shape,
        matvec=lambda x: cols * lu.solve(rows * np.ravel(x)),
        rmatvec=lambda x: rows * lu.solve(cols * np.ravel(x), trans="T"),
    )
    with np.errstate(over="ignore", invalid="ignore"):
        size = spla.onenormest(inverse, t=1)
    if not np.isfinite(size) or size == 0:
        return 0.0
    return float(1.0 / (spla.norm(A, 1) * size))


def converged(
    dq: np.ndarray,
    dy: np.ndarray,
    sizes: Sequence[int],
    lengths: Sequence[float],
    reach: np.ndarray,
    force: np.ndarray,
    tol: float,
    resolution: float = 0.0,
) -> np.ndarray:
    """Newton's convergence rule, per member: every increment below ``tol`` relative to its
    scale -- ``q`` to ``reach`` (the largest displacement met), each ``xi`` to its line's
    length, the multipliers to ``force`` (the largest of them and of the load).  ``dq``
    (B, n), ``dy`` (B, m) with the sliders' ``sizes`` and line ``lengths``.  A ``q``
    increment below ``resolution`` (what the positions ``X + q`` can resolve) also passes:
    a solution at rest (``q = 0``, the load taken by the sliders) moves by roundoff only."""
    first, multipliers = _unknown_columns(sizes)
    return (
        (np.abs(dq).max(axis=1, initial=0.0) <= np.maximum(tol * reach, resolution))
        & np.all(np.abs(dy[:, first]) <= tol * np.asarray(lengths, dtype=float), axis=1)
        & (np.abs(dy[:, multipliers]).max(axis=1, initial=0.0) <= tol * force)
    )


def _unknown_columns(sizes: Sequence[int]) -> tuple[np.ndarray, np.ndarray]:
    """Of the joints' unknowns side by side (``sizes`` of them each): the column of each
    joint's abscissa ``xi`` (its first), and the mask of the multipliers (the others)."""
    first = np.cumsum([0] + list(sizes[:-1]))
    multipliers = np.ones(sum(sizes), dtype=bool)
    multipliers[first] = False
    return first, multipliers


def newton_many(
    members: Sequence[SliderStatics],
    batches: Sequence[SliderBatch],
    loads: np.ndarray,
    starts: Sequence[tuple | None],
    tol: float,
    max_iterations: int,
    time: float = 0.0,
    scale: float = 1.0,
) -> list[tuple[np.ndarray, list, list[float]] | str]:
    """Newton on ``B`` independent members at once: the one Newton loop of the package.

    ``members`` share the first one's operator (stiffness, supports, back end); ``batches``
    holds, per slider, the members' sliders (:class:`~sliders.joints.slider.SliderBatch`);
    ``loads`` (B, n); ``starts``: per member ``(q, unknowns)`` or None (no displacement,
    projected ``xi``); ``time`` and ``scale``: where the drives are read and the scaling of
    the multipliers (:meth:`~sliders.joints.slider.SliderBatch.evaluate`).  Each member stops
    when it has converged (:func:`converged`, then one more residual), or fails on its own.
    A member whose scaled residual is below ``tol`` after a regular Newton step takes its
    next step with that step's Jacobian (a chord step: it only confirms convergence; the
    compiled loop, :mod:`sliders.solve.newton_kernel`, keeps that step's small system).
    Returns per member the converged ``q``, slider unknowns and scaled residual history, or
    the message of its failure: the singular-configuration diagnostic naming the free
    motion, or the last residual when Newton does not converge in ``max_iterations``.
    """
    lead = members[0]
    B, n = loads.shape
    sizes = [b.n_unknowns for b in batches]
    lengths = [b.length for b in batches]
    Q, Y = np.zeros((B, n)), np.zeros((B, sum(sizes)))
    warm = np.array([s is not None for s in starts], dtype=bool)
    for b, start in enumerate(starts):
        if start is not None:
            Q[b], Y[b] = start[0], np.concatenate(start[1])
    bounds = list(zip(np.cumsum([0] + sizes[:-1]), np.cumsum(sizes), strict=True))
    full, spans = _joined(batches, bounds)
    cold = np.flatnonzero(~warm)
    if cold.size:
        # one projection per batch of full, its sliders' unknowns side by side
        Y[cold] = np.concatenate(
            [
                (v if cold.size == B else _pick(v, len(span), B, cold))
                .initial_unknowns(np.tile(Q[cold], (len(span), 1)))
                .reshape(len(span), cold.size, -1)
                .transpose(1, 0, 2)
                .reshape(cold.size, -1)
                for v, span in zip(full, spans, strict=True)
            ],
            axis=1,
        )
    Q0, Y0 = Q.copy(), Y.copy()
    # the members whose last step was a regular Newton step, and that step's joint arrays
    kept = np.zeros(B, dtype=bool)
    previous: tuple[np.ndarray, list, list] = (np.zeros(0, dtype=int), [], [])
    load_scale = np.maximum(np.abs(loads).max(axis=1), 1e-300)
    # 4 ulp of the largest coordinate (at least 1: rotations are dimensionless)
    resolution = 4 * np.finfo(float).eps * max(1.0, np.abs(node_positions(lead.structure)).max())
    reach = np.abs(Q).max(axis=1, initial=0.0)
    done, ended = np.zeros(B, dtype=bool), np.zeros(B, dtype=bool)
    # the scaled residual of each member at each evaluation, up to its last (``last``)
    history, last = np.zeros((max_iterations + 1, B)), np.zeros(B, dtype=int)
    outcome: list = [None] * B
    active, view = np.arange(B), full
    multipliers = _unknown_columns(sizes)[1]
    for iteration in range(max_iterations + 1):
        rows = _rows(active, B)
        R = (lead.K @ Q[rows].T).T - loads[rows]
        going = ~done[active]
        r_y = np.zeros((len(active), sum(sizes)))
        # the converged members need their residuals only (the convergence check)
        for on in (
            [slice(None)]
            if going.all() or not going.any()
            else [np.flatnonzero(going), np.flatnonzero(~going)]
        ):
            joints = (
                view
                if isinstance(on, slice)
                else [
                    _pick(v, len(span), len(active), on)
                    for v, span in zip(view, spans, strict=True)
                ]
            )
            evaluated, stacked = _evaluate(
                joints, spans, Q[active[on]], Y[active[on]], time, scale, bool(going[on][0])
            )
            scatter_add(
                R,
                np.arange(len(active))[on][:, None],
                np.concatenate([d for d, _, _ in evaluated], axis=1),
                np.concatenate([r[:, : d.shape[1]] for d, r, _ in evaluated], axis=1),
            )
            r_y[on] = np.concatenate([r[:, d.shape[1] :] for d, r, _ in evaluated], axis=1)
            if going[on][0]:
                parts, whole = evaluated, stacked
        measure = np.maximum(np.abs(R[:, lead.free]).max(axis=1), np.abs(r_y).max(axis=1))
        history[iteration, active] = measure / load_scale[active]
        last[active] = iteration
        ended[active[~going]] = True  # converged, and its residual evaluated once more
        if not going.any():
            active = active[going]
            break
        if not going.all():
            R, r_y = R[going], r_y[going]
        stepping = active[going]
        cold = (
            ~np.any(Y[stepping][:, multipliers], axis=1)
            if lead.method == "bordered"
            else np.zeros(len(stepping), dtype=bool)
        )
        # below tol a step only confirms convergence: after a regular Newton step it is taken
        # with that step's Jacobian (a chord step), the last iteration's joint arrays
        chord = kept[stepping] & (history[iteration, stepping] <= tol)
        dq, dy = np.zeros_like(R), np.zeros_like(r_y)
        regular = np.zeros(len(stepping), dtype=bool)
        groups = [(np.flatnonzero(~chord), stepping, parts, whole)]
        if chord.any():
            groups.append((np.flatnonzero(chord), *previous))
        for which, among, step_parts, step_whole in groups:
            if which.size:
                rows = np.searchsorted(among, stepping[which])
                step_parts, step_whole = _member_rows(
                    step_parts, step_whole, spans, rows, len(among)
                )
                dq[which], dy[which], regular[which] = lead._steps(
                    [members[b] for b in stepping[which]],
                    R[which],
                    step_parts,
                    r_y[which],
                    step_whole,
                    cold[which],
                )
        kept[:] = False
        kept[stepping[regular & ~chord]] = True
        previous = (stepping, parts, whole)
        for i in np.flatnonzero(~regular).tolist():
            b = stepping[i]
            outcome[b] = members[b]._diagnose(
                member_parts(parts, i),
                f"the {lead.method} system has no finite solution",
                not np.any(Y[b, multipliers]),
            )
        active = active[going][regular]
        if not active.size:
            break
        if not regular.all():
            dq, dy = dq[regular], dy[regular]
        rows = _rows(active, B)
        Q[rows] += dq
        Y[rows] += dy
        reach[rows] = np.maximum.reduce(
            [reach[rows], np.abs(dq).max(axis=1), np.abs(Q[rows]).max(axis=1)]
        )
        force = np.maximum(load_scale[rows], np.abs(Y[rows][:, multipliers]).max(axis=1))
        done[rows] = converged(dq, dy, sizes, lengths, reach[rows], force, tol, resolution)
        if len(active) < len(view[0]) // len(spans[0]):
            view = [_pick(v, len(span), B, active) for v, span in zip(full, spans, strict=True)]
    for b in active.tolist():
        first = member_parts(
            [
                v.subset(np.array([b])).evaluate(Q0[b][None], Y0[b][None, i:j], time, scale)
                for v, (i, j) in zip(batches, bounds, strict=True)
            ],
            0,
        )
        outcome[b] = members[b]._diagnose(
            first,
            f"{NOT_CONVERGED_MESSAGE} in {max_iterations} iterations "
            f"(scaled residual {history[last[b], b]:.3g})",
            not np.any(Y0[b, multipliers]),
        )
    finished = np.flatnonzero(ended)
    parts = [Y[finished, i:j] for i, j in bounds]
    for n_b, b, q, *y in zip(last[finished] + 1, finished, Q[finished], *parts, strict=True):
        outcome[b] = (q, y, history[:n_b, b].tolist())
    return outcome


def _rows(active: np.ndarray, B: int) -> np.ndarray | slice:
    """``active`` (increasing members of ``B``) as an index: a slice when it holds them all
    (a view, where a fancy index copies)."""
    return slice(None) if len(active) == B else active


def scatter_add(R: np.ndarray, rows: np.ndarray, columns: np.ndarray, values: np.ndarray) -> None:
    """``R[rows, columns] += values`` with repeated entries summed (``np.add.at``, whose
    per-entry loop costs more than the rest of a Newton pass's bookkeeping): one
    ``np.bincount`` over the flat indices of the (B, n) array ``R``."""
    flat = (rows * R.shape[1] + columns).ravel()
    R += np.bincount(flat, values.ravel(), minlength=R.size).reshape(R.shape)


def _joined(
    batches: Sequence[SliderBatch], bounds: list[tuple[int, int]]
) -> tuple[list[SliderBatch], list[list]]:
    """The batches to evaluate and, per batch, the ``(start, stop)`` of the unknowns of each
    slider it holds: all sliders in one batch when they are alike
    (:meth:`SliderBatch.joined`: one evaluation for every joint of the members), else one
    batch per slider."""
    if len(batches) > 1:
        try:
            return [SliderBatch.joined(batches)], [bounds]
        except ValueError:
            pass
    return list(batches), [[b] for b in bounds]


def _pick(batch: SliderBatch, parts: int, size: int, members: np.ndarray) -> SliderBatch:
    """The given ``members`` of each of the ``parts`` consecutive blocks of ``size`` members
    of ``batch`` (a joined batch's sliders, :func:`_joined`)."""
    return batch.subset((np.arange(parts)[:, None] * size + members).ravel())


def _evaluate(
    view: list[SliderBatch],
    spans: list[list],
    q: np.ndarray,
    y: np.ndarray,
    time: float,
    scale: float,
    jacobian: bool,
) -> tuple[list, list]:
    """``(dofs, r, J)`` of the members at states ``q`` (B, n) and unknowns ``y`` (B, m)
    (:meth:`SliderBatch.evaluate`), each batch of ``view`` evaluated once for the sliders
    it holds (``spans``: their unknowns in ``y``, :func:`_joined`): per slider, and per
    batch (its sliders' members one slider after the other, as the condensed step takes
    them, :meth:`sliders.solve.condensed.CondensedOperator.step`)."""
    stacked = [
        batch.evaluate(
            np.tile(q, (len(span), 1)) if len(span) > 1 else q,
            np.concatenate([y[:, i:j] for i, j in span]),
            time,
            scale,
            jacobian=jacobian,
        )
        for batch, span in zip(view, spans, strict=True)
    ]
    return _per_slider(stacked, spans, len(q)), stacked


def _per_slider(stacked: list, spans: list[list], B: int) -> list:
    """Per slider, the ``(dofs, r, J)`` of its ``B`` members, from the arrays ``stacked``
    per batch of :func:`_evaluate` (a batch's sliders one after the other)."""
    out = []
    for (dofs, r, J), span in zip(stacked, spans, strict=True):
        if len(span) == 1:
            out.append((dofs, r, J))
            continue
        for k in range(len(span)):
            part = slice(k * B, (k + 1) * B)
            out.append((dofs[part], r[part], J.subset(part) if J is not None else None))
    return out


def _member_rows(
    parts: list, stacked: list, spans: list[list], rows: np.ndarray, B: int
) -> tuple[list, list]:
    """The members ``rows`` (of ``B``) of the joint arrays of :func:`_evaluate`, per slider
    (``parts``) and per batch (``stacked``); the arrays themselves when ``rows`` are all
    the members in order."""
    if len(rows) == B and np.array_equal(rows, np.arange(B)):
        return parts, stacked
    picked = []
    for (dofs, r, J), span in zip(stacked, spans, strict=True):
        index = (np.arange(len(span))[:, None] * B + rows).ravel()
        picked.append((dofs[index], r[index], J.subset(index)))
    return _per_slider(picked, spans, len(rows)), picked


def solve_many(
    members: Sequence[SliderStatics],
    loads: ArrayLike,
    tol: float = 1e-8,
    max_iterations: int = 25,
) -> list[SliderSolution | str]:
    """Solve independent problems of one shape together, each from its default start.

    ``members``: statics sharing the first one's operator (built with ``reuse``: the same
    stiffness, dof maps, supports and back end; e.g. a piston moved along its cylinder) with
    alike sliders (:class:`~sliders.joints.slider.SliderBatch`); ``loads``: one load vector each.
    The joints are evaluated for all members at once and, with the ``condensed`` back end,
    the Newton steps are one stacked solve (:func:`newton_many`, the loop and convergence
    rule of :meth:`SliderStatics.solve`).  Returns per member its :class:`SliderSolution`, or
    the message :meth:`SliderStatics.solve` would raise.  Raises ``ValueError`` when the
    members do not share the operator.
    """
    lead = members[0]
    for b, member in enumerate(members):
        if not (
            member.K is lead.K
            and member.method == lead.method
            and np.array_equal(member.free, lead.free)
            and len(member.sliders) == len(lead.sliders)
        ):
            raise ValueError(
                f"member {b} does not share member 0's operator (build it with "
                "reuse=, the same supports, back end and number of sliders)"
            )
    loads = np.array(loads, dtype=float)
    if loads.shape != (len(members), lead.structure.n_dofs) or not np.all(np.isfinite(loads)):
        raise ValueError(
            f"loads must be {len(members)} finite vectors of {lead.structure.n_dofs} rows"
        )
    batches = [
        SliderBatch([m.sliders[i] for m in members], [m.structure for m in members])
        for i in range(len(lead.sliders))
    ]
    outcomes = newton_many(members, batches, loads, [None] * len(members), tol, max_iterations)
    return [_solution(o) for o in outcomes]


def solve_translated(
    statics: SliderStatics,
    shifts: np.ndarray,
    loads: np.ndarray,
    tol: float = 1e-8,
    max_iterations: int = 25,
) -> list[SliderSolution | str]:
    """Solve ``B`` copies of ``statics`` with its beams moved rigidly, together.

    Copy ``b`` is the problem :func:`solve_many` would solve on statics built on the beams
    moved by ``shifts[b]`` (:meth:`fvbeam.beam.Beam.translated`, ``reuse=statics``) under
    ``loads[b]``, without building them: a translation changes neither the stiffness, nor
    the dofs, supports and slider unknowns, only the node positions the joints read
    (:meth:`~sliders.joints.slider.SliderBatch.translated`).  A piston moved along its cylinder is
    one ``statics`` and a shift per position.

    Parameters
    ----------
    statics
        The template: its structure, supports, sliders and back end.
    shifts
        (B, n_beams, 3): per copy, the translation of every beam (rigid bodies stay).
    loads
        (B, n_dofs): per copy, its load vector.
    tol, max_iterations
        As :meth:`SliderStatics.solve`.

    Returns
    -------
    Per copy its :class:`SliderSolution` (displacements from the moved reference) or the
    failure message.
    """
    loads = np.array(loads, dtype=float)
    B = len(shifts)
    if loads.shape != (B, statics.structure.n_dofs) or not np.all(np.isfinite(loads)):
        raise ValueError(f"loads must be {B} finite vectors of {statics.structure.n_dofs} rows")
    batches = [SliderBatch.translated(s, statics.structure, shifts) for s in statics.sliders]
    return [
        _solution(o)
        for o in newton_many([statics] * B, batches, loads, [None] * B, tol, max_iterations)
    ]


def _solution(outcome: tuple | str) -> SliderSolution | str:
    """A :func:`newton_many` outcome as a one-load-step :class:`SliderSolution` (a failure
    message stays)."""
    if isinstance(outcome, str):
        return outcome
    q, unknowns, residuals = outcome
    return SliderSolution(q, unknowns, residuals, [len(residuals) - 1])
