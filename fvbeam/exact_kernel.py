"""The geometrically exact beam's law at its evaluation points, compiled (numba).

The compiled twins of :class:`fvbeam.exact_beam.ExactBeam`'s numpy statement, which is the
law as the module docstring of :mod:`fvbeam.exact_beam` writes it: :func:`points` of
``ExactBeam.points`` (kinematics and stress at every point), and for the finite-volume
beams :func:`fv_residual`, :func:`fv_floor` and :func:`fv_blocks` of ``residual``,
``residual_floor`` and ``_fv_blocks`` (the region balances, their round-off bound and their
tangent blocks; :func:`fv_position_blocks` the last's block on the positions), with the
rotation tools of :mod:`fvbeam.rotations` they need at one point (:func:`exp_at`,
:func:`log_at`, :func:`update`, the coefficients of the tangent operators with the same
series below :data:`fvbeam.rotations.SERIES`).  ``tests/test_exact_kernel.py`` holds each
equal to its numpy statement to round-off at random finite rotations; the numpy statement is
for reading and testing, the solver runs these (``ExactBeam(beam, compiled=False)`` runs the
statement).

One point's work is a few hundred flops on 3x3 and 6x6 blocks: written as loops over them,
without temporaries from numpy's broadcasting, it takes about a microsecond, where the
statement's vectorised calls take a few microseconds each whatever the number of points.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from fvbeam.kernel_cache import guard
from fvbeam.rotations import SERIES

guard(__file__)  # numba's cache of these kernels, consistent with their sources


@numba.njit(cache=True, error_model="numpy")
def coefficients_at(t: float) -> tuple[float, float, float, float, float]:
    """``a, b, c, a'/t, b'/t`` at the angle ``t`` (:func:`fvbeam.rotations._coefficients`)."""
    t2 = t * t
    if t < SERIES:
        a = 0.5 - t2 / 24 + t2 * t2 / 720
        b = 1 / 6 - t2 / 120 + t2 * t2 / 5040
        c = 1 / 12 + t2 / 720 + t2 * t2 / 30240
        da = -1 / 12 + t2 / 180 - t2 * t2 / 6720
        db = -1 / 60 + t2 / 1260 - t2 * t2 / 60480
        return a, b, c, da, db
    sin, cos = math.sin(t), math.cos(t)
    a = (1 - cos) / t2
    b = (t - sin) / (t2 * t)
    c = (1 - t * sin / (2 * (1 - cos))) / t2
    da = (t * sin - 2 * (1 - cos)) / (t2 * t2)
    db = ((1 - cos) * t - 3 * (t - sin)) / (t2 * t2 * t)
    return a, b, c, da, db


@numba.njit(cache=True, error_model="numpy")
def skew_at(v: np.ndarray) -> np.ndarray:
    """The matrix of ``v x`` (3, 3)."""
    out = np.zeros((3, 3))
    out[0, 1], out[0, 2] = -v[2], v[1]
    out[1, 0], out[1, 2] = v[2], -v[0]
    out[2, 0], out[2, 1] = -v[1], v[0]
    return out


@numba.njit(cache=True, error_model="numpy")
def mm(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """``A @ B`` of small matrices (either may be a transposed view), as loops."""
    n, k, m = A.shape[0], A.shape[1], B.shape[1]
    out = np.zeros((n, m))
    for i in range(n):
        for j in range(k):
            aij = A[i, j]
            if aij != 0.0:
                for c in range(m):
                    out[i, c] += aij * B[j, c]
    return out


@numba.njit(cache=True, error_model="numpy")
def series_matrix(psi: np.ndarray, first: float, second: float) -> np.ndarray:
    """``I + first S + second S^2`` (3, 3) with ``S = skew(psi)``,
    ``S^2 = psi psi^T - |psi|^2 I``: ``exp``, ``J`` and ``J^-1`` of ``psi``."""
    t2 = psi[0] * psi[0] + psi[1] * psi[1] + psi[2] * psi[2]
    out = np.empty((3, 3))
    for i in range(3):
        for j in range(3):
            out[i, j] = second * psi[i] * psi[j]
        out[i, i] += 1.0 - second * t2
    out[0, 1] -= first * psi[2]
    out[0, 2] += first * psi[1]
    out[1, 0] += first * psi[2]
    out[1, 2] -= first * psi[0]
    out[2, 0] -= first * psi[1]
    out[2, 1] += first * psi[0]
    return out


@numba.njit(cache=True, error_model="numpy")
def exp_at(psi: np.ndarray) -> np.ndarray:
    """``exp(skew(psi))`` (Rodrigues, ``sin t / t = 1 - t^2 b``, ``(1 - cos t) / t^2 = a``):
    :func:`fvbeam.rotations.exp_map` at one rotation vector."""
    t = math.sqrt(psi[0] * psi[0] + psi[1] * psi[1] + psi[2] * psi[2])
    a, b, _, _, _ = coefficients_at(t)
    return series_matrix(psi, 1 - t * t * b, a)


@numba.njit(cache=True, error_model="numpy")
def log_at(R: np.ndarray) -> np.ndarray:
    """The principal rotation vector of ``R`` (:func:`fvbeam.rotations.log_map` at one
    rotation): the unit quaternion of ``R`` by its largest component (Shepperd's choice,
    which loses no digits near a half turn), then ``2 atan2(|v|, w) v / |v|`` with ``w >= 0``."""
    tr = R[0, 0] + R[1, 1] + R[2, 2]
    q = np.zeros(4)  # (x, y, z, w)
    if tr >= R[0, 0] and tr >= R[1, 1] and tr >= R[2, 2]:
        q[3] = 1 + tr
        q[0], q[1], q[2] = R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]
    else:
        i = 0 if R[0, 0] >= R[1, 1] and R[0, 0] >= R[2, 2] else (1 if R[1, 1] >= R[2, 2] else 2)
        j, k = (i + 1) % 3, (i + 2) % 3
        q[i] = 1 - tr + 2 * R[i, i]
        q[j] = R[j, i] + R[i, j]
        q[k] = R[k, i] + R[i, k]
        q[3] = R[k, j] - R[j, k]
    if q[3] < 0:
        q = -q
    norm = math.sqrt(q[0] ** 2 + q[1] ** 2 + q[2] ** 2 + q[3] ** 2)
    v = math.sqrt(q[0] ** 2 + q[1] ** 2 + q[2] ** 2) / norm
    w = q[3] / norm
    angle = 2 * math.atan2(v, w)
    # angle / v -> 2 / w (its series below 1e-4: the next term, v^2 / 3, is below eps there)
    scale = angle / v if v > 1e-4 else 2 / w * (1 + v * v / (3 * w * w))
    return q[:3] / norm * scale


@numba.njit(cache=True, error_model="numpy")
def update(R: np.ndarray, dphi: np.ndarray) -> np.ndarray:
    """Rotations ``R`` (n, 3, 3) turned by the spatial increments ``dphi`` (n, 3),
    ``exp(skew(dphi)) R``: :func:`fvbeam.rotations.update`."""
    out = np.empty_like(R)
    for a in range(R.shape[0]):
        out[a] = mm(exp_at(dphi[a]), R[a])
    return out


@numba.njit(cache=True, error_model="numpy")
def points(x: np.ndarray, R: np.ndarray, geometry: tuple) -> tuple[np.ndarray, ...]:
    """``ExactBeam.points``: ``psi_a, psi, psi', Lambda, x, x', [nu; kappa], F, M`` at each
    point (shapes of :class:`fvbeam.exact_beam.PointState`), for the node positions ``x``
    and rotations ``R`` and the beam's ``geometry`` (``ExactBeam.geometry``)."""
    nodes, reference, N, dN, dx0, C, _ = geometry
    P, npe = nodes.shape
    psi_nodes = np.zeros((P, npe, 3))
    psi = np.zeros((P, 3))
    dpsi = np.zeros((P, 3))
    Lam = np.zeros((P, 3, 3))
    xp = np.zeros((P, 3))
    dxp = np.zeros((P, 3))
    strain = np.zeros((P, 6))
    force = np.zeros((P, 3))
    moment = np.zeros((P, 3))
    for p in range(P):
        Rr = R[nodes[p, reference]]
        for a in range(npe):
            if a != reference:
                psi_nodes[p, a] = log_at(mm(Rr.T, R[nodes[p, a]]))
            psi[p] += N[p, a] * psi_nodes[p, a]
            dpsi[p] += dN[p, a] * psi_nodes[p, a]
            xp[p] += N[p, a] * x[nodes[p, a]]
            dxp[p] += dN[p, a] * x[nodes[p, a]]
        Lam[p] = mm(Rr, exp_at(psi[p]))
        t = math.sqrt(psi[p, 0] ** 2 + psi[p, 1] ** 2 + psi[p, 2] ** 2)
        a_, b_, _, _, _ = coefficients_at(t)
        J = series_matrix(psi[p], a_, b_)
        for i in range(3):
            for j in range(3):
                strain[p, i] += Lam[p, j, i] * dxp[p, j]
                strain[p, 3 + i] += J[j, i] * dpsi[p, j]
            strain[p, i] -= dx0[p, i]
        stress = np.zeros(6)
        for i in range(6):
            for j in range(6):
                stress[i] += C[p, i, j] * strain[p, j]
        for i in range(3):
            for j in range(3):
                force[p, i] += Lam[p, i, j] * stress[j]
                moment[p, i] += Lam[p, i, j] * stress[3 + j]
    return psi_nodes, psi, dpsi, Lam, xp, dxp, strain, force, moment


@numba.njit(cache=True, error_model="numpy")
def fv_residual(x: np.ndarray, geometry: tuple, state: tuple, n_dofs: int) -> np.ndarray:
    """``ExactBeam.residual`` of an fv beam: ``sum_p jump_a(p) [F; M + (x_p - x_a) x F]``,
    ``state`` the points' (``PointState.arrays``)."""
    nodes, jump = geometry[0], geometry[6]
    xp, force, moment = state[4], state[7], state[8]
    r = np.zeros(n_dofs)
    P, npe = nodes.shape
    for p in range(P):
        F = force[p]
        for a in range(npe):
            d = 6 * nodes[p, a]
            arm = xp[p] - x[nodes[p, a]]
            lever = np.cross(arm, F)
            for i in range(3):
                r[d + i] += jump[p, a] * F[i]
                r[d + 3 + i] += jump[p, a] * (moment[p, i] + lever[i])
    return r


@numba.njit(cache=True, error_model="numpy")
def fv_floor(x: np.ndarray, geometry: tuple, state: tuple, n_dofs: int) -> np.ndarray:
    """``ExactBeam.residual_floor`` of an fv beam (its docstring states the bound)."""
    nodes, _, _, dN, dx0, C, jump = geometry
    psi_nodes, _, _, _, xp, dxp, strain, force, moment = state
    out = np.zeros(n_dofs)
    P, npe = nodes.shape
    for p in range(P):
        e_nu = np.linalg.norm(dxp[p]) + np.linalg.norm(dx0[p])
        e_kappa = np.linalg.norm(strain[p, 3:])
        for a in range(npe):
            e_nu += abs(dN[p, a]) * np.linalg.norm(x[nodes[p, a]])
            e_kappa += abs(dN[p, a]) * (1 + np.linalg.norm(psi_nodes[p, a]))
        d_stress = np.zeros(6)
        for i in range(6):
            for j in range(6):
                d_stress[i] += abs(C[p, i, j]) * (e_nu if j < 3 else e_kappa)
        F = np.linalg.norm(force[p]) + np.linalg.norm(d_stress[:3])
        M = np.linalg.norm(moment[p]) + np.linalg.norm(d_stress[3:])
        for a in range(npe):
            d = 6 * nodes[p, a]
            arm = np.linalg.norm(xp[p] - x[nodes[p, a]])
            weight = abs(jump[p, a])
            for i in range(3):
                out[d + i] += weight * F
                out[d + 3 + i] += weight * (M + arm * F)
    return out


@numba.njit(cache=True, error_model="numpy")
def fv_position_blocks(geometry: tuple, state: tuple) -> np.ndarray:
    """The force balances' block on the positions of :func:`fv_blocks` (P, 3 npe, 3 npe):
    at fixed rotations ``dF = Lambda C_nn Lambda^T dx'`` (``d theta`` and ``d kappa`` vanish),
    so node ``a``'s row and node ``b``'s column hold ``jump_a N_b' Lambda C_nn Lambda^T``,
    ``C_nn`` the section's force-strain block in global axes."""
    nodes, _, _, dN, _, C, jump = geometry
    Lam = state[3]
    P, npe = nodes.shape
    blocks = np.zeros((P, 3 * npe, 3 * npe))
    for p in range(P):
        stiffness = mm(mm(Lam[p], C[p, :3, :3]), Lam[p].T)
        for a in range(npe):
            for b in range(npe):
                weight = jump[p, a] * dN[p, b]
                for i in range(3):
                    for j in range(3):
                        blocks[p, 3 * a + i, 3 * b + j] = weight * stiffness[i, j]
    return blocks


@numba.njit(cache=True, error_model="numpy")
def fv_blocks(x: np.ndarray, R: np.ndarray, geometry: tuple, state: tuple) -> np.ndarray:
    """``ExactBeam._fv_blocks``: each point's tangent block of the region balances
    (P, 6 npe, 6 npe), from the variations of ``ExactBeam._variations``."""
    nodes, reference, N, dN, _, C, jump = geometry
    psi_nodes, psi, dpsi, Lam, xp, dxp, _, force, moment = state
    P, npe = nodes.shape
    m = 6 * npe
    r = reference
    blocks = np.zeros((P, m, m))
    for p in range(P):
        Rr = R[nodes[p, r]]
        # d psi and d psi' (3, m): sum of N_a, N_a' times J(psi_a)^-1 R_r^T (dphi_a - dphi_r)
        d_psi = np.zeros((3, m))
        d_dpsi = np.zeros((3, m))
        for a in range(npe):
            if a == r:
                continue
            t = np.linalg.norm(psi_nodes[p, a])
            _, _, c, _, _ = coefficients_at(t)
            block = mm(series_matrix(psi_nodes[p, a], -0.5, c), Rr.T)
            for i in range(3):
                for j in range(3):
                    for col, sign in ((6 * a + 3 + j, 1.0), (6 * r + 3 + j, -1.0)):
                        d_psi[i, col] += sign * N[p, a] * block[i, j]
                        d_dpsi[i, col] += sign * dN[p, a] * block[i, j]
        t = np.linalg.norm(psi[p])
        a_, b_, _, da, db = coefficients_at(t)
        S = skew_at(psi[p])
        W = skew_at(dpsi[p])
        J = series_matrix(psi[p], a_, b_)
        dot = psi[p, 0] * dpsi[p, 0] + psi[p, 1] * dpsi[p, 1] + psi[p, 2] * dpsi[p, 2]
        dJ = a_ * W + b_ * (mm(W, S) + mm(S, W)) + dot * da * S + dot * db * mm(S, S)
        d_theta = mm(Rr, mm(J, d_psi))
        d_theta_s = mm(Rr, mm(dJ, d_psi) + mm(J, d_dpsi))
        d_x = np.zeros((3, m))
        d_xs = np.zeros((3, m))
        for i in range(3):
            d_theta[i, 6 * r + 3 + i] += 1.0
            for a in range(npe):
                d_x[i, 6 * a + i] = N[p, a]
                d_xs[i, 6 * a + i] = dN[p, a]
        d_strain = np.zeros((6, m))
        d_strain[:3] = mm(Lam[p].T, d_xs + mm(skew_at(dxp[p]), d_theta))
        d_strain[3:] = mm(Lam[p].T, d_theta_s)
        d_stress = mm(C[p], d_strain)
        F_hat = skew_at(force[p])
        dF = -mm(F_hat, d_theta) + mm(Lam[p], d_stress[:3])
        dM = -mm(skew_at(moment[p]), d_theta) + mm(Lam[p], d_stress[3:])
        F_dx = mm(F_hat, d_x)
        for a in range(npe):
            arm_dF = mm(skew_at(xp[p] - x[nodes[p, a]]), dF)
            s = jump[p, a]
            for i in range(3):
                for c in range(m):
                    blocks[p, 6 * a + i, c] = s * dF[i, c]
                    blocks[p, 6 * a + 3 + i, c] = s * (dM[i, c] + arm_dF[i, c] - F_dx[i, c])
                # - F x d_arm: d_arm = d_x - I on node a's displacement
                for j in range(3):
                    blocks[p, 6 * a + 3 + i, 6 * a + j] += s * F_hat[i, j]
    return blocks
