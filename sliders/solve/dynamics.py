"""Implicit dynamics of linear beams, rigid bodies, sliders and drives.

The equations of motion and the scheme are in :mod:`sliders.solve.integrator`.  A step is a static
problem on the scaled operator ``K' = M + (gamma'/beta') C + s K`` with the load
``s (f(t_{n+1}) + M (beta' q_hat - qdd_hat) + C (gamma' q_hat - v_hat))`` and the joint
multipliers scaled by ``s = 1 / beta'``: the one Newton loop of the package
(:func:`sliders.solve.statics.newton_many`) solves it, with either linear-algebra back end.  ``K'``
depends on the step size only, so it is built and factorised once per step size (the
condensed back end then iterates on the slider unknowns alone); a structure without sliders
needs one triangular solve per step.

Prescribed motions: dofs driven by :class:`~sliders.joints.drives.DofDrive` are eliminated like
supports and set to their value at ``t_{n+1}``; a slider's abscissa drive replaces its ``xi``
equation (:class:`~sliders.joints.slider.Slider`).

Failures (Newton not converging, a singular configuration, a slider leaving its line, an
adaptive step falling below its minimum) raise :class:`DynamicsError`, one message with the
time, carrying the last converged state; :meth:`Dynamics.run` closes its recorder first, so
the steps computed so far stay on disk.  A rigid motion that nothing holds is named
(:mod:`sliders.solve.mechanism`): at the static start, where only supports, sliders and
drives hold it (masses hold it only once moving: start from a given state instead), and in a
step, where a massless part's motions are free unless held.

Resuming: after every accepted step :meth:`Dynamics.run` hands its :class:`Cursor` (the state,
the next step size, the fixed steps left) to an optional checkpoint writer;
:meth:`Dynamics.resume` continues from such a cursor with the arithmetic of the uninterrupted
run (``docs/dynamics.md``, Checkpoints and resume).
"""

from __future__ import annotations

import itertools
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Protocol, runtime_checkable

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from fvbeam.geometry import vector3
from fvbeam.mass import weight
from fvbeam.mechanism import rigid_modes, unresisted
from fvbeam.structure import Structure
from fvbeam.support import DOF_NAMES, Support, complement
from sliders.forces.elements import ForceElement
from sliders.joints.drives import DofDrive, Motion
from sliders.joints.packed import JointPack
from sliders.joints.slider import Slider
from sliders.solve.dynamics_kernel import Schedule, SchemeState, Stepper, Trajectory, advance
from sliders.solve.factor import Factor
from sliders.solve.integrator import GeneralizedAlpha, Prediction, State
from sliders.solve.jumps import VelocityJump, VelocityJumpWarning, velocity_jumps
from sliders.solve.mechanism import MASSLESS_REMEDY, free_motion
from sliders.solve.newton import CompiledNewton
from sliders.solve.newton_kernel import CONVERGED, NOT_CONVERGED_MESSAGE, NewtonProblem
from sliders.solve.planar import check, check_load, out_of_plane
from sliders.solve.statics import SliderStatics

if TYPE_CHECKING:
    from tqdm import tqdm

#: What holds a motion left free at the static start of a time integration.
START_REMEDY = (
    "a time integration starts from the static equilibrium, which needs it held: a support, "
    "a slider or a drive; or start from a given state, Dynamics.state or State.load"
)


@runtime_checkable
class Tabulable(Protocol):
    """A load that gives its vectors at many times at once, one row per time
    (:class:`sliders.forces.moving_load.MovingLoad`)."""

    def at(self, times: np.ndarray) -> np.ndarray: ...


class Recorder(Protocol):
    """What :meth:`Dynamics.run` tells an observer of the integration
    (:class:`sliders.app.history.Recorder` is one)."""

    def start(self, dynamics: "Dynamics", state: State) -> None: ...

    def record(self, dynamics: "Dynamics", new: State, old: State) -> None: ...

    def close(self) -> None: ...


@dataclass(frozen=True)
class Cursor:
    """Where an integration stands after an accepted step: its ``state``, the size ``h`` of
    the next step, and with fixed steps the number of ``steps`` left (None: adaptive steps,
    which go on to ``t_end``).  With the recorder's rows, all a checkpoint needs to continue
    (:meth:`Dynamics.resume`): the scheme is one-step (its ``a`` is in the state), and the
    adaptive control keeps nothing but the next step size."""

    state: State
    h: float
    steps: int | None = None


#: What :meth:`Dynamics.run` calls after every accepted and recorded step, with its cursor
#: (:class:`sliders.app.checkpoint.Checkpoints` writes one every so often).
Checkpoint = Callable[[Cursor], None]

#: The most state entries (4 n + m per step) a compiled chunk of steps holds before its steps
#: are recorded, and the most steps in a chunk (:meth:`Dynamics._chunks`).
CHUNK_ENTRIES = 4_000_000
MAX_CHUNK = 500
#: The most times a fixed step whose Newton fails is halved (:meth:`Dynamics.split_step`).
MAX_HALVINGS = 4

#: A load: a fixed global vector, or a function of time returning one.
Load = np.ndarray | Callable[[float], np.ndarray]


class DynamicsError(RuntimeError):
    """A step that could not be completed; ``state`` is the last converged one."""

    def __init__(self, message: str, state: State) -> None:
        super().__init__(message)
        self.state = state


class NotConverged(DynamicsError):
    """A step whose Newton iterations did not converge (nothing else failed): a smaller step
    may (:meth:`Dynamics.split_step`)."""


@dataclass(frozen=True)
class Adaptive:
    """Error-controlled step: a step is accepted when its local error estimate
    (:meth:`GeneralizedAlpha.local_error`) is below ``atol + rtol max|q|`` on every dof;
    otherwise, or when Newton fails, it is halved, down to ``h_min``.  After an accepted step
    whose error is below 1/8 of the bound (the error scales as ``h^3``) the step doubles, up
    to ``h_max``.  Steps are the initial one times powers of two, so the factorisations of
    the few sizes in use are kept."""

    rtol: float = 1e-4
    atol: float = 1e-12
    h_min: float = 0.0
    h_max: float = np.inf

    def __post_init__(self) -> None:
        if not (self.rtol > 0 and self.atol >= 0 and self.h_min >= 0 and self.h_max > self.h_min):
            raise ValueError(
                f"adaptive step: need rtol > 0, atol >= 0, 0 <= h_min < h_max, got {self}"
            )


class Dynamics:
    """Time integration of ``structure`` held by ``supports``, ``sliders`` and ``drives``.

    Parameters
    ----------
    load
        External load: a global vector or a function of time (default none).
    mass
        ``lumped`` or ``consistent`` (:meth:`fvbeam.structure.Structure.mass`).
    damping
        Stiffness-proportional damping ``C = damping K`` (a viscoelastic section: the
        damping ratio of a mode of frequency ``omega`` is ``damping omega / 2``), or a
        matrix ``C``.
    gravity
        Acceleration of gravity, a 3-vector: the load ``M g`` on every translation.
    rho_inf
        Spectral radius at infinity of the scheme (:class:`GeneralizedAlpha`).
    plane
        ``xy``, ``yz`` or ``zx``: a planar problem, integrated on its in-plane dofs
        (:mod:`sliders.solve.planar`; ``ValueError`` naming what is not planar, and a load, a
        drive or a start out of the plane).
    method
        ``bordered`` or ``condensed`` (:class:`sliders.solve.statics.SliderStatics`).
    tol, max_iterations
        Newton's convergence rule (:func:`sliders.solve.statics.converged`).
    """

    def __init__(
        self,
        structure: Structure,
        supports: Sequence[Support] = (),
        sliders: Sequence[Slider] = (),
        load: Load | None = None,
        *,
        forces: Sequence[ForceElement] = (),
        plane: str | None = None,
        mass: str = "lumped",
        damping: float | sp.spmatrix = 0.0,
        gravity: Sequence[float] | None = None,
        drives: Sequence[DofDrive] = (),
        rho_inf: float = 0.8,
        method: str = "auto",
        tol: float = 1e-8,
        max_iterations: int = 25,
    ) -> None:
        self.structure, self.sliders, self.drives = structure, list(sliders), list(drives)
        self.forces = list(forces)
        #: Whether a step is a Newton loop (sliders or force elements) rather than one solve.
        self.nonlinear = bool(self.sliders or self.forces)
        self.scheme = GeneralizedAlpha(rho_inf)
        self.method, self.tol, self.max_iterations = method, tol, max_iterations
        n = structure.n_dofs
        self.K = structure.tangent(np.zeros(n)).tocsr()
        self.M = structure.mass(mass).tocsr()
        self.C = self._damping(damping)
        self._load = self._check_load(load)
        self.f_gravity = np.zeros(n)
        if gravity is not None:
            g = vector3(gravity, "gravity")
            self.f_gravity = weight(self.M, g)
        self.supports = list(supports) + [Support.at(d.node, d.dof) for d in self.drives]
        fixed = structure.support_dofs(supports)
        self.plane = plane
        if plane is not None:  # a planar problem: the out-of-plane dofs are held
            check(structure, self.sliders, plane, [self.K, self.M, self.C])
            check_load(structure, self.f_gravity, plane, "gravity")
            fixed = np.union1d(fixed, out_of_plane(structure, plane))
        self.driven = np.array(
            [structure.node_dofs(d.node)[DOF_NAMES.index(d.dof)] for d in self.drives], dtype=int
        )
        clash = np.intersect1d(fixed, self.driven)
        if clash.size or len(np.unique(self.driven)) < len(self.driven):
            name = structure.dof_name(clash[0] if clash.size else self.driven[0])
            raise ValueError(
                f"{name} is driven twice, or driven and supported (or out of the plane)"
            )
        self.free = complement(n, np.concatenate([fixed, self.driven]))
        self._operators: dict = {}
        #: The compiled problems without sliders, per step size.
        self._linear: dict[float, NewtonProblem] = {}
        self._pack: JointPack | None = None  # the joints, packed (joint_residuals)
        self._last_load: tuple[float, np.ndarray] | None = None

    def _damping(self, damping: float | sp.spmatrix) -> sp.csr_matrix:
        if sp.issparse(damping) or isinstance(damping, np.ndarray):
            C = sp.csr_matrix(damping)
            if C.shape != self.K.shape or not np.all(np.isfinite(C.data)):
                raise ValueError(
                    f"damping matrix must be finite and {self.K.shape}, got shape {C.shape}"
                )
            return C
        if not (np.isfinite(damping) and damping >= 0):
            raise ValueError(f"damping must be a finite coefficient >= 0, got {damping!r}")
        if damping == 0:
            return sp.csr_matrix(self.K.shape)  # no damping: an empty matrix, free products
        return (float(damping) * self.K).tocsr()

    def _check_load(self, load: Load | None) -> Callable[[float], np.ndarray]:
        n = self.structure.n_dofs
        self._constant = not callable(load)
        if load is None:
            return lambda t: np.zeros(n)
        if callable(load):
            return load
        f = np.asarray(load, dtype=float)
        if f.shape != (n,) or not np.all(np.isfinite(f)):
            raise ValueError(f"load must be a finite vector of {n} rows or a function of time")
        return lambda t: f

    def load(self, t: float) -> np.ndarray:
        """External load at ``t``, gravity included (read-only; the last one is kept, as a
        step and its recorder ask for the same ``t``, and a load that does not depend on time
        is built once); ``ValueError`` if it is not finite."""
        if self._last_load is not None and (self._constant or self._last_load[0] == t):
            return self._last_load[1]
        f = np.asarray(self._load(t), dtype=float) + self.f_gravity
        if f.shape != (self.structure.n_dofs,) or not np.all(np.isfinite(f)):
            raise ValueError(
                f"the load at t = {t:.6g} is not a finite vector of {self.structure.n_dofs} rows"
            )
        if self.plane is not None:
            check_load(self.structure, f, self.plane, f"the load at t = {t:.6g}")
        f.setflags(write=False)
        self._last_load = (t, f)
        return f

    def prescribe(self, q: np.ndarray, t: float) -> np.ndarray:
        """``q`` with the driven dofs set to their values at ``t``."""
        q = q.copy()
        for dof, drive in zip(self.driven, self.drives, strict=True):
            q[dof] = drive.motion(t)[0]
        return q

    def static_state(self, t: float = 0.0) -> State:
        """Static equilibrium under the load at ``t``, at rest: the usual start.
        :class:`DynamicsError` naming the rigid motions that the supports, sliders and drives
        leave free, if any (the masses do not hold them at rest)."""
        zero = np.zeros(self.structure.n_dofs)
        start = self.prescribe(zero, t)
        unknowns = [s.initial_unknowns(self.structure, start) for s in self.sliders]
        at_rest = State(t, zero, zero, zero, zero, [])
        if self.sliders and not self.forces:  # force elements may hold what sliders do not
            solver = self._solver("static")
            assert isinstance(solver, SliderStatics)  # the solver of a model with sliders
            free = solver.free_motion(start, unknowns, START_REMEDY)
            if free:
                raise DynamicsError(f"t = {t:.6g}: {free}", at_rest)
        q, unknowns, iterations = self._solve(
            "static", self.load(t), start, unknowns, t, 1.0, at_rest, None
        )
        return State(t, q, zero.copy(), zero.copy(), zero.copy(), unknowns, 0.0, iterations)

    def state(
        self,
        q: np.ndarray,
        v: np.ndarray | None = None,
        t: float = 0.0,
        unknowns: Sequence[np.ndarray] | None = None,
        qdd: np.ndarray | None = None,
    ) -> State:
        """A start from displacements ``q`` and velocities ``v`` (default 0) rather than from
        the static equilibrium (a touchdown, a release).

        Without sliders and force elements, the accelerations solve ``M qdd = f - K q - C v``
        on the free dofs (``ValueError`` if the mass is singular there).  With them, the
        joints' ``unknowns`` default to the projected abscissae and zero multipliers (the
        first step solves the multipliers: they are no state of the scheme), and the
        accelerations ``qdd`` to zero: a start in balance (a touchdown with the weight carried
        by the lift); give ``qdd`` otherwise."""
        n = self.structure.n_dofs
        q = np.asarray(q, dtype=float)
        v = np.zeros(n) if v is None else np.asarray(v, dtype=float)
        if q.shape != (n,) or v.shape != (n,) or not np.all(np.isfinite(q) & np.isfinite(v)):
            raise ValueError(f"q and v must be finite vectors of {n} rows")
        if self.nonlinear:
            if unknowns is None:
                unknowns = [s.initial_unknowns(self.structure, q) for s in self.sliders]
            unknowns = [np.array(y, dtype=float) for y in unknowns]
            sizes = [len(y) for y in unknowns]
            if sizes != [s.n_unknowns for s in self.sliders]:
                raise ValueError(
                    f"unknowns of sizes {sizes} given, the sliders have "
                    f"{[s.n_unknowns for s in self.sliders]}"
                )
            qdd = np.zeros(n) if qdd is None else np.asarray(qdd, dtype=float)
            if qdd.shape != (n,) or not np.all(np.isfinite(qdd)):
                raise ValueError(f"qdd must be a finite vector of {n} rows")
            return State(t, q.copy(), v.copy(), qdd.copy(), qdd.copy(), unknowns)
        f = self.load(t) - self.K @ q - self.C @ v
        M = self.M[self.free][:, self.free].tocsc()
        try:
            qdd_free = spla.splu(M).solve(f[self.free])
        except RuntimeError as exc:
            raise ValueError(
                "the mass matrix is singular on the free dofs (a dof with no "
                "mass: give the sections rotary inertia)"
            ) from exc
        qdd = np.zeros(n)
        qdd[self.free] = qdd_free
        return State(t, q.copy(), v.copy(), qdd.copy(), qdd, [])

    def operator(self, h: float) -> sp.csr_matrix:
        """The scaled Newton operator ``M + (gamma'/beta') C + K / beta'`` of a step ``h``."""
        beta_rate, gamma_rate = self.scheme.rates(h)
        return (self.M + (gamma_rate / beta_rate) * self.C + self.K / beta_rate).tocsr()

    def _solver(self, key: float | str) -> SliderStatics | tuple[Factor, sp.csr_matrix]:
        """The cached solver of the operator ``key`` (a step size, or ``static``): the
        statics of the sliders on it, or without sliders its factor on the free dofs and the
        operator itself."""
        if key not in self._operators:
            operator = self.K if isinstance(key, str) else self.operator(key)
            if self.nonlinear:
                self._operators[key] = SliderStatics(
                    self.structure,
                    self.supports,
                    self.sliders,
                    method=self.method,
                    operator=operator,
                    forces=self.forces,
                    plane=self.plane,
                )
            else:
                A = operator[self.free][:, self.free].tocsc()
                modes = rigid_modes(self.structure, self.free)
                modes = modes if isinstance(key, str) else unresisted(modes, A)
                position = np.full(self.structure.n_dofs, -1)
                position[self.free] = np.arange(len(self.free))
                remedy = START_REMEDY if isinstance(key, str) else MASSLESS_REMEDY
                free = free_motion(modes, position, [], [], remedy)
                if free:
                    raise ValueError(free)
                self._operators[key] = (Factor(A), operator.tocsr())
        return self._operators[key]

    def _solve(
        self,
        key: float | str,
        f: np.ndarray,
        start: np.ndarray,
        unknowns: list[np.ndarray],
        t: float,
        scale: float,
        last: State,
        velocity: tuple[np.ndarray, np.ndarray, float] | None,
    ) -> tuple[np.ndarray, list, int]:
        """Solve the (scaled) step problem: displacements, physical joint unknowns and
        Newton iterations; ``velocity``: ``(v_hat, q_hat, gamma')`` of the step (None: at
        rest); :class:`DynamicsError` on failure."""
        try:
            solver = self._solver(key)
            if isinstance(solver, tuple):
                factor, operator = solver
                q = start.copy()
                q[self.free] += factor.solve((f - operator @ start)[self.free])
                return q, [], 1
            outcome = solver.newton(
                f,
                (start, unknowns),
                self.tol,
                self.max_iterations,
                time=t,
                scale=scale,
                velocity=velocity,
            )
        except ValueError as exc:
            raise DynamicsError(f"t = {t:.6g}: {exc}", last) from exc
        if isinstance(outcome, str):
            failure = NotConverged if outcome.startswith(NOT_CONVERGED_MESSAGE) else DynamicsError
            raise failure(f"t = {t:.6g}: {outcome}", last)
        q, scaled, residuals = outcome
        return q, [_scale_multipliers(y, 1.0 / scale) for y in scaled], len(residuals) - 1

    def step(self, state: State, h: float) -> State:
        """One step of size ``h`` from ``state``; :class:`DynamicsError` on failure."""
        p: Prediction = self.scheme.predict(state, h)
        t, scale = state.t + h, 1.0 / p.beta_rate
        try:
            f = self.load(t)
        except ValueError as exc:
            raise DynamicsError(str(exc), state) from exc
        f_eff = (
            f
            + self.M @ (p.beta_rate * p.q_hat - p.qdd_hat)
            + self.C @ (p.gamma_rate * p.q_hat - p.v_hat)
        )
        start = self.prescribe(p.q_hat + self.scheme.beta * h * h * state.a, t)
        unknowns = [_scale_multipliers(y, scale) for y in state.unknowns]
        velocity = (p.v_hat, p.q_hat, p.gamma_rate)
        q, unknowns, iterations = self._solve(
            h, scale * f_eff, start, unknowns, t, scale, state, velocity
        )
        return p.complete(t, q, unknowns, self.scheme.beta, iterations)

    def split_step(self, state: State, h: float) -> State:
        """A fixed step of size ``h`` from ``state``; where its Newton fails, the step is
        taken in halves instead, each halved again where it fails, down to ``h /
        2^MAX_HALVINGS``, and the state at ``t + h`` returned (a fixed-step run keeps its
        grid; the state's ``h`` is its last substep's).  A regularised friction crossing its
        band of ``v_eps`` within one step needs it: from the saturated side the tangent does
        not see the band, and Newton cycles between the two signs of the sliding speed.
        :class:`DynamicsError` naming the step's failure and the smallest substep's, with
        ``state`` (the last state of the fixed grid), when even that fails; any other failure
        (a singular configuration, a slider off its line) at once."""
        try:
            return self.step(state, h)
        except NotConverged as exc:
            first = exc
        try:
            return self._in_halves(state, h, MAX_HALVINGS)
        except DynamicsError as exc:
            raise DynamicsError(
                f"{first}; and in steps down to h / {2**MAX_HALVINGS} ({exc})", state
            ) from exc

    def _in_halves(self, state: State, h: float, halvings: int) -> State:
        """Two steps of ``h / 2`` from ``state``, each in halves again where it fails
        (``halvings`` times at most)."""
        for _ in range(2):
            try:
                state = self.step(state, h / 2)
            except NotConverged:
                if halvings == 1:
                    raise
                state = self._in_halves(state, h / 2, halvings - 1)
        return state

    def constraint_forces(self, state: State) -> np.ndarray:
        """What the supports, drives and joints exert on the structure:
        ``M qdd + C v + K q - f`` (zero on the dofs nothing holds, to the solver's
        tolerance)."""
        return self.M @ state.qdd + self.C @ state.v + self.K @ state.q - self.load(state.t)

    def velocity_jumps(self, state: State) -> list[VelocityJump]:
        """The drives that set a mass moving at once from ``state`` at rest
        (:func:`sliders.solve.jumps.velocity_jumps`)."""
        return velocity_jumps(self.structure, self.M, self.drives, self.sliders, state)

    def joint_residuals(self, state: State) -> np.ndarray:
        """Largest position and orientation constraint violation of each slider at
        ``state`` (``|x_b - x(xi)|`` and ``|g_j|``)."""
        if state.violations is not None:
            return state.violations
        if self._pack is None:
            self._pack = JointPack(self.sliders, self.structure)
        return self._pack.violations(np.asarray(state.q, dtype=float), state.unknowns, state.t)

    def run(
        self,
        state: State,
        t_end: float,
        h: float,
        adaptive: Adaptive | None = None,
        recorder: "Recorder | None" = None,
        progress: bool = True,
        checkpoint: "Checkpoint | None" = None,
    ) -> State:
        """Integrate from ``state`` to ``t_end``.

        Fixed step (``adaptive`` None): ``h`` is shortened so that a whole number ``n`` of
        steps ends at ``t_end``, and exactly ``n`` steps are taken.  Adaptive: ``h`` is the
        first step (:class:`Adaptive`).  Each accepted state goes to ``recorder``, then its
        :class:`Cursor` to ``checkpoint``; with ``progress``, a bar shows simulated time on
        a terminal.  The recorder is closed on every exit (its files then hold the steps
        computed), and a failure raises :class:`DynamicsError` with the last converged
        state.  A drive that sets a mass moving at once from ``state`` at rest is warned of
        (:class:`~sliders.solve.jumps.VelocityJumpWarning`, :meth:`velocity_jumps`).
        """
        if not (np.isfinite(t_end) and t_end > state.t and np.isfinite(h) and h > 0):
            raise ValueError(
                f"need t_end > t = {state.t} and a step h > 0, got t_end = {t_end}, h = {h}"
            )
        if self.plane is not None:
            for what, values in (("displacement", state.q), ("velocity", state.v)):
                check_load(self.structure, values, self.plane, f"the start's {what}")
        jumps = self.velocity_jumps(state)
        if jumps:
            warnings.warn(
                "; ".join(map(str, jumps)) + ": start from rest instead, e.g. with a cosine "
                "Ramp (sliders.joints.drives.Ramp)",
                VelocityJumpWarning,
                stacklevel=2,
            )
        steps = None
        if adaptive is None:
            steps = int(np.ceil((t_end - state.t) / h * (1 - 1e-12)))
            h = (t_end - state.t) / steps
        if recorder is not None:
            recorder.start(self, state)
        return self.resume(Cursor(state, h, steps), t_end, adaptive, recorder, progress, checkpoint)

    def resume(
        self,
        cursor: "Cursor",
        t_end: float,
        adaptive: Adaptive | None = None,
        recorder: "Recorder | None" = None,
        progress: bool = True,
        checkpoint: "Checkpoint | None" = None,
    ) -> State:
        """Continue an integration to ``t_end`` from ``cursor``, as :meth:`run` goes on
        after the step that gave it: the same steps, the same arithmetic, bit for bit.
        ``recorder`` already holds the steps up to ``cursor.state``
        (:meth:`sliders.app.history.Recorder.resume`); ``adaptive`` is the run's (None
        exactly when ``cursor.steps`` counts fixed steps).  A cursor at the end returns its
        state."""
        if (cursor.steps is None) == (adaptive is None):
            raise ValueError(
                "a cursor of fixed steps resumes without adaptive, one of adaptive steps with it"
            )
        if not (np.isfinite(cursor.h) and cursor.h > 0 and (cursor.steps or 0) >= 0):
            raise ValueError(
                f"a cursor needs a step h > 0 and steps >= 0, got h = {cursor.h}, "
                f"steps = {cursor.steps}"
            )
        state, h, steps = cursor.state, cursor.h, cursor.steps
        from tqdm.auto import tqdm  # asyncio with it: not imported before a run

        try:
            with tqdm(
                total=max(t_end - state.t, 0.0),
                disable=None if progress else True,
                unit="s",
                desc="time",
                bar_format="{l_bar}{bar}| {n:.4g}/{total:.4g} [{elapsed}]",
            ) as bar:
                if steps is not None and self._compiled(h):
                    return self._chunks(state, h, steps, recorder, bar, checkpoint)
                while (
                    steps > 0 if steps is not None else t_end - state.t > 1e-12 * max(abs(t_end), h)
                ):
                    new, h = self._advance(
                        state, h if adaptive is None else min(h, t_end - state.t), adaptive
                    )
                    if steps is not None:
                        steps -= 1
                    if recorder is not None:
                        recorder.record(self, new, state)
                    bar.update(new.t - state.t)
                    state = new
                    if checkpoint is not None:
                        checkpoint(Cursor(state, h, steps))
        finally:
            if recorder is not None:
                recorder.close()
        return state

    def _compiled(self, h: float) -> bool:
        """Whether steps of size ``h`` run compiled (:mod:`sliders.solve.dynamics_kernel`):
        without sliders, or with the condensed back end."""
        try:
            solver = self._solver(h)
        except ValueError:
            return False  # the Python step names what is wrong
        return isinstance(solver, tuple) or solver.method == "condensed"

    def _chunks(
        self,
        state: State,
        h: float,
        steps: int,
        recorder: "Recorder | None",
        bar: tqdm,
        checkpoint: "Checkpoint | None",
    ) -> State:
        """``steps`` fixed steps of size ``h`` from ``state``, compiled a chunk at a time
        (:func:`sliders.solve.dynamics_kernel.advance`, the arithmetic of :meth:`step`); each
        step's state is then recorded, shown and handed to ``checkpoint`` as :meth:`resume`
        does.  A step that fails is taken again by :meth:`step`, which raises its
        :class:`DynamicsError`."""
        solver = self._solver(h)
        beta_rate, gamma_rate = self.scheme.rates(h)
        scheme = (
            self.scheme.alpha_m,
            self.scheme.alpha_f,
            self.scheme.beta,
            self.scheme.gamma,
            h,
            beta_rate,
            gamma_rate,
        )
        if isinstance(solver, tuple):
            if h not in self._linear:
                factor, operator = solver
                self._linear[h] = CompiledNewton(
                    self.structure, [], operator, self.free, factor, np.zeros((len(self.free), 0))
                ).problem
            problem, nonlinear = self._linear[h], False
        else:
            problem, nonlinear = solver.compiled.problem, True
        sizes = [s.n_unknowns for s in self.sliders]
        first = np.cumsum([0] + sizes[:-1]).astype(np.int64)[: len(sizes)]
        n, m = self.structure.n_dofs, sum(sizes)
        bounds = list(itertools.pairwise(np.cumsum([0] + sizes).tolist()))
        chunk = int(np.clip(CHUNK_ENTRIES // (4 * n + m + 1), 1, MAX_CHUNK))
        stepper = Stepper(
            scheme,
            _rows(self.M),
            _rows(self.C),
            problem,
            nonlinear,
            self.driven.astype(np.int64),
            first,
            float(self.tol),
            int(self.max_iterations),
        )
        q, v, a, qdd = (np.array(x, dtype=float) for x in (state.q, state.v, state.a, state.qdd))
        y = _joined(state.unknowns)
        while steps > 0:
            size = min(steps, chunk)
            times = np.cumsum(np.concatenate([[state.t], np.full(size, h)]))[1:]
            loads = self._loads(times)
            finite = np.isfinite(loads).all(axis=1)
            if not finite.all():  # up to the first bad load; its step raises below
                size = int(np.argmin(finite)) if len(loads) > 1 else 0
                times, loads = times[:size], loads[:size]
            driven = _table([d.motion for d in self.drives], times)
            drives = np.zeros((len(times), len(self.sliders)))
            for j, slider in enumerate(self.sliders):
                if slider.drive is not None:
                    drives[:, j] = _table([slider.drive], times)[:, 0]
            Q, V, A, QDD = (np.empty((size, n)) for _ in range(4))
            Y, iterations = np.empty((size, m)), np.zeros(size, dtype=np.int64)
            violations = np.zeros((size, len(self.sliders)))
            status, done, _ = advance(
                stepper,
                Schedule(
                    times,
                    loads,
                    driven.reshape(size, len(self.drives)),
                    drives.reshape(size, len(self.sliders)),
                ),
                SchemeState(q, v, a, qdd, y),
                Trajectory(SchemeState(Q, V, A, QDD, Y), iterations, violations),
            )
            # each step's state reads rows of this chunk's own arrays (new ones per chunk); the
            # progress bar moves once per chunk
            shown = state.t
            for i in range(done):
                new = State(
                    float(times[i]),
                    Q[i],
                    V[i],
                    A[i],
                    QDD[i],
                    [Y[i, a:b] for a, b in bounds],
                    h,
                    int(iterations[i]),
                    violations[i],
                )
                state = self._accepted(new, state, h, steps - 1 - i, recorder, None, checkpoint)
            bar.update(state.t - shown)
            steps -= done
            if status != CONVERGED:
                new = self.split_step(state, h)  # in halves, or raises its DynamicsError
                state = self._accepted(new, state, h, steps - 1, recorder, bar, checkpoint)
                steps -= 1
                q, v, a, qdd = (np.array(x) for x in (new.q, new.v, new.a, new.qdd))
                y = _joined(new.unknowns)
        return state

    def _accepted(
        self,
        new: State,
        old: State,
        h: float,
        steps: int,
        recorder: "Recorder | None",
        bar: tqdm | None,
        checkpoint: "Checkpoint | None",
    ) -> State:
        """An accepted step recorded, shown (unless ``bar`` is None) and checkpointed
        (``steps``: those left)."""
        if recorder is not None:
            recorder.record(self, new, old)
        if bar is not None:
            bar.update(new.t - old.t)
        if checkpoint is not None:
            checkpoint(Cursor(new, h, steps))
        return new

    def _loads(self, times: np.ndarray) -> np.ndarray:
        """The external load at each of ``times`` (gravity included), one row each; one row
        for all when it does not depend on time."""
        if self._constant:
            return self.load(float(times[0]))[None]
        if isinstance(self._load, Tabulable):
            table = self._load.at(times) + self.f_gravity
            if self.plane is not None:
                for t, f in zip(times, table, strict=True):
                    check_load(self.structure, f, self.plane, f"the load at t = {t:.6g}")
            return table
        return np.array([self.load(float(t)) for t in times])

    def _advance(self, state: State, h: float, adaptive: Adaptive | None) -> tuple[State, float]:
        """One accepted step and the next step size."""
        if adaptive is None:
            return self.split_step(state, h), h
        while True:
            try:
                new = self.step(state, h)
            except DynamicsError as exc:
                h = self._halve(h, adaptive, state, str(exc))
                continue
            bound = adaptive.atol + adaptive.rtol * max(np.abs(new.q).max(), 0.0)
            error = np.abs(self.scheme.local_error(state, new)[self.free]).max() / bound
            if error <= 1.0:
                return new, (min(2 * h, adaptive.h_max) if error < 0.125 else h)
            h = self._halve(h, adaptive, state, f"local error {error:.3g} times the bound")

    @staticmethod
    def _halve(h: float, adaptive: Adaptive, state: State, reason: str) -> float:
        if h / 2 < adaptive.h_min:
            raise DynamicsError(
                f"t = {state.t:.6g}: the step fell below its minimum "
                f"{adaptive.h_min:.3g} ({reason})",
                state,
            )
        return h / 2


def _table(motions: Sequence[Motion], times: np.ndarray) -> np.ndarray:
    """The values of ``motions`` at ``times``: (len(times), len(motions))."""
    out = np.zeros((len(times), len(motions)))
    for j, motion in enumerate(motions):
        out[:, j] = [motion(float(t))[0] for t in times]
    return out


def _joined(unknowns: Sequence[np.ndarray]) -> np.ndarray:
    """The joints' unknowns side by side."""
    return np.concatenate([np.asarray(u, dtype=float) for u in unknowns] + [np.zeros(0)])


def _rows(A: sp.spmatrix) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``A`` in compressed rows, as the compiled kernels take it: row pointers, column
    indices (int64) and values."""
    A = sp.csr_matrix(A)
    return A.indptr.astype(np.int64), A.indices.astype(np.int64), A.data.astype(float)


def _scale_multipliers(y: np.ndarray, factor: float) -> np.ndarray:
    """A joint's unknowns with the multipliers (all but ``xi``) times ``factor``."""
    out = np.array(y, dtype=float)
    out[1:] *= factor
    return out
