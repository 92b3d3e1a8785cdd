"""Static equilibrium of a structure with sliders: Newton-Raphson on the bordered system.

The beams are linear (stiffness ``K`` assembled once); the sliders touch a few dofs ``T`` and
add their own unknowns ``y``.  Each Newton step solves::

    (K + E) dq + A dy = -r_q,      C dq + D dy = -r_y

with ``E, A, C, D`` the sliders' Jacobian blocks on ``T`` and ``y`` (free dofs only; the
supports are eliminated).  ``K`` alone may be singular: a piston held only by its sliders is
a free body until the sliders are added, so the bordered matrix is factorised as a whole.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np

import scipy.sparse as sp
import scipy.sparse.linalg as spla

from fvbeam.statics import Structure, Support
from sliders.joint import Slider


@dataclass
class SliderSolution:
    """Displacements ``q``, each slider's unknowns ``[xi, lambda, (mu_2, mu_3)]``, the
    residual norms of the Newton iterations (forces scaled by the load), and their count."""

    q: np.ndarray
    unknowns: list[np.ndarray]
    residuals: list[float]

    @property
    def iterations(self) -> int:
        return len(self.residuals) - 1


class SliderStatics:
    """Equilibrium of ``structure`` held by ``supports`` and ``sliders``.

    ``reuse``: a previous instance on beams with the same stiffness objects, dof maps and
    supports (e.g. the same beams translated, :meth:`fvbeam.beam.Beam.translated`), whose
    assembled stiffness is then taken as it is; a sweep over positions builds it once.
    """

    def __init__(self, structure: Structure, supports: Sequence[Support],
                 sliders: Sequence[Slider], reuse: "SliderStatics | None" = None) -> None:
        self.structure, self.sliders = structure, list(sliders)
        names = [s.name for s in self.sliders]
        if len(set(names)) != len(names):
            raise ValueError(f"slider names must be unique, got {names}")
        fixed = structure.support_dofs(supports)
        if reuse is not None and reuse._same_operator(structure, fixed):
            self.K, self.free, self.K_free = reuse.K, reuse.free, reuse.K_free
            self._position = reuse._position
            return
        self.K = structure.tangent(np.zeros(structure.n_dofs)).tocsr()
        self.free = np.setdiff1d(np.arange(structure.n_dofs), fixed)
        self._position = np.full(structure.n_dofs, -1)
        self._position[self.free] = np.arange(len(self.free))
        self.K_free = self.K[self.free][:, self.free].tocoo()

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
              tol: float = 1e-8, max_iterations: int = 25) -> SliderSolution:
        """Newton-Raphson from ``start`` (default: no displacement, projected ``xi``).

        Converged when the increments fall below ``tol`` relative to their scale: ``q`` to its
        largest entry, ``xi`` to its line's length, multipliers to the largest of them and of
        the load.  Raises ``ValueError`` naming the free motion when the
        bordered system is singular, or the last residual when Newton does not converge.
        """
        n = self.structure.n_dofs
        q = np.zeros(n) if start is None else start[0].copy()
        ys = self.initial_unknowns(q) if start is None else [y.copy() for y in start[1]]
        scale = max(np.abs(f).max(), 1e-300)
        K, free = self.K, self.free
        residuals = []
        for _ in range(max_iterations + 1):
            r_q = K @ q - f
            parts = [s.assemble(self.structure, q, y) for s, y in zip(self.sliders, ys)]
            for dofs, rq, _, _ in parts:
                np.add.at(r_q, dofs, rq)
            r_y = np.concatenate([p[2] for p in parts])
            residuals.append(float(max(np.abs(r_q[free]).max(), np.abs(r_y).max()) / scale))
            if len(residuals) > 1 and converged:
                return SliderSolution(q, ys, residuals)
            dq, dy = self._step(r_q, parts, first=len(residuals) == 1)
            q += dq
            offsets = np.cumsum([0] + [len(y) for y in ys])
            ys = [y + dy[a:b] for y, a, b in zip(ys, offsets[:-1], offsets[1:])]
            force = max([scale] + [np.abs(y[1:]).max() for y in ys])
            steps = np.split(dy, offsets[1:-1])
            converged = (np.abs(dq).max() <= tol * max(np.abs(q).max(), 1e-300)
                         and all(abs(d[0]) <= tol * s.line.length
                                 and np.abs(d[1:]).max() <= tol * force
                                 for d, s in zip(steps, self.sliders)))
        raise ValueError(self._singular(self._first) or
                         f"Newton did not converge in {max_iterations} iterations "
                         f"(scaled residual {residuals[-1]:.3g})")

    def _step(self, r_q: np.ndarray, parts: list,
              first: bool = False) -> tuple[np.ndarray, np.ndarray]:
        """Newton increments from the bordered system on the free dofs and slider unknowns
        (the first iteration's matrix is kept to diagnose a failure)."""
        nf = len(self.free)
        rows, cols, vals = [self.K_free.row], [self.K_free.col], [self.K_free.data]
        r_y, offset = [], nf
        for dofs, _, ry, J in parts:
            k = len(dofs)
            index = np.concatenate([self._position[dofs], offset + np.arange(len(ry))])
            keep = index >= 0
            block = J[np.ix_(keep, keep)]
            rr, cc = np.meshgrid(index[keep], index[keep], indexing="ij")
            rows.append(rr.ravel())
            cols.append(cc.ravel())
            vals.append(block.ravel())
            r_y.append(ry)
            offset += len(ry)
        size = offset
        S = sp.csc_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                          shape=(size, size))
        rhs = -np.concatenate([r_q[self.free]] + r_y)
        if first:
            self._first = S
        try:
            z = spla.splu(S).solve(rhs)
        except RuntimeError:
            z = np.full(size, np.nan)
        if not np.all(np.isfinite(z)):
            raise ValueError(self._singular(S) or "the bordered system has no finite solution")
        dq = np.zeros_like(r_q)
        dq[self.free] = z[:nf]
        return dq, z[nf:]

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
            names += [f"{s.name}.{u}" for u in ("xi", "lambda_x", "lambda_y", "lambda_z",
                                                "mu_2", "mu_3")[:s.n_unknowns]]
        v = Vt[-1]
        top = np.argsort(-np.abs(v))[:3]
        moving = ", ".join(f"{names[i]} ({v[i]:+.2f})" for i in top if abs(v[i]) > 0.1)
        return ("singular configuration: the supports and sliders leave a free motion "
                f"(null vector mostly along {moving})")
