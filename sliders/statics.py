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
    per step (:mod:`sliders.condensed`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Sequence

import numpy as np

import scipy.sparse as sp
import scipy.sparse.linalg as spla

from fvbeam.statics import Structure, Support
from sliders.condensed import CondensedOperator
from sliders.joint import Slider

METHODS = ("bordered", "condensed")


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
    linear-algebra back end, ``bordered`` or ``condensed`` (module docstring).
    """

    def __init__(self, structure: Structure, supports: Sequence[Support],
                 sliders: Sequence[Slider], reuse: "SliderStatics | None" = None,
                 method: str = "bordered") -> None:
        if method not in METHODS:
            raise ValueError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
        self.structure, self.sliders, self.method = structure, list(sliders), method
        names = [s.name for s in self.sliders]
        if len(set(names)) != len(names):
            raise ValueError(f"slider names must be unique, got {names}")
        fixed = structure.support_dofs(supports)
        if reuse is not None and reuse._same_operator(structure, fixed):
            self.K, self.free, self.K_free = reuse.K, reuse.free, reuse.K_free
            self._position, self._condensed = reuse._position, reuse._condensed
        else:
            self.K = structure.tangent(np.zeros(structure.n_dofs)).tocsr()
            self.free = np.setdiff1d(np.arange(structure.n_dofs), fixed)
            self._position = np.full(structure.n_dofs, -1)
            self._position[self.free] = np.arange(len(self.free))
            self.K_free = self.K[self.free][:, self.free].tocoo()
            self._condensed = None
        if method == "condensed" and self._condensed is None:
            self._condensed = CondensedOperator(structure, self.K, self.free)

    def _same_operator(self, structure: Structure, fixed: np.ndarray) -> bool:
        old = self.structure
        return (len(old.beams) == len(structure.beams)
                and all(a.stiffness is b.stiffness for a, b in zip(old.beams, structure.beams))
                and all(np.array_equal(a, b) for a, b in zip(old.dof_maps, structure.dof_maps))
                and np.array_equal(np.setdiff1d(np.arange(structure.n_dofs), fixed),
                                   self.free))

    def initial_unknowns(self, q: np.ndarray) -> list[np.ndarray]:
        return [s.initial_unknowns(self.structure, q) for s in self.sliders]

    def solve(self, f: np.ndarray, start: tuple[np.ndarray, list[np.ndarray]] | None = None,
              tol: float = 1e-8, max_iterations: int = 25, load_steps: int = 1) -> SliderSolution:
        """Newton-Raphson from ``start`` (default: no displacement, projected ``xi``).

        ``load_steps``: the load is applied in that many equal increments, each solved from
        the previous one's converged state.  Converged when the increments fall below
        ``tol`` relative to their scale: ``q`` to its largest entry, ``xi`` to its line's
        length, multipliers to the largest of them and of the load.  (The scale of ``q`` is
        the largest displacement the solve has met, so a solution at rest, ``q = 0``, still
        converges.)  Raises ``ValueError``
        naming the free motion when the system is singular, or the last residual when
        Newton does not converge (with the load step, when there are several).
        """
        f = np.asarray(f, dtype=float)
        if f.shape != (self.structure.n_dofs,) or not np.all(np.isfinite(f)):
            raise ValueError(f"load vector must be finite with {self.structure.n_dofs} rows")
        if not (isinstance(load_steps, (int, np.integer)) and load_steps >= 1):
            raise ValueError(f"load_steps must be a positive integer, got {load_steps!r}")
        state, counts = start, []
        for k in range(1, load_steps + 1):
            try:
                q, ys, residuals = self._newton(f * (k / load_steps), state, tol,
                                                max_iterations)
            except ValueError as exc:
                if load_steps == 1:
                    raise
                raise ValueError(f"load step {k} of {load_steps}: {exc}") from exc
            counts.append(len(residuals) - 1)
            state = (q, ys)
        return SliderSolution(q, ys, residuals, counts)

    def _newton(self, f: np.ndarray, start: tuple[np.ndarray, list[np.ndarray]] | None,
                tol: float, max_iterations: int) -> tuple[np.ndarray, list, list[float]]:
        """One Newton solve: converged ``q``, slider unknowns and residual history."""
        n = self.structure.n_dofs
        q = np.zeros(n) if start is None else start[0].copy()
        ys = self.initial_unknowns(q) if start is None else [y.copy() for y in start[1]]
        scale = max(np.abs(f).max(), 1e-300)
        residuals, first, reach = [], None, np.abs(q).max(initial=0.0)
        for _ in range(max_iterations + 1):
            r_q = self.K @ q - f
            parts = [s.assemble(self.structure, q, y) for s, y in zip(self.sliders, ys)]
            for dofs, rq, _, _ in parts:
                np.add.at(r_q, dofs, rq)
            r_y = np.concatenate([np.zeros(0)] + [p[2] for p in parts])
            residuals.append(float(max(np.abs(r_q[self.free]).max(), np.abs(r_y).max(initial=0))
                                   / scale))
            if first is None:
                first = parts
            elif converged:
                return q, ys, residuals
            step = (self._condensed_step(r_q, parts) if self.method == "condensed"
                    else self._bordered_step(r_q, parts))
            if step is None:
                raise ValueError(self._singular(self._bordered(parts)[0])
                                 or f"the {self.method} system has no finite solution")
            dq, dy = step
            q += dq
            reach = max(reach, np.abs(dq).max(initial=0.0), np.abs(q).max(initial=0.0))
            offsets = np.cumsum([0] + [len(y) for y in ys])
            ys = [y + dy[a:b] for y, a, b in zip(ys, offsets[:-1], offsets[1:])]
            force = max([scale] + [np.abs(y[1:]).max() for y in ys])
            steps = np.split(dy, offsets[1:-1])
            converged = (np.abs(dq).max() <= tol * max(reach, 1e-300)
                         and all(abs(d[0]) <= tol * s.line.length
                                 and np.abs(d[1:]).max() <= tol * force
                                 for d, s in zip(steps, self.sliders)))
        raise ValueError(self._singular(self._bordered(first)[0]) or
                         f"Newton did not converge in {max_iterations} iterations "
                         f"(scaled residual {residuals[-1]:.3g})")

    def jacobian(self, q: np.ndarray, unknowns: Sequence[np.ndarray]) -> sp.csc_matrix:
        """The Newton matrix at ``q`` and the sliders' ``unknowns``: rows and columns are the
        free dofs (in order) followed by each slider's unknowns."""
        parts = [s.assemble(self.structure, q, y) for s, y in zip(self.sliders, unknowns)]
        return self._bordered(parts)[0]

    def _bordered(self, parts: list) -> tuple[sp.csc_matrix, list[np.ndarray]]:
        """The bordered matrix on the free dofs and slider unknowns, and the sliders'
        residuals ``r_y``."""
        nf = len(self.free)
        rows, cols, vals = [self.K_free.row], [self.K_free.col], [self.K_free.data]
        r_y, offset = [], nf
        for dofs, _, ry, J in parts:
            index = np.concatenate([self._position[dofs], offset + np.arange(len(ry))])
            keep = index >= 0
            rr, cc = np.meshgrid(index[keep], index[keep], indexing="ij")
            rows.append(rr.ravel())
            cols.append(cc.ravel())
            vals.append(J[np.ix_(keep, keep)].ravel())
            r_y.append(ry)
            offset += len(ry)
        S = sp.csc_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                          shape=(offset, offset))
        return S, r_y

    def _bordered_step(self, r_q: np.ndarray,
                       parts: list) -> tuple[np.ndarray, np.ndarray] | None:
        """Newton increments from the factorised bordered system; None if it is singular."""
        S, r_y = self._bordered(parts)
        try:
            z = spla.splu(S).solve(-np.concatenate([r_q[self.free]] + r_y))
        except RuntimeError:
            return None
        if not np.all(np.isfinite(z)):
            return None
        dq = np.zeros_like(r_q)
        dq[self.free] = z[:len(self.free)]
        return dq, z[len(self.free):]

    def _condensed_step(self, r_q: np.ndarray,
                        parts: list) -> tuple[np.ndarray, np.ndarray] | None:
        """Newton increments from the condensed system (:mod:`sliders.condensed`) on the
        touched free dofs; None if it is singular."""
        where = [self._position[p[0]] for p in parts]
        touched = np.unique(np.concatenate(where))
        touched = touched[touched >= 0]
        t, m = len(touched), sum(len(p[2]) for p in parts)
        J = np.zeros((t + m, t + m))
        offset = t
        for w, (_, _, ry, block) in zip(where, parts):
            keep = np.flatnonzero(w >= 0)
            local = np.concatenate([keep, len(w) + np.arange(len(ry))])
            index = np.concatenate([np.searchsorted(touched, w[keep]),
                                    offset + np.arange(len(ry))])
            J[np.ix_(index, index)] += block[np.ix_(local, local)]
            offset += len(ry)
        step = self._condensed.step(r_q[self.free], touched, J,
                                    np.concatenate([p[2] for p in parts]))
        if step is None:
            return None
        dq = np.zeros_like(r_q)
        dq[self.free] = step[0]
        return dq, step[1]

    def _singular(self, S: sp.spmatrix) -> str | None:
        """If the bordered matrix is singular once its rows and columns are equilibrated
        (smallest singular value below 1e-12 of the largest), name the unknowns that move
        along its null vector; else None."""
        A = S.toarray()
        A = A / np.abs(A).max(axis=1, keepdims=True).clip(1e-300)
        A = A / np.abs(A).max(axis=0, keepdims=True).clip(1e-300)
        _, sigma, Vt = np.linalg.svd(A)
        if sigma[-1] > 1e-12 * sigma[0]:
            return None
        names = [self.structure.dof_name(d) for d in self.free]
        for s in self.sliders:
            names += [f"{s.name}.{u}" for u in s.unknown_names]
        v = Vt[-1]
        top = np.argsort(-np.abs(v))[:3]
        moving = ", ".join(f"{names[i]} ({v[i]:+.2f})" for i in top if abs(v[i]) > 0.1)
        return ("singular configuration: the supports and sliders leave a free motion "
                f"(null vector mostly along {moving})")
