"""Laws of the kernels' array copies: each equals numpy's slice assignment, compiled and as Python, on every dtype
and layout the kernels pass (rows, columns, strided views)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from redkin import _array_copy

DTYPES = (np.float64, np.complex128, np.int64, np.bool_)


def _values(rng: np.random.Generator, shape: tuple[int, ...], dtype) -> np.ndarray:
    raw = rng.normal(size=shape) + 1j * rng.normal(size=shape)
    return (raw if dtype is np.complex128 else raw.real > 0 if dtype is np.bool_ else raw.real * 100).astype(dtype)


@pytest.mark.parametrize("compiled", [True, False], ids=["compiled", "python"])
@pytest.mark.parametrize("dtype", DTYPES, ids=lambda d: np.dtype(d).name)
@settings(max_examples=15, deadline=None)
@given(rows=st.integers(1, 6), columns=st.integers(1, 9), seed=st.integers(0, 2**32 - 1))
def test_copies_equal_slice_assignment(compiled, dtype, rows, columns, seed):
    rng = np.random.default_rng(seed)
    copy_into = _array_copy.copy_into if compiled else _array_copy.copy_into.py_func
    copy_rows_into = _array_copy.copy_rows_into if compiled else _array_copy.copy_rows_into.py_func
    source = _values(rng, (rows, columns), dtype)
    for out_of, source_of in [(lambda a: a[rows - 1], lambda s: s[0]),  # a row from another row
                              (lambda a: a[:, columns - 1], lambda s: s[:, 0]),  # a column (strided) from one
                              (lambda a: a[0, ::2], lambda s: s[rows - 1, ::2])]:  # strided views
        out = _values(rng, (rows, columns), dtype)
        expected = out.copy()
        out_of(expected)[:] = source_of(source)
        copy_into(out_of(out), source_of(source))
        assert np.array_equal(out, expected)
    out = _values(rng, (rows, columns), dtype)
    copy_rows_into(out, source)
    assert np.array_equal(out, source)
    out = _values(rng, (rows + 2, columns), dtype)
    expected = out.copy()
    expected[1:rows + 1] = source
    copy_rows_into(out[1:rows + 1], source)
    assert np.array_equal(out, expected)
