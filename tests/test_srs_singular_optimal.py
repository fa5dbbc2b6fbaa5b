"""Singular arm angles ([000 eqs. 31-34], theta = 0 and pi), optimal arm angles ([000 eqs. 36-40]), path control
(section 6.2.2) and paper section 6.2."""

from pathlib import Path

import numpy as np
import pytest

from redkin.circle import ArcSet
from redkin.models import barrett_wam, pa10_7c
from redkin.reproduce import printed
from redkin.srs import (
    arm_angle_of,
    arm_angle_path,
    feasible_arm_angles,
    ik,
    optimal_arm_angles,
    pose_from,
    singular_arm_angles,
)
from tests.support.srs_arms import shoulder_rotation, wrist_rotation

GRID = np.linspace(-np.pi, np.pi, 20001, endpoint=False)


def branch_string(state):
    return str(state.branch_strings())


@pytest.mark.parametrize(
    "q, joint",
    [
        ([0.3, 0.0, 0.5, 0.9, 0.2, 0.4, 0.1], 2),  # shoulder singular
        ([0.3, 0.7, 0.5, 0.9, 0.2, 0.0, 0.1], 6),  # wrist singular
        ([0.0, 0.0, 0.0, -1.0, 0.2, 0.4, 0.1], 2),  # shoulder singular at psi = +-pi (reference flips)
        ([0.0, -0.6, 0.0, -1.0, 0.2, 0.0, 0.1], 6),  # wrist singular at psi = +-pi
    ],
)
def test_singular_arm_angle_is_found_where_the_configuration_is(q, joint):
    chain = pa10_7c().with_limits(np.full(7, -4.0), np.full(7, 4.0))
    q = np.array(q)
    state = arm_angle_of(chain, q)
    result = singular_arm_angles(chain, chain.fk(q), branch_string(state))
    angles = result.shoulder if joint == 2 else result.wrist
    assert len(angles) == 1 and np.cos(angles[0] - state.psi) == pytest.approx(1.0, abs=1e-12)
    theta = ik(chain, chain.fk(q), angles[0], branch_string(state))
    assert abs(np.sin(theta[joint - 1])) < 1e-7
    if q[0] == 0.0 and q[2] == 0.0:
        assert abs(abs(angles[0]) - np.pi) < 1e-9


@pytest.mark.parametrize("name", ["gen3.urdf", "jaco2.urdf", "iiwa14_rosi.urdf"])
@pytest.mark.parametrize("joint", [1, 5])
@pytest.mark.parametrize("value", [0.0, np.pi])
def test_a_pair_on_one_line_in_the_users_joint_values_is_singular(name, joint, value):
    """Exact S-R-S arms whose zero pose is ``theta = pi`` of the Table 1 form: the neighbours of the examples' arms,
    in the user's joint values (the Gen3's ``q_2 = 0`` and ``q_6 = 0`` are ``theta = pi``, the Jaco2's and the
    iiwa's ``theta = 0``).  At ``q_2`` (``q_6``) = 0 or pi axes 1 and 3 (5 and 7) lie on one line, parallel or
    antiparallel, by the chain's own frames; [000 eqs. 31-34] with their ``theta = pi`` counterpart give the
    configuration's arm angle, and the solution at every singular arm angle has the pair on one line."""
    from redkin.srs import nearly_srs
    from redkin.urdf import load_urdf

    chain = nearly_srs(load_urdf(Path(__file__).resolve().parents[1] / "src" / "redkin" / "examples" / name)).neighbour
    first, second = (0, 2) if joint == 1 else (4, 6)

    def off_line(q):  # the sine of the angle between the pair's axes (standard DH: joint k turns about z_(k-1))
        frames = chain.frames(q)
        return np.linalg.norm(np.cross(frames[first, :3, 2], frames[second, :3, 2]))

    rng = np.random.default_rng(7)
    for _ in range(5):
        q = rng.uniform(-2.5, 2.5, 7)
        q[joint] = value
        assert off_line(q) < 1e-12
        state = arm_angle_of(chain, q)
        pose = chain.fk(q)
        result = singular_arm_angles(chain, pose, branch_string(state))
        angles = np.array(result.shoulder if joint == 1 else result.wrist)
        assert angles.size and np.abs(np.angle(np.exp(1j * (angles - state.psi)))).min() < 1e-9
        for psi in angles:
            assert off_line(ik(chain, pose, psi, branch_string(state))) < 1e-7


def test_no_singularity_for_generic_pose_and_degenerate_everywhere_case():
    chain = pa10_7c()
    q = np.array([0.3, 0.7, 0.5, 0.9, 0.2, 0.4, 0.1])
    result = singular_arm_angles(chain, chain.fk(q), "+++")
    assert result.shoulder == () and result.wrist == () and result.shoulder_residual < 0
    # sampled check: theta_2 and theta_6 stay away from 0 on the whole circle
    theta = ik(chain, np.broadcast_to(chain.fk(q), GRID.shape + (4, 4)), GRID, "+++")
    assert np.min(np.abs(theta[:, 1])) > 1e-3 and np.min(np.abs(theta[:, 5])) > 1e-3
    # arm stretched along the joint-1 axis: every arm angle is shoulder singular
    stretched = chain.fk(np.array([0.0, 0.0, 0.0, 0.0, 0.3, 0.5, 0.0]))
    everywhere = singular_arm_angles(chain, stretched, "+++")
    assert everywhere.shoulder_everywhere
    with pytest.raises(ValueError, match="tolerance"):
        singular_arm_angles(chain, stretched, "+++", tolerance=-1.0)


def test_paper_section_6_2_1_singularity_coefficients_and_branch():
    chain = pa10_7c()
    pose = pose_from(np.array([0.55, 0.0, 0.767]), np.array([[0, 0, 1], [0, 1, 0], [-1, 0, 0.0]]))
    result = singular_arm_angles(chain, pose, "+++")
    assert np.allclose(result.shoulder_coefficients, printed.SECTION_6_2_1_SHOULDER_COEFFICIENTS, atol=5e-4)
    assert np.allclose(result.wrist_coefficients, printed.SECTION_6_2_1_WRIST_COEFFICIENTS, atol=5e-4)
    assert np.allclose(result.shoulder, [0.0]) and np.allclose(result.wrist, [0.0])
    # the printed feasible set [-63.277, 63.277] belongs to branch ++- (theta_6 < 0); +++ is empty
    assert feasible_arm_angles(chain, pose, "+++").is_empty
    other = feasible_arm_angles(chain, pose, "++-").feasible
    bound = printed.SECTION_6_2_1_PSI_BOUND
    assert np.allclose(np.degrees(other.arcs), [[-bound, bound]], atol=5e-4)


def objective(chain, pose, branch, target, psi, part):
    theta = ik(chain, np.broadcast_to(pose, psi.shape + (4, 4)), psi, branch)
    if part == "shoulder":
        return np.einsum("...ij,ij->...", shoulder_rotation(theta), shoulder_rotation(target))
    return np.einsum("...ij,ij->...", wrist_rotation(theta), wrist_rotation(target))


WAM_LIMITED = barrett_wam().with_limits(np.radians([-150, -113, -157, -50, -270, -90, -172]),
                                        np.radians([150, 113, 157, 180, 70, 90, 172]))


@pytest.mark.parametrize("chain", [pa10_7c(), WAM_LIMITED], ids=["pa10", "wam"])
def test_optimal_angles_are_the_sampled_maximisers_and_clamp_to_nearest_feasible(chain):
    rng = np.random.default_rng(11)
    for _ in range(5):
        q = rng.uniform(-0.8, 0.8, 7) + [0, 0, 0, 1.2, 0, 0, 0]
        pose = chain.fk(q)
        target = rng.uniform(-1, 1, 7)
        result = optimal_arm_angles(chain, pose, "+++", target=target, weights=(0.3, 0.7))
        for part in ("shoulder", "wrist"):
            f = objective(chain, pose, "+++", target, GRID, part)
            best = GRID[np.argmax(f)]
            assert abs(np.sin((getattr(result, part).unclamped - best) / 2)) < 1e-3
        f = (0.3 * objective(chain, pose, "+++", target, GRID, "shoulder")
             + 0.7 * objective(chain, pose, "+++", target, GRID, "wrist"))
        assert abs(np.sin((result.overall.unclamped - GRID[np.argmax(f)]) / 2)) < 1e-3
        feasible = feasible_arm_angles(chain, pose, "+++").feasible
        if feasible.is_empty:
            assert result.overall.feasible is None
        else:
            assert feasible.contains(result.overall.feasible, tolerance=1e-12)
            inside = feasible.contains(GRID)
            at = np.array([result.overall.feasible])
            f_at = (0.3 * objective(chain, pose, "+++", target, at, "shoulder")
                    + 0.7 * objective(chain, pose, "+++", target, at, "wrist"))
            assert np.max(f[inside]) <= f_at[0] + 1e-9


def test_paper_section_6_2_2_optimal_angles_and_joint_vector():
    chain = pa10_7c()
    pose = pose_from(np.array([0.65, 0.0, 0.5]), np.array([[0, -1, 0], [-1, 0, 0], [0, 0, -1.0]]))
    target = np.radians([0, 90, 0, 0, 0, 90, 0])
    result = optimal_arm_angles(chain, pose, "+++", target=target, weights=(0.5, 0.5))
    assert np.degrees(result.shoulder.unclamped) == pytest.approx(printed.SECTION_6_2_2_SHOULDER_OPTIMUM, abs=5e-4)
    assert np.degrees(result.wrist.unclamped) == pytest.approx(printed.SECTION_6_2_2_WRIST_OPTIMUM, abs=5e-4)
    assert np.degrees(result.overall.unclamped) == pytest.approx(printed.SECTION_6_2_2_OPTIMUM, abs=5e-4)
    theta = np.degrees(ik(chain, pose, result.overall.feasible, "+++"))
    assert np.allclose(theta, printed.SECTION_6_2_2_THETA_AT_OPTIMUM, atol=5e-4)
    assert np.allclose(np.degrees(ik(chain, pose, 0.0, "+++")), printed.SECTION_6_2_2_THETA_AT_ZERO, atol=5e-4)
    # our feasible set is [-45.991, 45.991] (the paper prints [-43.246, 43.246]); psi_w clamps to its end
    feasible = feasible_arm_angles(chain, pose, "+++").feasible
    bound = printed.SECTION_6_1_PSI_BOUND  # the paper's own 6.1 bound: its 6.2.2 set is a misprint
    assert np.allclose(np.degrees(feasible.arcs), [[-bound, bound]], atol=5e-4)
    assert np.degrees(result.wrist.feasible) == pytest.approx(bound, abs=5e-4)
    # the default targets (limit midpoints) give other optima
    default = optimal_arm_angles(chain, pose, "+++")
    assert abs(np.degrees(default.overall.unclamped) - printed.SECTION_6_2_2_OPTIMUM) > 1.0


def gamma_pose(gamma):
    rotation = np.array([[-np.cos(gamma), -np.sin(gamma), 0], [-np.sin(gamma), np.cos(gamma), 0], [0, 0, -1.0]])
    return pose_from(np.array([0.65, 0.0, 0.5]), rotation)


def test_path_control_reaches_further_than_fixed_psi():
    chain = pa10_7c()
    gammas = np.radians(np.arange(0.0, 180.0, 1.0))
    poses = np.array([gamma_pose(g) for g in gammas])
    target = np.radians([0, 90, 0, 0, 0, 90, 0])
    fixed = arm_angle_path(chain, poses, "+++", fixed_psi=0.0)
    controlled = arm_angle_path(chain, poses, "+++", target=target)
    # the first whole degree beyond Gamma_0 = [-120, 120] and beyond Gamma = [-147.693, 147.693]
    assert np.degrees(gammas[fixed.first_unreachable]) == pytest.approx(np.floor(printed.SECTION_6_2_2_GAMMA_FIXED) + 1)
    assert np.degrees(gammas[controlled.first_unreachable]) == pytest.approx(np.ceil(printed.SECTION_6_2_2_GAMMA))
    ok = controlled.reachable
    assert np.all(chain.within_limits(controlled.q[ok], tolerance=1e-9, wrap=True))
    assert np.abs(chain.fk(controlled.q) - poses).max() < 1e-9
    assert fixed.q.shape == (180, 7) and np.all(fixed.psi == 0.0)


def test_optimal_bad_inputs():
    chain = pa10_7c()
    pose = gamma_pose(0.0)
    with pytest.raises(ValueError, match="weights"):
        optimal_arm_angles(chain, pose, weights=(0.0, 0.0))
    with pytest.raises(ValueError, match="target"):
        optimal_arm_angles(chain, pose, target=[0.0] * 6)
    with pytest.raises(ValueError, match="pose"):
        optimal_arm_angles(chain, np.stack([pose, pose]))
    assert optimal_arm_angles(chain, pose, feasible=ArcSet.empty()).overall.feasible is None


def test_huge_weights_give_the_optimum_of_their_ratio():
    """[000 eq. 40] depends on the weights' ratio only: (1e308, 1e308) is (0.5, 0.5), without overflow."""
    import warnings

    from redkin.models import pa10_7c
    from redkin.srs import optimal_arm_angles

    chain = pa10_7c()
    pose = chain.fk(np.radians([10.0, 30.0, 0.0, 60.0, 0.0, 45.0, 0.0]))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        huge = optimal_arm_angles(chain, pose, "+++", weights=(1e308, 1e308))
    plain = optimal_arm_angles(chain, pose, "+++", weights=(0.5, 0.5))
    assert huge.overall == plain.overall
