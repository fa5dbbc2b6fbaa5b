"""What every arm-angle function does at its public edge: the arm, the poses and psi checked, and the
error of a batch the kernels flagged (private to :mod:`redkin.srs`).

The kernels of :mod:`redkin.srs._ik_kernels` check each pose themselves
(:func:`redkin._pose_kernels.pose_defect`) and report a status; only a
batch with a flagged pose comes here for the words of its error.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from redkin._validation import as_float_array, check_finite, check_pose
from redkin.chain import SerialChain
from redkin.errors import RedkinError, UnreachablePoseError
from redkin.srs import _ik_kernels
from redkin.srs.geometry import SRSGeometry, srs_geometry


def as_geometry(arm: SerialChain | SRSGeometry) -> SRSGeometry:
    """An :class:`SRSGeometry` from a chain (checked, derived once per chain) or a geometry (as is)."""
    return arm if isinstance(arm, SRSGeometry) else srs_geometry(arm)


def check_psi(psi: ArrayLike) -> np.ndarray:
    """Arm angles as a finite float array."""
    array = as_float_array(psi, "psi")
    check_finite(array, "psi")
    return array


def _unreachable_error(geometry, distance: np.ndarray, reach: np.ndarray) -> UnreachablePoseError | None:
    """The error naming the first pose whose wrist is out of reach, or ``None``.

    ``distance`` is ``|x_sw|`` and ``reach`` whether [000 eq. 11] has a solution, batched.
    """
    bad = ~reach
    if not bad.any():
        return None
    index = tuple(int(i) for i in np.unravel_index(int(np.argmax(bad)), bad.shape))
    count = int(bad.sum())
    where = f" (pose {index}; {count} unreachable)" if bad.ndim else ""
    mean, amplitude, _ = geometry.elbow_equation
    return UnreachablePoseError(
        f"unreachable position: shoulder-wrist distance {float(distance[index]):.6g} m must lie in "
        f"[{np.sqrt(max(mean - amplitude, 0.0)):.6g}, {np.sqrt(mean + amplitude):.6g}] m{where}",
        index=index, count=count,
    )


def as_poses(pose: ArrayLike) -> np.ndarray:
    """``pose`` as a float array of shape ``(..., 4, 4)`` (its values are checked by the kernels)."""
    array = as_float_array(pose, "pose")
    if array.ndim < 2 or array.shape[-2:] != (4, 4):
        raise RedkinError(f"pose must have shape (..., 4, 4), got shape {array.shape}")
    return array


def raise_for_bad_pose(pose: np.ndarray, status: np.ndarray) -> None:
    """Raise the ``ValueError`` of :func:`redkin._validation.check_pose` if the kernels flagged a pose
    (:data:`redkin.srs._ik_kernels.BAD_POSE`)."""
    if (status == _ik_kernels.BAD_POSE).any():
        check_pose(pose)
        raise RedkinError("pose must be finite with a proper rotation block and last row [0, 0, 0, 1]")


def raise_for_status(geometry, pose: np.ndarray, status: np.ndarray, distance: np.ndarray) -> None:
    """Raise the ``ValueError`` of the first failing check of a batch the kernels flagged:
    :func:`raise_for_bad_pose`, then :func:`_unreachable_error`."""
    raise_for_bad_pose(pose, status)
    error = _unreachable_error(geometry, distance, status != _ik_kernels.UNREACHABLE)
    if error is not None:
        raise error
