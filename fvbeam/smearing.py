"""Smearing kernels: a point load at ``xi`` spread over ``[xi - smearing, xi + smearing]``.

``smearing`` is the kernel's half-width, a length; 0 is an exact point load.  Two kernels:

* ``box``: uniform density ``1 / (2 smearing)``.  The share of each fv region then varies
  linearly with ``xi`` near an evaluation point, as in the reference implementation's ramps.
* ``hat``: triangle ``(1 - |s - xi| / smearing) / smearing``; the shares vary with a
  continuous derivative, which Newton prefers.

Near a beam end the kernel is cut at the end and rescaled so the whole load stays on the beam.
"""

from __future__ import annotations

import numpy as np

KERNELS = ("box", "hat")


def check_smearing(smearing: float, kernel: str) -> float:
    smearing = float(smearing)
    if not np.isfinite(smearing) or smearing < 0:
        raise ValueError(f"smearing must be a finite length >= 0, got {smearing}")
    if kernel not in KERNELS:
        raise ValueError(f"unknown smearing kernel {kernel!r}; choose one of {', '.join(KERNELS)}")
    return smearing


def density(r: np.ndarray, smearing: float, kernel: str) -> np.ndarray:
    """Kernel value at offsets ``r = s - xi`` (integrates to 1 over [-smearing, smearing])."""
    inside = np.abs(r) < smearing
    if kernel == "box":
        return inside / (2 * smearing)
    return inside * (1 - np.abs(r) / smearing) / smearing


def kernel_breaks(xi: float, smearing: float) -> np.ndarray:
    """Points where the kernel is not smooth."""
    return np.array([xi - smearing, xi, xi + smearing])
