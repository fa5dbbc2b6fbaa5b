"""The limit-avoiding arm angle of nearly S-R-S arms on the real arm (:mod:`redkin.srs.nearly_optimal`).

Laws, on the Kinova Gen3 (its joints limited to +-2.9 rad so that feasible sets have ends), the Jaco2 and the
ROS-Industrial iiwa:

- **no sample beats it**: of 20 000 arm angles, none where the branch has a certified solution has a larger
  objective ([000 eqs. 36, 38, 40], computed here from the neighbour's shoulder and wrist frames) than the unclamped
  optimum by more than :data:`ALLOWANCE`, and none inside the real feasible set more than the clamped optimum;
- **inside**: the clamped optimum lies in the feasible set (1e-9 rad) and the branch has a certified solution there;
  it is the unclamped one where that is inside;
- an empty feasible set has no clamped optimum; bad input raises ValueError.

The search is only as good as the solutions it is given: the laws are stated for poses where
:func:`redkin.srs.nearly.ik` finds the branch at 99 % of the sampled arm angles or more (on 100 random poses x 8
branches: all of the Jaco2's, 99.0 % of the Gen3's, 99.5 % of the ROS-I iiwa's) on one sheet (no joint steps by
more than :data:`SHEET_JUMP` between neighbouring samples); elsewhere (the stretched elbow, the wrist near axis 1,
the shoulder near ``theta_2 = 0``) the branch's solutions come from several sheets, with gaps or jumps between
them, and a sample of another sheet can beat the optimum found on the best sample's sheet (the Gen3's seed 0,
branch ``--+``: the weighted objective's supremum lies where the returned solution jumps from one sheet to another,
at psi = 0, and is attained by neither).
"""

from __future__ import annotations

import functools
from pathlib import Path

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import redkin
from redkin.circle import ArcSet
from redkin.srs import BRANCHES, feasible_arm_angles_nearly, nearly_srs
from redkin.srs.nearly import NearlySRS
from redkin.srs.nearly_optimal import optimal_arm_angles_nearly
from redkin.srs.nearly_search import solutions_at

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
#: How much a sampled arm angle may beat the optimum in the objective (which spans [-1, 3]): the bisection's
#: 1e-10 rad times the objective's slope, and the certificate's 1e-9 in the joint values.
ALLOWANCE = 1e-9
PARTS = ("shoulder", "wrist", "overall")
#: A joint step [rad] between neighbouring samples of the dense grid (3e-4 rad apart) that marks a jump from one
#: sheet of the branch's solutions to another.
SHEET_JUMP = 0.5


@functools.cache
def _arm(name: str) -> NearlySRS:
    if name == "gen3":
        chain = redkin.get_robot("kinova-gen3")
        return nearly_srs(chain.with_limits(np.full(7, -2.9), np.full(7, 2.9)))
    pytest.importorskip("urdf_parser_py", reason="the urdf extra (urdfdom-py) is not installed")
    from redkin.urdf import load_urdf

    return nearly_srs(load_urdf(EXAMPLES / ("jaco2.urdf" if name == "jaco2" else "iiwa14_rosi.urdf")))


def _objectives(arm: NearlySRS, q: np.ndarray, target: np.ndarray, weights) -> np.ndarray:
    """[000 eqs. 36, 38, 40] at ``q`` (M, 7): traces of the neighbour's shoulder and wrist rotations against the
    target's, written here from the frames."""
    frames = arm.geometry.chain.frames(np.concatenate([q, target[None]]))[..., :3, :3]
    shoulder = np.swapaxes(frames[:, 0], -1, -2) @ frames[:, 3]
    wrist = np.swapaxes(frames[:, 4], -1, -2) @ frames[:, 7]
    f_s = np.einsum("mij,ij->m", shoulder[:-1], shoulder[-1])
    f_w = np.einsum("mij,ij->m", wrist[:-1], wrist[-1])
    r_s, r_w = weights
    return np.stack([f_s, f_w, (r_s * f_s + r_w * f_w) / max(r_s, r_w)])


def _at(arm: NearlySRS, pose: np.ndarray, psi: float, branch, target, weights) -> np.ndarray:
    q, exists = solutions_at(arm, pose, np.array([psi]), branch)
    assert exists[0]
    return _objectives(arm, q, target, weights)[:, 0]


def _random_pose(arm: NearlySRS, rng: np.random.Generator) -> np.ndarray:
    lower = np.where(np.isfinite(arm.chain.lower), arm.chain.lower, -np.pi)
    upper = np.where(np.isfinite(arm.chain.upper), arm.chain.upper, np.pi)
    return arm.chain.fk(rng.uniform(lower, upper))


def _check(arm: NearlySRS, pose: np.ndarray, branch, weights=(0.5, 0.5), target=None) -> int | None:
    """The laws of the module docstring for one pose and branch; how many clamped optima were checked (``None`` for
    a pose where the branch is found at fewer than 99 % of the sampled arm angles)."""
    feasible = feasible_arm_angles_nearly(arm, pose, branch).feasible
    result = optimal_arm_angles_nearly(arm, pose, branch, target=target, weights=weights, feasible=feasible)
    dense = np.linspace(-np.pi, np.pi, 20_000, endpoint=False)
    q, exists = solutions_at(arm, pose, dense, result.branch)
    step = np.abs(np.angle(np.exp(1j * (np.roll(q, -1, axis=0) - q)))).max(axis=1)[exists & np.roll(exists, -1)]
    if exists.mean() < 0.99 or step.max(initial=0.0) > SHEET_JUMP:
        return None
    values = np.where(exists, _objectives(arm, q, result.target, result.weights), -np.inf)
    inside = exists & np.asarray(feasible.contains(dense))
    checked = 0
    for k, part in enumerate(PARTS):
        optimum = getattr(result, part)
        if not exists.any():
            assert np.isnan(optimum.unclamped) and optimum.feasible is None
            continue
        assert _at(arm, pose, optimum.unclamped, result.branch, result.target, result.weights)[k] >= \
            values[k].max() - ALLOWANCE
        if feasible.is_empty:
            assert optimum.feasible is None
            continue
        assert optimum.feasible is not None and feasible.contains(optimum.feasible, 1e-9)
        if feasible.contains(optimum.unclamped):
            assert optimum.feasible == optimum.unclamped
        if inside.any():
            assert _at(arm, pose, optimum.feasible, result.branch, result.target, result.weights)[k] >= \
                values[k][inside].max() - ALLOWANCE
            checked += 1
    return checked


@pytest.mark.parametrize("name", ["gen3", "jaco2", "rosi"])
@settings(max_examples=4, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), branch=st.sampled_from(BRANCHES))
def test_no_sampled_arm_angle_beats_the_optimum(name, seed, branch):
    arm = _arm(name)
    assume(_check(arm, _random_pose(arm, np.random.default_rng(seed)), branch) is not None)


def test_clamped_optima_are_checked_with_other_weights_and_targets():
    arm = _arm("gen3")
    rng = np.random.default_rng(7)
    checked = 0
    for weights in ((1.0, 0.0), (0.2, 0.8)):
        for _ in range(3):
            checked += _check(arm, _random_pose(arm, rng), "+-+", weights, rng.uniform(-1.0, 1.0, 7)) or 0
    assert checked >= 9  # the set is neither empty nor left out: the clamp itself was compared with samples


def test_an_empty_feasible_set_has_no_clamped_optimum():
    arm = _arm("gen3")
    pose = _random_pose(arm, np.random.default_rng(1))
    result = optimal_arm_angles_nearly(arm, pose, "+++", feasible=ArcSet.empty())
    assert all(getattr(result, part).feasible is None for part in PARTS)
    assert all(np.isfinite(getattr(result, part).unclamped) for part in PARTS)


@pytest.mark.parametrize("kwargs", [{"pose": np.full((4, 4), np.nan)}, {"branch": "++"}, {"target": np.zeros(6)},
                                    {"weights": (0.0, 0.0)}, {"weights": (-1.0, 1.0)}])
def test_bad_input_raises_value_error(kwargs):
    arguments = {"pose": np.eye(4), "branch": "+++", "feasible": ArcSet.full()} | kwargs
    with pytest.raises(ValueError):
        optimal_arm_angles_nearly(_arm("gen3"), **arguments)
