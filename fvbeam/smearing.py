"""Smearing kernels: a point load at ``xi`` spread over ``[xi - smearing, xi + smearing]``.

``smearing`` is the kernel's half-width, a length; 0 is an exact point load (the Dirac
delta).  Two kernels ``K(r)`` of the offset ``r = s - xi`` (``docs/theory.md``, eq. T6):

* ``box``: uniform density ``1 / (2 smearing)``.  The share of each fv region then varies
  linearly with ``xi`` near an evaluation point, as in the reference implementation's ramps.
* ``hat``: triangle ``(1 - |r| / smearing) / smearing``; the shares vary with a
  continuous derivative, which Newton prefers.

Near a beam end the kernel is cut at the end and rescaled so the whole load stays on the beam.
The kernel is integrated against the test functions by one scikit-fem ``LinearForm``
(:meth:`fvbeam.beam.Beam.kernel_transfer`); its derivative in ``xi`` (the chain's
``dG/dxi``) by the same form with :func:`slope` as the density, plus point evaluations at
the kernel's :func:`steps`.
"""

from __future__ import annotations

import numpy as np

KERNELS = ("box", "hat")
#: Gauss points per piece of a kernel's support, between the element ends, the evaluation
#: points and the kernel's break points: exact for the kernel (degree <= 1) times a test
#: function (degree <= 2).  The form (:meth:`fvbeam.beam.Beam.kernel_transfer`) and its
#: compiled copy (:meth:`sliders.lines.batched.ChainStack.transfer`) both use it.
KERNEL_GAUSS_POINTS = 3


def check_smearing(smearing: float, kernel: str) -> float:
    """``smearing`` as a float, or ``ValueError`` naming a negative or non-finite smearing or
    an unknown kernel."""
    smearing = float(smearing)
    if not np.isfinite(smearing) or smearing < 0:
        raise ValueError(f"smearing must be a finite length >= 0, got {smearing}")
    if kernel not in KERNELS:
        raise ValueError(f"unknown smearing kernel {kernel!r}; choose one of {', '.join(KERNELS)}")
    return smearing


def density(r: np.ndarray, smearing: float, kernel: str) -> np.ndarray:
    """Kernel value ``K(r)`` at offsets ``r = s - xi`` (integrates to 1 over
    [-smearing, smearing], ``smearing > 0``)."""
    r = np.asarray(r, dtype=float)
    inside = np.abs(r) < smearing
    if kernel == "box":
        return inside / (2 * smearing)
    return inside * (1 - np.abs(r) / smearing) / smearing


def slope(r: np.ndarray, smearing: float, kernel: str) -> np.ndarray:
    """``dK/dr`` at offsets ``r`` away from the kernel's :func:`steps`: 0 for the box,
    ``-sign(r) / smearing^2`` inside the hat."""
    r = np.asarray(r, dtype=float)
    if kernel == "box":
        return np.zeros_like(r)
    return -np.sign(r) * (np.abs(r) < smearing) / smearing**2


def steps(smearing: float, kernel: str) -> tuple[np.ndarray, np.ndarray]:
    """Offsets ``r`` where the kernel jumps and the jumps ``K(r+) - K(r-)``: the Dirac part
    of ``dK/dr`` (box: ``+-1 / (2 smearing)`` at ``-+smearing``; the hat is continuous)."""
    if kernel == "box":
        return np.array([-smearing, smearing]), np.array([1.0, -1.0]) / (2 * smearing)
    return np.zeros(0), np.zeros(0)


def kernel_breaks(xi: float, smearing: float) -> np.ndarray:
    """Points where the kernel is not smooth."""
    return np.array([xi - smearing, xi, xi + smearing])
