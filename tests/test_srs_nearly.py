"""Nearly S-R-S arms (:mod:`redkin.srs.nearly`, docs/srs.md "Nearly S-R-S arms"), tried on the descriptions a user
has: the Kinova Gen3 (``kinova-gen3``), the ROS-Industrial iiwa (``examples/iiwa14_rosi.urdf``), the Jaco2
(``examples/jaco2.urdf``) and iiwa URDFs whose right angles are rounded.

Laws:

- **detection**: each is of class ``"nearly S-R-S"`` and its departures are the offsets a user knows (Gen3 11.75 mm
  between axes 1 and 3, 12.75 mm along axis 4, 0.35 mm between axes 5 and 7; ROS-I iiwa its 0.436 mm x-offset;
  Jaco2 1.6 mm at the shoulder and 11.4 mm at the elbow); ``redkin robots --show FILE --json`` states them in mm;
- **rounded angles**: an iiwa URDF with pi/2 written 1.570796, 1.57079633 or 1.5708 is snapped to class
  ``"S-R-S"``, and its arm-angle IK and feasible sets equal the exact iiwa's to the size of its rounding;
- **certificate**: every row of :func:`redkin.srs.nearly.ik` that exists reaches the pose (FK by
  :meth:`SerialChain.fk` within 1e-9 m and 1e-9 rad) at the requested arm angle (:func:`redkin.srs.nearly.arm_angle`
  within 1e-9 rad); nothing is NaN, a missing row is zeros, and ``within_limits`` is ``exists`` and within the
  chain's limits (modulo whole turns, as the closed forms report angles);
- **one per branch**: every row that exists lies on its own branch, the real arm's signs of theta_2, theta_4 from
  the real stretched elbow (dense sampling of q4 finds it) and theta_6, so no solution is listed twice;
- **the arm angle**: ``nearly.arm_angle`` (compiled) equals ``srs.arm_angle_of`` on the neighbour, and its
  closed-form gradient (Newton's seventh row) equals central differences;
- **completeness**: the configuration that made a random pose is found at its own arm angle on its own branch for at
  least 97 % of random poses; within 1 deg of the stretched elbow, of q3 = 0 and of theta_2 = pi its own branch is
  found for 99 % of poses, and every branch on which an oracle independent of ``nearly.ik`` finds a solution (damped
  Newton in numpy, benchmarks/bench_nearly.py's ``existing_branches``) for 99 % (98 % at theta_2 = pi);
- **shape**: a batch ``(..., 4, 4)`` equals the loop over its poses, one branch equals its row of all eight;
- **the same arm**: on the ROS-I iiwa the answers equal the exact ``kuka-iiwa14``'s at the same psi to the size of
  the 0.436 mm offset (relative to the 0.4 m links), away from singular configurations;
- **degenerate poses** (the stretched elbow, q3 = 0, the wrist on axis 1): what is found is certified;
- **bad input** (a NaN pose, psi of a shape that does not broadcast, an unknown branch, a bad tolerance) raises
  ValueError; a tolerance below the Gen3's offsets refuses it naming the 11.75 mm;
- the front door ``redkin.ik(chain, pose, psi=...)`` and ``redkin ik ROBOT --psi X --all --json`` give the same
  certified solutions and list the missing branches.
"""

from __future__ import annotations

import functools
import json
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import least_squares

import redkin
from redkin.arms.classify import arm_angle_class
from redkin.chain import SerialChain
from redkin.circle import wrap_angle
from redkin.cli.main import main
from redkin.errors import NotArmAngleClassError
from redkin.srs import (
    BRANCHES,
    arm_angle_of,
    feasible_arm_angles,
    ik_all_branches,
    nearly,
    nearly_srs,
    reachable,
)
from redkin.srs.conventions import departures
from redkin.srs.nearly import _kernels as _nearly_kernels

EXAMPLES = Path(__file__).resolve().parents[1] / "src" / "redkin" / "examples"
BENCHMARKS = Path(__file__).resolve().parents[1] / "benchmarks"
ROSI = EXAMPLES / "iiwa14_rosi.urdf"
JACO2 = EXAMPLES / "jaco2.urdf"
#: The certificate the API promises: metres, radians of rotation and of arm angle.
CERTIFICATE = 1e-9
#: The ROS-I iiwa's x-offset at joints 2 and 4 [m], as its file prints it, and the iiwa's forearm [m].
ROSI_OFFSET, LINK = 0.00043624, 0.4


def _bench():
    """benchmarks/bench_nearly.py, whose ``existing_branches`` is the oracle of which branches exist."""
    sys.path.insert(0, str(BENCHMARKS))
    import bench_nearly

    return bench_nearly


def _load(path: Path) -> SerialChain:
    from redkin.urdf import load_urdf

    return load_urdf(path)


@functools.cache
def _gen3() -> SerialChain:
    return redkin.get_robot("kinova-gen3")


@functools.cache
def _rosi() -> SerialChain:
    return _load(ROSI)


def _arm(name: str) -> nearly.NearlySRS:
    return nearly_srs(_gen3() if name == "gen3" else _rosi())


def _wrapped(angle: np.ndarray) -> np.ndarray:
    return np.angle(np.exp(1j * np.asarray(angle)))


def _pose_errors(reached: np.ndarray, target: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Position error [m] and rotation angle [rad] of poses (..., 4, 4) against targets, the angle from both the sine
    and the cosine of ``R_target^T R`` (accurate near 0)."""
    position = np.linalg.norm(reached[..., :3, 3] - target[..., :3, 3], axis=-1)
    relative = np.swapaxes(target[..., :3, :3], -1, -2) @ reached[..., :3, :3]
    sine = np.linalg.norm(relative - np.swapaxes(relative, -1, -2), axis=(-2, -1)) / (2.0 * np.sqrt(2.0))
    cosine = (np.trace(relative, axis1=-2, axis2=-1) - 1.0) / 2.0
    return position, np.arctan2(sine, cosine)


def _in_limits(chain: SerialChain, q: np.ndarray) -> np.ndarray:
    """Whether every joint of ``q`` (..., 7) has a value ``q_i + 2 pi k`` within its limits (1e-9 rad of slack);
    a joint without limits always does."""
    lower, upper = chain.lower - 1e-9, chain.upper + 1e-9
    limited = np.isfinite(lower) & np.isfinite(upper)
    turns = np.ceil((np.where(limited, lower, 0.0) - q) / (2.0 * np.pi))
    shifted = q + 2.0 * np.pi * turns
    return np.all(~limited | (shifted <= np.where(limited, upper, 0.0)), axis=-1)


def _random_q(chain: SerialChain, count: int, rng: np.random.Generator) -> np.ndarray:
    """Joint vectors uniform in the limits; a joint without limits anywhere in (-pi, pi)."""
    lower = np.where(np.isfinite(chain.lower), chain.lower, -np.pi)
    upper = np.where(np.isfinite(chain.upper), chain.upper, np.pi)
    return rng.uniform(lower, upper, (count, chain.n))


def _assert_certified(arm: nearly.NearlySRS, result: nearly.NearlySolutions, poses: np.ndarray,
                      psi: np.ndarray) -> None:
    """The law of every answer of :func:`nearly.ik`, with poses (N, 4, 4), psi (N,) and results (N, B, ...)."""
    q, exists = result.q, result.exists
    assert q.shape == exists.shape + (7,) and result.within_limits.shape == exists.shape
    assert result.parameter == "psi"
    assert np.all(np.isfinite(q))
    assert np.all(q[~exists] == 0.0)
    position, rotation = _pose_errors(arm.chain.fk(q), poses[:, None])
    angle = np.abs(_wrapped(nearly.arm_angle(arm, q) - psi[:, None]))
    assert np.all(position[exists] <= CERTIFICATE), position[exists].max()
    assert np.all(rotation[exists] <= CERTIFICATE), rotation[exists].max()
    assert np.all(angle[exists] <= CERTIFICATE), angle[exists].max()
    np.testing.assert_array_equal(result.within_limits, exists & _in_limits(arm.chain, q))
    # one solution per branch, on its own branch: rows never repeat a solution
    rows = np.broadcast_to([BRANCHES.index(branch) for branch in result.branches], exists.shape)
    np.testing.assert_array_equal(_real_branch(arm, q)[exists], rows[exists])


def _real_branch(arm: nearly.NearlySRS, q: np.ndarray) -> np.ndarray:
    """The index in :data:`BRANCHES` of each configuration's branch on the real arm: the signs of the neighbour's
    theta_2, theta_4 minus the real arm's stretched elbow and theta_6 at the same joint values."""
    theta = arm.geometry.theta_of_q(q)[..., [1, 3, 5]] - np.array([0.0, arm.real_phase, 0.0])
    signs = np.where(_wrapped(theta) < 0.0, -1.0, 1.0)
    return np.argmax(np.all(signs[..., None, :] == arm.geometry.kernel_branches, axis=-1), axis=-1)


def _own_branch(arm: nearly.NearlySRS, q: np.ndarray) -> np.ndarray:
    """The index in :data:`BRANCHES` of each configuration's own branch (the neighbour's signs at the same q)."""
    return np.array([BRANCHES.index(tuple(int(s) for s in signs)) for signs in arm_angle_of(arm.geometry, q).branch])


def _found_itself(arm: nearly.NearlySRS, q: np.ndarray) -> np.ndarray:
    """Whether :func:`nearly.ik` of each configuration's pose at its own arm angle returns it on its own branch."""
    result = nearly.ik(arm, arm.chain.fk(q), nearly.arm_angle(arm, q))
    rows, own = np.arange(len(q)), _own_branch(arm, q)
    gap = np.abs(_wrapped(result.q[rows, own] - q)).max(axis=-1)
    return result.exists[rows, own] & (gap <= 1e-6)


def _meeting_point(points: np.ndarray, directions: np.ndarray) -> np.ndarray:
    """The least-squares meeting point of lines (unit directions)."""
    across = np.eye(3) - directions[:, :, None] * directions[:, None, :]
    return np.linalg.solve(across.sum(axis=0), np.einsum("kij,kj->i", across, points))


def _wrist_from_axis_1(chain: SerialChain, q: np.ndarray) -> np.ndarray:
    """The vector from axis 1 to the wrist (the meeting point of axes 5-7) across axis 1, at one q."""
    directions, points = chain.joint_axes(q)
    across = _meeting_point(points[4:], directions[4:]) - points[0]
    return across - (across @ directions[0]) * directions[0]


def _wrist_on_axis_1(chain: SerialChain, q: np.ndarray) -> np.ndarray:
    """``q`` with q2 and q3 moved so that the wrist lies on axis 1 (to about 1e-15 m)."""
    def gap(values: np.ndarray) -> np.ndarray:
        return _wrist_from_axis_1(chain, np.concatenate([q[:1], values, q[3:]]))

    found = least_squares(gap, q[1:3], xtol=1e-15, ftol=1e-15, gtol=1e-15).x
    moved = np.concatenate([q[:1], found, q[3:]])
    assert np.linalg.norm(gap(found)) <= 1e-12
    return moved


# ---------------------------------------------------------------------------------------------------- detection


def test_gen3_is_nearly_srs_with_its_offsets():
    chain = _gen3()
    kind = arm_angle_class(chain)
    assert kind.kind == "nearly S-R-S"
    assert kind.reason == f"{nearly_srs(chain).describe()}, and solutions are polished on the real arm"
    found = {what: value for what, value, unit in departures(chain) if unit == "m"}
    assert found["axes 1 and 3 miss each other by"] == pytest.approx(0.01175, abs=1e-9)
    assert found["the elbow is offset along axis 4 by"] == pytest.approx(0.01275, abs=1e-9)
    assert found["axes 5 and 7 miss each other by"] == pytest.approx(0.00035, abs=2e-7)  # 0.3501 mm
    assert [what for what, _, _ in departures(chain)[:3]] == [
        "the elbow is offset along axis 4 by", "axes 1 and 3 miss each other by", "axes 5 and 7 miss each other by"]
    for millimetres in ("11.75 mm", "12.75 mm", "0.3501 mm"):
        assert millimetres in kind.reason


def test_rosi_iiwa_is_nearly_srs_with_its_offset():
    chain = _rosi()
    assert arm_angle_class(chain).kind == "nearly S-R-S"
    dropped = departures(chain)
    # the file's x-offsets at joints 2 and 4 (-0.43624 and +0.43624 mm) put axes 2 and 3 that far from axis 1
    assert {what for what, _, _ in dropped} == {"axes 1 and 2 miss each other by", "axes 1 and 3 miss each other by"}
    assert all(unit == "m" and value == pytest.approx(ROSI_OFFSET, abs=1e-12) for _, value, unit in dropped)
    assert "0.4362 mm" in arm_angle_class(chain).reason


def test_jaco2_is_nearly_srs_with_its_offsets():
    if not JACO2.exists():
        pytest.skip("examples/jaco2.urdf is not there")
    chain = _load(JACO2)
    assert arm_angle_class(chain).kind == "nearly S-R-S"
    found = {what: value for what, value, unit in departures(chain)}
    # the file's joint 2 origin y = 0.0016 m and joint 5 origin z = -0.0114 m; its right angles are exact
    assert found == pytest.approx({"the elbow is offset along axis 4 by": 0.0114,
                                   "axes 1 and 3 miss each other by": 0.0016}, abs=1e-12)


@pytest.mark.parametrize(("robot", "states"), [
    ("kinova-gen3", ("11.75 mm", "12.75 mm", "0.3501 mm")),
    (str(EXAMPLES / "gen3.urdf"), ("11.75 mm", "12.75 mm", "0.3505 mm")),
    (str(ROSI), ("axes 1 and 2 miss each other by 0.4362 mm",)),
    (str(JACO2), ("the elbow is offset along axis 4 by 11.4 mm", "axes 1 and 3 miss each other by 1.6 mm")),
])
def test_cli_robots_show_states_the_offsets(capsys, robot, states):
    if robot.endswith(".urdf"):
        if not Path(robot).exists():
            pytest.skip(f"{robot} is not there")
    assert main(["robots", "--show", robot, "--json"]) == 0
    shown = json.loads(capsys.readouterr().out)
    assert shown["class"] == "nearly S-R-S"
    for text in states:
        assert text in shown["class_reason"]


# ---------------------------------------------------------------------------------------------- rounded angles

#: pi/2 as examples/iiwa14.urdf prints it, and the roundings a user's file may have instead
_HALF_PI_PRINTED = "1.57079632679490"
ROUNDED = ("1.570796", "1.57079633", "1.5708")


@pytest.fixture(scope="module")
def rounded(tmp_path_factory) -> dict[str, SerialChain]:
    """examples/iiwa14.urdf with its pi/2 written with each of :data:`ROUNDED`'s digits."""
    text = (EXAMPLES / "iiwa14.urdf").read_text()
    assert text.count(_HALF_PI_PRINTED) == 6
    folder = tmp_path_factory.mktemp("rounded")
    chains = {}
    for digits in ROUNDED:
        path = folder / f"iiwa14_{digits}.urdf"
        path.write_text(text.replace(_HALF_PI_PRINTED, digits))
        chains[digits] = _load(path)
    return chains


def _rounding(chain: SerialChain) -> float:
    """The description's rounding: its largest departure from S-R-S (radians off perpendicular here)."""
    (_, value, unit), *_ = departures(chain)
    assert unit == "rad"
    return value


def _conditioning(chain: SerialChain, q: np.ndarray) -> np.ndarray:
    """``min(|sin q2|, |sin q4|, |sin q6|, rho / 0.4 m)`` of exact-iiwa configurations (..., 7), ``rho`` the wrist's
    distance from axis 1: near 0 the joint values move far for a small change of the arm (a singular shoulder,
    elbow or wrist, or an arm angle whose reference plane turns fast)."""
    flat = q.reshape(-1, 7)
    rho = np.array([np.linalg.norm(_wrist_from_axis_1(chain, row)) for row in flat]).reshape(q.shape[:-1])
    return np.minimum(np.abs(np.sin(q[..., [1, 3, 5]])).min(axis=-1), rho / LINK)


@pytest.mark.parametrize("digits", ROUNDED)
def test_rounded_iiwa_is_snapped_to_srs(rounded, digits):
    chain = rounded[digits]
    kind = arm_angle_class(chain)
    assert kind.kind == "S-R-S"
    assert "rounding" in kind.reason
    assert 1e-9 < _rounding(chain) <= 1e-5  # 3.2e-9 (8 digits), 3.3e-7 (6 digits), 3.7e-6 rad (1.5708)


@pytest.mark.parametrize("digits", ROUNDED)
def test_rounded_iiwa_ik_equals_exact_to_its_rounding(rounded, digits):
    exact, chain = _load(EXAMPLES / "iiwa14.urdf"), rounded[digits]
    rng = np.random.default_rng(11)
    q = _random_q(exact, 500, rng)
    q[:, 3] = np.where(q[:, 3] < 0.0, np.minimum(q[:, 3], -0.1), np.maximum(q[:, 3], 0.1))  # in reach of both
    poses, psi = exact.fk(q), arm_angle_of(exact, q).psi
    expected = ik_all_branches(exact, poses, psi)
    difference = np.abs(_wrapped(ik_all_branches(chain, poses, psi) - expected)).max(axis=-1)
    # |dq| * conditioning <= 25 x the rounding; measured (seed 11, 4000 solutions) at most 13.8 x for each of the
    # three roundings (17.5 x over 16 000 solutions of another seed); the largest |dq| 4.1e-6, 4.1e-4 and 4.6e-3 rad
    # for 8 digits, 6 digits and 1.5708, near singular configurations
    assert np.all(difference * _conditioning(exact, expected) <= 25.0 * _rounding(chain))


@pytest.mark.parametrize("digits", ROUNDED)
def test_rounded_iiwa_feasible_sets_equal_exact_to_their_rounding(rounded, digits):
    exact, chain = _load(EXAMPLES / "iiwa14.urdf"), rounded[digits]
    rng = np.random.default_rng(12)
    q = _random_q(exact, 40, rng)
    q[:, 3] = np.where(q[:, 3] < 0.0, np.minimum(q[:, 3], -0.1), np.maximum(q[:, 3], 0.1))
    worst = 0.0
    for pose in exact.fk(q):
        for branch in BRANCHES:
            mine, theirs = feasible_arm_angles(chain, pose, branch).feasible, feasible_arm_angles(exact, pose,
                                                                                                  branch).feasible
            worst = max(worst, mine.union(theirs).length - mine.intersection(theirs).length)
    # the measure of the symmetric difference of the two sets: measured 104 x the rounding here (seed 12, 40 poses
    # x 8 branches), 250 x over 300 poses of another seed, for each rounding (an arc's end moves by the rounding
    # over theta_i's slope where it meets a limit)
    assert worst <= 1e3 * _rounding(chain)


# ------------------------------------------------------------------------------------------- the laws of nearly.ik


@settings(max_examples=30, deadline=None)
@given(st.sampled_from(["gen3", "rosi"]), st.integers(0, 2**32 - 1), st.booleans())
def test_every_answer_is_certified(name, seed, own_angle):
    arm, rng = _arm(name), np.random.default_rng(seed)
    q = _random_q(arm.chain, 40, rng)
    poses = arm.chain.fk(q)
    psi = nearly.arm_angle(arm, q) if own_angle else rng.uniform(-np.pi, np.pi, len(q))
    result = nearly.ik(arm, poses, psi)
    assert result.q.shape == (40, 8, 7) and result.branches == BRANCHES
    _assert_certified(arm, result, poses, psi)
    assert result.exists.any()


@pytest.mark.parametrize(("name", "rate"), [("gen3", 0.97), ("rosi", 0.97)])
def test_the_configuration_is_found_at_its_own_arm_angle(name, rate):
    arm = _arm(name)
    q = _random_q(arm.chain, 2000, np.random.default_rng(2026))
    # measured (seed 2026): Gen3 99.5 %, ROS-I iiwa 100 %; the Gen3's misses lie near singular configurations, where
    # the real arm has a second solution on the same branch and the row holds that one
    assert _found_itself(arm, q).mean() >= rate


def test_arm_angle_is_the_neighbours_and_its_gradient_central_differences():
    """nearly.arm_angle (compiled) equals srs.arm_angle_of on the neighbour at the same q; the kernel's closed-form
    gradient (the Newton row of nearly.ik) equals central differences of it (joints 5-7 do not move it)."""
    arm = _arm("gen3")
    q = _random_q(arm.chain, 300, np.random.default_rng(41))
    psi = nearly.arm_angle(arm, q)
    assert np.abs(_wrapped(psi - arm_angle_of(arm.geometry, q).psi)).max() <= 1e-12
    work, gradient = _nearly_kernels.scratch()[0][2], np.empty((len(q), 7))
    for k in range(len(q)):
        value = _nearly_kernels.arm_angle_one(q[k], *arm.kernel_model, work, gradient[k], True)
        assert abs(_wrapped(value - psi[k])) <= 1e-15
    step, differences = 1e-6, np.empty_like(gradient)
    for j in range(7):
        turned = np.zeros(7)
        turned[j] = step
        differences[:, j] = _wrapped(nearly.arm_angle(arm, q + turned) - nearly.arm_angle(arm, q - turned)) / (2 * step)
    # measured: at most 3.1e-9 apart (central differences' rounding, 1e-16 / 1e-6 times the slope)
    np.testing.assert_allclose(gradient, differences, atol=1e-7 * (1.0 + np.abs(differences).max()))
    assert np.all(gradient[:, 4:] == 0.0)


@pytest.mark.parametrize("name", ["gen3", "rosi", "jaco2"])
def test_real_stretched_elbow_is_where_the_elbow_reaches_farthest(name):
    """NearlySRS.real_phase: the neighbour's theta_4 where the distance between a point of axis 3 and a point of axis
    5 (their nearest to axes 2 and 6) is largest, found here by dense sampling of q4 with the other joints fixed."""
    if name == "jaco2" and not JACO2.exists():
        pytest.skip("examples/jaco2.urdf is not there")
    arm = _arm(name) if name != "jaco2" else nearly_srs(_load(JACO2))
    chain, rng = arm.chain, np.random.default_rng(5)
    q = np.repeat(_random_q(chain, 1, rng), 20001, axis=0)
    q[:, 3] = np.linspace(-np.pi, np.pi, 20001)
    directions, points = chain.joint_axes(q)
    def nearest(k: int, other: int) -> np.ndarray:  # the point of axis k nearest axis `other`
        d, e, across = directions[:, k], directions[:, other], points[:, k] - points[:, other]
        b = np.sum(d * e, axis=-1)
        return points[:, k] + ((b * np.sum(e * across, -1) - np.sum(d * across, -1)) / (1.0 - b * b))[:, None] * d
    distance = np.linalg.norm(nearest(2, 1) - nearest(4, 5), axis=-1)
    farthest = arm.geometry.theta_of_q(q[np.argmax(distance)])[3]
    assert abs(_wrapped(farthest - arm.real_phase)) <= 2.0 * np.pi / 20000
    # the Gen3's and Jaco2's offsets lie along the elbow axis or across axis 1 and keep the neighbour's stretch; the
    # ROS-I iiwa's x-offset at joint 4 turns it by atan(0.436 mm / 420 mm), its shoulder-elbow length
    moved = abs(_wrapped(arm.real_phase - arm.geometry.elbow_equation.phase))
    if name == "rosi":
        assert moved == pytest.approx(np.arctan(ROSI_OFFSET / 0.42), rel=1e-3)
    else:
        assert moved <= 1e-9


def _near(q: np.ndarray, rng: np.random.Generator, arm: nearly.NearlySRS, case: str) -> np.ndarray:
    """``q`` moved within 1 deg of a degenerate configuration: the stretched elbow, q3 = 0, or theta_2 = pi."""
    q = q.copy()
    theta = arm.geometry.theta_of_q(q)
    near = np.radians(rng.uniform(-1.0, 1.0, len(q)))
    if case == "stretched elbow":
        theta[:, 3] = arm.real_phase + near
    elif case == "theta_2 = pi":
        theta[:, 1] = np.pi + near
    else:
        return np.concatenate([q[:, :2], near[:, None], q[:, 3:]], axis=1)
    return arm.geometry.q_of_theta(theta)


# Measured (seed 31, 300 poses each; the oracle of benchmarks/bench_nearly.py, independent of nearly.ik, run on the
# poses with fewer than 8 rows), near the stretched elbow / q3 = 0 / theta_2 = pi: Gen3 own branch 100 / 100 /
# 99.7 %, every branch the oracle finds 99.7 / 100 / 99.0 %; ROS-I iiwa own branch 100 % throughout, every branch
# 100 / 100 / 99.7 %.  The misses lie with theta_2 within a few mrad of pi (where the sign of theta_2, and so the
# branch, of two nearby solutions differs) or the wrist near axis 1 (where the arm angle degenerates).
@pytest.mark.parametrize("name", ["gen3", "rosi"])
@pytest.mark.parametrize("case", ["stretched elbow", "q3 = 0", "theta_2 = pi"])
def test_existing_branches_are_found_near_degenerate_configurations(name, case):
    """Near the stretched elbow, q3 = 0 and the shoulder's theta_2 = pi: the configuration's own branch is found
    (it exists: the configuration lies on it), and so is every branch on which the test's oracle finds a solution
    (damped Newton in numpy from 64 starts per pose, benchmarks/bench_nearly.py's existing_branches)."""
    bench = _bench()
    arm, rng = _arm(name), np.random.default_rng(31)
    q = _near(_random_q(arm.chain, 300, rng), rng, arm, case)
    poses, psi = arm.chain.fk(q), nearly.arm_angle(arm, q)
    result = nearly.ik(arm, poses, psi)
    _assert_certified(arm, result, poses, psi)
    assert result.exists[np.arange(len(q)), _real_branch(arm, q)].mean() >= 0.99
    short = np.flatnonzero(result.exists.sum(axis=-1) < 8)
    exists, _ = bench.existing_branches(arm, poses[short], psi[short], q[short])
    missed = (exists & ~result.exists[short]).any(axis=-1)
    assert missed.sum() <= (0.02 if case == "theta_2 = pi" else 0.01) * len(q)


@settings(max_examples=10, deadline=None)
@given(st.sampled_from(["gen3", "rosi"]), st.integers(0, 2**32 - 1), st.booleans())
def test_batch_equals_loop(name, seed, scalar_psi):
    arm, rng = _arm(name), np.random.default_rng(seed)
    poses = arm.chain.fk(_random_q(arm.chain, 6, rng)).reshape(2, 3, 4, 4)
    psi = rng.uniform(-np.pi, np.pi, () if scalar_psi else (2, 3))
    batch = nearly.ik(arm, poses, psi)
    assert batch.q.shape == (2, 3, 8, 7) and batch.exists.shape == batch.within_limits.shape == (2, 3, 8)
    angles = np.broadcast_to(psi, (2, 3))
    for index in np.ndindex(2, 3):
        one = nearly.ik(arm, poses[index], angles[index])
        assert one.q.shape == (8, 7)
        np.testing.assert_array_equal(batch.q[index], one.q)
        np.testing.assert_array_equal(batch.exists[index], one.exists)
        np.testing.assert_array_equal(batch.within_limits[index], one.within_limits)


@settings(max_examples=10, deadline=None)
@given(st.sampled_from(["gen3", "rosi"]), st.integers(0, 2**32 - 1), st.sampled_from(BRANCHES), st.booleans())
def test_one_branch_is_its_row_of_all(name, seed, branch, as_text):
    arm, rng = _arm(name), np.random.default_rng(seed)
    q = _random_q(arm.chain, 20, rng)
    poses, psi = arm.chain.fk(q), nearly.arm_angle(arm, q) + rng.normal(0.0, 0.3, len(q))
    every, one = nearly.ik(arm, poses, psi), nearly.ik(arm, poses, psi, str(branch) if as_text else branch)
    row = BRANCHES.index(branch)
    assert one.branches == (branch,) and one.q.shape == (20, 1, 7)
    np.testing.assert_array_equal(one.q[:, 0], every.q[:, row])
    np.testing.assert_array_equal(one.exists[:, 0], every.exists[:, row])
    np.testing.assert_array_equal(one.within_limits[:, 0], every.within_limits[:, row])


def test_rosi_iiwa_answers_equal_the_exact_iiwa():
    arm, exact = _arm("rosi"), redkin.get_robot("kuka-iiwa14")
    q = _random_q(arm.chain, 1000, np.random.default_rng(3))
    poses = arm.chain.fk(q)
    psi = nearly.arm_angle(arm, q)
    # the same arm angle: the ROS-I iiwa's at q is the exact iiwa's at q (measured 7e-15 rad)
    assert np.abs(_wrapped(psi - arm_angle_of(exact, q).psi)).max() <= 1e-12
    inside = reachable(exact, poses)
    result = nearly.ik(arm, poses[inside], psi[inside])
    expected = ik_all_branches(exact, poses[inside], psi[inside])
    both = result.exists
    # measured: 99.77 % of the exact iiwa's solutions have a certified ROS-I counterpart
    assert both.mean() >= 0.97
    difference = np.abs(_wrapped(result.q - expected)).max(axis=-1)[both]
    # |dq| * conditioning <= 25 x offset / 0.4 m (measured 16.4 x; the median |dq| is 2.6e-3 rad, 2.4 x 1.1e-3,
    # 1 % above 0.059 rad, near singular configurations or the wrist near axis 1)
    assert np.all(difference * _conditioning(exact, expected)[both] <= 25.0 * ROSI_OFFSET / LINK)
    # and the exact iiwa puts the ROS-I answers within 3 offsets of the pose (measured 0.87 mm, 2 offsets)
    targets = np.broadcast_to(poses[inside][:, None], result.q.shape[:2] + (4, 4))
    position, _ = _pose_errors(exact.fk(result.q[both]), targets[both])
    assert position.max() <= 3.0 * ROSI_OFFSET


def _stretched(q: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    q = q.copy()
    q[:, 3] = np.radians(rng.uniform(-1.0, 1.0, len(q)))
    q[:5, 3] = 0.0
    return q


def _q3_zero(q: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    q = q.copy()
    q[:, 2] = np.radians(rng.uniform(-1.0, 1.0, len(q)))
    q[:5, 2] = 0.0
    return q


# Success rates at these poses (1000 poses each made by _stretched and _q3_zero, seed 101: the configuration itself
# found at its own arm angle, and in brackets a certified row on its own branch): Gen3 stretched 79.7 % (99.6 %),
# q3 = 0 99.4 % (99.9 %), random 99.5 % (100 %); ROS-I iiwa stretched 96.8 % (99.6 %), q3 = 0 100 % (100 %), random
# 100 % (100 %).  Near the stretch the real arm can have two solutions on one branch (the elbow's sign is that of
# theta_4 from the real stretched elbow, and both lie on one side), and a row holds one of them (Gen3 q = (-2.74,
# 1.13, 2.33, 0.0072, 2.48, 2.0, -3.03): +++ returns q4 = 0.0343 and the
# elbow-down branches are missing).  With the wrist on axis 1 the arm angle is degenerate
# (paper 000's reference plane is not defined there): on the ROS-I iiwa every configuration of such a pose has
# psi = 0 or pi, on the Gen3 its psi lie on an arc of about 0.7 rad, so other psi have no solution and a certified
# answer at the pose's own psi need not be its configuration (ROS-I 0 %, own branch certified for every pose;
# Gen3 3.3 %).  1e-3 rad of q2 away from it, the ROS-I iiwa has solutions at every psi again.
@pytest.mark.parametrize("name", ["gen3", "rosi"])
@pytest.mark.parametrize("case", ["stretched elbow", "q3 = 0", "wrist on axis 1"])
def test_degenerate_poses_are_certified(name, case):
    arm, rng = _arm(name), np.random.default_rng(27)
    q = _random_q(arm.chain, 40, rng)
    if case == "stretched elbow":
        q = _stretched(q, rng)
    elif case == "q3 = 0":
        q = _q3_zero(q, rng)
    else:
        q = np.array([_wrist_on_axis_1(arm.chain, row) for row in q[:15]])
    poses = arm.chain.fk(q)
    own = nearly.arm_angle(arm, q)
    for psi in (own, rng.uniform(-np.pi, np.pi, len(q))):
        result = nearly.ik(arm, poses, psi)
        _assert_certified(arm, result, poses, psi)
        assert result.exists.any() or psi is not own  # at its own arm angle, each pose has its configuration


def _nan_position(home: np.ndarray) -> np.ndarray:
    pose = home.copy()
    pose[0, 3] = np.nan
    return pose


@pytest.mark.parametrize(("make_pose", "psi", "branch"), [
    (lambda home: np.full((4, 4), np.nan), 0.0, None),
    (_nan_position, 0.0, None),
    (lambda home: home[:3, :3], 0.0, None),
    (lambda home: home, np.nan, None),
    (lambda home: home, "a quarter", None),
    (lambda home: np.stack([home, home]), np.zeros(3), None),
    (lambda home: home, 0.0, "++x"),
    (lambda home: home, 0.0, "++++"),
    (lambda home: home, 0.0, (1, 2, 1)),
])
def test_bad_input_raises_value_error(make_pose, psi, branch):
    arm = _arm("gen3")
    with pytest.raises(ValueError):
        nearly.ik(arm, make_pose(arm.chain.fk(np.full(7, 0.3))), psi, branch)


def test_an_arm_angle_turns_whole_turns_before_it_is_solved():
    """An arm angle of 1e8 rad is the arm angle it wraps to (the Newton steps compare arm angles: it found no
    solution there; the exact classes wrapped it already)."""
    arm = _arm("gen3")
    pose = arm.chain.fk(np.full(7, 0.3))
    far, near = nearly.ik(arm, pose, 1e8), nearly.ik(arm, pose, float(wrap_angle(1e8)))
    assert far.exists.any()
    np.testing.assert_array_equal(far.exists, near.exists)
    np.testing.assert_array_equal(far.q, near.q)


def test_tolerance_below_the_offsets_refuses_naming_them():
    with pytest.raises(NotArmAngleClassError) as refused:
        nearly_srs(_gen3(), tolerance=1e-4)
    assert isinstance(refused.value, ValueError)
    assert "0.01175 m" in str(refused.value) or "11.75 mm" in str(refused.value)


def test_tolerance_above_every_departure_accepts():
    """The tolerance holds for the departures as reported: a tolerance of 13 mm, above every departure of the Gen3
    (12.75 mm the largest), accepts it (its elbow offset was once measured on the moved axes, 18.8 mm)."""
    chain = _gen3()
    assert max(value for _what, value, _unit in departures(chain)) < 0.013
    assert nearly_srs(chain, tolerance=0.013).neighbour.n == 7


@pytest.mark.parametrize("tolerance", [0.01, 0.03, 0.044, 0.046, 0.05])
def test_an_offset_elbow_is_dropped_only_within_the_tolerance(tolerance):
    """A WAM (offset elbow, a_3 = 45 mm) with a 0.3 mm shoulder offset: its neighbour keeps the offset elbow while
    the tolerance is under 45 mm, the axes' distance as a user measures it, and drops it from there on; every
    departure it reports lies within the tolerance (the plain elbow was once decided by the axes' distance from a
    least-squares point, 22.5 mm, so that 30 mm dropped the 45 mm offset)."""
    a = np.array([0.0003, 0.0, 0.045, -0.045, 0.0, 0.0, 0.0])
    chain = SerialChain(a=a, alpha=np.array([-np.pi / 2, np.pi / 2] * 3 + [0.0]),
                        d=np.array([0.0, 0.0, 0.55, 0.0, 0.3, 0.0, 0.06]), name="wam-shoulder-offset")
    arm = nearly_srs(chain, tolerance)
    assert max(value for _what, value, unit in arm.departures if unit == "m") <= tolerance
    assert (np.abs(arm.neighbour.a).max() > 0.04) == (tolerance < 0.045)


@pytest.mark.parametrize("tolerance", [0.0, -0.01, np.nan, np.inf])
def test_bad_tolerance_raises_value_error(tolerance):
    with pytest.raises(ValueError, match="tolerance"):
        nearly_srs(_gen3(), tolerance=tolerance)


# ---------------------------------------------------------------------------------------- front door and the CLI


def test_front_door_solves_the_gen3_at_psi():
    arm = _arm("gen3")
    q = _random_q(arm.chain, 30, np.random.default_rng(5))
    poses, psi = arm.chain.fk(q), nearly.arm_angle(arm, q)
    result = redkin.ik(arm.chain, poses, psi=psi)
    assert result.parameter == "psi" and result.branches == BRANCHES
    _assert_certified(arm, result, poses, psi)
    direct = nearly.ik(arm, poses, psi)
    np.testing.assert_array_equal(result.q, direct.q)
    np.testing.assert_array_equal(result.exists, direct.exists)
    one = redkin.ik(arm.chain, poses, psi=psi, branch="-+-")
    np.testing.assert_array_equal(one.q[:, 0], direct.q[:, BRANCHES.index((-1, 1, -1))])


def test_cli_ik_psi_all_json(capsys):
    arm = _arm("gen3")
    q = np.array([0.4, 0.7, -0.3, 1.2, 0.5, -0.9, 0.2])
    pose = arm.chain.fk(q)
    psi = float(nearly.arm_angle(arm, q))
    argv = ["ik", "kinova-gen3", "--position", *map(repr, pose[:3, 3].tolist()),
            "--rotation", *map(repr, pose[:3, :3].ravel().tolist()), "--psi", repr(psi), "--all", "--json"]
    assert main(argv) == 0
    answer = json.loads(capsys.readouterr().out)
    assert answer["parameter"] == "psi" and answer["psi"] == psi
    expected = nearly.ik(arm, pose, psi)
    found = {row["branch"]: row for row in answer["solutions"]}
    assert set(found) == {str(b) for b, e in zip(BRANCHES, expected.exists) if e}
    assert answer["missing"] == [str(b) for b, e in zip(BRANCHES, expected.exists) if not e]
    assert len(found) >= 1
    solutions = np.array([found[label]["q"] for label in found])
    position, rotation = _pose_errors(arm.chain.fk(solutions), pose)
    assert position.max() <= CERTIFICATE and rotation.max() <= CERTIFICATE
    assert np.abs(_wrapped(nearly.arm_angle(arm, solutions) - psi)).max() <= CERTIFICATE
    own = str(BRANCHES[_own_branch(arm, q[None])[0]])
    np.testing.assert_allclose(found[own]["q"], q, atol=1e-9)
    for row in found.values():
        assert row["within_limits"] == bool(_in_limits(arm.chain, np.array(row["q"])))
