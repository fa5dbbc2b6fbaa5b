"""Nearly S-R-S arm-angle IK (issue 27, item 6): redkin.srs.nearly.ik beside ssik 8.2's approximate-S-R-S solver.

Run: ``python benchmarks/bench_nearly.py`` (10^4 random poses and 10^3 near-singular poses per set and arm, about
three minutes with ssik); ``--poses N`` (random poses), ``--near M`` (poses per near-singular set), ``--arms``
(a subset of gen3, gen3-urdf, jaco2), ``--ssik-python K`` (poses for ssik's one-swivel Python call, 1000 by
default), ``--quick`` (200 random, 50 near, 20 for the Python call).  Prints the machine, one table per arm and the
issue's targets.  ``--feasible`` runs only the feasible-set check below (``--feasible-poses N`` random poses, 100
by default; ``--feasible-near M`` poses of each near-singular draw, 0 by default; ``--feasible-samples S``, 10^4 by
default; ``--feasible-arms``; ``--feasible-first K``; ``--feasible-no-ssik``).  At 10^5 arm angles the sampling
takes about 7-13 s per pose on 2 shared cores, and 30-110 s on a pose near the stretched elbow (``nearly.ik``
searching for the branches that do not exist there): ``--feasible-poses 16 --feasible-near 8 --feasible-samples
100000`` on the three arms took 44-50 minutes (benchmarks/README.md, issue 38).

The arms:

* ``gen3``: ``redkin.models.get_robot("kinova-gen3")``, the Gen3 in the User Guide's DH form with exact right
  angles.  Its poses differ from ssik's Gen3 by up to about 1.4e-5 m (printed): the maker's URDF writes pi/2 as
  1.5708 and pi as 3.1416, and ssik keeps those digits.  A pose is not a frame away from the other model's (the
  axes themselves differ by 7.3e-6 rad), so ssik's answers cannot be certified on this model at 1e-9: this arm
  is redkin's alone.
* ``gen3-urdf``: ``examples/gen3.urdf`` from ``base_link`` to ``end_effector_link``, the frames of ssik's
  ``ssik.prebuilt.kinova.gen3_ik`` (its FK equals ours to about 3e-15, checked and printed): the side-by-side arm.
  redkin classes it nearly S-R-S too (its departures include the rounding, 0.00021 deg off perpendicular).
* ``jaco2``: ``examples/jaco2.urdf`` from ``j2s7s300_link_base`` to ``j2s7s300_link_7``, the frames of ssik's
  ``j2s7s300_ik`` (FK equal to about 1e-15).  (ssik's ``jaco2_ik`` is the six-joint j2n6s200.)

Poses: FK of joint vectors drawn uniformly within the limits (an unlimited joint in [-pi, pi]) by one
``numpy.random.default_rng(1)`` per arm: the random set, then the set within 1 deg of the stretched elbow (q4 within
1 deg of the value where the neighbour's theta_4 is its elbow phase: 0 on the Gen3, pi on the Jaco2) and the set
within 1 deg of q3 = 0 (the user's joint value), the other joints uniform.

redkin: ``nearly.ik(arm, pose, psi)`` with ``arm = nearly_srs(chain)`` and ``psi = nearly.arm_angle(arm, q)`` of
the joint vector that made the pose; every branch (8 rows).  Timed one pose per call (``time.perf_counter`` around
each call: median and 99th percentile), at 16 arm angles in one call (ssik's sweep), and as one call on all the
random poses (best of 3, seconds per pose).  **Success** (the issue's): every branch that exists on the real arm at
the pose and its own arm angle is found and certified.  A row counts when it passes our own certificate (our FK
within 1e-9 m and 1e-9 rad of the pose, ``nearly.arm_angle`` within 1e-9 rad of psi: the certificate redkin states,
checked again here) and lies on its row's branch (the signs of the neighbour's theta_2, theta_4 minus the real arm's
stretched elbow, and theta_6 at the same joint values).  Which branches exist is decided independently of
``nearly.ik`` by an oracle (:func:`existing_branches`): damped Newton in numpy on the 7 equations, the arm angle by
``srs.arm_angle_of`` and its gradient by central differences, from 32 random joint vectors and 32 starts made from
the neighbour's closed form, each answer certified the same way; it runs on the poses where redkin returned fewer
than 8 rows, and q's own branch and every row that counts exist as well.  The misses are split by where the missed
solution (the oracle's) lies: the wrist near axis 1, the elbow near its stretch, theta_2 or theta_6 near 0 or pi.
Also counted: a row on q's own branch (one solution per branch: near the stretch or theta_2 = +-pi the real arm can
have two on one branch, and q itself need not be the one returned).

ssik 8.2 (``pip install ssik==8.2.*``; skipped with the reason when it does not import):

* Its redundancy parameter is the elbow's swivel angle: the angle of the elbow joint's origin about the line from
  its shoulder pivot to its wrist pivot, from the projection of the base's z axis (``ssik.chart``'s
  ``param_of``; ``ssik.solvers.seven_r.srs``).  That is the same kind of parameter as paper 000's arm angle with a
  different zero (the world's z instead of the reference plane of theta_3 = 0) and, on these arms, different
  pivots (ssik's least-squares near-intersections).  More to the point, ssik's approximate-S-R-S solver
  (``seven_r.srs_polished``) seeds its polish with the exact closed form of the snapped arm at the requested swivel
  angles and then runs Levenberg-Marquardt on the six pose equations only: the swivel angle is not held, so an
  answer lies on the self-motion near, not at, the requested angle (the drift is printed).  ssik has no call for
  the solutions at a given redundancy parameter of the real arm.
* Timed: its native C++ call for every solution of a pose, the prepared ``Solver`` that the artifact's
  ``solve(T)`` calls, with ``respect_limits=0`` (no joint-limit filter, as ours): 16 swivel angles x 8 branches,
  polished.  Its Python ``srs_polished.solve(kb, T, swivel_samples=[s])`` solves at one swivel angle (the native
  call takes no angle); it is timed on the first ``--ssik-python`` random poses, at ``s`` = ssik's swivel angle of
  the joint vector that made the pose, and its answers are compared with that joint vector.
* Success: every answer is judged by our FK (1e-9 m and 1e-9 rad).  Since ssik cannot be asked for q's own
  parameter, its comparable count is "q's branch found": a certified answer of the native sweep on q's Table 1
  branch (the branch signs of redkin's neighbour).  Also printed: the distinct branches among its certified
  answers per pose, beside redkin's certified rows.

**Feasible sets** (``--feasible``; issue 27's "feasible sets vs dense sampling" target, issue 38's certified sets):
the Gen3 (``examples/gen3.urdf`` as above), the Jaco2 (``examples/jaco2.urdf``) and the ROS-Industrial iiwa
(``examples/iiwa14_rosi.urdf``, base_link to tool0), with limits that cut the circle: the Gen3's and Jaco2's
continuous joints 1, 3, 5, 7 get +-2.9 rad for the check (:data:`CONTINUOUS_LIMIT`), the other joints and the
iiwa's keep their own.  Poses (:func:`feasible_draws`): FK of q uniform within those limits (``default_rng(3)``,
the sequence of the earlier runs), and with ``--feasible-near M``, M poses of each near-singular draw (issue 38's
"Done when"), q uniform within the limits and then one joint moved next to a singular value
(:func:`singular_values`, from ``arm.neighbour.offset``, ``.sign`` and ``arm.real_phase``): q6 within 1e-6..1e-3
rad of a value where the neighbour's theta_6 is 0 or pi (a straight wrist), q2 the same for theta_2 (a straight
shoulder), q4 within 1e-5..1e-2 rad of the real arm's stretched elbow (the distance ``10^u``, u uniform, either
sign).  Per pose:

* ``feasible_arm_angles_nearly_all(arm, pose)``, the 8 branches' certified sets from one self-motion, timed per
  pose (median, 90th percentile and largest per draw), and whether the self-motion was followed whole
  (``complete``; where not, a set may miss arcs of the curves not followed, and its missed runs are counted
  apart; a false run is a soundness bug everywhere);
* M uniform arm angles (``psi[0] = -pi``, spacing 2 pi / M), all 8 branches in one ``nearly.ik`` call per pose
  (it broadcasts one pose against an array of psi): a sample is feasible where the branch's row is marked found,
  passes our certificate (FK 1e-9 m and rad, ``nearly.arm_angle`` 1e-9 rad) and ``chain.within_limits`` modulo
  whole turns (the samples where this differs from ``nearly.ik``'s own flag are counted).  This is the
  independent check: nothing of the sets' self-motion is used;
* compared: runs of consecutive feasible samples outside the computed set (missed; 2 samples or more are an arc
  wider than the spacing, and any sample farther than 1e-6 rad from the set breaks the issue's target; a run
  within :data:`FOLD_SLACK` of the set's end whose row Newton's steps cannot take to rounding, :func:`exact_row`,
  is not a solution the set misses but the certificate's slack beyond a fold, and is counted apart, as is a run
  at any distance whose row :func:`row_leaves_branch` shows is no solution of its branch), runs of
  infeasible samples inside it (false, with the depth: distance from the set's nearest end; a run where the branch
  has a second solution within the limits, :func:`second_solution`, from ``branch_solutions`` on the pose's own
  curves, is counted apart, and so is a one-sample run at a set's end next to which, 1e-7 rad away, the branch has
  a solution within the limits, :func:`boundary_solution`: its solutions there run into a singular configuration
  exactly at that arm angle and the sample's own sign rounds to the other branch), and the ends
  of the computed arcs (agreeing when the sample just inside is feasible
  and the one just outside is not, i.e. the sampled boundary within one spacing).
* ssik 8.2 on the same poses, each call right after ours (:func:`load_ssik_feasible`; the Gen3 and the Jaco2,
  whose frames ssik ships): its native C++ solver as in the IK part (``Solver.solve(T, respect_limits=0)``), and
  its feasible-swivel arcs (``_swivel_limits._branch_arcs`` over ``_enumerate_branches`` of its best-fit S-R-S
  arm, with our limits).  ssik has no feasible set of the real arm for these approximate-S-R-S arms:
  ``ssik.chart.charts`` refuses ``seven_r.srs_polished``, and its in-limits fallback seeds LM from these arcs.

Each flagged run (up to :data:`CLASSIFIED` per arm: false runs first, then missed runs) is printed with its draw,
pose index, branch, psi and the pose's q (the pose is FK(q) of the limited chain), how it is counted,
``nearly.ik``'s row there, the oracle's (:func:`existing_branches`) solution of the branch and whether it lies
within the limits (an infeasible sample the oracle finds feasible is ``nearly.ik`` missing the branch, not the
set), where the solution lies (:func:`where_solutions_lie`) and the distance to the branch's nearest singular arm
angle (``singular_arm_angles_nearly``).

Times are per call, failures included.  The machine may be shared: the load average is printed at the start and
the end.
"""

from __future__ import annotations

import argparse
import inspect
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np
from timing import load_average, machine_lines  # benchmarks/timing.py (the script's folder is on sys.path)

from redkin import thread_count
from redkin.chain import SerialChain
from redkin.circle import ArcSet
from redkin.models import get_robot
from redkin.srs import (
    BRANCHES,
    NearlyFeasible,
    NearlySolutions,
    NearlySRS,
    SelfMotion,
    arm_angle_of,
    branch_solutions,
    feasible_arm_angles,
    feasible_arm_angles_nearly_all,
    nearly,
    nearly_srs,
    reachable,
    singular_arm_angles_nearly,
    srs_geometry,
)
from redkin.srs import ik as exact_ik
from redkin.srs.nearly.search import polished
from redkin.urdf import load_urdf

BRANCH_NAMES = tuple(str(b) for b in BRANCHES)
EXAMPLES = Path(__file__).resolve().parents[1] / "src" / "redkin" / "examples"
#: The certificate: position [m], rotation angle [rad] and arm angle [rad].
TOLERANCE = 1e-9
#: A returned row "is" the joint vector that made the pose when every joint is this close (radians, modulo 2 pi).
SAME = 1e-6
#: Half-width of the near-singular sets [rad].
NEAR = np.radians(1.0)
#: ssik's native sweep: swivel angles per pose (its default; the native call takes no angle).
SSIK_SWEEP = 16


class Arm(NamedTuple):
    description: str
    load: Callable[[], SerialChain]
    ssik: str  # the ssik.prebuilt.kinova module whose frames equal ours, or "" when there is none
    reference: str  # the ssik module to compare the FK with (printed), for an arm whose model differs


ARMS = {
    "gen3": Arm('redkin.models.get_robot("kinova-gen3") (DH, exact right angles)',
                lambda: get_robot("kinova-gen3"), "", "gen3_ik"),
    "gen3-urdf": Arm("examples/gen3.urdf, base_link to end_effector_link",
                     lambda: load_urdf(EXAMPLES / "gen3.urdf", base="base_link", tip="end_effector_link"),
                     "gen3_ik", "gen3_ik"),
    "jaco2": Arm("examples/jaco2.urdf, j2s7s300_link_base to j2s7s300_link_7",
                 lambda: load_urdf(EXAMPLES / "jaco2.urdf", base="j2s7s300_link_base", tip="j2s7s300_link_7"),
                 "j2s7s300_ik", "j2s7s300_ik"),
}


class PoseSet(NamedTuple):
    """Joint vectors, the poses they make and redkin's arm angles of them."""

    label: str
    q: np.ndarray
    poses: np.ndarray
    psi: np.ndarray


class Success(NamedTuple):
    """How redkin or ssik did on a pose set."""

    poses: int
    found: int  # redkin: every branch that exists found and certified; ssik: q's branch among the certified answers
    short: int  # poses with fewer than 8 certified rows (redkin) or distinct certified branches (ssik)
    singular: int  # misses whose q is near a singular configuration (:func:`near_singular`)
    rows: float  # certified rows (redkin) or distinct certified branches (ssik) per pose
    uncertified: int  # rows the solver returned (redkin: marked as existing) that fail our certificate or branch
    own: int = 0  # redkin: a certified row on q's own branch
    unseen: int = 0  # redkin: certified rows on branches the oracle did not find
    causes: str = ""  # redkin: where the missed branches' solutions (the oracle's) lie


# ----------------------------------------------------------------------------- poses and checks
def wrapped(angle: np.ndarray) -> np.ndarray:
    """Angles into ``[-pi, pi)``."""
    return np.mod(angle + np.pi, 2.0 * np.pi) - np.pi


def in_limits(chain: SerialChain, rng: np.random.Generator, count: int) -> np.ndarray:
    """``count`` joint vectors uniform within the limits (an unlimited joint in [-pi, pi])."""
    lower = np.where(np.isfinite(chain.lower), chain.lower, -np.pi)
    upper = np.where(np.isfinite(chain.upper), chain.upper, np.pi)
    return rng.uniform(lower, upper, (count, chain.n))


def stretched_q4(arm: NearlySRS) -> float:
    """The user's q4 where the neighbour's theta_4 is its elbow phase (the stretched elbow), moved into q4's limits
    by whole turns."""
    theta = np.zeros(7)
    theta[3] = arm.geometry.elbow_equation.phase
    value = float(arm.geometry.q_of_theta(theta)[3])
    lower = arm.chain.lower[3] if np.isfinite(arm.chain.lower[3]) else -np.pi
    return lower + float(np.mod(value - lower, 2.0 * np.pi))


def pose_sets(arm: NearlySRS, count: int, near: int) -> list[PoseSet]:
    """The random set and the sets within :data:`NEAR` of the stretched elbow and of q3 = 0, from one Generator."""
    chain = arm.chain
    rng = np.random.default_rng(1)
    random = in_limits(chain, rng, count)
    stretched = in_limits(chain, rng, near)
    stretched[:, 3] = stretched_q4(arm) + rng.uniform(-NEAR, NEAR, near)
    q3 = in_limits(chain, rng, near)
    q3[:, 2] = rng.uniform(-NEAR, NEAR, near)
    sets = []
    for label, q in (("random in-limit q", random), ("within 1 deg of the stretched elbow", stretched),
                     ("within 1 deg of q3 = 0", q3)):
        assert chain.within_limits(q).all(), label
        sets.append(PoseSet(label, q, chain.fk(q), nearly.arm_angle(arm, q)))
    return sets


def pose_errors(chain: SerialChain, q: np.ndarray, poses: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Position error [m] and rotation angle [rad] of our FK of ``q`` against ``poses`` (broadcast); the angle of
    E = R_pose^T R is atan2(|vee(E - E^T)| / 2, (trace E - 1) / 2), accurate for small angles."""
    reached = chain.fk(q)
    position = np.linalg.norm(reached[..., :3, 3] - poses[..., :3, 3], axis=-1)
    error = np.swapaxes(poses[..., :3, :3], -1, -2) @ reached[..., :3, :3]
    skew = np.stack([error[..., 2, 1] - error[..., 1, 2], error[..., 0, 2] - error[..., 2, 0],
                     error[..., 1, 0] - error[..., 0, 1]], axis=-1)
    angle = np.arctan2(np.linalg.norm(skew, axis=-1) / 2.0, (np.trace(error, axis1=-2, axis2=-1) - 1.0) / 2.0)
    return position, angle


def certified(chain: SerialChain, q: np.ndarray, poses: np.ndarray) -> np.ndarray:
    """Our certificate of rows ``q`` (..., 7) against ``poses`` (..., 4, 4): FK within :data:`TOLERANCE` m and rad."""
    position, angle = pose_errors(chain, q, poses)
    return (position <= TOLERANCE) & (angle <= TOLERANCE)


def branch_signs(arm: NearlySRS, q: np.ndarray) -> np.ndarray:
    """Table 1 branch signs (..., 3) of joint vectors on the neighbour (redkin's branches)."""
    return np.asarray(arm_angle_of(arm.geometry, q).branch)


def distance(rows: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Largest joint difference modulo 2 pi of rows (..., R, 7) from ``q`` (..., 7)."""
    return np.abs(wrapped(rows - q[..., None, :])).max(axis=-1)


def redkin_success(arm: NearlySRS, poses: PoseSet, result: NearlySolutions) -> Success:
    """Whether redkin found every branch that exists at each pose and its own arm angle, certified by our checks.

    A row counts when it passes our certificate (FK within 1e-9 m and rad, ``nearly.arm_angle`` within 1e-9 rad)
    and lies on its own row's branch (:func:`real_branch`).  A branch exists where q lies on it, where redkin
    returned a row that counts, or where the oracle (:func:`existing_branches`, run on the poses with fewer than 8
    rows) found a solution on it.
    """
    rows, exists = result.q, result.exists
    count = len(rows)
    goals = np.broadcast_to(poses.poses[:, None], rows.shape[:2] + (4, 4))
    angle_error = np.abs(wrapped(nearly.arm_angle(arm, rows) - poses.psi[:, None]))
    good = exists & certified(arm.chain, rows, goals) & (angle_error <= TOLERANCE)
    good &= real_branch(arm, rows) == np.arange(8)
    own_branch = real_branch(arm, poses.q)
    existing = good.copy()
    existing[np.arange(count), own_branch] = True
    short = np.flatnonzero(good.sum(axis=-1) < 8)
    unseen = 0
    solutions = np.full((count, 8, 7), np.nan)
    if short.size:
        oracle, solutions[short] = existing_branches(arm, poses.poses[short], poses.psi[short], poses.q[short])
        unseen = int((good[short] & ~oracle).sum())
        existing[short] |= oracle
    missed = existing & ~good
    solutions[np.arange(count), own_branch] = poses.q
    found = ~missed.any(axis=-1)
    return Success(count, int(found.sum()), int(short.size), int(np.sum(~found & near_singular(arm, poses.q))),
                   float(good.sum(axis=-1).mean()), int((exists & ~good).sum()),
                   int(good[np.arange(count), own_branch].sum()), unseen,
                   miss_causes(arm, poses.poses, solutions, missed))


#: Below this sine a missed solution counts as near the stretched elbow, a singular shoulder or wrist, or with its
#: wrist near axis 1 (:func:`miss_causes`).
CAUSE_SINE = 0.05


def miss_causes(arm: NearlySRS, poses: np.ndarray, solutions: np.ndarray, missed: np.ndarray) -> str:
    """Where the missed branches' solutions lie, counted once each by the first that applies: the wrist within
    :data:`CAUSE_SINE` (a sine seen from the shoulder) of axis 1, where the arm angle degenerates; the elbow near
    its stretch; the shoulder (theta_2 near 0 or pi) or wrist (theta_6) near singular; elsewhere."""
    if not missed.any():
        return "none"
    pose_index, branch = np.nonzero(missed)
    places = where_solutions_lie(arm, poses[pose_index], solutions[pose_index, branch])
    return ", ".join(f"{name} {int(np.sum(places == name))}" for name in CAUSES if np.any(places == name))


#: :func:`where_solutions_lie`'s labels, in the order they are tried.
CAUSES = ("wrist near axis 1", "near the stretched elbow", "theta_2 near 0 or pi", "theta_6 near 0 or pi",
          "elsewhere")


def where_solutions_lie(arm: NearlySRS, poses: np.ndarray, q: np.ndarray) -> np.ndarray:
    """The first label of :data:`CAUSES` that applies to each solution ``q`` (M, 7) of ``poses`` (M, 4, 4): the
    wrist within :data:`CAUSE_SINE` (a sine seen from the shoulder) of axis 1, the neighbour's theta_4 within it of
    the real stretched elbow, theta_2 or theta_6 within it of 0 or pi, else "elsewhere"."""
    geometry = arm.geometry
    frame = np.linalg.inv(geometry.chain.base) @ poses @ np.linalg.inv(geometry.chain.tool)
    wrist = frame[:, :3, 3] - geometry.d_wt * frame[:, :3, 2] - np.array([0.0, 0.0, geometry.d_bs])
    sines = np.hypot(wrist[:, 0], wrist[:, 1]) / np.linalg.norm(wrist, axis=-1)
    theta = geometry.theta_of_q(q)
    tests = (sines < CAUSE_SINE, np.abs(np.sin(theta[:, 3] - arm.real_phase)) < CAUSE_SINE,
             np.abs(np.sin(theta[:, 1])) < CAUSE_SINE, np.abs(np.sin(theta[:, 5])) < CAUSE_SINE,
             np.ones(len(q), dtype=bool))
    return np.select(tests, CAUSES, default=CAUSES[-1])


#: :func:`near_singular`'s bound on the sines of the neighbour's theta_2, theta_4 and theta_6.
SINGULAR_SINE = 0.05


def near_singular(arm: NearlySRS, q: np.ndarray) -> np.ndarray:
    """Whether the sine of the neighbour's theta_2, theta_4 - phi or theta_6 at ``q`` (..., 7) is below
    :data:`SINGULAR_SINE` (shoulder, elbow or wrist near its singular configuration)."""
    theta = arm.geometry.theta_of_q(q)[..., [1, 3, 5]] - np.array([0.0, arm.geometry.elbow_equation.phase, 0.0])
    return np.abs(np.sin(theta)).min(axis=-1) < SINGULAR_SINE


def distinct_rows(rows: np.ndarray) -> int:
    """How many of ``rows`` (R, 7) differ from every earlier row by more than :data:`SAME` (modulo 2 pi)."""
    return sum(k == 0 or bool(np.all(distance(rows[None, :k], rows[k][None])[0] > SAME)) for k in range(len(rows)))


# ----------------------------------------------------------------------------- which branches exist
#: The oracle's random starts per pose, Newton iterations per start, and the step of its central differences.
ORACLE_STARTS, ORACLE_ITERATIONS, ORACLE_STEP = 32, 40, 1e-7


def real_branch(arm: NearlySRS, q: np.ndarray) -> np.ndarray:
    """The index in :data:`redkin.srs.BRANCHES` (as ``nearly.ik`` orders its rows) of each joint vector's branch on
    the real arm (..., 7): the signs of the neighbour's theta_2, theta_4 minus the real arm's stretched elbow, and
    theta_6, at the same joint values."""
    theta = arm.geometry.theta_of_q(q)[..., [1, 3, 5]] - np.array([0.0, arm.real_phase, 0.0])
    signs = np.where(wrapped(theta) < 0.0, -1.0, 1.0)
    table = arm.geometry.kernel_branches  # row b: the Table 1 signs of BRANCHES[b]
    return np.argmax(np.all(signs[..., None, :] == table, axis=-1), axis=-1)


def _oracle_residual(arm: NearlySRS, q: np.ndarray, poses: np.ndarray, psi: np.ndarray) -> np.ndarray:
    """``[p_t - p; rotation vector of R_t R^T; psi - psi(q)]`` (M, 7), the arm angle by ``srs.arm_angle_of``."""
    reached = arm.chain.fk(q)
    relative = poses[:, :3, :3] @ np.swapaxes(reached[:, :3, :3], -1, -2)
    skew = np.stack([relative[:, 2, 1] - relative[:, 1, 2], relative[:, 0, 2] - relative[:, 2, 0],
                     relative[:, 1, 0] - relative[:, 0, 1]], axis=-1)
    size = np.linalg.norm(skew, axis=-1)
    angle = np.arctan2(0.5 * size, 0.5 * (np.trace(relative, axis1=-2, axis2=-1) - 1.0))
    scale = np.where(size > 0.0, angle / np.where(size > 0.0, size, 1.0), 0.5)
    turn = wrapped(psi - arm_angle_of(arm.geometry, q).psi)
    return np.concatenate([poses[:, :3, 3] - reached[:, :3, 3], scale[:, None] * skew, turn[:, None]], axis=-1)


def existing_branches(arm: NearlySRS, poses: np.ndarray, psi: np.ndarray, known: np.ndarray,
                      seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """Which branches have a solution on the real arm at each pose (N, 4, 4) and arm angle (N,), found independently
    of ``nearly.ik``: damped Newton in numpy on the 7 equations (the arm angle by ``srs.arm_angle_of``, its gradient
    by central differences) from :data:`ORACLE_STARTS` random joint vectors per pose, from the neighbour's closed
    form on every branch (as is, with its elbow mirrored across the stretch and opened by 0.05 rad both ways), and
    from ``known`` (N, 7) joint vectors, each certified by our FK (1e-9 m, 1e-9 rad) and ``arm_angle_of`` (1e-9
    rad) and labelled by :func:`real_branch`: whether each branch exists, (N, 8) in the order of ``nearly.ik``'s
    rows, and one solution of each that does (N, 8, 7), NaN where none was found."""
    count = len(poses)
    rng = np.random.default_rng(seed)
    starts = [rng.uniform(-np.pi, np.pi, (count, ORACLE_STARTS, 7)), known[:, None]]
    neighbour = arm.geometry
    inside = np.asarray(reachable(neighbour, poses))
    for name in BRANCH_NAMES:
        closed = np.zeros((count, 7))
        closed[inside] = exact_ik(neighbour, poses[inside], psi[inside], name)
        theta = neighbour.theta_of_q(closed)
        for change in ("as is", "mirrored", "opened +", "opened -"):
            moved = theta.copy()
            relative = wrapped(theta[:, 3] - arm.real_phase)
            if change == "mirrored":
                moved[:, 3] = arm.real_phase - relative
            elif change != "as is":
                moved[:, 3] = arm.real_phase + (1.0 if change == "opened +" else -1.0) * np.maximum(np.abs(relative),
                                                                                                    0.05)
            starts.append(neighbour.q_of_theta(moved)[:, None])
    q = np.concatenate(starts, axis=1)
    per_pose = q.shape[1]
    q = q.reshape(-1, 7)
    goals = np.repeat(poses, per_pose, axis=0)
    angles = np.repeat(psi, per_pose)
    active = np.arange(len(q))
    for _ in range(ORACLE_ITERATIONS):
        if active.size == 0:
            break
        now = q[active]
        residual = _oracle_residual(arm, now, goals[active], angles[active])
        size = np.abs(residual).sum(axis=-1)
        keep = (size > 1e-14) & np.isfinite(size)
        active, now, residual = active[keep], now[keep], residual[keep]
        jacobian = np.empty((len(now), 7, 7))
        jacobian[:, :6] = arm.chain.jacobian(now)
        moved = np.repeat(now[None], 8, axis=0)  # the arm angle moves with joints 1-4 only
        for j in range(4):
            moved[2 * j, :, j] += ORACLE_STEP
            moved[2 * j + 1, :, j] -= ORACLE_STEP
        values = arm_angle_of(arm.geometry, moved).psi.reshape(4, 2, len(now))
        jacobian[:, 6, :4] = (wrapped(values[:, 0] - values[:, 1]) / (2.0 * ORACLE_STEP)).T
        jacobian[:, 6, 4:] = 0.0
        damping = (0.05 * np.sum(residual * residual, axis=-1) + 1e-12)[:, None, None] * np.eye(7)
        transposed = np.swapaxes(jacobian, -1, -2)
        step = np.linalg.solve(transposed @ jacobian + damping, (transposed @ residual[..., None]))[..., 0]
        largest = np.abs(step).max(axis=-1, keepdims=True)
        q[active] = now + step * np.minimum(1.0, 0.5 / np.maximum(largest, 1e-300))
    residual = _oracle_residual(arm, q, goals, angles)
    position = np.linalg.norm(residual[:, :3], axis=-1)
    rotation = np.linalg.norm(residual[:, 3:6], axis=-1)
    good = (position <= TOLERANCE) & (rotation <= TOLERANCE) & (np.abs(residual[:, 6]) <= TOLERANCE)
    exists = np.zeros((count, 8), dtype=bool)
    solutions = np.full((count, 8, 7), np.nan)
    labels = real_branch(arm, q)
    pose_index = np.repeat(np.arange(count), per_pose)
    exists[pose_index[good], labels[good]] = True
    solutions[pose_index[good], labels[good]] = q[good]
    return exists, solutions


def per_call(solve: Callable[[int], Any], count: int) -> tuple[np.ndarray, list[Any]]:
    """Seconds of each call ``solve(k)``, k < count, and what the calls returned."""
    seconds = np.empty(count)
    out = []
    for k in range(count):
        start = time.perf_counter()
        out.append(solve(k))
        seconds[k] = time.perf_counter() - start
    return seconds, out


# ----------------------------------------------------------------------------- ssik
class Ssik(NamedTuple):
    """ssik's prebuilt arm: its module, KinBody, prepared native Solver and swivel-circle constants."""

    module: Any
    kb: Any
    solver: Any
    shoulder: np.ndarray
    ee_offset: np.ndarray
    elbow_index: int
    version: str


def load_ssik(name: str) -> Ssik | str:
    """ssik's prebuilt Kinova arm ``name``, or why it cannot be had."""
    try:
        import importlib

        import ssik
        from ssik import _native

        module = importlib.import_module(f"ssik.prebuilt.kinova.{name}")
    except Exception as exc:
        return f"ssik not importable ({type(exc).__name__}: {exc}); pip install 'ssik==8.2.*'"
    if not _native.native_available():
        return "ssik's C++ extension is not shipped for this platform"
    kb = module._KB
    geometry = _native.srs_polished_native_geometry(kb)  # the relaxed pivots srs_polished solves with
    solver = _native._solver(_native._load_ext(), kb, module.SOLVER_NAME)  # what module.solve(T) calls
    if geometry is None or solver is None:
        return f"ssik does not class {name} as approximately S-R-S"
    return Ssik(module, kb, solver, np.asarray(geometry["shoulder_pivot"]), np.asarray(geometry["ee_offset_local"]),
                int(geometry["elbow_index"]), ssik.__version__)


def ssik_fk_residual(chain: SerialChain, peer: Ssik, rng: np.random.Generator, count: int = 200) -> float:
    """Largest entry of ``chain.fk(q) - ssik fk(q)`` over random joint vectors in [-pi, pi]."""
    q = rng.uniform(-np.pi, np.pi, (count, 7))
    return float(max(np.abs(chain.fk(x) - peer.module.fk(x)).max() for x in q))


def ssik_native(peer: Ssik, pose: np.ndarray) -> np.ndarray:
    """Every answer of ssik's native call (its 16-swivel sweep, polished; no limit filter), (k, 7)."""
    return np.reshape(np.asarray(peer.solver.solve(pose, 0)[0], dtype=float), (-1, 7))


def ssik_one_swivel(peer: Ssik, pose: np.ndarray, swivel: float) -> np.ndarray:
    """ssik's answers at one swivel angle (its Python ``srs_polished.solve``), (k, 7)."""
    from ssik.solvers.seven_r import srs_polished

    answers, _ = srs_polished.solve(peer.kb, pose, swivel_samples=np.array([swivel]))
    return np.reshape(np.array([answer.q for answer in answers], dtype=float), (-1, 7))


def ssik_swivel(peer: Ssik, q: np.ndarray, pose: np.ndarray) -> float:
    """ssik's swivel angle of ``q`` at ``pose``: the elbow joint's origin about its shoulder-wrist line, from the
    base z axis projected on the circle's plane (``ssik.chart``'s ``param_of``)."""
    from ssik.solvers.seven_r.srs import _frame_at_joint_batch, _swivel_basis

    wrist = pose[:3, 3] - pose[:3, :3] @ peer.ee_offset
    axis = (wrist - peer.shoulder) / np.linalg.norm(wrist - peer.shoulder)
    first, second = _swivel_basis(axis)
    _, origin = _frame_at_joint_batch(peer.kb, q[None, :], peer.elbow_index)
    elbow = origin[0] - peer.shoulder
    return float(np.arctan2(elbow @ second, elbow @ first))


def ssik_success(arm: NearlySRS, poses: PoseSet, answers: list[np.ndarray]) -> Success:
    """ssik's native answers on a pose set: q's branch among the certified answers, distinct certified branches."""
    found = short = singular = uncertified = branches = 0
    own = branch_signs(arm, poses.q)
    near = near_singular(arm, poses.q)
    for k, rows in enumerate(answers):
        good = certified(arm.chain, rows, poses.poses[k]) if len(rows) else np.zeros(0, dtype=bool)
        uncertified += int((~good).sum())
        signs = branch_signs(arm, rows[good]) if good.any() else np.zeros((0, 3))
        hit = bool(np.any(np.all(signs == own[k], axis=-1)))
        count = len({tuple(s) for s in signs.astype(int)})
        found += hit
        short += not hit and count < 8
        singular += not hit and bool(near[k])
        branches += count
    return Success(len(poses.q), found, short, singular, branches / max(len(answers), 1), uncertified)


# ----------------------------------------------------------------------------- one arm
class Timing(NamedTuple):
    median: float
    p99: float


def timing(seconds: np.ndarray) -> Timing:
    return Timing(float(np.median(seconds)), float(np.percentile(seconds, 99)))


class ArmResult(NamedTuple):
    name: str
    lines: list[str]
    redkin_one: Timing
    redkin_batch: float  # seconds per pose
    ssik_native: Timing | None
    redkin: list[Success]  # per pose set
    ssik: list[Success] | None


def measure(name: str, count: int, near: int, python_count: int) -> ArmResult:
    spec = ARMS[name]
    chain = spec.load()
    arm = nearly_srs(chain)
    lines = [f"## {name}: {spec.description}", "", f"- {arm.describe()}"]
    peer = load_ssik(spec.reference)
    if isinstance(peer, str):
        lines.append(f"- ssik skipped: {peer}")
    else:
        residual = ssik_fk_residual(chain, peer, np.random.default_rng(7))
        lines.append(f"- FK of ssik {peer.version}'s `{spec.reference}` ({peer.module.SOLVER_NAME}) minus ours, "
                     f"200 random q: {residual:.2g}"
                     + ("" if spec.ssik else "; different models, so ssik is not run on this arm's poses"))
        if not spec.ssik:
            peer = "its poses are not ssik's model's (above)"
        elif residual > 1e-12:
            lines.append("- ssik skipped: its model is not ours")
            peer = "model differs"
    sets = pose_sets(arm, count, near)
    lines.append(f"- stretched elbow at q4 = {stretched_q4(arm):.6g} rad; poses: {count} random, {near} per near set")
    random = sets[0]
    nearly.ik(arm, random.poses[0], random.psi[0])  # compiled (or loaded from the cache) before the clock
    seconds, singles = per_call(lambda k: nearly.ik(arm, random.poses[k], random.psi[k]), count)
    one = timing(seconds)
    sweep = np.linspace(-np.pi, np.pi, SSIK_SWEEP, endpoint=False)
    sixteen = timing(per_call(lambda k: nearly.ik(arm, random.poses[k], sweep), min(count, 1000))[0])
    batch = min(_seconds(lambda: nearly.ik(arm, random.poses, random.psi)) for _ in range(3)) / count
    results = [nearly.ik(arm, s.poses, s.psi) for s in sets]
    agree = sum(np.array_equal(single.exists, results[0].exists[k]) and np.array_equal(single.q, results[0].q[k])
                for k, single in enumerate(singles))
    redkin = [redkin_success(arm, s, r) for s, r in zip(sets, results)]
    rows = [("redkin `nearly.ik(arm, T, psi)`, one pose per call, 8 branches", _times(one)),
            (f"redkin, one pose at {SSIK_SWEEP} arm angles in one call (ssik's sweep; {min(count, 1000)} poses)",
             _times(sixteen)),
            (f"redkin, {count} poses in one call ({thread_count()} threads)", f"{batch * 1e6:.1f} µs per pose"),
            ("  one call per pose and the batch return the same rows", f"{agree}/{count} poses")]
    ssik_time = ssik_results = None
    if not isinstance(peer, str):
        ssik_native(peer, random.poses[0])
        seconds, answers = per_call(lambda k: ssik_native(peer, random.poses[k]), count)
        ssik_time = timing(seconds)
        per_pose = float(np.mean([len(a) for a in answers]))
        rows.append((f"ssik native C++ call, all answers ({SSIK_SWEEP} swivel angles x 8 branches, polished)",
                     f"{_times(ssik_time)}; {per_pose:.1f} answers per pose"))
        rows.append(("  redkin one pose / ssik native", f"{one.median / ssik_time.median:.2f} x median, "
                                                        f"{one.p99 / ssik_time.p99:.2f} x p99"))
        rows.append(("  redkin batch per pose / ssik native median", f"{batch / ssik_time.median:.2f} x"))
        rows.append((f"  redkin at {SSIK_SWEEP} arm angles / ssik native (the same {SSIK_SWEEP} x 8 workload)",
                     f"{sixteen.median / ssik_time.median:.2f} x median"))
        rows.extend(_one_swivel_rows(arm, peer, random, min(count, python_count)))
        ssik_results = [ssik_success(arm, sets[0], answers)]
        for s in sets[1:]:
            ssik_results.append(ssik_success(arm, s, [ssik_native(peer, pose) for pose in s.poses]))
    lines += ["", "| measurement | result |", "|---|---|"] + [f"| {label} | {value} |" for label, value in rows]
    lines += ["", "| pose set | redkin: every existing branch found, certified | q's branch found | poses with < 8 "
                  f"rows | misses near a singular q (a sine < {SINGULAR_SINE:g}) | certified rows per pose | "
                  "rows marked found that fail our check | rows the oracle did not find | ssik native: q's branch "
                  "among certified answers | distinct certified branches per pose | answers that fail our FK check |",
              "|---|---|---|---|---|---|---|---|---|---|---|"]
    for k, s in enumerate(sets):
        r = redkin[k]
        line = (f"| {s.label} | {_percent(r.found, r.poses)} | {_percent(r.own, r.poses)} | {r.short} | "
                f"{r.singular} | {r.rows:.2f} | {r.uncertified} | {r.unseen} |")
        if ssik_results is None:
            line += " skipped | | |"
        else:
            p = ssik_results[k]
            line += f" {_percent(p.found, p.poses)} | {p.rows:.2f} | {p.uncertified} |"
        lines.append(line)
    lines += [""] + [f"- missed branches, {s.label}: {r.causes}" for s, r in zip(sets, redkin)]
    lines.append("")
    return ArmResult(name, lines, one, batch, ssik_time, redkin, ssik_results)


def _one_swivel_rows(arm: NearlySRS, peer: Ssik, poses: PoseSet, count: int) -> list[tuple[str, str]]:
    """ssik's Python call at one swivel angle, that of the joint vector that made each pose."""
    swivels = [ssik_swivel(peer, poses.q[k], poses.poses[k]) for k in range(count)]
    ssik_one_swivel(peer, poses.poses[0], swivels[0])
    seconds, answers = per_call(lambda k: ssik_one_swivel(peer, poses.poses[k], swivels[k]), count)
    found = 0
    nearest, drift = [], []
    for k, rows in enumerate(answers):
        good = rows[certified(arm.chain, rows, poses.poses[k])] if len(rows) else rows
        if len(good):
            gap = distance(good[None], poses.q[k][None])[0]
            found += bool(np.any(gap <= SAME))
            nearest.append(float(gap.min()))
            drift.extend(abs(float(wrapped(np.array(ssik_swivel(peer, row, poses.poses[k]) - swivels[k]))))
                         for row in good)
    return [(f"ssik Python `srs_polished.solve(kb, T, swivel_samples=[s])`, one swivel angle ({count} poses)",
             f"{_times(timing(seconds))}; {np.mean([len(a) for a in answers]):.2f} answers per pose"),
            ("  at s = ssik's swivel of q: q itself among its certified answers (within 1e-6 rad)",
             f"{_percent(found, count)}; nearest certified answer to q: median {np.median(nearest):.2g} rad"),
            ("  swivel angle of its certified answers minus s (the polish does not hold it)",
             f"median {np.median(drift):.2g} rad, 90th percentile {np.percentile(drift, 90):.2g} rad")]


def _seconds(call: Callable[[], object]) -> float:
    start = time.perf_counter()
    call()
    return time.perf_counter() - start


def _us(seconds: float) -> str:
    return f"{seconds * 1e6:.3g} µs" if seconds < 1e-3 else f"{seconds * 1e3:.3g} ms"


def _times(t: Timing) -> str:
    return f"median {_us(t.median)}, p99 {_us(t.p99)}"


def _percent(count: int, total: int) -> str:
    return f"{100.0 * count / max(total, 1):.2f} %"


# ----------------------------------------------------------------------------- feasible sets vs dense sampling
#: The continuous joints (Gen3 and Jaco2 joints 1, 3, 5, 7) get these limits [rad] in the feasible-set check, so
#: that every joint's limits cut the circle of arm angles.
CONTINUOUS_LIMIT = 2.9
FEASIBLE_ARMS: dict[str, tuple[str, Callable[[], SerialChain]]] = {
    "gen3": (ARMS["gen3-urdf"].description, ARMS["gen3-urdf"].load),
    "jaco2": (ARMS["jaco2"].description, ARMS["jaco2"].load),
    "iiwa14-rosi": ("examples/iiwa14_rosi.urdf, base_link to tool0 (ROS-Industrial, 0.436 mm offsets)",
                    lambda: load_urdf(EXAMPLES / "iiwa14_rosi.urdf")),
}
#: ssik's prebuilt arm whose frames are those of each feasible-set arm (its FK is checked against ours in the run);
#: ssik ships no ROS-I iiwa (its iiwa14 is KUKA's exact S-R-S arm).
FEASIBLE_SSIK = {"gen3": "gen3_ik", "jaco2": "j2s7s300_ik"}
#: The pose draws of ``--feasible``: the random poses, then those near a singular configuration (issue 38).
DRAWS = ("random", "straight wrist", "straight shoulder", "stretched elbow")
#: Each near draw: the user's joint (index) moved near its singular value, and the range of that distance [rad]
#: (a power of ten uniform between the two, either sign).
NEAR_DRAWS = {"straight wrist": (5, (1e-6, 1e-3)), "straight shoulder": (1, (1e-6, 1e-3)),
              "stretched elbow": (3, (1e-5, 1e-2))}
#: Flagged arcs per arm that are classified (oracle, singular arm angles); the rest are only counted.
CLASSIFIED = 30
#: The target's width [rad]: a feasible sample farther than this from the computed set is an arc it misses.
MISSED = 1e-6
#: Issue 38's speed target: certified sets of all 8 branches of one pose [s].
POSE_TARGET = 5e-3
#: Arm angles per call of ``nearly.ik`` in the sampling (memory).
CHUNK = 20_000


def limited(chain: SerialChain) -> SerialChain:
    """``chain`` with its unlimited joints limited to +-:data:`CONTINUOUS_LIMIT`."""
    return chain.with_limits(np.where(np.isfinite(chain.lower), chain.lower, -CONTINUOUS_LIMIT),
                             np.where(np.isfinite(chain.upper), chain.upper, CONTINUOUS_LIMIT))


class Draw(NamedTuple):
    """One pose of the feasible-set check: its draw (:data:`DRAWS`), its place in that draw's sequence, and the
    joint vector that made it."""

    kind: str
    index: int
    q: np.ndarray


def singular_values(arm: NearlySRS, joint: int, stretched: bool, margin: float) -> np.ndarray:
    """The user's values of ``joint`` within its limits (at least ``margin`` inside them, modulo whole turns) where
    the neighbour's theta (``offset + sign q``) is 0 or pi, or with ``stretched``, where theta_4 is the real arm's
    stretched elbow (``arm.real_phase``)."""
    neighbour, chain = arm.neighbour, arm.chain
    sign, offset = neighbour.sign[joint], neighbour.offset[joint]
    theta = np.array([arm.real_phase]) if stretched else np.array([0.0, np.pi])
    values = sign * (theta - offset)
    low, high = chain.lower[joint], chain.upper[joint]
    values = low + np.mod(values - low, 2.0 * np.pi)
    return np.unique(values[(values >= low + margin) & (values <= high - margin)])


def feasible_draws(arm: NearlySRS, count: int, near: int, first: int = 0) -> list[Draw]:
    """Joint vectors of the check: places ``first .. first + count - 1`` of the random sequence (q uniform within
    the limits, ``default_rng(3)``) and ``first .. first + near - 1`` of each near draw (:data:`NEAR_DRAWS`): q
    uniform within the limits, then the draw's joint set to the singular value (:func:`singular_values`) nearest it
    plus ``+-10^u``, u uniform (``default_rng((38, k))`` for the k-th near draw, one pose at a time, so that a run
    in parts draws what one run draws)."""
    chain = arm.chain
    random = in_limits(chain, np.random.default_rng(3), first + count)
    draws = [Draw("random", first + k, q) for k, q in enumerate(random[first:])]
    for k, kind in enumerate(DRAWS[1:]):
        joint, (small, large) = NEAR_DRAWS[kind]
        values = singular_values(arm, joint, kind == "stretched elbow", large)
        if values.size == 0:
            continue
        rng = np.random.default_rng((38, k))
        for index in range(first + near):
            q = in_limits(chain, rng, 1)[0]
            moved = rng.choice([-1.0, 1.0]) * 10.0 ** rng.uniform(np.log10(small), np.log10(large))
            q[joint] = values[np.argmin(np.abs(values - q[joint]))] + moved
            if index >= first:
                draws.append(Draw(kind, index, q))
    assert all(chain.within_limits(d.q) for d in draws)
    return draws


def sampled_feasible(arm: NearlySRS, pose: np.ndarray, psi: np.ndarray) -> tuple[np.ndarray, int]:
    """Where each branch has a solution within the limits at each arm angle ``psi`` (M,), (M, 8) in the order of
    ``nearly.ik``'s rows: a row that ``nearly.ik`` marks found and that passes our certificate (FK within 1e-9 m and
    rad, ``nearly.arm_angle`` within 1e-9 rad) and ``chain.within_limits`` (modulo whole turns); and how many samples
    this verdict differs from ``nearly.ik``'s own ``within_limits``."""
    feasible = np.empty((len(psi), 8), dtype=bool)
    differ = 0
    for start in range(0, len(psi), CHUNK):
        angles = psi[start:start + CHUNK]
        result = nearly.ik(arm, pose, angles)
        angle_error = np.abs(wrapped(nearly.arm_angle(arm, result.q) - angles[:, None]))
        ours = (result.exists & certified(arm.chain, result.q, pose) & (angle_error <= TOLERANCE)
                & arm.chain.within_limits(result.q, wrap=True))
        feasible[start:start + CHUNK] = ours
        differ += int(np.sum(ours != result.within_limits))
    return feasible, differ


#: Residual [m, rad] that Newton's steps reach from a row that is an exact solution (:func:`exact_row`).
EXACT = 1e-12
#: How far [rad of arm angle] beyond a set's end a run whose row is not exact may lie and still count as the
#: certificate's slack beyond a fold (up to 5.9e-5 rad measured in the earlier runs): farther, or outside an empty
#: set, it is a missed run whatever :func:`exact_row` says (near a stretched elbow Newton's steps stall on whole
#: arcs of true solutions).
FOLD_SLACK = 1e-4


def exact_row(arm: NearlySRS, pose: np.ndarray, psi: float, branch: int) -> bool:
    """Whether ``nearly.ik``'s row of ``branch`` at ``psi`` is an exact solution: Levenberg-Marquardt steps on the
    seven equations (``redkin.srs.nearly.search.polished``) take it to :data:`EXACT` (our FK and arm angle) on the
    same branch.  Beyond a fold, where the branch has ceased to exist, the certificate (1e-9) still accepts rows up to
    about 1e-5 rad of arm angle away (the seven equations are nearly singular), which these steps cannot take to
    rounding."""
    row = nearly.ik(arm, pose, psi, BRANCH_NAMES[branch])
    if not row.exists[0]:
        return False
    q = polished(arm, row.q, pose, lambda values: nearly.arm_angle(arm, values), psi)[0][0]
    errors = pose_errors(arm.chain, q[None], pose[None])
    return bool(max(errors[0][0], errors[1][0]) <= EXACT
                and abs(wrapped(nearly.arm_angle(arm, q) - psi)) <= EXACT and nearly.branch_of(arm, q) == branch)


def row_leaves_branch(arm: NearlySRS, pose: np.ndarray, psi: float, branch: int,
                      ends: np.ndarray) -> bool:
    """Whether ``nearly.ik``'s row of ``branch`` at ``psi`` is shown not to be a solution of that branch there, at
    any distance from the set: the steps of :func:`exact_row` take it to rounding on another branch (next to a
    stretched elbow the row's elbow sign is a near-solution's), or they stall and the pose's self-motion, entered
    from where they stopped (``_self_motion_kernels.started``: the curve's nearest point, the arm angle free), is met
    within :data:`MISSED` (1e-6 rad) of an end of the branch's set, ``ends``: the row lies beyond the fold there,
    accepted by the certificate's 1e-9 slack."""
    row = nearly.ik(arm, pose, psi, BRANCH_NAMES[branch])
    if not row.exists[0]:
        return False
    q = polished(arm, row.q, pose, lambda values: nearly.arm_angle(arm, values), psi)[0][0]
    errors = pose_errors(arm.chain, q[None], pose[None])
    exact = max(errors[0][0], errors[1][0]) <= EXACT and abs(wrapped(nearly.arm_angle(arm, q) - psi)) <= EXACT
    if exact:
        return bool(nearly.branch_of(arm, q) != branch)
    from redkin.srs.nearly import _self_motion_kernels as kernels

    point, tangent, gradient, state = np.empty(7), np.empty(7), np.empty(7), np.empty(kernels.STATE)
    if not kernels.started(np.ascontiguousarray(q), np.ascontiguousarray(pose), arm.kernel_real, arm.kernel_model,
                           arm.kernel_bounds, kernels.scratch(), point, tangent, gradient, state):
        return False
    return bool(len(ends) and np.min(np.abs(wrapped(ends - state[kernels.PSI]))) <= MISSED)


def second_solution(arm: NearlySRS, pose: np.ndarray, psi: float, branch: int,
                    curves: Sequence[SelfMotion] | None = None) -> bool:
    """Whether the branch has a solution at ``psi`` within the limits that passes our certificate (FK 1e-9 m and
    rad, ``nearly.arm_angle`` 1e-9 rad, ``nearly.branch_of``), among all its solutions there on the self-motion
    (``redkin.srs.branch_solutions`` on the pose's ``curves``, those its sets were read off: no second trace):
    where it has two, ``nearly.ik`` returns one."""
    solutions = branch_solutions(arm, pose, psi, BRANCH_NAMES[branch],
                                 curves=None if curves is None else tuple(curves))
    if len(solutions) == 0:
        return False
    good = (certified(arm.chain, solutions, pose) & arm.chain.within_limits(solutions, wrap=True)
            & (np.abs(wrapped(nearly.arm_angle(arm, solutions) - psi)) <= TOLERANCE)
            & (nearly.branch_of(arm, solutions) == branch))
    return bool(good.any())


#: How far in arm angle [rad] from a one-sample false run :func:`boundary_solution` looks for a solution of the
#: branch within the limits: far below the issue's resolution of 1e-6 rad.
BOUNDARY_REACH = 1e-7


def boundary_solution(arm: NearlySRS, pose: np.ndarray, psi: float, branch: int,
                      curves: Sequence[SelfMotion] | None = None) -> bool:
    """Whether the branch has a solution within the limits that passes our certificate at ``psi -+``
    :data:`BOUNDARY_REACH` (:func:`second_solution` there): a one-sample false run at the end of a set where the
    branch's solutions within the limits run into a singular configuration exactly at ``psi`` (the shoulder's
    ``theta_2 = 0`` lies at ``psi = 0`` or ``pi``), whose own branch sign rounds to the neighbouring branch: the
    set's closed end, not an arc it claims without a solution."""
    return any(second_solution(arm, pose, psi + side * BOUNDARY_REACH, branch, curves) for side in (-1.0, 1.0))


def cyclic_runs(mask: np.ndarray) -> list[np.ndarray]:
    """The maximal runs of consecutive True entries of ``mask`` (M,), read cyclically, as index arrays."""
    if not mask.any():
        return []
    if mask.all():
        return [np.arange(len(mask))]
    start = int(np.argmin(mask))  # a False entry: no run crosses it
    edges = np.diff(np.concatenate([[0], np.roll(mask, -start).astype(int), [0]]))
    return [(np.arange(low, high) + start) % len(mask)
            for low, high in zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1))]


def end_distance(arcs: ArcSet, psi: np.ndarray, outside: bool = False) -> np.ndarray:
    """Distance [rad] of each arm angle from the nearest end of the set's arcs (inf for an empty or full set); for
    arm angles ``outside`` the set, from the nearest end of its intervals in [-pi, pi] (what ``contains`` reads: an
    interval that stops 1e-13 rad short of the seam is an arc across it in ``arcs``, but holds neither +pi nor -pi),
    so the distance from the set itself."""
    if arcs.is_empty or arcs.is_full:
        return np.full(len(psi), np.inf)
    ends = np.array([end for arc in (arcs.intervals if outside else arcs.arcs) for end in arc])
    return np.abs(wrapped(psi[:, None] - ends)).min(axis=-1)


class Flag(NamedTuple):
    """A disagreement of the computed set with the sampling on one pose and branch."""

    kind: str  # "missed": feasible samples outside the set; "false": infeasible samples inside it
    pose: int  # the pose's place in its draw's sequence
    branch: int  # index in BRANCHES
    psi: float  # the run's sample farthest from the set's nearest end
    samples: int  # samples in the run
    distance: float  # that sample's distance from the set's nearest end [rad]
    draw: str = "random"  # the pose's draw (DRAWS)
    complete: bool = True  # whether the pose's self-motion was followed whole (NearlyFeasible.complete)


class Comparison(NamedTuple):
    """One pose and branch: the disagreements and how the set's ends agree with the sampled boundary."""

    flags: list[Flag]
    ends_agreeing: int
    ends_checked: int
    narrow: int  # computed arcs that hold no sample


def compare(psi: np.ndarray, feasible: np.ndarray, arcs: ArcSet, pose: int, branch: int, draw: str = "random",
            complete: bool = True) -> Comparison:
    """The computed set ``arcs`` against the sampled verdicts ``feasible`` at the uniform arm angles ``psi`` (M,),
    ``psi[0] = -pi``: runs of feasible samples outside the set, runs of infeasible samples inside it, and each end of
    a computed arc that holds a sample, which agrees when the sample just inside the end is feasible and the one just
    outside is not (the sampled boundary within one spacing of the end)."""
    count = len(psi)
    spacing = 2.0 * np.pi / count
    inside = np.asarray(arcs.contains(psi))
    flags = []
    for kind, mask in (("missed", feasible & ~inside), ("false", ~feasible & inside)):
        for run in cyclic_runs(mask):
            distance = end_distance(arcs, psi[run], outside=kind == "missed")
            far = int(np.argmax(distance))
            flags.append(Flag(kind, pose, branch, float(psi[run[far]]), len(run), float(distance[far]), draw,
                              complete))
    agreeing = checked = narrow = 0
    if not (arcs.is_empty or arcs.is_full):
        for low, high in arcs.arcs:
            first = int(np.ceil((low + np.pi) / spacing - 1e-9)) % count
            if (psi[first] - low) % (2.0 * np.pi) > (high - low) % (2.0 * np.pi):
                narrow += 1
                continue
            last = int(np.floor((high + np.pi) / spacing + 1e-9)) % count
            agreeing += int(feasible[first] and not feasible[(first - 1) % count])
            agreeing += int(feasible[last] and not feasible[(last + 1) % count])
            checked += 2
    return Comparison(flags, agreeing, checked, narrow)


class DrawResult(NamedTuple):
    """One draw's poses on one arm: the flags sorted by kind, the counts and the times per pose."""

    kind: str
    poses: int
    pose_branches: int
    nonempty: int  # pose-branches with a feasible arm angle, computed or sampled
    incomplete: int  # poses whose self-motion was not followed whole
    missed: list[Flag]  # feasible samples outside the set whose row is exact (on complete and incomplete poses)
    beyond: list[Flag]  # runs outside the set whose row Newton's steps cannot take to rounding (exact_row)
    false: list[Flag]  # infeasible samples inside the set, no second solution there
    second: list[Flag]  # runs inside the set held by a second solution within the limits
    boundary: list[Flag]  # one-sample false runs at a set's end next to a solution within the limits (1e-7 rad)
    ends_agreeing: int
    ends_checked: int
    narrow: int
    differ: int
    seconds: np.ndarray  # feasible_arm_angles_nearly_all per pose
    sample_seconds: float  # the sampling, all poses
    ssik_native: np.ndarray | None  # ssik's native call per pose (same poses)
    ssik_arcs: np.ndarray | None  # ssik's feasible-swivel arcs of its best-fit S-R-S arm per pose
    ssik_nonempty: int  # ssik's branches with an arc


class FeasibleResult(NamedTuple):
    name: str
    lines: list[str]
    pose_branches: int
    missed: list[Flag]
    false: list[Flag]
    draws: tuple[DrawResult, ...] = ()
    ssik: str = ""  # the ssik configuration timed, or why it was not


class SsikFeasible(NamedTuple):
    """ssik's calls on a feasible-set arm: its native solver and its feasible-swivel arcs on its best-fit pivots."""

    peer: Ssik
    classification: Any  # ssik's SrsClassification of the best-fit S-R-S arm (is_approximately_srs_7r(...).base)
    limits: list[tuple[float, float]]  # our limits, passed to its arcs
    describe: str


def load_ssik_feasible(name: str, chain: SerialChain) -> SsikFeasible | str:
    """ssik's prebuilt arm for the feasible-set arm ``name`` (:data:`FEASIBLE_SSIK`) with our FK, or why not."""
    if name not in FEASIBLE_SSIK:
        return "ssik ships no model of this arm"
    peer = load_ssik(FEASIBLE_SSIK[name])
    if isinstance(peer, str):
        return peer
    residual = ssik_fk_residual(chain, peer, np.random.default_rng(7), 50)
    if residual > 1e-12:
        return f"ssik's {FEASIBLE_SSIK[name]} FK differs from ours by {residual:.2g}"
    from ssik.core.tolerances import DEFAULT_TOLERANCE_POLICY
    from ssik.kinematics.predicates import is_approximately_srs_7r

    approximate = is_approximately_srs_7r(peer.kb, max_drift_m=0.04, policy=DEFAULT_TOLERANCE_POLICY)
    if approximate is None:
        return f"ssik does not class {FEASIBLE_SSIK[name]} as approximately S-R-S"
    describe = (f"ssik {peer.version}, `ssik.prebuilt.kinova.{FEASIBLE_SSIK[name]}` ({peer.module.SOLVER_NAME}; FK "
                f"minus ours {residual:.2g}): its native C++ `Solver.solve(T, respect_limits=0)` as `solve(T)` calls "
                f"it ({SSIK_SWEEP} swivel angles x 8 branches, LM-polished, no limit filter), and its feasible-swivel "
                "arcs `_swivel_limits._branch_arcs(branch, limits)` over `_enumerate_branches(kb, "
                "is_approximately_srs_7r(kb).base, T)` with our limits (the elbow's moved by whole turns to its "
                "value, which `_branch_arcs` compares as it is) (Python: the exact-S-R-S resolver on its "
                "best-fit pivots, which its in-limits fallback for approximate arms seeds LM from; not arcs of "
                "the real arm, and its arm angle is its swivel angle); one thread, default tolerance policy")
    return SsikFeasible(peer, approximate.base, [(float(lo), float(hi)) for lo, hi in zip(chain.lower, chain.upper)],
                        describe)


def ssik_feasible_arcs(peer: SsikFeasible, pose: np.ndarray) -> list[list[tuple[float, float]]]:
    """ssik's feasible-swivel arcs of each branch of its best-fit S-R-S arm at ``pose`` (:func:`load_ssik_feasible`)."""
    from ssik.solvers.seven_r._swivel_limits import _branch_arcs, _enumerate_branches

    arcs = []
    for branch in _enumerate_branches(peer.peer.kb, peer.classification, pose):
        # _branch_arcs compares the elbow's value with its limits as it is, not modulo whole turns (on the Jaco2,
        # q4 in [0.52, 5.76], it would drop every branch whose elbow comes out negative): its limits are moved by
        # the whole turns that bring the elbow's value into them, if any
        low, high = peer.limits[3]
        turns = 2.0 * np.pi * np.floor((branch.q3 - low) / (2.0 * np.pi))
        limits = [*peer.limits[:3], (low + turns, high + turns), *peer.limits[4:]]
        arcs.append(_branch_arcs(branch, limits))
    return arcs


def measure_feasible(name: str, count: int, samples: int, first: int = 0, near: int = 0,
                     ssik: bool = True) -> FeasibleResult:
    """``feasible_arm_angles_nearly_all`` on ``count`` random poses and ``near`` poses of each near draw
    (:func:`feasible_draws`) of one arm, every branch, against ``samples`` uniform arm angles (module docstring,
    "Feasible sets"); the poses are places ``first ..`` of each draw's sequence, so that a long run can be split into
    parts that together are the whole (flags name the draw and the place).  With ``ssik``, ssik's calls
    (:func:`load_ssik_feasible`) are timed on the same poses, each right after ours."""
    description, load = FEASIBLE_ARMS[name]
    chain = limited(load())
    arm = nearly_srs(chain)
    draws = feasible_draws(arm, count, near, first)
    poses = chain.fk(np.array([d.q for d in draws]))
    psi = np.linspace(-np.pi, np.pi, samples, endpoint=False)
    spacing = 2.0 * np.pi / samples
    peer = load_ssik_feasible(name, load()) if ssik else "not asked (ssik=False)"
    feasible_arm_angles_nearly_all(arm, poses[0])  # compiled (or loaded from the cache) before the clock
    if not isinstance(peer, str):
        ssik_native(peer.peer, poses[0])
        ssik_feasible_arcs(peer, poses[0])
    flags: list[Flag] = []
    sets: dict[tuple[str, int], tuple[NearlyFeasible, ...]] = {}
    where = {(d.kind, d.index): k for k, d in enumerate(draws)}
    tallies: dict[str, dict[str, Any]] = {}
    for k, draw in enumerate(draws):
        tally = tallies.setdefault(draw.kind, {"poses": 0, "nonempty": 0, "incomplete": 0, "agreeing": 0,
                                               "checked": 0, "narrow": 0, "differ": 0, "seconds": [],
                                               "sampling": 0.0, "native": [], "arcs": [], "ssik_nonempty": 0})
        start = time.perf_counter()
        every = feasible_arm_angles_nearly_all(arm, poses[k])
        tally["seconds"].append(time.perf_counter() - start)
        if not isinstance(peer, str):
            tally["native"].append(_seconds(lambda: ssik_native(peer.peer, poses[k])))
            start = time.perf_counter()
            theirs = ssik_feasible_arcs(peer, poses[k])
            tally["arcs"].append(time.perf_counter() - start)
            tally["ssik_nonempty"] += sum(bool(arcs) for arcs in theirs)
        complete = every[0].complete
        tally["poses"] += 1
        tally["incomplete"] += not complete
        start = time.perf_counter()
        feasible, different = sampled_feasible(arm, poses[k], psi)
        tally["sampling"] += time.perf_counter() - start
        tally["differ"] += different
        flagged = False
        for b in range(8):
            arcs = every[b].feasible
            tally["nonempty"] += not arcs.is_empty or bool(feasible[:, b].any())
            comparison = compare(psi, feasible[:, b], arcs, draw.index, b, draw.kind, complete)
            flags += comparison.flags
            flagged |= bool(comparison.flags)
            tally["agreeing"] += comparison.ends_agreeing
            tally["checked"] += comparison.ends_checked
            tally["narrow"] += comparison.narrow
        if flagged:
            sets[draw.kind, draw.index] = every

    def curves_of(flag: Flag) -> tuple[SelfMotion, ...]:
        return sets[flag.draw, flag.pose][0].curves

    def pose_of(flag: Flag) -> np.ndarray:
        return poses[where[flag.draw, flag.pose]]

    beyond = [f for f in flags if f.kind == "missed" and (
        (f.distance <= FOLD_SLACK and not exact_row(arm, pose_of(f), f.psi, f.branch))
        or row_leaves_branch(arm, pose_of(f), f.psi, f.branch,
                             np.asarray(sets[f.draw, f.pose][f.branch].feasible.arcs, dtype=float).ravel()))]
    missed = [f for f in flags if f.kind == "missed" and f not in beyond]
    second = [f for f in flags
              if f.kind == "false" and second_solution(arm, pose_of(f), f.psi, f.branch, curves_of(f))]
    boundary = [f for f in flags if f.kind == "false" and f not in second and f.samples == 1 and f.distance == 0.0
                and boundary_solution(arm, pose_of(f), f.psi, f.branch, curves_of(f))]
    false = [f for f in flags if f.kind == "false" and f not in second and f not in boundary]
    results = []
    for kind in DRAWS:
        if kind not in tallies:
            continue
        t = tallies[kind]

        def mine(values: list[Flag], kind: str = kind) -> list[Flag]:
            return [f for f in values if f.draw == kind]

        results.append(DrawResult(kind, t["poses"], 8 * t["poses"], t["nonempty"], t["incomplete"], mine(missed),
                                  mine(beyond), mine(false), mine(second), mine(boundary), t["agreeing"],
                                  t["checked"], t["narrow"], t["differ"], np.array(t["seconds"]), t["sampling"],
                                  np.array(t["native"]) if t["native"] else None,
                                  np.array(t["arcs"]) if t["arcs"] else None, t["ssik_nonempty"]))
    near_text = ""
    if near:
        near_text = (f"; {near} poses of each near draw (places {first}-{first + near - 1}: q uniform within the "
                     "limits, then q6 within 1e-6..1e-3 rad of a value where the neighbour's theta_6 is 0 or pi, q2 "
                     "the same for theta_2, q4 within 1e-5..1e-2 rad of the real arm's stretched elbow; "
                     "default_rng((38, k)))")
    values = {kind: singular_values(arm, NEAR_DRAWS[kind][0], kind == "stretched elbow", NEAR_DRAWS[kind][1][1])
              for kind in DRAWS[1:]}
    lines = [f"## feasible sets, {name}: {description}", "", f"- {arm.describe()}",
             f"- limits (rad): lower {np.round(chain.lower, 4).tolist()}, upper {np.round(chain.upper, 4).tolist()}"
             f"{'' if np.isfinite(load().lower).all() else f' (continuous joints given +-{CONTINUOUS_LIMIT})'}",
             f"- singular values of the near draws (user's joint values): q6 {np.round(values['straight wrist'], 9)}, "
             f"q2 {np.round(values['straight shoulder'], 9)}, q4 {np.round(values['stretched elbow'], 9)}",
             f"- {count} random poses (FK of q uniform within the limits, default_rng(3); places {first}-"
             f"{first + count - 1} of its sequence){near_text}; x 8 branches; {samples} arm angles sampled per pose "
             f"(spacing {spacing:.3g} rad)",
             f"- ssik: {peer if isinstance(peer, str) else peer.describe}", ""]
    lines += draw_table(results, spacing)
    counted = {**{f: "a missed run" for f in missed}, **{f: "beyond a fold (row not exact)" for f in beyond},
               **{f: "**a false run**" for f in false}, **{f: "held by a second solution" for f in second},
               **{f: "at the set's closed end (boundary_solution)" for f in boundary}}
    lines += classify(arm, draws, poses, where, flags, sets, spacing, counted)
    lines.append("")
    return FeasibleResult(name, lines, sum(r.pose_branches for r in results), missed, false, tuple(results),
                          peer if isinstance(peer, str) else peer.describe)


def _spread(seconds: np.ndarray) -> str:
    """Median / 90th percentile / largest of per-pose times."""
    return " / ".join(_us(float(v)) for v in (np.median(seconds), np.percentile(seconds, 90), seconds.max()))


def _farthest(values: list[Flag]) -> str:
    if not values:
        return "-"
    largest = max(f.distance for f in values)
    return "the set is empty" if np.isinf(largest) else f"{largest:.3g} rad"


def draw_table(results: list[DrawResult], spacing: float) -> list[str]:
    """One column per draw: the comparison with the sampling and the times per pose."""
    header = "| measurement | " + " | ".join(r.kind for r in results) + " |"
    lines = [header, "|---|" + "---|" * len(results)]

    def row(label: str, cell: Callable[[DrawResult], str]) -> None:
        lines.append(f"| {label} | " + " | ".join(cell(r) for r in results) + " |")

    def wide(r: DrawResult) -> list[Flag]:
        return [f for f in r.missed if f.samples >= 2]

    def split(values: list[Flag]) -> str:
        several = sum(f.samples >= 2 for f in values)
        return f"{several} / {len(values) - several}"

    row("poses (pose-branches with a feasible arm angle, computed or sampled)",
        lambda r: f"{r.poses} ({r.nonempty} of {r.pose_branches})")
    row("poses whose self-motion was not followed whole (`complete` False)",
        lambda r: f"{r.incomplete} ({_percent(r.incomplete, r.poses)})")
    row(f"missed runs: >= 2 feasible samples outside the set (wider than {spacing:.2g} rad) / single",
        lambda r: split(r.missed))
    row("  of them on poses not followed whole (allowed there)",
        lambda r: split([f for f in r.missed if not f.complete]))
    row("  widest run; farthest missed sample from the set",
        lambda r: f"{max((f.samples for f in r.missed), default=0)} samples; {_farthest(r.missed)}")
    row(f"  missed runs with a sample more than {MISSED:g} rad from the set, on poses followed whole",
        lambda r: str(sum(f.distance > MISSED and f.complete for f in r.missed)))
    row(f"runs outside the set, within {FOLD_SLACK:g} rad of its end, whose row is not exact (beyond a fold, "
        "`exact_row`; not counted above)",
        lambda r: f"{len(r.beyond)}; farthest {_farthest(r.beyond)}")
    row("**false runs: infeasible samples inside the set** (samples, deepest from the set's nearest end)",
        lambda r: f"{len(r.false)} ({sum(f.samples for f in r.false)}, {_farthest(r.false)})")
    row("runs inside the set held by a second solution within the limits (`second_solution`; runs, samples)",
        lambda r: f"{len(r.second)}, {sum(f.samples for f in r.second)}")
    row(f"one-sample false runs at a set's end with a solution within the limits {BOUNDARY_REACH:g} rad away "
        "(`boundary_solution`; not counted above)", lambda r: str(len(r.boundary)))
    row("ends of computed arcs within one spacing of the sampled boundary (arcs holding no sample)",
        lambda r: f"{r.ends_agreeing}/{r.ends_checked} ({r.narrow})")
    row("samples where our check and `nearly.ik`'s `within_limits` differ", lambda r: str(r.differ))
    row("`feasible_arm_angles_nearly_all`, 8 branches, per pose: median / p90 / max", lambda r: _spread(r.seconds))
    row(f"  within issue 38's {_us(POSE_TARGET)} per pose (median)",
        lambda r: "met" if np.median(r.seconds) <= POSE_TARGET else "**not met**")
    row("ssik native call, per pose (same poses): median / p90 / max",
        lambda r: "-" if r.ssik_native is None else _spread(r.ssik_native))
    row("  ours / ssik native, median (p90)",
        lambda r: "-" if r.ssik_native is None else
        f"{np.median(r.seconds) / np.median(r.ssik_native):.3g} x "
        f"({np.percentile(r.seconds, 90) / np.percentile(r.ssik_native, 90):.3g} x)")
    row("ssik feasible-swivel arcs of its best-fit S-R-S arm, 8 branches, per pose: median / p90 / max "
        "(branches with an arc)",
        lambda r: "-" if r.ssik_arcs is None else f"{_spread(r.ssik_arcs)} ({r.ssik_nonempty})")
    row("  ours / ssik's arcs, median", lambda r: "-" if r.ssik_arcs is None else
        f"{np.median(r.seconds) / np.median(r.ssik_arcs):.3g} x")
    row(f"sampling ({round(2.0 * np.pi / spacing)} arm angles, 8 branches per call), per pose",
        lambda r: _us(r.sample_seconds / max(r.poses, 1)))
    return lines


def classify(arm: NearlySRS, draws: list[Draw], poses: np.ndarray, where: dict[tuple[str, int], int],
             flags: list[Flag], sets: dict[tuple[str, int], tuple[NearlyFeasible, ...]], spacing: float,
             counted: dict[Flag, str]) -> list[str]:
    """One line per flagged run (the :data:`CLASSIFIED` first: false runs, then missed runs on poses followed
    whole, then the rest, each farthest from the set first), to reproduce and explain it: how it is ``counted``,
    ``nearly.ik``'s row at the run's arm angle, the oracle's (:func:`existing_branches`) solution of the branch
    there and whether it lies within the limits, where the solution lies (:func:`where_solutions_lie`), and the
    distance to the branch's nearest singular arm angle (``singular_arm_angles_nearly``)."""
    if not flags:
        return []
    order = ["**a false run**", "a missed run", "beyond a fold (row not exact)", "held by a second solution",
             "at the set's closed end (boundary_solution)"]
    chosen = sorted(flags, key=lambda f: (order.index(counted[f]) + 0.5 * (counted[f] == "a missed run"
                                                                           and not f.complete),
                                          -f.distance))[:CLASSIFIED]
    index = np.array([where[f.draw, f.pose] for f in chosen])
    angles = np.array([f.psi for f in chosen])
    q = np.array([d.q for d in draws])
    exists, solutions = existing_branches(arm, poses[index], angles, q[index])
    lines = ["", f"Flagged runs ({len(chosen)} of {len(flags)}, farthest from the set first; q: the pose's joint "
                 "vector, pose = FK(q) of the limited chain):", ""]
    for k, flag in enumerate(chosen):
        pose = poses[index[k]]
        every = sets[flag.draw, flag.pose]
        row = nearly.ik(arm, pose, flag.psi, BRANCH_NAMES[flag.branch])
        found = bool(row.exists[0])
        oracle = bool(exists[k, flag.branch])
        solution = row.q[0] if found else solutions[k, flag.branch]
        if found:
            verdict = f"nearly.ik row {'within' if row.within_limits[0] else 'outside'} the limits"
        else:
            verdict = "nearly.ik: branch missing"
        if oracle:
            inside = bool(arm.chain.within_limits(solutions[k, flag.branch], wrap=True))
            verdict += f"; oracle: a solution {'within' if inside else 'outside'} the limits"
        else:
            verdict += "; oracle: none"
        if found or oracle:
            verdict += f"; {where_solutions_lie(arm, pose[None], solution[None])[0]}; {_solution_facts(arm, solution)}"
        facts = _neighbour_facts(arm, pose, flag.psi, BRANCH_NAMES[flag.branch], solution, every[flag.branch].delta)
        singular = _singular(arm, pose, BRANCH_NAMES[flag.branch], every[0].curves)
        marks = np.array(singular.shoulder + singular.wrist)
        nearest = f"{np.abs(wrapped(marks - flag.psi)).min():.3g} rad" if marks.size else "none"
        lines.append(f"- {flag.kind}, counted as {counted[flag]}: {flag.draw} pose {flag.pose}, branch "
                     f"{BRANCH_NAMES[flag.branch]}, psi = "
                     f"{flag.psi!r} ({flag.samples} samples, about {flag.samples * spacing:.2g} rad wide; "
                     f"{flag.distance:.3g} rad from the set's nearest end); self-motion "
                     f"{'complete' if flag.complete else 'not followed whole'} ({len(every[0].curves)} curves, "
                     f"{every[0].samples} points); {verdict}; nearest singular arm angle {nearest}; "
                     f"{facts}; set {[(round(a, 6), round(b, 6)) for a, b in every[flag.branch].feasible.arcs]}; "
                     f"q = {q[index[k]].tolist()}")
    return lines


def _singular(arm: NearlySRS, pose: np.ndarray, branch: str, curves: tuple[SelfMotion, ...]) -> Any:
    """``singular_arm_angles_nearly`` of the pose and branch, on the pose's own ``curves`` where it takes them (no
    second trace of the self-motion)."""
    if "curves" in inspect.signature(singular_arm_angles_nearly).parameters:
        return singular_arm_angles_nearly(arm, pose, branch, curves=curves)
    return singular_arm_angles_nearly(arm, pose, branch)


def _solution_facts(arm: NearlySRS, solution: np.ndarray) -> str:
    """The joint of ``solution`` (7,) nearest its limit (modulo whole turns; negative: beyond it) and the sines of
    the neighbour's theta_2, theta_4 from the real stretched elbow, and theta_6 there."""
    lower, upper = arm.chain.lower, arm.chain.upper
    middle = 0.5 * (lower + upper)
    moved = middle + wrapped(solution - middle)
    margin = np.minimum(moved - lower, upper - moved)
    joint = int(np.argmin(margin))
    theta = arm.geometry.theta_of_q(solution)
    sines = np.abs(np.sin([theta[1], theta[3] - arm.real_phase, theta[5]]))
    return (f"tightest joint q{joint + 1} = {moved[joint]:.4f}, margin {margin[joint]:.3g} rad; |sin| of theta_2, "
            f"theta_4 - stretch, theta_6: {sines[0]:.2g}, {sines[1]:.2g}, {sines[2]:.2g}")


def _neighbour_facts(arm: NearlySRS, pose: np.ndarray, psi: float, branch: str, solution: np.ndarray,
                     delta: float) -> str:
    """The set's own ``delta`` (:attr:`NearlyFeasible.delta`), the difference of ``solution`` from the nearest of
    the neighbour's closed-form solutions at ``psi``, and whether the neighbour's set for limits loosened by
    ``delta`` holds ``psi`` (:attr:`NearlyFeasible.outer`'s premise for a feasible sample)."""
    if not reachable(arm.geometry, pose):
        return f"delta {delta:.3g} rad; the neighbour does not reach the pose"
    closed = np.stack([exact_ik(arm.geometry, pose, psi, name) for name in BRANCH_NAMES])
    gap = float(distance(closed[None], solution[None])[0].min()) if np.isfinite(solution).all() else np.nan
    loose = arm.neighbour.with_limits(arm.neighbour.lower - delta, arm.neighbour.upper + delta)
    holds = bool(feasible_arm_angles(srs_geometry(loose), pose, branch).feasible.contains(psi))
    return (f"delta {delta:.3g} rad, |q - q_N| there {gap:.3g} rad; the neighbour's set loosened by delta "
            f"{'holds' if holds else 'does not hold'} psi")


def feasible_table(results: list[FeasibleResult]) -> list[str]:
    """Issue 38's targets per arm and draw at the size run: no false run, no missed arc wider than 1e-6 rad on a
    pose followed whole, and the 8 branches of a pose within :data:`POSE_TARGET` (median)."""
    lines = ["## Issue 38 targets: certified nearly S-R-S sets vs dense sampling", "",
             "| arm | draw | poses | incomplete | missed runs (>= 2 samples / single) | farthest missed sample | "
             f"missed runs more than {MISSED:g} rad from the set on complete poses | false runs | per pose: median "
             "/ p90 / max | ours / ssik native (median) | target: no false run or far missed run | target: <= "
             f"{_us(POSE_TARGET)} per pose |", "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in results:
        for d in r.draws:
            wide = sum(f.samples >= 2 for f in d.missed)
            far = sum(f.distance > MISSED and f.complete for f in d.missed)
            ratio = "-" if d.ssik_native is None else f"{np.median(d.seconds) / np.median(d.ssik_native):.3g} x"
            lines.append(f"| {r.name} | {d.kind} | {d.poses} | {d.incomplete} | {wide} / {len(d.missed) - wide} | "
                         f"{_farthest(d.missed)} | {far} | {len(d.false)} | {_spread(d.seconds)} | {ratio} | "
                         f"{'met' if far == 0 and not d.false else '**not met**'} | "
                         f"{'met' if np.median(d.seconds) <= POSE_TARGET else '**not met**'} |")
    return lines


# ----------------------------------------------------------------------------- the targets
def targets_table(results: list[ArmResult]) -> list[str]:
    """The issue's targets per arm, each marked met or not met."""
    names = [r.name for r in results]
    lines = ["## Issue 27 targets", "", "| measurement | " + " | ".join(names) + " | target |",
             "|---|" + "---|" * len(names) + "---|"]

    def row(label: str, values: list[tuple[float, str] | None], goal: float, at_most: bool, text: str) -> None:
        cells = []
        for value in values:
            if value is None:
                cells.append("n/a")
                continue
            met = value[0] <= goal if at_most else value[0] >= goal
            cells.append(f"{value[1]}, {'met' if met else '**not met**'}")
        lines.append(f"| {label} | " + " | ".join(cells) + f" | {text} |")

    row("one pose, all branches at psi: redkin median", [(r.redkin_one.median, _us(r.redkin_one.median))
                                                         for r in results], 100e-6, True, "<= 100 µs")
    row("  the same / ssik native median (same poses)",
        [None if r.ssik_native is None else (r.redkin_one.median / r.ssik_native.median,
                                            f"{r.redkin_one.median / r.ssik_native.median:.2f} x")
         for r in results], 0.25, True, "<= 0.25 x")
    goals = (0.999, 0.99, 0.99)
    for k, goal in enumerate(goals):
        row(f"success, {('random', 'near the stretched elbow', 'near q3 = 0')[k]}: every existing branch, certified",
            [(r.redkin[k].found / r.redkin[k].poses, _percent(r.redkin[k].found, r.redkin[k].poses))
             for r in results], goal, False, f">= {goal * 100:g} %")
    return lines


def main(argv: Sequence[str] | None = None) -> list[ArmResult] | list[FeasibleResult]:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--poses", type=int, default=10_000, help="random poses per arm (default 10000)")
    parser.add_argument("--near", type=int, default=1000, help="poses per near-singular set (default 1000)")
    parser.add_argument("--ssik-python", type=int, default=1000,
                        help="poses for ssik's one-swivel Python call (default 1000)")
    parser.add_argument("--arms", nargs="+", choices=list(ARMS), default=list(ARMS), help="a subset of the arms")
    parser.add_argument("--quick", action="store_true", help="200 random poses, 50 near, 20 for the Python call")
    parser.add_argument("--feasible", action="store_true",
                        help="only the feasible sets against dense sampling (module docstring)")
    parser.add_argument("--feasible-poses", type=int, default=100,
                        help="random poses per arm for --feasible (default 100)")
    parser.add_argument("--feasible-near", type=int, default=0,
                        help="for --feasible, poses of each near draw (straight wrist, straight shoulder, stretched "
                             "elbow) besides the random ones (default 0)")
    parser.add_argument("--feasible-samples", type=int, default=10_000,
                        help="arm angles sampled per pose for --feasible (default 10000)")
    parser.add_argument("--feasible-arms", nargs="+", choices=list(FEASIBLE_ARMS), default=list(FEASIBLE_ARMS),
                        help="a subset of the arms for --feasible")
    parser.add_argument("--feasible-first", type=int, default=0,
                        help="for --feasible, start at this place of each draw's sequence (default 0): a long run in "
                             "parts")
    parser.add_argument("--feasible-no-ssik", action="store_true", help="for --feasible, do not time ssik")
    args = parser.parse_args(argv)
    if args.feasible:
        return main_feasible(args.feasible_arms, args.feasible_poses, args.feasible_samples, parser,
                             args.feasible_first, args.feasible_near, not args.feasible_no_ssik)
    count, near, python_count = (200, 50, 20) if args.quick else (args.poses, args.near, args.ssik_python)
    if min(count, near, python_count) < 1:
        parser.error("--poses, --near and --ssik-python must be positive")
    print("# Nearly S-R-S arm-angle IK, issue 27 (benchmarks/bench_nearly.py)\n")
    print("\n".join(machine_lines(("numpy", "numba", "ssik"))) + "\n", flush=True)
    results = []
    for name in args.arms:
        results.append(measure(name, count, near, python_count))
        print("\n".join(results[-1].lines), flush=True)
    print("\n".join(targets_table(results)))
    print(f"\n- load average at the end (1, 5, 15 min): {load_average()}")
    return results


def main_feasible(arms: Sequence[str], count: int, samples: int, parser: argparse.ArgumentParser,
                  first: int = 0, near: int = 0, ssik: bool = True) -> list[FeasibleResult]:
    """The feasible-set section alone (``--feasible``), on places ``first ..`` of each draw's sequence."""
    if count < 0 or near < 0 or count + near < 1 or samples < 8 or first < 0:
        parser.error("--feasible-poses and --feasible-near must be >= 0 and not both 0, --feasible-samples at least 8 "
                     "and --feasible-first >= 0")
    print("# Nearly S-R-S feasible arm angles vs dense sampling, issues 27 and 38 "
          "(benchmarks/bench_nearly.py --feasible)\n")
    print("\n".join(machine_lines(("numpy", "numba", "ssik"))) + "\n", flush=True)
    results = []
    for name in arms:
        start = time.perf_counter()
        results.append(measure_feasible(name, count, samples, first, near, ssik))
        print("\n".join(results[-1].lines), flush=True)
        print(f"- {name}: {time.perf_counter() - start:.0f} s wall, load average (1, 5, 15 min) {load_average()}\n",
              flush=True)
    print("\n".join(feasible_table(results)))
    print(f"\n- load average at the end (1, 5, 15 min): {load_average()}")
    return results


if __name__ == "__main__":
    main()
