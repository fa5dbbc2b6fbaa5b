"""The compiled feasible sets (redkin.srs._feasible_kernels): a batch equals its items one at a time, on any thread
count.

Laws: a batch split into chunks on the thread pool (>= 256 poses) gives bit
for bit what one call per pose gives; so do 1, 2 and 3 threads; the eight branches of one pose at once equal each branch
alone; the closed-form roots are roots.
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from redkin import _compiled
from redkin._compiled import PARALLEL_BATCH, set_threads
from redkin.models import kuka_iiwa14, pa10_7c
from redkin.srs import BRANCHES, feasible_arm_angles, feasible_arm_angles_batch, feasible_pieces
from redkin.srs._feasible_kernels import sinusoid_roots
from redkin.srs.feasible import feasible_pieces_all_branches
from tests.support.srs_arms import random_poses

COUNT = 2 * PARALLEL_BATCH + 37  # several chunks on the thread pool, of unequal sizes


def poses_of(chain, count, seed):
    """Reachable poses of ``chain`` from random joint values (some with theta_2 or theta_6 at 0: stretched groups)."""
    return random_poses(chain, count, np.random.default_rng(seed), stretched=True)


def arms():
    """The PA10 with its own limits and the iiwa (branch senses flipped) with limits across +-pi."""
    iiwa = kuka_iiwa14()
    return [pa10_7c(), iiwa.with_limits(np.full(7, np.pi - 2.0), np.full(7, np.pi + 2.0))]


@pytest.mark.parametrize("chain", arms(), ids=["pa10", "iiwa-crossing"])
@pytest.mark.parametrize("branch", ["+++", "-+-", "+--"])
def test_a_batch_equals_single_calls_bit_for_bit(chain, branch):
    poses = poses_of(chain, COUNT, 1)
    batch = feasible_pieces(chain, poses, branch)
    assert batch.start.shape == (COUNT, 24)
    for i in range(COUNT):
        alone = feasible_pieces(chain, poses[i], branch)
        np.testing.assert_array_equal(alone.start, batch.start[i])
        np.testing.assert_array_equal(alone.end, batch.end[i])
        np.testing.assert_array_equal(alone.feasible, batch.feasible[i])
    sets = feasible_arm_angles_batch(chain, poses[:PARALLEL_BATCH], branch)  # per-joint rows on the pool too
    for i in range(0, PARALLEL_BATCH, 17):
        single = feasible_arm_angles(chain, poses[i], branch)
        assert single.feasible == sets[i].feasible == batch.arc_set((i,))
        assert all(single.per_joint[j] == sets[i].per_joint[j] for j in range(1, 8))


def test_results_do_not_depend_on_the_thread_count(monkeypatch):
    monkeypatch.setattr(_compiled, "POOL_SECONDS", 0.0)  # on the pool however short the batch
    chain = pa10_7c()
    poses = poses_of(chain, COUNT, 2)
    results = []
    try:
        for count in (1, 2, 3):
            set_threads(count)
            pieces = feasible_pieces(chain, poses, "+-+")
            every = feasible_pieces_all_branches(chain, poses)
            results.append((pieces.start, pieces.end, pieces.feasible, every.start, every.end, every.feasible))
    finally:
        set_threads(None)
    for other in results[1:]:
        for first, same in zip(results[0], other):
            np.testing.assert_array_equal(first, same)


@pytest.mark.parametrize("chain", arms(), ids=["pa10", "iiwa-crossing"])
def test_all_branches_at_once_equal_each_branch_alone(chain):
    """The cuts of each elbow sign serve its four branches; the slots follow BRANCHES in the chain's senses."""
    poses = poses_of(chain, COUNT, 3).reshape(COUNT, 1, 4, 4)  # batch shapes are kept
    every = feasible_pieces_all_branches(chain, poses)
    assert every.start.shape == (COUNT, 1, 8, 24)
    for k, branch in enumerate(BRANCHES):
        alone = feasible_pieces(chain, poses, branch)
        np.testing.assert_array_equal(every.start[..., k, :], alone.start)
        np.testing.assert_array_equal(every.end[..., k, :], alone.end)
        np.testing.assert_array_equal(every.feasible[..., k, :], alone.feasible)
    one = feasible_pieces_all_branches(chain, poses[0, 0])
    assert one.start.shape == (8, 24)
    assert [one.arc_set((k,)) for k in range(8)] == [every.arc_set((0, 0, k)) for k in range(8)]


def test_all_branches_reject_bad_input_like_one_branch():
    chain = pa10_7c()
    with pytest.raises(ValueError, match="pose must have shape"):
        feasible_pieces_all_branches(chain, np.eye(3))
    far = np.eye(4)
    far[0, 3] = 5.0
    with pytest.raises(ValueError, match="unreachable"):
        feasible_pieces_all_branches(chain, far)
    assert feasible_pieces_all_branches(chain, np.zeros((0, 4, 4))).start.shape == (0, 8, 24)


@settings(max_examples=200, deadline=None)
@given(st.floats(-10, 10), st.floats(-10, 10), st.floats(-15, 15))
def test_sinusoid_roots_are_roots_in_range(p, q, r):
    """p sin psi + q cos psi + r = 0 at both roots, which lie in [-pi, pi]; NaN exactly where |r| > hypot(p, q)."""
    first, second = sinusoid_roots(p, q, r)
    rho = np.hypot(p, q)
    if np.isnan(first):
        assert np.isnan(second) and (abs(r) > rho * (1 + 1e-12) or rho <= 1e-12)
        return
    for psi in (first, second):
        assert -np.pi <= psi <= np.pi
        assert abs(p * np.sin(psi) + q * np.cos(psi) + r) <= 1e-9 * max(1.0, rho)


@settings(max_examples=60, deadline=None)
@given(widths=st.lists(st.tuples(st.floats(1e-3, 0.3), st.floats(0.0, 0.2), st.booleans()), min_size=1,
                       max_size=30),
       start=st.floats(-np.pi, 0.0))
def test_an_arc_set_of_pieces_with_gaps_keeps_the_gaps(widths, start):
    """``FeasiblePieces.arc_set`` on any number of sorted pieces, touching or with gaps between them (a nearly S-R-S,
    Franka-class or cell family's pieces; it read exactly 24 touching ones): the union of the kept pieces, a gap
    ending a run (it was joined over), each piece wider than the runs' tolerance."""
    from redkin.circle import ArcSet
    from redkin.srs.feasible import FeasiblePieces

    lo, hi, kept, at = [], [], [], start
    for width, gap, keep in widths:
        lo.append(at)
        hi.append(at + width)
        kept.append(keep)
        at += width + gap
    if at - start > 2 * np.pi - 1e-3:
        return  # the pieces must fit on the circle once
    pieces = FeasiblePieces(np.array(lo), np.array(hi), np.array(kept))
    expected = ArcSet([(a, b) for a, b, keep in zip(lo, hi, kept) if keep])
    assert pieces.arc_set().isclose(expected, 1e-12)
