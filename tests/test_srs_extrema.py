"""Extrema of the joint angles over the arm angle ([000 eqs. 21-28]): redkin.srs.joint_extrema.

Every reported property is checked against redkin.srs.ik sampled densely on the circle of arm angles.
"""

from dataclasses import replace

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from redkin.models import barrett_wam, pa10_7c, planar_arm, srs_chain
from redkin.srs import (
    BRANCHES,
    feasible_arm_angles,
    ik,
    joint_extrema,
    pose_from,
    singular_arm_angles,
    srs_geometry,
)
from redkin.srs.extrema import _LIMIT_CASES, _limit_case, _tangent_case
from tests.support.srs_arms import offset_elbow_chain, wrap

SAMPLES = 200_000
GRID = np.linspace(-np.pi, np.pi, SAMPLES, endpoint=False)
STEP = 1e-5  # central finite difference step (radians of psi)
PSI_JOINTS = (1, 2, 3, 5, 6, 7)
WIDE = (np.full(7, -4.0), np.full(7, 4.0))  # limits that never bind (ranges >= 2 pi: unlimited)


def sampled(arm, pose, branch, psi=GRID):
    """Joint values of ik at arm angles psi, shape (len(psi), 7)."""
    return ik(arm, np.broadcast_to(pose, np.shape(psi) + (4, 4)), psi, branch)


def check_stationary_points(arm, pose, branch, extrema):
    """At each reported extremum the central difference of q(psi) vanishes and q is a local max / min."""
    for joint, result in extrema.items():
        if result.maximum is None:
            continue
        # distance between the two extrema: tiny only next to the singular case (theta_2 or theta_6 near 0),
        # where theta swings by nearly pi within it and a fixed finite-difference step would straddle both
        separation = abs(wrap(result.maximum.psi - result.minimum.psi))
        for point, sign in ((result.maximum, 1.0), (result.minimum, -1.0)):
            value = sampled(arm, pose, branch, np.array([point.psi]))[0, joint - 1]
            # next to a singular case the joint is ill-conditioned (rounding / sin theta_6 ~ 1 / separation^2):
            # ik and joint_extrema take different float paths to the same value
            assert abs(wrap(value - point.value)) < 1e-12 / min(1.0, separation) ** 2
            scale = min(1.0, separation)
            if scale > 1e-6:  # below, rounding of theta (~1e-16 / scale) swamps any difference quotient
                step = STEP * scale
                pair = sampled(arm, pose, branch, np.array([point.psi - step, point.psi + step]))[:, joint - 1]
                derivative = wrap(pair[1] - pair[0]) / (2.0 * step)
                assert abs(derivative) < 1e-6 / scale, (joint, derivative)
            # local maximum (sign +1) or minimum (sign -1) on neighbourhoods at the scale of the function
            for width in (1e-2, separation / 4):
                near = sampled(arm, pose, branch, point.psi + np.linspace(-width, width, 41))[:, joint - 1]
                assert np.all(sign * wrap(near - point.value) <= 1e-12), joint


def check_against_dense_sampling(arm, pose, branch, extrema, tolerance=1e-6):
    """Global max / min equal dense sampling (wrap-aware); monotonic joints never turn back."""
    q = sampled(arm, pose, branch)
    for joint, result in extrema.items():
        values = q[:, joint - 1]
        if result.case == "periodic":
            lift = np.unwrap(values)  # ik wraps values into limits that cross +-pi, so any joint may jump by 2 pi
            # a cosine-type joint reaching 0 or pi (theta_2 or theta_6 singular) has a kink there, where the
            # grid misses the extremum by up to |slope| * step / 2 (first order) instead of second order
            ends = np.sin([result.maximum.value, result.minimum.value])
            close = 1e-4 if result.kind == "cosine" and np.min(np.abs(ends)) < 1e-6 else tolerance
            assert abs(wrap(lift.max() - result.maximum.value)) < close, joint
            assert abs(wrap(lift.min() - result.minimum.value)) < close, joint
            width = np.mod(result.maximum.value - result.minimum.value, 2 * np.pi)
            assert abs(wrap(np.ptp(lift) - width)) < close
            assert width > 1e-7  # smaller swings are reported as constant
            # the sampled arg max / arg min sit at the reported arm angles (unless theta is nearly flat)
            if np.ptp(lift) > 1e-3:
                assert abs(wrap(GRID[np.argmax(lift)] - result.maximum.psi)) < 1e-2, joint
                assert abs(wrap(GRID[np.argmin(lift)] - result.minimum.psi)) < 1e-2, joint
        elif result.case in ("monotonic", "singular"):
            # singular: theta jumps by pi at result.jump, so differences are taken modulo pi
            # (at the singular arm angle itself only theta_1 + theta_3 is defined: that sample is left out)
            period = np.pi if result.case == "singular" else 2.0 * np.pi
            steps = np.diff(np.append(values, values[0]))
            steps = np.mod(steps + period / 2, period) - period / 2
            if result.case == "singular":
                at_jump = np.abs(wrap(GRID - result.jump)) < 1e-9
                steps = steps[~(at_jump | np.roll(at_jump, -1))]
            assert result.direction in (1, -1)
            assert np.all(result.direction * steps > -1e-9), joint
            if result.case == "monotonic":  # a monotonic tangent-type joint winds once around the circle
                assert steps.sum() == pytest.approx(2 * np.pi * result.direction, abs=1e-6)
        elif result.case == "undefined":  # singular at every arm angle: theta_2 (theta_6) is 0 or pi throughout
            middle = q[:, 1 if joint < 4 else 5]
            assert np.max(np.abs(np.sin(middle))) < 1e-6, joint
        else:
            assert result.case == "constant"
            assert np.ptp(wrap(values - values[0])) < 1e-6, joint


def check_limit_cases(arm, pose, branch, extrema):
    """Section 4.3: the case of each periodic joint matches its feasible set Psi_i ([000 eq. 29])."""
    sets = feasible_arm_angles(arm, pose, branch).per_joint
    for joint, result in extrema.items():
        if result.limit_case is None:
            continue
        own = sets[joint]
        limits = arm.lower[joint - 1], arm.upper[joint - 1]
        extremes = result.maximum.value, result.minimum.value
        if arm.limited[joint - 1] and min(abs(wrap(v - l)) for v in extremes for l in limits) < 1e-9:
            continue  # an extreme touching a limit: the touching point may or may not count as an arc
        if result.limit_case == 1:
            assert own.is_empty, joint
        elif result.limit_case == 5:
            assert own.is_full, joint
        else:
            assert not own.is_empty and not own.is_full
            has_max, has_min = own.contains(result.maximum.psi), own.contains(result.minimum.psi)
            expected = {2: (True, False), 3: (False, True), 4: (False, False)}[result.limit_case]
            assert (has_max, has_min) == expected, (joint, result.limit_case)
            if result.limit_case == 4:
                assert len(own.arcs) == 2


def check_all(arm, pose, branch, **kwargs):
    extrema = joint_extrema(arm, pose, branch)
    assert tuple(extrema) == PSI_JOINTS
    check_stationary_points(arm, pose, branch, extrema)
    check_against_dense_sampling(arm, pose, branch, extrema, **kwargs)
    check_limit_cases(arm, pose, branch, extrema)
    return extrema


# ------------------------------------------------------------------ paper 000, section 6.1


def test_paper_pose_of_section_6_1():
    arm = pa10_7c()
    pose = pose_from(np.array([0.65, 0.0, 0.5]), np.diag([-1.0, 1.0, -1.0]))
    extrema = check_all(arm, pose, "+++")
    kinds = {j: (e.kind, e.case) for j, e in extrema.items()}
    assert kinds == {
        1: ("tangent", "periodic"), 2: ("cosine", "periodic"), 3: ("tangent", "monotonic"),
        5: ("tangent", "monotonic"), 6: ("cosine", "periodic"), 7: ("tangent", "periodic"),
    }
    # theta at psi = 0 printed in 6.1: [0, 25.666, 0, 82.872, 0, 71.463, 0] deg; psi = 0 is where
    # theta_2 and theta_6 are smallest, so the printed values are their minima
    assert extrema[2].minimum.psi == pytest.approx(0.0, abs=1e-12)
    assert np.degrees(extrema[2].minimum.value) == pytest.approx(25.666, abs=5e-4)
    assert np.degrees(extrema[6].minimum.value) == pytest.approx(71.463, abs=5e-4)
    # Psi_1 = Psi_7 = [-180, 180] (case 5); Psi_2, Psi_6 are regions around psi_min (case 3);
    # Psi_3, Psi_5 single arcs bounded by the limits (monotonic joints)
    assert [extrema[j].limit_case for j in PSI_JOINTS] == [5, 3, None, None, 3, 5]
    assert all(extrema[j].monotonic for j in (3, 5)) and not any(extrema[j].monotonic for j in (1, 2, 6, 7))


@pytest.mark.parametrize("branch", [str(b) for b in BRANCHES])
def test_every_branch_of_a_generic_pose(branch):
    arm = pa10_7c()
    pose = arm.fk(np.array([0.4, 0.8, -0.6, 1.1, 0.7, -0.9, 0.3]))
    extrema = check_all(arm, pose, branch)
    plus = joint_extrema(arm, pose, "+" + branch[1] + "+")
    for joint in (1, 3, 5, 7):  # sigma = -1 turns a tangent-type angle by pi: same arm angles, same case
        assert extrema[joint].case == plus[joint].case
        if extrema[joint].maximum is not None:
            assert extrema[joint].maximum.psi == pytest.approx(plus[joint].maximum.psi, abs=1e-12)


# ------------------------------------------------------------------ singular and degenerate poses


@pytest.mark.parametrize(
    "q, group",
    [
        ([0.3, 0.0, 0.5, 0.9, 0.2, 0.4, 0.1], "shoulder"),  # theta_2 = 0
        ([0.3, 0.7, 0.5, 0.9, 0.2, 0.0, 0.1], "wrist"),  # theta_6 = 0
        ([0.0, 0.0, 0.0, -1.0, 0.2, 0.4, 0.1], "shoulder"),  # singular at psi = +-pi
        ([0.0, -0.6, 0.0, -1.0, 0.2, 0.0, 0.1], "wrist"),  # wrist singular at psi = +-pi
    ],
)
def test_singular_case_jumps_where_singular_arm_angles_says(q, group):
    arm = pa10_7c().with_limits(*WIDE)
    pose = arm.fk(np.array(q))
    branch = "+" + ("+" if q[3] >= 0 else "-") + "+"
    extrema = check_all(arm, pose, branch)
    singular = singular_arm_angles(arm, pose, branch)
    angles = singular.shoulder if group == "shoulder" else singular.wrist
    joints = (1, 3) if group == "shoulder" else (5, 7)
    for joint in joints:
        result = extrema[joint]
        assert result.case == "singular" and result.monotonic and result.maximum is None
        assert abs(wrap(result.jump - angles[0])) < 1e-8
        # theta jumps by pi across the singular arm angle
        across = sampled(arm, pose, branch, result.jump + np.array([-1e-7, 1e-7]))[:, joint - 1]
        assert abs(abs(wrap(across[1] - across[0])) - np.pi) < 1e-4
    for joint in {1, 3, 5, 7} - set(joints):
        assert extrema[joint].case != "singular"
    # the cosine-type joint touches 0 at the same arm angle: its (kinked) minimum
    cosine = extrema[2 if group == "shoulder" else 6]
    assert abs(wrap(cosine.minimum.psi - angles[0])) < 1e-8 and abs(cosine.minimum.value) < 1e-7


def test_wrist_on_the_joint_1_axis():
    # equal upper arm and forearm: theta_2 = -theta_4 / 2 puts the wrist on the joint-1 axis
    arm = srs_chain(0.3, 0.4, 0.4, 0.1)
    pose = arm.fk(np.array([0.2, -0.5, 0.0, 1.0, 0.4, 0.6, -0.3]))
    extrema = check_all(arm, pose, "+++")
    assert extrema[2].case == "constant" and extrema[2].maximum is None  # theta_2 does not depend on psi
    assert extrema[1].case == "monotonic" and extrema[1].direction == 1  # theta_1 = psi + const
    assert extrema[1].coefficients[:2] == pytest.approx((0.0, 0.0), abs=1e-12)
    values = sampled(arm, pose, "+++", GRID[:1000])[:, 0]
    assert np.allclose(wrap(values - GRID[:1000] - (values[0] - GRID[0])), 0.0, atol=1e-9)


def test_stretched_elbow_theta4_zero():
    arm = pa10_7c().with_limits(*WIDE)
    pose = arm.fk(np.array([0.3, 0.6, 0.2, 0.0, 0.5, 0.7, -0.2]))
    extrema = check_all(arm, pose, "+++")
    # the upper arm lies on the shoulder-wrist axis: theta_1 and theta_2 stay, theta_3 turns with psi
    assert extrema[1].case == "constant" and extrema[2].case == "constant"
    assert extrema[3].case == "monotonic"


def test_sign_and_offset_of_the_chain_swap_maximum_and_minimum():
    base = pa10_7c().with_limits(*WIDE)
    sign = np.array([-1.0, -1.0, 1.0, 1.0, 1.0, -1.0, -1.0])
    offset = np.array([0.2, -0.1, 0.0, 0.0, 0.3, 0.0, 0.1])
    arm = replace(base, sign=sign, offset=offset)
    pose = arm.fk(np.array([0.4, 0.8, -0.6, 1.1, 0.7, -0.9, 0.3]))
    extrema = check_all(arm, pose, "+++")
    # the arm's "+++" names the signs of its own q_2, q_4, q_6: the Table 1 branch "-+-" of the plain chain
    same_branch = str(srs_geometry(arm).table1_branch("+++"))
    assert same_branch == "-+-"
    plain = joint_extrema(base, pose, same_branch)
    for joint in PSI_JOINTS:
        if extrema[joint].case == "periodic" and sign[joint - 1] < 0:
            assert extrema[joint].maximum.psi == pytest.approx(plain[joint].minimum.psi, abs=1e-12)
        if extrema[joint].monotonic:
            assert extrema[joint].direction == plain[joint].direction * int(sign[joint - 1])


# ------------------------------------------------------------------ the five cases of section 4.3


def test_limit_case_function_covers_the_five_cases_and_the_wrap():
    lo, hi = -1.0, 1.0
    assert _limit_case(-1.5, -2.0, lo, hi, True) == 1
    assert _limit_case(0.5, -2.0, lo, hi, True) == 2
    assert _limit_case(2.0, 0.5, lo, hi, True) == 3
    assert _limit_case(2.0, -2.0, lo, hi, True) == 4
    assert _limit_case(0.5, -0.5, lo, hi, True) == 5
    assert _limit_case(2.0, -2.0, lo, hi, False) == 5
    # limits crossing +-pi: [2.5, 3.8] is [2.5, pi] and [-pi, -2.48]
    assert _limit_case(-2.6, 3.0, 2.5, 3.8, True) == 5
    assert _limit_case(-2.0, 3.0, 2.5, 3.8, True) == 3
    # both extremes within wide limits but the sweep crosses their gap at +-pi
    assert _limit_case(-2.9, 2.9, -3.0, 3.0, True) is None
    assert set(_LIMIT_CASES) == {1, 2, 3, 4, 5}


def test_limit_cases_on_a_crafted_pose_reach_every_case():
    base = pa10_7c()
    pose = base.fk(np.array([0.4, 0.8, -0.6, 1.1, 0.7, -0.9, 0.3]))
    free = joint_extrema(base.with_limits(*WIDE), pose, "+++")
    seen = set()
    for joint in (2, 6):  # cosine type: periodic in [0, pi]
        top, bottom = free[joint].maximum.value, free[joint].minimum.value
        middle = 0.5 * (top + bottom)
        for lo, hi, case in [
            (top + 0.1, top + 0.2, 1), (middle, top + 0.1, 2), (bottom - 0.1, middle, 3),
            (middle - 0.01, middle + 0.01, 4), (bottom - 0.1, top + 0.1, 5),
        ]:
            lower, upper = WIDE[0].copy(), WIDE[1].copy()
            lower[joint - 1], upper[joint - 1] = lo, hi
            arm = base.with_limits(lower, upper)
            result = joint_extrema(arm, pose, "+++")[joint]
            assert result.limit_case == case
            seen.add(case)
            check_limit_cases(arm, pose, "+++", {joint: result})
    assert seen == {1, 2, 3, 4, 5}


def test_tangent_case_classifies_the_sign_of_eq_24():
    derivative = np.array([[1.0, 0.0, 0.5], [0.3, 0.0, 1.0], [0.6, 0.8, 1.0], [0.0, 0.0, 1e-14]])
    assert _tangent_case(derivative).tolist() == ["periodic", "monotonic", "singular", "constant"]
    # constant is relative to the size of N and D: the same coefficients are monotonic for tiny N and D
    assert _tangent_case(derivative[3:], scale=1e-14).tolist() == ["monotonic"]


# ------------------------------------------------------------------ random poses and random S-R-S geometries

# Generic random inputs come from a seeded generator: hypothesis' own float shrinking drifts to doubly degenerate
# poses (theta_4 ~ 1e-7 with theta_6 ~ 1e-15), whose near-singular cases the explicit tests above cover one at a time.
angles = st.floats(-np.pi, np.pi, allow_nan=False)
joint_vectors = st.integers(0, 2**32 - 1).map(
    lambda seed: np.random.default_rng(seed).uniform(-np.pi, np.pi, 7).tolist()
)
lengths = st.floats(0.05, 1.0)


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(q=joint_vectors, branch=st.sampled_from([str(b) for b in BRANCHES]), model=st.sampled_from(["pa10", "wam"]))
def test_random_poses_pa10_and_wam(q, branch, model):
    arm = pa10_7c() if model == "pa10" else barrett_wam()
    pose = arm.fk(np.array(q))
    check_all(arm, pose, branch)


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    d=st.tuples(lengths, lengths, lengths, lengths),
    elbow_offsets=st.one_of(st.just((0.0, 0.0)), st.tuples(st.floats(-0.2, 0.2), st.floats(-0.2, 0.2))),
    q=joint_vectors,
    limits=st.lists(st.tuples(angles, st.floats(0.05, 2 * np.pi - 0.05)), min_size=7, max_size=7),
    branch=st.sampled_from([str(b) for b in BRANCHES]),
)
def test_random_srs_and_offset_elbow_geometries_and_limits(d, elbow_offsets, q, limits, branch):
    lower = np.array([lo for lo, _ in limits])
    upper = lower + np.array([width for _, width in limits])
    arm = offset_elbow_chain(*d, *elbow_offsets).with_limits(lower, upper)
    pose = arm.fk(np.array(q))
    check_all(arm, pose, branch)


# ------------------------------------------------------------------ bad input


def test_bad_input_raises_value_error_naming_the_argument():
    arm = pa10_7c()
    pose = arm.fk(np.zeros(7))
    with pytest.raises(ValueError, match="one pose"):
        joint_extrema(arm, np.stack([pose, pose]), "+++")
    with pytest.raises(ValueError, match="pose"):
        joint_extrema(arm, np.full((4, 4), np.nan), "+++")
    with pytest.raises(ValueError, match="pose"):
        joint_extrema(arm, np.eye(3), "+++")
    with pytest.raises(ValueError, match="branch"):
        joint_extrema(arm, pose, "+x+")
    with pytest.raises(ValueError, match="tolerance"):
        joint_extrema(arm, pose, "+++", tolerance=-1.0)
    with pytest.raises(ValueError, match="unreachable"):
        joint_extrema(arm, pose_from(np.array([3.0, 0.0, 0.0]), np.eye(3)), "+++")
    with pytest.raises(ValueError, match=r"S-R-S|7 joints"):
        joint_extrema(planar_arm(), pose, "+++")
