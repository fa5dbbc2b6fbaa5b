"""Feasible arm-angle sets against dense sampling of IK with an FK check ([000 eqs. 21-30]), and random limits."""

import numpy as np

from redkin.circle import _intersect_all, wrap_angle
from redkin.srs import ik

GRID = np.linspace(-np.pi, np.pi, 6001, endpoint=False)


def sampled_feasibility(chain, pose, branch, psi):
    """Joint-limit check of IK at each psi, with the FK round trip checked too."""
    poses = np.broadcast_to(pose, psi.shape + (4, 4))
    q = ik(chain, poses, psi, branch)
    assert np.abs(chain.fk(q) - poses).max() < 1e-9
    return chain.joints_within_limits(q, wrap=True)


def assert_set_matches_sampling(chain, pose, branch, result, margin=1e-7):
    per_joint = sampled_feasibility(chain, pose, branch, GRID)
    ends = np.array([e for s in [result.feasible, *result.per_joint.values()] for iv in s.intervals for e in iv])
    near = np.zeros(GRID.shape, bool)
    if ends.size:
        near = np.min(np.abs(wrap_angle(GRID[:, None] - ends[None, :])), axis=1) < margin
    for j in range(1, 8):
        inside = result.per_joint[j].contains(GRID)
        assert np.array_equal(inside[~near], per_joint[~near, j - 1]), f"joint {j}"
    overall = result.feasible.contains(GRID)
    assert np.array_equal(overall[~near], np.all(per_joint, axis=1)[~near])
    # every arc, however narrow, is feasible inside; every gap infeasible inside
    for lo, hi in result.feasible.intervals:
        inner = np.linspace(lo, hi, 7)[1:-1] if hi - lo > 2 * margin else np.array([(lo + hi) / 2])
        assert np.all(sampled_feasibility(chain, pose, branch, inner)), (lo, hi)
    for lo, hi in result.feasible.complement().intervals:
        if hi - lo > 4 * margin:
            inner = np.linspace(lo + margin, hi - margin, 9)
            assert not np.any(np.all(sampled_feasibility(chain, pose, branch, inner), axis=1)), (lo, hi)
    # [000 eq. 30]: the overall set is the intersection of the per-joint sets
    assert result.feasible.isclose(_intersect_all(result.per_joint.values()), 1e-9)


def random_limits(rng, q, crossing):
    """Limits around q (so sets tend to be non-empty) with random widths; optionally across +-pi."""
    width = rng.uniform(0.2, 4.0, 7)
    centre = q + rng.uniform(-0.5, 0.5, 7) * width
    if crossing:
        centre = np.where(rng.random(7) < 0.5, np.pi + rng.uniform(-0.3, 0.3, 7), centre)
    return centre - width / 2, centre + width / 2
