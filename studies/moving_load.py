"""A constant force crossing a simply supported beam: the discrete model and its references.

The beam lies along x, ``L = 1``, bent in the x-y plane by a force ``F = 1`` along y moving
at ``c`` from ``x = 0`` (``t = 0``, beam at rest) to ``x = L`` (``t = L / c``).  Section:
``EJ = m = 1``, ``GA = 1e5`` (``EJ / (GA L^2) = 1e-5``), no rotary inertia.  At the
paper's Sec. 6 slenderness (``1e-3``) the continuum's response carries shear-wave fronts
(free-vibration terms decaying only like ``j^-2``, weighted by ``c / sqrt(GA / m)``) that
the meshes resolve at a lower rate, and the max-norm orders become erratic on fine meshes
(``docs/dynamics.md``, "Moving load"); the slender section keeps the measured rates those
of the formulations.  The speed is half the critical one,
``c = 0.5 pi sqrt(EJ / m) / L`` (Fryba's ``alpha = 0.5``).  Supports: a pin (``ux uy uz``)
and ``rx`` at ``x = 0``, ``uy uz`` at ``x = L``; the out-of-plane dofs carry no load.

:class:`Problem` holds these numbers; the work-precision study
(:mod:`studies.work_precision`) runs other problems through the same functions, and past the
crossing into the free vibration (:func:`simulate`'s ``t_end``).

Two references (``docs/dynamics.md``, "Moving load"):

* :func:`fvbeam.closed_forms.moving_load_simply_supported`, the continuum's modal series;
* :func:`semi_discrete`, the exact solution of the model's own ODE ``M qdd + K q = f(t)``
  (no time-stepping error): the massless rotations condensed out, the translations in the
  modes of ``(K*, M)``, each mode integrated in closed form over the intervals on which the
  load vector is a polynomial in ``t``.  The load vector of a point load is a polynomial in
  its abscissa between the formulation's break points (element ends; fv also the
  evaluation points, across which it jumps), so each piece is read off exactly by
  interpolating ``Beam.point_load`` at ``degree + 1`` interior times.  After the crossing
  the force sits on the end support and the free dofs are unloaded.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np
import scipy.linalg as sla

from fvbeam import Beam, RigidBody, Section, Structure, Support, formulation, straight
from fvbeam.closed_forms import moving_load_simply_supported
from sliders.forces.moving_load import MovingLoad
from sliders.joints.drives import Linear, Ramp
from sliders.joints.slider import Slider
from sliders.lines.chain import BeamChain
from sliders.solve.dynamics import Dynamics
from sliders.solve.integrator import State


@dataclass(frozen=True)
class Problem:
    """A simply supported beam of length ``L`` (bending ``EJ``, shear ``GA``, mass ``m`` per
    length, no rotary inertia) crossed by a force ``F`` at ``alpha`` times the critical speed
    ``pi sqrt(EJ / m) / L`` of the Euler-Bernoulli beam (Fryba's ``alpha``)."""

    L: float = 1.0
    EJ: float = 1.0
    GA: float = 1e5
    m: float = 1.0
    F: float = 1.0
    alpha: float = 0.5

    @property
    def speed(self) -> float:
        return self.alpha * np.pi * np.sqrt(self.EJ / self.m) / self.L

    @property
    def crossing(self) -> float:
        """The crossing time ``L / c``."""
        return self.L / self.speed

    def exact_midspan(self, t: np.ndarray, rtol: float = 1e-8) -> np.ndarray:
        """The continuum's mid-span deflection at times ``t >= 0``, the free vibration after
        the crossing included (:func:`moving_load_simply_supported`)."""
        return moving_load_simply_supported(
            self.L / 2, t, self.L, self.EJ, self.GA, self.m, self.F, self.speed, rtol=rtol
        )


#: The verification scene (module docstring).
VERIFICATION = Problem()
L, EJ, GA, M_PER_LENGTH, F = (
    VERIFICATION.L,
    VERIFICATION.EJ,
    VERIFICATION.GA,
    VERIFICATION.m,
    VERIFICATION.F,
)
#: Speed: half the critical speed ``pi sqrt(EJ / m) / L`` of the Euler-Bernoulli beam.
SPEED = VERIFICATION.speed
CROSSING = VERIFICATION.crossing
#: Mass matrix per formulation: fv lumped (its only kind), Galerkin and cubic consistent.
MASS = {
    "fv2": "lumped",
    "fv3": "lumped",
    "galerkin-p1": "consistent",
    "galerkin-p2": "consistent",
    "cubic": "consistent",
}
#: How the force is applied: ``point_load``, the load vector of ``Beam.point_load`` at
#: ``c t`` rebuilt every step; ``slider``, a massless body carrying the force, driven along
#: the beam at ``c`` by a spherical slider (:class:`sliders.joints.drives.Ramp` from 0 to
#: ``L`` over the crossing, then at rest on the end support).
LOADINGS = ("point_load", "slider")
#: Degree in the load's abscissa of a point load's vector between break points.
LOAD_DEGREE = {"fv2": 1, "fv3": 1, "galerkin-p1": 1, "galerkin-p2": 2, "cubic": 3}


@dataclass
class Model:
    """The supported beam, its structure and the moving load."""

    formulation: str
    n_elements: int
    beam: Beam
    structure: Structure
    supports: list[Support]
    smearing: float = 0.0
    problem: Problem = VERIFICATION

    @cached_property
    def load(self) -> MovingLoad:
        """The force at ``xi = c t``, on the end support (so carried by it) once it has
        crossed: its global load vector at ``t``, ``load(t)``, or at many times,
        ``load.at(t)`` (what the compiled steps read, a chunk at a time)."""
        p = self.problem
        return MovingLoad(
            BeamChain(self.structure, [0]),
            Linear(0.0, p.speed),
            force=(0.0, p.F, 0.0),
            smearing=self.smearing,
        )

    @property
    def midspan(self) -> int:
        """Global dof of the mid-span deflection ``u_y(L / 2)`` (a vertex: even meshes)."""
        return int(self.structure.node_dofs((0, self.n_elements // 2))[1])

    def dynamics(self, rho_inf: float, loading: str = "point_load") -> Dynamics:
        """Generalized-alpha on the model, the force applied as :data:`LOADINGS` says."""
        if loading not in LOADINGS:
            raise ValueError(f"loading must be one of {', '.join(LOADINGS)}, got {loading!r}")
        if loading == "point_load":
            return Dynamics(
                self.structure,
                self.supports,
                load=self.load,
                mass=MASS[self.formulation],
                rho_inf=rho_inf,
            )
        p = self.problem
        structure = Structure([self.beam], bodies=[RigidBody("body", (0, 0, 0), mass=0.0)])
        slider = Slider(
            "spherical",
            BeamChain(structure, [0]),
            "body",
            drive=Ramp(0.0, p.L, 0.0, p.crossing, "linear"),
            smearing=self.smearing,
            name="body",
        )
        return Dynamics(
            structure,
            self.supports + [Support("body", kind="rx+ry+rz")],
            [slider],
            structure.nodal_load("body", (0.0, p.F, 0.0)),
            mass=MASS[self.formulation],
            rho_inf=rho_inf,
            method="condensed",
        )


def section(problem: Problem = VERIFICATION) -> Section:
    """The beam's section: bending and shear in both planes, no rotary inertia (``EA``
    and ``GJ`` play no role in this bending problem)."""
    return Section.diagonal(
        EA=1e3 * problem.EJ,
        GAy=problem.GA,
        GAz=problem.GA,
        GJ=problem.EJ,
        EJy=problem.EJ,
        EJz=problem.EJ,
        mass_per_length=problem.m,
        name="moving-load",
    )


def model(
    name: str, n_elements: int, smearing: float = 0.0, problem: Problem = VERIFICATION
) -> Model:
    """The simply supported beam of ``n_elements`` (even) elements of formulation ``name``."""
    if n_elements % 2:
        raise ValueError(f"n_elements must be even (mid-span on a node), got {n_elements}")
    npe = formulation(name).nodes_per_element
    beam = Beam(straight((0, 0, 0), (problem.L, 0, 0), n_elements, npe), section(problem), name)
    supports = [Support(0, "start", "ux+uy+uz+rx"), Support(0, "end", "uy+uz")]
    return Model(name, n_elements, beam, Structure([beam]), supports, smearing, problem)


def scene(
    formulation: str,
    n_elements: int,
    steps: int,
    rho_inf: float,
    t_end: float,
    problem: Problem = VERIFICATION,
) -> dict[str, Any]:
    """The ``slider`` loading of :meth:`Model.dynamics` as a scene (``docs/scenes.md``): the
    beam of ``n_elements`` (even) elements, a massless body carrying the force on a
    spherical slider driven from ``0`` to ``L`` over the crossing (a linear ramp, then at
    rest on the end support), ``steps`` steps per crossing of generalized-alpha to
    ``t_end``; ``nodes.csv`` keeps every beam node's ``uy`` at every step (the mid-span one
    is the deflection measured), ``history.csv`` the steps and times only."""
    if n_elements % 2:
        raise ValueError(f"n_elements must be even (mid-span on a node), got {n_elements}")
    p = problem
    material = section(p)
    stiffness = dict(
        zip(("EA", "GAy", "GAz", "GJ", "EJy", "EJz"), np.diag(material.stiffness), strict=True)
    )
    return {
        "title": f"moving load, {formulation}, {n_elements} elements, {steps} steps per crossing",
        "formulation": formulation,
        "section": [
            {"name": "beam"}
            | {k: float(v) for k, v in stiffness.items()}
            | {"mass_per_length": p.m}
        ],
        "beam": [
            {
                "name": "beam",
                "section": "beam",
                "straight": {
                    "start": [0.0, 0.0, 0.0],
                    "end": [p.L, 0.0, 0.0],
                    "elements": n_elements,
                },
            }
        ],
        "body": [{"name": "body", "position": [0.0, 0.0, 0.0]}],
        "support": [
            {"node": "beam.start", "kind": "ux+uy+uz+rx"},
            {"node": "beam.end", "kind": "uy+uz"},
            {"node": "body", "kind": "rx+ry+rz"},
        ],
        "slider": [{"name": "body", "kind": "spherical", "line": "beam", "body": "body"}],
        "load": [{"kind": "nodal", "node": "body", "force": [0.0, p.F, 0.0]}],
        "drive": [
            {
                "kind": "abscissa",
                "slider": "body",
                "motion": {
                    "kind": "ramp",
                    "start": 0.0,
                    "end": p.L,
                    "t0": 0.0,
                    "t1": p.crossing,
                    "shape": "linear",
                },
            }
        ],
        "study": {
            "kind": "dynamic",
            "t_end": t_end,
            "step": p.crossing / steps,
            "rho_inf": rho_inf,
            "mass": MASS[formulation],
            "method": "condensed",
        },
        "output": {
            "csv": ["nodes"],
            "nodes": {"nodes": ["beam"], "columns": ["uy"]},
            "history": [],
        },
    }


def simulate(
    m: Model,
    steps: int,
    rho_inf: float = 0.8,
    t_end: float | None = None,
    loading: str = "point_load",
) -> tuple[np.ndarray, np.ndarray]:
    """Times and mid-span deflections of fixed generalized-alpha steps, ``steps`` of them
    across the crossing, from rest (the load enters on the support: zero acceleration at
    ``t = 0``), on to ``t_end`` (default the crossing time; a whole number of steps) with
    the same step; the force applied as ``loading`` says (:data:`LOADINGS`)."""
    d = m.dynamics(rho_inf, loading)
    if loading == "point_load":
        zero = np.zeros(m.structure.n_dofs)
        state = State(0.0, zero, zero, zero, zero)
    else:
        state = d.static_state()  # the slider's multipliers in equilibrium (zero load)
    h = m.problem.crossing / steps
    total = steps if t_end is None else int(round(t_end / h))
    probe = Probe(m.midspan)
    d.run(state, total * h, h, recorder=probe, progress=False)
    # the nominal times: the run's add h step by step, and may end an ulp past them
    return h * np.arange(total + 1), np.array(probe.w)


class Probe:
    """A recorder (:class:`sliders.solve.dynamics.Recorder`) of one dof's history."""

    def __init__(self, dof: int) -> None:
        self.dof, self.w = dof, [0.0]

    def start(self, dynamics: Dynamics, state: State) -> None:
        self.w = [float(state.q[self.dof])]

    def record(self, dynamics: Dynamics, new: State, old: State) -> None:
        self.w.append(float(new.q[self.dof]))

    def close(self) -> None:
        pass


def exact_midspan(t: np.ndarray, rtol: float = 1e-8) -> np.ndarray:
    """The verification scene's mid-span deflection (:meth:`Problem.exact_midspan`)."""
    return VERIFICATION.exact_midspan(t, rtol)


def relative_error(w: np.ndarray, reference: np.ndarray, scale: np.ndarray | None = None) -> float:
    """``max_t |w - w_ref| / max_t |w_scale|``, by default ``w_scale = w_ref``."""
    scale = reference if scale is None else scale
    return float(np.abs(w - reference).max() / np.abs(scale).max())


def semi_discrete(m: Model, t: np.ndarray) -> np.ndarray:
    """Mid-span deflection of the model's exact semi-discrete solution at times ``t``
    (module docstring)."""
    d = m.dynamics(1.0)
    free = d.free
    mass = d.M[free][:, free].toarray()
    moving = np.flatnonzero(np.diag(mass) > 0)  # translations with mass
    still = np.setdiff1d(np.arange(len(free)), moving)  # massless rotations
    K = d.K[free][:, free].toarray()
    Kmm, Kms = K[np.ix_(moving, moving)], K[np.ix_(moving, still)]
    Ksm, Kss = K[np.ix_(still, moving)], K[np.ix_(still, still)]
    condense = Kms @ np.linalg.inv(Kss)  # f* = f_m - Kms Kss^-1 f_s
    omega2, V = sla.eig(Kmm - condense @ Ksm, mass[np.ix_(moving, moving)])
    if np.abs(omega2.imag).max() > 1e-9 * np.abs(omega2).max() or omega2.real.min() <= 0:
        raise ValueError("the condensed modes are not real and positive")
    omega, V = np.sqrt(omega2.real), V.real
    modal = np.linalg.solve(V, np.linalg.inv(mass[np.ix_(moving, moving)]))
    project = modal @ np.hstack([np.eye(len(moving)), -condense])  # f_free -> modal force
    order = np.concatenate([moving, still])

    def force(times: np.ndarray) -> np.ndarray:  # (n_modes, len(times))
        f = np.array([m.load(s)[free][order] for s in times]).T
        return project @ f

    mid = np.flatnonzero(free[moving] == m.midspan)[0]
    breaks = _load_breaks(m)
    if t.max() > breaks[-1]:  # the free vibration after the crossing: no load on the beam
        breaks = np.append(breaks, t.max())
    degree = LOAD_DEGREE[m.formulation]
    q, v = np.zeros(len(omega)), np.zeros(len(omega))
    out = np.zeros(len(t))
    for t0, t1 in zip(breaks[:-1], breaks[1:], strict=True):
        # the piece's modal force as a polynomial in s = t - t0, from interior samples
        s = (t1 - t0) * (np.arange(degree + 1) + 0.5) / (degree + 1)
        g = force(t0 + s) @ np.linalg.inv(np.vander(s, degree + 1, increasing=True)).T
        inside = (t >= t0) & (t <= t1)
        qs, _ = _polynomial_response(omega, g, q, v, t[inside] - t0)
        out[inside] = V[mid] @ qs
        q, v = _polynomial_response(omega, g, q, v, np.array([t1 - t0]))
        q, v = q[:, 0], v[:, 0]
    return out


def _load_breaks(m: Model) -> np.ndarray:
    """Times at which the load vector's polynomial piece changes (module docstring), up to
    the crossing time."""
    if m.smearing:
        raise ValueError("semi_discrete takes a point load (smearing = 0)")
    local = m.beam.formulation.breakpoints()
    xi = m.beam.mesh.abscissae(np.arange(m.n_elements)[:, None], local).ravel()
    return np.unique(np.clip(xi, 0, m.problem.L)) / m.problem.speed


def _polynomial_response(
    omega: np.ndarray, g: np.ndarray, q0: np.ndarray, v0: np.ndarray, s: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Exact ``q(s), q'(s)`` of ``q'' + omega^2 q = sum_i g_i s^i`` (degree <= 3) from
    ``q0, v0``: the particular solution ``g / omega^2 - g'' / omega^4`` (the fourth
    derivative of ``g`` vanishes) plus the free oscillation that meets the initial values."""
    g = np.pad(g, ((0, 0), (0, 4 - g.shape[1])))
    w2 = omega[:, None] ** 2
    # the particular solution's coefficients in s, and its derivative's
    curvature = np.pad(np.stack([2 * g[:, 2], 6 * g[:, 3]], axis=1), ((0, 0), (0, 2)))
    p = g / w2 - curvature / w2**2
    dp = p[:, 1:] * np.arange(1, 4)
    powers = np.power.outer(s, np.arange(4))  # (len(s), 4)
    A, B = q0 - p[:, 0], (v0 - dp[:, 0]) / omega
    ws = np.multiply.outer(omega, s)
    c, sn = np.cos(ws), np.sin(ws)
    return (
        A[:, None] * c + B[:, None] * sn + p @ powers.T,
        omega[:, None] * (B[:, None] * c - A[:, None] * sn) + dp @ powers[:, :3].T,
    )
