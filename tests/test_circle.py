"""Laws of ArcSet: set operations equal pointwise logic on dense samples; wrapped arcs are one arc."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from redkin.circle import ArcSet, _intersect_all, wrap_angle

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
