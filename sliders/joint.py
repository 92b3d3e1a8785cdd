"""Slider joints: a node of the structure slides on a line (paper Secs. 3-4).

The body is a node of the structure (a beam node or a rigid body, six dofs ``u_b, theta_b``,
linear kinematics like the beams) carrying the sliding point at ``offset`` and the slider axes ``frame``
(columns ``e1, e2, e3``; ``e1`` along the line).  The line is a :class:`BeamChain` or a rigid
line.  Unknowns ``y = [xi, lambda (3), mu_2, mu_3, mu_1]``: ``mu_2, mu_3`` for the classical
and spline sliders, ``mu_1`` for the spline slider.  With
``x_b = X_b + offset + u_b + theta_b x offset`` and ``m`` the couple of the orientation
constraints:

=====================  ==================================================  =============
equation               residual                                            paper
=====================  ==================================================  =============
body force             ``+ lambda``                                         eq. 3
body moment            ``+ f_b x lambda + m``, ``f_b = theta_b x offset``   eqs. 3-5
line beams             ``- G(xi) lambda`` (test functions, smeared; T6)     Sec. 4
                       and ``- m`` shared by the nodes (below)
xi                     ``- l . lambda + sum_j mu_j d g_j / d xi``           eqs. 3-5
position               ``x_b - x(xi)``                                      eq. 1
orientation            ``g_j``                                              Secs. 3.2-3.3
=====================  ==================================================  =============

Two orientation models (``docs/sliders.md`` compares them):

* ``section`` (default; classical and spline): the constraints hold the body's axes to the
  line's *section frame*, the reference frame turned by the section rotation ``theta_L(xi)``
  interpolated linearly between the two nodes around ``xi``; the couple goes to those two
  nodes with the same weights (consistent virtual work).  A correction for the kink that the
  couple itself puts in the rotation makes the constraint second-order accurate.
* ``slope`` (classical only): the paper's eq. (4) on the gradient ``l`` of the interpolated
  centreline, the couple ``m = sum_j mu_j e_bj x l`` carried to the rotation dofs by the
  test functions, as the reference implementation does; first-order accurate, and singular
  when both sliders of the sliding-beams setup fall in one node's region.

Neither routes the couple through ``d l / d q`` as a force dipole on the slope: on
shear-deformable beams the dipole form loses the couple under mesh refinement.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from fvbeam.geometry import cross, orthonormal3, skew_matrices, vector3
from fvbeam.statics import Structure
from sliders.chain import BeamChain, LineRotation
from sliders.lines import LinePoint, RigidLine, axial

KINDS = ("spherical", "classical", "spline")
ORIENTATIONS = ("section", "slope")
UNKNOWNS = ("xi", "lambda_x", "lambda_y", "lambda_z", "mu_2", "mu_3", "mu_1")


@dataclass
class Slider:
    """A structure node sliding on a line.

    Parameters
    ----------
    kind
        ``spherical``, ``classical`` or ``spline``.
    line
        A :class:`BeamChain` of the same structure, or a rigid line.
    body
        The sliding node: ``(beam index, node)`` (node: index, ``'start'`` or ``'end'``) or
        the name of a rigid body of the structure.
    offset
        Sliding point relative to the node, in global axes of the reference configuration.
    frame
        Slider axes ``[e1, e2, e3]`` (columns) in the reference configuration.
    smearing, kernel
        Spread of the reaction force along the line (:mod:`fvbeam.smearing`); the couple of
        the ``section`` orientation is shared linearly between nodes and never jumps.
    orientation
        ``section`` or ``slope`` (module docstring).
    end_stops
        Stops at both ends of the line.  Without them, ``xi`` leaving the line is an error
        naming it; with them, the sliding point rests at the end (``xi`` held there, the
        reaction's tangential part ``l . lambda`` is the stop's force) while the stop pushes,
        and leaves it when the stop would have to pull.
    name
        Label used in error messages.
    """

    kind: str
    line: BeamChain | RigidLine
    body: tuple[int, int | str] | str
    offset: np.ndarray = field(default_factory=lambda: np.zeros(3))
    frame: np.ndarray = field(default_factory=lambda: np.eye(3))
    smearing: float = 0.0
    kernel: str = "box"
    orientation: str = "section"
    end_stops: bool = False
    name: str = "slider"

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"{self.name}: kind must be one of {', '.join(KINDS)}, "
                             f"got {self.kind!r}")
        if self.orientation not in ORIENTATIONS:
            raise ValueError(f"{self.name}: orientation must be one of "
                             f"{', '.join(ORIENTATIONS)}, got {self.orientation!r}")
        if self.orientation == "slope" and self.kind != "classical":
            raise ValueError(f"{self.name}: orientation 'slope' is the classical slider's "
                             f"(paper eq. 4); a {self.kind} slider needs 'section'")
        self.offset = vector3(self.offset, f"{self.name}: offset")
        self.frame = orthonormal3(self.frame, f"{self.name}: frame")

    @property
    def n_unknowns(self) -> int:
        """``xi``, ``lambda``; ``mu_2, mu_3`` for the classical and spline sliders; ``mu_1``
        for the spline slider."""
        return {"spherical": 4, "classical": 6, "spline": 7}[self.kind]

    @property
    def unknown_names(self) -> tuple[str, ...]:
        """Names of the joint's unknowns, in order (for messages and outputs)."""
        return UNKNOWNS[:self.n_unknowns]

    def body_dofs(self, structure: Structure) -> np.ndarray:
        """The six global dofs of the body node."""
        return structure.node_dofs(self.body)

    def reference_point(self, structure: Structure) -> np.ndarray:
        """The sliding point in the reference configuration."""
        return structure.node_position(self.body) + self.offset

    def initial_unknowns(self, structure: Structure, q: np.ndarray) -> np.ndarray:
        """``xi`` from projecting the sliding point on the line, multipliers 0."""
        point = self.reference_point(structure) + q[self.body_dofs(structure)[:3]]
        if isinstance(self.line, BeamChain):
            xi = self.line.project(point, q)
        else:
            xi = self.line.project(point)
        if self.kind == "spline":
            self._check_frame(xi)
        return np.concatenate([[xi], np.zeros(self.n_unknowns - 1)])

    def _check_frame(self, xi: float) -> None:
        """The spline slider's constraint is linearised about the line's frame: the slider
        frame must match it at the starting ``xi`` (within 0.1 rad)."""
        R0 = (self.line.rotation(xi).R0 if isinstance(self.line, BeamChain)
              else self.line.at(xi).R)
        angle = np.arccos(np.clip((np.trace(self.frame @ R0.T) - 1) / 2, -1.0, 1.0))
        if angle > 0.1:
            raise ValueError(f"{self.name}: a spline slider's frame must match the line's frame "
                             f"at xi = {xi:.6g} (columns {np.round(R0, 6).tolist()}); it is "
                             f"turned {angle:.3g} rad from it")

    def _line(self, xi: float, q: np.ndarray) -> _LineState:
        """The line's geometry, interpolation and load transfer at ``xi``."""
        if isinstance(self.line, BeamChain):
            interp = self.line.interpolation(xi)
            x, l, l_xi = interp.geometry(q)  # noqa: E741
            dofs, G, dG = self.line.transfer(xi, self.smearing, self.kernel)
            rotation = (self.line.rotation(xi) if self.kind != "spherical"
                        and self.orientation == "section" else None)
            tangent, tangent_xi = interp.tangent(q)
            return _LineState(x, l, l_xi, np.zeros(3), interp.dofs, interp.N, interp.dN,
                              interp.d2N, dofs, G, dG, rotation, None, tangent, tangent_xi,
                              interp.tangent_dofs, interp.T, interp.T_xi)
        p = self.line.at(xi)
        none = np.zeros(0, dtype=int)
        return _LineState(p.x, p.l, p.l_xi, p.l_xixi, none.reshape(0, 3), np.zeros(0),
                          np.zeros(0), np.zeros(0), none, np.zeros((0, 6)), np.zeros((0, 6)),
                          None, p, p.l, p.l_xi, none.reshape(0, 3), np.zeros(0), np.zeros(0))

    def assemble(self, structure: Structure, q: np.ndarray, y: np.ndarray):
        """Residual and Jacobian of the joint on the structure dofs it touches.

        Returns
        -------
        dofs : (t,) global dofs touched
        r_q : (t,) contribution to the structure residual on them
        r_y : (n_unknowns,) the joint's own equations
        J : (t + n_unknowns, t + n_unknowns) derivative of ``[r_q; r_y]`` in ``[q_t; y]``
        """
        xi, lam = float(y[0]), y[1:4]
        if self.end_stops:
            xi = min(max(xi, 0.0), self.line.length)
        line = self._line(xi, q)
        body = self.body_dofs(structure)
        rotation_dofs = (line.rotation.dofs.ravel() if line.rotation is not None
                         else np.zeros(0, dtype=int))
        dofs, where = np.unique(np.concatenate([body, line.interp_dofs.ravel(),
                                                line.load_dofs, rotation_dofs,
                                                line.tangent_dofs.ravel()]),
                                return_inverse=True)
        t = len(dofs)
        at = _Layout(t, where, line.interp_dofs.size, len(line.load_dofs), rotation_dofs.size)
        r = np.zeros(t + self.n_unknowns)
        J = np.zeros((len(r), len(r)))
        theta = q[body[3:]]
        f_b = cross(theta, self.offset)
        x_b = self.reference_point(structure) + q[body[:3]] + f_b
        # body force and moment (eq. 3)
        r[at.body] += lam
        r[at.turn] += cross(self.offset + f_b, lam)
        J[at.body, at.lam] += np.eye(3)
        J[np.ix_(at.turn, at.turn)] += skew_matrices(lam) @ skew_matrices(self.offset)
        J[at.turn, at.lam] += skew_matrices(self.offset + f_b)
        # the force on the line (Sec. 4, eq. T6)
        G, dG = line.G[:, :3], line.dG[:, :3]
        np.add.at(r, at.load, -G @ lam)
        J[at.load, at.xi] -= dG @ lam
        J[at.load, at.lam] -= G
        # xi equation (eq. 3, on the recovered tangent) and position constraint (eq. 1)
        r[at.xi] = -line.tangent @ lam
        J[at.xi, at.xi] = -line.tangent_xi @ lam
        J[at.xi, at.lam] = -line.tangent
        for c in range(len(line.T)):
            J[at.xi, at.tangent[c]] -= line.T[c] * lam
        r[at.lam] = x_b - line.x
        J[at.lam, at.body] += np.eye(3)
        J[at.lam, at.turn] -= skew_matrices(self.offset)
        J[at.lam, at.xi] = -line.l
        for a in range(len(line.N)):
            J[at.lam, at.interp[a]] -= line.N[a] * np.eye(3)
        if self.kind == "spherical":
            pass
        elif self.orientation == "slope":
            self._slope_orientation(q, y, theta, line, at, r, J)
        else:
            self._section_orientation(q, y, theta, line, at, r, J)
        if self.end_stops:
            self._end_stop(float(y[0]), lam, line, at, r, J)
        return dofs, r[:t], r[t:], J

    def _end_stop(self, xi: float, lam: np.ndarray, line: _LineState, at: _Layout,
                  r: np.ndarray, J: np.ndarray) -> None:
        """Replace the ``xi`` equation by ``xi = end`` beyond an end, or at an end where the
        stop pushes: the force on the body, ``-lambda``, points back into the line
        (``l . lambda > 0`` at the far end, ``< 0`` at the start).  At the end itself the
        derivatives in ``xi`` are the one-sided ones of the line."""
        length = self.line.length
        for end, sign in ((0.0, -1.0), (length, 1.0)):
            beyond = sign * (xi - end) > 0
            pushing = abs(xi - end) <= 1e-12 * length and sign * (line.l @ lam) > 0
            if beyond or pushing:
                r[at.xi] = xi - end
                J[at.xi] = 0.0
                J[at.xi, at.xi] = 1.0

    def _slope_orientation(self, q, y, theta, line, at, r, J) -> None:
        """Classical slider on the line's gradient, ``e_bj . l = 0`` (paper eq. 4), its couple
        ``m = sum mu_j e_bj x l`` carried by the test functions to the rotation dofs."""
        mu = y[4:]
        axes = self.frame[:, 1:3]
        e_b = axes + cross(theta, axes.T).T
        l, l_xi, G = line.l, line.l_xi, line.G[:, 3:]  # noqa: E741
        m = cross(e_b.T, l).T @ mu
        r[at.turn] += m
        np.add.at(r, at.load, -G @ m)
        J[at.load, at.xi] -= line.dG[:, 3:] @ m
        for j in range(2):
            e, e0, row = e_b[:, j], axes[:, j], at.t + 4 + j
            dm_dtheta = mu[j] * skew_matrices(l) @ skew_matrices(e0)
            dm_dxi = mu[j] * cross(e, l_xi)
            dm_dmu = cross(e, l)
            J[np.ix_(at.turn, at.turn)] += dm_dtheta
            J[at.turn, at.xi] += dm_dxi
            J[at.turn, row] += dm_dmu
            J[np.ix_(at.load, at.turn)] -= G @ dm_dtheta
            J[at.load, at.xi] -= G @ dm_dxi
            J[at.load, row] -= G @ dm_dmu
            r[at.xi] += mu[j] * e @ l_xi
            J[at.xi, at.turn] += mu[j] * cross(e0, l_xi)
            J[at.xi, at.xi] += mu[j] * e @ line.l_xixi
            J[at.xi, row] += e @ l_xi
            r[row] = e @ l
            J[row, at.turn] += cross(e0, l)
            J[row, at.xi] += e @ l_xi
            for a in range(len(line.N)):
                dm_du = mu[j] * skew_matrices(e) * line.dN[a]
                J[np.ix_(at.turn, at.interp[a])] += dm_du
                J[np.ix_(at.load, at.interp[a])] -= G @ dm_du
                J[at.xi, at.interp[a]] += mu[j] * line.d2N[a] * e
                J[row, at.interp[a]] += line.dN[a] * e

    def _section_orientation(self, q, y, theta, line, at, r, J) -> None:
        """Orientation constraints on the line's section frame, linear in the rotations.

        ``g_j = g0_j(xi) + n_j(xi) . (theta_b - theta_L)``: classical (``j = 2, 3``)
        ``g0 = e_j . t0``, ``n = e_j x t0``; spline (``j = 1``) ``g0 = t0 . ax(F R0^T)``,
        ``n = t0`` -- eqs. (4), (5) and Sec. 4 linearised, with ``R0 = [t0, ...]`` the line's
        reference frame and ``F`` the slider frame.  The virtual work of ``sum mu_j g_j``
        gives the couple ``m = sum mu_j n_j`` on the body, ``-w_a m`` on the two line nodes
        that carry ``theta_L`` and the ``xi`` row.  The constraint reads ``theta_L`` plus
        ``kink C m``: the exact rotation at a couple lies off the linear interpolation of its
        nodal values by that much (``docs/sliders.md``).
        """
        mu = y[4:]
        if line.rotation is None:
            p = line.point
            R0, k0, k0_xi = p.R, p.k, p.k_xi
            theta_L = theta_L_xi = np.zeros(3)
            w = w_xi = np.zeros(0)
            kink = kink_xi = 0.0
            compliance = np.zeros((3, 3))
        else:
            rot = line.rotation
            R0, k0, k0_xi = rot.R0, rot.k0, rot.k0_xi
            nodal = q[rot.dofs]
            w, w_xi = rot.w, rot.w_xi
            theta_L, theta_L_xi = w @ nodal, w_xi @ nodal
            kink, kink_xi, compliance = rot.kink, rot.kink_xi, rot.compliance
        t0 = R0[:, 0]
        t1 = cross(k0, t0)
        t2 = cross(k0_xi, t0) + cross(k0, t1)
        axes = self.frame[:, 1:3].T
        n = [cross(axes, t0), cross(axes, t1), cross(axes, t2)]
        g = [axes @ t0, axes @ t1, axes @ t2]
        if self.kind == "spline":
            B = self.frame @ R0.T
            dB = -B @ skew_matrices(k0)
            ddB = -dB @ skew_matrices(k0) - B @ skew_matrices(k0_xi)
            a0, a1, a2 = axial(B), axial(dB), axial(ddB)
            n = [np.vstack([n[0], t0]), np.vstack([n[1], t1]), np.vstack([n[2], t2])]
            g = [np.append(g[0], t0 @ a0), np.append(g[1], t1 @ a0 + t0 @ a1),
                 np.append(g[2], t2 @ a0 + 2 * t1 @ a1 + t0 @ a2)]
        n0, n1, n2 = n
        d = theta - theta_L
        m, m_xi = n0.T @ mu, n1.T @ mu
        shift = kink * compliance @ m
        rows = at.t + 4 + np.arange(len(mu))
        r[at.turn] += m
        J[at.turn, at.xi] += m_xi
        J[np.ix_(at.turn, rows)] += n0.T
        along = g[1] + n1 @ d - n0 @ theta_L_xi
        r[at.xi] += mu @ along
        J[at.xi, at.turn] += m_xi
        J[at.xi, at.xi] += mu @ (g[2] + n2 @ d - 2 * n1 @ theta_L_xi)
        J[at.xi, rows] += along
        r[rows] = g[0] + n0 @ (d - shift)
        J[np.ix_(rows, at.turn)] += n0
        J[rows, at.xi] += (along - n1 @ shift
                           - n0 @ (compliance @ (kink_xi * m + kink * m_xi)))
        J[np.ix_(rows, rows)] -= kink * n0 @ compliance @ n0.T
        for a in range(len(w)):
            node = at.rotation[a]
            r[node] -= w[a] * m
            J[node, at.xi] -= w_xi[a] * m + w[a] * m_xi
            J[np.ix_(node, rows)] -= w[a] * n0.T
            J[at.xi, node] -= w[a] * m_xi + w_xi[a] * m
            J[np.ix_(rows, node)] -= w[a] * n0


@dataclass(frozen=True)
class _LineState:
    """What the joint needs of the line at ``xi``: geometry, the interpolation (chains), the
    load transfer, the section rotation (chains) or the rigid line's point, and the tangent
    of the frictionless condition with its dofs and coefficients (chains: the recovered
    tangent, :meth:`sliders.chain.BeamChain._tangent_recovery`; rigid lines: ``l``)."""

    x: np.ndarray
    l: np.ndarray  # noqa: E741
    l_xi: np.ndarray
    l_xixi: np.ndarray
    interp_dofs: np.ndarray
    N: np.ndarray
    dN: np.ndarray
    d2N: np.ndarray
    load_dofs: np.ndarray
    G: np.ndarray
    dG: np.ndarray
    rotation: LineRotation | None
    point: LinePoint | None
    tangent: np.ndarray
    tangent_xi: np.ndarray
    tangent_dofs: np.ndarray
    T: np.ndarray
    T_xi: np.ndarray


class _Layout:
    """Positions in the joint's local arrays: body translations and rotations, the line's
    interpolation, load, rotation and tangent dofs, then ``xi``, ``lambda`` and the
    multipliers."""

    def __init__(self, t: int, where: np.ndarray, n_interp: int, n_load: int,
                 n_rotation: int) -> None:
        self.t, self.body, self.turn = t, where[:3], where[3:6]
        self.interp = where[6:6 + n_interp].reshape(-1, 3)
        start = 6 + n_interp + n_load
        self.load = where[6 + n_interp:start]
        self.rotation = where[start:start + n_rotation].reshape(-1, 3)
        self.tangent = where[start + n_rotation:].reshape(-1, 3)
        self.xi, self.lam = t, slice(t + 1, t + 4)
