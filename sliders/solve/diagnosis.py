"""Which motion a singular Newton matrix leaves free, named without a dense copy of it.

The bordered Newton matrix ``S`` (:mod:`sliders.solve.statics`: rows and columns the free
dofs, then the joints' unknowns) is singular, as the back ends' own tests and the old dense
diagnosis take it, when its rows and columns equilibrated (each scaled by its largest
entry) have a singular value below :data:`~sliders.solve.condensed.SINGULAR_RCOND` of the
largest.  A problem of 1e5 elements has 6e5 unknowns: a dense copy of ``S`` (2.9 TB) and its
SVD are out of reach, so the null space is sought where a singular structure has it:

1. **The free rigid motions and the joints' unknowns.**  A part's stiffness is positive
   definite on every motion but its rigid ones (:mod:`fvbeam.mechanism`), so a null vector
   of ``S`` moves the dofs along the free rigid motions ``Phi`` only, with the joints'
   unknowns (a part held by sliders that let it slide, multipliers that hold one motion
   twice).  ``S W`` with ``W = [Phi, 0; 0, I]`` is a thin matrix (one column per free
   motion and per joint unknown); the singular values and right vectors of its small ``R``
   factor give every null vector of ``S`` in that subspace.
2. **Otherwise, a near-null vector** of the whole, by inverse iteration on ``S^T S`` with a
   sparse LU of the equilibrated ``S`` (:func:`near_null`; an ``S`` SuperLU finds exactly
   singular is factorised shifted by the rounding of its entries), named by the unknowns it
   mostly moves.

The largest singular value of the equilibrated ``S`` is bounded by ``sqrt(|S|_1
|S|_inf)`` (Higham, *Accuracy and Stability of Numerical Algorithms*, Sec. 6.2), which the
threshold is taken of.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from fvbeam.mechanism import RigidModes, free_motion_message, motion_phrases
from fvbeam.structure import Structure
from sliders.joints.slider import Slider
from sliders.solve.condensed import SINGULAR_RCOND

#: Inverse iterations on ``S^T S`` for the near-null vector.
ITERATIONS = 4
#: A free motion is named as the parts' rigid motions when its displacements are more than
#: this share of its norm (a unit vector in balanced units), with the joints' unknowns whose
#: entries are more than this; a near-null vector by its largest entries down to this
#: share of the largest.
SHARE = 0.1


def equilibration(A: sp.spmatrix) -> tuple[np.ndarray, np.ndarray]:
    """The scales ``r``, ``c`` of the rows and columns that make the largest entry of every
    row and column of ``diag(1 / r) A diag(1 / c)`` one (an empty row or column: 1)."""
    A = abs(sp.csr_matrix(A))
    rows = A.max(axis=1).toarray().ravel()
    rows[rows == 0] = 1.0
    cols = (sp.diags(1.0 / rows) @ A).max(axis=0).toarray().ravel()
    cols[cols == 0] = 1.0
    return rows, cols


def near_null(A: sp.spmatrix) -> np.ndarray | None:
    """A unit vector ``x`` that minimises ``|A x|``, by :data:`ITERATIONS` inverse iterations
    on ``A^T A`` from a fixed start, with SuperLU's factorisation of ``A`` (shifted by the
    rounding of a row's products, ``k eps`` for ``k`` stored entries, if SuperLU finds ``A``
    exactly singular).  None when even that fails."""
    n = A.shape[0]
    try:
        lu = spla.splu(sp.csc_matrix(A))
    except RuntimeError:
        k = max(int(np.diff(sp.csr_matrix(A).indptr).max(initial=0)), 1)
        try:
            lu = spla.splu(sp.csc_matrix(A + k * np.finfo(float).eps * sp.eye(n)))
        except RuntimeError:
            return None
    x = _start(n)
    for _ in range(ITERATIONS):
        x = lu.solve(lu.solve(x, trans="T"))
        norm = np.linalg.norm(x)
        if not np.isfinite(norm) or norm == 0:
            return None
        x /= norm
    return x


def singular_motion(
    S: sp.spmatrix,
    rigid: RigidModes,
    structure: Structure,
    free: np.ndarray,
    sliders: Sequence[Slider],
    remedy: str,
) -> str | None:
    """The message naming the free motion of the bordered Newton matrix ``S`` (rows and
    columns: the ``free`` dofs of ``structure``, then each of the ``sliders``' unknowns), or
    None when ``S`` is regular (module docstring).

    In the free rigid motions ``rigid`` and the joints' unknowns: the parts' motions
    (:func:`fvbeam.mechanism.motion_phrases`) with the joints' unknowns that move with them;
    else, or when the null vector hardly moves the dofs, the unknowns that the null vector
    mostly moves.  ``remedy``: what would hold the motion."""
    S = sp.csr_matrix(S)
    nf = len(free)
    rows, cols = equilibration(S)
    balanced = (sp.diags(1.0 / rows) @ S @ sp.diags(1.0 / cols)).tocsr()
    largest = np.sqrt(spla.norm(balanced, 1) * spla.norm(balanced, np.inf))
    tolerance = SINGULAR_RCOND * largest
    names = [f"{s.name}.{u}" for s in sliders for u in s.unknown_names]

    def name(i: int) -> str:
        return structure.dof_name(int(free[i])) if i < nf else names[i - nf]

    null = _subspace_null(balanced, rigid.phi, cols, tolerance)
    if null.shape[1] and np.linalg.norm(null[:nf], axis=0).max() > SHARE:
        unit = null / cols[:, None]  # back to the unknowns' own units
        a = rigid.phi.T @ unit[:nf]
        joints = nf + np.flatnonzero(np.abs(null[nf:]).max(axis=1, initial=0.0) > SHARE)
        carried = [
            f"slider '{names[i - nf].removesuffix('.xi')}' sliding along its line"
            if names[i - nf].endswith(".xi")
            else names[i - nf]
            for i in joints
        ]
        phrases = motion_phrases(rigid, np.vstack([a, unit[joints]]), carried)
        return free_motion_message("supports and sliders", phrases, remedy)
    if null.shape[1]:  # the projection of a fixed vector: the same whatever the basis
        v = null @ (null.T @ _start(len(null)))
    else:
        x = near_null(balanced)
        if x is not None and np.linalg.norm(balanced @ x) > tolerance:
            return None
        if x is None:
            return "singular configuration: the supports and sliders leave a free motion"
        v = x
    v = v / np.linalg.norm(v)
    top = np.argsort(-np.abs(v))[:3]
    moving = ", ".join(
        f"{name(int(i))} ({v[i]:+.2f})" for i in top if abs(v[i]) > SHARE * abs(v[top[0]])
    )
    return (
        "singular configuration: the supports and sliders leave a free motion "
        f"(null vector mostly along {moving})"
    )


def _subspace_null(
    balanced: sp.csr_matrix, phi: np.ndarray, cols: np.ndarray, tolerance: float
) -> np.ndarray:
    """The null vectors of the equilibrated ``balanced`` (columns scaled by ``cols``) among
    the free rigid motions ``phi`` and the joints' unknowns (``W = [phi, 0; 0, I]``), as
    orthonormal columns in balanced units: the right singular vectors of the thin
    ``balanced W`` (through its small ``R`` factor) whose singular values are within
    ``tolerance``."""
    nf = phi.shape[0]
    m = balanced.shape[0] - nf
    W = np.zeros((balanced.shape[0], phi.shape[1] + m))  # balanced units: cols times unknowns
    W[:nf, : phi.shape[1]] = phi * cols[:nf, None]
    W[nf:, phi.shape[1] :] = np.diag(cols[nf:])
    if W.shape[1] == 0:
        return W
    W /= np.linalg.norm(W, axis=0)
    R = np.linalg.qr(np.asarray(balanced @ W), mode="r")
    _, sigma, Vt = np.linalg.svd(R, full_matrices=True)
    sigma = np.concatenate([sigma, np.zeros(len(Vt) - len(sigma))])
    found = Vt[sigma <= tolerance]
    if not len(found):
        return np.zeros((balanced.shape[0], 0))
    return np.linalg.qr(W @ found.T)[0]


def _start(n: int) -> np.ndarray:
    """The fixed vector the near-null vectors start from (seeded, so that a diagnosis is
    repeatable); a vector of a degenerate null space is named by its projection."""
    return np.random.default_rng(0).standard_normal(n)
