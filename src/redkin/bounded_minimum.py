"""A local minimum of a function of one variable inside an interval, without derivatives: Brent's method (R. P.
Brent, *Algorithms for Minimization without Derivatives*, 1973, chapter 5), golden-section steps made faster by
parabolic interpolation through the three best points so far.

The Franka class's limit-avoiding q7 (:mod:`redkin.franka.optimal`) refines its sampled minima with it.  It was
``scipy.optimize.minimize_scalar(method="bounded")``, the same method; importing ``scipy.optimize`` (about 0.3-0.45 s
on this project's 2-core machine, ``scipy.linalg`` with it) was half of a first ``redkin arm-angles`` on a Franka-class
arm (issue 42).  The stopping rule is scipy's: the bracket around the best point is within ``xatol / 3`` plus
``sqrt(eps)`` of it, relative.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from redkin.errors import RedkinError

#: The golden section's smaller part, ``(3 - sqrt 5) / 2``.
_GOLDEN = 0.5 * (3.0 - math.sqrt(5.0))
#: The relative part of the tolerance: the square root of the machine epsilon, below which a minimum's position is
#: lost in the rounding of the function's values near it.
_SQRT_EPS = math.sqrt(2.220446049250313e-16)


def bounded_minimum(function: Callable[[float], float], low: float, high: float, xatol: float = 1e-5,
                    iterations: int = 500) -> tuple[float, float]:
    """A local minimiser of ``function`` in ``[low, high]`` and its value, by Brent's method.

    Parameters
    ----------
    function : callable
        ``float -> float``; finite wherever it is evaluated (give a ceiling in place of ``inf``).
    low, high : float
        The interval, ``low < high``; neither end is evaluated.
    xatol : float
        The absolute part of the tolerance on the minimiser's position.
    iterations : int
        At most this many evaluations after the first.

    Returns
    -------
    x, value : float
        The best point found and ``function(x)``: the global minimiser where ``function`` is unimodal on the interval.

    Raises
    ------
    ValueError
        For an empty or unbounded interval.
    """
    if not (math.isfinite(low) and math.isfinite(high) and low < high):
        raise RedkinError(f"the interval must be finite and not empty, got [{low}, {high}]")
    a, b = low, high
    x = w = v = a + _GOLDEN * (b - a)
    fx = fw = fv = function(x)
    step = previous = 0.0  # the last step, and the one before it (a parabola's must be less than half of that)
    for _ in range(iterations):
        middle = 0.5 * (a + b)
        tolerance = _SQRT_EPS * abs(x) + xatol / 3.0
        if abs(x - middle) <= 2.0 * tolerance - 0.5 * (b - a):
            break
        parabolic = False
        if abs(previous) > tolerance:  # the vertex of the parabola through x, w and v
            r = (x - w) * (fx - fv)
            q = (x - v) * (fx - fw)
            p = (x - v) * q - (x - w) * r
            q = 2.0 * (q - r)
            if q > 0.0:
                p = -p
            else:
                q = -q
            longer, previous = previous, step
            if abs(p) < abs(0.5 * q * longer) and q * (a - x) < p < q * (b - x):
                step, parabolic = p / q, True
                if x + step - a < 2.0 * tolerance or b - (x + step) < 2.0 * tolerance:
                    step = tolerance if x < middle else -tolerance  # not next to an end
        if not parabolic:  # a golden-section step into the larger part
            previous = (b - x) if x < middle else (a - x)
            step = _GOLDEN * previous
        u = x + step if abs(step) >= tolerance else x + math.copysign(tolerance, step)
        fu = function(u)
        if fu <= fx:
            if u < x:
                b = x
            else:
                a = x
            v, fv, w, fw, x, fx = w, fw, x, fx, u, fu
        else:
            if u < x:
                a = u
            else:
                b = u
            if fu <= fw or w == x:
                v, fv, w, fw = w, fw, u, fu
            elif fu <= fv or v == x or v == w:
                v, fv = u, fu
    return x, fx
