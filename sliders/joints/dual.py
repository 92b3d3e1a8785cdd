"""Forward-mode automatic differentiation by dual numbers, for the joints' point laws.

A :class:`Dual` is a value ``a`` with its gradient ``a'`` in seeded directions,
``a + a' epsilon`` with ``epsilon^2 = 0``: sums and products of duals carry the chain rule
(``(a b)' = a' b + a b'``), so a function written with arithmetic only, run on duals, returns
its value and its exact derivative (Griewank and Walther, *Evaluating Derivatives*, 2nd ed.,
Sec. 3.1).  The joints' laws (:mod:`sliders.joints.equations`) are written once, as
residuals; their Jacobian is what this module derives from them.

Duals sit in numpy object arrays (3-vectors, small matrices), so the laws keep numpy's
``@``, :func:`numpy.cross` and slicing.  A gradient is kept sparse, ``{direction: entry}``,
so that a quantity carries only the directions it depends on: the derivative's structural
zeros (the blocks a law does not write) cost nothing and stay exactly zero.  The value and
the entries may be of any number type with ``+ - * /`` (floats; the round-off carrying
numbers of the tests), and every product with a scalar keeps the dual's own entries on the
left (``a' * b``), so that a number type of the caller's is applied as its own arithmetic.
"""

from __future__ import annotations

from typing import Any

import numpy as np


class Dual:
    """``value + sum_j grad[j] epsilon_j``: a number and its derivative in the directions
    ``j`` its sparse gradient names (zero in the others)."""

    __slots__ = ("grad", "value")

    def __init__(self, value: Any, grad: dict[int, Any]) -> None:
        self.value, self.grad = value, grad

    def __add__(self, other: Any) -> Any:
        if isinstance(other, Dual):
            return Dual(self.value + other.value, _added(self.grad, other.grad, 1))
        if isinstance(other, np.ndarray):
            return NotImplemented
        return Dual(self.value + other, self.grad)

    def __sub__(self, other: Any) -> Any:
        if isinstance(other, Dual):
            return Dual(self.value - other.value, _added(self.grad, other.grad, -1))
        if isinstance(other, np.ndarray):
            return NotImplemented
        return Dual(self.value - other, self.grad)

    def __rsub__(self, other: Any) -> Any:
        return Dual(other - self.value, {j: -a for j, a in self.grad.items()})

    def __mul__(self, other: Any) -> Any:
        if isinstance(other, Dual):
            grad = {j: a * other.value for j, a in self.grad.items()}
            for j, a in other.grad.items():
                grad[j] = grad[j] + a * self.value if j in grad else a * self.value
            return Dual(self.value * other.value, grad)
        if isinstance(other, np.ndarray):
            return NotImplemented
        return Dual(self.value * other, {j: a * other for j, a in self.grad.items()})

    def __truediv__(self, other: Any) -> Any:
        if isinstance(other, Dual):
            ratio = self.value / other.value
            grad = _added(self.grad, {j: a * ratio for j, a in other.grad.items()}, -1)
            return Dual(ratio, {j: a / other.value for j, a in grad.items()})
        if isinstance(other, np.ndarray):
            return NotImplemented
        return Dual(self.value / other, {j: a / other for j, a in self.grad.items()})

    def __neg__(self) -> Dual:
        return Dual(-self.value, {j: -a for j, a in self.grad.items()})

    __radd__ = __add__
    __rmul__ = __mul__

    def __repr__(self) -> str:
        return f"Dual({self.value!r}, {self.grad!r})"


def _added(a: dict[int, Any], b: dict[int, Any], sign: int) -> dict[int, Any]:
    """The gradient ``a + sign b``."""
    out = dict(a)
    for j, e in b.items():
        if j in out:
            out[j] = out[j] + e if sign > 0 else out[j] - e
        else:
            out[j] = e if sign > 0 else -e
    return out


def seeded(value: np.ndarray, directions: dict[int, np.ndarray]) -> np.ndarray:
    """``value`` (any shape) as an object array of duals whose derivative in direction ``j``
    is ``directions[j]`` (``value``'s shape) and zero in the others (a constant where
    ``directions`` is empty); an entry that is a plain zero is left out of the gradient."""
    value = np.asarray(value)
    out = np.empty(value.shape, dtype=object)
    for index in np.ndindex(value.shape):
        grad = {j: _scalar(d[index]) for j, d in directions.items()}
        grad = {j: e for j, e in grad.items() if not (isinstance(e, int | float) and e == 0)}
        out[index] = Dual(_scalar(value[index]), grad)
    return out


def values(a: np.ndarray) -> np.ndarray:
    """The values of an object array of duals (or numbers), in an object array."""
    out = np.empty(np.shape(a), dtype=object)
    for index in np.ndindex(out.shape):
        e = a[index]
        out[index] = e.value if isinstance(e, Dual) else e
    return out


def gradients(a: np.ndarray, n: int) -> np.ndarray:
    """The gradients of an object array of duals in the directions ``0 .. n - 1``,
    ``a.shape + (n,)``: 0.0 where an entry does not depend on a direction (a plain number
    on none)."""
    out = np.full(np.shape(a) + (n,), 0.0, dtype=object)
    for index in np.ndindex(np.shape(a)):
        e = a[index]
        if isinstance(e, Dual):
            for j, d in e.grad.items():
                out[index + (j,)] = d
    return out


def _scalar(x: Any) -> Any:
    """A numpy scalar as the Python number it holds (any other number as it is), so that
    its products with duals are the duals' own."""
    return x.item() if isinstance(x, np.generic) else x
