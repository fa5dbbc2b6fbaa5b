"""A witness for an arm angle of a nearly S-R-S arm's feasible set: a certified solution of the branch within the
limits, found along the pose's self-motion (tests of :mod:`redkin.srs.nearly.feasible` and
:mod:`redkin.srs.nearly.self_motion`)."""

from __future__ import annotations

import numpy as np

from redkin.srs import BRANCHES, self_motion
from redkin.srs.branches import parse_branch
from redkin.srs.nearly import arm_angle, branch_of, ik

#: The self-motion's step [rad] (``self_motion``'s default).
STEP = 0.05
#: Starts of the walk to an arm angle lie at least this far apart [rad]: the points of a curve cluster where it
#: meets a limit, and the nearest in arm angle may all lie on one side of a fold.
APART = 1e-3


def _wrapped(angles):
    return np.angle(np.exp(1j * np.asarray(angles)))


def _pose_residual(arm, q: np.ndarray, pose: np.ndarray) -> np.ndarray:
    """Position and (small) rotation error of our FK of ``q`` against ``pose``, world-referred."""
    reached = arm.chain.fk(q)
    turn = pose[:3, :3] @ reached[:3, :3].T
    return np.concatenate([pose[:3, 3] - reached[:3, 3],
                           0.5 * np.array([turn[2, 1] - turn[1, 2], turn[0, 2] - turn[2, 0], turn[1, 0] - turn[0, 1]])])


def _along_to(arm, pose: np.ndarray, q: np.ndarray, psi: float) -> np.ndarray:
    """From the solution ``q``, Newton's steps in the arm angle along the self-motion (the null vector of our
    Jacobian, the arm angle's rate by central differences), each followed by Gauss-Newton steps back onto the pose:
    stays on the curve through ``q``, where a Newton solve of the seven equations at once may jump across a nearby
    branch boundary."""
    q = q.copy()
    for _ in range(40):
        for _ in range(4):
            q = q + np.linalg.pinv(arm.chain.jacobian(q)) @ _pose_residual(arm, q, pose)
        off = float(_wrapped(psi - arm_angle(arm, q)))
        if abs(off) < 1e-12:
            break
        direction = np.linalg.svd(arm.chain.jacobian(q))[2][-1]
        rate = float(_wrapped(arm_angle(arm, q + 1e-7 * direction) - arm_angle(arm, q - 1e-7 * direction))) / 2e-7
        q = q + np.clip(off / rate, -0.01, 0.01) * direction
    return q


def witnessed(arm, pose: np.ndarray, branch: str, psi: float) -> bool:
    """Whether a certified solution of the branch within the limits at the arm angle ``psi`` is found from the pose's
    self-motion: from points of the curves through ``nearly.ik``'s solutions on 72 arm angles that lie on the branch
    and within the limits, nearest in arm angle first and farther than :data:`APART` from each other (twelve),
    :func:`_along_to` ``psi``, checked with our FK, arm angle, branch and limits."""
    row = BRANCHES.index(parse_branch(branch))
    grid = np.linspace(-np.pi, np.pi, 72, endpoint=False)
    solved = ik(arm, np.broadcast_to(pose, grid.shape + (4, 4)), grid, branch)
    curves = []
    for q in solved.q[solved.exists[:, 0], 0]:
        if not any(np.linalg.norm(_wrapped(curve.q - q), axis=-1).min() < STEP for curve in curves):
            curves.append(self_motion(arm, pose, q, step=0.01))
    points = np.concatenate([curve.q for curve in curves])
    good = (branch_of(arm, points) == row) & arm.chain.within_limits(points, wrap=True)
    order = np.argsort(np.abs(_wrapped(arm_angle(arm, points) - psi)))
    starts: list[np.ndarray] = []
    for k in order[good[order]]:  # nearest in arm angle first, one per place on the curves (points cluster at events)
        if all(np.linalg.norm(_wrapped(points[k] - start)) > APART for start in starts):
            starts.append(points[k])
            if len(starts) == 12:
                break
    for start in starts:
        q = _along_to(arm, pose, start, psi)
        if (np.abs(arm.chain.fk(q) - pose).max() < 1e-9 and abs(_wrapped(arm_angle(arm, q) - psi)) < 1e-9
                and branch_of(arm, q) == row and arm.chain.within_limits(q, wrap=True)):
            return True
    return False


#: Residual [m, rad] of an exact solution: what Newton's steps reach at a solution that exists, and do not near the
#: end of a branch at a fold, where a certificate of 1e-9 accepts joint values up to about 1e-6 rad of arm angle beyond
#: where the self-motion turns back (a small singular value of the seven equations).
EXACT = 1e-12


def exact(arm, pose: np.ndarray, q: np.ndarray, psi: float) -> bool:
    """Whether Levenberg-Marquardt steps (:func:`redkin.srs.nearly.search.polished`) from the certified solution
    ``q`` at the arm angle ``psi`` reach a solution to :data:`EXACT` (our FK and arm angle) on the same branch (next
    to the stretched elbow a certified row can lie across the branch boundary from the exact solution)."""
    from redkin.srs.nearly.search import polished

    polished_q = polished(arm, q[None], pose, lambda values: arm_angle(arm, values), psi)[0][0]
    return bool(np.abs(_pose_residual(arm, polished_q, pose)).max() <= EXACT
                and abs(_wrapped(arm_angle(arm, polished_q) - psi)) <= EXACT
                and branch_of(arm, polished_q) == branch_of(arm, q))
