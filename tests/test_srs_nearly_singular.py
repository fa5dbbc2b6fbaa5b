"""Singular arm angles of nearly S-R-S arms on the real arm (:mod:`redkin.srs.nearly.singular`).

Laws, on the Kinova Gen3, the Jaco2 and the ROS-Industrial iiwa as the examples' URDFs describe them, with
configurations written in the user's joint values and every alignment judged here, independently of redkin, from
the joint axes that the URDF's own joints compose to (:func:`tests.support.urdf_reference.reference_fk`): a pair is
aligned where the angle between its axes' directions is 0 or pi.

- **q_2 = 0 and q_6 = 0 are found**: on these arms (the Gen3's are ``theta = pi`` of the Table 1 form, the
  Jaco2's and the iiwa's ``theta = 0``) a random configuration with ``q_2 = 0`` (``q_6 = 0``) has axes 1 and 3
  (5 and 7) aligned, and its pose has its arm angle (:func:`redkin.srs.nearly.arm_angle`) among the singular arm
  angles on both branches that meet there, with a nearest approach of 0; the same at ``q = pi``, where the Gen3's
  URDF (pi/2 written as 1.5708) leaves the axes 7.3e-6 rad apart and only the nearest-approach law applies;
- **the nearest approach is no farther than a near-aligned configuration**: the pose of a random configuration
  with ``q_2`` or ``q_6`` = 1e-4 (where the Gen3's wrist turns half a turn within a milliradian of arm angle and
  ``nearly.ik`` misses solutions or returns another of a branch's two) has a nearest approach on the
  configuration's branch at most its misalignment;
- **certified**: every singular arm angle comes with a configuration that reaches the pose (1e-9 m, 1e-9 rad), has
  the pair aligned to 1e-9 rad, the arm angle and the branch's other two signs;
- **a flat stretch is one minimum**: where ``|sigma|`` along a curve varies by rounding only, the search takes one
  minimum there, not one per wiggle;
- **nearest approach against dense sampling**: where the branch's certified solutions exist at every one of 20 000
  arm angles, none of them has the pair nearer alignment than the nearest approach (by more than 1e-12 rad);
- **bad input** raises ValueError.
"""

from __future__ import annotations

import functools
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from redkin.srs import BRANCHES, nearly_srs
from redkin.srs.branches import branch_of_theta
from redkin.srs.nearly import NearlySRS, arm_angle
from redkin.srs.nearly.search import solutions_at
from redkin.srs.nearly.singular import _local_minima, alignment_angles, singular_arm_angles_nearly
from tests.support.urdf_reference import reference_fk

EXAMPLES = Path(__file__).resolve().parents[1] / "src" / "redkin" / "examples"
FILES = {"gen3": "gen3.urdf", "jaco2": "jaco2.urdf", "rosi": "iiwa14_rosi.urdf"}
CERTIFICATE = 1e-9
#: The pairs as joint indices (0-based) and the index of the branch sign that flips through their alignment.
PAIRS = {"shoulder": (0, 2, 0), "wrist": (4, 6, 2)}


@dataclass(frozen=True)
class Case:
    """An arm as redkin loads it and as its URDF writes it: the text, the tip link, and each moving joint's child
    link and axis in that link's frame."""

    arm: NearlySRS
    text: str
    tip: str
    links: tuple[str, ...]
    axes: tuple[np.ndarray, ...]


@functools.cache
def _case(name: str) -> Case:
    from redkin.urdf import load_urdf

    path = EXAMPLES / FILES[name]
    text = path.read_text()
    joints = ET.fromstring(text).findall("joint")
    parents = {joint.find("parent").get("link") for joint in joints}
    tip = next(joint.find("child").get("link") for joint in joints if joint.find("child").get("link") not in parents)
    moving = [joint for joint in joints if joint.get("type") in ("revolute", "continuous")]
    axes = tuple(np.array([float(v) for v in joint.find("axis").get("xyz").split()]) for joint in moving)
    return Case(nearly_srs(load_urdf(path)), text, tip, tuple(joint.find("child").get("link") for joint in moving),
                tuple(axis / np.linalg.norm(axis) for axis in axes))


def _axes(case: Case, q: np.ndarray) -> np.ndarray:
    """The world directions (7, 3) of the joint axes at ``q``, from the URDF's joints: a joint's turn about its own
    axis leaves that axis where it is, so its child link's rotation carries it."""
    return np.array([reference_fk(case.text, q, link)[:3, :3] @ axis for link, axis in zip(case.links, case.axes)])


def _misalignment(case: Case, q: np.ndarray, part: str) -> float:
    """The angle [rad] between the lines of the pair's axes at ``q``: 0 where they are parallel or antiparallel."""
    first, second, _ = PAIRS[part]
    directions = _axes(case, q)
    a, b = directions[first], directions[second]
    return float(np.arctan2(np.linalg.norm(np.cross(a, b)), abs(a @ b)))


def _wrapped(angle):
    return np.angle(np.exp(1j * np.asarray(angle)))


def _pose_errors(reached: np.ndarray, target: np.ndarray) -> tuple[float, float]:
    position = np.linalg.norm(reached[:3, 3] - target[:3, 3])
    relative = target[:3, :3].T @ reached[:3, :3]
    sine = np.linalg.norm(relative - relative.T) / (2.0 * np.sqrt(2.0))
    return float(position), float(np.arctan2(sine, (np.trace(relative) - 1.0) / 2.0))


def _configuration(case: Case, seed: int, part: str, value: float) -> np.ndarray:
    """Random joint values in the user's conventions with ``q_2`` (``q_6``) set to ``value``, the elbow at least
    0.3 rad from stretched and from folded (where ``nearly.ik`` misses solutions)."""
    rng = np.random.default_rng(seed)
    arm = case.arm
    while True:
        q = rng.uniform(-2.5, 2.5, 7)
        q[PAIRS[part][0] + 1] = value
        elbow = _wrapped(arm.geometry.theta_of_q(q)[3] - arm.real_phase)
        if 0.3 <= abs(elbow) <= np.pi - 0.3:
            return q


def _branches(arm: NearlySRS, signs: np.ndarray) -> list:
    return [b for b in BRANCHES if tuple(arm.geometry.kernel_branch(b)[0]) in {tuple(s) for s in signs}]


def _assert_certified(case: Case, result, pose: np.ndarray) -> None:
    arm = case.arm
    signs = np.array(arm.geometry.kernel_branch(result.branch)[0])
    for part, kept in (("shoulder", [1, 2]), ("wrist", [0, 1])):
        angles, q = np.array(getattr(result, part)), getattr(result, f"{part}_q")
        assert q.shape == (len(angles), 7) and np.all(np.diff(angles) > 0)
        for psi, row in zip(angles, q):
            position, rotation = _pose_errors(reference_fk(case.text, row, case.tip), pose)
            assert position <= CERTIFICATE and rotation <= CERTIFICATE
            assert _misalignment(case, row, part) <= CERTIFICATE
            assert abs(_wrapped(arm_angle(arm, row) - psi)) <= CERTIFICATE
            own = branch_of_theta(arm.geometry.theta_of_q(row), arm.real_phase)
            assert np.all(own[kept] == signs[kept])


@pytest.mark.parametrize("name", list(FILES))
@pytest.mark.parametrize("part", list(PAIRS))
@pytest.mark.parametrize("value", [0.0, np.pi])
@settings(max_examples=3)
@given(seed=st.integers(0, 2**32 - 1))
def test_q2_or_q6_at_zero_or_pi_is_found_at_its_arm_angle(name, part, value, seed):
    case = _case(name)
    arm = case.arm
    q = _configuration(case, seed, part, value)
    pose, own = reference_fk(case.text, q, case.tip), float(arm_angle(arm, q))
    misalignment = _misalignment(case, q, part)
    if value == 0.0:
        assert misalignment <= 1e-12  # q_2 = 0 (q_6 = 0) is aligned on these arms, whatever its Table 1 theta
    signs = branch_of_theta(arm.geometry.theta_of_q(q), arm.real_phase)
    flipped = signs.copy()
    flipped[PAIRS[part][2]] *= -1
    for branch in _branches(arm, [signs, flipped] if misalignment <= 1e-12 else [signs]):
        result = singular_arm_angles_nearly(arm, pose, branch)
        _assert_certified(case, result, pose)
        nearest = getattr(result, f"{part}_nearest")
        assert nearest is not None and nearest.angle <= misalignment + 1e-12, (branch, nearest, misalignment)
        if misalignment <= 1e-12:
            found = np.array(getattr(result, part))
            assert found.size and np.abs(_wrapped(found - own)).min() <= CERTIFICATE, (branch, found, own)


@pytest.mark.parametrize("name", list(FILES))
@pytest.mark.parametrize("part", list(PAIRS))
@settings(max_examples=4)
@given(seed=st.integers(0, 2**32 - 1))
def test_the_nearest_approach_is_no_farther_than_a_near_aligned_configuration(name, part, seed):
    case = _case(name)
    arm = case.arm
    q = _configuration(case, seed, part, 1e-4)
    misalignment = _misalignment(case, q, part)
    assert 5e-5 <= misalignment <= 2e-4
    pose = reference_fk(case.text, q, case.tip)
    (branch,) = _branches(arm, [branch_of_theta(arm.geometry.theta_of_q(q), arm.real_phase)])
    result = singular_arm_angles_nearly(arm, pose, branch)
    _assert_certified(case, result, pose)
    nearest = getattr(result, f"{part}_nearest")
    assert nearest is not None and nearest.angle <= misalignment + 1e-12, (nearest, misalignment)


@pytest.mark.parametrize("name", ["gen3", "jaco2"])
@pytest.mark.parametrize("seed", [3, 8])
def test_nearest_approach_against_dense_sampling(name, seed):
    case = _case(name)
    arm = case.arm
    q0 = np.random.default_rng(seed).uniform(-2.0, 2.0, 7)
    pose = arm.chain.fk(q0)
    dense = np.linspace(-np.pi, np.pi, 20_000, endpoint=False)
    checked = 0
    for branch in BRANCHES:
        result = singular_arm_angles_nearly(arm, pose, branch)
        _assert_certified(case, result, pose)
        q, exists = solutions_at(arm, pose, dense, result.branch)
        if not exists.all():
            continue  # a gap: the sampled minimum may sit at its edge, nearer than the grid's
        checked += 1
        for k, part in enumerate(("shoulder", "wrist")):
            nearest = getattr(result, f"{part}_nearest")
            sampled = np.abs(alignment_angles(arm, q)[k])
            assert nearest.angle <= sampled.min() + 1e-12
    assert checked >= 2


def test_alignment_angles_are_the_angle_between_the_axes_lines():
    case = _case("gen3")
    rng = np.random.default_rng(0)
    q = rng.uniform(-np.pi, np.pi, (40, 7))
    q[:10, 1] = 0.0
    q[10:20, 5] = np.pi
    sigma = np.stack(alignment_angles(case.arm, q), axis=-1)
    for k, part in enumerate(PAIRS):
        expected = np.array([_misalignment(case, row, part) for row in q])
        assert np.allclose(np.abs(sigma[:, k]), expected, atol=1e-12)
        # smooth through both alignments: the sign turns where joint 2 (6) passes through 0 and through pi
        for value in (0.0, np.pi):
            through = np.repeat(q[20:], 2, axis=0)
            through[:, PAIRS[part][0] + 1] = value + np.tile([1e-3, -1e-3], len(q) - 20)
            turned = alignment_angles(case.arm, through)[k].reshape(-1, 2)
            assert np.all(turned[:, 0] * turned[:, 1] < 0.0) and np.allclose(turned[:, 0], -turned[:, 1], rtol=0.1)


def test_a_stretch_that_only_rounding_varies_is_one_minimum():
    """Along a curve where the self-motion leaves a pair still (an exact wrist's aligned configurations at a singular
    pose: 300 000 points), ``|sigma|`` varies by rounding only; it is one minimum, not one per wiggle."""
    rng = np.random.default_rng(1)
    flat = 0.3 * (1.0 + 1e-15 * rng.standard_normal(100_000))
    assert len(_local_minima(flat, closed=False)) == 1 and len(_local_minima(flat, closed=True)) == 1
    valley = np.concatenate([np.linspace(1.0, 0.2, 50), flat[:1000] - 0.1, np.linspace(0.2, 1.0, 50)])
    (only,) = _local_minima(valley, closed=True)
    assert valley[only] == valley.min()
    # a minimum across the seam of a closed curve is one; an open curve's ends are two
    seam = np.concatenate([np.linspace(0.1, 1.0, 20), np.linspace(1.0, 0.1, 20)])
    assert len(_local_minima(seam, closed=True)) == 1 and len(_local_minima(seam, closed=False)) == 2
    # missing values (off the branch) bound a minimum; none where nothing is finite
    assert list(_local_minima(np.array([np.inf, 0.5, 0.7, np.inf, 0.9]), closed=False)) == [1, 4]
    assert _local_minima(np.full(5, np.inf), closed=True).size == 0


def test_an_unreachable_pose_has_none():
    arm = _case("gen3").arm
    pose = np.eye(4)
    pose[:3, 3] = [3.0, 0.0, 0.0]
    result = singular_arm_angles_nearly(arm, pose)
    assert result.shoulder == () and result.wrist == () and result.shoulder_nearest is None
    assert result.neighbour is None and result.shoulder_q.shape == (0, 7)


@pytest.mark.parametrize("kwargs", [{"pose": np.full((4, 4), np.nan)}, {"branch": "+x+"}, {"samples": 4},
                                    {"samples": 8.5}, {"pose": np.eye(4)[None].repeat(2, 0)}])
def test_bad_input_raises_value_error(kwargs):
    arguments = {"pose": np.eye(4), "branch": "+++", "samples": 64} | kwargs
    with pytest.raises(ValueError):
        singular_arm_angles_nearly(_case("gen3").arm, **arguments)
