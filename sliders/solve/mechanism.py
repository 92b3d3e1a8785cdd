"""The singular-structure check with sliders: the rigid motions neither supports nor sliders hold.

:func:`fvbeam.mechanism.rigid_modes` gives the rigid motions ``Phi`` that the supports leave
free (on the time integrator's operator ``M + c K``, :func:`fvbeam.mechanism.unresisted`
keeps those it does not resist: the massless parts').  Sliders may hold them: the piston of
the sliding-beams setup is held by its two sliders alone.  At a state whose multipliers are
all zero (every start from rest: a static solve from its default start, a sweep's cold
point, the static start of a time integration) the joints' Jacobian blocks ``E`` (the slot
forces in the dofs) and ``A_xi`` (in the abscissa) vanish, being linear in the multipliers,
and ``(Phi a, d xi, 0)`` is a null vector of the Newton matrix (the bordered one,
:mod:`sliders.solve.statics`) exactly when::

    C Phi a + D_xi d xi = 0

with ``C`` and ``D_xi`` the derivatives of every joint equation (``xi``, position,
orientation) in the structure dofs and in the abscissae: a motion the joint equations let
through.  The Newton matrix is then singular whatever the load, and :func:`free_motion` names
the motion, in the words of :func:`fvbeam.mechanism.motion_phrases` with each slider's
abscissa as ``slider 'key' sliding along its line``.  (Its ``xi`` row vanishes too at zero
multipliers, ``-l . lambda + sum mu dg/dxi``, unless a drive or an end stop holds ``xi``:
then it is the unit row that keeps ``d xi = 0``.)  The Newton matrix may also be singular
with a null vector in the multipliers (joints that hold the same motion twice); the back
ends' own tests catch that (:meth:`sliders.solve.statics.SliderStatics._singular`).

A motion held only by the multipliers themselves (a bead at rest in a curved wire under a
load: the ``xi`` row's ``-l_/xi . lambda``) has no stiffness at zero multipliers: from rest
the Newton matrix is singular, and the check names it.  Such a solve starts from the
multipliers instead (``start=``, as ``tests/test_rigid_line_sliders.py`` does); a warm start
is not checked.

The small matrix has a row per joint equation and a column per rigid motion and per slider.
Its rows and columns are equilibrated (scaled by their largest entries) and its null space
is spanned by the right singular vectors whose singular values fall below
:data:`sliders.solve.condensed.SINGULAR_RCOND` of the largest: the threshold of the
condensed back end's regularity test.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from fvbeam.mechanism import RigidModes, free_motion_message, motion_phrases
from fvbeam.structure import Structure
from sliders.joints.slider import Slider
from sliders.solve.condensed import SINGULAR_RCOND

#: What holds a free motion, in the message of a static solve.
REMEDY = "hold it with a support, a slider or a drive"
#: What holds a massless part's free motion in a time step (a mass holds it there).
MASSLESS_REMEDY = f"{REMEDY}, or give the part mass"


def member_parts(stacked: list, b: int) -> list:
    """Member ``b``'s ``(dofs, r_q, r_y, J)`` per slider from the stacked slot arrays
    ``(dofs, r, J)`` of :meth:`sliders.joints.slider.SliderBatch.evaluate` (``J`` dense)."""
    out = []
    for dofs, r, J in stacked:
        t = dofs.shape[1]
        out.append((dofs[b], r[b, :t], r[b, t:], J.subset(np.array([b])).dense()[0]))
    return out


def joint_parts(
    structure: Structure,
    sliders: Sequence[Slider],
    q: np.ndarray,
    unknowns: Sequence[np.ndarray],
    time: float = 0.0,
    scale: float = 1.0,
) -> list:
    """Each slider's ``(dofs, r_q, r_y, J)`` at the state ``q`` and ``unknowns`` (drives read
    at ``time``, multipliers scaled by ``scale``,
    :meth:`~sliders.joints.slider.SliderBatch.evaluate`)."""
    return member_parts(
        [
            s.batch(structure).evaluate(q[None], np.asarray(y, dtype=float)[None], time, scale)
            for s, y in zip(sliders, unknowns, strict=True)
        ],
        0,
    )


def free_motion(
    modes: RigidModes,
    position: np.ndarray,
    parts: list,
    sliders: Sequence[Slider],
    remedy: str = REMEDY,
) -> str | None:
    """The message naming the motions that neither the supports nor the sliders hold, or
    None (module docstring).

    Parameters
    ----------
    modes
        The free rigid motions of the operator.
    position
        The position of each global dof among the free dofs, -1 where supported.
    parts
        Each slider's ``(dofs, r_q, r_y, J)`` (:func:`joint_parts`) at a state whose
        multipliers are zero.
    sliders
        The sliders, named in the message.
    remedy
        What would hold the motion, at the end of the message.
    """
    if modes.k == 0:
        return None
    phi = np.vstack([modes.phi, np.zeros((1, modes.k))])  # row -1: a supported dof
    columns = modes.k + len(parts)
    rows = [np.zeros((0, columns))]
    for j, (dofs, _, _, J) in enumerate(parts):
        t = len(dofs)
        block = np.zeros((J.shape[0] - t, columns))
        block[:, : modes.k] = J[t:, :t] @ phi[position[dofs]]
        block[:, modes.k + j] = J[t:, t]
        rows.append(block)
    null = _null_space(np.vstack(rows))
    if null.shape[1] == 0:
        return None
    extras = [f"slider '{s.name}' sliding along its line" for s in sliders]
    held_by = "supports and sliders" if sliders else "supports"
    return free_motion_message(held_by, motion_phrases(modes, null, extras), remedy)


def _null_space(G: np.ndarray) -> np.ndarray:
    """The null space of ``G`` equilibrated by rows and columns (module docstring), in the
    unknowns of ``G``."""
    rows = np.abs(G).max(axis=1, initial=0.0)
    G = G / np.where(rows > 0, rows, 1.0)[:, None]
    cols = np.abs(G).max(axis=0, initial=0.0)
    scale = np.where(cols > 0, 1.0 / np.where(cols > 0, cols, 1.0), 1.0)
    G = np.vstack([G * scale, np.zeros((max(G.shape[1] - G.shape[0], 0), G.shape[1]))])
    _, sigma, Vt = np.linalg.svd(G)
    null = Vt[sigma <= SINGULAR_RCOND * sigma.max(initial=0.0)].T
    return scale[:, None] * null
