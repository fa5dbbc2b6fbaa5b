"""The two merges the collision-free sets end with (numpy, not a loop over every decided interval): laws on random
intervals.

* ``merged_intervals`` (q7 sets, the free q7 intervals): disjoint sorted arcs whose union is the union of the
  intervals, each end an end of one of them;
* ``Decided.stretches`` and ``Decided.free_runs`` (every pose's branches at once): per branch, the removed intervals,
  touching ones of one cause as one stretch, every removed interval inside exactly one stretch of its cause, free
  intervals in none; the free intervals, touching ones as one run, every free interval inside exactly one run.
"""

from __future__ import annotations

from itertools import pairwise

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from redkin.arms.feasible_sets import merged_intervals
from redkin.collision.arm_angle_free import COLLISION, UNDECIDED, Decided

intervals = st.lists(st.tuples(st.floats(-4.0, 4.0), st.floats(0.0, 1.0)), max_size=30)


@settings(max_examples=100, deadline=None)
@given(intervals)
def test_merged_intervals_is_the_union_in_disjoint_sorted_arcs(pairs):
    start = np.array([a for a, _ in pairs], dtype=float)
    end = start + np.array([w for _, w in pairs], dtype=float)
    merged = merged_intervals(start, end)
    bounds = merged.bounds
    assert not merged.wraps.any()
    assert np.all(bounds[:, 0] <= bounds[:, 1]) and np.all(bounds[1:, 0] > bounds[:-1, 1])  # disjoint, sorted
    assert set(bounds[:, 0]) <= set(start) and set(bounds[:, 1]) <= set(end)
    probe = np.concatenate([start, end, np.linspace(-5.0, 6.0, 2001)])
    inside = np.any((probe[:, None] >= start) & (probe[:, None] <= end), axis=1)
    covered = np.any((probe[:, None] >= bounds[:, 0]) & (probe[:, None] <= bounds[:, 1]), axis=1)
    np.testing.assert_array_equal(covered, inside)


@settings(max_examples=100, deadline=None)
@given(st.lists(st.tuples(st.floats(0.001, 0.5), st.integers(0, 2), st.integers(0, 3), st.booleans(),
                          st.integers(0, 2)), max_size=30))
def test_stretches_and_free_runs_join_touching_intervals_of_one_cause(steps):
    """Intervals laid end to end on each of three branches (a gap after some), each free (0), blocked by pair ``w``
    (1) or undecided (2); pairs 2 and 3 are named alike (two shapes of one link against one obstacle).  A run or a
    stretch never joins two branches."""
    names = [("link_1", "post"), ("link_2", "post"), ("link_5", "lamp"), ("link_5", "lamp")]
    lo, hi, owner, kind, which, at = [], [], [], [], [], [0.0, 0.0, 0.0]
    for width, k, w, gap, branch in steps:
        lo.append(at[branch])
        hi.append(at[branch] + width)
        owner.append(branch)
        kind.append(k)
        which.append(w)
        at[branch] += width + (0.1 if gap else 0.0)
    parts = (np.array(lo, dtype=float), np.array(hi, dtype=float), np.array(owner, dtype=np.int64),
             np.array(kind, dtype=np.int64), np.array(which, dtype=np.int64))
    order = np.random.default_rng(0).permutation(len(lo))  # any order in
    decided = Decided.of(tuple(part[order] for part in parts))
    every_stretch, (run_lo, run_hi, run_owner) = decided.stretches(3, names, float), decided.free_runs()
    assert np.all(np.diff(run_owner) >= 0)  # sorted by owner
    for branch in range(3):
        stretches = every_stretch[branch]
        runs = list(zip(run_lo[run_owner == branch].tolist(), run_hi[run_owner == branch].tolist(), strict=True))
        assert all(a.end < b.start or (a.end == b.start and (a.cause, a.link, a.against)
                                       != (b.cause, b.link, b.against))
                   for a, b in pairwise(stretches))  # sorted, and touching ones differ in cause
        assert all(a[1] < b[0] for a, b in pairwise(runs))  # sorted, and touching free intervals joined
        for start, end, b, k, w in zip(lo, hi, owner, kind, which):
            if b != branch:
                continue
            holding = [s for s in stretches if s.start <= start and end <= s.end]
            in_runs = [r for r in runs if r[0] <= start and end <= r[1]]
            if k == 0:
                assert not any(s.start < end and start < s.end for s in stretches) and len(in_runs) == 1
                continue
            assert not any(r[0] < end and start < r[1] for r in runs)
            cause = (COLLISION, *names[w]) if k == 1 else (UNDECIDED, "", "")
            assert [(s.cause, s.link, s.against) for s in holding] == [cause]
