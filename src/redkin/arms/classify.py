"""Which closed-form class a chain belongs to: S-R-S, S-R-S with an offset elbow, the Franka class, nearly S-R-S, or
a general chain.

The arm-angle functions (paper 000) serve the first two classes, whose
redundancy parameter is the arm angle psi; :mod:`redkin.franka` serves the
third, whose parameter is q7; :mod:`redkin.srs.nearly` the fourth, an arm
within :data:`redkin.srs.nearly.TOLERANCE_DEFAULT` of an exact S-R-S neighbour,
whose arm angle is the neighbour's; a general chain has FK, Jacobian, the
numerical pose IK, velocity IK and virtual arms, but no closed form.
"""

from __future__ import annotations

from collections.abc import Callable
from functools import partial
from typing import TYPE_CHECKING, NamedTuple

import numpy as np

from redkin.chain import SerialChain
from redkin.errors import RedkinError
from redkin.srs.geometry import SRSGeometry, srs_geometry

if TYPE_CHECKING:
    from redkin.franka.geometry import FrankaGeometry
    from redkin.srs.nearly import NearlySRS

#: The classes, in the words ``redkin robots`` prints.
SRS, OFFSET_ELBOW, FRANKA, NEARLY_SRS, GENERAL = ("S-R-S", "S-R-S, offset elbow", "Franka (q7)", "nearly S-R-S",
                                                 "general chain")


class ArmClass(NamedTuple):
    """A chain's arm-angle class and why, in one line."""

    kind: str
    reason: str


def arm_angle_class(chain: SerialChain, tolerance: float | None = None) -> ArmClass:
    """Whether ``chain`` has closed-form IK, and which kind (see :data:`SRS`, :data:`OFFSET_ELBOW`, :data:`FRANKA`,
    :data:`NEARLY_SRS`, :data:`GENERAL`).

    ``tolerance`` is the largest departure from an exact S-R-S neighbour (metres between axes that must meet,
    radians off perpendicular) of a nearly S-R-S arm (:func:`redkin.srs.nearly_srs`); default
    :data:`redkin.srs.nearly.TOLERANCE_DEFAULT`.  It decides only between nearly S-R-S and a general chain.

    The reason of a general chain names the first condition of each closed
    form it violates, with its distance or angle (the messages
    :func:`redkin.srs.srs_geometry` and :func:`redkin.franka.franka_geometry` raise); that of a nearly S-R-S arm
    what its neighbour drops and how far their poses differ; that of an S-R-S arm snapped from rounded numbers
    (:func:`redkin.srs.conventions.table1_form`) how far it was snapped.
    """
    kind, reason = class_and_reason(chain, tolerance)
    return ArmClass(kind, reason())


def class_and_reason(chain: SerialChain, tolerance: float | None = None) -> tuple[str, Callable[[], str]]:
    """The class of :func:`arm_angle_class` now, and its reason later: a function that words it.

    Words that say how far a nearly S-R-S or snapped arm's poses move (:func:`redkin.srs.conventions.model_error`)
    cost a search over the joint values (about 1 s before numba is loaded), which most commands never print: a warm
    ``redkin ik`` on the Gen3 took 1.6 s with it, 1.1 s without.  The function is picklable (a
    :func:`functools.partial`).
    """
    from redkin.franka.geometry import franka_geometry
    from redkin.srs.conventions import departures
    from redkin.srs.nearly import TOLERANCE_DEFAULT, nearly_srs

    tolerance = TOLERANCE_DEFAULT if tolerance is None else check_tolerance(tolerance)
    try:
        geometry = srs_geometry(chain)
    except ValueError as exc:
        try:
            franka = franka_geometry(chain)
        except ValueError as other:
            if chain.n != 7:
                return GENERAL, partial(str, str(exc))  # the text, not the exception and its frames
            try:
                nearly = nearly_srs(chain, tolerance)
            except ValueError:
                return GENERAL, partial(str, f"{exc} (beyond the nearly S-R-S tolerance of {tolerance:g} m); {other}")
            return NEARLY_SRS, partial(_nearly_reason, nearly)
        return FRANKA, partial(_franka_reason, chain, franka)
    kind = OFFSET_ELBOW if geometry.offset_elbow else SRS
    return kind, partial(_srs_reason, chain, geometry, bool(departures(chain)))


def _nearly_reason(nearly: NearlySRS) -> str:
    return f"{nearly.describe()}, and solutions are polished on the real arm"


def _franka_reason(chain: SerialChain, franka: FrankaGeometry) -> str:
    snapped = _snapped(chain, franka.form, False) if franka.snapped else ""
    return (f"spherical shoulder, axes 5 and 6 meet, axis 7 offset a_6 {abs(franka.a6):.6g} m from axis 6, elbow "
            f"offsets {abs(franka.a3):.6g} m and {abs(franka.a4):.6g} m: the redundancy parameter is q7{snapped}")


def _srs_reason(chain: SerialChain, geometry: SRSGeometry, snapped: bool) -> str:
    lengths = f"d_se {geometry.d_se:.6g} m, d_ew {geometry.d_ew:.6g} m"
    if snapped:  # its departures are the description's rounding
        lengths += _snapped(chain, geometry.chain, True)
    if geometry.offset_elbow:
        return (f"joints 1-3 and 5-7 meet in points, joints 3-5 do not: {lengths}, elbow offsets a_3 "
                f"{geometry.a3:.6g} m, a_4 {geometry.a4:.6g} m")
    return f"joints 1-3, 3-5 and 5-7 meet in points: {lengths}"


def check_tolerance(tolerance: float | str) -> float:
    """The nearly S-R-S tolerance (a number, or its text from the command line) as a float: a finite number > 0
    (a ``RedkinError`` naming it otherwise)."""
    try:
        value = float(tolerance)
    except (TypeError, ValueError):
        raise RedkinError(f"the nearly S-R-S tolerance must be a number of metres > 0, got {tolerance!r}") from None
    if not (np.isfinite(value) and value > 0.0):
        raise RedkinError(f"the nearly S-R-S tolerance must be a finite number of metres > 0, got {tolerance!r}")
    return value


def _snapped(chain: SerialChain, exact: SerialChain, srs: bool) -> str:
    """How a description whose departures are rounding was snapped to the exact arm of its class: for an S-R-S arm
    its largest departure, and how far the poses then move."""
    from redkin.srs.conventions import departures, model_error

    position, rotation = model_error(chain, exact)
    largest = ""
    if srs:
        what, value, unit = departures(chain)[0]
        largest = f": {what} {value:.3g} {unit} at most"
    return (f" (snapped to the exact arm from the description's rounding{largest}; poses differ by up to "
            f"{position:.2g} m and {rotation:.2g} rad)")
