"""Offset elbows (the Barrett WAM class): the arm-angle theory of paper 000 with |SW|^2 = C + R cos(theta_4 - phi).

The laws of the S-R-S tests, on the WAM and on random offset elbows: FK(IK) = x on every branch, the
arm angle inverts IK, the elbow equation equals the distance the chain's own frames give, feasible
sets equal dense sampling (in test_srs_feasible.py and test_srs_speedpaths.py through ``tests.support.srs_arms``),
singular arm angles sit where theta_2 or theta_6 vanish, and the same arm written another way
(modified DH, reversed joints, a URDF with turned frames) is solved in its own joint values.
"""

import json

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from redkin.chain import SerialChain
from redkin.cli.main import main
from redkin.models import barrett_wam, get_robot
from redkin.srs import (
    BRANCHES,
    arm_angle_of,
    feasible_arm_angles,
    ik,
    ik_all_branches,
    reachable,
    singular_arm_angles,
    srs_geometry,
)
from tests.support.feasible_sampling import assert_set_matches_sampling, random_limits
from tests.support.srs_arms import offset_elbow_chain, wrap

ROUND_TRIP = 1e-9


def shoulder_wrist_distance(chain, q):
    """|SW| from the chain's own frames: the shoulder is frame 2's origin, the wrist frame 5's (standard DH)."""
    frames = chain.frames(q)
    return np.linalg.norm(frames[..., 5, :3, 3] - frames[..., 2, :3, 3], axis=-1)


def test_wam_round_trip_10000_poses_all_branches():
    chain = barrett_wam()
    rng = np.random.default_rng(1)
    poses = chain.fk(rng.uniform(-np.pi, np.pi, (10_000, 7)))
    psi = rng.uniform(-np.pi, np.pi, 10_000)
    q = ik_all_branches(chain, poses, psi)
    assert np.abs(chain.fk(q) - poses[:, None]).max() < ROUND_TRIP
    # the branches claim the signs of theta_2, theta_4 - phi and theta_6, and arm_angle_of reads them back
    phase = srs_geometry(chain).elbow_equation.phase
    assert 0.1 < phase < 0.3  # the WAM's longest reach is at theta_4 = 11 deg, not 0
    signs = np.sign(np.stack([q[..., 1], wrap(q[..., 3] - phase), q[..., 5]], axis=-1))
    assert np.all((signs == np.array(BRANCHES)) | (np.abs(signs) == 0))
    state = arm_angle_of(chain, q[:500])
    assert np.allclose(np.cos(state.psi - psi[:500, None]), 1.0, atol=1e-9)
    assert np.array_equal(state.branch, np.broadcast_to(np.array(BRANCHES), (500, 8, 3)))


def test_elbow_equation_is_the_distance_the_frames_give():
    """|SW|^2 = C + R cos(theta_4 - phi) against the chain's frames, for the WAM and random offsets."""
    rng = np.random.default_rng(2)
    chains = [barrett_wam()] + [offset_elbow_chain(*rng.uniform(0.05, 0.8, 4), *rng.uniform(-0.3, 0.3, 2))
                                for _ in range(20)]
    for chain in chains:
        q = rng.uniform(-np.pi, np.pi, (50, 7))
        mean, amplitude, phase = srs_geometry(chain).elbow_equation
        assert np.allclose(shoulder_wrist_distance(chain, q) ** 2, mean + amplitude * np.cos(q[:, 3] - phase),
                           rtol=0, atol=1e-13)
        # longest and shortest reach at theta_4 = phi and phi + pi
        extremes = shoulder_wrist_distance(chain, np.outer([0, np.pi], [0, 0, 0, 1, 0, 0, 0]) + phase * np.eye(7)[3])
        assert np.allclose(extremes ** 2, [mean + amplitude, mean - amplitude], atol=1e-13)


@pytest.mark.slow
@settings(max_examples=40, deadline=None)
@given(lengths=st.lists(st.floats(0.05, 0.9), min_size=4, max_size=4),
       offsets=st.lists(st.one_of(st.just(0.0), st.floats(-0.3, 0.3)), min_size=2, max_size=2),
       tool_sign=st.sampled_from([-1.0, 0.0, 1.0]), seed=st.integers(0, 2**31))
def test_round_trip_on_random_offset_elbows(lengths, offsets, tool_sign, seed):
    """Random a_3, a_4 (either may be 0), d_wt of any sign, with joint signs and offsets: FK(IK) and the arm angle."""
    rng = np.random.default_rng(seed)
    d_bs, d_se, d_ew, d_wt = lengths
    plain = offset_elbow_chain(d_bs, d_se, d_ew, d_wt * tool_sign, *offsets)
    chain = SerialChain(a=plain.a, alpha=plain.alpha, d=plain.d, sign=rng.choice([-1, 1], 7),
                        offset=rng.uniform(-np.pi, np.pi, 7))
    q = rng.uniform(-np.pi, np.pi, (200, 7))
    poses = chain.fk(q)
    solutions = ik_all_branches(chain, poses, rng.uniform(-np.pi, np.pi, (200, 1)))
    assert np.abs(chain.fk(solutions) - poses[:, None]).max() < ROUND_TRIP
    state = arm_angle_of(chain, q)
    for k in range(0, 200, 20):
        again = ik(chain, poses[k], state.psi[k], str(state.branch_strings()[k]))
        assert np.allclose(wrap(again - q[k]), 0.0, atol=1e-8)


def test_reference_plane_is_theta3_zero_and_the_elbow_turns_right_handed():
    chain = barrett_wam()
    rng = np.random.default_rng(3)
    poses = chain.fk(rng.uniform(-np.pi, np.pi, (100, 7)))
    q0 = ik_all_branches(chain, poses, 0.0)
    assert np.allclose(np.sin(q0[..., 2]), 0.0, atol=1e-9)  # theta_3 = 0 (or pi on the sigma_2 = - branches)
    q1 = ik(chain, poses, 1e-4, "+++")
    frames0, frames1 = chain.frames(q0[:, 0]), chain.frames(q1)
    shoulder, wrist = frames0[:, 2, :3, 3], frames0[:, 5, :3, 3]
    axis = np.cross(frames0[:, 3, :3, 3] - shoulder, frames1[:, 3, :3, 3] - shoulder)
    assert np.all(np.einsum("ij,ij->i", axis, wrist - shoulder) > 0)


def test_both_elbows_meet_at_the_longest_and_shortest_reach():
    chain = barrett_wam()
    phase = srs_geometry(chain).elbow_equation.phase
    for theta4 in (phase, phase - np.pi):
        pose = chain.fk(np.array([0.3, 0.5, 0.2, theta4, 0.1, 0.4, 0.2]))
        solutions = ik_all_branches(chain, pose, 0.6)
        assert np.abs(chain.fk(solutions) - pose).max() < ROUND_TRIP
        assert np.allclose(wrap(solutions[:, 3] - wrap(theta4)), 0.0, atol=2e-7)  # acos near +-1: sqrt(eps)


def test_out_of_reach_poses_name_the_reach_interval():
    chain = barrett_wam()
    mean, amplitude, _ = srs_geometry(chain).elbow_equation
    far = np.eye(4)
    far[:3, 3] = [0.0, 0.0, np.sqrt(mean + amplitude) + chain.d[6] + 1e-4]  # wrist just beyond the longest reach
    near = far.copy()
    near[:3, 3] = [0.0, 0.0, np.sqrt(mean + amplitude) + chain.d[6] - 1e-4]
    assert reachable(chain, np.stack([far, near])).tolist() == [False, True]
    with pytest.raises(ValueError,
                       match=rf"must lie in \[{np.sqrt(mean - amplitude):.6g}, {np.sqrt(mean + amplitude):.6g}\]"):
        ik(chain, far, 0.0)


@pytest.mark.parametrize("q, joint", [
    ([0.3, 0.0, 0.5, 0.9, 0.2, 0.4, 0.1], 2),
    ([0.3, 0.7, 0.5, 0.9, 0.2, 0.0, 0.1], 6),
    ([0.3, 0.7, 0.5, -0.9, 0.2, 0.0, 0.1], 6),
])
def test_singular_arm_angles_are_where_theta_2_or_theta_6_vanish(q, joint):
    chain = barrett_wam()
    q = np.array(q)
    state = arm_angle_of(chain, q)
    branch = str(state.branch_strings())
    result = singular_arm_angles(chain, chain.fk(q), branch)
    angles = result.shoulder if joint == 2 else result.wrist
    assert len(angles) == 1 and np.cos(angles[0] - state.psi) == pytest.approx(1.0, abs=1e-12)
    assert abs(np.sin(ik(chain, chain.fk(q), angles[0], branch)[joint - 1])) < 1e-7
    generic = singular_arm_angles(chain, chain.fk(np.array([0.3, 0.7, 0.5, 0.9, 0.2, 0.4, 0.1])), "+++")
    assert generic.shoulder == () and generic.wrist == ()


def test_feasible_sets_of_the_wam_with_narrow_limits_crossing_pi():
    rng = np.random.default_rng(5)
    chain = barrett_wam()
    q = rng.uniform(-np.pi, np.pi, 7)
    pose = chain.fk(q)
    for branch in BRANCHES:
        limited = chain.with_limits(*random_limits(rng, q, crossing=True))
        assert_set_matches_sampling(limited, pose, str(branch), feasible_arm_angles(limited, pose, branch))


def _other_descriptions(chain):
    """The same offset-elbow arm as modified DH rows, and with joints reversed and zero poses moved."""
    modified = SerialChain(a=np.r_[0.0, chain.a[:6]], alpha=np.r_[0.0, chain.alpha[:6]], d=chain.d, convention="mdh")
    reversed_joints = SerialChain(a=chain.a, alpha=chain.alpha, d=chain.d, sign=[1, -1, -1, 1, -1, 1, -1],
                                  offset=[0.2, 0, 3.0, -0.5, 0, 1.0, 0])
    flipped_twists = SerialChain(a=-chain.a, alpha=-chain.alpha, d=chain.d)  # every common normal turned over
    return {"modified DH": modified, "reversed joints": reversed_joints, "flipped twists": flipped_twists}


@pytest.mark.parametrize("name", ["modified DH", "reversed joints", "flipped twists"])
def test_the_wam_in_other_descriptions_is_solved_in_its_own_joint_values(name):
    chain = _other_descriptions(barrett_wam())[name]
    rng = np.random.default_rng(6)
    q = rng.uniform(-np.pi, np.pi, (300, 7))
    poses = chain.fk(q)
    assert np.abs(chain.fk(ik_all_branches(chain, poses, 1.1)) - poses[:, None]).max() < ROUND_TRIP
    state = arm_angle_of(chain, q)
    for k in range(0, 300, 30):
        again = ik(chain, poses[k], state.psi[k], str(state.branch_strings()[k]))
        assert np.allclose(wrap(again - q[k]), 0.0, atol=1e-8)
    limited = chain.with_limits(q[0] - 0.001, q[0] + 0.001)  # +-1 mrad round a solution: a tiny arc, still found
    branch = str(state.branch_strings()[0])
    result = feasible_arm_angles(limited, poses[0], branch)
    assert result.feasible.contains(state.psi[0], tolerance=1e-12) and result.feasible.length < 0.05
    assert_set_matches_sampling(limited, poses[0], branch, result, margin=1e-9)


def test_a_wam_urdf_with_turned_frames_and_reversed_axes(tmp_path):
    """A URDF of the WAM whose joint frames are turned about their axes and whose axes point either way."""
    from tests.support.urdf_reference import reference_fk, urdf

    wam = barrett_wam()
    rows = list(zip(wam.a, wam.alpha, wam.d))
    turns = [0.4, -1.0, 2.0, 0.3, -0.7, 1.3, 0.0]  # each joint frame turned this far about its axis
    axes = [1, -1, 1, -1, -1, 1, 1]
    joints, previous_turn = [], 0.0
    for k in range(8):  # joint k + 1 sits where DH row k ends; the last is the fixed tool (row 7)
        a, alpha, d = rows[k - 1] if k else (0.0, 0.0, 0.0)
        turn = turns[k] if k < 7 else 0.0
        # DH: Rz(theta) Tz(d) Tx(a) Rx(alpha); the previous frame's turn is undone first
        xyz = f"{a * np.cos(-previous_turn):.17g} {a * np.sin(-previous_turn):.17g} {d:.17g}"
        kind, axis = ("revolute", f"0 0 {axes[k]}") if k < 7 else ("fixed", "")
        joints.append((kind, xyz, _origin_rpy(-previous_turn, alpha, turn), axis))
        previous_turn = turn
    text = urdf(joints, name="wam")
    path = tmp_path / "wam.urdf"
    path.write_text(text)
    chain = get_robot(path)
    rng = np.random.default_rng(7)
    q = rng.uniform(chain.lower, chain.upper, (100, 7))
    assert np.allclose(chain.fk(q[0]), reference_fk(text, q[0], "l8"), atol=1e-12)
    assert np.allclose(chain.fk(q[:3] * axes), wam.fk(q[:3]), atol=1e-12)  # the WAM, joints turning as the axes say
    solutions = ik_all_branches(chain, chain.fk(q), 0.4)
    assert np.abs(chain.fk(solutions) - chain.fk(q)[:, None]).max() < ROUND_TRIP
    for branch in BRANCHES[:4]:
        pose = chain.fk(q[1])
        assert_set_matches_sampling(chain, pose, str(branch), feasible_arm_angles(chain, pose, branch))


def _origin_rpy(before: float, alpha: float, turn: float) -> str:
    """rpy of ``Rz(before) Rx(alpha) Rz(turn)`` (URDF: R = Rz(yaw) Ry(pitch) Rx(roll))."""
    def rz(t):
        return np.array([[np.cos(t), -np.sin(t), 0], [np.sin(t), np.cos(t), 0], [0, 0, 1]])

    rx = np.array([[1, 0, 0], [0, np.cos(alpha), -np.sin(alpha)], [0, np.sin(alpha), np.cos(alpha)]])
    r = rz(before) @ rx @ rz(turn)
    pitch = np.arcsin(-np.clip(r[2, 0], -1, 1))
    roll, yaw = np.arctan2(r[2, 1], r[2, 2]), np.arctan2(r[1, 0], r[0, 0])
    return f"{roll:.17g} {pitch:.17g} {yaw:.17g}"


def test_arms_outside_the_class_are_refused_with_the_reason():
    wam = barrett_wam()
    through_shoulder = offset_elbow_chain(0.3, 0.0, 0.4, 0.1, 0.0, 0.05)  # joint 4's axis meets the shoulder
    with pytest.raises(ValueError, match="shoulder and elbow coincide \\(joint 4's axis passes through the shoulder"):
        srs_geometry(through_shoulder)
    with pytest.raises(ValueError, match="shoulder and elbow coincide"):
        srs_geometry(SerialChain(a=np.r_[0.0, through_shoulder.a[:6]], alpha=np.r_[0.0, through_shoulder.alpha[:6]],
                                 d=through_shoulder.d, convention="mdh"))
    along_joint_4 = SerialChain(a=wam.a, alpha=wam.alpha, d=np.r_[wam.d[:3], 0.02, wam.d[4:]])
    with pytest.raises(ValueError, match=r"offset 0\.02 m along joint 4"):
        srs_geometry(along_joint_4)


def test_cli_ik_and_arm_angles_on_the_wam(capsys):
    wam = barrett_wam().with_limits(np.full(7, -2.5), np.full(7, 2.5))
    q = np.array([0.3, 0.7, 0.5, 0.9, 0.2, 0.4, 0.1])
    pose = wam.fk(q)
    argv = ["--position", *(f"{v:.17g}" for v in pose[:3, 3]),
            "--rotation", *(f"{v:.17g}" for v in pose[:3, :3].ravel())]
    assert main(["ik", "barrett-wam", *argv, "--psi", "0.5", "--all", "--json"]) == 0
    solutions = np.array([s["q"] for s in json.loads(capsys.readouterr().out)["solutions"]])
    assert solutions.shape == (8, 7) and np.abs(wam.fk(solutions) - pose).max() < ROUND_TRIP
    state = arm_angle_of(wam, q)
    assert main(["arm-angles", "barrett-wam", *argv, "--branch", str(state.branch_strings()), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["fixed"]["4"] == pytest.approx(0.9, abs=1e-9)
    model = get_robot("barrett-wam")
    expected = feasible_arm_angles(model, pose, str(state.branch_strings())).feasible.intervals
    assert np.allclose(np.array(data["feasible"]).reshape(-1, 2), np.array(expected).reshape(-1, 2), atol=1e-12)


def test_paper_003_elbow_singularity_is_where_the_two_elbow_branches_meet():
    """D_e of paper 003 (the WAM's elbow singularity index) is -K sin(theta_4 - phi): it vanishes exactly where
    |SW| is longest or shortest, and its sign is minus the elbow branch sign of the arm-angle IK."""
    from redkin.velocity import WamFactorisation

    wam = barrett_wam()
    index = WamFactorisation.from_chain(wam).index
    q = np.random.default_rng(8).uniform(-np.pi, np.pi, (2000, 7))
    elbow = arm_angle_of(wam, q).branch[:, 1]
    d_e = index(q)
    away = np.abs(d_e) > 1e-9
    assert np.all(np.sign(d_e[away]) == -elbow[away])
    phase = srs_geometry(wam).elbow_equation.phase
    assert abs(index(np.r_[0, 0, 0, phase, 0, 0, 0])) < 1e-15


def test_feasible_arm_angles_along_a_velocity_ik_run_contain_its_arm_angle_exactly_when_in_range():
    """The report's WAM subsection: along an SC run, psi(t) is in the feasible set iff q(t) is within the limits."""
    from redkin.models import barrett_wam7
    from redkin.reproduce import printed
    from redkin.reproduce.paper_003 import _feasible_along_path
    from redkin.velocity import SingularityConsistent, WamFactorisation, simulate

    wam = barrett_wam()
    ranges = barrett_wam7()
    chain = wam.with_limits(ranges.lower, ranges.upper)
    q0 = np.radians(printed.SECTION_4_Q0_DEG)  # paper 003 section 4's start ...
    q0[5] = np.radians(80.0)  # ... with q6 inside Barrett's +-91.7 deg
    run = simulate(wam, q0, np.array(printed.SECTION_4_TWIST), 1.0, SingularityConsistent(eps=printed.SECTION_4_D_EPS),
                   dt=5e-3, index=WamFactorisation.from_chain(wam).index)
    psi, branches, sets = _feasible_along_path(chain, run.q[::10])
    within = chain.joints_within_limits(run.q[::10], wrap=True).all(axis=-1)
    assert within.any()
    assert [s.contains(p, tolerance=1e-9) for s, p in zip(sets, psi)] == within.tolist()
    assert set(branches.tolist()) <= {str(b) for b in BRANCHES}
