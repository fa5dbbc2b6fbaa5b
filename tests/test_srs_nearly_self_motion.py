"""The self-motion of nearly S-R-S arms and the feasible sets read off it (:mod:`redkin.srs.nearly_self_motion`).

Laws:

- **a curve of solutions**: every point of :func:`self_motion` reaches the pose (our FK), its tangent is a unit
  vector the Jacobian maps to zero, neighbouring points lie within a step, a closed curve comes back to its start
  (modulo whole turns), and ``rates`` is the derivative of the arm angle along the tangent (central differences);
- **two solutions on one branch**: on the Kinova Gen3 pose where the elbow is near its stretch and the wrist near
  axis 1 (benchmarks/README.md, issue 27: pose 643), a branch has two certified solutions at one arm angle, one
  within the limits and one outside; the feasible set holds every arm angle where :func:`redkin.srs.nearly.ik`'s
  row is within the limits, and at every arm angle of the set a certified solution on the branch within the limits
  exists (found by Newton's steps along the curve from its points, checked with our FK, arm angle, branch and
  limits);
- ``branch_solutions`` there returns certified solutions of the branch, each once, nearly.ik's row first and one within
  the limits;
- bad input raises ValueError.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from redkin.errors import RedkinError
from redkin.srs import BRANCHES, branch_solutions, feasible_arm_angles_nearly, self_motion
from redkin.srs.branches import parse_branch
from redkin.srs.nearly import arm_angle, branch_of, ik
from tests.support.nearly_witness import witnessed
from tests.test_srs_nearly_feasible import _arm, _far_from_ends

#: The Gen3 pose with two solutions on one branch (benchmarks/README.md, issue 27, pose 643 of the sequence).
TWO_SOLUTIONS = [-0.661847496495, -0.001169086142, 1.449071562504, -0.085238499031, 2.113904835201, -0.443021865056,
                 -0.083355566602]


#: The self-motion's step [rad].
STEP = 0.05


def _wrapped(angles: np.ndarray) -> np.ndarray:
    return np.angle(np.exp(1j * angles))


@settings(max_examples=12, deadline=None)
@given(name=st.sampled_from(["gen3", "jaco2", "iiwa14-rosi"]), seed=st.integers(0, 2**32 - 1))
def test_a_self_motion_is_a_curve_of_solutions(name, seed):
    arm = _arm(name)
    q = np.random.default_rng(seed).uniform(arm.chain.lower, arm.chain.upper)
    pose = arm.chain.fk(q)
    curve = self_motion(arm, pose, q, step=STEP)
    assert len(curve.psi) > 10
    assert np.abs(arm.chain.fk(curve.q) - pose).max() < 1e-10
    np.testing.assert_allclose(np.linalg.norm(curve.tangents, axis=-1), 1.0, atol=1e-12)
    assert np.abs(np.einsum("mij,mj->mi", arm.chain.jacobian(curve.q), curve.tangents)).max() < 1e-8
    steps = np.linalg.norm(np.diff(curve.q, axis=0), axis=-1)
    assert steps.max() <= 1.01 * STEP
    if curve.closed:
        assert np.linalg.norm(_wrapped(curve.q[-1] - curve.q[0])) <= 1.01 * STEP
    np.testing.assert_allclose(arm_angle(arm, curve.q), curve.psi, atol=1e-12)
    epsilon = 1e-6
    ahead = arm_angle(arm, curve.q + epsilon * curve.tangents)
    behind = arm_angle(arm, curve.q - epsilon * curve.tangents)
    differences = _wrapped(ahead - behind) / (2.0 * epsilon)
    np.testing.assert_allclose(curve.rates, differences, atol=1e-4 * (1.0 + np.abs(differences).max()))


@pytest.mark.parametrize("branch", ["-++", "+--", "-+-"])
def test_two_solutions_on_one_branch(branch):
    arm = _arm("gen3")
    pose = arm.chain.fk(np.array(TWO_SOLUTIONS))
    feasible = feasible_arm_angles_nearly(arm, pose, branch).feasible
    psi = np.linspace(-np.pi, np.pi, 720, endpoint=False)
    far = _far_from_ends(psi, feasible)
    held = np.asarray(feasible.contains(psi))
    row = ik(arm, np.broadcast_to(pose, psi.shape + (4, 4)), psi, branch)
    assert not np.any(far & row.within_limits[:, 0] & ~held)  # every arm angle nearly.ik finds within the limits
    second = far & held & ~row.within_limits[:, 0]
    assert second.any(), "no arm angle where nearly.ik's row lies outside the limits and the set holds it any more"
    assert all(witnessed(arm, pose, branch, angle) for angle in psi[second][::7])
    for angle in psi[second][::29]:  # every solution of the branch there: nearly.ik's row and one within the limits
        solutions = branch_solutions(arm, pose, angle, branch)
        assert np.abs(arm.chain.fk(solutions) - pose).max() < 1e-9
        assert np.abs(_wrapped(arm_angle(arm, solutions) - angle)).max() < 1e-9
        assert np.all(branch_of(arm, solutions) == BRANCHES.index(parse_branch(branch)))
        assert arm.chain.within_limits(solutions, wrap=True).any()
        np.testing.assert_array_equal(solutions[0], ik(arm, pose, angle, branch).q[0])  # nearly.ik's row first
        apart = np.abs(_wrapped(solutions[:, None] - solutions[None])).max(axis=-1)
        assert np.all(apart[~np.eye(len(solutions), dtype=bool)] > 1e-5)  # each solution once


def test_bad_input():
    arm = _arm("gen3")
    q = np.array(TWO_SOLUTIONS)
    pose = arm.chain.fk(q)
    with pytest.raises(ValueError, match="does not reach the pose"):
        self_motion(arm, pose, q + 0.1)
    with pytest.raises(ValueError, match="step"):
        self_motion(arm, pose, q, step=0.0)
    with pytest.raises(ValueError, match="one joint vector"):
        self_motion(arm, pose, np.stack([q, q]))
    with pytest.raises(RedkinError, match="one \\(4, 4\\) pose"):
        self_motion(arm, np.stack([pose, pose]), q)
    with pytest.raises(ValueError, match="psi"):
        branch_solutions(arm, pose, np.nan, "+++")
    with pytest.raises(ValueError, match="branch"):
        branch_solutions(arm, pose, 0.0, "+x+")
