"""Scratch arrays on a kernel's stack (fvbeam.scratch) behave as ``np.empty`` / ``np.zeros``,
and a borrowed view as the reshaped slice it stands for.

Each check has an exact answer: the arrays hold what was written into them (no two share
memory), have the shape and dtype asked, a kernel that uses them gives, bit for bit, what the
same kernel gives on heap arrays, and a shape larger than its reserved space raises; a
borrowed view reads and writes the entries of the slice, and is refused for an array not
known to be contiguous.
"""

import numba
import numpy as np
import pytest

from fvbeam.scratch import borrowed, stack_empty, stack_matrix3, stack_vector3, stack_zeros


@numba.njit
def _filled(npe: int) -> tuple:
    """Three scratch arrays filled with distinct values, copied out to the heap."""
    a = stack_empty(9, (3, npe), np.float64)
    b = stack_zeros(9, (npe, 3), np.float64)
    c = stack_empty(3, (npe,), np.int64)
    for i in range(3):
        for j in range(npe):
            a[i, j] = 10.0 * i + j
    for j in range(npe):
        c[j] = -j - 1
    return a.copy(), b.copy(), c.copy()


@numba.njit
def _fixed_shapes() -> tuple:
    """Two 3-vectors and two 3x3 matrices, each filled with its own value, copied out."""
    a, b = stack_vector3(), stack_vector3()
    A, B = stack_matrix3(), stack_matrix3()
    a[:], b[:], A[:], B[:] = 1.0, 2.0, 3.0, 4.0
    return a.copy(), b.copy(), A.copy(), B.copy()


@numba.njit
def _outer_sum(x: np.ndarray, stack: bool) -> float:
    """sum_k sum_ij (x_i x_j + k) over 20 fresh 3 x 3 scratch matrices."""
    total = 0.0
    for k in range(20):
        a = stack_empty(9, (3, 3), np.float64) if stack else np.empty((3, 3))
        for i in range(3):
            for j in range(3):
                a[i, j] = x[i] * x[j] + k
        total += a.sum()
    return total


@numba.njit
def _too_large(npe: int) -> None:
    stack_empty(6, (3, npe), np.float64)[0, 0] = 1.0


@pytest.mark.parametrize("npe", [1, 2, 3])
def test_scratch_arrays_hold_what_was_written(npe):
    a, b, c = _filled(npe)
    assert a.shape == (3, npe) and b.shape == (npe, 3) and c.shape == (npe,)
    assert a.dtype == np.float64 and c.dtype == np.int64
    np.testing.assert_array_equal(a, 10.0 * np.arange(3)[:, None] + np.arange(npe))
    np.testing.assert_array_equal(b, np.zeros((npe, 3)))
    np.testing.assert_array_equal(c, -np.arange(1, npe + 1))


def test_each_fixed_shape_scratch_array_is_its_own():
    a, b, A, B = _fixed_shapes()
    np.testing.assert_array_equal(a, np.full(3, 1.0))
    np.testing.assert_array_equal(b, np.full(3, 2.0))
    np.testing.assert_array_equal(A, np.full((3, 3), 3.0))
    np.testing.assert_array_equal(B, np.full((3, 3), 4.0))


def test_a_kernel_on_scratch_arrays_equals_it_on_heap_arrays():
    x = np.array([0.3, -1.7, 2.9])
    assert _outer_sum(x, True) == _outer_sum(x, False)
    assert _outer_sum(x, True) == pytest.approx(
        sum(np.multiply.outer(x, x).sum() + 9 * k for k in range(20)), rel=1e-15
    )


def test_a_shape_beyond_the_reserved_space_raises():
    _too_large(2)
    with pytest.raises(ValueError, match="reserved stack space"):
        _too_large(3)


@numba.njit
def _through_view(a: np.ndarray, offset: int, rows: int, cols: int) -> np.ndarray:
    """The view's first entry set to -1, then the view copied out."""
    view = borrowed(a, offset, (rows, cols))
    view[0, 0] = -1.0
    return view.copy()


@pytest.mark.parametrize("offset, rows, cols", [(0, 2, 3), (5, 3, 2), (7, 1, 5)])
def test_a_borrowed_view_is_the_reshaped_slice(offset, rows, cols):
    a = np.arange(12.0)
    expected = a.copy()
    expected[offset] = -1.0
    got = _through_view(a, offset, rows, cols)
    np.testing.assert_array_equal(got, expected[offset : offset + rows * cols].reshape(rows, cols))
    np.testing.assert_array_equal(a, expected)  # written through to the caller's array


def test_a_borrowed_view_of_a_strided_array_is_refused():
    with pytest.raises(numba.core.errors.TypingError):
        _through_view(np.arange(12.0)[::2], 0, 2, 3)
