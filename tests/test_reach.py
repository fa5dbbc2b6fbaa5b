"""Reach bounds: a pose beyond the arm's reach (or inside its shortest) is proven so before any search.

Laws: the tool point of any joint vector lies within the links' bound of :meth:`SerialChain.reach` (standard and
modified DH, URDFs, tools); the bound is reached by a stretched S-R-S arm, so a point a few centimetres beyond is
rejected; the closed forms' own distances (the shoulder-wrist distance of S-R-S arms, of the Franka class over
every q7) hold every solution, and a pose they put out of reach has no solution at any value of the parameter; the
results of :func:`redkin.ik` and the numerical solver carry the verdict, and the solver spends one start, not its
budget, on such a pose.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import redkin
from redkin import franka, get_robot, srs
from redkin.errors import RedkinError, UnreachablePoseError
from redkin.franka import _kernels as franka_kernels
from redkin.franka.geometry import franka_geometry
from redkin.franka.ik import frames_seven
from redkin.franka.ik import reach as franka_reach
from redkin.numerical import ik as numerical_ik
from redkin.srs.geometry import pose_from
from redkin.srs.ik import reach as srs_reach

EXAMPLES = Path(__file__).resolve().parents[1] / "src" / "redkin" / "examples"
#: Arms of every description: standard DH (PA10, iiwa, Gen3, WAM, planar), modified DH (Panda, humanoid, xArm7),
#: and URDFs with base and tool transforms (the Sawyer's tool is turned and offset).
NAMES = ["pa10-7c", "kuka-iiwa14", "kinova-gen3", "barrett-wam", "planar-5", "franka-panda", "humanoid-right",
         "ufactory-xarm7", str(EXAMPLES / "sawyer.urdf"), str(EXAMPLES / "panda.urdf"), str(EXAMPLES / "gen3.urdf")]
#: An exact S-R-S arm and its rotation pointing the tool down (the PA10's tool z along its forearm when stretched).
DOWN = np.diag([1.0, -1.0, -1.0])


def _chain(name: str):
    return get_robot(name)


def _random_q(chain, rng: np.random.Generator, count: int) -> np.ndarray:
    """Joint values anywhere on the circle (the bound holds outside the limits too)."""
    return rng.uniform(-np.pi, np.pi, (count, chain.n))


# --------------------------------------------------------------------------------------------- the links' bound


@settings(max_examples=30, deadline=None)
@given(name=st.sampled_from(NAMES), seed=st.integers(0, 2**32 - 1))
def test_no_joint_vector_puts_the_tool_beyond_the_links_bound(name, seed):
    chain = _chain(name)
    centre, radius = chain.reach_bound
    q = _random_q(chain, np.random.default_rng(seed), 256)
    q[0] = 0.0  # a degenerate one: every joint at its zero
    poses = chain.fk(q)
    distance = np.linalg.norm(poses[:, :3, 3] - centre, axis=-1)
    assert np.all(distance <= radius * (1.0 + 1e-12))
    reach = chain.reach(poses)
    assert not reach.out.any() and np.array_equal(reach.distance, distance) and np.all(reach.miss == 0.0)


@pytest.mark.parametrize("name", NAMES)
def test_the_bounds_centre_lies_on_joint_1s_axis_at_every_joint_vector(name):
    chain = _chain(name)
    centre, _ = chain.reach_bound
    directions, points = chain.joint_axes(_random_q(chain, np.random.default_rng(5), 16))
    across = np.cross(centre - points[:, 0], directions[:, 0])
    assert np.abs(across).max() < 1e-12


def test_the_bound_is_reached_by_a_stretched_pa10_and_a_few_cm_beyond_is_out():
    """Stretched (q2 = q4 = q6 = 0) at any q1, q3, q5, q7, the PA10's tool is d_se + d_ew + d_wt = 1 m from the
    shoulder; 3 cm further along the arm is proven out of reach, 1 cm inside is not."""
    chain = get_robot("pa10-7c")
    centre, radius = chain.reach_bound
    assert np.allclose(centre, [0.0, 0.0, 0.317], atol=1e-15) and radius == pytest.approx(1.0, abs=1e-15)
    q = _random_q(chain, np.random.default_rng(9), 64)
    q[:, [1, 3, 5]] = 0.0
    poses = chain.fk(q)
    along = (poses[:, :3, 3] - centre) / np.linalg.norm(poses[:, :3, 3] - centre, axis=-1, keepdims=True)
    assert np.allclose(np.linalg.norm(poses[:, :3, 3] - centre, axis=-1), radius, atol=1e-12, rtol=0.0)
    for step, out in ((0.03, True), (-0.01, False)):
        moved = poses.copy()
        moved[:, :3, 3] += step * along
        reach = chain.reach(moved)
        assert np.all(reach.out == out)
        assert np.allclose(reach.miss, max(step, 0.0), atol=1e-12)


def test_a_tolerance_lets_a_target_within_it_of_the_bound_count_as_reached():
    chain = get_robot("pa10-7c")
    pose = chain.fk(np.zeros(7))
    pose[2, 3] += 5e-4  # half a millimetre beyond the stretched arm
    assert chain.reach(pose).out and not chain.reach(pose, tolerance=1e-3).out


@pytest.mark.parametrize("pose, fragment", [
    (np.eye(3), "shape"),
    (np.full((4, 4), np.nan), "finite"),
])
def test_a_malformed_pose_is_refused(pose, fragment):
    with pytest.raises(RedkinError, match=fragment):
        get_robot("pa10-7c").reach(pose)


# ---------------------------------------------------------------------------------------------------- S-R-S arms


@pytest.mark.parametrize("name", ["pa10-7c", "kuka-iiwa14", "barrett-wam"])
def test_the_shoulder_wrist_distance_of_every_solution_lies_in_the_range_and_out_is_the_closed_forms_refusal(name):
    """[000 eq. 11]: FK poses lie in ``[lower, upper]``; a pose out of reach is exactly one ``srs.ik`` refuses (on
    the WAM with its offset elbow too), whether beyond the reach or inside the shortest."""
    chain = get_robot(name)
    poses = chain.fk(_random_q(chain, np.random.default_rng(3), 200))
    reach = srs_reach(chain, poses)
    assert not reach.out.any() and reach.lower < reach.upper
    assert np.all((reach.distance >= reach.lower - 1e-9) & (reach.distance <= reach.upper + 1e-9))
    geometry = srs.srs_geometry(chain)  # its Table 1 form: frame 7 in frame 0 is base^-1 pose tool^-1
    form = geometry.chain
    for length, side in ((reach.upper + 0.05, "beyond"), (0.5 * reach.lower, "inside")):
        wrist = np.array([0.0, 0.0, geometry.d_bs]) + length * np.array([0.6, 0.0, 0.8])  # [000 eq. 4]
        frame7 = pose_from(wrist + DOWN @ [0.0, 0.0, geometry.d_wt], DOWN)
        pose = form.base @ frame7 @ form.tool
        verdict = srs_reach(chain, pose)
        assert verdict.out and verdict.distance == pytest.approx(length, abs=1e-9)
        assert verdict.miss == pytest.approx(abs(length - (reach.upper if side == "beyond" else reach.lower)),
                                             abs=1e-9)
        with pytest.raises(UnreachablePoseError):
            srs.ik(chain, pose, 0.3)
        assert not srs.reachable(chain, pose)


def test_redkin_ik_carries_the_reach_of_each_pose_and_arm_angle():
    chain = get_robot("pa10-7c")
    near = chain.fk(np.array([0.3, 0.6, -0.2, 1.1, 0.4, -0.7, 0.3]))
    far = pose_from(np.array([10.0, 0.0, 0.0]), DOWN)
    poses = np.stack([near, far])
    result = redkin.ik(chain, poses[:, None], psi=np.array([0.0, 0.1, 0.2]))
    assert result.reach.out.shape == (2, 3) and result.exists.shape == (2, 3, 8)
    assert result.reach.out.tolist() == [[False] * 3, [True] * 3]
    assert result.exists[0].all() and not result.exists[1].any() and np.all(result.q[1] == 0.0)
    assert result.reach.measure == "the shoulder-wrist distance" and result.reach.upper == pytest.approx(0.93)


# ------------------------------------------------------------------------------------------------ Franka class


def _wrist_distances(chain, pose: np.ndarray, q7: np.ndarray) -> np.ndarray:
    """``|W - S|`` at each q7 [F1]-[F2], read off the solver's own kernels."""
    geometry = franka_geometry(chain)
    t07 = frames_seven(geometry, pose)
    arm = geometry.kernel_arm
    out = []
    for theta7 in geometry.form.offset[6] + q7:
        _, _, _, w = franka_kernels.wrist_and_frame_six(t07, theta7, arm)
        out.append(np.hypot(np.hypot(w[0], w[1]), w[2] - arm[franka_kernels.D1]))
    return np.array(out)


@pytest.mark.parametrize("name", ["franka-panda", "franka-fr3", "ufactory-xarm7"])
def test_the_franka_class_distance_over_q7_is_the_circles_and_out_means_no_q7_has_a_solution(name):
    chain = get_robot(name)
    rng = np.random.default_rng(11)
    reachable = chain.fk(rng.uniform(chain.lower, chain.upper, (50, 7)))
    assert not franka_reach(chain, reachable).out.any()
    q7 = np.linspace(-np.pi, np.pi, 721)
    offsets = rng.normal(size=(40, 3))
    targets = reachable[:40].copy()
    targets[:, :3, 3] += offsets / np.linalg.norm(offsets, axis=-1, keepdims=True) * rng.uniform(0.0, 1.5, (40, 1))
    reach = franka_reach(chain, targets)
    assert reach.out.any() and not reach.out.all()
    for pose, distance, out in zip(targets, reach.distance, reach.out):
        sampled = _wrist_distances(chain, pose, q7)
        if out:  # beyond (or inside) at every q7: no branch at any sampled q7
            assert sampled.min() > reach.upper or sampled.max() < reach.lower
            assert distance == pytest.approx(sampled.min() if sampled.min() > reach.upper else sampled.max(),
                                             abs=1e-4)  # sampled every half degree of q7
            assert not franka.ik(chain, pose, q7[::20]).exists.any()
        else:  # the circle meets the range: a sampled q7 comes within the sampling's reach of it
            assert sampled.min() <= reach.upper + 1e-4 and sampled.max() >= reach.lower - 1e-4


def test_redkin_ik_at_q7_carries_the_reach():
    chain = get_robot("franka-fr3")
    far = pose_from(np.array([2.0, 0.0, 0.5]), DOWN)
    result = redkin.ik(chain, far, q7=0.5)
    assert result.reach.out and not result.exists.any()
    assert result.reach.measure == "the shoulder-wrist distance at the most favourable q7"


# ----------------------------------------------------------------------------- nearly S-R-S and the numerical solver


def test_a_nearly_srs_arm_takes_the_links_bound_and_does_not_solve_a_pose_beyond_it():
    chain = get_robot("kinova-gen3")
    near = chain.fk(np.array([0.4, 0.7, -0.3, 1.2, 0.5, -0.9, 0.2]))
    far = pose_from(np.array([2.0, 0.0, 0.5]), DOWN)
    result = redkin.ik(chain, np.stack([near, far]), psi=0.3)
    assert result.reach.out.tolist() == [False, True] and not result.exists[1].any()
    assert result.reach.upper == chain.reach_bound[1]


@pytest.mark.parametrize("name", ["kinova-gen3", "franka-panda", "planar-5"])
def test_the_numerical_solver_spends_one_start_on_a_pose_out_of_reach(name):
    chain = get_robot(name)
    q = _random_q(chain, np.random.default_rng(2), 4)
    poses = chain.fk(q)
    poses[1::2, 0, 3] += 5.0
    result = numerical_ik(chain, poses, restarts=30)
    assert result.reach.out.tolist() == [False, True, False, True]
    assert result.starts[1::2].tolist() == [1, 1] and not result.found[1::2].any()
    assert np.all(result.error[1::2, 0] >= result.reach.miss[1::2] - 1e-12)  # no joint vector comes nearer
    reference = chain.reach(poses, tolerance=1e-9)
    assert np.array_equal(result.reach.distance, reference.distance)
    assert np.array_equal(result.reach.out, reference.out)


def test_the_numerical_solver_searches_a_target_beyond_the_bound_by_less_than_its_tolerance():
    chain = get_robot("pa10-7c")
    pose = chain.fk(np.zeros(7))
    pose[2, 3] += 5e-4
    tight = numerical_ik(chain, pose, restarts=3)
    loose = numerical_ik(chain, pose, restarts=3, tolerance=(1e-3, 1e-9))
    assert tight.reach.out and tight.starts == 1
    assert not loose.reach.out and loose.starts >= 1
