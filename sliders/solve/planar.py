"""Planar problems solved on their in-plane dofs.

A structure whose nodes, joints, loads and motions lie in a coordinate plane, and whose
stiffness, mass and damping couple no in-plane dof with an out-of-plane one (the plane's
normal a principal axis of every section and body), deforms in that plane only: the
out-of-plane translation and the two in-plane-axis rotations of every node stay zero, and so
do the joints' reactions out of the plane (the multiplier of the position constraint along
the normal, the orientation multipliers whose couples turn about in-plane axes).  A solve
given ``plane`` holds those dofs (as supports do) and pins those multipliers to zero (their
equations replaced by ``y_k = 0``, :mod:`sliders.joints.packed`): half the dofs, the same
answer (``tests/test_planar.py`` holds the two equal to roundoff).

:func:`out_of_plane` lists the dofs, :func:`pinned` a joint's multipliers (:func:`pin` puts
their equations into a joint's Jacobian), :func:`check`
refuses a problem that is not planar in the plane asked for, naming what leaves it, and
:func:`check_load` a load with out-of-plane components (scenes find their plane themselves:
:meth:`sliders.app.model.Model.plane`).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import scipy.sparse as sp

from fvbeam.mechanism import node_positions
from fvbeam.structure import Structure
from fvbeam.support import DOF_NAMES
from sliders.joints.slider import Slider
from sliders.lines.rigid import RigidLine

#: The coordinate planes by name, and the axis normal to each.
PLANES = {"yz": 0, "zx": 1, "xy": 2}
#: A coupling or an offset below this fraction of its matrix's or the structure's size is
#: roundoff (the frames of curved in-plane beams carry ``1e-17`` out-of-plane parts).
TIE = 1e-12


def normal(plane: str) -> int:
    """The axis (0, 1, 2) normal to ``plane`` (``xy``, ``yz`` or ``zx``)."""
    if plane not in PLANES:
        raise ValueError(f"plane must be one of {', '.join(PLANES)}, got {plane!r}")
    return PLANES[plane]


def out_of_plane_names(axis: int) -> tuple[str, ...]:
    """The dof names (``ux`` ... ``rz``) out of the plane normal to ``axis``."""
    return (DOF_NAMES[axis],) + tuple(DOF_NAMES[3 + a] for a in range(3) if a != axis)


def out_of_plane(structure: Structure, plane: str) -> np.ndarray:
    """The dofs a planar solve holds: every node's translation along the normal and its
    rotations about the two in-plane axes."""
    c = normal(plane)
    per_node = [c] + [3 + a for a in range(3) if a != c]
    nodes = np.arange(structure.n_dofs // 6)
    return np.sort((6 * nodes[:, None] + np.array(per_node)).ravel())


def pinned(slider: Slider, plane: str) -> list[int]:
    """The joint's unknowns a planar solve pins to zero (indices into its ``y``): the
    reaction's component along the normal; the orientation multiplier ``mu_j`` whose body
    axis ``e_bj`` is the normal (its couple ``e_bj x l`` turns about an in-plane axis); the
    spline slider's ``mu_1`` (a couple about the line).  ``ValueError`` when neither body
    axis ``e2``, ``e3`` of a classical or spline slider is the normal (its orientation
    constraints mix the planes)."""
    c = normal(plane)
    out = [1 + c]
    if slider.kind == "spherical":
        return out
    axes = [j for j in (1, 2) if abs(abs(slider.frame[c, j]) - 1.0) <= TIE]
    if not axes:
        raise ValueError(
            f"slider {slider.name!r}: neither of its axes e2, e3 is the normal of plane "
            f"{plane}, so its orientation constraints are not planar"
        )
    out.append(3 + axes[0])  # y = [xi, lambda (3), mu_2, mu_3, mu_1]
    if slider.kind == "spline":
        out.append(6)
    return out


def pin(J: np.ndarray, slots: int, pins: Sequence[int]) -> np.ndarray:
    """A joint's Jacobian ``J`` on ``[q(slots); y]`` (rows: its ``slots`` slot forces, then
    its equations) with the equation row of every unknown ``k`` in ``pins`` (:func:`pinned`)
    replaced by the unit row of ``y_k = 0``, as the compiled joints hold it
    (:func:`sliders.joints.packed.evaluate_joint`): the Newton matrix a planar solve
    factorises.  Without it a pinned multiplier's column has its entries on out-of-plane
    dofs only, all held, and the matrix is singular along it whatever the state."""
    if not len(pins):
        return J
    J = J.copy()
    for k in pins:
        J[slots + k] = 0.0
        J[slots + k, slots + k] = 1.0
    return J


def check(
    structure: Structure,
    sliders: Sequence[Slider],
    plane: str,
    matrices: Sequence[sp.spmatrix],
    checked: Sequence[Slider] = (),
) -> None:
    """``ValueError`` naming the first thing that leaves ``plane``: a node off the plane of
    the others, a sliding point or a rigid line off it, a slider whose axes mix the planes,
    a stiffness, mass or damping (``matrices``, on all dofs) coupling an in-plane dof with an
    out-of-plane one beyond :data:`TIE` of its largest entry.  ``checked``: the sliders of a
    problem this one is moved from (:meth:`~sliders.joints.slider.Slider.moved`), slider by
    slider; a slider's rigid line and axes are not checked again where they are that
    slider's (the same objects)."""
    c = normal(plane)
    positions = node_positions(structure)
    size = max(1.0, float(np.abs(positions).max(initial=0.0)))
    level = float(positions[0, c]) if len(positions) else 0.0
    off = np.flatnonzero(np.abs(positions[:, c] - level) > TIE * size)
    if off.size:
        name = structure.dof_name(6 * int(off[0])).rsplit(" ", 1)[0]
        raise ValueError(f"{name} lies off the plane {plane} of the structure's first node")
    previous: list[Slider | None] = [*checked[: len(sliders)]]
    previous += [None] * (len(sliders) - len(previous))
    for slider, old in zip(sliders, previous, strict=True):
        point = structure.node_position(slider.body) + slider.offset
        if abs(point[c] - level) > TIE * size:
            raise ValueError(f"slider {slider.name!r}: its sliding point is off plane {plane}")
        if old is not None and slider.line is old.line and slider.frame is old.frame:
            continue
        if isinstance(slider.line, RigidLine):
            xi = np.linspace(0.0, slider.line.length, 33)
            heights = [slider.line.derivatives(float(x))[0][c] for x in xi]
            if np.abs(np.array(heights) - level).max() > TIE * size:
                raise ValueError(f"slider {slider.name!r}: its line leaves plane {plane}")
        pinned(slider, plane)
    if matrices:  # none on a moved problem, whose operator was checked where it was built
        _check_coupling(structure, plane, matrices)


def moved_in_plane(old: Structure, new: Structure, plane: str) -> bool:
    """Whether ``new``, a moved copy of ``old`` (:meth:`~fvbeam.structure.Structure.moved`),
    keeps every node's coordinate along the normal of ``plane`` exactly (a move within the
    plane): then its nodes, sliding points and chains lie in the plane as ``old``'s did, and
    :func:`check` need not run again."""
    c = normal(plane)
    for a, b in zip(old.beams, new.beams, strict=True):
        if a is not b and not np.array_equal(a.mesh.points[:, c], b.mesh.points[:, c]):
            return False
    return all(
        a is b or float(a.position[c]) == float(b.position[c])
        for a, b in zip(old.bodies, new.bodies, strict=True)
    )


def _check_coupling(structure: Structure, plane: str, matrices: Sequence[sp.spmatrix]) -> None:
    """:func:`check`'s ``ValueError`` naming the first pair of dofs, one in ``plane`` and
    one out of it, that one of ``matrices`` couples beyond :data:`TIE` of its largest
    entry."""
    outside = np.zeros(structure.n_dofs, dtype=bool)
    outside[out_of_plane(structure, plane)] = True
    for A in matrices:
        A = sp.coo_matrix(A)
        big = float(np.abs(A.data).max(initial=0.0))
        across = (outside[A.row] != outside[A.col]) & (np.abs(A.data) > TIE * big)
        if across.any():
            i = int(np.flatnonzero(across)[0])
            raise ValueError(
                f"{structure.dof_name(int(A.row[i]))} and {structure.dof_name(int(A.col[i]))} "
                f"are coupled: the structure does not deform in plane {plane} alone"
            )


def check_load(
    structure: Structure,
    f: np.ndarray,
    plane: str,
    what: str = "the load",
    held: np.ndarray | None = None,
) -> None:
    """``ValueError`` naming the first out-of-plane dof ``f`` loads (beyond :data:`TIE` of
    its largest entry); ``held``: :func:`out_of_plane` of the structure, when known."""
    held = out_of_plane(structure, plane) if held is None else held
    big = float(np.abs(f).max(initial=0.0))
    bad = held[np.abs(f[held]) > TIE * big]
    if bad.size:
        raise ValueError(f"{what} acts on {structure.dof_name(int(bad[0]))}, out of plane {plane}")
