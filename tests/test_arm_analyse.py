"""Arm.analyse (issue 39): one answer of what a pose's redundancy holds, for every class, that agrees with the
front door's own questions (feasible, optimal, singular, joint_sets) and with the solutions themselves: a joint
the pose fixes has that value at every parameter; membership of the arcs is the arcs' own (through the seam too);
bad input is a ValueError in words."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import redkin
from redkin.arms.analysis import in_arcs
from redkin.circle import ArcSet

#: Where each joint lies in its range (a range wider than the circle read as [-pi, pi)): inside the limits and away
#: from a straight shoulder, elbow or wrist on every arm below.
FRACTIONS = np.array([0.6, 0.75, 0.4, 0.35, 0.55, 0.75, 0.6])
#: A configuration inside the limits of every arm below (the Panda's) for the poses of the questions on bad input.
Q = np.array([0.3, 0.5, -0.2, -1.2, 0.4, 1.0, 0.3])


def _inside(arm: redkin.Arm) -> np.ndarray:
    lower, upper = np.maximum(arm.chain.lower, -np.pi), np.minimum(arm.chain.upper, np.pi)
    return lower + (0.05 + 0.9 * FRACTIONS) * (upper - lower)


def _close(a: float, b: float, wraps: bool) -> bool:
    if not (np.isfinite(a) and np.isfinite(b)):
        return np.isfinite(a) == np.isfinite(b)
    gap = np.angle(np.exp(1j * (a - b))) if wraps else a - b
    return abs(gap) < 1e-9


@pytest.mark.parametrize("source", ["iiwa14.urdf", "barrett-wam7", "panda.urdf", "gen3.urdf"])
def test_the_analysis_agrees_with_the_front_doors_questions(source):
    arm = redkin.arm(source)
    q = _inside(arm)
    pose = arm.fk(q)
    analysis = arm.analyse(pose)
    parameter = analysis.parameter
    assert parameter == arm.parameter and [b.branch for b in analysis.branches] == list(arm.branches)
    feasible = arm.feasible(pose)
    optimal = arm.optimal(pose)
    for k, (label, branch) in enumerate(zip(arm.branches, analysis.branches)):
        expected = feasible.arcs(label).bounds
        np.testing.assert_allclose(analysis.sets[k], expected, atol=1e-9)
        np.testing.assert_array_equal(analysis.sets[k], branch.arcs)
        unclamped, inside = branch.optimal["overall"]
        assert _close(inside, optimal.value[k], parameter.wraps)
        assert _close(unclamped, optimal.unclamped[k], parameter.wraps)
        if branch.per_joint is not None:
            joints = arm.joint_sets(pose, label)
            assert set(branch.per_joint) == set(joints)
            for joint, arcs in joints.items():
                np.testing.assert_array_equal(branch.per_joint[joint], arcs)
        if branch.singular is not None:
            singular = arm.singular(pose, label)
            np.testing.assert_allclose(branch.singular["shoulder"].values, singular.shoulder[0], atol=1e-12)
            np.testing.assert_allclose(branch.singular["wrist"].values, singular.wrist[0], atol=1e-12)
    own = analysis.branches[arm.branches.index(str(arm.branch_of(q)))]
    assert arm.within_limits(q) and in_arcs(np.array([float(arm.parameter_of(q))]), own.arcs, 1e-9)[0]


@pytest.mark.parametrize("source", ["iiwa14.urdf", "barrett-wam7"])
def test_a_joint_the_pose_fixes_has_that_value_at_every_parameter(source):
    arm = redkin.arm(source)
    pose = arm.fk(_inside(arm))
    values = np.linspace(-np.pi, np.pi, 37)
    solutions = arm.ik(np.broadcast_to(pose, (len(values), 4, 4)), values)
    for k, branch in enumerate(arm.analyse(pose).branches):
        assert branch.fixed, "an S-R-S arm's elbow does not depend on the arm angle"
        for joint, value in branch.fixed.items():
            np.testing.assert_allclose(solutions.q[:, k, joint - 1], value, atol=1e-9)


def test_classes_without_a_part_leave_it_out():
    panda = redkin.arm("panda.urdf").analyse(redkin.arm("panda.urdf").fk(Q), "+-+")
    assert len(panda.branches) == 1 and panda.branches[0].per_joint is None and panda.branches[0].singular is None
    assert set(panda.branches[0].optimal) == {"overall"} and panda.complete and len(panda.sets) == 8
    iiwa = redkin.arm("iiwa14.urdf").analyse(redkin.arm("iiwa14.urdf").fk(Q), ["+++", "---"])
    assert [b.branch for b in iiwa.branches] == ["+++", "---"]
    assert list(iiwa.branches[0].optimal) == ["shoulder", "wrist", "overall"] and not iiwa.remarks


@settings(max_examples=60)
@given(start=st.floats(-np.pi, np.pi), length=st.floats(0.0, 2 * np.pi - 1e-6),
       values=st.lists(st.floats(-np.pi, np.pi), min_size=1, max_size=20))
def test_membership_is_the_arc_sets_own(start, length, values):
    """An arc through the seam (start > end) holds the values on either side of +-pi; the empty set none."""
    end = float(np.angle(np.exp(1j * (start + length))))
    arcs = ArcSet([(start, end)]) if length > 0 else ArcSet([])
    points = np.array(values)
    expected = np.asarray(arcs.contains(points, 1e-12), dtype=bool)
    np.testing.assert_array_equal(in_arcs(points, np.array(arcs.arcs, dtype=float).reshape(-1, 2)), expected)


@pytest.mark.parametrize("call, fragment", [
    (lambda arm: arm.analyse(np.stack([np.eye(4)] * 2)), r"one \(4, 4\) pose"),
    (lambda arm: arm.analyse(np.full((4, 4), np.nan)), "finite"),
    (lambda arm: arm.analyse(arm.fk(Q), "+x+"), "branch must be one of"),
    (lambda arm: arm.analyse(arm.fk(Q), target=[0.0] * 6), "target"),
])
def test_bad_input_is_a_value_error_in_words(call, fragment):
    with pytest.raises(ValueError, match=fragment):
        call(redkin.arm("iiwa14.urdf"))


def test_a_general_chain_and_weights_on_q7_refuse_in_words():
    with pytest.raises(ValueError, match="need a redundancy parameter"):
        redkin.arm("sawyer.urdf").analyse(np.eye(4))
    panda = redkin.arm("panda.urdf")
    with pytest.raises(ValueError, match="weights weigh the shoulder"):
        panda.analyse(panda.fk(Q), weights=(1.0, 0.5))


@pytest.mark.parametrize("source, measure", [
    ("iiwa14.urdf", "shoulder-wrist distance"),
    ("panda.urdf", "shoulder-wrist distance at the most favourable q7"),
    ("gen3.urdf", "on joint 1's axis"),
])
def test_a_pose_out_of_reach_is_an_unreachable_pose_error_on_every_class(source, measure, capsys):
    """Every class refuses a pose its reach proves out of reach, before any search, in one line with the distance:
    ``redkin arm-angles`` exits 2 with that line, as for any bad input (the Franka class and nearly S-R-S arms
    printed empty sets with exit 0 before)."""
    arm = redkin.arm(source)
    far = np.eye(4)
    far[:3, 3] = [5.0, 0.0, 0.0]
    with pytest.raises(redkin.errors.UnreachablePoseError, match=measure):
        arm.analyse(far)
    near = arm.fk(_inside(arm))  # in reach: an analysis, whatever its sets
    assert len(arm.analyse(near).branches) == 8
    from redkin.cli.main import main

    assert main(["arm-angles", source, "--position", "5", "0", "0", "--quat", "1", "0", "0", "0"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "unreachable pos" in err[0] and measure in err[0]
