"""Slider joints: a node of the structure slides on a line (paper Secs. 3-4).

The body is a node of the structure (a beam node, six dofs ``u_b, theta_b``, linear kinematics
like the beams) carrying the sliding point at ``offset`` and the slider axes ``frame``
(columns ``e1, e2, e3``; ``e1`` along the line).  The line is a :class:`BeamChain` or a rigid
line.  Unknowns of the joint ``y = [xi, lambda (3), mu_2, mu_3]`` (``mu`` for the classical
slider only).  With ``x_b = X_b + offset + u_b + theta_b x offset``,
``e_bj = e_j + theta_b x e_j`` and ``W = [lambda; m]``, ``m = sum_j mu_j e_bj x l``:

=====================  ==================================================  =============
equation               residual                                            paper
=====================  ==================================================  =============
body force             ``+ lambda``                                         eq. 3
body moment            ``+ f_b x lambda + m``, ``f_b = theta_b x offset``   eqs. 3, 4
line beams             ``- G(xi) W`` (test functions, smeared; eq. T6)      Sec. 4
xi                     ``- l . lambda + sum_j mu_j e_bj . l_/xi``           eqs. 3, 4
position               ``x_b - x(xi)``                                      eq. 1
classical              ``e_b2 . l``, ``e_b3 . l``                           Sec. 3.2
=====================  ==================================================  =============

The classical couple ``m`` enters the line beams through the rotation rows of the test
functions, as a couple, not through ``d l / d q`` as a force dipole on the slope
(``docs/sliders.md`` explains why: on shear-deformable beams the dipole form loses the
couple under mesh refinement); the constraint itself stays on ``l``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from fvbeam.geometry import skew_matrices, vector3
from fvbeam.statics import Structure
from sliders.chain import BeamChain
from sliders.lines import RigidLine

KINDS = ("spherical", "classical")


@dataclass
class Slider:
    """A structure node sliding on a line.

    Parameters
    ----------
    kind
        ``spherical`` or ``classical``.
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
        Spread of the reaction along the line (:mod:`fvbeam.smearing`).
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
    name: str = "slider"

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"{self.name}: kind must be one of {', '.join(KINDS)}, "
                             f"got {self.kind!r}")
        self.offset = vector3(self.offset, f"{self.name}: offset")
        frame = np.asarray(self.frame, dtype=float)
        if frame.shape != (3, 3) or not np.allclose(frame.T @ frame, np.eye(3), atol=1e-12):
            raise ValueError(f"{self.name}: frame must be an orthonormal 3x3 matrix")
        self.frame = frame

    @property
    def n_unknowns(self) -> int:
        """``xi``, ``lambda`` and, for the classical slider, ``mu_2, mu_3``."""
        return 4 if self.kind == "spherical" else 6

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
        return np.concatenate([[xi], np.zeros(self.n_unknowns - 1)])

    def _line(self, xi: float, q: np.ndarray):
        """Line geometry, interpolation dofs and coefficients, and load transfer at ``xi``."""
        if isinstance(self.line, BeamChain):
            interp = self.line.interpolation(xi)
            x, l, l_xi = interp.geometry(q)  # noqa: E741
            dofs, G, dG = self.line.transfer(xi, self.smearing, self.kernel)
            return (x, l, l_xi, np.zeros(3), interp.dofs, interp.N, interp.dN, interp.d2N,
                    dofs, G, dG)
        p = self.line.at(xi)
        none = np.zeros(0, dtype=int)
        return (p.x, p.l, p.l_xi, p.l_xixi, none.reshape(0, 3), np.zeros(0), np.zeros(0),
                np.zeros(0), none, np.zeros((0, 6)), np.zeros((0, 6)))

    def assemble(self, structure: Structure, q: np.ndarray, y: np.ndarray):
        """Residual and Jacobian of the joint on the structure dofs it touches.

        Returns
        -------
        dofs : (t,) global dofs touched
        r_q : (t,) contribution to the structure residual on them
        r_y : (n_unknowns,) the joint's own equations
        J : (t + n_unknowns, t + n_unknowns) derivative of ``[r_q; r_y]`` in ``[q_t; y]``
        """
        xi, lam, mu = float(y[0]), y[1:4], y[4:]
        (x, l, l_xi, l_xixi, interp_dofs, N, dN, d2N,  # noqa: E741
         load_dofs, G, dG) = self._line(xi, q)
        body = self.body_dofs(structure)
        dofs, where = np.unique(np.concatenate([body, interp_dofs.ravel(), load_dofs]),
                                return_inverse=True)
        t = len(dofs)
        ib, it_ = where[:3], where[3:6]
        iu = where[6:6 + interp_dofs.size].reshape(-1, 3)
        ig = where[6 + interp_dofs.size:]
        n = t + self.n_unknowns
        r = np.zeros(n)
        J = np.zeros((n, n))
        k_xi, k_lam, k_pos = t, slice(t + 1, t + 4), slice(t + 1, t + 4)  # rows = cols
        theta = q[body[3:]]
        f_b = np.cross(theta, self.offset)
        x_b = self.reference_point(structure) + q[body[:3]] + f_b
        axes = self.frame[:, 1:1 + len(mu)]
        e_b = axes + np.cross(theta, axes.T).T
        m = np.cross(e_b.T, l).T @ mu if len(mu) else np.zeros(3)
        W = np.concatenate([lam, m])
        # body force and moment
        r[ib] += lam
        r[it_] += np.cross(self.offset + f_b, lam) + m
        J[ib, k_lam] += np.eye(3)
        J[np.ix_(it_, it_)] += skew_matrices(lam) @ skew_matrices(self.offset)
        J[it_, k_lam] += skew_matrices(self.offset + f_b)
        # line reaction
        np.add.at(r, ig, -G @ W)
        J[ig, k_xi] -= dG @ W
        J[np.ix_(ig, np.arange(k_lam.start, k_lam.stop))] -= G[:, :3]
        # xi equation and position constraint
        r[k_xi] = -l @ lam
        J[k_xi, k_xi] = -l_xi @ lam
        J[k_xi, k_lam] = -l
        r[k_pos] = x_b - x
        J[k_pos, ib] += np.eye(3)
        J[np.ix_(np.arange(k_pos.start, k_pos.stop), it_)] -= skew_matrices(self.offset)
        J[k_pos, k_xi] = -l
        for a in range(len(N)):
            J[np.ix_(np.arange(k_pos.start, k_pos.stop), iu[a])] -= N[a] * np.eye(3)
            J[k_xi, iu[a]] -= dN[a] * lam
        # classical: couple and rotation constraints
        for j in range(len(mu)):
            e, e0, row = e_b[:, j], axes[:, j], t + 4 + j
            dm_dtheta = mu[j] * skew_matrices(l) @ skew_matrices(e0)
            dm_dxi = mu[j] * np.cross(e, l_xi)
            dm_dmu = np.cross(e, l)
            J[np.ix_(it_, it_)] += dm_dtheta
            J[it_, k_xi] += dm_dxi
            J[it_, row] += dm_dmu
            J[np.ix_(ig, it_)] -= G[:, 3:] @ dm_dtheta
            J[ig, k_xi] -= G[:, 3:] @ dm_dxi
            J[ig, row] -= G[:, 3:] @ dm_dmu
            r[k_xi] += mu[j] * e @ l_xi
            J[k_xi, it_] += mu[j] * np.cross(e0, l_xi)
            J[k_xi, k_xi] += mu[j] * e @ l_xixi
            J[k_xi, row] += e @ l_xi
            r[row] = e @ l
            J[row, it_] += np.cross(e0, l)
            J[row, k_xi] += e @ l_xi
            for a in range(len(N)):
                dm_du = mu[j] * skew_matrices(e) * dN[a]
                J[np.ix_(it_, iu[a])] += dm_du
                J[np.ix_(ig, iu[a])] -= G[:, 3:] @ dm_du
                J[k_xi, iu[a]] += mu[j] * d2N[a] * e
                J[row, iu[a]] += dN[a] * e
        return dofs, r[:t], r[t:], J
