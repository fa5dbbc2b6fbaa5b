"""Nearly S-R-S IK continued along arm angles (:func:`redkin.srs.nearly.ik_continued`, the path graph's nodes).

Laws, on the Gen3 and the ROS-I iiwa, over sweeps of arm angle per pose and branch (random poses, and poses next to
the stretched elbow and a straight wrist):

- **the same existence and certificate as** :func:`redkin.srs.nearly.ik`: an item has a solution exactly where
  ``ik``'s row of its branch does, and every solution reaches the pose at its arm angle to 1e-9 on its own branch
  (the real arm's signs); where the branch has one solution there, it is ``ik``'s (to 1e-8 rad);
- **groups are independent**: a batch equals each group solved alone, bit for bit, on one thread or two, in any
  order of the items;
- **bad input** (shapes that do not match, a branch row outside 0-7, a NaN pose) raises ValueError.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import redkin
from redkin._compiled import set_threads
from redkin.srs import BRANCHES, nearly, nearly_srs
from tests.test_srs_nearly import CERTIFICATE, _pose_errors, _random_q, _real_branch, _rosi, _wrapped


def _arm(name: str) -> nearly.NearlySRS:
    return nearly_srs(redkin.get_robot("kinova-gen3") if name == "gen3" else _rosi())


def _sweeps(arm: nearly.NearlySRS, q: np.ndarray, count: int, spacing: float,
            rng: np.random.Generator) -> tuple[np.ndarray, ...]:
    """Items of every branch of the poses of ``q`` (P, 7): ``count`` arm angles per pose and branch from the pose's
    own, ``spacing`` apart (jittered), as the path graph's nodes lie: poses, arm angles, rows, groups."""
    poses = arm.chain.fk(q)
    own = nearly.arm_angle(arm, q)
    p, b, k = (a.ravel() for a in np.meshgrid(np.arange(len(q)), np.arange(len(BRANCHES)), np.arange(count),
                                              indexing="ij"))
    psi = _wrapped(own[p] + (k - count // 2 + rng.uniform(-0.3, 0.3, k.shape)) * spacing)
    return poses[p], psi, b, p * len(BRANCHES) + b


@settings(max_examples=6, deadline=None, derandomize=True)
@given(name=st.sampled_from(["gen3", "rosi"]), seed=st.integers(0, 2**32 - 1),
       spacing=st.sampled_from([0.01, 0.05, 0.2]), near=st.sampled_from(["random", "elbow", "wrist"]))
def test_continued_rows_are_ik_rows_certified_on_their_branch(name, seed, spacing, near):
    arm, rng = _arm(name), np.random.default_rng(seed)
    q = _random_q(arm.chain, 3, rng)
    if near == "elbow":  # within a degree of the stretched elbow (the neighbour's theta_4 at the real phase)
        stretched = arm.geometry.q_of_theta(np.r_[np.zeros(3), arm.real_phase, np.zeros(3)])[3]
        q[:, 3] = stretched + rng.uniform(-0.017, 0.017, len(q))
    elif near == "wrist":  # q6 within a degree of a straight wrist
        q[:, 5] = rng.uniform(-0.017, 0.017, len(q))
    poses, psi, rows, groups = _sweeps(arm, q, 12, spacing, rng)
    found, exists = nearly.ik_continued(arm, poses, psi, rows, groups)
    reference = nearly.ik(arm, poses, psi)
    own = reference.q[np.arange(len(rows)), rows]
    np.testing.assert_array_equal(exists, reference.exists[np.arange(len(rows)), rows])
    assert np.all(found[~exists] == 0.0) and np.all(np.isfinite(found))
    position, rotation = _pose_errors(arm.chain.fk(found[exists]), poses[exists])
    angle = np.abs(_wrapped(nearly.arm_angle(arm, found[exists]) - psi[exists]))
    assert max(position.max(initial=0.0), rotation.max(initial=0.0), angle.max(initial=0.0)) <= CERTIFICATE
    np.testing.assert_array_equal(_real_branch(arm, found[exists]), rows[exists])
    apart = np.abs(_wrapped(found[exists] - own[exists])).max(axis=-1, initial=0.0)
    # where they differ, the branch has two solutions there: ik's row is the other one, also certified on it
    assert np.mean(apart <= 1e-8) >= 0.9, apart.max()


def test_groups_are_independent_of_the_batch_the_threads_and_the_order():
    arm, rng = _arm("gen3"), np.random.default_rng(4)
    poses, psi, rows, groups = _sweeps(arm, _random_q(arm.chain, 4, rng), 10, 0.05, rng)
    whole, whole_exists = nearly.ik_continued(arm, poses, psi, rows, groups)
    for group in np.unique(groups)[::5]:
        mine = groups == group
        alone, alone_exists = nearly.ik_continued(arm, poses[mine], psi[mine], rows[mine], groups[mine])
        np.testing.assert_array_equal(alone, whole[mine])
        np.testing.assert_array_equal(alone_exists, whole_exists[mine])
    shuffled = rng.permutation(len(psi))
    for threads in (1, 2):
        try:
            set_threads(threads)
            again, again_exists = nearly.ik_continued(arm, poses[shuffled], psi[shuffled], rows[shuffled],
                                                      groups[shuffled])
        finally:
            set_threads(None)
        np.testing.assert_array_equal(again, whole[shuffled])
        np.testing.assert_array_equal(again_exists, whole_exists[shuffled])


def test_bad_input_is_a_value_error():
    arm = _arm("gen3")
    pose = arm.chain.fk(np.full(7, 0.3))
    poses, psi, rows, groups = np.stack([pose, pose]), np.array([0.1, 0.2]), np.array([0, 0]), np.array([0, 0])
    with pytest.raises(ValueError, match="K poses"):
        nearly.ik_continued(arm, poses, psi[:1], rows, groups)
    with pytest.raises(ValueError, match="rows must be branch rows 0-7"):
        nearly.ik_continued(arm, poses, psi, np.array([0, 8]), groups)
    bad = poses.copy()
    bad[1, 0, 0] = np.nan
    with pytest.raises(ValueError, match="finite"):
        nearly.ik_continued(arm, bad, psi, rows, groups)
    q, exists = nearly.ik_continued(arm, poses[:0], psi[:0], rows[:0], groups[:0])
    assert q.shape == (0, 7) and exists.shape == (0,)
