"""The displacement bound of the collision-free sets of the Franka class and of nearly S-R-S arms
(``redkin.collision.joint_motion``): the module docstring's sums, written here as loops over capsules, pairs and
joints, and the same bits for a batch of joint bounds as for each row alone (the sets of a batch of intervals must
not depend on which intervals share a call).  That the bound holds along the self-motion is
tests/test_collision_free_q7.py's and tests/test_collision_free_nearly.py's."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import redkin
from redkin.collision import builtin_body, scene_of
from redkin.collision.clearance import checked_pairs
from redkin.collision.joint_motion import _joint_levers, pair_displacements, pair_levers

CELL = {"margin": 0.01, "obstacles": [
    {"name": "post", "type": "capsule", "a": [0.45, 0.25, -0.2], "b": [0.45, 0.25, 1.2], "radius": 0.05},
    {"name": "lamp", "type": "sphere", "center": [0.2, -0.4, 0.8], "radius": 0.12}]}


@pytest.fixture(scope="module", params=["franka-panda", "kinova-gen3"])
def setting(request):
    arm = redkin.arm(request.param)
    body = builtin_body(request.param, arm.chain)
    pairs = checked_pairs(body, scene_of(CELL))
    return arm.chain, body, pairs, pair_levers(arm.chain, body, pairs)


def _looped(delta: np.ndarray, chain, body, pairs) -> np.ndarray:
    """The module docstring's bound, one pair and one joint at a time: a capsule on frame ``k`` moves by at most the
    smaller of ``sum_{j <= k} delta_j L_j`` and ``sum_{j > k} delta_j L'_j``; two capsules on frames ``k1``, ``k2`` by
    at most the smaller of the sum of their moves and the levers of joints ``min(k1, k2) + 1 .. max(k1, k2)`` from
    either link (base side from the outer, tip side from the inner)."""
    base, tip = _joint_levers(chain, body)
    shift = np.empty(len(body))
    for c in range(len(body)):
        below = above = 0.0
        for j in range(chain.n):
            below += delta[j] * base[c, j]
            above += delta[j] * tip[c, j]
        shift[c] = np.minimum(below, above)  # nan wins, as in numpy
    total = np.empty(len(pairs.capsule))
    for p, (first, second) in enumerate(zip(pairs.capsule, pairs.other)):
        if second < 0:  # against an obstacle
            total[p] = shift[first]
            continue
        k1, k2 = body.frame[first], body.frame[second]
        outer, inner = (first, second) if k1 >= k2 else (second, first)
        from_outer = from_inner = 0.0
        for j in range(min(k1, k2), max(k1, k2)):  # joints min + 1 .. max, counted from 1
            from_outer += delta[j] * base[outer, j]
            from_inner += delta[j] * tip[inner, j]
        total[p] = np.minimum(np.minimum(from_outer, from_inner), shift[first] + shift[second])
    return total


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**31), rows=st.integers(1, 40), unbounded=st.booleans())
def test_the_bound_is_the_documented_sums_and_a_batch_gives_each_row_s_bits(setting, seed, rows, unbounded):
    chain, body, pairs, levers = setting
    assert (pairs.other >= 0).any() and (pairs.other < 0).any()  # self pairs and obstacle pairs both checked
    rng = np.random.default_rng(seed)
    delta = rng.uniform(0.0, 0.5, (rows, chain.n)) * (rng.random((rows, chain.n)) < 0.8)
    if unbounded:  # a joint not bounded: the bound of every pair that joint moves is infinite (or nan: 0 * inf)
        delta[rng.integers(rows), rng.integers(chain.n)] = np.inf
    with np.errstate(invalid="ignore"):
        batch = pair_displacements(delta, levers)
        assert batch.shape == (rows, len(pairs.capsule))
        for r in range(rows):
            alone = pair_displacements(delta[r:r + 1], levers)[0]
            np.testing.assert_array_equal(alone, batch[r])
            looped = _looped(delta[r], chain, body, pairs)
            np.testing.assert_array_equal(np.isnan(looped), np.isnan(batch[r]))
            np.testing.assert_allclose(batch[r], looped, rtol=1e-14, atol=0.0)
