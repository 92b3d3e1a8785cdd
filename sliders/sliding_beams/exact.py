"""Closed-form tip stiffness of the sliding-beams setup (paper Sec. 6, Figures 3-5).

Cylinder C on ``[0, L]`` along x, clamped at 0; piston P on ``[s, s + L]``, its axial
translation and spin held at its bottom.  Slider A: P's bottom end slides on C (at ``x = s``);
slider B: C's top end slides on P (at ``x = L``, ``L - s`` from P's bottom).  A transverse
force ``F`` at P's tip.  Both beams are Timoshenko beams with bending stiffness ``EJ`` and
shear stiffness ``GA``; the answer is exact within linear theory (``docs/sliders.md``):

* forces: each slider passes a transverse force, ``R_A`` onto P's bottom (``-R_A`` onto C at
  ``s``) and ``R_B`` onto C's top (``-R_B`` onto P at ``L - s``);
* classical sliders also pass couples ``M_A``, ``M_B`` the same way, and hold the body's
  rotation to the other beam's *section rotation* at the contact (``orientation="section"``,
  continuous there) or to its *slope* (``"slope"``, the constraint ``e_b2 . l = 0``); a
  concentrated force makes a Timoshenko beam's slope jump by ``R / GA``, and the slope
  constraint takes the mean of the two sides, the limit of a vanishing symmetric smearing;
* C is a cantilever; P is a cantilever clamped at its bottom plus a rigid motion ``a + b y``.

Six linear equations (P's force and moment balance, two contact displacements, two contact
rotations, or ``M_A = M_B = 0`` for spherical sliders) give the reactions and P's motion.
"""

from __future__ import annotations

import numpy as np

Load = tuple[str, float, float]  # ("force" | "couple", station, magnitude)


def cantilever(
    loads: list[Load], y: float, length: float, EJ: float, GA: float, side: str = "mean"
) -> np.ndarray:
    """Deflection ``v``, rotation ``theta`` and slope ``v'`` at ``y`` of a Timoshenko
    cantilever on ``[0, length]`` clamped at 0 under point forces and couples (superposition).

    Under a force the slope jumps by ``Q / GA``; there ``side`` picks the ``left`` or
    ``right`` limit or their ``mean``, except at the ends, where only one side exists (a force
    at the clamp does not load the beam; a force at the free end shears it up to the end).
    """
    v = theta = slope = 0.0
    for kind, eta, Q in loads:
        below = y < eta
        if kind == "force":
            if y <= eta:
                dv, dt = y**2 * (3 * eta - y) / (6 * EJ) + y / GA, (2 * eta * y - y**2) / (2 * EJ)
            else:
                dv, dt = eta**2 * (3 * y - eta) / (6 * EJ) + eta / GA, eta**2 / (2 * EJ)
            if y == eta:
                share = {"left": 1.0, "right": 0.0, "mean": 0.5}[side]
                gamma = 0.0 if eta == 0 else (1.0 / GA if eta == length else share / GA)
            else:
                gamma = 1.0 / GA if below else 0.0
        else:
            dv = y**2 / (2 * EJ) if y <= eta else eta * (2 * y - eta) / (2 * EJ)
            dt, gamma = min(y, eta) / EJ, 0.0
        v, theta, slope = v + Q * dv, theta + Q * dt, slope + Q * (dt + gamma)
    return np.array([v, theta, slope])


def sliding_beams(
    s: float,
    L: float,
    EJ: float,
    GA: float,
    kind: str,
    F: float = 1.0,
    orientation: str = "section",
    slope_side: str = "mean",
) -> dict[str, float]:
    """Reactions, tip deflection and normalised tip stiffness ``k L^3 / EJ`` at offset ``s``.

    ``kind``: ``spherical`` or ``classical``.  ``s`` in ``[0, L)``.  ``orientation``: what a
    classical slider holds the body's rotation to, the other beam's ``section`` rotation or
    its ``slope``; ``slope_side``: which slope where a force makes it jump (see
    :func:`cantilever`).
    """
    if kind not in ("spherical", "classical"):
        raise ValueError(f"kind must be 'spherical' or 'classical', got {kind!r}")
    if orientation not in ("section", "slope"):
        raise ValueError(f"orientation must be 'section' or 'slope', got {orientation!r}")
    read = 1 if orientation == "section" else 2
    if not 0 <= s < L:
        raise ValueError(f"the piston offset s = {s} must lie in [0, L = {L})")

    def residual(u: np.ndarray) -> np.ndarray:
        Ra, Rb, Ma, Mb, a, b = u
        C = [("force", s, -Ra), ("couple", s, -Ma), ("force", L, Rb), ("couple", L, Mb)]
        P = [("force", L - s, -Rb), ("couple", L - s, -Mb), ("force", L, F)]
        at_A = cantilever(C, s, L, EJ, GA, slope_side)
        vC_L, thetaC_L, _ = cantilever(C, L, L, EJ, GA)
        at_B = cantilever(P, L - s, L, EJ, GA, slope_side)
        equations = [
            Ra - Rb + F,
            Ma - Mb - Rb * (L - s) + F * L,
            a - at_A[0],
            a + b * (L - s) + at_B[0] - vC_L,
        ]
        if kind == "classical":
            equations += [b - at_A[read], thetaC_L - (b + at_B[read])]
        else:
            equations += [Ma, Mb]
        return np.array(equations)

    r0 = residual(np.zeros(6))
    A = np.column_stack([residual(e) - r0 for e in np.eye(6)])
    Ra, Rb, Ma, Mb, a, b = np.linalg.solve(A, -r0)
    tip = (
        a
        + b * L
        + cantilever(
            [("force", L - s, -Rb), ("couple", L - s, -Mb), ("force", L, F)], L, L, EJ, GA
        )[0]
    )
    return {"R_A": Ra, "R_B": Rb, "M_A": Ma, "M_B": Mb, "tip": tip, "k_norm": F / tip * L**3 / EJ}
