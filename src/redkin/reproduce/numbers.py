"""Numbers as the report prints them: the paper's digits plus one, zeros without a sign, one format per column.

* A value with ``|x| < _ZERO`` is printed ``0``; nothing is printed as ``-0``.
* A comparison row prints ours with one decimal more than the paper's value
  as written (``45.991`` -> ``45.9908``), and the difference with the same
  decimals and a sign.
* A column of a plain table gets one format for all its numbers: fixed
  decimals that give its smallest non-zero value three significant digits,
  or, when that needs more than four decimals or the largest value reaches
  a million, scientific notation (``7.64 × 10⁻⁷``) for the whole column.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

from redkin.reproduce.comparison import is_number

#: Magnitudes below this are printed as 0 (rounding residue of a quantity that is zero).
_ZERO = 1e-12
#: Most decimals a column is printed with before it turns scientific.
_MAX_DECIMALS = 4
#: Significant digits of a plain column.
_SIGNIFICANT = 3
_SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


def printed_decimals(value: float) -> int:
    """Decimals of a paper value as written: ``45.991`` -> 3, ``45`` and ``90.0`` -> 0, ``1e-05`` -> 5."""
    if isinstance(value, int):
        return 0
    mantissa, _, exponent = repr(float(value)).partition("e")
    fraction = mantissa.partition(".")[2].rstrip("0")
    return max(len(fraction) - (int(exponent) if exponent else 0), 0)


def fixed(value: float, decimals: int, sign: bool = False) -> str:
    """``value`` with ``decimals`` decimals; ``0`` below :data:`_ZERO`, never ``-0``; ``sign`` adds ``+``."""
    if abs(value) < _ZERO:
        return "0"
    text = f"{value:{'+' if sign else ''}.{decimals}f}"
    if float(text) == 0.0:  # rounds to zero: no sign
        return text.lstrip("+-")
    return text


def _scientific(value: float, significant: int = _SIGNIFICANT) -> str:
    """``7.64 × 10⁻⁷``; ``0`` below :data:`_ZERO`."""
    if abs(value) < _ZERO:
        return "0"
    mantissa, _, exponent = f"{value:.{significant - 1}e}".partition("e")
    power = int(exponent)
    return mantissa if power == 0 else f"{mantissa} × 10{str(power).translate(_SUPERSCRIPT)}"


def general(value: float) -> str:
    """One number on its own: the format a column of just this value would get."""
    return column_format([value])(value)


def column_format(values: Sequence[Any]) -> Callable[[Any], str]:
    """One formatter for every number of a column (ints stay whole, words pass through)."""
    floats = [abs(float(v)) for v in values if is_number(v) and not isinstance(v, int)]
    nonzero = [v for v in floats if v >= _ZERO]
    if not nonzero:
        decimals, use_scientific = 0, False
    else:
        decimals = max(_SIGNIFICANT - 1 - math.floor(math.log10(min(nonzero))), 0)
        use_scientific = decimals > _MAX_DECIMALS or max(nonzero) >= 1e6

    def show(value: Any) -> str:
        if isinstance(value, int) and not isinstance(value, bool):
            return str(value)
        if not is_number(value):
            return text(value)
        return _scientific(float(value)) if use_scientific else fixed(float(value), decimals)

    return show


def text(value: Any) -> str:
    """A cell that is not a number: ``None`` as a dash, lists with their items formatted, the rest as words."""
    if value is None:
        return "–"
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(general(v) if is_number(v) else text(v) for v in value) + "]"
    if isinstance(value, float) or value in ("inf", "-inf", "nan"):  # non-finite, as summary.json stores them
        return {"inf": "∞", "-inf": "-∞"}.get(str(value), str(value))
    return str(value)
