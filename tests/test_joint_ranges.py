"""Joint ranges are ranges (issue 22): only a continuous joint is unlimited; a range wider than 2 pi keeps its stops.

The laws are checked against an independent reading of a range, written here: ``lower <= q <= upper``, and the
representatives ``q + 2 pi k`` for a window of ``k`` wide enough for any range drawn.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from redkin.chain import SerialChain
from redkin.models import get_robot, kuka_iiwa14, ufactory_xarm7
from redkin.srs import BRANCHES, arm_angle_of, arm_angle_path, feasible_arm_angles, ik_all_branches
from redkin.torso_arm.branches import wrap_to_limits
from tests.support.urdf_reference import reference_fk

EXAMPLES = Path(__file__).resolve().parents[1] / "src" / "redkin" / "examples"
TURN = 2.0 * np.pi
SHIFTS = np.arange(-8, 9)  # enough whole turns for any angle and range drawn below

angles = st.floats(-6.0 * np.pi, 6.0 * np.pi, allow_nan=False)
starts = st.floats(-4.0 * np.pi, 4.0 * np.pi, allow_nan=False)
widths = st.floats(0.0, 4.0 * np.pi, allow_nan=False)


def _one_joint(lower: float, upper: float) -> SerialChain:
    return SerialChain(a=[0.3], alpha=[0.0], d=[0.0], lower=[lower], upper=[upper])


def _inside(values: np.ndarray, lower: float, upper: float) -> np.ndarray:
    """Every representative of ``values`` (..., K) that lies in the range, the reference's way."""
    return (values >= lower) & (values <= upper)


@settings(max_examples=300, deadline=None)
@given(starts, widths, angles)
def test_within_limits_is_the_range_itself(lower, width, q):
    """0 wrong answers: plain ``lower <= q <= upper`` whatever the width; modulo 2 pi, a representative inside."""
    upper = lower + width
    chain = _one_joint(lower, upper)
    assert bool(chain.within_limits([q])) == (lower <= q <= upper)
    assert bool(chain.limited[0])
    assert bool(chain.covers_circle[0]) == (width >= TURN)
    some = bool(np.any(_inside(q + TURN * SHIFTS, lower, upper)))
    gaps = np.mod(np.array([q - lower, lower - q, q - upper, upper - q]), TURN)
    if gaps.min() > 1e-9:
        assert bool(chain.within_limits([q], wrap=True)) == some  # away from the stops, where rounding may decide


@settings(max_examples=300, deadline=None)
@given(starts, widths, angles, st.one_of(st.none(), angles))
def test_nearest_in_range_picks_the_representative_the_docs_promise(lower, width, q, seed):
    upper = lower + width
    chain = _one_joint(lower, upper)
    placed = float(chain.nearest_in_range([q], near=None if seed is None else [seed])[0])
    assert np.isclose(np.cos(placed), np.cos(q), atol=1e-9) and np.isclose(np.sin(placed), np.sin(q), atol=1e-9)
    candidates = q + TURN * SHIFTS
    assume(np.min(np.abs(np.concatenate([candidates - lower, candidates - upper]))) > 1e-9)  # rounding decides there
    inside = candidates[_inside(candidates, lower, upper)]
    target = 0.5 * (lower + upper) if seed is None else seed
    if inside.size:
        assert lower <= placed <= upper
        assert abs(placed - target) <= np.min(np.abs(inside - target)) + 1e-9
    elif seed is not None:
        assert abs(placed - seed) <= np.pi + 1e-9
    else:
        assert -np.pi - 1e-9 < placed <= np.pi + 1e-9


@settings(max_examples=300, deadline=None)
@given(st.integers(-2, 1), st.integers(1, 3), st.integers(1, 3), st.integers(-6, 6), st.floats(0.0, 0.5))
def test_a_value_turned_onto_a_stop_of_whole_turns_stays_within_it(stop_turns, width_turns, turns, ulps, past):
    """A stop at a whole number of turns (the xArm7's -2 pi) and a value a few ulps from that stop plus whole turns,
    with a seed near the stop: the turned value may round past the stop, and must be put on it (found by
    tests/test_numerical_ik: an xArm7 solution at -6.283185307179587 below its -2 pi stop)."""
    lower = TURN * stop_turns
    upper = lower + TURN * width_turns
    value = lower + TURN * min(turns, width_turns)
    for _ in range(abs(ulps)):
        value = np.nextafter(value, np.inf if ulps > 0 else -np.inf)
    chain = _one_joint(lower, upper)
    placed = chain.nearest_in_range([value], near=[lower - past])
    assert lower <= float(placed[0]) <= upper and bool(chain.within_limits(placed))


def test_the_xarm_joint_one_value_below_its_stop():
    xarm = ufactory_xarm7()
    q, near = np.zeros(7), np.zeros(7)
    q[0], near[0] = 6.283185307179585, -6.0
    placed = xarm.nearest_in_range(q, near=near)
    assert placed[0] >= xarm.lower[0] and bool(xarm.within_limits(placed))


def test_a_value_in_place_comes_back_bit_for_bit():
    chain = _one_joint(-4.7124, 4.7124)
    q = np.array([[0.123456789], [-3.5], [4.7124], [-4.7124]])
    np.testing.assert_array_equal(chain.nearest_in_range(q, near=q), q)
    assert float(chain.nearest_in_range([-3.5])[0]) == pytest.approx(-3.5 + TURN)  # nearer the middle 0
    middle = np.array([[0.123456789], [-2.5]])
    np.testing.assert_array_equal(chain.nearest_in_range(middle), middle)  # nearest the middle 0 already


def test_unlimited_and_half_open_ranges():
    free = _one_joint(-np.inf, np.inf)
    assert not free.limited[0] and free.covers_circle[0] and free.within_limits([1e3])
    assert float(free.nearest_in_range([3 * np.pi])[0]) == pytest.approx(np.pi)
    assert float(free.nearest_in_range([0.1], near=[20.0])[0]) == pytest.approx(0.1 + 3 * TURN)
    below = _one_joint(-np.inf, 1.0)  # a stop on one side only
    assert below.limited[0] and not below.within_limits([1.5]) and below.within_limits([-50.0])
    placed = float(below.nearest_in_range([1.5])[0])
    assert placed <= 1.0 and placed == pytest.approx(1.5 - TURN)
    assert float(below.middle[0]) == pytest.approx(1.0 - np.pi)


def test_sawyer_description_keeps_its_wrist_range():
    """Rethink's Sawyer: right_j6 turns +-4.7124 rad; 5.0 is past the stop (the issue's example), 4.0 is not."""
    path = EXAMPLES / "sawyer.urdf"
    chain = get_robot(str(path))
    assert chain.joint_names[-1] == "right_j6" and chain.upper[-1] == pytest.approx(4.7124)
    assert np.all(chain.limited)
    assert not chain.within_limits([0, 0, 0, 0, 0, 0, 5.0])
    assert chain.within_limits([0, 0, 0, 0, 0, 0, 4.0])
    assert chain.within_limits([0, 0, 0, 0, 0, 0, 5.0 - TURN])
    text = path.read_text()
    q = np.random.default_rng(3).uniform(chain.lower, chain.upper, (20, 7))
    for row in q:  # the model against an independent product of the file
        np.testing.assert_allclose(chain.fk(row), reference_fk(text, row, "right_hand"), atol=1e-12)


def test_xarm_two_turn_ranges_keep_their_stops():
    chain = ufactory_xarm7()
    assert np.all(chain.limited) and list(np.flatnonzero(chain.covers_circle)) == [0, 2, 4, 6]
    q = np.zeros(7)
    q[0] = TURN + 0.1
    assert not chain.within_limits(q) and chain.within_limits(q, wrap=True)
    q[0] = TURN - 0.1
    assert chain.within_limits(q)


def _wide_iiwa(rng: np.random.Generator) -> SerialChain:
    """The iiwa with random ranges of width 0..4 pi round random centres."""
    centre = rng.uniform(-2 * np.pi, 2 * np.pi, 7)
    half = 0.5 * rng.uniform(0.0, 4 * np.pi, 7)
    return kuka_iiwa14().with_limits(centre - half, centre + half)


@settings(max_examples=25, deadline=None)
@given(st.integers(0, 2**32 - 1))
def test_closed_form_ik_places_each_angle_in_wide_ranges(seed):
    """S-R-S IK on ranges up to 4 pi: FK holds, and each joint value is inside its range whenever an angle has a
    representative there, nearest the range's middle; psi is feasible exactly when the whole vector is in range."""
    rng = np.random.default_rng(seed)
    chain = _wide_iiwa(rng)
    pose = kuka_iiwa14().fk(rng.uniform(-2.0, 2.0, 7))
    psi = rng.uniform(-np.pi, np.pi, 16)
    q = ik_all_branches(chain, np.broadcast_to(pose, (16, 4, 4)), psi)  # (16, 8, 7)
    np.testing.assert_allclose(chain.fk(q), np.broadcast_to(pose, q.shape[:-1] + (4, 4)), atol=1e-9)
    candidates = q[..., None] + TURN * SHIFTS  # (16, 8, 7, K)
    inside = _inside(candidates, chain.lower[:, None], chain.upper[:, None])
    has = inside.any(axis=-1)
    middle = chain.middle
    distance = np.where(inside, np.abs(candidates - middle[:, None]), np.inf).min(axis=-1)
    placed = (q >= chain.lower) & (q <= chain.upper)
    margin = np.minimum(np.abs(np.mod(q - chain.lower + np.pi, TURN) - np.pi),
                        np.abs(np.mod(q - chain.upper + np.pi, TURN) - np.pi))
    clear = margin > 1e-9  # away from the stops, where rounding may decide
    assert np.all(placed[has & clear])
    assert np.all((np.abs(q - middle) <= distance + 1e-9)[has & clear])
    for b, branch in enumerate(BRANCHES):
        feasible = feasible_arm_angles(chain, pose, branch).feasible
        ends = np.array([end for interval in feasible.intervals for end in interval] or [np.inf])
        for k, value in enumerate(psi):
            if np.min(np.abs(ends - value)) > 1e-7 and np.all(clear[k, b]):
                assert bool(feasible.contains(value)) == bool(chain.within_limits(q[k, b]))


def test_path_through_a_wide_range_stays_continuous():
    """Along a path, a range wider than a turn is left continuously (nearest the last waypoint), never by a jump."""
    base = kuka_iiwa14()
    lower, upper = base.lower.copy(), base.upper.copy()
    lower[6], upper[6] = -4.7, 4.7  # a Sawyer-like wrist
    chain = base.with_limits(lower, upper)
    q0 = np.array([0.3, 0.6, 0.2, -1.2, 0.4, 0.9, 2.8])
    steps = np.linspace(0.0, 1.2, 60)
    path_q = np.repeat(q0[None], len(steps), axis=0)
    path_q[:, 6] += steps  # joint 7 turns through +pi
    poses = base.fk(path_q)
    state = arm_angle_of(base, path_q[0])
    branch = str(state.branch_strings())
    psi_path = arm_angle_path(chain, poses, branch, fixed_psi=float(state.psi))
    jumps = np.abs(np.diff(psi_path.q, axis=0))
    assert jumps.max() < 0.1
    assert np.all(chain.within_limits(psi_path.q, tolerance=1e-9))
    assert psi_path.q[-1, 6] > np.pi  # it went on past pi, inside the +-4.7 range


def test_torso_arm_wrap_to_limits_takes_the_middle_of_a_wide_range():
    from redkin.models import humanoid_right_arm

    arm = humanoid_right_arm()
    lower, upper = arm.lower.copy(), arm.upper.copy()
    lower[1], upper[1] = 0.0, 4 * np.pi  # two turns round 2 pi
    chain = arm.with_limits(lower, upper)
    q = np.zeros((1, 8))
    q[0, 1] = 0.5
    wrapped = wrap_to_limits(chain, q)
    assert wrapped[0, 1] == pytest.approx(0.5 + TURN)  # of 0.5 and 0.5 + 2 pi, the one nearest 2 pi
