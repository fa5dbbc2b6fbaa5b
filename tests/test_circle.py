"""Laws of ArcSet: set operations equal pointwise logic on dense samples; wrapped arcs are one arc."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from redkin.arms.feasible_sets import owner_arcs
from redkin.circle import ArcSet, _intersect_all, arc_length, circle_arcs, owner_runs, wrap_angle

GRID = np.linspace(-np.pi, np.pi, 4001, endpoint=False)
MARGIN = 1e-9

arc = st.tuples(st.floats(-4.0, 4.0), st.floats(0.0, 6.0)).map(lambda t: (t[0], t[0] + t[1]))
arc_sets = st.lists(arc, max_size=4).map(ArcSet)


def near_end(sets, angles):
    ends = np.array([e for s in sets for iv in s.intervals for e in iv] + [np.pi, -np.pi])
    return np.min(np.abs(wrap_angle(angles[:, None] - ends[None, :])), axis=1) < 1e-6


@settings(max_examples=60, deadline=None)
@given(arc_sets, arc_sets)
def test_union_intersection_complement_match_pointwise_logic(a, b):
    ina, inb = a.contains(GRID), b.contains(GRID)
    skip = near_end([a, b], GRID)
    assert np.array_equal(a.union(b).contains(GRID)[~skip], (ina | inb)[~skip])
    assert np.array_equal(a.intersection(b).contains(GRID)[~skip], (ina & inb)[~skip])
    assert np.array_equal(a.complement().contains(GRID)[~skip], (~ina)[~skip])


@settings(max_examples=60, deadline=None)
@given(arc_sets)
def test_length_matches_sampling_and_complement(a):
    fraction = a.contains(GRID).mean()
    assert abs(a.length - 2 * np.pi * fraction) < 2 * np.pi * (2 * len(a.intervals) + 1) / len(GRID)
    assert abs(a.length + a.complement().length - 2 * np.pi) < 1e-9


@settings(max_examples=60, deadline=None)
@given(arc_sets, st.floats(-10, 10))
def test_nearest_is_in_set_and_no_sample_is_closer(a, angle):
    nearest = a.nearest(angle)
    if a.is_empty:
        assert nearest is None
        return
    assert a.contains(nearest, tolerance=1e-12)
    distance = abs(wrap_angle(nearest - angle))
    members = GRID[a.contains(GRID)]
    if members.size:
        assert distance <= np.min(np.abs(wrap_angle(members - angle))) + 1e-12


def test_arc_through_pi_is_one_arc_printed_with_lo_greater_than_hi():
    s = ArcSet([(3.0, -3.0)])
    assert len(s.arcs) == 1
    lo, hi = s.arcs[0]
    assert lo == pytest.approx(3.0) and hi == pytest.approx(-3.0)
    assert s.contains(np.pi) and s.contains(-np.pi + 0.05) and not s.contains(0.0)
    assert s.length == pytest.approx(2 * np.pi - 6.0)


def test_full_and_empty_are_values():
    full, empty = ArcSet.full(), ArcSet.empty()
    assert full.is_full and not full.is_empty and full.length == pytest.approx(2 * np.pi)
    assert empty.is_empty and empty.arcs == [] and empty.length == 0.0
    assert full.complement().is_empty and empty.complement().is_full
    assert ArcSet([(0.0, 7.0)]).is_full
    assert _intersect_all([]) == full
    assert full.intersection(ArcSet([(1.0, 2.0)])) == ArcSet([(1.0, 2.0)])
    assert ArcSet([(-1.0, 0.0), (0.0, 1.0)]).arcs == [(-1.0, 1.0)]
    assert repr(ArcSet([(1.0, 2.0)])).startswith("ArcSet([")


def test_bad_arcs_raise():
    with pytest.raises(ValueError, match="pair"):
        ArcSet([(1.0, 2.0, 3.0)])
    with pytest.raises(ValueError, match="finite"):
        ArcSet([(np.nan, 1.0)])


@settings(max_examples=300, deadline=None)
@given(st.floats(-1e6, 1e6) | st.sampled_from([np.pi, -np.pi, 3 * np.pi, -3 * np.pi, 0.0, -0.0, 1e-300]))
def test_wrap_angle_of_a_float_equals_the_array_path_bit_for_bit(angle):
    """The scalar fast path (Python %) and the array path (np.mod) give the same float in [-pi, pi)."""
    scalar = wrap_angle(float(angle))
    assert type(scalar) is float
    assert scalar == float(wrap_angle(np.array([angle]))[0])
    assert -np.pi <= scalar < np.pi


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.sampled_from([-np.pi, np.pi]), st.floats(-1e-12, 1e-12), st.floats(0.1, 2.0)),
                min_size=1, max_size=2))
def test_an_arc_shown_through_the_seam_holds_the_seam(ends):
    """Ends within the seam tolerance of +-pi (as sets located numerically come out): wherever ``arcs`` shows an arc
    through +-pi, the set holds +-pi; and each arc holds its ends and its middle."""
    pieces = [(-np.pi + abs(off), -np.pi + abs(off) + width) if seam < 0 else (np.pi - abs(off) - width,
              np.pi - abs(off)) for seam, off, width in ends]
    s = ArcSet._from_intervals(pieces)
    for lo, hi in s.arcs:
        middle = wrap_angle(lo + ((hi - lo) % (2 * np.pi) if lo > hi else hi - lo) / 2)
        assert s.contains(lo, 1e-12) and s.contains(hi, 1e-12) and s.contains(middle)  # wrapping rounds ends
        if lo > hi:
            assert s.contains(np.pi) and s.contains(-np.pi)


seam_starts = st.sampled_from([-np.pi, np.pi, np.pi - 1e-13, -np.pi + 5e-13, 0.0, 3 * np.pi])
owned_arcs = st.lists(st.tuples(st.integers(0, 3), st.floats(-7.0, 7.0) | seam_starts,
                                st.floats(0.0, 7.0) | st.sampled_from([0.0, 1e-13, 2 * np.pi, 1.0])), max_size=12)


@settings(max_examples=200, deadline=None)
@given(owned_arcs)
def test_many_owners_arcs_at_once_equal_each_owners_arc_set(arcs):
    """circle_arcs, the arcs of many owners merged in one numpy pass, gives each owner exactly ArcSet(...).arcs
    (the same floats, the arc through the seam last), seam ends, whole turns and touching arcs included; with
    owner_runs it is the one merge of FeasibleSets.arcs and the collision-free sets."""
    owner = np.array([o for o, _, _ in arcs], dtype=np.int64)
    lo = np.array([start for _, start, _ in arcs])
    hi = lo + np.array([length for _, _, length in arcs])
    bounds, wraps, arc_owner = circle_arcs(lo, hi, owner)
    for k in range(4):
        expected = ArcSet(list(zip(lo[owner == k].tolist(), hi[owner == k].tolist(), strict=True))).arcs
        assert bounds[arc_owner == k].tolist() == [list(map(float, arc)) for arc in expected]
        assert wraps[arc_owner == k].tolist() == [arc[0] > arc[1] for arc in expected]


@settings(max_examples=100, deadline=None)
@given(owned_arcs)
def test_runs_of_many_owners_are_each_owners_union(arcs):
    """owner_runs (no tolerance): each owner's runs are disjoint, sorted, and cover exactly its intervals."""
    owner = np.array([o for o, _, _ in arcs], dtype=np.int64)
    lo = np.array([start for _, start, _ in arcs])
    hi = lo + np.array([length for _, _, length in arcs])
    run_lo, run_hi, run_owner = owner_runs(lo, hi, owner)
    assert np.all(np.diff(run_owner) >= 0)
    for k in range(4):
        mine = np.stack([run_lo[run_owner == k], run_hi[run_owner == k]], axis=-1)
        assert np.all(mine[1:, 0] > mine[:-1, 1])  # disjoint and sorted
        points = np.concatenate([lo[owner == k], hi[owner == k], (lo[owner == k] + hi[owner == k]) / 2])
        for x in points:  # every point of an interval lies in a run, and each run's ends are intervals' ends
            assert np.any((mine[:, 0] <= x) & (x <= mine[:, 1]))
        assert set(mine[:, 0].tolist()) <= set(lo[owner == k].tolist())
        assert set(mine[:, 1].tolist()) <= set(hi[owner == k].tolist())
        for start, end in mine:  # and no run bridges a gap: its intervals, in order, each start within the reach
            inside = (lo[owner == k] >= start) & (hi[owner == k] <= end)
            order = np.argsort(lo[owner == k][inside])
            starts, ends = lo[owner == k][inside][order], hi[owner == k][inside][order]
            assert starts[0] == start and np.all(starts[1:] <= np.maximum.accumulate(ends)[:-1])


@settings(max_examples=100, deadline=None)
@given(owned_arcs, st.integers(0, 2), st.booleans())
def test_owner_arcs_split_gives_every_owner_its_own(arcs, spare, wraps):
    """owner_arcs(...).split(owners) returns one Arcs per owner, ``owners`` of them (none for no owner, empty ones
    for owners without intervals), each the owner's merged arcs alone."""
    owner = np.array([o for o, _, _ in arcs], dtype=np.int64)
    lo = np.array([start for _, start, _ in arcs])
    hi = lo + np.array([length for _, _, length in arcs])
    owners = (int(owner.max()) + 1 if len(owner) else 0) + spare
    every = owner_arcs(lo, hi, owner, wraps).split(owners)
    assert len(every) == owners
    for k, arcs_k in enumerate(every):
        alone = owner_arcs(lo[owner == k], hi[owner == k], np.zeros(int(np.sum(owner == k)), dtype=np.int64),
                           wraps).split(1)[0]
        assert np.array_equal(arcs_k.bounds, alone.bounds) and np.array_equal(arcs_k.wraps, alone.wraps)
        assert arcs_k.bounds.shape[1:] == (2,)


@given(st.floats(-np.pi, np.pi), st.floats(-np.pi, np.pi))
def test_arc_length_is_the_length_of_the_arc_from_start_up_to_end(start, end):
    """``arc_length`` of ends as redkin writes them (through +-pi where ``start > end``) is the length of that arc's
    ArcSet, and the whole circle ``(-pi, pi)`` is 2 pi where ``(end - start) mod 2 pi`` made it 0."""
    assert arc_length(start, end) == pytest.approx(ArcSet([(start, end if end >= start else end + 2 * np.pi)]).length,
                                                   abs=1e-12)
    assert arc_length(-np.pi, np.pi) == 2 * np.pi and arc_length(start, start) == 0.0
