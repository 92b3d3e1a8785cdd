"""The arithmetic the laws' statements are written with, beyond ``+ - * / **`` and
comparisons: numpy here (:data:`NUMPY`); the generators (:mod:`sliders.joints.generate`,
:mod:`sliders.forces.generate`) pass sympy's in its place to differentiate and print them.

A branch is ``where(condition, a, b)`` with a strict inequality (the derivative at a kink is
that of the branch it selects), ``both`` the logical and of two conditions.
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

NUMPY = SimpleNamespace(
    where=np.where,
    both=np.logical_and,
    abs=np.abs,
    sqrt=np.sqrt,
    exp=np.exp,
    tanh=np.tanh,
    atan=np.arctan,
    sin=np.sin,
)
