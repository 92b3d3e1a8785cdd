"""A force law given by the user: a function with its partial derivatives, checked once.

``UserLaw("spring", f, df, points=..., scales=...)`` wraps ``f(*states) -> value`` and
``df(*states) -> (df/dstate_1, ...)`` (numpy, elementwise over the states) as a law of
:mod:`sliders.forces.laws`: calling it returns the value followed by its partials.  On
construction every partial is compared with central differences
(:func:`sliders.forces.differences.central_difference`, its derived tolerance) at each of the
given points; a mismatch is refused with a ``ValueError`` naming the law, the state and the
point.  The points should lie where the law is smooth (away from its kinks): where it is not,
the differences cannot check it, and the error says so.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from sliders.forces.differences import central_difference
from sliders.forces.laws import Law, state

#: The stencil's largest offset as a fraction of a state's scale.
STEP = 1e-2


@dataclass(frozen=True)
class UserLaw:
    """A user's force law with its derivative, checked against central differences once.

    Parameters
    ----------
    name : str
        The law's name, quoted by every error.
    function : callable
        ``function(*states) -> value``, elementwise over the states (numpy arrays).
    derivative : callable
        ``derivative(*states) -> (partial_1, ..., partial_n)``, one partial per state.
    points : array_like
        ``(m, n)``: ``m`` states at which to check, ``n`` values each (one row per point).
    scales : array_like
        ``(n,)``, ``> 0``: the size over which the law changes along each state; the
        stencil's largest offset is ``STEP`` times it.

    Examples
    --------
    >>> import numpy as np
    >>> law = UserLaw(
    ...     "cubic spring",
    ...     lambda s: 1e4 * s + 1e6 * s**3,
    ...     lambda s: (1e4 + 3e6 * s**2,),
    ...     points=[[-0.05], [0.0], [0.1]],
    ...     scales=[0.1],
    ... )
    >>> force, stiffness = law(0.5)
    >>> float(force), float(stiffness)
    (130000.0, 760000.0)
    """

    name: str
    function: Callable[..., ArrayLike]
    derivative: Callable[..., Sequence[ArrayLike]]
    points: ArrayLike
    scales: ArrayLike

    def __post_init__(self) -> None:
        if not (isinstance(self.name, str) and self.name):
            raise ValueError(f"user law: name must be a non-empty string, got {self.name!r}")
        law = f"user law '{self.name}'"
        scales = np.atleast_1d(state(self.scales, law, "scales"))
        if scales.ndim != 1 or np.any(scales <= 0):
            raise ValueError(f"{law}: scales must be positive, one per state, got {scales}")
        points = np.atleast_2d(state(self.points, law, "points"))
        if points.ndim != 2 or points.shape[1] != scales.size:
            raise ValueError(
                f"{law}: points must be rows of {scales.size} states (one per scale), got "
                f"shape {points.shape}"
            )
        object.__setattr__(self, "scales", scales)
        object.__setattr__(self, "points", points)
        self._check()

    @property
    def arity(self) -> int:
        """The number of states the law takes."""
        return int(np.size(self.scales))

    def __call__(self, *states: ArrayLike) -> Law:
        """The value and its partials at ``states`` (broadcast together), checked finite."""
        law = f"user law '{self.name}'"
        if len(states) != self.arity:
            raise ValueError(f"{law}: takes {self.arity} states, got {len(states)}")
        x = [state(s, law, f"state {i + 1}") for i, s in enumerate(states)]
        value = state(self.function(*x), law, "value")
        partials = tuple(self.derivative(*x))
        if len(partials) != self.arity:
            raise ValueError(
                f"{law}: derivative must return {self.arity} partials, got {len(partials)}"
            )
        checked = [state(p, law, f"partial {i + 1}") for i, p in enumerate(partials)]
        shape = np.broadcast_shapes(*(np.shape(a) for a in (value, *checked, *x)))
        return tuple(np.array(np.broadcast_to(a, shape)) for a in (value, *checked))

    def _check(self) -> None:
        law = f"user law '{self.name}'"
        points = np.asarray(self.points)
        _, *partials = self(*points.T)
        for i, scale in enumerate(np.asarray(self.scales)):

            def along(xi: np.ndarray, *others: np.ndarray, i: int = i) -> np.ndarray:
                return np.asarray(self.function(*others[:i], xi, *others[i:]), dtype=float)

            others = tuple(np.delete(points, i, axis=1).T)
            try:
                estimate, tolerance = central_difference(along, points[:, i], STEP * scale, others)
            except ValueError as error:
                raise ValueError(
                    f"{law}: cannot check the partial in state {i + 1}: {error}"
                ) from None
            wrong = np.abs(partials[i] - estimate) > tolerance
            if np.any(wrong):
                j = int(np.argmax(wrong))
                raise ValueError(
                    f"{law}: the partial in state {i + 1} at {points[j].tolist()} is "
                    f"{partials[i][j]:.9g}, central differences give {estimate[j]:.9g} "
                    f"(+- {tolerance[j]:.3g})"
                )
