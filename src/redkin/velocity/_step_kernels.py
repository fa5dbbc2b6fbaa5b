"""The compiled core of the velocity steps (paper 003): least squares (pseudoinverse, DLS) and the SC step.

The one implementation in redkin of each step; the public functions of
:mod:`redkin.velocity.baselines` and :mod:`redkin.velocity.proposed` and the
controllers of :mod:`redkin.velocity.controller` validate their inputs and
call these kernels.  Each step comes as a kernel of one configuration
(``*_one``, callable from Python with one Jacobian), a control step of one
configuration that builds the Jacobian itself (``*_control``, one call per
servo tick), and a loop over items ``start .. stop - 1`` of a batch of
Jacobians ``(N, m, n)`` (:func:`~redkin._compiled.run_batch` hands out the
chunks; every item is computed alone, so a batch equals its items one by
one, bit for bit, on any number of threads).  Inputs are trusted: C-contiguous float64 arrays.

Singular values come from the one-sided Jacobi method (Hestenes) on the
rows of ``J`` (:func:`orthogonal_rows`): plane rotations ``W`` turn the rows
until they are mutually orthogonal, ``W^T J = B`` with rows ``b_k = sigma_k
u_k^T``.  Then ``J = W B`` is an SVD up to normalisation and every filtered
inverse of ``J`` is a sum over the rows,

    q_dot = sum_k gain_k (W^T v)_k b_k,

with ``gain_k = 1 / sigma_k^2`` for the pseudoinverse (0 below the cut-off)
and ``1 / (sigma_k^2 + lambda^2)`` for damped least squares.  Jacobi is
backward stable like LAPACK's SVD (the tests hold the pseudoinverse to
``1e-13 cond(J)`` of numpy's, exactly singular Jacobians included) and
makes no calls: LAPACK's SVD from a kernel allocates its workspace on every
call, about 8 us for a 6 x 7 Jacobian, while the rotations (about 6 sweeps,
the twist rotated alongside instead of ``W`` kept) take 2-3 us.

The exact SC path at ``D_e = 0`` needs ``sum_i D_i n_i = adj(M) [t'; 0]``
with ``M = [J; c^T]``, ``c_i = (-1)^i D_i`` (derived in
:mod:`redkin.velocity.proposed`): Cramer's rule,
``(adj(M) r)_i = det(M with column i replaced by r)``, with determinants by
Gaussian elimination with partial pivoting (:func:`determinant`), which
stays exact in the limit where ``M`` becomes singular (no inverse taken).
"""

from __future__ import annotations

from math import sqrt

import numpy as np

from redkin import _chain_kernels
from redkin._compiled import kernel

#: Largest number of Jacobi sweeps (a 6 x 7 Jacobian needs 5 to 8).
MAX_SWEEPS = 40
#: Rows count as orthogonal when ``|b_i . b_k| <= ORTHOGONAL * |b_i| |b_k|``.
ORTHOGONAL = 1e-15
#: Relative cut-off of the SC method's pseudoinverse: machine precision (LAPACK ``dgelss`` with ``rcond < 0``).
MACHINE_EPSILON = float(np.finfo(float).eps)
#: ``measure`` codes of :func:`damping`.
CONSTANT, SIGMA, MANIPULABILITY = 0, 1, 2
#: Codes returned by the control steps (:func:`sc_control`, :func:`pinv_control`).
DONE, Q_NOT_FINITE, TWIST_NOT_FINITE, NO_FACTORS = 0, 1, 2, 3


# ------------------------------------------------------------ linear algebra
@kernel
def orthogonal_rows(b, v):
    """One-sided Jacobi: rotate the rows of ``b`` (m, n) until they are orthogonal, and ``v`` (m,) with them.

    On entry ``b`` holds ``J`` and ``v`` a twist; on exit ``b = W^T J`` with
    mutually orthogonal rows (``|b_k| = sigma_k``) and ``v = W^T v`` for the
    orthogonal ``W`` of the rotations (``J = W b``).  Each pair's norms are
    summed afresh before its rotation (norms carried through the rotations
    lose the small ones to cancellation).
    """
    m, n = b.shape
    for _ in range(MAX_SWEEPS):
        rotated = False
        for i in range(m - 1):
            for k in range(i + 1, m):
                alpha = beta = gamma = 0.0
                for c in range(n):
                    alpha += b[i, c] * b[i, c]
                    beta += b[k, c] * b[k, c]
                    gamma += b[i, c] * b[k, c]
                if gamma == 0.0 or abs(gamma) <= ORTHOGONAL * sqrt(alpha * beta):
                    continue
                rotated = True
                zeta = (beta - alpha) / (2.0 * gamma)
                t = (1.0 if zeta >= 0.0 else -1.0) / (abs(zeta) + sqrt(1.0 + zeta * zeta))
                cos = 1.0 / sqrt(1.0 + t * t)
                sin = cos * t
                for c in range(n):
                    bi, bk = b[i, c], b[k, c]
                    b[i, c], b[k, c] = cos * bi - sin * bk, sin * bi + cos * bk
                v[i], v[k] = cos * v[i] - sin * v[k], sin * v[i] + cos * v[k]
        if not rotated:
            return


@kernel
def row_squares(b):
    """``|b_k|^2`` of each row of ``b`` (m,)."""
    m, n = b.shape
    squares = np.empty(m)
    for k in range(m):
        total = 0.0
        for c in range(n):
            total += b[k, c] * b[k, c]
        squares[k] = total
    return squares


@kernel
def singular_values(b):
    """``sigma_k = |b_k|`` of the rows of :func:`orthogonal_rows`'s ``b``, largest first, ``min(m, n)`` of them."""
    m, n = b.shape
    sigma = np.empty(m)
    squares = row_squares(b)
    for k in range(m):
        value, i = sqrt(squares[k]), k
        while i > 0 and sigma[i - 1] < value:  # insertion sort, largest first
            sigma[i] = sigma[i - 1]
            i -= 1
        sigma[i] = value
    return sigma[: min(m, n)]


@kernel
def filtered(b, along, damping, rcond, out):
    """``sum_k gain_k along_k b_k`` into ``out`` (n,), with ``b`` and ``along = W^T v`` from :func:`orthogonal_rows`.

    ``J^+ v`` for ``damping = 0`` (rows with ``sigma_k <= rcond sigma_max``
    dropped), else ``J^T (J J^T + lambda^2 I)^-1 v``.
    """
    m, n = b.shape
    squares = row_squares(b)
    largest = 0.0
    for k in range(m):
        largest = max(largest, squares[k])
    cutoff = rcond * sqrt(largest)
    for c in range(n):
        out[c] = 0.0
    for k in range(m):
        if damping > 0.0:
            gain = 1.0 / (squares[k] + damping * damping)
        elif squares[k] > 0.0 and sqrt(squares[k]) > cutoff:
            gain = 1.0 / squares[k]
        else:
            continue
        for c in range(n):
            out[c] += gain * along[k] * b[k, c]


@kernel
def determinant(a, lu):
    """``det a`` of a square ``a`` (k, k): Gaussian elimination with partial pivoting in the scratch ``lu`` (k, k)."""
    k = a.shape[0]
    for r in range(k):
        for c in range(k):
            lu[r, c] = a[r, c]
    det = 1.0
    for col in range(k):
        pivot = col
        for r in range(col + 1, k):
            if abs(lu[r, col]) > abs(lu[pivot, col]):
                pivot = r
        if lu[pivot, col] == 0.0:
            return 0.0
        if pivot != col:
            for c in range(col, k):
                lu[col, c], lu[pivot, c] = lu[pivot, c], lu[col, c]
            det = -det
        det *= lu[col, col]
        for r in range(col + 1, k):
            factor = lu[r, col] / lu[col, col]
            for c in range(col + 1, k):
                lu[r, c] -= factor * lu[col, c]
    return det


@kernel
def column_minors_one(jac, out):
    """``det J_i``, ``J`` (m, m + 1) without column ``i``, into ``out`` (m + 1,) [003 eq. 5]."""
    m, n = jac.shape
    reduced = np.empty((m, m))
    lu = np.empty((m, m))
    for i in range(n):
        for r in range(m):
            for c in range(m):
                reduced[r, c] = jac[r, c if c < i else c + 1]
        out[i] = determinant(reduced, lu)


@kernel
def adjugate_times(square, rhs, out):
    """``adj(M) r`` for a square ``M`` (k, k) by Cramer's rule: ``out_i = det(M with column i replaced by r)``."""
    k = square.shape[0]
    replaced = square.copy()
    lu = np.empty((k, k))
    for i in range(k):
        for r in range(k):
            replaced[r, i] = rhs[r]
        out[i] = determinant(replaced, lu)
        for r in range(k):
            replaced[r, i] = square[r, i]


# --------------------------------------------------------- blend [003 eqs. 11, 21, 22]
@kernel
def twist_scale_of(x, eps):
    """``g(x) = x (3 - x^2 / eps^2) / (2 eps)`` for ``|x| <= eps``, ``sign(x)`` outside: the realised
    twist factor of [003 eq. 22], derived with the blend of [003 eq. 21]."""
    if abs(x) <= eps:
        return x * (3.0 - (x / eps) ** 2) / (2.0 * eps)
    return 1.0 if x > 0.0 else (-1.0 if x < 0.0 else x)  # NaN stays NaN


@kernel
def weight_of(x, eps):
    """``w(x) = g(x) / x``: ``(3 - x^2 / eps^2) / (2 eps)`` inside the region, ``1 / |x|`` outside: the blend of
    [003 eq. 11], and of [003 eq. 21] (repaired) with ``x = D_e``."""
    if abs(x) <= eps:
        return (3.0 - (x / eps) ** 2) / (2.0 * eps)
    return 1.0 / abs(x)


@kernel
def rotation_factor_of(x, eps):
    """``clip(x / eps, -1, 1)``, the factor on the rotational command ([003 eq. 22] text)."""
    ratio = x / eps
    return 1.0 if ratio > 1.0 else (-1.0 if ratio < -1.0 else ratio)


@kernel
def blend(x, eps, scale, weight, rotation):
    """``g``, ``w`` and the rotation factor of every entry of ``x`` (N,) into the three outputs (N,)."""
    for b in range(x.shape[0]):
        scale[b] = twist_scale_of(x[b], eps)
        weight[b] = weight_of(x[b], eps)
        rotation[b] = rotation_factor_of(x[b], eps)


# ------------------------------------------------------------ one configuration
@kernel
def damping(sigma, max_damping, threshold, measure):
    """``lambda`` from the singular values ``sigma`` (largest first): ``max_damping`` itself for ``CONSTANT``;
    else ``max_damping sqrt(1 - min(s / threshold, 1)^2)`` with ``s = sigma_min`` (``SIGMA``) or ``prod sigma``."""
    if measure == CONSTANT:
        return max_damping
    value = sigma[sigma.shape[0] - 1]
    if measure == MANIPULABILITY:
        value = 1.0
        for s in sigma:
            value *= s
    ratio = min(value / threshold, 1.0)
    return max_damping * sqrt(1.0 - ratio * ratio)


@kernel
def least_squares_one(jac, twist, max_damping, threshold, measure, rcond, out):
    """Filtered inverse ``q_dot`` (n,) of one Jacobian ``J`` (m, n) and twist ``v`` (m,); returns ``lambda``.

    ``J^+ v`` (``CONSTANT``, ``max_damping = 0``; singular values at most
    ``rcond sigma_max`` dropped), ``J^T (J J^T + lambda^2 I)^-1 v``
    (``CONSTANT``, ``lambda = max_damping``), or the adaptive damping of
    :func:`damping` (``SIGMA``, ``MANIPULABILITY``; the pseudoinverse where
    it is zero).
    """
    b = jac.copy()
    along = twist.copy()
    orthogonal_rows(b, along)
    lam = max_damping if measure == CONSTANT else damping(singular_values(b), max_damping, threshold, measure)
    filtered(b, along, lam, rcond, out)
    return lam


@kernel
def sc_one(jac, twist, index, factors, eps, direction, self_motion, modify_rotation, near_zero, qdot, target):
    """The singularity-consistent step [003 eqs. 9, 15, 17-22] of one Jacobian ``J`` (m, m + 1).

    ``target`` (m,) receives ``b_ep g(D_e) t'``, where ``t'`` is ``twist``
    with its rotational rows (3..5, if ``modify_rotation``) times ``b_ep
    clip(D_e / eps, -1, 1)`` [003 eq. 22]; ``qdot`` (m + 1,) the joint velocity
    ``b_ep (w(D_e) / D_s) sum_i D_i n_i + b_sm n_sm`` [003 eqs. 9, 15, 21].
    Where ``|D_e| >= near_zero`` the sum is ``D_e D_s J^+ t'`` [003 eqs. 17-20],
    so ``qdot = J^+ target`` and ``factors`` is not read; below it the sum is
    ``adj(M) [t'; 0]`` with ``M = [J; c^T]``, ``c_i = (-1)^i D_i``, exact on
    ``D_e = 0``.  Returns ``False`` (and leaves ``qdot`` unset) where that
    path meets ``D_s = sum_i D_i^2 = 0``.
    """
    m, n = jac.shape
    turn = direction * rotation_factor_of(index, eps)
    rhs = np.zeros(n)  # [t'; 0]
    for r in range(m):
        rhs[r] = twist[r] * turn if modify_rotation and r >= 3 else twist[r]
    scale = direction * twist_scale_of(index, eps)  # b_ep g(D_e), [003 eq. 22]
    for r in range(m):
        target[r] = scale * rhs[r]
    if abs(index) >= near_zero:
        # J^+ (b_ep g t'), [003 eqs. 18, 21]; int(): not a literal, so the batch's compiled least_squares_one serves
        least_squares_one(jac, target, 0.0, 0.0, int(CONSTANT), MACHINE_EPSILON, qdot)
    else:
        d_s = 0.0
        for i in range(n):
            d_s += factors[i] * factors[i]  # [003 eq. 20]
        if not d_s > 0.0:
            return False
        square = np.empty((n, n))
        for r in range(m):
            for c in range(n):
                square[r, c] = jac[r, c]
        for c in range(n):
            square[m, c] = factors[c] if c % 2 == 0 else -factors[c]
        adjugate_times(square, rhs, qdot)
        gain = direction * weight_of(index, eps) / d_s  # [003 eq. 21]: b_i = b_ep w(D_e) D_i / D_s
        for c in range(n):
            qdot[c] *= gain
    if self_motion != 0.0:  # [003 eq. 9]: b_sm n_sm, n_sm,i = (-1)^i det J_i [003 eqs. 4-5]
        minors = np.empty(n)
        column_minors_one(jac, minors)
        for c in range(n):
            qdot[c] += self_motion * (minors[c] if c % 2 == 0 else -minors[c])
    return True


# ------------------------------------------------------------ control loop
@kernel
def finite(values):
    """Whether every entry of ``values`` (1-D) is finite."""
    for value in values:
        if not (value - value == 0.0):  # NaN and +-inf give NaN
            return False
    return True


@kernel
def chain_jacobian(q, links, ends, standard, jac):
    """The tool Jacobian (6, n) of a chain's link table at ``q`` (:func:`~redkin._chain_kernels.jacobian_one`)."""
    tool = bool(True)  # noqa: UP018 - not the literal True: the chain's compiled jacobian_one (a bool) serves
    _chain_kernels.jacobian_one(q, links, ends, standard, links.shape[0], tool, np.zeros(3),
                               np.empty((links.shape[0], 2)), jac)


@kernel
def sc_control(q, twist, links, ends, standard, index, factors, eps, direction, self_motion, modify_rotation,
               near_zero, jac, qdot, target):
    """One control step of the SC method: checks, the chain's Jacobian into ``jac`` and :func:`sc_one`.

    Returns :data:`DONE`, :data:`Q_NOT_FINITE`, :data:`TWIST_NOT_FINITE` or
    :data:`NO_FACTORS` (``D_s = 0`` on the exact path).
    """
    if not finite(q):
        return Q_NOT_FINITE
    if not finite(twist):
        return TWIST_NOT_FINITE
    chain_jacobian(q, links, ends, standard, jac)
    if not sc_one(jac, twist, index, factors, eps, direction, self_motion, modify_rotation, near_zero, qdot, target):
        return NO_FACTORS
    return DONE


@kernel
def pinv_control(q, twist, links, ends, standard, rcond, jac, qdot):
    """One control step of the pseudoinverse: checks, the chain's Jacobian into ``jac`` and ``J^+ v`` into ``qdot``."""
    if not finite(q):
        return Q_NOT_FINITE
    if not finite(twist):
        return TWIST_NOT_FINITE
    chain_jacobian(q, links, ends, standard, jac)
    least_squares_one(jac, twist, 0.0, 1.0, int(CONSTANT), rcond, qdot)  # int(): as in sc_one
    return DONE


# ------------------------------------------------------------------- batches
# Loops over items start..stop - 1 of the leading axis (redkin._compiled.run_batch hands out the chunks).
@kernel
def least_squares(start, stop, jac, twist, max_damping, threshold, measure, rcond, out, lam):
    """:func:`least_squares_one` for items ``start .. stop - 1``: ``J`` of ``jac`` (N, m, n) and ``v`` of ``twist``
    (N, m); ``out`` (N, n), ``lam`` (N,)."""
    for b in range(start, stop):
        lam[b] = least_squares_one(jac[b], twist[b], max_damping, threshold, measure, rcond, out[b])


@kernel
def sc(start, stop, jac, twist, index, factors, eps, direction, self_motion, modify_rotation, near_zero, qdot, target,
       ok):
    """:func:`sc_one` for items ``start .. stop - 1``: ``jac`` (N, m, n), ``twist`` (N, m), ``index`` (N,),
    ``factors`` (N, n); ``ok`` (N,)."""
    for b in range(start, stop):
        ok[b] = sc_one(jac[b], twist[b], index[b], factors[b], eps, direction, self_motion, modify_rotation,
                       near_zero, qdot[b], target[b])


@kernel
def column_minors(start, stop, jac, out):
    """:func:`column_minors_one` for items ``start .. stop - 1`` of ``jac`` (N, m, m + 1); ``out`` (N, m + 1)."""
    for b in range(start, stop):
        column_minors_one(jac[b], out[b])
