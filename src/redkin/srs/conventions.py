"""S-R-S arms in their makers' conventions: detection, and the same arm in paper 000's Table 1 form.

Paper 000 solves an arm written as Table 1: standard DH with every ``a_i =
0``, twists ``(-90, 90, -90, 90, -90, 90, 0)`` deg and ``d_2 = d_4 = d_6 = 0``.
A maker's description (a URDF, a DH table with other twists, modified DH,
joints turning the other way, another zero pose) describes the same
geometry differently.  What makes an arm S-R-S does not depend on the
description: at any configuration

* joints 1-3 meet in one point, the shoulder S;
* joints 5-7 meet in one point, the wrist W;
* joints 3-5 meet in one point, the elbow E (no elbow offset);
* consecutive axes are perpendicular;
* S, E and W are distinct.

An offset elbow (the Barrett WAM) keeps all but the third: joints 3-5 need
not meet, provided the common normals of joints 3-4 and of joints 4-5 meet
joint 4's axis at one point (``d_4 = 0``) and that axis passes through
neither S nor W.  Its Table 1 form has ``a_3``, ``a_4`` as the elbow offsets
(docs/srs.md, "Offset elbows").

:func:`table1_form` checks these on the joint lines at ``q = 0`` (reporting
the distances when they fail) and writes the Table 1 chain whose joints turn
about the same lines: frame 0 on joint 1's line where the base's origin
projects onto it, common normals turned so that the twists take Table 1's
signs (:func:`redkin._joint_lines.dh_rows_from_lines`), joints 3 and 5 turned
over where needed so that ``d_se`` and ``d_ew`` are not negative (``sign =
-1``), the DH angles at ``q = 0`` as offsets, the rest in ``base`` and
``tool``.  Its ``q`` and limits are the original chain's, and so is its
pose for every ``q``: the arm-angle functions take and return the user's
own joint values.
"""

from __future__ import annotations

import hashlib
from dataclasses import replace
from pathlib import Path
from weakref import WeakKeyDictionary

import numpy as np

from redkin._disk_cache import keep, kept
from redkin._joint_lines import certify_same_poses, dh_rows_from_lines, meeting_point
from redkin.chain import SerialChain
from redkin.circle import HALF_PI
from redkin.errors import NotArmAngleClassError

#: The link twists of paper 000 Table 1.
TABLE1_ALPHA = np.array([-HALF_PI, HALF_PI, -HALF_PI, HALF_PI, -HALF_PI, HALF_PI, 0.0])

#: Largest distance (metres) of a joint axis from the point where its group meets, and largest
#: ``|cos|`` between consecutive axes, for an S-R-S arm.  Tight on purpose: a chain accepted here is
#: solved in closed form as if it were exactly S-R-S, so a looser test would return wrong answers.
_SRS_TOLERANCE = 1e-9
#: Departures from S-R-S at most this large (metres, radians) are rounding of the description: pi/2 printed as
#: 1.5708 (as Kinova and UFactory print it) is 3.7e-6 rad off, which moves axes about 1e-6 m apart on a 0.3 m link;
#: :func:`table1_form` snaps them to the exact neighbour (and :mod:`redkin.franka.geometry` the Franka class).
SNAP_DISTANCE, SNAP_ANGLE = 1e-5, 1e-5
#: An elbow whose axes 3-5 miss one point by more than this is an offset elbow (the WAM's 45 mm); below it, and
#: below the tolerance of :func:`neighbour_form`, a plain elbow whose offset is dropped.
_ELBOW_OFFSET = 1e-9
_GROUPS = (("shoulder", (0, 1, 2)), ("wrist", (4, 5, 6)))
#: Chains already converted (chains are immutable): a conversion with its FK check costs about 2 ms,
#: and every arm-angle call on a chain asks for it.
_CONVERTED: WeakKeyDictionary[SerialChain, SerialChain] = WeakKeyDictionary()


def _joint_lines(chain: SerialChain) -> tuple[np.ndarray, np.ndarray]:
    """Points and unit directions of the joint lines at ``q = 0``, directions turning with positive ``q``."""
    directions, points = chain.joint_axes(np.zeros(chain.n))
    return points, directions * chain.sign[:, None]


def table1_form(chain: SerialChain) -> SerialChain:
    """The same arm as a paper 000 Table 1 chain, with the same joint values, limits and poses.

    A description whose axes miss the conditions only by rounding (every departure of
    :func:`departures` at most :data:`SNAP_DISTANCE` m and :data:`SNAP_ANGLE` rad, e.g. pi/2 written
    with 6 digits) is snapped: its exact neighbour (:func:`neighbour_form`) stands for it, and differs
    from it by no more than its own rounding.

    Raises
    ------
    ValueError
        Naming the first S-R-S condition the arm violates, with the distance
        or angle that violates it (see the module docstring).
    """
    if chain not in _CONVERTED:
        try:
            _CONVERTED[chain] = _convert(chain, _SRS_TOLERANCE)
        except NotArmAngleClassError as exact:
            if not _snaps(chain):
                raise
            try:
                _CONVERTED[chain] = neighbour_form(chain, SNAP_DISTANCE)
            except NotArmAngleClassError:
                raise exact from None
    return _CONVERTED[chain]


def neighbour_form(chain: SerialChain, tolerance: float) -> SerialChain:
    """The exact S-R-S (or offset-elbow) arm nearest a chain whose axes miss the conditions by at most
    ``tolerance`` (metres for distances, radians for angles), in Table 1 form with the chain's joint values
    and limits.

    The axes of the shoulder and of the wrist are moved, parallel to themselves, through their least-squares
    meeting points, the twists are set to Table 1's right angles, the offsets that S-R-S arms do not have are
    dropped, and the tool is chosen so that the neighbour's pose at ``q = 0`` is the chain's.  What was dropped
    is :func:`departures`; how far the poses then differ is :func:`model_error`.

    Raises
    ------
    NotArmAngleClassError
        For a departure beyond ``tolerance``, named as for an exact S-R-S arm.
    """
    return _convert(chain, tolerance)


def _snaps(chain: SerialChain) -> bool:
    """Whether every departure of the chain from S-R-S is rounding (:data:`SNAP_DISTANCE`, :data:`SNAP_ANGLE`)."""
    if chain.n != 7:
        return False
    for _, value, unit in departures(chain, SNAP_DISTANCE):
        if value > (SNAP_DISTANCE if unit == "m" else SNAP_ANGLE):
            return False
    return True


def degrees_apart(angle: float, expected: float = 90.0) -> str:
    """An angle between axes in degrees, with the fewest decimals that print it unlike ``expected``: ``89.9``,
    ``89.99996`` (not ``90``, which a fixed number of significant digits can print for an angle that is not).

    A reason text that says an angle is not what the class needs must show a different number.
    """
    for decimals in range(16):
        text = f"{angle:.{decimals}f}"
        if text != f"{expected:.{decimals}f}":
            return text
    return f"{angle!r}"


def departures(chain: SerialChain, tolerance: float = 0.0) -> list[tuple[str, float, str]]:
    """How a 7-joint chain's axes at ``q = 0`` miss the S-R-S conditions, largest first: ``(what, value, unit)``.

    Distances (``unit`` ``"m"``) are as a user measures them: two axes that must meet (the shoulder's 1-3, the
    wrist's 5-7) miss each other by the length of their common normal, and the elbow is offset along axis 4 by
    the distance between the feet of the common normals of axes 3-4 and 4-5 on it (``d_4``; an offset across
    axis 4, the WAM's ``a_3`` and ``a_4``, is the offset-elbow class's geometry, not a departure, except where it
    is at most ``tolerance``: a neighbour with that tolerance drops it).  Angles (``"rad"``) are how far
    consecutive axes are from perpendicular.  Departures below 1e-12 are left out.
    """
    points, directions = _joint_lines(chain)
    found = []
    for i, k in ((0, 1), (1, 2), (0, 2), (4, 5), (5, 6), (4, 6)):
        found.append((f"axes {i + 1} and {k + 1} miss each other by", _line_distance(points[i], directions[i],
                                                                                    points[k], directions[k]), "m"))
    upper = _normal_foot(points[2], directions[2], points[3], directions[3])
    lower = _normal_foot(points[4], directions[4], points[3], directions[3])
    found.append(("the elbow is offset along axis 4 by", float(abs((lower - upper) @ directions[3])), "m"))
    if _elbow_gap(points, directions) <= tolerance:  # a plain elbow for such a neighbour
        for i, k in ((2, 3), (3, 4)):
            found.append((f"axes {i + 1} and {k + 1} miss each other by",
                          _line_distance(points[i], directions[i], points[k], directions[k]), "m"))
    for i in range(6):
        cosine = float(abs(directions[i] @ directions[i + 1]))
        found.append((f"axes {i + 1} and {i + 2} are off perpendicular by", float(np.arcsin(min(cosine, 1.0))),
                      "rad"))
    return sorted([item for item in found if item[1] > 1e-12], key=lambda item: -item[1])


def _elbow_gap(points: np.ndarray, directions: np.ndarray) -> float:
    """How far axis 4 misses axes 3 and 5, the larger common normal: the offset across the elbow (the WAM's
    ``a_3``) as a user measures it, which a neighbour drops only within its tolerance."""
    return max(_line_distance(points[i], directions[i], points[k], directions[k]) for i, k in ((2, 3), (3, 4)))


def _normal_foot(p1: np.ndarray, u1: np.ndarray, p2: np.ndarray, u2: np.ndarray) -> np.ndarray:
    """The foot on line 2 of the common normal of lines 1 and 2 (unit directions); for parallel lines, the point
    of line 2 nearest ``p1``."""
    normal = np.cross(u1, u2)
    if float(np.linalg.norm(normal)) <= 1e-9:
        return p2 + ((p1 - p2) @ u2) * u2
    _, t, _ = np.linalg.solve(np.column_stack([u1, -u2, -normal]), p2 - p1)
    return p2 + t * u2


def model_error(chain: SerialChain, neighbour: SerialChain) -> tuple[float, float]:
    """The largest position [m] and rotation [rad] difference of the two chains' poses over all joint values.

    Each is the largest over :data:`_MODEL_SAMPLES` fixed configurations (uniform in ``[-pi, pi]^n``, the same every
    call), raised by a local search (BFGS, :func:`scipy.optimize.minimize`; the position's gradient from the
    two chains' Jacobians) from the :data:`_MODEL_STARTS` largest: a local maximum, the global one wherever the
    samples find its basin.  A rotation difference whose samples all lie below :data:`ROUNDING_ROTATION` is the
    rounding of the two FKs (axes of the same directions: the chains differ in offsets only) and is not searched.

    The search costs a command on a nearly S-R-S arm about 0.7 s as Python, so its result is kept on disk
    (:mod:`redkin._disk_cache`, under ``model-errors``), named by a digest of the two chains' kinematics and of this
    module's source: the same two chains read it back, bit for bit.
    """
    key = _model_key(chain, neighbour)
    found = kept(_MODEL_KIND, key)
    if isinstance(found, list) and len(found) == 2 and all(isinstance(value, float) for value in found):
        return found[0], found[1]
    errors = _searched_model_error(chain, neighbour)
    keep(_MODEL_KIND, key, list(errors))
    return errors


#: The folder of the kept model errors in redkin's cache (:mod:`redkin._disk_cache`).
_MODEL_KIND = "model-errors"


def _model_key(chain: SerialChain, neighbour: SerialChain) -> str:
    """The digest :func:`model_error`'s result is kept by: both chains' FK data (links, base and tool, convention)
    and the source of this module (another search is another result)."""
    digest = hashlib.sha256(Path(__file__).read_bytes())
    for each in (chain, neighbour):
        digest.update(each._links.tobytes() + each._ends.tobytes() + bytes([each._standard]))
    return digest.hexdigest()


def _searched_model_error(chain: SerialChain, neighbour: SerialChain) -> tuple[float, float]:
    """:func:`model_error`'s search."""
    from scipy.optimize import minimize

    q = np.random.default_rng(0).uniform(-np.pi, np.pi, (_MODEL_SAMPLES, chain.n))
    position, rotation = _pose_differences(chain, neighbour, q)
    scale = max(float(position.max()), 1e-300), max(float(rotation.max()), 1e-300)  # the searches see sizes near 1

    def position_and_gradient(x: np.ndarray) -> tuple[float, np.ndarray]:
        apart = chain.fk(x)[:3, 3] - neighbour.fk(x)[:3, 3]
        size = float(np.linalg.norm(apart))
        moved = chain.jacobian(x)[:3] - neighbour.jacobian(x)[:3]
        return -size / scale[0], -(apart @ moved) / (max(size, 1e-300) * scale[0])

    def rotation_only(x: np.ndarray) -> float:
        return -float(_pose_differences(chain, neighbour, x[None])[1][0]) / scale[1]

    largest = []
    for values, negated, gradient, unit in ((position, position_and_gradient, True, scale[0]),
                                            (rotation, rotation_only, False, scale[1])):
        found = float(values.max())
        if not gradient and found < ROUNDING_ROTATION:
            largest.append(found)
            continue
        for start in q[np.argsort(values)[-_MODEL_STARTS:]]:
            found = max(found, -unit * float(minimize(negated, start, jac=gradient, method="BFGS").fun))
        largest.append(found)
    return largest[0], largest[1]


#: :func:`model_error`'s sample configurations, and how many of the largest start its local search.
_MODEL_SAMPLES, _MODEL_STARTS = 4096, 4
#: A rotation difference [rad] of two chains' poses below this is the rounding of their FK (about 1e-15 for axes of
#: the same directions), not a difference of the chains: :func:`model_error` does not search it, and words say so.
ROUNDING_ROTATION = 1e-12


def _pose_differences(chain: SerialChain, neighbour: SerialChain, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The position [m] and rotation angle [rad] between the two chains' poses at joint values ``q`` (M, n)."""
    mine, theirs = chain.fk(q), neighbour.fk(q)
    position = np.linalg.norm(mine[:, :3, 3] - theirs[:, :3, 3], axis=-1)
    relative = np.einsum("nji,njk->nik", mine[:, :3, :3], theirs[:, :3, :3])
    cosine = np.clip((np.trace(relative, axis1=-2, axis2=-1) - 1.0) / 2.0, -1.0, 1.0)
    sine = np.linalg.norm(relative - np.swapaxes(relative, -1, -2), axis=(-2, -1)) / (2.0 * np.sqrt(2.0))
    return position, np.arctan2(sine, cosine)


def _line_distance(p1: np.ndarray, u1: np.ndarray, p2: np.ndarray, u2: np.ndarray) -> float:
    """The length of the common normal of two lines (unit directions): the distance a user measures between
    two axes."""
    normal = np.cross(u1, u2)
    size = float(np.linalg.norm(normal))
    if size > 1e-9:
        return float(abs((p2 - p1) @ normal) / size)
    return _distance_to_line(p2, p1, u1)


def _convert(chain: SerialChain, tolerance: float) -> SerialChain:
    """:func:`table1_form` (``tolerance`` :data:`_SRS_TOLERANCE`: the same arm) or :func:`neighbour_form`
    without the cache."""
    if chain.n != 7:
        raise NotArmAngleClassError(f"an S-R-S arm has 7 joints, {chain.name!r} has {chain.n}", chain.name)
    points, directions = _joint_lines(chain)
    centres = {}
    for name, group in _GROUPS:
        centres[name], distance = meeting_point(points[list(group)], directions[list(group)])
        gap, i, k = max((_line_distance(points[i], directions[i], points[k], directions[k]), i, k)
                        for i, k in ((group[0], group[1]), (group[1], group[2]), (group[0], group[2])))
        if max(distance, gap) > tolerance:  # the tolerance holds for the offsets as departures() reports them
            numbers = "-".join(str(k + 1) for k in group[::2])
            raise NotArmAngleClassError(f"{chain.name!r} is not S-R-S: joints {numbers} do not meet in one point: "
                                        f"axes {i + 1} and {k + 1} miss each other by {gap:.4g} m", chain.name,
                                        float(gap))
    offset_elbow = _elbow_gap(points, directions) > max(tolerance, _ELBOW_OFFSET)
    cosines = np.abs(np.sum(directions[:-1] * directions[1:], axis=-1))
    if np.arcsin(min(cosines.max(), 1.0)) > tolerance:
        k = int(np.argmax(cosines))
        off = np.degrees(np.arcsin(min(cosines[k], 1.0)))
        raise NotArmAngleClassError(f"{chain.name!r} is not S-R-S: axes {k + 1} and {k + 2} are not perpendicular "
                                    f"({degrees_apart(90.0 - off)} deg apart, {off:.3g} deg off)", chain.name,
                                    float(np.radians(off)))
    shoulder, wrist = centres["shoulder"], centres["wrist"]
    for name, centre in (("shoulder", shoulder), ("wrist", wrist)):
        if _distance_to_line(centre, points[3], directions[3]) <= _SRS_TOLERANCE:
            raise NotArmAngleClassError(f"{chain.name!r} is not S-R-S: its {name} and elbow coincide "
                                        f"(joint 4's axis passes through the {name})", chain.name, 0.0)
    # the elbow ends of the upper arm and the forearm: where the common normals meet joints 3 and 5
    upper_end = _foot(points[2], directions[2], points[3])
    lower_end = _foot(points[4], directions[4], points[3])
    sign = np.ones(7)
    sign[2] = -1.0 if (upper_end - shoulder) @ directions[2] < 0.0 else 1.0  # d_se >= 0: joint 3 points S -> E
    sign[4] = -1.0 if (wrist - lower_end) @ directions[4] < 0.0 else 1.0  # d_ew >= 0: joint 5 points E -> W
    lines = directions * sign[:, None]
    through = np.array([shoulder, shoulder, shoulder, points[3], wrist, wrist, wrist])
    base_origin = chain.base[:3, 3]
    origin = shoulder + ((base_origin - shoulder) @ lines[0]) * lines[0]
    rows, frame0, frame7 = dh_rows_from_lines(through, lines, np.sign(TABLE1_ALPHA), origin)
    # the elbow's offset along joint 4 as departures() measures it, on the description's own axes (the rows' d_4 is
    # taken from the axes moved through S and W, which a neighbour changes)
    along = abs((_normal_foot(points[4], directions[4], points[3], directions[3])
                 - _normal_foot(points[2], directions[2], points[3], directions[3])) @ directions[3])
    elbow_offset = abs(rows[3, 2]) if tolerance <= _SRS_TOLERANCE else float(along)
    if elbow_offset > tolerance:
        raise NotArmAngleClassError(
            f"{chain.name!r} is not S-R-S: joints 3-5 do not meet, and its elbow is offset {elbow_offset:.3g} m "
            "along joint 4 (only offsets across joint 4, as on the WAM, are solved)",
            chain.name, float(elbow_offset))
    a = np.zeros(7)  # rounding only, except an offset elbow's a_3 and a_4
    if offset_elbow:
        a[2:4] = rows[2:4, 0]
    d = rows[:, 2].copy()
    d[[1, 3, 5]] = 0.0  # the groups meet (d_4: checked above); their computed values are rounding
    converted = SerialChain(  # the twists are Table 1's by construction: rows[:, 1] only rounds them
        a=a, alpha=TABLE1_ALPHA, d=d,
        offset=rows[:, 3], sign=sign, lower=chain.lower, upper=chain.upper, **chain.motion_limits, base=frame0,
        tool=np.linalg.inv(frame7) @ chain.fk(np.zeros(7)), convention="dh", name=chain.name,
        source=f"{chain.source} (as paper 000 Table 1)", joint_names=chain.joint_names,
    )
    if tolerance > _SRS_TOLERANCE:  # a neighbour: its rows are snapped, so its tool makes the poses at q = 0 agree
        home = replace(converted, tool=np.eye(4)).fk(np.zeros(7))
        converted = replace(converted, tool=np.linalg.inv(home) @ chain.fk(np.zeros(7)),
                            source=f"{chain.source} (its exact S-R-S neighbour, as paper 000 Table 1)")
    if np.cos(converted.offset[2]) < 0.0:  # the reference plane theta_3 = 0 where the chain's own q_3 = 0
        converted = _elbow_pair_turned(converted)
    if tolerance <= _SRS_TOLERANCE:
        certify_same_poses(chain, converted, "Table 1 form")
    return converted


def _elbow_pair_turned(chain: SerialChain) -> SerialChain:
    """The same arm with theta_3 and theta_5 turned by pi, theta_4 negated and a_3, a_4 negated.

    Table 1 form has this symmetry: ``Rz(pi)`` commutes with ``Tz`` and turns
    ``Rx(alpha)``, ``Tx(a)`` into ``Rx(-alpha)``, ``Tx(-a)``, so both
    descriptions give the same pose for every ``q``.  Of the two, the one
    with ``|offset_3| <= pi/2`` is kept, so that the arm angle does not
    depend on which one a description happens to give.
    """
    offset, sign, a = chain.offset.copy(), chain.sign.copy(), chain.a.copy()
    offset[[2, 4]] = np.mod(offset[[2, 4]], 2.0 * np.pi) - np.pi  # turned by pi, in [-pi, pi)
    offset[3], sign[3] = -offset[3], -sign[3]
    a[2:4] = -a[2:4]
    return replace(chain, a=a, offset=offset, sign=sign)


def _foot(point: np.ndarray, direction: np.ndarray, other_point: np.ndarray) -> np.ndarray:
    """The point of a line closest to a line perpendicular to it through ``other_point`` (their common
    normal's foot)."""
    return point + ((other_point - point) @ direction) * direction


def _distance_to_line(point: np.ndarray, line_point: np.ndarray, direction: np.ndarray) -> float:
    """Distance of a point from a line with unit direction."""
    across = point - line_point
    return float(np.linalg.norm(across - (across @ direction) * direction))
