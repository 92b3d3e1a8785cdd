"""Modes about a solved static state: frequencies, damping ratios and mode shapes.

The structure with its supports, sliders and force elements, linearised about a converged
state ``(q, y)`` of :class:`~sliders.solve.statics.SliderStatics`, vibrates as::

    M q'' + C q' + (K + E) q + A y = 0,      C_y q + D y = 0

with ``[K + E, A; C_y, D]`` the Newton matrix of the statics at the state
(:meth:`~sliders.solve.statics.SliderStatics.jacobian`: the beams' stiffness on the free dofs
bordered by each slider's Jacobian in its abscissa and multipliers) plus the force elements'
stiffness ``dr/dq`` at rest, ``M`` the structure's mass (zero on the sliders' unknowns: the
abscissa and the multipliers carry no inertia, the constraint rows stay constraints), ``C``
the stiffness-proportional damping ``damping K`` of the beams (as in
:class:`~sliders.solve.dynamics.Dynamics`) plus the force elements' ``dr/dv``.  The pencil is
solved by :func:`fvbeam.modes.lowest_modes` (one sparse LU of the bordered matrix per state,
shift-invert).

Real modes when the damping is absent or proportional (``C = damping J``: neither sliders
nor force elements; each mode's ratio is then ``damping omega / 2``), complex modes
otherwise, whose eigenvalue ``s`` gives the natural frequency ``|s|`` and the damping ratio
``-Re s / |s|``; overdamped (non-oscillating) roots are not returned.

The beams are linear: about a loaded state the modes take the beams' unloaded stiffness
(no geometric stiffness of the preload; the sliders' terms in their multipliers are kept),
which :func:`modes_about` says in a warning.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.optimize import linear_sum_assignment

from fvbeam.modes import lowest_modes
from sliders.forces.kernel import evaluate_element
from sliders.solve.statics import SliderSolution, SliderStatics

#: The warning of a state under load (module docstring).
PRELOAD_WARNING = (
    "modes about a loaded state take the beams' linear, unloaded stiffness: the geometric "
    "stiffness of the preload is not included"
)


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
    unknowns
        (m, k) the sliders' unknowns' part of each mode, the sliders' in order.
    """

    omega: np.ndarray
    damping_ratio: np.ndarray
    shapes: np.ndarray
    unknowns: np.ndarray

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


def modes_about(
    statics: SliderStatics,
    solution: SliderSolution,
    count: int,
    *,
    mass: str = "lumped",
    damping: float = 0.0,
    window: tuple[float, float] | None = None,
) -> StateModes:
    """The ``count`` lowest modes about the state ``solution`` of ``statics`` (module
    docstring).

    Parameters
    ----------
    statics
        The problem (3-D: a planar one's joints are pinned out of its plane, which the
        bordered matrix does not express).
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

    Raises
    ------
    ValueError
        A bad argument, a planar problem, or a state whose linearised stiffness is singular.
    """
    if not (isinstance(count, (int, np.integer)) and count >= 1):
        raise ValueError(f"count must be an integer >= 1, got {count!r}")
    if not (np.isfinite(damping) and damping >= 0):
        raise ValueError(f"damping must be a finite coefficient >= 0, got {damping!r}")
    if window is not None and not (0 <= window[0] < window[1]):
        raise ValueError(f"window must be (f_min, f_max) with 0 <= f_min < f_max, got {window}")
    if statics.plane is not None:
        raise ValueError("modes are solved on the 3-D problem: build its statics without plane")
    q = solution.q
    if np.any(q != 0):
        warnings.warn(PRELOAD_WARNING, UserWarning, stacklevel=2)
    structure, free = statics.structure, statics.free
    nf = len(free)
    J = statics.jacobian(q, solution.unknowns)
    N = J.shape[0]
    K_f, C_f = _force_blocks(statics, q)
    pad = ((0, N - nf), (0, N - nf))
    J = (J + _padded(K_f, pad)).tocsc()
    M = _padded(structure.mass(mass)[free][:, free], pad).tocsc()
    C = _padded(damping * statics.K_free + C_f, pad).tocsr()
    C.eliminate_zeros()
    proportional = C.nnz == 0 or not (statics.sliders or statics.forces)
    shift = 0.0 if window is None else (2 * np.pi * window[0]) ** 2
    wanted = count if window is None else 2 * count
    try:
        spectrum = lowest_modes(J, M, wanted, None if proportional else C, shift)
    except RuntimeError as exc:  # splu: exactly singular
        raise ValueError(f"the linearised problem is singular at the state: {exc}") from exc
    if proportional:
        if spectrum.s.size and spectrum.s.min() <= 0:
            raise ValueError(
                "the linearised stiffness is not positive at the state (omega^2 = "
                f"{spectrum.s.min():.6g}): a motion the supports and sliders leave free, "
                "or a buckled state"
            )
        omega = np.sqrt(spectrum.s)
        zeta = damping * omega / 2
        vectors = spectrum.vectors
    else:
        s = spectrum.s
        omega, zeta, vectors = np.abs(s), -s.real / np.abs(s), spectrum.vectors
    order = np.argsort(omega)
    if statics.sliders:
        order = order[_resolved(spectrum.s[order], spectrum.s.dtype.kind == "c", shift)]
    if window is not None:
        low, high = 2 * np.pi * np.asarray(window)
        order = order[(omega[order] >= low * (1 - 1e-12)) & (omega[order] <= high)]
    order = order[:count]
    omega, zeta, vectors = omega[order], zeta[order], vectors[:, order]
    vectors = _normalised(vectors, M)
    shapes = np.zeros((structure.n_dofs, len(order)), dtype=vectors.dtype)
    shapes[free] = vectors[:nf]
    return StateModes(omega, zeta, shapes, vectors[nf:])


#: The unit roundoff.
UNIT_ROUNDOFF = float(np.finfo(float).eps) / 2


def _resolved(s: np.ndarray, damped: bool, shift: float) -> np.ndarray:
    """Which eigenvalues ``s`` (by ascending frequency) stand clear of the spurious roots of
    the constraints: the sliders' rows make the zero eigenvalue of the inverse pencil
    ``nu = 1 / (s - sigma)`` defective (Jordan blocks of the index-2 and, in first-order
    form, index-3 constraints), whose rounding-error perturbation ``u`` moves it by ``u^(1/2)``
    (``u^(1/3)``) times the largest ``|nu|`` (Lidskii's perturbation of a Jordan block;
    Moro, Burke and Overton, SIAM J. Matrix Anal. Appl. 18 (1997) 793).  Kept: ``|nu|``
    above ten times that; with a warning when any is dropped."""
    sigma = 1j * np.sqrt(shift) if damped else shift
    nu = 1 / np.abs(s - sigma) if s.size else s.real
    level = 10 * UNIT_ROUNDOFF ** (1 / 3 if damped else 1 / 2) * (nu.max() if nu.size else 0)
    keep = nu > level
    if not keep.all():
        warnings.warn(
            f"{int((~keep).sum())} of the modes asked for lie too far above the lowest to be "
            "told from the constraints' spurious roots in double precision, and are left out",
            UserWarning,
            stacklevel=3,
        )
    return keep


def _padded(A: sp.spmatrix, pad: tuple[tuple[int, int], tuple[int, int]]) -> sp.coo_matrix:
    """``A`` bordered by zero rows and columns (the sliders' unknowns)."""
    A = sp.coo_matrix(A)
    shape = (A.shape[0] + pad[0][1], A.shape[1] + pad[1][1])
    return sp.coo_matrix((A.data, (A.row, A.col)), shape=shape)


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
