"""Arm-angle inverse kinematics of S-R-S arms (paper 000 section 3.3, [000 eqs. 11-19]).

Given a pose and an arm angle ``psi``, each of the eight branches (signs of
theta_2, theta_4, theta_6) has exactly one joint vector.  Everything is
batched over leading axes of the pose and computed by the compiled kernels
of :mod:`redkin.srs._ik_kernels`.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from redkin._compiled import kernel_array, run_batch
from redkin._validation import as_float_array, check_output_array
from redkin.chain import Reach, SerialChain
from redkin.errors import RedkinError
from redkin.srs import _ik_kernels
from redkin.srs._targets import as_geometry, as_poses, check_psi, raise_for_bad_pose, raise_for_status
from redkin.srs.branches import Branch
from redkin.srs.coefficients import ArmAngleCoefficients, coefficient_arrays
from redkin.srs.geometry import SRSGeometry


def reach(arm: SerialChain | SRSGeometry, pose: ArrayLike) -> Reach:
    """The shoulder-wrist distance ``|x_sw|`` of target poses against the range [000 eq. 11] allows.

    The wrist point of a pose does not depend on the arm angle, and ``|x_sw|^2 = C + R cos(theta_4 - phi)``
    [000 eq. 11], so a pose whose ``|x_sw|`` lies outside ``[sqrt(C - R), sqrt(C + R)]`` (``[|d_se - d_ew|,
    d_se + d_ew]`` without elbow offsets) has no solution at any arm angle on any branch.

    Parameters
    ----------
    arm : SerialChain or SRSGeometry
    pose : array_like, shape (..., 4, 4)

    Returns
    -------
    Reach
        ``out`` exactly where the closed form has no solution (the rounding slack
        :data:`redkin.srs._ik_kernels.REACH_TOLERANCE` on ``cos(theta_4 - phi)``).

    Raises
    ------
    ValueError
        For a malformed pose.
    """
    geometry = as_geometry(arm)
    pose = as_poses(pose)
    _, status, distance = coefficient_arrays(geometry, pose, 1)
    raise_for_bad_pose(pose, status)
    mean, amplitude, _ = geometry.elbow_equation
    return Reach(distance, float(np.sqrt(max(mean - amplitude, 0.0))), float(np.sqrt(mean + amplitude)),
                 status == _ik_kernels.UNREACHABLE, "the shoulder-wrist distance")


def reachable(arm: SerialChain | SRSGeometry, pose: ArrayLike) -> np.ndarray:
    """Which target poses put the wrist within reach of the elbow ([000 eq. 11] has a solution; :func:`reach`).

    The arm-angle functions raise :class:`redkin.errors.UnreachablePoseError`
    (a ``ValueError``) for a batch holding an unreachable pose; filter the batch with this mask first, e.g.
    ``ok = reachable(arm, poses); q = ik(arm, poses[ok], psi)``.

    Parameters
    ----------
    arm : SerialChain or SRSGeometry
    pose : array_like, shape (..., 4, 4)

    Returns
    -------
    numpy.ndarray of bool, shape (...)
        True where ``|x_sw|`` lies in ``[|d_se - d_ew|, d_se + d_ew]``, or for an
        offset elbow in ``[sqrt(C - R), sqrt(C + R)]`` (with the rounding slack
        :data:`redkin.srs._ik_kernels.REACH_TOLERANCE` on ``cos(theta_4 - phi)``).

    Raises
    ------
    ValueError
        For a malformed pose.
    """
    return ~reach(arm, pose).out


def theta_at(coefficients: ArmAngleCoefficients, psi: ArrayLike, branch: Branch) -> np.ndarray:
    """The 7 DH angles ``(..., 7)`` at arm angles ``psi`` for one branch [000 eqs. 11, 13-15, 17-19].

    ``psi`` broadcasts against the batch shape of ``coefficients``
    (:func:`redkin.srs._ik_kernels.branch_angles`).
    """
    psi = np.asarray(psi, dtype=float)
    shape = np.broadcast_shapes(coefficients.theta4.shape, psi.shape)
    entries = kernel_array(coefficients.entries, shape + coefficients.entries.shape[-2:])
    entries = entries.reshape((-1,) + entries.shape[-2:])
    count = len(entries)  # not .shape[0]: numpy's stubs type this reshape's result as 0-d
    theta4 = kernel_array(coefficients.theta4, shape).reshape(count)
    psi = kernel_array(psi, shape).reshape(count)
    signs = np.broadcast_to(np.array([[branch.shoulder, branch.wrist]], dtype=float), (count, 2))
    theta = np.empty((count, 7))
    run_batch(_ik_kernels.angles_at, count, entries, theta4, psi, kernel_array(signs), theta)
    return theta.reshape(shape + (7,))


def solve_with_status(geometry: SRSGeometry, pose: ArrayLike, psi: ArrayLike, branches: np.ndarray,
                      out: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Joint values ``(..., B, 7)`` of the chain for Table 1 branch signs ``branches`` (B, 3), whether each row lies
    within the limits ``(..., B)``, each pose's status ``(...)`` (:data:`redkin.srs._ik_kernels.OK` or
    :data:`~redkin.srs._ik_kernels.UNREACHABLE`: the rows of an unreachable pose are meaningless) and the validated
    poses ``(..., 4, 4)``.

    One compiled call per batch (:func:`redkin.srs._ik_kernels.solve_poses`): the pose and psi checks, [000 eqs.
    4-19], the chain's joint values and their limits.  Only a batch the kernel flags goes through the slower checks
    that word the error.  The joint values are written into ``out`` where given (:func:`ik_all_branches`), and the
    first value returned is then ``out`` itself.

    Raises
    ------
    RedkinError
        For a malformed pose or psi, or an ``out`` that cannot hold the joint values (a ``ValueError``).
    """
    pose = as_poses(pose)
    psi_array = as_float_array(psi, "psi")
    shape = pose.shape[:-2]
    if psi_array.shape != shape:
        try:
            shape = np.broadcast_shapes(shape, psi_array.shape)
        except ValueError:
            raise RedkinError(f"psi of shape {psi_array.shape} does not broadcast against the pose batch "
                             f"{pose.shape[:-2]}") from None
    rows = shape + (branches.shape[0], 7)
    q = np.empty(rows) if out is None else check_output_array(out, rows)
    if not shape:  # one pose: no batch to lay out
        pose, psi_array = kernel_array(pose), kernel_array(psi_array)
        within = np.empty(branches.shape[0], dtype=np.bool_)
        status = _ik_kernels.solve_single(pose, psi_array, branches, *geometry.kernel_tables, q, within)
        if status != _ik_kernels.OK and status != _ik_kernels.UNREACHABLE:
            _raise_for(geometry, pose, psi_array)
        return q, within, np.array(status), pose
    if pose.shape[:-2] != shape:
        pose = np.broadcast_to(pose, shape + (4, 4))
    psi_array = np.broadcast_to(psi_array, shape)
    poses = kernel_array(pose.reshape((-1, 4, 4)))  # a copy where a pose was broadcast
    angles = kernel_array(psi_array.reshape(-1))
    count = len(poses)  # not .shape[0]: numpy's stubs type this reshape's result as 0-d
    within = np.empty((count, branches.shape[0]), dtype=np.bool_)
    status = np.empty(count, dtype=np.int64)
    if run_batch(_ik_kernels.solve_poses, count, poses, angles, branches, *geometry.kernel_tables,
                 q.reshape((count,) + q.shape[-2:]), within, status) \
            and np.any((status != _ik_kernels.OK) & (status != _ik_kernels.UNREACHABLE)):
        _raise_for(geometry, pose, psi_array)
    return q, within.reshape(shape + branches.shape[:1]), status.reshape(shape), pose


def solve(geometry: SRSGeometry, pose: ArrayLike, psi: ArrayLike, branches: np.ndarray,
          out: np.ndarray | None = None) -> np.ndarray:
    """Joint values ``(..., B, 7)`` of the chain for Table 1 branch signs ``branches`` (B, 3), validated
    (:func:`solve_with_status`), written into ``out`` where given.

    Raises
    ------
    RedkinError
        For a malformed pose or psi (a ``ValueError``).
    UnreachablePoseError
        For a wrist position out of reach; its ``index`` names the first such pose of a batch.
    """
    q, _, status, pose = solve_with_status(geometry, pose, psi, branches, out)
    if np.any(status != _ik_kernels.OK):
        _raise_for(geometry, pose, np.asarray(psi, dtype=float))
    return q


def _raise_for(geometry: SRSGeometry, pose: np.ndarray, psi: np.ndarray) -> None:
    """Raise the error of a batch :func:`redkin.srs._ik_kernels.solve_poses` flagged: psi, then the poses."""
    check_psi(psi)
    _, flags, distance = coefficient_arrays(geometry, pose, 1)
    raise_for_status(geometry, pose, flags, distance)


def ik(
    arm: SerialChain | SRSGeometry,
    pose: ArrayLike,
    psi: ArrayLike,
    branch: str | Branch = "+++",
) -> np.ndarray:
    """Joint values reaching ``pose`` with arm angle ``psi`` on one branch.

    Parameters
    ----------
    arm : SerialChain or SRSGeometry
        A 7R arm whose shoulder and wrist axes meet in points (S-R-S, or an
        offset elbow): any description, converted once to paper 000's Table 1 form.
    pose : array_like, shape (..., 4, 4)
        Target poses of the tool in the base frame.
    psi : array_like, broadcastable to the batch shape
        Arm angles in radians (right-handed about shoulder -> wrist, [000 eq. 6]).
    branch : str or Branch
        Signs of theta_2, theta_4, theta_6, e.g. ``"+-+"``.

    Returns
    -------
    numpy.ndarray, shape (..., 7)
        Joint values ``q`` of the chain (each wrapped into its limit range
        when a multiple of 2 pi gets it there, else into ``[-pi, pi)``; in a
        range wider than 2 pi, the representative nearest the range's middle:
        ``arm.nearest_in_range(q, near=seed)`` picks the one nearest a seed).
        They may violate the limits: see :func:`redkin.srs.feasible_arm_angles`.

    Raises
    ------
    RedkinError
        For a malformed pose or psi (a ``ValueError``).
    UnreachablePoseError
        For a wrist position out of reach; its ``index`` names the first such pose of a batch.
    """
    geometry = as_geometry(arm)
    return solve(geometry, pose, psi, geometry.kernel_branch(branch))[..., 0, :]


def ik_all_branches(arm: SerialChain | SRSGeometry, pose: ArrayLike, psi: ArrayLike, *,
                    out: np.ndarray | None = None) -> np.ndarray:
    """Joint values of all eight branches, shape ``(..., 8, 7)`` in the order of :data:`BRANCHES`.

    ``psi`` broadcasts against the batch shape of ``pose``.  See :func:`ik`.
    Both elbow signs' frames [000 eqs. 4-12, 16] are computed once per pose and
    shared by their four branches.

    Parameters
    ----------
    arm, pose, psi
        As for :func:`ik`.
    out : numpy.ndarray, shape (..., 8, 7), optional
        A C-contiguous float64 array to write the joint values into, returned.  A loop that solves batch after
        batch of the same size into one buffer skips allocating (and the operating system's zeroing of) a fresh
        output every call: for 2·10^5 poses that is 90 MB, a third of the first call's time.

    Raises
    ------
    RedkinError
        For a malformed pose, psi or ``out`` (a ``ValueError``).
    UnreachablePoseError
        For a wrist position out of reach; its ``index`` names the first such pose of a batch.
    """
    geometry = as_geometry(arm)
    return solve(geometry, pose, psi, geometry.kernel_branches, out)
