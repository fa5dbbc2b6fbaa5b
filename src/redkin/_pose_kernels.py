"""The compiled check that a 4x4 array is a pose, shared by the kernels that take target poses.

Kept apart from the solvers' packages so that any kernel module may import it without loading a package (the
numerical IK's kernels and the S-R-S kernels use each other's pieces).
"""

from __future__ import annotations

from math import isfinite

from redkin._compiled import kernel
from redkin._constants import MAX_LENGTH

#: Tolerance of the pose check (:data:`redkin._validation.ROTATION_TOLERANCE`).
POSE_TOLERANCE = 1e-6
#: What :func:`pose_defect` returns.
OK, BAD_POSE = 0, 1


@kernel
def pose_defect(pose):
    """:data:`OK`, or :data:`BAD_POSE` for a pose that is not finite, whose translation is farther than
    :data:`~redkin._constants.MAX_LENGTH` in a coordinate, whose last row is not ``0 0 0 1`` or whose rotation block
    is not a proper rotation within :data:`POSE_TOLERANCE` (the checks of :func:`redkin._validation.check_pose`,
    which words the error)."""
    for r in range(4):
        for c in range(4):
            if not isfinite(pose[r, c]):
                return BAD_POSE
    for r in range(3):
        if abs(pose[r, 3]) > MAX_LENGTH:
            return BAD_POSE
    for c in range(4):
        if abs(pose[3, c] - (1.0 if c == 3 else 0.0)) > POSE_TOLERANCE:
            return BAD_POSE
    for r in range(3):
        for c in range(3):
            dot = pose[r, 0] * pose[c, 0] + pose[r, 1] * pose[c, 1] + pose[r, 2] * pose[c, 2]
            if abs(dot - (1.0 if r == c else 0.0)) > POSE_TOLERANCE:
                return BAD_POSE
    # orthonormal within the tolerance, |det| is 1 within about 4.5 times it: its sign alone tells a rotation from a
    # reflection (as check_pose tests it; |det - 1| <= tolerance refused rotations check_pose accepts)
    det = (pose[0, 0] * (pose[1, 1] * pose[2, 2] - pose[1, 2] * pose[2, 1])
           - pose[0, 1] * (pose[1, 0] * pose[2, 2] - pose[1, 2] * pose[2, 0])
           + pose[0, 2] * (pose[1, 0] * pose[2, 1] - pose[1, 1] * pose[2, 0]))
    return OK if det > 0.0 else BAD_POSE
