"""The real roots of the Franka class's limit polynomials ([F8]): subdivision finds every one, and settles
polynomials with complex roots near the unit circle without the eigenvalue route; the double roots of a square whose
coefficients were summed from terms that cancel (an arm without elbow offsets) are candidates, however their
rounding lifts them.

Each polynomial is a product of factors ``cos(theta - a) - c`` of known roots: real ones (``|c| < 1``, roots
``a +- arccos c``) and pairs of complex ones at distance ``eps`` from the real axis (``c = +-cosh eps``), the case
that needed thousands of cells before the subdivision's bounds took the derivatives at the cell's middle.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import Phase, assume, example, given, settings
from hypothesis import strategies as st

from redkin.franka._kernels import (
    _NEAR_ZERO,
    _TERM_ROUNDING,
    SAMPLES,
    coefficient_roots,
    global_bounds,
    isolated_roots,
    trig_coefficients,
    trig_value,
)

#: A factor: ``(a, kind, size)``; kind 0 a real pair of roots ``a +- arccos(size)``, kind 1 a complex pair
#: ``a +- i eps`` (``cos(theta - a) - cosh(eps)``), kind 2 the same below (``cos(theta - a) + cosh(eps)``).
_FACTOR = st.tuples(st.floats(-np.pi, np.pi), st.integers(0, 2), st.floats(0.0, 1.0))


def _roots_and_samples(factors, smallest_eps: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The real roots of the product of ``factors``, its values at the :data:`SAMPLES` angles ``2 pi j / n``, and
    the real parts and distances ``(K, 2)`` of its complex pairs;
    the examples where two roots, or a root and a complex pair's real part, lie closer than 0.01 are passed over
    (clusters of roots are the eigenvalue route's case, and a multiple root is found only to a root of the
    rounding)."""
    theta = 2.0 * np.pi * np.arange(SAMPLES) / SAMPLES
    values = np.ones(SAMPLES)
    roots, centres, pairs = [], [], []
    for a, kind, size in factors:
        if kind == 0:
            c = 0.98 * (2.0 * size - 1.0)
            half_width = np.arccos(c)
            roots += [a - half_width, a + half_width]
            centres += [a - half_width, a + half_width]
        else:
            centres.append(a if kind == 1 else a + np.pi)
            eps = smallest_eps * (0.3 / smallest_eps) ** size  # log-uniform in [smallest_eps, 0.3]
            c = np.cosh(eps) if kind == 1 else -np.cosh(eps)
            pairs.append((a if kind == 1 else a + np.pi, eps))
        values *= np.cos(theta - a) - c
    centres_wrapped = np.sort(np.mod(np.array(centres), 2.0 * np.pi))
    gaps = np.diff(np.append(centres_wrapped, centres_wrapped[0] + 2.0 * np.pi))
    assume(len(centres) == 1 or gaps.min() >= 0.01)
    return np.mod(np.array(roots) + np.pi, 2.0 * np.pi) - np.pi, values, np.array(pairs).reshape(-1, 2)


def _half(values: np.ndarray, degree: int) -> np.ndarray:
    """``(g_0, ..., g_D)`` of the trigonometric polynomial sampled at ``2 pi j / n``."""
    return np.ascontiguousarray(np.fft.fft(values)[: degree + 1] / len(values))


def _allowed(half: np.ndarray, root: float) -> float:
    """How far a found root may lie from the true one: 1e-8, or where the polynomial is flat there what rounding
    allows at its slope: the Newton steps stop where ``|G|`` is at most 1e-15 of the largest value ``G`` can take,
    and ``G``'s own rounding there is as large again (fresh draws found roots 1.01 and 1.17 times the first alone)."""
    _, _, floor = global_bounds(half, 0.0)
    return max(1e-8, 2e-15 * floor / _NEAR_ZERO / abs(trig_value(half, root)[1]))


def _distance_on_circle(found: np.ndarray, root: float) -> float:
    return float(np.min(np.abs(np.mod(found - root + np.pi, 2.0 * np.pi) - np.pi))) if len(found) else np.inf


@settings(max_examples=150, deadline=None)
@given(st.lists(_FACTOR, min_size=1, max_size=8))
@example([(0.0, 1, 0.0), (3.0, 0, 0.0), (2.75, 0, 0.0), (-0.5, 0, 1.0), (-0.25, 1, 0.0)])  # fresh draws: flat
@example([(-1.0, 0, 0.0), (-2.0, 0, 0.0), (-1.6640625, 2, 0.0), (-1.6484375, 2, 0.0)])  # below the floor between
@example([(0.0, 1, 0.0), (-0.25, 1, 0.0), (0.0, 0, 1.0), (3.0, 0, 0.0)])  # a root of slope 9e-8
@example([(0.0, 0, 0.0), (0.0, 0, 1.0), (0.0, 0, 0.25), (0.0, 0, 0.125), (0.0, 2, 0.0), (2.0, 0, 0.8125),
          (0.25, 0, 0.0), (-0.25, 0, 0.0)])  # a fresh draw: a flat root found 1.01 times the stop's allowance off
@example([(0.0, 0, 0.0), (0.0, 0, 0.25), (0.0, 2, 0.0), (2.0, 0, 1.0), (2.0, 0, 0.8125), (0.546875, 0, 0.140625),
          (-0.5, 0, 0.0), (-0.0625, 0, 0.0)])  # a fresh draw: five roots in 0.1 rad, two eigenvalues 3.5e-3 off
def test_subdivision_settles_complex_roots_near_the_circle_and_finds_every_real_root(factors):
    """Every real root is found, to 1e-8 or to what the coefficients' rounding allows at its slope; every candidate
    is a root, within 3 eps of a complex pair, or a point where ``|G|`` is below the kernel's floor (a cell that may
    hold a double root gives its middle).  Subdivision settles the polynomial without the eigenvalue route, unless
    ``G`` lies below the floor on a stretch away from the real roots (several factors small at once), where it hands
    over (-1) and the eigenvalue route finds every root."""
    roots, values, pairs = _roots_and_samples(factors, smallest_eps=1e-4)
    out = np.empty(2 * len(factors) + 8)
    half = _half(values, len(factors))
    _, _, floor = global_bounds(half, 0.0)
    simple = np.empty(len(out), dtype=bool)
    count = isolated_roots(half, 0.0, -np.pi, np.pi, 4 * len(half), out, simple)
    if count < 0:  # handed over: only where G is flat below the floor away from the roots
        grid = np.linspace(-np.pi, np.pi, 20001)
        flat = grid[np.abs([trig_value(half, t)[0] for t in grid]) <= floor]
        assert any(_distance_on_circle(roots, t) > 1e-3 for t in flat)
        coefficients = np.empty(2 * len(factors) + 1, dtype=np.complex128)
        largest = trig_coefficients(values, len(factors), 0.0, coefficients)
        count = coefficient_roots(coefficients, largest, 0.0, out, simple)
        assert not simple[:count].any()  # the eigenvalue route's candidates are not taken as simple roots
    found = out[:count]
    for root in roots:
        assert _distance_on_circle(found, root) <= _allowed(half, root)
    for candidate in found:  # a real root, or where a complex pair nearly touches the circle (a near-double root)
        near_pair = any(_distance_on_circle(np.array([centre]), candidate) <= 3.0 * eps for centre, eps in pairs)
        assert near_pair or _distance_on_circle(roots, candidate) <= 1e-8 \
            or abs(trig_value(half, candidate)[0]) <= floor


@pytest.mark.xfail(strict=True, reason="known, found by fresh draws on 2026-12-05 and not yet fixed (also on "
                   "e84aab3): in a cluster of roots whose values lie at G's rounding, the eigenvalues, polished, stay "
                   "3.9e-3 from a root, twice what the law allows at its slope")
@settings(phases=[Phase.explicit], deadline=None)  # the draw below alone, as a property test (the law's assume)
@given(st.lists(_FACTOR, min_size=1, max_size=8))
@example([(0.0, 0, 0.12359993949127482), (0.0, 2, 0.0), (1.9184019316533547, 1, 0.0), (2.00001, 0, 0.837313009912114),
          (0.546180425600908, 0, 0.1433119925593336), (0.0, 0, 0.0), (-0.3333333333333333, 0, 0.0),
          (-0.08237415722027874, 0, 0.0)])
def test_a_cluster_whose_roots_the_eigenvalue_route_places_too_far(factors):
    """A fresh draw of the law above that fails: the root at 2.8485 has its nearest candidate 3.9e-3 away.  Strict:
    when the eigenvalue route locates such clusters this fails, and the draw becomes an @example of the law."""
    test_subdivision_settles_complex_roots_near_the_circle_and_finds_every_real_root.hypothesis.inner_test(factors)


@settings(max_examples=100, deadline=None)
@given(st.lists(_FACTOR, min_size=1, max_size=8), st.floats(0.0, np.pi / SAMPLES))
@example([(0.0, 0, 0.0), (0.0, 0, 0.001953125), (3.0, 1, 0.0), (0.25, 0, 0.0)], 0.0)  # a fresh draw: 1.2e-8 off
@example([(0.0, 0, 0.0), (0.0, 0, 1.0), (0.0, 1, 0.0), (1.0, 0, 1.0), (1.0, 1, 0.0), (3.0, 0, 0.0), (2.5, 0, 0.0),
          (-1.0, 0, 0.0)], 0.0)  # a fresh draw: 1.17 times the stop's allowance off
def test_every_real_root_is_a_candidate_however_close_the_complex_ones(factors, phase):
    """Complex pairs down to 1e-7 from the circle, where the subdivision may hand over to the eigenvalues: every
    real root is a candidate, to 1e-8 or to what rounding allows at its slope (a root next to a near-double complex
    pair is flat: the fresh draw's, 1.2e-8 from the true one, may be 1.5e-7)."""
    roots, values, _ = _roots_and_samples(factors, smallest_eps=1e-7)
    half = _half(values, len(factors))
    shifted = _roots_and_samples([(a - phase, kind, size) for a, kind, size in factors], 1e-7)[1]
    out = np.empty(2 * 8)
    coefficients = np.empty(2 * len(factors) + 1, dtype=np.complex128)
    largest = trig_coefficients(shifted, len(factors), phase, coefficients)  # the samples taken from phase on
    count = coefficient_roots(coefficients, largest, 0.0, out, np.empty(len(out), dtype=bool))
    for root in roots:
        assert _distance_on_circle(out[:count], root) <= _allowed(half, root)


@settings(max_examples=100, deadline=None)
@given(st.lists(st.tuples(st.floats(-np.pi, np.pi), st.floats(0.0, 1.0)), min_size=1, max_size=4),
       st.integers(0, 2**32 - 1))
@example([(0.0, 0.8658923849495466), (2.417292637137211, 0.0), (-3.1152546389095273, 0.5), (3.0, 0.71875)], 1)
def test_the_double_roots_of_a_square_summed_from_cancelling_terms_are_candidates(factors, seed):
    """``G = P^2`` with ``P`` of real roots only, each coefficient perturbed by the rounding of terms 1e4 times its
    size (four units of their last place, either sign; the Panda's level polynomials cancel up to 5e3-fold, random
    arms' 1e4-fold): where the subdivision settles, each root of ``P``, a double root of ``G`` that the rounding
    lifts off zero or splits, has a candidate joined to it by a stretch on which ``|G| <= 2 floor`` (what rounding
    of the floor's size cannot tell from a root).  With a floor from ``G``'s own size alone, such roots had none;
    the example's, whose least value fell on the edge of a cell, had none while the monotone test left out the
    rounding of ``G1`` (a fresh draw)."""
    roots, values, _ = _roots_and_samples([(a, 0, size) for a, size in factors], smallest_eps=1e-4)
    square = _half(values * values, 2 * len(factors))
    terms = 1e4 * (abs(square[0]) + 2.0 * np.abs(square[1:]).sum())
    rounding = np.random.default_rng(seed).uniform(-1.0, 1.0, (2, len(square))) * 4.0 * np.finfo(float).eps * 1e4
    half = np.ascontiguousarray(square + np.abs(square) * (rounding[0] + 1j * np.r_[0.0, rounding[1, 1:]]))
    out = np.empty(2 * 8)
    count = isolated_roots(half, terms, -np.pi, np.pi, 4 * len(half), out, np.empty(len(out), dtype=bool))
    assume(count >= 0)  # handed to the eigenvalue route: the laws above
    floor = 2.0 * _TERM_ROUNDING * terms
    for root in roots:
        assert count > 0
        step = np.mod(out[:count] - root + np.pi, 2.0 * np.pi) - np.pi
        nearest = root + step[np.argmin(np.abs(step))]
        stretch = np.linspace(root, nearest, 2001)
        assert max(abs(trig_value(square, t)[0]) for t in stretch) <= floor, (root, out[:count])
