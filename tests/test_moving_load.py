"""A force crossing a simply supported beam: closed form, mesh and step convergence.

Sources of the asserted numbers (``docs/dynamics.md``, "Moving load"):

* **Closed form.** :func:`fvbeam.closed_forms.moving_load_simply_supported` is Fryba's modal series
  (1999, Ch. 1) extended to a Timoshenko beam without rotary inertia.  Its checks:

  - *Fryba's Euler-Bernoulli series* as printed, ``v0 sum 1/(j^2 (j^2 - alpha^2)) [sin(j w t)
    - alpha / j sin(w_j t)] sin(j pi x / L)``, ``v0 = 2 F L^3 / (pi^4 EJ)``, kept to ``N``
    terms: its tail is at most ``sum_{j>N} 2 F / (L kappa_j (1 - r_j)) <= 2 F L^3 /
    (3 pi^4 EJ N^3 (1 - r_{N+1}))`` (``|sin| <= 1``), and the function's own truncation is
    bounded by :func:`moving_load_truncation`; the two bounds are the tolerance.
  - *Quasi-static limit.* ``w(x, a / c) - w_static(x, a) = sum (2 F / L) sin(k a) sin(k x)
    [1 / D_j - 1 / kappa_j] - sum (2 F / L) r_j sin(omega_j t) sin(k x) / D_j`` with
    ``D_j = kappa_j (1 - r_j^2)``; both brackets are at most ``r_1 / (kappa_j (1 - r_1))``
    (``r_j <= r_1``) and ``sum 2 / (L kappa_j) = L^3 / (45 EJ) + L / (3 GA)``
    (``sum j^-4 = pi^4 / 90``, ``sum j^-2 = pi^2 / 6``), so ``|w - w_static| <= r_1 / (1 - r_1)
    F (L^3 / (45 EJ) + L / (3 GA))`` plus the truncation bound.  ``GA = 10`` makes the shear
    deflection larger than the bending one, so a wrong shear term cannot pass.
  - *Truncation bound*: ``|w_N - w_ref| <= bound(N) + bound(N_ref)`` (triangle inequality)
    for a few ``N``, ``N_ref = 30000`` terms in the reference.
  - *After the crossing* (``t > L / c``) each mode vibrates freely from its state at
    ``L / c``: :func:`moving_load_modes` is checked against ``q(T) cos(omega s) + q'(T) /
    omega sin(omega s)`` built from its own crossing branch at ``T`` (continuity of deflection
    and velocity, and the free oscillator), at and off resonance, to roundoff: ``16 eps``
    times the largest phase ``omega t`` in play times the mode's amplitude bound
    ``(2 F / L)(1 + r_j) / |D_j|``.  The deflection after the crossing is the plain modal
    sum (the string part vanishes at ``a = L``), to roundoff.
  - *Convergence in the number of modes.*  Against 2000 (Euler-Bernoulli) or 20000 terms, the
    max-norm error of ``N = 10, 20, 40, 80`` terms over a grid of ``x`` and ``t``: the terms
    decay like ``j^-p`` (``p = 4`` for the remainder during the crossing, ``p = 5`` for the
    free vibration after it, Euler-Bernoulli: ``r_j / D_j ~ j^-1 j^-4``; ``p = 2`` with shear,
    ``r_j -> c / c_s``, ``D_j ~ GA k_j^2``), so the error decays like a tail sum, ``N^(1-p)``
    when the terms add up coherently, and at most like the first omitted term, ``N^-p``:
    observed orders within ``[p - 1, p]`` widened by the order tolerance.
  - *Symmetry* of the static closed form: Maxwell-Betti reciprocity ``w(x; a) = w(a; x)``
    and the mirror ``w(L - x; L - a) = w(x; a)``, to roundoff (``1e-14`` of the values).

* **Mesh, past the crossing.** The same for galerkin-p2 over ``0 <= t <= 1.5 L / c`` (the
  crossing and the free vibration after it), on the same meshes: order 3, the
  free vibration's error being that of the P2 modes (order 4) excited by the crossing.

* **Mesh.** The exact semi-discrete solution (:func:`studies.moving_load.semi_discrete`: no
  time-stepping error) against the closed form, relative max-norm error of the mid-span
  deflection over the crossing, ``n = 16, 32, 64``.  Expected orders: fv3 **2** (its
  frequencies and static deflections converge at order 2, ``docs/dynamics.md``); galerkin-p2
  **3**: the P2 eigenvalues converge at order 4, but by reciprocity the mid-span deflection
  under the load at ``xi`` is the P2 solution for a load at mid-span *evaluated at xi*, a point
  inside an element, where a piecewise-quadratic approximation of the piecewise-cubic static
  deflection errs at ``O(h^3)``; cubic **2**: its static deflections are exact wherever the
  load is (nodally exact, ``docs/theory.md`` Sec. 9), so only its dynamics err, and its
  frequencies converge as ``A h^4 + B (EJ / (GA L^2)) h^2`` (``tests/test_cubic.py``), the
  shear term ruling from about 30 elements at this section's ``1e-5``.  Observed orders (both
  doublings) within ``0.5`` of these (measured for cubic: 2.36 and 2.06, at errors of
  ``3.0e-5`` to ``1.4e-6``, below galerkin-p2's ``8.7e-5`` to ``1.2e-5``).
  The section is slender (``EJ / (GA L^2) = 1e-5``, module docstring of
  :mod:`studies.moving_load`, which says why).

* **Step.** Generalized-alpha (second order for every ``rho_inf``, Chung and Hulbert 1993)
  against the exact semi-discrete solution of the *same* mesh, so only the time error is
  measured, for ``rho_inf`` in ``{1, 0.8, 0.5}``, ``400, 800, 1600`` steps across the crossing,
  on two-element meshes.  Their highest loaded frequency ``omega_max`` is 137 rad/s (fv3),
  172 rad/s (galerkin-p2) and 201 rad/s (cubic, consistent mass); the accumulated phase
  error of that mode, ``omega_max^3 h^2 T / 12``, is 0.17 rad at 800 steps for fv3 and
  ``(201 / 137)^3`` times that, 0.54 rad, for cubic: small enough for the doublings to lie
  in the asymptotic range (measured for cubic: 1.99 to 2.00).  Observed orders within
  ``0.5`` of 2.

* **Loadings.**  The ``slider`` loading (a massless body driven along the beam by a
  spherical slider) is the ``point_load`` one: at a prescribed abscissa the slider's
  equations are linear in the dofs (linear kinematics) and transfer the force through the
  same test functions (eq. T6), so the two histories differ only by what the slider's Newton
  loop leaves, below its tolerance (``Dynamics.tol``, relative to the deflection).
"""

from __future__ import annotations

import numpy as np
import pytest

from fvbeam.closed_forms import (
    moving_load_modes,
    moving_load_simply_supported,
    moving_load_truncation,
    simply_supported_point_load,
)
from studies import moving_load as ml

ORDER_TOLERANCE = 0.5


def observed_orders(errors: list[float]) -> np.ndarray:
    e = np.asarray(errors)
    return np.log2(e[:-1] / e[1:])


# -- the closed form ------------------------------------------------------------------------
def test_euler_bernoulli_limit_is_frybas_series():
    L, EJ, m, F = 2.0, 3.0, 1.5, 0.7
    critical = np.pi / L * np.sqrt(EJ / m)
    alpha = 0.6
    c = alpha * critical
    x, t = np.meshgrid([0.3 * L, 0.5 * L, 0.9 * L], np.linspace(0, L / c, 7))
    N = 200
    j = np.arange(1, N + 1)[:, None, None]
    omega = np.pi * c / L
    omega_j = j**2 * np.pi**2 / L**2 * np.sqrt(EJ / m)
    v0 = 2 * F * L**3 / (np.pi**4 * EJ)
    fryba = v0 * np.sum(
        (np.sin(j * omega * t) - alpha / j * np.sin(omega_j * t))
        * np.sin(j * np.pi * x / L)
        / (j**2 * (j**2 - alpha**2)),
        axis=0,
    )
    r = alpha / (N + 1)
    tail = 2 * F * L**3 / (3 * np.pi**4 * EJ * N**3 * (1 - r))
    w = moving_load_simply_supported(x, t, L, EJ, np.inf, m, F, c, n_modes=N)
    bound = tail + moving_load_truncation(N, L, EJ, np.inf, m, F, c)
    assert np.abs(w - fryba).max() <= bound
    assert np.abs(w).max() > 1e3 * bound


@pytest.mark.parametrize("a", [0.1, 0.35, 0.5, 0.8, 1.3])
def test_quasi_static_limit(a):
    L, EJ, GA, m, F = 1.0, 1.0, 10.0, 1.0, 1.0
    c = 1e-4 * np.pi / L * np.sqrt(EJ / m)
    x = np.linspace(0, L, 11)
    w = moving_load_simply_supported(x, a / c, L, EJ, GA, m, F, c)
    static = simply_supported_point_load(x, min(a, L), L, EJ, GA, F)  # 0 once it left
    kappa_1 = 1 / (L**4 / (np.pi**4 * EJ) + L**2 / (np.pi**2 * GA))
    r1 = np.pi / L * c * np.sqrt(m / kappa_1)
    rtol = 1e-8  # the default truncation, relative to the static mid-span deflection
    after = 2.0 if a > L else 1.0  # the free vibration's terms: twice the bound (docstring)
    bound = after * r1 / (1 - r1) * F * (L**3 / (45 * EJ) + L / (3 * GA)) + rtol * F * (
        L**3 / (48 * EJ) + L / (4 * GA)
    )
    assert np.abs(w - static).max() <= bound
    midspan = simply_supported_point_load(L / 2, L / 2, L, EJ, GA, F)
    assert midspan > 1e3 * bound  # the bound is tight enough to catch a wrong term
    if a < L:
        shear = F * np.minimum(x, a) * (L - np.maximum(x, a)) / (GA * L)
        assert shear.max() > 1e3 * bound  # the shear part is resolved


EPS = np.finfo(float).eps
#: Moving-load cases of the post-crossing checks: (GA, alpha) with ``L = 1, EJ = 1e4,
#: m = 10, F = 100`` (the work-precision problem); alpha = 1 puts mode 1 at resonance.
POST_CROSSING = [(np.inf, 0.5), (1e7, 0.5), (np.inf, 1.0), (1e5, 0.9)]


def _case(GA: float, alpha: float) -> tuple[float, float, float, float, float, float]:
    L, EJ, m, F = 1.0, 1e4, 10.0, 100.0
    return L, EJ, GA, m, F, alpha * np.pi / L * np.sqrt(EJ / m)


@pytest.mark.parametrize("GA, alpha", POST_CROSSING)
def test_free_vibration_continues_the_crossing(GA, alpha):
    L, EJ, GA, m, F, c = _case(GA, alpha)
    T = L / c
    j = np.arange(1, 41, dtype=float)
    k = j * np.pi / L
    kappa = 1 / (1 / (EJ * k**4) + 1 / (GA * k**2))
    omega, r = np.sqrt(kappa / m), k * c / np.sqrt(kappa / m)
    q_T, v_T = moving_load_modes(j, T, L, EJ, GA, m, F, c)
    s = np.linspace(0, 0.5 * T, 97)[1:, None]
    q, v = moving_load_modes(j, T + s[:, 0], L, EJ, GA, m, F, c)
    free_q = q_T * np.cos(omega * s) + v_T / omega * np.sin(omega * s)
    free_v = v_T * np.cos(omega * s) - omega * q_T * np.sin(omega * s)
    amplitude = np.where(
        np.abs(1 - r) < 1e-8,
        F / (L * kappa) * (1 + omega * 1.5 * T),  # the resonant mode's growth, t <= 1.5 T
        2 * F / L * (1 + r) / np.abs(kappa - m * (k * c) ** 2),
    )
    tol = 16 * EPS * (1 + omega * 1.5 * T) * amplitude
    assert np.all(np.abs(q - free_q) <= tol)
    assert np.all(np.abs(v - free_v) <= omega * tol)
    assert np.abs(q).max() > 1e6 * tol.max()  # the modes are excited


@pytest.mark.parametrize("GA, alpha", POST_CROSSING)
def test_deflection_after_crossing_is_the_modal_sum(GA, alpha):
    L, EJ, GA, m, F, c = _case(GA, alpha)
    T, N = L / c, 60
    x, t = np.linspace(0, L, 9)[:, None], np.linspace(T, 1.5 * T, 31)[None, :]
    j = np.arange(1, N + 1, dtype=float)
    q, _ = moving_load_modes(j, t[0], L, EJ, GA, m, F, c)
    modal = np.sin(np.multiply.outer(x[:, 0], j * np.pi / L)) @ q.T
    w = moving_load_simply_supported(x, t, L, EJ, GA, m, F, c, n_modes=N)
    assert np.abs(w - modal).max() <= 1e-12 * np.abs(modal).max()


@pytest.mark.parametrize(
    "GA, window, p, n_ref",
    [(np.inf, "crossing", 4, 2000), (np.inf, "after", 5, 2000), (1e6, "after", 2, 20000)],
)
def test_series_converges_at_its_rate(GA, window, p, n_ref):
    L, EJ, GA, m, F, c = _case(GA, 0.5)
    T = L / c
    times = np.linspace(0, T, 61) if window == "crossing" else np.linspace(T, 1.5 * T, 61)
    x, t = np.linspace(0, L, 11)[:, None], times[None, :]
    reference = moving_load_simply_supported(x, t, L, EJ, GA, m, F, c, n_modes=n_ref)
    errors = [
        np.abs(moving_load_simply_supported(x, t, L, EJ, GA, m, F, c, n_modes=N) - reference).max()
        for N in (10, 20, 40, 80)
    ]
    orders = observed_orders(errors)
    assert np.all(orders >= p - 1 - ORDER_TOLERANCE) and np.all(orders <= p + ORDER_TOLERANCE)
    assert errors[-1] <= moving_load_truncation(80, L, EJ, GA, m, F, c)


@pytest.mark.parametrize("N", [3, 30, 300])
def test_truncation_bound(N):
    L, EJ, GA, m, F = 1.0, 1.0, 1e3, 1.0, 1.0
    c = 0.5 * np.pi / L * np.sqrt(EJ / m)
    x, t = np.meshgrid(np.linspace(0, L, 9), np.linspace(0, L / c, 9))
    N_ref = 30_000
    reference = moving_load_simply_supported(x, t, L, EJ, GA, m, F, c, n_modes=N_ref)
    w = moving_load_simply_supported(x, t, L, EJ, GA, m, F, c, n_modes=N)
    bound = moving_load_truncation(N, L, EJ, GA, m, F, c)
    assert np.abs(w - reference).max() <= bound + moving_load_truncation(N_ref, L, EJ, GA, m, F, c)
    assert moving_load_truncation(N_ref, L, EJ, GA, m, F, c) < 0.1 * bound


def test_static_symmetry():
    L, EJ, GA, F = 1.3, 2.0, 5.0, 1.1
    x, a = np.meshgrid(np.linspace(0, L, 13), np.linspace(0, L, 13))
    w = simply_supported_point_load(x, a, L, EJ, GA, F)
    scale = np.abs(w).max()
    assert np.abs(w - simply_supported_point_load(a, x, L, EJ, GA, F)).max() <= 1e-14 * scale
    assert (
        np.abs(w - simply_supported_point_load(L - x, L - a, L, EJ, GA, F)).max() <= 1e-14 * scale
    )


def test_bad_input_is_named():
    with pytest.raises(ValueError, match="t >= 0"):
        moving_load_simply_supported(0.5, -1.0, c=1.0)
    with pytest.raises(ValueError, match="mode numbers"):
        moving_load_modes(0.5, 1.0)
    with pytest.raises(ValueError, match="GA > m c"):
        moving_load_simply_supported(0.5, 0.1, GA=1.0, c=2.0)


# -- the discrete model ---------------------------------------------------------------------
@pytest.mark.parametrize("formulation, order", [("fv3", 2), ("galerkin-p2", 3), ("cubic", 2)])
def test_mesh_convergence(formulation, order):
    t = np.linspace(0, ml.CROSSING, 401)
    exact = ml.exact_midspan(t)
    errors = [
        ml.relative_error(ml.semi_discrete(ml.model(formulation, n), t), exact)
        for n in (16, 32, 64)
    ]
    assert np.all(np.abs(observed_orders(errors) - order) <= ORDER_TOLERANCE), errors


def test_mesh_convergence_past_the_crossing():
    t = np.linspace(0, 1.5 * ml.CROSSING, 601)
    exact = ml.exact_midspan(t)
    errors = [
        ml.relative_error(ml.semi_discrete(ml.model("galerkin-p2", n), t), exact)
        for n in (16, 32, 64)
    ]
    assert np.all(np.abs(observed_orders(errors) - 3) <= ORDER_TOLERANCE), errors


@pytest.mark.parametrize("formulation", ["fv3", "galerkin-p2", "cubic"])
@pytest.mark.parametrize("rho_inf", [1.0, 0.8, 0.5])
def test_step_convergence(formulation, rho_inf):
    m = ml.model(formulation, 2)
    errors = []
    for steps in (400, 800, 1600):
        t, w = ml.simulate(m, steps, rho_inf)
        errors.append(ml.relative_error(w, ml.semi_discrete(m, t)))
    assert np.all(np.abs(observed_orders(errors) - 2) <= ORDER_TOLERANCE), errors


@pytest.mark.parametrize("formulation", ["fv3", "galerkin-p2", "cubic"])
def test_slider_loading_is_the_point_load(formulation):
    t_end = 1.5 * ml.CROSSING  # the crossing and the free vibration after it
    _, point = ml.simulate(ml.model(formulation, 4), 100, 0.8, t_end, "point_load")
    m = ml.model(formulation, 4)
    _, slider = ml.simulate(m, 100, 0.8, t_end, "slider")
    assert np.abs(slider - point).max() <= m.dynamics(0.8).tol * np.abs(point).max()
    assert np.abs(point).max() > 0


def test_benchmark_row_reports_time_and_error_split():
    """Shape of the moving-load benchmark (speed is never asserted): the error against the
    closed form is at most its spatial plus its time part (triangle inequality)."""
    from studies.bench_dynamics import moving_load_bench

    result = moving_load_bench(formulations=("galerkin-p2",), repeats=1, steps=100, progress=False)
    (row,) = result["rows"]
    assert not result["interrupted"] and row["steps"] == 100
    assert 0 < row["seconds_per_step"]["min"] <= row["seconds_per_step"]["median"]
    assert row["rel_error"] <= (row["rel_error_space"] + row["rel_error_time"]) * (1 + 1e-12)
