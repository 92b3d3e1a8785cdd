"""Scratch arrays on the stack of a compiled kernel (numba), instead of the heap; borrowed
views of a caller's array.

A compiled kernel's ``np.empty`` is a heap allocation with a reference count: a ``malloc``,
an atomic increment and decrement per use across calls, and a ``free`` (docs/performance.md,
"Where the time goes now": about a third of the warm static solve).  A kernel's scratch
arrays -- the few small buffers it fills and reads before it returns, whose size has a
bound known when the module is written (a node's three coordinates, an element's nodes) --
need none of that: :func:`stack_empty` reserves them in the calling kernel's stack frame
(LLVM's ``alloca``, once per call site, in the function's entry block) and views them as an
array without a reference count.

Rules for the caller (what makes the view safe):

- the array never leaves the kernel that makes it (never returned, stored or captured);
  it lives until that kernel returns, and the caller of :func:`stack_empty` must be compiled
  with ``inline="always"`` into it, or be it;
- the array is filled before it is read (like ``np.empty``; there is no zeroed twin);
- the shape asked fits in the reserved ``size`` entries (checked: :func:`stack_empty` raises
  ``ValueError`` when it does not).

:func:`borrowed` is the same idea for a view: the entries ``offset ..`` of a flat array
seen with another shape, without the reference count (and the reshape call) of
``a[offset:offset + n].reshape(shape)``.  It is for a kernel reading a packed array its
caller holds for the whole call (the joints' fields, :mod:`sliders.joints.packed`); the view
must not outlive that call.
"""

from __future__ import annotations

import numba
import numpy as np
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic


@intrinsic
def _reserve(typingctx, size, dtype):
    """A pointer to ``size`` (a literal integer) entries of ``dtype`` in the entry block's
    stack frame of the kernel being compiled."""
    if not isinstance(size, types.IntegerLiteral):
        return None
    count = size.literal_value

    def codegen(context, builder, signature, args):
        return cgutils.alloca_once(builder, context.get_value_type(dtype.dtype), size=count)

    return types.CPointer(dtype.dtype)(size, dtype), codegen


@intrinsic
def _address(typingctx, array, offset):
    """A pointer to entry ``offset`` of the contiguous ``array``'s data (a typing error for
    an array that is not known to be C-contiguous)."""
    if not (isinstance(array, types.Array) and array.layout == "C"):
        return None

    def codegen(context, builder, signature, args):
        data = context.make_array(signature.args[0])(context, builder, args[0]).data
        return builder.gep(data, [args[1]])

    return types.CPointer(array.dtype)(array, offset), codegen


@numba.njit(inline="always")
def borrowed(array, offset, shape):
    """The entries ``offset ..`` of the contiguous 1-D ``array`` as a C-ordered array of
    ``shape``, borrowed: no reference count, valid while the caller holds ``array``."""
    return numba.carray(_address(array, offset), shape)


@numba.njit(inline="always")
def stack_empty(size, shape, dtype):
    """An uninitialised C-ordered array of ``shape`` viewing ``size`` (a literal integer,
    the bound) entries of ``dtype`` on the stack of the kernel this is inlined into;
    ``ValueError`` when ``shape`` holds more than ``size`` entries."""
    count = 1
    for extent in shape:
        count *= extent
    if count > size:
        raise ValueError("a scratch array larger than its reserved stack space")
    return numba.carray(_reserve(size, dtype), shape)


@numba.njit(inline="always")
def stack_zeros(size, shape, dtype):
    """:func:`stack_empty` filled with zeros."""
    out = stack_empty(size, shape, dtype)
    out[:] = 0
    return out


@numba.njit(inline="always")
def stack_vector3():
    """An uninitialised float 3-vector on the stack (:func:`stack_empty`)."""
    return stack_empty(3, (3,), np.float64)


@numba.njit(inline="always")
def stack_matrix3():
    """An uninitialised float 3x3 matrix on the stack (:func:`stack_empty`)."""
    return stack_empty(9, (3, 3), np.float64)
