"""redkin.arm (issue 39): one arm, one API.  The laws every class keeps through the front door: the round trip
``ik(fk(q), parameter_of(q))[branch_of(q)] == q``; the same rows as the class's own functions; batched equals looped;
a feasible set holds exactly the values at which the branch's row lies within the limits; a pose out of reach is a
row that does not exist, with its reason; bad input is a ValueError."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

import redkin
from redkin import franka, srs
from redkin.arms import FeasibleSets
from redkin.circle import wrap_angle
from redkin.srs import nearly

#: The examples' files of issue 39's "Done when" (the WAM by its model name: no maker's file ships), each with the
#: FK difference between the file and the exact arm the closed form solves (the xArm7's description is snapped).
CLASS_ARMS = {"pa10.toml": 1e-9, "iiwa14.urdf": 1e-9, "barrett-wam7": 1e-9, "panda.urdf": 1e-9, "fr3.urdf": 1e-9,
              "xarm7.urdf": 1e-4, "gen3.urdf": 1e-8}


def _inside(arm: redkin.Arm, fraction: np.ndarray) -> np.ndarray:
    """A configuration inside the limits (a range wider than the circle read as [-pi, pi))."""
    lower = np.maximum(arm.chain.lower, -np.pi)
    upper = np.minimum(arm.chain.upper, np.pi)
    return lower + (0.05 + 0.9 * fraction) * (upper - lower)


@pytest.mark.parametrize("source", sorted(CLASS_ARMS))
@settings(max_examples=12)
@given(fraction=st.lists(st.floats(0.0, 1.0) | st.just(0.5), min_size=7, max_size=7))
@example(fraction=[0.5, 0.49609375, 0.5, 0.0, 0.5, 0.0, 0.5])  # fresh draws: the xArm7 at q2 = 3.1e-3
@example(fraction=[0.5, 0.5, 0.5, 0.5, 0.5, 1.0, 0.5])  # and at q2 = 0.0177
@example(fraction=[0.5, 0.0, 0.0, 0.5, 0.5, 0.0, 0.0])  # the Gen3 at q4 = 0, on the elbow's branch boundary
def test_round_trip_through_the_front_door(source, fraction):
    """The issue's script, unchanged for every class: the solution at a configuration's own parameter and branch is
    the configuration (up to whole turns, and the snapped description's error).  At a singular configuration (the
    midpoint fractions 0.5 draw straight wrists and shoulders on purpose) the row reaches the pose, but may be
    another point of the degenerate self-motion (q5 and q7 of a straight wrist are known only by their sum)."""
    arm = redkin.arm(source)
    q = _inside(arm, np.array(fraction))
    pose = arm.fk(q)
    t, branch = arm.parameter_of(q), arm.branch_of(q)
    solutions = arm.ik(pose, t)
    row = solutions.q[..., arm.branches.index(branch), :]
    degenerate = _aligned(arm, q)
    # a nearly S-R-S arm's polished solution may be missed at a degenerate configuration (issue 38): not elsewhere
    assert solutions.exists[arm.branches.index(branch)] or (degenerate
                                                            and arm.kind == redkin.arms.classify.NEARLY_SRS)
    tolerance = CLASS_ARMS[source]
    if solutions.exists.any():
        assert np.max(np.abs(arm.fk(solutions.q[solutions.exists]) - pose)) < max(tolerance, 1e-9)
    if not degenerate:  # the parameter and branch name one configuration, to the description's error over the
        # conditioning: a snapped description (the xArm7's, 1e-4) moves q1 and q3 by about its error over the angle
        # of axes 1 and 3 (3.1e-3 rad at q2 = 3.1e-3, 1.3e-3 at q2 = 0.0177: fresh draws)
        allowed = max(tolerance * 10, 1e-7) / _conditioning(arm, q)
        if arm.kind == redkin.arms.classify.NEARLY_SRS and np.max(np.abs(wrap_angle(row - q))) >= allowed:
            # next to a fold a nearly S-R-S branch has two solutions at one value (issue 38): q is the other one;
            # and q on a branch's boundary (the Gen3 at q4 = 0, its real stretched elbow: a fresh draw) is a
            # solution of the branch on either side, which the solver's rounding picks
            rows = np.concatenate([arm.every_solution(pose, float(t), str(tied)) for tied in _tied_branches(arm, q)])
            row = rows[np.argmin(np.abs(wrap_angle(rows - q)).max(axis=1))]
        assert np.max(np.abs(wrap_angle(row - q))) < allowed


def _tied_branches(arm: redkin.Arm, q: np.ndarray) -> list[str]:
    """The branches of the configurations within 1e-9 rad of ``q`` along joints 2, 4 and 6: ``q``'s own, and where
    ``q`` lies on a branch's boundary (within rounding) the branch across it."""
    nearby = q + np.concatenate([np.zeros((1, 7)), 1e-9 * np.eye(7)[[1, 3, 5]], -1e-9 * np.eye(7)[[1, 3, 5]]])
    return sorted({str(arm.branch_of(each)) for each in nearby})


def _conditioning(arm: redkin.Arm, q: np.ndarray) -> float:
    """The least of 1, the sines of the angles between axes 1 and 3 and between axes 5 and 7, and the Jacobian's
    smallest singular value: how far the configuration is from a straight shoulder or wrist or a singularity."""
    axes = arm.jacobian(q)[3:]
    sines = [np.linalg.norm(np.cross(axes[:, i], axes[:, j])) for i, j in ((0, 2), (4, 6))]
    return float(min(1.0, *sines, np.linalg.svd(arm.jacobian(q), compute_uv=False)[-1]))


def _aligned(arm: redkin.Arm, q: np.ndarray) -> bool:
    """Whether axes 1 and 3 or 5 and 7 are within 1e-3 rad of parallel (a straight shoulder or wrist: the branch's
    solutions at the parameter's value are a continuum), or the Jacobian within 1e-3 of rank 6."""
    axes = arm.jacobian(q)[3:]
    straight = [np.linalg.norm(np.cross(axes[:, i], axes[:, j])) < 1e-3 for i, j in ((0, 2), (4, 6))]
    return any(straight) or np.linalg.svd(arm.jacobian(q), compute_uv=False)[-1] < 1e-3


@pytest.mark.parametrize("source", sorted(CLASS_ARMS))
def test_the_front_door_agrees_with_the_class_functions(source):
    """Every row, exists and within-limits flag equals the class's own function on the same pose and value."""
    arm = redkin.arm(source)
    rng = np.random.default_rng(3)
    q = _inside(arm, rng.random((6, 7)))
    poses, values = arm.fk(q), arm.parameter_of(q)
    ours = arm.ik(poses, values)
    assert ours.q.shape == (6, 8, 7) and ours.exists.shape == ours.within_limits.shape == (6, 8)
    assert ours.branches == tuple(str(b) for b in srs.BRANCHES) == arm.branches
    if arm.parameter.name == "q7":
        theirs = franka.ik(franka.franka_geometry(arm.chain), poses, values)
        np.testing.assert_array_equal(ours.q, theirs.q)
        np.testing.assert_array_equal(ours.exists, theirs.exists)
        np.testing.assert_array_equal(ours.within_limits, theirs.within_limits)
    elif arm.kind == redkin.arms.classify.NEARLY_SRS:
        theirs = nearly.ik(nearly.nearly_srs(arm.chain), poses, values)
        np.testing.assert_array_equal(ours.q, theirs.q)
        np.testing.assert_array_equal(ours.exists, theirs.exists)
    else:
        np.testing.assert_array_equal(ours.q, srs.ik_all_branches(arm.chain, poses, values))
        assert ours.exists.all()
        np.testing.assert_array_equal(ours.within_limits, arm.chain.within_limits(ours.q, tolerance=1e-12))
    np.testing.assert_array_equal(ours.parameter, np.broadcast_to(values[:, None], (6, 8)))
    assert ours.method == "closed form"


@pytest.mark.parametrize("source", ["iiwa14.urdf", "panda.urdf", "barrett-wam7"])
def test_batched_equals_looped(source):
    """ik, feasible, parameter_of and branch_of over a (2, 3) batch equal the same calls pose by pose."""
    arm = redkin.arm(source)
    q = _inside(arm, np.random.default_rng(5).random((2, 3, 7)))
    poses = arm.fk(q)
    values = np.linspace(-1.0, 1.0, 6).reshape(2, 3)
    batch, sets = arm.ik(poses, values), arm.feasible(poses)
    assert arm.parameter_of(q).shape == arm.branch_of(q).shape == (2, 3)
    for index in np.ndindex(2, 3):
        one = arm.ik(poses[index], values[index])
        np.testing.assert_array_equal(batch.q[index], one.q)
        np.testing.assert_array_equal(batch.exists[index], one.exists)
        np.testing.assert_array_equal(batch.within_limits[index], one.within_limits)
        single = arm.feasible(poses[index])
        for branch in arm.branches:
            np.testing.assert_array_equal(sets.arcs(branch, index).bounds, single.arcs(branch).bounds)
        assert arm.parameter_of(q[index]) == arm.parameter_of(q)[index]
        assert arm.branch_of(q[index]) == arm.branch_of(q)[index]


@pytest.mark.parametrize("source", ["iiwa14.urdf", "barrett-wam7", "panda.urdf", "fr3.urdf"])
@settings(max_examples=6)
@given(fraction=st.lists(st.floats(0.0, 1.0), min_size=7, max_size=7))
def test_a_feasible_set_holds_exactly_the_values_within_the_limits(source, fraction):
    """On the exact classes, ``contains(t, branch)`` is ``ik(pose, t).within_limits[branch]`` on a dense grid of t
    (values within 1e-6 of an arc's end skipped: there the two sides of a limit meet)."""
    arm = redkin.arm(source)
    pose = arm.fk(_inside(arm, np.array(fraction)))
    sets = arm.feasible(pose)
    low, high = arm.parameter.domain
    grid = np.linspace(low, high, 1441)
    rows = arm.ik(np.broadcast_to(pose, (len(grid), 4, 4)), grid)
    for b, branch in enumerate(arm.branches):
        arcs = sets.arcs(branch)
        ends = arcs.bounds.reshape(-1)
        near_end = np.min(np.abs(wrap_angle(grid[:, None] - ends[None, :])), axis=1) < 1e-6 if len(ends) else \
            np.zeros(len(grid), bool)
        inside = sets.contains(grid, branch)
        np.testing.assert_array_equal(inside[~near_end], rows.within_limits[~near_end, b])
        assert sets.contains(grid, b).tolist() == inside.tolist()  # a label or an index
        if arm.parameter.wraps:  # an arc through the seam is one arc, flagged
            assert np.array_equal(arcs.wraps, arcs.bounds[:, 0] > arcs.bounds[:, 1])
        else:
            assert not arcs.wraps.any() and np.all(np.diff(arcs.bounds.reshape(-1)) >= 0)
    union = sets.union()
    for t in grid[::40]:
        assert any(sets.contains(t, branch) for branch in arm.branches) == _in_arcs(union, t, arm.parameter.wraps)


def _in_arcs(arcs, t: float, wraps: bool) -> bool:
    for (lo, hi), through in zip(arcs.bounds, arcs.wraps, strict=True):
        if (t >= lo - 1e-12 or t <= hi + 1e-12) if through else (lo - 1e-12 <= t <= hi + 1e-12):
            return True
    return False


def test_an_arc_through_the_seam_is_one_wrapping_arc():
    """Pieces on either side of +-pi make one arc flagged ``wraps``; q7 never wraps."""
    pi = np.pi
    start = np.array([[[-pi, 0.0, 2.0]]])
    end = np.array([[[-2.5, 1.0, pi]]])
    keep = np.ones((1, 1, 3), bool)
    sets = FeasibleSets(start[0], end[0], keep[0], ("+++",), "psi", True, True)
    arcs = sets.arcs("+++")
    assert arcs.bounds.tolist() == [[0.0, 1.0], [2.0, -2.5]] and arcs.wraps.tolist() == [False, True]
    assert sets.contains([3.0, -3.0, -2.0, 0.5], "+++").tolist() == [True, True, False, True]
    line = FeasibleSets(start[0], end[0], keep[0], ("+++",), "q7", False, True)
    assert line.arcs(0).bounds.tolist() == [[-pi, -2.5], [0.0, 1.0], [2.0, pi]] and not line.arcs(0).wraps.any()
    with pytest.raises(ValueError, match="branch must be one of"):
        sets.contains(0.0, "+-+")
    with pytest.raises(ValueError, match="at must index one pose"):
        sets.arcs("+++", (0, 1))


@pytest.mark.parametrize("source", ["pa10.toml", "panda.urdf", "gen3.urdf"])
def test_a_pose_out_of_reach_is_rows_that_do_not_exist_with_the_reason(source):
    arm = redkin.arm(source)
    poses = np.stack([arm.fk(_inside(arm, np.full(7, 0.4))), np.eye(4)])
    poses[1, 0, 3] = 10.0
    result = arm.ik(poses, 0.2)
    assert not result.exists[1].any() and not result.within_limits[1].any() and not result.q[1].any()
    assert bool(result.reach.out[1]) and not bool(result.reach.out[0])
    assert all(text.startswith("out of reach:") and " m, outside [" in text for text in result.reason[1])
    assert all(text == "" or not text.startswith("out of reach") for text in result.reason[0])
    assert np.array_equal(result.reason[0] == "", result.exists[0])


def test_a_general_chain_answers_numerically_and_refuses_a_parameter_in_words():
    """The Sawyer (a shoulder offset: no closed form) has no parameter and no branches; ik without t is the
    numerical solver's, its rows the solutions found."""
    arm = redkin.arm("sawyer.urdf")
    assert arm.parameter is None and arm.branches == () and arm.kind == redkin.arms.classify.GENERAL
    q = _inside(arm, np.full(7, 0.45))
    pose = arm.fk(q)
    found = arm.ik(pose, q0=q + 0.05, count=2)
    assert found.method == "numerical" and found.q.shape == (2, 7) and found.branches == ("1", "2")
    assert found.exists[0] and np.max(np.abs(arm.fk(found.q[0]) - pose)) < 1e-6
    for call in (lambda: arm.ik(pose, 0.1), lambda: arm.feasible(pose), lambda: arm.parameter_of(q),
                 lambda: arm.ik(pose, branches="+++")):
        with pytest.raises(ValueError, match="sawyer"):
            call()


def test_numerical_rows_go_to_their_branches_with_their_own_parameter():
    arm = redkin.arm("iiwa14.urdf")
    q = _inside(arm, np.full(7, 0.6))
    pose = arm.fk(q)
    found = arm.ik(pose, q0=q)
    assert found.method == "numerical" and found.q.shape == (8, 7) and found.exists.sum() == 1
    row = int(np.flatnonzero(found.exists)[0])
    assert arm.branches[row] == arm.branch_of(found.q[row])
    assert found.parameter[row] == pytest.approx(float(arm.parameter_of(found.q[row])))
    assert np.isnan(found.parameter[~found.exists]).all()
    assert found.reason[~found.exists].tolist() == ["no solution of the branch found"] * 7


@pytest.mark.parametrize("source", ["iiwa14.urdf", "panda.urdf"])
def test_at_the_optimal_value_the_row_is_within_the_limits(source):
    arm = redkin.arm(source)
    pose = arm.fk(_inside(arm, np.full(7, 0.55)))
    best = arm.optimal(pose)
    result = arm.ik(pose, "optimal")
    np.testing.assert_array_equal(result.parameter, np.asarray(best.value, dtype=float))
    feasible = ~np.isnan(best.value.astype(float))
    assert feasible.any()
    np.testing.assert_array_equal(result.within_limits, feasible)
    sets = arm.feasible(pose)
    for b in np.flatnonzero(feasible):
        assert sets.contains(best.value[b], int(b))


def test_singular_values_and_every_solution():
    """S-R-S: the singular arm angles are paper 000's; every solution at a value is the branch's one row; the
    Franka class says it has no singular analysis."""
    arm = redkin.arm("iiwa14.urdf")
    pose = arm.fk(_inside(arm, np.full(7, 0.3)))
    singular = arm.singular(pose, ["+++", "-+-"])
    assert singular.shoulder.shape == (2,) and singular.branches == ("+++", "-+-")
    expected = srs.singular_arm_angles(arm.chain, pose, "+++")
    assert singular.shoulder[0] == expected.shoulder and singular.wrist[0] == expected.wrist
    every = arm.every_solution(pose, 0.4, "+-+")
    np.testing.assert_array_equal(every, arm.ik(pose, 0.4, branches="+-+").q)
    with pytest.raises(ValueError, match="singular"):
        redkin.arm("panda.urdf").singular(pose)


def test_q0_moves_each_joint_by_whole_turns_towards_it():
    arm = redkin.arm("xarm7.urdf")  # every joint but 2, 4 and 6 spans +-2 pi
    q = _inside(arm, np.full(7, 0.3))
    pose = arm.fk(q)
    shifted = q - 2 * np.pi * np.sign(q) * np.array([1, 0, 1, 0, 1, 0, 0])  # the other whole turn, in range
    result = arm.ik(pose, q[6], q0=shifted)
    row = result.q[arm.branches.index(arm.branch_of(q))]
    assert np.max(np.abs(row - shifted)) < 1e-4


def test_bad_input_is_a_value_error_in_words():
    arm = redkin.arm("iiwa14.urdf")
    pose = arm.fk(np.zeros(7))
    cases = {
        "pose must be finite": lambda: arm.ik(np.full((4, 4), np.nan), 0.0),
        "shape": lambda: arm.ik(np.eye(3), 0.0),
        "psi": lambda: arm.ik(pose, np.nan),
        "branch must be one of": lambda: arm.ik(pose, 0.0, branches="+x+"),
        "numerical solver": lambda: arm.ik(pose, 0.0, count=3),
        "'optimal'": lambda: arm.ik(pose, "best"),
        "q must": lambda: arm.parameter_of(np.zeros(6)),
        "one \\(4, 4\\) pose": lambda: arm.every_solution(np.stack([pose, pose]), 0.0, "+++"),
        "tolerance": lambda: redkin.arm("gen3.urdf", srs_tolerance=-1.0),
        "source must be": lambda: redkin.arm(3.0),  # type: ignore[arg-type]
        "SerialChain takes none": lambda: redkin.arm(arm.chain, tip="x"),
    }
    for words, call in cases.items():
        with pytest.raises(ValueError, match=words):
            call()
    with pytest.raises(ValueError):
        redkin.arm("no-such-robot")


@pytest.mark.parametrize("source", ["iiwa14.urdf", "panda.urdf", "gen3.urdf", "sawyer.urdf"])
def test_input_numpy_would_bend_is_refused_on_every_class(source):
    """Found by a sweep: a complex value lost its imaginary part with a warning, a pose 1e160 m away gave the Franka
    class a NaN reach (its poses are checked in the kernel), and every_solution's branch and value were asserted or
    iterated, not checked.  Each is refused in words, alone and in a batch."""
    arm = redkin.arm(source)
    pose = arm.fk(_inside(arm, np.full(7, 0.4)))
    far = pose.copy()
    far[0, 3] = 1e160
    t = () if arm.parameter is None else (0.3,)
    for poses in (far, np.stack([pose, far])):
        with pytest.raises(ValueError, match=r"pose translation must be at most 1e\+06 m in magnitude"):
            arm.ik(poses, *t)
    with pytest.raises(ValueError, match="q must be real numbers, not complex ones"):
        arm.fk(_inside(arm, np.full(7, 0.4)) + 1j)
    with pytest.raises(ValueError, match="pose must be real numbers"):
        arm.ik(pose + 0j, *t)
    with pytest.raises(ValueError, match="q must be numeric"):
        arm.fk(["0.1"] * 7)
    if arm.parameter is None:
        return
    with pytest.raises(ValueError, match="t must be real numbers"):
        arm.ik(pose, np.array([0.3 + 1j]))
    with pytest.raises(ValueError, match="branch must be one of"):
        arm.every_solution(pose, 0.3, None)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="t must be one value"):
        arm.every_solution(pose, np.array([0.1, 0.2]), arm.branches[0])  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="branches must be a branch label or a list of them"):
        arm.ik(pose, 0.3, branches=0)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r"target must be at most 1e\+06 rad"):  # NaN on the Franka class
        arm.optimal(pose, target=np.full(7, 1e300))


def test_an_arm_is_built_once_per_chain_and_redkin_ik_goes_through_it():
    chain = redkin.get_robot("franka-panda")
    arm = redkin.arm(chain)
    assert redkin.arm(chain) is arm and redkin.arm(chain, srs_tolerance=0.01) is not arm
    pose = chain.fk(np.array([0.1, -0.3, 0.2, -2.0, 0.1, 1.7, 0.4]))
    old = redkin.ik(chain, pose, q7=0.4, branch="+-+")
    new = arm.ik(pose, 0.4, branches="+-+")
    np.testing.assert_array_equal(old.q, new.q)
    assert old.parameter == "q7" and str(old.branches[0]) == "+-+"


@pytest.mark.parametrize("source", sorted(CLASS_ARMS) + ["sawyer.urdf"])
def test_the_reason_is_worded_when_asked_and_the_arm_pickles(source, monkeypatch):
    """Classifying does not measure how far a nearly S-R-S or snapped arm's poses move (a search over the joint
    values that most questions never print); the reason, asked, is the classifier's, and an arm (the function
    that words it included) goes through pickle, as a process pool sends it."""
    import pickle

    from redkin.arms.classify import arm_angle_class
    from redkin.srs import conventions
    from redkin.srs.nearly import arm as nearly_arm

    chain = redkin.get_robot(source)
    searched = []
    measure = conventions.model_error
    for module in (conventions, nearly_arm):
        monkeypatch.setattr(module, "model_error", lambda *a: searched.append(1) or measure(*a))
    arm = redkin.arm(chain)
    assert searched == [] and "reason" not in vars(arm)
    assert arm.reason == arm_angle_class(chain).reason
    worded = arm.reason
    if arm.kind == redkin.arms.classify.NEARLY_SRS or "snapped" in worded:
        assert searched and "poses differ by up to" in worded
    copy = pickle.loads(pickle.dumps(arm))
    assert copy.kind == arm.kind and copy.reason == worded


def test_the_pages_example_runs_and_shows_what_it_says(capsys):
    """docs/arm.md's examples, as a newcomer pastes them one after the other: the round trip prints True, the q7
    of q is feasible, and its analysis holds the same set and no singular values."""
    import re
    from pathlib import Path

    page = (Path(__file__).resolve().parents[1] / "docs" / "arm.md").read_text(encoding="utf-8")
    first, second = re.findall(r"^```python\n(.*?)^```", page, flags=re.S | re.M)
    names: dict = {}
    exec(compile(first, "docs/arm.md", "exec"), names)
    lines = capsys.readouterr().out.splitlines()
    assert lines[0] == "Franka (q7) q7 ('+++', '++-', '+-+')" and lines[1] == "True" and lines[-1].endswith("True")
    exec(compile(second, "docs/arm.md", "exec"), names)
    assert capsys.readouterr().out.rstrip().endswith("None")
    np.testing.assert_array_equal(names["shown"].arcs, names["sets"].arcs(names["branch"]).bounds)


def test_optimal_takes_a_target_and_weights_as_the_class_functions_do():
    arm = redkin.arm("iiwa14.urdf")
    pose = arm.fk(_inside(arm, np.full(7, 0.35)))
    target = _inside(arm, np.full(7, 0.6))
    best = arm.optimal(pose, "+-+", target=target, weights=(0.2, 0.8))
    expected = srs.optimal_arm_angles(arm.chain, pose, "+-+", target=target, weights=(0.2, 0.8)).overall
    assert best.unclamped[0] == expected.unclamped
    if expected.feasible is None:
        assert np.isnan(best.value[0])
    else:
        assert best.value[0] == expected.feasible
    panda = redkin.arm("panda.urdf")
    hand = panda.fk(_inside(panda, np.full(7, 0.4)))
    assert panda.optimal(hand, "+++", target=target).unclamped[0] == franka.optimal_q7(
        panda.chain, hand, "+++", target=target).unclamped
    with pytest.raises(ValueError, match="weights"):
        panda.optimal(hand, weights=(0.5, 0.5))
    with pytest.raises(ValueError, match="weights"):
        arm.optimal(pose, weights=(-1.0, 0.5))


def test_per_joint_sets_intersect_to_the_feasible_set():
    """[000 eq. 30]: the feasible set is the intersection of the per-joint sets [000 eq. 29]; the Franka class has
    no per-joint sets and says so."""
    from redkin.circle import ArcSet

    arm = redkin.arm("pa10.toml")
    pose = arm.fk(_inside(arm, np.full(7, 0.3)))
    for branch in arm.branches:
        joints = arm.joint_sets(pose, branch)
        assert sorted(joints) == list(range(1, 8))
        together = ArcSet.full()
        for arcs in joints.values():
            together = together.intersection(ArcSet(arcs.tolist()))
        expected = ArcSet(arm.feasible(pose).arcs(branch).bounds.tolist())
        assert together.isclose(expected, 1e-9)
    with pytest.raises(ValueError, match="per-joint"):
        redkin.arm("panda.urdf").joint_sets(pose, "+++")


def test_path_resolution_takes_an_arm_and_reads_its_class_from_it():
    """resolve_path on an Arm is resolve_path on its chain; path_family is the family the arm was built with."""
    from redkin.paths import path_family, resolve_path

    arm = redkin.arm("iiwa14.urdf")
    start, end = _inside(arm, np.full(7, 0.4)), _inside(arm, np.full(7, 0.55))
    poses = arm.fk(start + np.linspace(0.0, 1.0, 6)[:, None] * (end - start))
    ours, theirs = resolve_path(arm, poses, max_step=0.2), resolve_path(arm.chain, poses, max_step=0.2)
    assert ours.ok and theirs.ok
    np.testing.assert_array_equal(ours.q, theirs.q)
    assert path_family(arm) is path_family(arm.chain) is arm.implementation.family
    with pytest.raises(ValueError, match="general chain"):
        path_family(redkin.arm("sawyer.urdf"))


def test_numerical_rows_of_a_batch_are_the_solvers_solutions_by_branch():
    """Several solutions per pose (count=3) over a batch of two, the arm given as a path: each solution the solver
    found lands in its own branch's row (the first found where two share one, the seed's own in the seed's
    branch), with its own parameter, and no row holds anything else."""
    from pathlib import Path

    from redkin.examples import resolve
    from redkin.numerical import ik as numerical_ik

    arm = redkin.arm(Path(resolve("iiwa14.urdf")))  # a path, as pathlib gives it
    q = np.stack([_inside(arm, np.full(7, 0.6)), _inside(arm, np.full(7, 0.35))])
    poses = arm.fk(q)
    batch = arm.ik(poses, q0=q, count=3)
    solver = numerical_ik(arm.chain, poses, q0=q, count=3)
    assert batch.q.shape == (2, 8, 7) and batch.method == "numerical"
    for k in range(2):
        found = solver.q[k][solver.found[k]]
        labels = [str(b) for b in arm.branch_of(found)]
        expected = {label: found[labels.index(label)] for label in labels}  # the first of each branch
        assert sorted(expected) == [arm.branches[r] for r in np.flatnonzero(batch.exists[k])]
        for label, solution in expected.items():
            np.testing.assert_array_equal(batch.q[k, arm.branches.index(label)], solution)
        assert np.max(np.abs(batch.q[k, arm.branches.index(arm.branch_of(q[k]))] - q[k])) < 1e-6
        np.testing.assert_allclose(batch.parameter[k][batch.exists[k]], arm.parameter_of(batch.q[k][batch.exists[k]]))
