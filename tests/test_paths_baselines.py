"""How the baselines are judged (redkin.paths.judge_path): the first waypoint that misses its pose, breaks a limit
or breaks the step bound, the joint and by how much; and the plane of feasible pieces along a path."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from redkin.errors import RedkinError
from redkin.models import get_robot
from redkin.paths import LIMIT_SLACK, feasible_along_path, judge_path, resolve_path
from redkin.srs import feasible_pieces_all_branches


def _line(chain, rng, count=6):
    """A joint-space line 0.3 rad inside the limits, steps of at most 0.05 rad."""
    lower = np.where(np.isfinite(chain.lower), chain.lower + 0.3, -np.pi)
    upper = np.where(np.isfinite(chain.upper), chain.upper - 0.3, np.pi)
    a = rng.uniform(lower, upper)
    b = np.clip(a + rng.uniform(-0.2, 0.2, 7), lower, upper)
    return a + (b - a) * np.linspace(0.0, 1.0, count)[:, None]


@settings(max_examples=20, deadline=None)
@given(st.integers(0, 2**31), st.sampled_from(["kuka-iiwa14", "pa10-7c", "barrett-wam7"]), st.integers(0, 5),
       st.integers(0, 6), st.floats(1e-6, 0.5), st.booleans())
def test_a_limit_broken_at_one_waypoint_is_found_with_its_joint_and_excess(seed, robot, k, joint, excess, upper):
    chain = get_robot(robot)
    q = _line(chain, np.random.default_rng(seed))
    assert judge_path(chain, q, 0.1, chain.fk(q)).ok
    if chain.covers_circle[joint]:
        return
    inside = q[k, joint]
    limit = chain.upper[joint] if upper else chain.lower[joint]
    q[k, joint] = limit + (excess if upper else -excess)
    judged = judge_path(chain, q, 10.0)
    assert (judged.first_failure, judged.reason, judged.joint) == (k, "limit", joint + 1)
    assert judged.excess == pytest.approx(excess, abs=1e-12)
    assert not judged.within_limits[k] and judged.within_limits.sum() == len(q) - 1
    assert judged.clearance[k] == pytest.approx(-excess, abs=1e-12) and np.all(np.delete(judged.clearance, k) > 0)
    q[k, joint] = inside + 2 * np.pi  # the same angle as a value in range, but not one to command
    turned = judge_path(chain, q, 10.0)
    assert (turned.reason, turned.joint) == ("limit", joint + 1)
    assert turned.excess == pytest.approx(inside + 2 * np.pi - chain.upper[joint], abs=1e-12)


def test_a_step_over_the_bound_names_the_joint_and_how_far_over():
    chain = get_robot("kuka-iiwa14")
    q = _line(chain, np.random.default_rng(4))
    q[3:, 5] += 0.13
    judged = judge_path(chain, q, 0.1)
    assert (judged.first_failure, judged.reason, judged.joint) == (3, "step", 6)
    move = abs(q[3, 5] - q[2, 5])
    assert judged.excess == pytest.approx(move - 0.1, abs=1e-12)
    assert judged.jump[2] == pytest.approx(move / 0.1) and judged.within_limits.all()
    assert "waypoint 3" in judged.message and "joint 6" in judged.message


def test_values_that_miss_the_pose_or_are_missing_fail_first_there():
    chain = get_robot("pa10-7c")
    q = _line(chain, np.random.default_rng(5))
    poses = chain.fk(q)
    moved = q.copy()
    moved[2, 0] += 1e-6
    judged = judge_path(chain, moved, 0.1, poses)
    assert (judged.first_failure, judged.reason, judged.joint) == (2, "pose", None)
    assert 1e-7 < judged.excess < 1e-5
    assert judge_path(chain, moved, 0.1).ok  # without the poses only limits and bound are judged
    q[4] = np.nan
    judged = judge_path(chain, q, 0.1, poses)
    assert (judged.first_failure, judged.reason, judged.joint, judged.excess) == (4, "no-solution", None, None)
    assert np.isnan(judged.clearance[4]) and np.isfinite(np.delete(judged.clearance, 4)).all()


def test_a_limit_met_within_the_slack_is_kept():
    chain = get_robot("kuka-iiwa14")
    q = _line(chain, np.random.default_rng(6), 3)
    q[1, 3] = chain.upper[3] + 0.5 * LIMIT_SLACK
    assert judge_path(chain, q, 10.0).ok


def test_a_resolved_path_is_judged_lawful():
    chain = get_robot("barrett-wam7")
    q = _line(chain, np.random.default_rng(7), 8)
    poses = chain.fk(q)
    result = resolve_path(chain, poses, 0.12)
    judged = judge_path(chain, result.q, result.step, poses, "global", result.psi, result.branch)
    assert judged.ok and judged.reason is None and judged.method == "global" and judged.branch == result.branch
    assert judged.clearance.min() == pytest.approx(result.clearance, abs=1e-15)


def test_bad_input_is_refused():
    chain = get_robot("kuka-iiwa14")
    with pytest.raises(RedkinError, match=r"shape \(N, 7\)"):
        judge_path(chain, np.zeros((3, 6)), 0.1)
    with pytest.raises(RedkinError, match="one pose per row"):
        judge_path(chain, np.zeros((3, 7)), 0.1, chain.fk(np.zeros((2, 7))))
    with pytest.raises(RedkinError, match="max_step"):
        judge_path(chain, np.zeros((3, 7)), -0.1)


def test_the_plane_is_the_feasible_pieces_of_each_waypoint():
    chain = get_robot("kuka-iiwa14")
    q = _line(chain, np.random.default_rng(8), 4)
    poses = chain.fk(q)
    plane = feasible_along_path(chain, poses)
    direct = feasible_pieces_all_branches(chain, poses)
    np.testing.assert_array_equal(plane.feasible, direct.feasible)
    np.testing.assert_array_equal(plane.start, direct.start)
    with pytest.raises(RedkinError, match=r"shape \(N, 4, 4\)"):
        feasible_along_path(chain, poses[0])
