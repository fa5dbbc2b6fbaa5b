"""Thesis 001 chapter 5: wrist manipulability and its maps."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from redkin.torso_arm import humanoid_arm, position_ik
from redkin.torso_arm.manipulability import (
    _wrist_jacobian_from_joints,
    _wrist_manipulability,
    gram_manipulability,
    stacked_dual_manipulability,
)
from redkin.torso_arm.maps import (
    _torso_mirror,
    best_dual_arm_map,
    best_manipulability_map,
    dual_arm_map,
    manipulability_map,
    plane_grid,
    region_above,
)


def test_torso_arm_w_independent_of_theta1():
    arm = humanoid_arm()
    rng = np.random.default_rng(0)
    q = rng.uniform(-3, 3, (200, 8))
    w = _wrist_manipulability(arm, q)
    for theta1 in (-1.2, 0.4, 2.5):
        moved = q.copy()
        moved[:, 0] = theta1
        np.testing.assert_allclose(_wrist_manipulability(arm, moved), w, rtol=1e-10, atol=1e-14)


def test_torso_arm_closed_form_jacobian_equals_chain():
    arm = humanoid_arm()
    q = np.random.default_rng(1).uniform(-3, 3, (300, 8))
    chain_jac = arm.chain.jacobian(q, frame=6)[:, :3, :5]
    ours = _wrist_jacobian_from_joints(arm, q[:, :5])
    np.testing.assert_allclose(np.abs(ours), np.abs(chain_jac), atol=1e-12)
    np.testing.assert_allclose(gram_manipulability(ours), _wrist_manipulability(arm, q), atol=1e-12)


@pytest.mark.parametrize("side", ["right", "left"])
def test_torso_arm_map_at_a_point_equals_direct_w(side):
    arm = humanoid_arm(side)
    x = 0.6 if side == "right" else -0.6
    grid = plane_grid("z=0.25", (x - 0.4, x + 0.4, -0.3, 0.6), 9)
    psi, phi = 0.3, -0.5
    result = manipulability_map(arm, grid, psi, phi, reference="vector", within_limits=False)
    sol = position_ik(arm, grid.points, psi, phi, reference="vector")
    assert np.array_equal(result.valid, sol.ok)
    assert result.valid.any()
    q = np.concatenate([sol.q, np.zeros(sol.q.shape[:-1] + (3,))], axis=-1)[sol.ok]
    direct = _wrist_manipulability(arm, q)  # (k, 4): every branch has the same w
    np.testing.assert_allclose(direct, np.broadcast_to(direct[:, :1], direct.shape), atol=1e-12)
    np.testing.assert_allclose(result.values[sol.ok], direct[:, 0], atol=1e-12)
    limited = manipulability_map(arm, grid, psi, phi, reference="vector")
    np.testing.assert_array_equal(limited.valid, sol.within_limits.any(axis=-1))


def test_torso_arm_best_map_dominates_fixed_maps():
    arm = humanoid_arm()
    grid = plane_grid("y=0.3", (0.0, 1.0, -0.5, 0.7), 8)
    best = best_manipulability_map(arm, grid, samples=(9, 12))
    for psi in (-0.5, 0.0, 0.6):
        fixed = manipulability_map(arm, grid, psi, 0.0, reference="vector")
        both = fixed.valid & best.valid
        assert np.all(best.values[both] >= fixed.values[both] - 0.02)  # coarse sweep: near or above
    assert best.valid.sum() >= 1


def test_torso_arm_dual_measure_is_stacked_jacobian():
    rng = np.random.default_rng(2)
    jr, jl = rng.normal(size=(3, 5)), rng.normal(size=(3, 5))
    full = np.zeros((6, 9))
    full[:3, 0], full[3:, 0] = jr[:, 0], jl[:, 0]
    full[:3, 1:5], full[3:, 5:] = jr[:, 1:], jl[:, 1:]
    assert stacked_dual_manipulability(jr, jl) == pytest.approx(np.prod(np.linalg.svd(full, compute_uv=False)))


def test_torso_arm_dual_map_uses_symmetric_posture_and_custom_measure():
    grid = plane_grid("z=0.3", (0.2, 0.9, -0.2, 0.6), 6)
    calls = []

    def measure(jr, jl):
        calls.append((jr.shape, jl.shape))
        return np.linalg.norm(jr, axis=(-2, -1)) - np.linalg.norm(jl, axis=(-2, -1))

    result = dual_arm_map(grid, 0.2, 0.1, reference="vector", measure=measure, within_limits=False)
    assert calls and result.valid.any()
    np.testing.assert_allclose(result.values[result.valid], 0.0, atol=1e-12)  # mirror postures: equal norms
    theta = 0.7
    p = np.array([0.3, 0.2, 0.5])
    np.testing.assert_allclose(_torso_mirror(theta, _torso_mirror(theta, p)), p, atol=1e-15)
    best = best_dual_arm_map(grid, samples=(5, 6))
    assert best.values.shape == grid.points.shape[:-1]


def test_torso_arm_region_above_threshold():
    grid = plane_grid("z=0.3", (0.0, 1.0, -0.4, 0.8), 12)
    result = manipulability_map(humanoid_arm(), grid, 0.2, 0.0, reference="vector")
    low, high = region_above(result, 0.0), region_above(result, float(np.nanmedian(result.values)))
    assert np.array_equal(low.mask, result.valid)
    assert high.area <= low.area and np.all(result.values[high.mask] >= high.threshold)
    with pytest.raises(ValueError, match="threshold"):
        region_above(result, -1.0)


def test_torso_arm_plane_grid_validates():
    with pytest.raises(ValueError, match="plane"):
        plane_grid("w=1", (0, 1, 0, 1), 5)
    with pytest.raises(ValueError, match="extent"):
        plane_grid("z=0", (1, 0, 0, 1), 5)
    with pytest.raises(ValueError, match="resolution"):
        plane_grid("z=0", (0, 1, 0, 1), 1)


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(-np.pi, np.pi), min_size=8, max_size=8), st.sampled_from(["x", "y", "z"]),
       st.sampled_from(["right", "left"]))
def test_reach_extent_holds_every_wrist_the_arm_can_reach(q, axis, side):
    """Any joint values, limits or not: the wrist lies in the default extent of the plane through it."""
    from redkin.torso_arm.geometry import WRIST_FRAME
    from redkin.torso_arm.maps import reach_extent

    arm = humanoid_arm(side)
    wrist = arm.chain.frames(np.array(q))[WRIST_FRAME, :3, 3]
    fixed = "xyz".index(axis)
    u, v = np.delete(wrist, fixed)
    u0, u1, v0, v1 = reach_extent(arm, f"{axis}={float(wrist[fixed])!r}")
    assert u0 < u < u1 and v0 < v < v1
