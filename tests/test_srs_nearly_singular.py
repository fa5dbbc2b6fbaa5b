"""Singular arm angles of nearly S-R-S arms on the real arm (:mod:`redkin.srs.nearly_singular`).

Laws, on the Kinova Gen3, the Jaco2 and the ROS-Industrial iiwa:

- **certified**: every singular arm angle comes with a configuration that reaches the pose (1e-9 m, 1e-9 rad), has
  the pair's axes parallel (their cross product, computed here from :meth:`SerialChain.joint_axes`, within 1e-9),
  the arm angle (:func:`redkin.srs.nearly.arm_angle`) and the branch's other two signs;
- **complete on aligned poses**: the pose of a configuration whose axes 1 and 3 (or 5 and 7) are parallel has that
  configuration's arm angle among its singular arm angles, on both branches that meet there;
- **nearest approach against dense sampling**: where the branch's certified solutions exist at every one of 20 000
  arm angles, none of them has the pair nearer alignment than the located nearest approach (by more than 1e-12 rad),
  and the located one is a certified solution with that angle;
- **bad input** raises ValueError.
"""

from __future__ import annotations

import functools
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import least_squares

import redkin
from redkin.srs import BRANCHES, nearly_srs
from redkin.srs.nearly import NearlySRS, arm_angle
from redkin.srs.nearly_search import solutions_at
from redkin.srs.nearly_singular import alignment_angles, singular_arm_angles_nearly

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
CERTIFICATE = 1e-9
#: The pairs as joint indices (0-based) and the index of the branch sign that flips through their alignment.
PAIRS = {"shoulder": (0, 2, 0), "wrist": (4, 6, 2)}


@functools.cache
def _arm(name: str) -> NearlySRS:
    if name == "gen3":
        return nearly_srs(redkin.get_robot("kinova-gen3"))
    pytest.importorskip("urdf_parser_py", reason="the urdf extra (urdfdom-py) is not installed")
    from redkin.urdf import load_urdf

    return nearly_srs(load_urdf(EXAMPLES / ("jaco2.urdf" if name == "jaco2" else "iiwa14_rosi.urdf")))


def _wrapped(angle):
    return np.angle(np.exp(1j * np.asarray(angle)))


def _cross(arm: NearlySRS, q: np.ndarray, part: str) -> np.ndarray:
    """The size of the cross product of the pair's unit axes at ``q`` (..., 7): the sine of their angle."""
    first, second, _ = PAIRS[part]
    directions, _ = arm.chain.joint_axes(q)
    return np.linalg.norm(np.cross(directions[..., first, :], directions[..., second, :]), axis=-1)


def _pose_errors(reached: np.ndarray, target: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    position = np.linalg.norm(reached[..., :3, 3] - target[:3, 3], axis=-1)
    relative = target[:3, :3].T @ reached[..., :3, :3]
    sine = np.linalg.norm(relative - np.swapaxes(relative, -1, -2), axis=(-2, -1)) / (2.0 * np.sqrt(2.0))
    cosine = (np.trace(relative, axis1=-2, axis2=-1) - 1.0) / 2.0
    return position, np.arctan2(sine, cosine)


def _aligned_configuration(arm: NearlySRS, rng: np.random.Generator, part: str) -> np.ndarray:
    """A random configuration with the pair's axes parallel as the neighbour's are at theta_2 = 0 (theta_6 = 0):
    the neighbour's angle set to 0, then joint 2 (6) moved until the real axes are parallel."""
    theta = arm.geometry.theta_of_q(rng.uniform(-2.0, 2.0, 7))
    middle = 1 if part == "shoulder" else 5
    theta[middle] = 0.0
    elbow = _wrapped(theta[3])  # away from the stretched and the folded elbow, where nearly.ik misses solutions
    theta[3] = np.sign(elbow) * np.clip(abs(elbow), 0.3, np.pi - 0.3)
    q = arm.geometry.q_of_theta(theta)

    def sine(value: np.ndarray) -> np.ndarray:
        moved = q.copy()
        moved[middle] = value[0]
        return np.array([_cross(arm, moved, part)])

    q[middle] = least_squares(sine, q[middle:middle + 1], xtol=1e-15, ftol=1e-15, gtol=1e-15).x[0]
    assert _cross(arm, q, part) <= 1e-12
    return q


def _branches_through(arm: NearlySRS, q: np.ndarray, part: str) -> list:
    """The two branches (user labels) that meet at an aligned configuration: its own signs, the pair's either way."""
    from redkin.srs.branches import branch_of_theta

    signs = branch_of_theta(arm.geometry.theta_of_q(q), arm.real_phase)
    flipped = signs.copy()
    flipped[PAIRS[part][2]] *= -1
    return [b for b in BRANCHES if tuple(arm.geometry.kernel_branch(b)[0]) in (tuple(signs), tuple(flipped))]


def _assert_certified(arm: NearlySRS, result, pose: np.ndarray) -> None:
    from redkin.srs.branches import branch_of_theta

    signs = np.array(arm.geometry.kernel_branch(result.branch)[0])
    for part, kept in (("shoulder", [1, 2]), ("wrist", [0, 1])):
        angles, q = np.array(getattr(result, part)), getattr(result, f"{part}_q")
        assert q.shape == (len(angles), 7) and np.all(np.diff(angles) > 0)
        if not len(angles):
            continue
        position, rotation = _pose_errors(arm.chain.fk(q), pose)
        assert position.max() <= CERTIFICATE and rotation.max() <= CERTIFICATE
        assert _cross(arm, q, part).max() <= CERTIFICATE
        assert np.abs(_wrapped(arm_angle(arm, q) - angles)).max() <= CERTIFICATE
        own = branch_of_theta(arm.geometry.theta_of_q(q), arm.real_phase)
        assert np.all(own[:, kept] == signs[kept])


@pytest.mark.parametrize("name", ["gen3", "jaco2", "rosi"])
@pytest.mark.parametrize("part", ["shoulder", "wrist"])
@settings(max_examples=6, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_an_aligned_configuration_is_found_at_its_arm_angle(name, part, seed):
    arm = _arm(name)
    q = _aligned_configuration(arm, np.random.default_rng(seed), part)
    pose, own = arm.chain.fk(q), float(arm_angle(arm, q))
    for branch in _branches_through(arm, q, part):
        result = singular_arm_angles_nearly(arm, pose, branch)
        _assert_certified(arm, result, pose)
        found = np.array(getattr(result, part))
        assert found.size and np.abs(_wrapped(found - own)).min() <= CERTIFICATE, (branch, found, own)


@pytest.mark.parametrize("name", ["gen3", "jaco2"])
@pytest.mark.parametrize("seed", [3, 8])
def test_nearest_approach_against_dense_sampling(name, seed):
    arm = _arm(name)
    rng = np.random.default_rng(seed)
    q0 = rng.uniform(-2.0, 2.0, 7)
    pose = arm.chain.fk(q0)
    dense = np.linspace(-np.pi, np.pi, 20_000, endpoint=False)
    checked = 0
    for branch in BRANCHES:
        result = singular_arm_angles_nearly(arm, pose, branch)
        _assert_certified(arm, result, pose)
        q, exists = solutions_at(arm, pose, dense, result.branch)
        if not exists.all():
            continue  # a gap: the sampled minimum may sit at its edge, nearer than the grid's
        checked += 1
        for k, part in enumerate(("shoulder", "wrist")):
            nearest = getattr(result, f"{part}_nearest")
            sampled = np.abs(alignment_angles(arm, q)[k])
            assert nearest.angle <= sampled.min() + 1e-12
            located, found = solutions_at(arm, pose, np.array([nearest.psi]), result.branch)
            assert found[0] and np.isclose(np.abs(alignment_angles(arm, located)[k][0]), nearest.angle, atol=1e-15)
            assert np.isclose(np.arcsin(np.clip(_cross(arm, located, part)[0], 0, 1)), min(nearest.angle,
                              np.pi - nearest.angle), atol=1e-9)
    assert checked >= 2


def test_an_unreachable_pose_has_none():
    arm = _arm("gen3")
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
        singular_arm_angles_nearly(_arm("gen3"), **arguments)
