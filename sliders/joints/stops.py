"""A slider's end stops, stated once: where the ``xi`` equation becomes ``xi = end``.

Beyond an end of its line, or at an end where the stop pushes (the reaction on the body,
``-lambda``, points back into the line: ``l . lambda > 0`` at the far end, ``< 0`` at the
start), a slider with end stops holds its abscissa at that end: its ``xi`` equation is
replaced by ``xi - end = 0`` (unit derivative in ``xi``).  ``xi`` within ``1e-12`` of the
length of an end is at that end (:func:`fvbeam.geometry.locate_abscissa`).  The compiled
joint (:func:`sliders.joints.packed.evaluate_joint`) and the batched one
(:meth:`sliders.joints.slider.SliderBatch.evaluate`) both call :func:`end_stop`.
"""

from __future__ import annotations

import numba
import numpy as np

from fvbeam.kernel_cache import guard

guard(__file__)  # numba's cache of these kernels, consistent with their sources


@numba.njit(cache=True, inline="never")
def end_stop(xi: float, along: float, length: float) -> tuple[bool, float]:
    """Whether the stop holds ``xi`` on a line of ``length``, and the residual ``xi - end``
    that replaces the ``xi`` equation then (0.0 otherwise); ``along = l . lambda``."""
    for side in range(2):
        end, sign = (0.0, -1.0) if side == 0 else (length, 1.0)
        beyond = sign * (xi - end) > 0
        pushing = abs(xi - end) <= 1e-12 * length and sign * along > 0
        if beyond or pushing:
            return True, xi - end
    return False, 0.0


@numba.njit(cache=True)
def end_stops(
    xi: np.ndarray, along: np.ndarray, length: float, hit: np.ndarray, residual: np.ndarray
) -> None:
    """:func:`end_stop` of ``B`` members into ``hit`` and ``residual`` (B,)."""
    for b in range(len(xi)):
        hit[b], residual[b] = end_stop(xi[b], along[b], length)
