"""Brent's bounded search (``redkin.bounded_minimum``): the minimiser of a unimodal function to its tolerance, the
nearer end where the minimum lies outside, a local minimum of any function, at most as low as scipy's
``minimize_scalar(method="bounded")`` (the same method, written independently) finds on unimodal functions, and a
clear refusal of an empty interval."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from scipy.optimize import minimize_scalar

from redkin.bounded_minimum import bounded_minimum

_SQRT_EPS = math.sqrt(np.finfo(float).eps)


def _tolerance(x: float, xatol: float) -> float:
    """How far from the true minimiser the search may stop (its stopping rule, with room for a last step)."""
    return 2.0 * (_SQRT_EPS * abs(x) + xatol)


ends = st.tuples(st.floats(-10.0, 10.0), st.floats(1e-3, 5.0))


@settings(max_examples=200, deadline=None)
@given(interval=ends, where=st.floats(-0.5, 1.5), power=st.sampled_from([1.0, 2.0, 4.0]),
       scale=st.floats(1e-3, 1e3), xatol=st.sampled_from([1e-10, 1e-5]))
@example(interval=(0.0, 1.0), where=0.5, power=2.0, scale=1.0, xatol=1e-10)
@example(interval=(-3.0, 1e-3), where=1.5, power=1.0, scale=1e3, xatol=1e-10)  # the minimum beyond the upper end
def test_a_unimodal_function_s_minimiser_is_found_to_the_tolerance(interval, where, power, scale, xatol):
    """``scale |x - c|^power`` (a kink at ``power`` 1, flat at 4): the search stops within its tolerance of ``c``
    clipped into the interval, inside the interval, and as low as scipy's search but for what that tolerance allows."""
    low, width = interval
    high = low + width
    centre = low + where * width
    calls = []

    def function(x: float) -> float:
        calls.append(x)
        return scale * abs(x - centre) ** power

    x, value = bounded_minimum(function, low, high, xatol=xatol)
    assert low < x < high and all(low < c < high for c in calls)  # neither end is evaluated
    assert value == function(x)
    target = min(max(centre, low), high)
    slack = _tolerance(target, xatol) if power <= 2.0 else _tolerance(target, xatol) ** 0.5  # flat: 4th power
    assert abs(x - target) <= slack, (x, target)
    theirs = minimize_scalar(function, bounds=(low, high), method="bounded", options={"xatol": xatol})
    assert value <= theirs.fun + scale * slack ** power  # no worse than theirs but for the tolerance's reach


@settings(max_examples=100, deadline=None)
@given(seed=st.integers(0, 2**31), xatol=st.sampled_from([1e-10, 1e-6]))
def test_any_function_s_answer_is_a_local_minimum(seed, xatol):
    """On a sum of random sines (several minima), the answer is lower than its neighbours 1e-5 away, unless it is
    within the tolerance of an end (where the infimum may lie)."""
    rng = np.random.default_rng(seed)
    amplitude, frequency, phase = rng.normal(size=5), rng.uniform(0.5, 8.0, 5), rng.uniform(0, 2 * np.pi, 5)

    def function(x: float) -> float:
        return float(np.sum(amplitude * np.sin(frequency * x + phase)))

    low, high = -1.0, 1.0 + rng.uniform(0.0, 2.0)
    x, value = bounded_minimum(function, low, high, xatol=xatol)
    if min(x - low, high - x) > 1e-4:
        assert value <= function(x - 1e-5) + 1e-12 and value <= function(x + 1e-5) + 1e-12


def test_a_minimum_at_a_jump_is_approached_from_its_low_side():
    """Where the function jumps down (as the optimal q7's objective does where a branch's joints jump by pi), the
    search ends next to the jump on its low side."""
    jump = 0.3

    def function(x: float) -> float:
        return (x - 0.2) ** 2 + 1.0 if x < jump else (x - jump) + 0.5

    x, value = bounded_minimum(function, 0.0, 1.0, xatol=1e-10)
    assert jump <= x <= jump + _tolerance(jump, 1e-10) and value == pytest.approx(0.5, abs=1e-7)


@pytest.mark.parametrize("low, high", [(1.0, 1.0), (2.0, 1.0), (0.0, math.inf), (math.nan, 1.0)])
def test_an_empty_or_unbounded_interval_is_refused(low, high):
    with pytest.raises(ValueError, match="interval"):
        bounded_minimum(lambda x: x * x, low, high)
