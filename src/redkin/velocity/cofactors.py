"""Cofactor building blocks of the column-augmented Jacobian (paper 003 section 2.1).

For a Jacobian ``J`` of shape ``(m, m + 1)`` (one degree of redundancy, e.g.
6 x 7), ``J_i`` is ``J`` without column ``i``.  Everything here is a
polynomial in the entries of ``J`` (determinants only, no inverse), so it
stays finite and exact at singularities.  All functions batch over leading
axes.  Indices are 0-based in code; the paper's ``(-1)^(i+1)`` for 1-based
``i`` is ``(-1)^i`` here.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from redkin._compiled import kernel_array, run_batch
from redkin._validation import as_float_array, check_finite, check_jacobian_and_twist
from redkin.errors import RedkinError
from redkin.velocity import _step_kernels


def _without_each_column(matrix: np.ndarray) -> np.ndarray:
    """Stack of ``matrix`` with column ``i`` removed, shape ``(..., k, rows, k - 1)``."""
    k = matrix.shape[-1]
    keep = np.array([[j for j in range(k) if j != i] for i in range(k)])  # (k, k-1)
    return np.moveaxis(matrix[..., keep], -2, -3)


def column_minors(jacobian: ArrayLike) -> np.ndarray:
    """``det J_i`` for every removed column ``i``, shape ``(..., m + 1)`` [003 eq. 5].

    By Cauchy-Binet, ``det(J J^T) = sum_i det(J_i)^2``.  The kernel
    :func:`~redkin.velocity._step_kernels.column_minors_one` (Gaussian
    elimination with partial pivoting), which the SC step's self-motion term uses too.
    """
    jac = _redundant_one(jacobian)
    lead, (m, n) = jac.shape[:-2], jac.shape[-2:]
    flat = kernel_array(jac.reshape(-1, m, n))
    out = np.empty((flat.shape[0], n))
    run_batch(_step_kernels.column_minors, flat.shape[0], flat, out)
    return out.reshape(lead + (n,))


def self_motion_vector(jacobian: ArrayLike) -> np.ndarray:
    """Self-motion joint velocity ``n_sm`` with ``C_sm,i = (-1)^(i+1) det J_i`` [003 eqs. 4-5].

    ``J n_sm = 0`` (Laplace expansion of a matrix with a repeated row); it is
    zero only where ``rank J < m``.
    """
    minors = column_minors(jacobian)
    signs = (-1.0) ** np.arange(minors.shape[-1])
    return signs * minors


def fixed_joint_vectors(jacobian: ArrayLike, twist: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """End-point null-space vectors ``n_i`` of ``[J  -t]`` with joint ``i`` fixed [003 eqs. 6-8].

    With joint ``i`` fixed the arm is non-redundant, and Cramer's rule gives
    ``J_i adj(J_i) t = det(J_i) t``.  So ``n_i`` is ``adj(J_i) t`` with a zero
    inserted at position ``i`` [003 eq. 7], and ``[n_i; det J_i]`` spans the null
    space of the column-augmented Jacobian ``[J  -t]`` [003 eq. 2] with joint
    ``i`` fixed: ``J n_i = det(J_i) t``, so the twist size is
    ``q_dot_* = det J_i`` [003 eq. 10].  The sign convention differs from [003 eq. 6] as
    transcribed (which puts ``(-1)^(i+1)`` on the last entry); ours makes
    ``q_dot_* = det J_i`` hold for every ``i`` as [003 eqs. 10, 16] require.

    Parameters
    ----------
    jacobian : array_like, shape (..., m, m + 1)
    twist : array_like, shape (..., m)
        Any twist (not necessarily unit); ``n_i`` is linear in it.

    Returns
    -------
    vectors : numpy.ndarray, shape (..., m + 1, m + 1)
        Row ``i`` is ``n_i``.
    minors : numpy.ndarray, shape (..., m + 1)
        ``det J_i``.
    """
    jac, vel = check_jacobian_and_twist(jacobian, twist, one_redundant=True)
    m, k = jac.shape[-2:]
    reduced = _without_each_column(jac)  # (..., k, m, m)
    # Cramer: (adj(J_i) t)_c = det(J_i with column c replaced by t).
    replaced = np.repeat(reduced[..., None, :, :], m, axis=-3).copy()  # (..., k, m, m, m)
    for c in range(m):
        replaced[..., c, :, c] = vel[..., None, :]
    # numpy's det meets a zero pivot on an exactly singular J_i and warns while returning the right 0
    with np.errstate(divide="ignore"):
        minors = np.linalg.det(reduced)
        adj_t = np.linalg.det(replaced)  # (..., k, m)
    vectors = np.zeros(jac.shape[:-2] + (k, k))
    keep = np.array([[j for j in range(k) if j != i] for i in range(k)])
    rows = np.arange(k)[:, None]
    vectors[..., rows, keep] = adj_t
    return vectors, minors


def weighted_sum(weights: ArrayLike, vectors: np.ndarray) -> np.ndarray:
    """``n_sum = sum_i b_i n_i`` [003 eq. 15] for weights ``(..., k)`` and vectors ``(..., k, k)``."""
    return np.einsum("...i,...ij->...j", np.asarray(weights, dtype=float), vectors)


def adjugate(matrix: ArrayLike) -> np.ndarray:
    """Adjugate (transpose of the cofactor matrix) of square matrices ``(..., k, k)``.

    Computed from ``(k-1) x (k-1)`` minors, so it is exact for singular input
    (where ``det(A) inv(A)`` is undefined).
    """
    mat = as_float_array(matrix, "matrix")
    if mat.ndim < 2 or mat.shape[-1] != mat.shape[-2]:
        raise RedkinError(f"matrix must have shape (..., k, k), got shape {mat.shape}")
    check_finite(mat, "matrix")
    k = mat.shape[-1]
    if k == 1:
        return np.ones_like(mat)
    minor_cols = _without_each_column(mat)  # (..., j, k, k-1): column j removed
    minors = np.linalg.det(_without_each_column(np.swapaxes(minor_cols, -1, -2)))  # (..., j, i): row i removed
    signs = (-1.0) ** np.add.outer(np.arange(k), np.arange(k))
    return signs * minors  # adj[j, i] = (-1)^(i+j) M_ij


def _redundant_one(jacobian: ArrayLike) -> np.ndarray:
    jac = as_float_array(jacobian, "jacobian")
    if jac.ndim < 2 or jac.shape[-1] != jac.shape[-2] + 1:
        raise RedkinError(f"jacobian must have shape (..., m, m + 1) (e.g. 6 x 7), got shape {jac.shape}")
    check_finite(jac, "jacobian")
    return jac
