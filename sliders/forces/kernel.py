"""Force elements evaluated compiled (numba): residual and Jacobian on their slots.

:func:`evaluate_element` is what the compiled Newton step calls for every element of
:mod:`sliders.forces.elements` at every iteration: from the slots' displacements ``q`` and
velocities ``v`` (both (6,)), it writes the residual ``r = -force`` (6,) and the Jacobian
``J = dr/dq + c_v dr/dv`` (6, 6), both times ``scale`` (the time integrator's scaling of the
step's force equations).  The equations:

``AXIAL`` (slots: node ``a``'s, then node ``b``'s translations)
    ``d = x_b - x_a``, ``l = |d|``, ``n = d / l``, stroke ``S = extended - l`` and its rate
    ``S' = -n . (v_b - v_a)``; the law ``F(S, S')`` pushes ``b`` by ``F n`` and ``a`` by
    ``-F n``.  With ``P = (I - n n) / l`` (``dn/dd``): ``d(F n)/dd = F P - n (F_S n +
    F_S' P (v_b - v_a))`` and ``d(F n)/d(v_b - v_a) = -F_S' n n``.
``TYRE`` (slots: the axle's translations, the wheel's rotations)
    deflection ``d = R0 - (x - g) . N`` and ``d' = -v . N``, the radial force ``F_z(d, d')``
    along ``N`` (:func:`sliders.forces.compiled_laws.tyre_radial`); the axle's forward speed
    ``u = v . e`` and the spin ``omega = w . a`` (``a = N x e``), the longitudinal force
    ``F_x(u, omega, F_z)`` along ``e`` (:func:`~sliders.forces.compiled_laws.tyre_longitudinal`);
    the wheel takes the moment ``-R0 F_x a``.

The Python reference is :func:`reference` (numpy, the same equations written with the laws of
:mod:`sliders.forces.laws`); ``tests/test_force_elements.py`` holds the two equal to roundoff
and the Jacobians to central differences.
"""

from __future__ import annotations

import numba
import numpy as np

from fvbeam.kernel_cache import guard
from sliders.forces import laws
from sliders.forces.compiled_laws import strut, tyre_longitudinal, tyre_radial
from sliders.forces.elements import AXIAL, TYRE

guard(__file__)  # numba's cache of these kernels, consistent with their sources


@numba.njit(cache=True, inline="never")
def evaluate_element(
    kind: int,
    p: np.ndarray,
    q: np.ndarray,
    v: np.ndarray,
    c_v: float,
    scale: float,
    r: np.ndarray,
    J: np.ndarray,
) -> None:
    """One element's ``r`` (6,) and ``J`` (6, 6), overwritten (module docstring); ``p``: its
    packed constants (:meth:`sliders.forces.elements.ForceElement.packed`)."""
    r[:] = 0.0
    J[:, :] = 0.0
    if kind == AXIAL:
        d, w = np.empty(3), np.empty(3)
        for c in range(3):
            d[c] = p[3 + c] + q[3 + c] - p[c] - q[c]
            w[c] = v[3 + c] - v[c]
        length = np.sqrt(d[0] ** 2 + d[1] ** 2 + d[2] ** 2)
        n = d / length
        rate = -(n[0] * w[0] + n[1] * w[1] + n[2] * w[2])
        force, f_s, f_rate = strut(p[7:], p[6] - length, rate)
        P = (np.eye(3) - np.outer(n, n)) / length
        Pw = P @ w
        D = force * P - np.outer(n, f_s * n + f_rate * Pw) - c_v * f_rate * np.outer(n, n)
        for i in range(3):
            r[i] = scale * force * n[i]
            r[3 + i] = -scale * force * n[i]
            for j in range(3):
                J[i, j] = -scale * D[i, j]
                J[i, 3 + j] = scale * D[i, j]
                J[3 + i, j] = scale * D[i, j]
                J[3 + i, 3 + j] = -scale * D[i, j]
    elif kind == TYRE:
        x0, g, N, e, a, law = p[0:3], p[3:6], p[6:9], p[9:12], p[12:15], p[15:]
        radius = law[0]
        height = 0.0
        sink = 0.0
        forward = 0.0
        spin = 0.0
        for c in range(3):
            height += (x0[c] + q[c] - g[c]) * N[c]
            sink -= v[c] * N[c]
            forward += v[c] * e[c]
            spin += v[3 + c] * a[c]
        f_z, fz_d, fz_rate = tyre_radial(law, radius - height, sink)
        f_x, fx_u, fx_w, fx_n = tyre_longitudinal(law, forward, spin, f_z)
        gz, gx = np.zeros(6), np.zeros(6)
        for c in range(3):
            gz[c] = -(fz_d + c_v * fz_rate) * N[c]
            gx[c] = fx_n * gz[c] + c_v * fx_u * e[c]
            gx[3 + c] = c_v * fx_w * a[c]
        for i in range(3):
            r[i] = -scale * (f_z * N[i] + f_x * e[i])
            r[3 + i] = scale * radius * f_x * a[i]
            for j in range(6):
                J[i, j] = -scale * (N[i] * gz[j] + e[i] * gx[j])
                J[3 + i, j] = scale * radius * a[i] * gx[j]


def reference(
    kind: int, p: np.ndarray, q: np.ndarray, v: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The element's residual ``r`` (6,) and its derivatives ``dr/dq``, ``dr/dv`` (6, 6), in
    numpy with the laws of :mod:`sliders.forces.laws` (unscaled): the equations of the
    module docstring as written, for the tests."""
    if kind == AXIAL:
        strut_law = laws.Strut(
            area=p[7],
            pressure=p[8],
            volume=p[9],
            exponent=p[10],
            ambient=p[11],
            compression=p[12],
            rebound=p[13],
            stop_stiffness=p[14],
            stroke_min=p[15],
            stroke_max=p[16],
        )
        d = (p[3:6] + q[3:6]) - (p[0:3] + q[0:3])
        w = v[3:6] - v[0:3]
        length = np.linalg.norm(d)
        n = d / length
        force, f_s, f_rate = (float(x) for x in strut_law(p[6] - length, -n @ w))
        P = (np.eye(3) - np.outer(n, n)) / length
        D_d = force * P - np.outer(n, f_s * n + f_rate * P @ w)
        D_w = -f_rate * np.outer(n, n)
        sign = np.array([[-1.0, 1.0], [1.0, -1.0]])  # rows a, b; columns a, b
        return (
            np.concatenate([force * n, -force * n]),
            np.kron(sign, D_d),
            np.kron(sign, D_w),
        )
    x0, g, N, e, a, law = p[0:3], p[3:6], p[6:9], p[9:12], p[12:15], p[15:]
    radius, k, c, B, C, D, eps = law
    deflection = radius - (x0 + q[:3] - g) @ N
    f_z, fz_d, fz_rate = (
        float(x) for x in laws.tyre_radial(deflection, -v[:3] @ N, stiffness=k, damping=c)
    )
    f_x, fx_u, fx_w, fx_n = (
        float(x)
        for x in laws.tyre_longitudinal(
            v[:3] @ e, v[3:] @ a, f_z, radius=radius, B=B, C=C, D=D, speed_eps=eps
        )
    )
    zero = np.zeros(3)
    dz_q = np.concatenate([-fz_d * N, zero])
    dz_v = np.concatenate([-fz_rate * N, zero])
    dx_q = fx_n * dz_q
    dx_v = fx_n * dz_v + np.concatenate([fx_u * e, fx_w * a])
    r = np.concatenate([-(f_z * N + f_x * e), radius * f_x * a])

    def rows(dz: np.ndarray, dx: np.ndarray) -> np.ndarray:
        return np.vstack([-(np.outer(N, dz) + np.outer(e, dx)), radius * np.outer(a, dx)])

    return r, rows(dz_q, dx_q), rows(dz_v, dx_v)
