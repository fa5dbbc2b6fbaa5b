"""Closed-form inverse kinematics of Franka-class arms at a given q7 (docs/franka.md, [F1]-[F7]).

With q7 fixed, the flange pose fixes frame 6 and the wrist point W [F1];
``|W - S|`` fixes q4 up to two elbow solutions [F2]-[F3]; the shoulder
point seen from frame 6 fixes q5 up to two wrist solutions and then q6
[F4]-[F6]; the shoulder's rotation gives q1-q3 up to the two solutions of a
spherical shoulder [F7].  So a pose and q7 have at most 2 x 2 x 2 = 8
solutions, named by three signs (:data:`BRANCHES`):

* shoulder -- the sign of ``q_2`` where the description's ``q_2 = 0`` is the shoulder singularity (as in every
  maker's description we know); precisely, the sign of ``sin theta_2`` in the solver's form, turned over where that
  form's zero of joint 2 is nearer ``theta = pi`` (:attr:`FrankaGeometry.branch_senses`);
* elbow -- the sign of ``theta_4 - phi``, on either side of the elbow angle ``phi`` of the longest reach
  (``|W - S|`` largest), as on an offset-elbow S-R-S arm;
* wrist -- the sign of ``cos q_5`` likewise (precisely of ``cos theta_5``, turned over in the same way).

A branch may not exist at a given pose and q7 (the elbow cannot span ``|W
- S|``, or the wrist cannot turn the shoulder point into place); that is a
value (``exists`` false), not an error.  Solutions are returned whether or
not they lie within the joint limits; ``within_limits`` says which do.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from redkin._compiled import kernel_array, run_batch
from redkin._validation import as_float_array, check_finite, check_pose
from redkin.chain import Reach, SerialChain
from redkin.errors import RedkinError
from redkin.franka import _kernels
from redkin.franka.geometry import AMPLITUDE, MEAN, FrankaGeometry, franka_geometry
from redkin.srs.branches import BRANCHES, Branch

#: The parameter of the Franka class's solutions, as results and the command line name it.
PARAMETER = "q7"
#: Slack of :func:`reach` on ``|W - S|^2``, relative to ``R`` of [F2]: the solver's own (``1e-12``) and far more, so
#: that a pose :func:`reach` puts out has no elbow at any q7 in the solver too.
_REACH_SLACK = 1e-9


class Q7Solutions(NamedTuple):
    """The solutions of poses at values of q7.

    Attributes
    ----------
    q : numpy.ndarray, shape (..., B, 7)
        Joint values in the chain's conventions, one row per branch of ``branches``
        (zeros where the branch does not exist).
    exists : numpy.ndarray of bool, shape (..., B)
    within_limits : numpy.ndarray of bool, shape (..., B)
        Exists and lies within the chain's joint limits, with a slack of 1e-12 rad (rounding).
    branches : tuple of Branch
    parameter : str
        ``"q7"``: the redundancy parameter these solutions are a function of.
    """

    q: np.ndarray
    exists: np.ndarray
    within_limits: np.ndarray
    branches: tuple[Branch, ...]
    parameter: str = PARAMETER


def as_franka(arm: SerialChain | FrankaGeometry) -> FrankaGeometry:
    """The :class:`FrankaGeometry` of a chain (derived once and cached on it), or the geometry itself.

    Raises
    ------
    NotArmAngleClassError
        If the chain is not of the Franka class, naming the condition it breaks.
    """
    return arm if isinstance(arm, FrankaGeometry) else franka_geometry(arm)


def frames_seven(geometry: FrankaGeometry, pose: ArrayLike) -> np.ndarray:
    """Validated target poses ``(..., 4, 4)`` as frame 7 of the solver's form in its frame 0 (``base^-1 pose
    tool^-1``), computed as the solver computes it (:func:`redkin.franka._kernels.seventh_frames`): a q7 at the end
    of a feasible arc, where the branch's existence turns on rounding, then has the solution the sets found.

    The poses are checked in the kernel (:func:`redkin._pose_kernels.pose_defect`); where it refuses one,
    :func:`redkin._validation.check_pose` words the error (and passes a pose it refuses only by rounding at the
    tolerance)."""
    pose = as_float_array(pose, "pose")
    if pose.ndim < 2 or pose.shape[-2:] != (4, 4):
        check_pose(pose)  # the words of a malformed shape
    flat = np.ascontiguousarray(pose.reshape(-1, 4, 4))
    frames = np.empty_like(flat)
    if run_batch(_kernels.seventh_frames, len(flat), flat, geometry.kernel_ends, frames):
        check_pose(pose)
    return frames.reshape(pose.shape)


def ik(
    arm: SerialChain | FrankaGeometry,
    pose: ArrayLike,
    q7: ArrayLike,
    branch: str | Branch | tuple[int, int, int] | None = None,
) -> Q7Solutions:
    """Every solution (or one branch's) of target poses at values of joint 7 [F1]-[F7].

    Parameters
    ----------
    arm : SerialChain or FrankaGeometry
        A Franka-class arm (:func:`redkin.franka.franka_geometry`).
    pose : array_like, shape (..., 4, 4)
        Target poses of the chain's tool frame in its base frame.
    q7 : array_like, shape (...)
        Values of joint 7 in the chain's conventions (radians), broadcast against the poses' batch shape.
    branch : str or Branch, optional
        One branch (``"+-+"``: signs of shoulder, elbow, wrist; module
        docstring); default all eight, in the order of :data:`BRANCHES`.

    Returns
    -------
    Q7Solutions
        With ``B = 8``, or ``B = 1`` for one branch.

    Raises
    ------
    ValueError
        For a chain not of the Franka class, a malformed pose (shape, NaN, a
        rotation that is not orthonormal), a non-finite q7 or a malformed branch.
    """
    geometry = as_franka(arm)
    if branch is None:
        chosen, first = BRANCHES, 0
    else:
        first = geometry.branch_index(branch)
        chosen = (BRANCHES[first],)
    if type(pose) is not np.ndarray or pose.dtype != np.float64:  # a float64 array is taken as it is
        pose = as_float_array(pose, "pose")
    if pose.ndim < 2 or pose.shape[-2:] != (4, 4):
        raise RedkinError(f"pose must have shape (..., 4, 4), got shape {pose.shape}")
    # a float q7 is passed as it is, anything else converted once (on one pose the conversions took a third of the
    # call's time)
    q7 = q7 if isinstance(q7, float) else as_float_array(q7, "q7")
    if pose.ndim == 2 and (isinstance(q7, float) or q7.ndim == 0):  # one pose: no batch to lay out, the tables in
        # one argument
        q = np.empty((len(chosen), 7))
        flags = np.empty((2, len(chosen)), dtype=bool)
        if _kernels.solve_single(kernel_array(pose), float(q7), geometry.kernel_table, first, len(chosen), q,
                                 flags) != _kernels.OK:
            _raise_for(pose, np.asarray(q7))
        return Q7Solutions(q, flags[0], flags[1], chosen)
    q7 = np.asarray(q7)  # a float, for the batch's broadcasting
    tables = (geometry.kernel_arm, geometry.kernel_ends, geometry.kernel_branches[first:first + len(chosen)],
              geometry.kernel_joints)
    try:
        shape = np.broadcast_shapes(pose.shape[:-2], q7.shape)
    except ValueError:
        raise RedkinError(f"q7 of shape {q7.shape} does not broadcast against the pose batch "
                          f"{pose.shape[:-2]}") from None
    count = int(np.prod(shape, dtype=np.int64))
    poses = kernel_array(pose, shape + (4, 4)).reshape(count, 4, 4)
    values = kernel_array(q7, shape).reshape(count)
    q = np.empty((count, len(chosen), 7))
    exists = np.empty((count, len(chosen)), dtype=bool)
    within = np.empty((count, len(chosen)), dtype=bool)
    if run_batch(_kernels.solve_poses, count, poses, values, *tables, q, exists, within):
        _raise_for(pose, q7)
    return Q7Solutions(q.reshape(shape + q.shape[1:]), exists.reshape(shape + (len(chosen),)),
                       within.reshape(shape + (len(chosen),)), chosen)


def reach(arm: SerialChain | FrankaGeometry, pose: ArrayLike) -> Reach:
    """The shoulder-wrist distance ``|W - S|`` of target poses over every q7, against the elbow's range [F1]-[F2].

    Turning q7 moves W on a circle about axis 7: ``W = O_7 - R_07 Rz(-theta_7) (a_6, d_6, 0)``, of radius ``rho_W =
    hypot(a_6, d_6)`` about the flange origin ``O_7`` in the plane normal to ``z_7`` [F1].  With ``h`` the height of
    ``S - O_7`` along ``z_7`` and ``rho`` its distance from the axis, ``|W - S|`` runs over ``[sqrt(h^2 + (rho -
    rho_W)^2), sqrt(h^2 + (rho + rho_W)^2)]``; the elbow spans ``[sqrt(C - R), sqrt(C + R)]`` [F2].  Where the two
    do not meet, no q7 has a solution.

    Parameters
    ----------
    arm : SerialChain or FrankaGeometry
    pose : array_like, shape (..., 4, 4)

    Returns
    -------
    Reach
        ``distance`` the value of ``|W - S|`` over q7 nearest the elbow's range (its least where beyond the
        reach, its greatest where inside the shortest); ``out`` where they do not meet by more than rounding.

    Raises
    ------
    ValueError
        For a chain not of the Franka class or a malformed pose.
    """
    geometry = as_franka(arm)
    t07 = frames_seven(geometry, pose)
    offset = t07[..., :3, 3] - np.array([0.0, 0.0, geometry.d1])
    height = np.einsum("...i,...i->...", offset, t07[..., :3, 2])
    across = np.sqrt(np.maximum(np.einsum("...i,...i->...", offset, offset) - height * height, 0.0))
    circle = float(np.hypot(geometry.a6, geometry.d6))
    nearest = np.hypot(height, across - circle)
    farthest = np.hypot(height, across + circle)
    mean, amplitude = geometry.kernel_arm[MEAN], geometry.kernel_arm[AMPLITUDE]
    lower, upper = float(np.sqrt(max(mean - amplitude, 0.0))), float(np.sqrt(mean + amplitude))
    slack = _REACH_SLACK * amplitude
    out = (nearest * nearest > mean + amplitude + slack) | (farthest * farthest < mean - amplitude - slack)
    return Reach(np.minimum(np.maximum(lower, nearest), farthest), lower, upper, out,
                 "the shoulder-wrist distance at the most favourable q7")


def _raise_for(pose: np.ndarray, q7: np.ndarray) -> None:
    """Raise the error of a batch the kernels flagged: a q7 that is not finite, then a malformed pose."""
    check_finite(q7, "q7")
    check_pose(pose)
    raise RedkinError("pose must be finite with a proper rotation block and last row [0, 0, 0, 1]")
