"""The limit-avoiding arm angle of nearly S-R-S arms, read off the certified self-motion
(:mod:`redkin.srs.nearly.optimal`).

Laws, on the Kinova Gen3 (``examples/gen3.urdf``) and Jaco2 (continuous joints limited to +-2.9 rad) and the
ROS-Industrial iiwa, at random poses and at poses within 1e-6..1e-3 rad of a straight wrist or shoulder (``q6`` or
``q2`` in the user's joint values), for the configuration's own branch and a drawn one:

- **the optimum is a certified solution**: each optimum's configuration reaches the pose (our FK, 1e-9 m and rad),
  has the optimum's arm angle (:func:`redkin.srs.nearly.arm_angle`, 1e-9 rad) and lies on the branch
  (:func:`redkin.srs.nearly.branch_of`); the clamped one lies within the limits (``within_limits``) at an arm angle
  of the feasible set (1e-9 rad), and is worth the unclamped one where that lies within the limits in the set;
- **no certified solution beats it**: the branch's certified solutions, :func:`redkin.srs.nearly.ik`'s rows at
  20 000 arm angles and every solution :func:`redkin.srs.branch_solutions` gives at 8 arm angles and at the optima's
  own (both where the branch has two), each taken onto the self-motion (:func:`_onto_the_self_motion`), have no
  objective ([000 eqs. 36, 38, 40], written here from the chain's frames) larger than the unclamped optimum's by
  more than :data:`ALLOWANCE`, nor those within the limits at arm angles of the feasible set than the clamped
  one's;
- a narrower feasible set given by the caller clamps to it, its ends within steps included; an empty one leaves no
  clamped optimum; a pose out of reach has no optimum;
- given curves give what the curves followed inside give; curves that did not close say the result may be
  incomplete;
- the objectives' derivative along the self-motion equals central differences;
- bad input raises ValueError.

The laws are stated where the self-motion was followed whole (:attr:`NearlyOptimal.complete`).
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from redkin.circle import ArcSet
from redkin.srs import BRANCHES, branch_solutions
from redkin.srs._rotations import group_rotations
from redkin.srs.nearly import NearlySRS, arm_angle, branch_of, ik
from redkin.srs.nearly.optimal import _objectives, optimal_arm_angles_nearly
from redkin.srs.nearly.self_motion import whole_self_motion
from tests.test_srs_nearly_feasible import _arm
from tests.test_srs_nearly_self_motion import _configuration

#: How much a solution may beat the optimum in the objective (which spans [-1, 3]): the bisection's 1e-10 rad of arc
#: times the objective's slope, and rounding.
ALLOWANCE = 1e-9
PARTS = ("shoulder", "wrist", "overall")
#: Where a configuration is drawn (:func:`tests.test_srs_nearly_self_motion._configuration`).
NEAR = ["anywhere", "straight wrist", "straight shoulder"]
#: Arm angles of nearly.ik's rows compared with the optimum.
DENSE = np.linspace(-np.pi, np.pi, 20_000, endpoint=False)


def _objectives_here(arm: NearlySRS, q: np.ndarray, target: np.ndarray, weights) -> np.ndarray:
    """[000 eqs. 36, 38, 40] at ``q`` (M, 7): traces of the neighbour's shoulder and wrist rotations against the
    target's, written here from the frames (3, M)."""
    frames = arm.geometry.chain.frames(np.concatenate([np.reshape(q, (-1, 7)), target[None]]))[..., :3, :3]
    shoulder = np.swapaxes(frames[:, 0], -1, -2) @ frames[:, 3]
    wrist = np.swapaxes(frames[:, 4], -1, -2) @ frames[:, 7]
    f_s = np.einsum("mij,ij->m", shoulder[:-1], shoulder[-1])
    f_w = np.einsum("mij,ij->m", wrist[:-1], wrist[-1])
    r_s, r_w = weights
    return np.stack([f_s, f_w, (r_s * f_s + r_w * f_w) / max(r_s, r_w)])


def _onto_the_self_motion(arm: NearlySRS, pose: np.ndarray, q: np.ndarray, row: int) -> tuple[np.ndarray, np.ndarray]:
    """Certified solutions ``q`` (M, 7) taken onto the pose's self-motion by Gauss-Newton steps on the pose (the
    pseudo-inverse of our geometric Jacobian; near a fold a row certified to 1e-9 lies up to 1e-5 rad from the
    self-motion, and its objective up to 3e-8 from the solutions'), and which of them reach it to 1e-12 on branch
    ``row``."""
    for _ in range(4):
        reached = arm.chain.fk(q)
        turn = pose[:3, :3] @ np.swapaxes(reached[:, :3, :3], -1, -2)
        error = np.concatenate([pose[:3, 3] - reached[:, :3, 3],
                                0.5 * np.stack([turn[:, 2, 1] - turn[:, 1, 2], turn[:, 0, 2] - turn[:, 2, 0],
                                                turn[:, 1, 0] - turn[:, 0, 1]], axis=-1)], axis=-1)
        q = q + np.einsum("mij,mj->mi", np.linalg.pinv(arm.chain.jacobian(q)), error)
    exact = np.abs(arm.chain.fk(q) - pose).max(axis=(-1, -2)) <= 1e-12
    return q, exact & (branch_of(arm, q) == row)


def _certified(arm: NearlySRS, pose: np.ndarray, q: np.ndarray, psi: float, row: int) -> None:
    """``q`` reaches ``pose`` (our FK), has the arm angle ``psi`` and lies on branch ``row``."""
    error = np.abs(arm.chain.fk(q) - pose)
    assert error[:3, 3].max() <= 1e-9 and error[:3, :3].max() <= 1e-9
    assert abs(np.angle(np.exp(1j * (float(arm_angle(arm, q)) - psi)))) <= 1e-9
    assert int(branch_of(arm, q)) == row


def _check(arm: NearlySRS, pose: np.ndarray, branch: str, curves, weights=(0.5, 0.5), target=None) -> int:
    """The laws of the module docstring for one pose and branch; how many clamped optima were compared with
    solutions inside the feasible set."""
    result = optimal_arm_angles_nearly(arm, pose, branch, target=target, weights=weights, curves=curves)
    row = BRANCHES.index(result.branch)
    feasible = result.feasible
    solved = ik(arm, np.broadcast_to(pose, DENSE.shape + (4, 4)), DENSE, result.branch)
    optima = [getattr(result, part) for part in PARTS]
    probes = np.concatenate([np.linspace(-np.pi, np.pi, 8, endpoint=False),
                             [value for o in optima for value in (o.unclamped, o.feasible)
                              if value is not None and np.isfinite(value)]])
    every = [branch_solutions(arm, pose, float(angle), result.branch, curves) for angle in probes]
    q, exact = _onto_the_self_motion(arm, pose, np.concatenate([solved.q[solved.exists[:, 0], 0], *every]), row)
    values = np.where(exact, _objectives_here(arm, q, result.target, result.weights), -np.inf)
    inside = exact & arm.chain.within_limits(q, wrap=True) & np.asarray(feasible.contains(arm_angle(arm, q)), bool)
    compared = 0
    for k, (part, optimum) in enumerate(zip(PARTS, optima)):
        unclamped_q, feasible_q = result.unclamped_q[part], result.feasible_q[part]
        if unclamped_q is None:
            assert np.isnan(optimum.unclamped) and optimum.feasible is None and not exact.any()
            continue
        _certified(arm, pose, unclamped_q, optimum.unclamped, row)
        best = _objectives_here(arm, unclamped_q, result.target, result.weights)[k, 0]
        assert values[k].max(initial=-np.inf) <= best + ALLOWANCE
        if optimum.feasible is None:
            assert not inside.any()
            continue
        _certified(arm, pose, feasible_q, optimum.feasible, row)
        assert arm.chain.within_limits(feasible_q)
        assert feasible.contains(optimum.feasible, 1e-9)
        clamped = _objectives_here(arm, feasible_q, result.target, result.weights)[k, 0]
        if arm.chain.within_limits(unclamped_q) and feasible.contains(optimum.unclamped):
            assert clamped >= best - ALLOWANCE  # the unclamped one where that is within the limits
        if inside.any():
            assert values[k][inside].max() <= clamped + ALLOWANCE
            compared += 1
    return compared


@pytest.mark.parametrize("name", ["gen3", "jaco2", "iiwa14-rosi"])
@settings(max_examples=5, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), near=st.sampled_from(NEAR), drawn=st.sampled_from([str(b) for b in BRANCHES]))
def test_no_certified_solution_beats_the_optimum(name, seed, near, drawn):
    arm, q = _configuration(name, seed, near)
    pose = arm.chain.fk(q)
    curves, complete = whole_self_motion(arm, pose)
    if not complete:  # the laws are stated for a self-motion followed whole
        return
    own = str(BRANCHES[int(branch_of(arm, q))])
    for branch in {own, drawn}:
        _check(arm, pose, branch, curves)


def test_clamped_optima_are_compared_with_other_weights_and_targets():
    rng = np.random.default_rng(7)
    compared = 0
    for weights in ((1.0, 0.0), (0.2, 0.8)):
        for seed in range(3):
            arm, q = _configuration("gen3", seed + 10, "anywhere")
            pose = arm.chain.fk(q)
            curves = whole_self_motion(arm, pose)[0]
            compared += _check(arm, pose, "+-+", curves, weights, rng.uniform(-1.0, 1.0, 7))
    assert compared >= 9  # the set is neither empty nor left out: the clamp itself was compared with solutions


def test_a_narrower_feasible_set_clamps_to_its_ends():
    arm, q = _configuration("gen3", 3, "anywhere")
    pose = arm.chain.fk(q)
    curves = whole_self_motion(arm, pose)[0]
    branch = str(BRANCHES[int(branch_of(arm, q))])
    whole = optimal_arm_angles_nearly(arm, pose, branch, curves=curves)
    psi = float(whole.overall.feasible)
    narrow = ArcSet([(psi + 0.05, psi + 0.3)])  # the optimum of the whole set left out: an end is the best
    result = optimal_arm_angles_nearly(arm, pose, branch, feasible=narrow, curves=curves)
    assert result.feasible is narrow
    located = result.overall
    assert located.feasible is not None and narrow.contains(located.feasible, 1e-9)
    _certified(arm, pose, result.feasible_q["overall"], located.feasible, BRANCHES.index(result.branch))
    assert arm.chain.within_limits(result.feasible_q["overall"])
    psi_dense = np.linspace(psi + 0.05, psi + 0.3, 2001)
    solved = ik(arm, np.broadcast_to(pose, psi_dense.shape + (4, 4)), np.angle(np.exp(1j * psi_dense)), branch)
    good = solved.exists[:, 0] & solved.within_limits[:, 0]
    assert good.any()
    values = _objectives_here(arm, solved.q[good, 0], result.target, result.weights)[2]
    clamped = _objectives_here(arm, result.feasible_q["overall"], result.target, result.weights)[2, 0]
    assert values.max() <= clamped + ALLOWANCE


def test_an_empty_feasible_set_has_no_clamped_optimum():
    arm, q = _configuration("gen3", 1, "anywhere")
    pose = arm.chain.fk(q)
    result = optimal_arm_angles_nearly(arm, pose, "+++", feasible=ArcSet.empty())
    assert all(getattr(result, part).feasible is None for part in PARTS)
    assert all(result.feasible_q[part] is None for part in PARTS)
    assert all(np.isfinite(getattr(result, part).unclamped) for part in PARTS)


def test_a_pose_out_of_reach_has_no_optimum():
    arm = _arm("gen3")
    pose = np.eye(4)
    pose[:3, 3] = [5.0, 0.0, 0.0]
    result = optimal_arm_angles_nearly(arm, pose, "+-+")
    assert result.feasible.is_empty and result.complete
    for part in PARTS:
        optimum = getattr(result, part)
        assert np.isnan(optimum.unclamped) and optimum.feasible is None and result.unclamped_q[part] is None


def test_given_curves_give_the_same_optima_and_say_when_incomplete():
    arm, q = _configuration("iiwa14-rosi", 2, "anywhere")
    pose = arm.chain.fk(q)
    curves, complete = whole_self_motion(arm, pose)
    inside = optimal_arm_angles_nearly(arm, pose, "-+-", weights=(0.3, 0.7))
    given_curves = optimal_arm_angles_nearly(arm, pose, "-+-", weights=(0.3, 0.7), curves=curves)
    assert complete and inside.complete and given_curves.complete
    for part in PARTS:
        assert getattr(inside, part) == getattr(given_curves, part)
    opened = tuple(curve._replace(closed=False) for curve in curves)
    assert not optimal_arm_angles_nearly(arm, pose, "-+-", curves=opened).complete


@settings(max_examples=6, deadline=None)
@given(name=st.sampled_from(["gen3", "jaco2", "iiwa14-rosi"]), seed=st.integers(0, 2**32 - 1),
       near=st.sampled_from(NEAR))
def test_the_objectives_derivative_along_the_self_motion_is_their_central_difference(name, seed, near):
    arm, q = _configuration(name, seed, near)
    rng = np.random.default_rng(seed)
    curve = whole_self_motion(arm, arm.chain.fk(q))[0][0]
    picked = rng.choice(len(curve.q), size=min(20, len(curve.q)), replace=False)
    points, tangents = curve.q[picked], curve.tangents[picked]
    goals = group_rotations(arm.geometry, rng.uniform(-1.0, 1.0, 7))
    weights = (float(rng.uniform(0.1, 1.0)), float(rng.uniform(0.1, 1.0)))
    slopes = _objectives(arm, points, tangents, goals, weights)[1]
    step = 1e-6
    central = (_objectives(arm, points + step * tangents, tangents, goals, weights)[0]
               - _objectives(arm, points - step * tangents, tangents, goals, weights)[0]) / (2.0 * step)
    np.testing.assert_allclose(slopes, central, atol=1e-8)


@pytest.mark.parametrize("kwargs", [{"pose": np.full((4, 4), np.nan)}, {"pose": np.eye(4)[None]}, {"branch": "++"},
                                    {"target": np.zeros(6)}, {"weights": (0.0, 0.0)}, {"weights": (-1.0, 1.0)},
                                    {"feasible": [(0.0, 1.0)]}, {"curves": [np.zeros((3, 7))]}])
def test_bad_input_raises_value_error(kwargs):
    arguments = {"pose": np.eye(4), "branch": "+++", "feasible": ArcSet.full()} | kwargs
    with pytest.raises(ValueError):
        optimal_arm_angles_nearly(_arm("gen3"), **arguments)


def test_curves_of_another_pose_raise_value_error():
    arm, q = _configuration("gen3", 4, "anywhere")
    curves = whole_self_motion(arm, arm.chain.fk(q))[0]
    other = arm.chain.fk(q + 0.1)
    with pytest.raises(ValueError, match="curves"):
        optimal_arm_angles_nearly(arm, other, "+++", curves=curves)
