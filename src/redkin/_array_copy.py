"""Copying one array into another inside a kernel, without numba's slice assignment.

``out[:] = source`` (or ``out[k] = row``, any assignment of an array) compiles numba's general setitem with its
broadcasting and its error message for mismatched shapes: about 2 s the first time a process compiles one, then
0.15-0.2 s for each kernel that holds one, against 0.06 s for a kernel with a loop (numba 0.68 on this 2-core
machine, ``benchmarks/README.md``, "Array copies without slice assignment").  The kernels call these instead; the
shapes are the caller's to match, as they are for the loops around them.
"""

from __future__ import annotations

from redkin._compiled import kernel


@kernel
def copy_into(out, source):
    """``out[i] = source[i]`` for every ``i`` of ``out`` (1-D; ``source`` at least as long)."""
    for i in range(out.shape[0]):
        out[i] = source[i]


@kernel
def copy_rows_into(out, source):
    """``out[i, j] = source[i, j]`` for every ``i, j`` of ``out`` (2-D; ``source`` at least as large)."""
    for i in range(out.shape[0]):
        for j in range(out.shape[1]):
            out[i, j] = source[i, j]
