"""Adjugate (pseudoinverse-based) singularity-consistent direction (paper 003 section 2.2, [003 eqs. 12-14]).

``n_pi = J^T adj(J J^T) t`` [003 eq. 12] is the minimum-norm end-point vector:
``J n_pi = det(J J^T) t`` [003 eq. 13], so it has no algorithmic singularity --
``det(J J^T) = 0`` only at true singularities.  But there
``J^T adj(J J^T) = 0`` [003 eq. 14]: the joint velocity vanishes and the arm
cannot leave the singularity.  By Cauchy-Binet it equals the weighted sum of
[003 eq. 15] with ``b_i = det J_i`` [003 eq. 17].
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from redkin._validation import check_jacobian_and_twist
from redkin.velocity.cofactors import adjugate


def adjugate_direction(jacobian: ArrayLike, twist: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
    """``n_pi = J^T adj(J J^T) t`` and the twist size ``det(J J^T)`` [003 eqs. 12-13].

    Returns
    -------
    direction : numpy.ndarray, shape (..., n)
    size : numpy.ndarray, shape (...)
        ``J n_pi = size * t``.
    """
    jac, vel = check_jacobian_and_twist(jacobian, twist)
    gram = jac @ np.swapaxes(jac, -1, -2)
    direction = np.einsum("...ji,...jk,...k->...i", jac, adjugate(gram), vel)
    return direction, np.linalg.det(gram)
