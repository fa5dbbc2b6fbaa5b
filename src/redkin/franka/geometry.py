"""The Franka class: detection in any description, and the arm in the form the q7 solver reads (docs/franka.md).

A 7R arm is of the Franka class when, at any configuration,

* axes 1-3 meet in one point, the shoulder S (a spherical shoulder);
* axes 3, 4 and 5 form an offset elbow as on the Barrett WAM: axis 4 is
  perpendicular to axes 3 and 5 and the common normals of axes 3-4 and 4-5
  meet axis 4 in one point (the elbow offsets ``a_3``, ``a_4`` may be zero);
* axes 5 and 6 meet in one point, the wrist point W;
* axis 7 is perpendicular to axis 6 and misses it by an offset ``a_6 > 0``
  (0.088 m on the Panda and the FR3);
* consecutive axes are perpendicular.

Fixing q7 and the flange pose fixes frame 6 and so W; the distance
``|W - S|`` then fixes q4 and the rest follows in closed form
(:mod:`redkin.franka.ik`).  :func:`franka_geometry` checks the conditions on
the joint lines at ``q = 0`` (naming the first one that fails with the
offset or angle that breaks it) and writes the same arm as standard DH rows
with paper 000 Table 1's twists ``(-90, 90, -90, 90, -90, 90, 0)`` deg,

    ``a = (0, 0, a_3, a_4, 0, a_6, 0)``, ``d = (d_1, 0, d_3, 0, d_5, d_6, 0)``,

the DH angle ``theta_k = offset_k + q_k`` of each joint turning the way the
chain's own ``q_k`` turns, the rest in ``base`` and ``tool``: the user's
joint values, limits and poses are kept (checked by FK on sample
configurations).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np

from redkin._joint_lines import certify_same_poses, dh_rows_from_lines, meeting_point
from redkin.chain import SerialChain
from redkin.errors import NotArmAngleClassError, RedkinError
from redkin.srs.branches import BRANCHES, Branch, parse_branch
from redkin.srs.conventions import TABLE1_ALPHA
from redkin.srs.geometry import elbow_equation

#: Largest distance (metres) between axes that must meet, and largest ``|cos|`` between axes that must be
#: perpendicular.  Tight on purpose, as for S-R-S arms: an arm accepted here is solved as if it were exactly of the
#: class.
_CLASS_TOLERANCE = 1e-9
#: The largest difference of a pose entry between a description and its snapped form (rounding of the description).
_SNAP_POSE = 1e-4
_CACHE_KEY = "_franka_geometry"
# Columns of :attr:`FrankaGeometry.kernel_arm`.
D1, A3, D3, A4, D5, A6, D6, MEAN, AMPLITUDE, PHASE = range(10)
#: Where :attr:`FrankaGeometry.kernel_table` holds each table, one after another: ``kernel_arm`` (10,), then
#: ``kernel_ends`` (2, 4, 4), ``kernel_branches`` (8, 3) and ``kernel_joints`` (5, 7), each flattened.
TABLE_ENDS, TABLE_BRANCHES, TABLE_JOINTS, TABLE_SIZE = 10, 42, 66, 101


@dataclass(frozen=True, eq=False)
class FrankaGeometry:
    """A Franka-class arm reduced to what the q7 solver needs.

    Attributes
    ----------
    chain : SerialChain
        The chain it was built from (joint values ``q`` refer to it).
    form : SerialChain
        The same arm in the solver's DH form (module docstring), with the same joint values, limits and poses.
    d1, a3, d3, a4, d5, a6, d6 : float
        The lengths of that form: base to shoulder, the elbow (``a_3``, ``d_3``, ``a_4``, ``d_5``), the wrist offset
        ``a_6`` of axis 7 from axis 6, and ``d_6``, how far along axis 6 from W the offset starts (0 on the Panda).
    """

    chain: SerialChain
    form: SerialChain
    d1: float
    a3: float
    d3: float
    a4: float
    d5: float
    a6: float
    d6: float
    snapped: bool = False

    @cached_property
    def kernel_arm(self) -> np.ndarray:
        """The arm as :mod:`redkin.franka._kernels` reads it: ``d1, a3, d3, a4, d5, a6, d6, C, R, phi`` with the
        elbow equation ``|W - S|^2 = C + R cos(theta_4 - phi)`` ([F2] in docs/franka.md)."""
        equation = elbow_equation(self.a3, self.a4, self.d3, self.d5)
        return _read_only(np.array([self.d1, self.a3, self.d3, self.a4, self.d5, self.a6, self.d6, *equation]))

    @cached_property
    def kernel_ends(self) -> np.ndarray:
        """``base^-1`` and ``tool^-1`` of the form, (2, 4, 4): frame 7 in frame 0 is ``base^-1 pose tool^-1``."""
        return _read_only(np.linalg.inv(np.stack([self.form.base, self.form.tool])))

    @cached_property
    def kernel_joints(self) -> np.ndarray:
        """``offset, sign, wrap, lower, upper`` (5, 7) of the form: ``q = theta - offset`` shifted into range
        (:func:`redkin.srs._ik_kernels.chain_values`)."""
        form = self.form
        table = np.stack([form.offset, form.sign, np.ones(7), form.lower, form.upper])
        return _read_only(table)

    @cached_property
    def kernel_limits(self) -> np.ndarray:
        """``lower, upper, limited`` (3, 7) in the form's DH angles ``theta``; ``limited`` is 0 for a joint whose
        range covers the circle (no constraint modulo ``2 pi``)."""
        form = self.form
        limited = ~form.covers_circle
        lower = np.where(limited, form.offset + form.lower, 0.0)
        upper = np.where(limited, form.offset + form.upper, 0.0)
        return _read_only(np.stack([lower, upper, limited.astype(float)]))

    @cached_property
    def branch_senses(self) -> np.ndarray:
        """Per branch sign (shoulder, elbow, wrist), +1 or -1: turned over where the DH zero of joint 2 (the
        shoulder) or of joint 5 (the wrist) is nearer ``theta = pi`` than 0, so that a branch names the signs of
        the user's own ``q_2`` and ``cos q_5``."""
        offset = self.form.offset
        return np.array([1.0 if np.cos(offset[1]) >= 0.0 else -1.0, 1.0,
                         1.0 if np.cos(offset[4]) >= 0.0 else -1.0])

    @cached_property
    def kernel_branches(self) -> np.ndarray:
        """The solver's signs ``(shoulder, elbow, wrist)`` of each branch of :data:`BRANCHES`, (8, 3)."""
        return _read_only(np.array(BRANCHES, dtype=float) * self.branch_senses)

    @cached_property
    def kernel_table(self) -> np.ndarray:
        """:attr:`kernel_arm`, :attr:`kernel_ends`, :attr:`kernel_branches` and :attr:`kernel_joints` in one array
        (:data:`TABLE_SIZE`,), each from its ``TABLE_`` offset: what a one-pose call passes as one argument (numba
        unboxes each argument of a call: one array instead of four takes about 0.75 us less)."""
        return _read_only(np.concatenate([self.kernel_arm, self.kernel_ends.ravel(), self.kernel_branches.ravel(),
                                          self.kernel_joints.ravel()]))

    def branch_index(self, branch: str | Branch | tuple[int, int, int]) -> int:
        """Index into :data:`BRANCHES` of a branch given as ``"+-+"`` or three signs.

        Raises
        ------
        ValueError
            For a malformed branch (:func:`redkin.srs.branches.parse_branch`).
        """
        return BRANCHES.index(parse_branch(branch))


def _read_only(array: np.ndarray) -> np.ndarray:
    array = np.ascontiguousarray(array, dtype=float)
    array.setflags(write=False)
    return array


def franka_geometry(chain: SerialChain) -> FrankaGeometry:
    """The q7 solver's view of a Franka-class arm, in any description (derived once per chain and cached on it).

    Raises
    ------
    NotArmAngleClassError
        Naming the first condition of the class (module docstring) that the
        arm breaks, with the offset or angle that breaks it (a
        ``ValueError``; its ``distance`` attribute holds that measure).
    RedkinError
        If ``chain`` is not a :class:`~redkin.chain.SerialChain`.
    """
    if not isinstance(chain, SerialChain):
        raise RedkinError(f"chain must be a SerialChain, got {type(chain).__name__}")
    cached = chain.__dict__.get(_CACHE_KEY)
    if cached is None:
        cached = _derive(chain)
        object.__setattr__(chain, _CACHE_KEY, cached)
    if isinstance(cached, NotArmAngleClassError):
        raise NotArmAngleClassError(str(cached), cached.chain_name, cached.distance)
    return cached


def _derive(chain: SerialChain) -> FrankaGeometry | NotArmAngleClassError:
    """:func:`franka_geometry` without the cache; a refusal is returned (and cached) rather than raised.

    A description that misses the class only by rounding (axes off by at most
    :data:`redkin.srs.conventions.SNAP_DISTANCE` m and :data:`~redkin.srs.conventions.SNAP_ANGLE` rad, e.g.
    UFactory's xArm7 URDF with pi/2 printed as 1.5708) is snapped to the exact arm, as S-R-S arms are.
    """
    try:
        return _convert(chain, snap=False)
    except NotArmAngleClassError as refusal:
        try:
            return _convert(chain, snap=True)
        except NotArmAngleClassError:
            return refusal


def _refuse(chain: SerialChain, reason: str, distance: float) -> NotArmAngleClassError:
    return NotArmAngleClassError(f"{chain.name!r} is not of the Franka class: {reason}", chain.name, distance)


def _line_distance(p1: np.ndarray, u1: np.ndarray, p2: np.ndarray, u2: np.ndarray) -> float:
    """Distance between two lines (unit directions)."""
    normal = np.cross(u1, u2)
    size = np.linalg.norm(normal)
    across = p2 - p1
    if size < 1e-12:
        return float(np.linalg.norm(across - (across @ u1) * u1))
    return float(abs(across @ normal) / size)


def _convert(chain: SerialChain, snap: bool) -> FrankaGeometry:
    """The Franka-class form of a chain (exact, or snapped from rounding); a refusal names the first condition the
    chain breaks."""
    from redkin.srs.conventions import SNAP_ANGLE, SNAP_DISTANCE, degrees_apart

    distance, angle_tolerance = (SNAP_DISTANCE, np.sin(SNAP_ANGLE)) if snap else (_CLASS_TOLERANCE, _CLASS_TOLERANCE)
    if chain.n != 7:
        raise _refuse(chain, f"it has {chain.n} joints, not 7", 0.0)
    directions, points = chain.joint_axes(np.zeros(7))
    directions = directions * chain.sign[:, None]
    cosines = np.abs(np.sum(directions[:-1] * directions[1:], axis=-1))
    if cosines.max() > angle_tolerance:
        k = int(np.argmax(cosines))
        angle = float(np.degrees(np.arccos(np.clip(cosines[k], 0.0, 1.0))))
        raise _refuse(chain, f"axes {k + 1} and {k + 2} are {degrees_apart(angle)} deg apart, not 90",
                      np.radians(90.0 - angle))
    for first, second in ((0, 1), (1, 2), (0, 2), (4, 5)):
        gap = _line_distance(points[first], directions[first], points[second], directions[second])
        if gap > distance:
            raise _refuse(chain, f"axes {first + 1} and {second + 1} miss each other by {gap:.6g} m "
                                 f"(they must meet)", gap)
    wrist_offset = _line_distance(points[5], directions[5], points[6], directions[6])
    if wrist_offset <= _CLASS_TOLERANCE:
        raise _refuse(chain, "axes 6 and 7 meet (no wrist offset): an S-R-S wrist, solved by the arm angle instead",
                      wrist_offset)
    shoulder = meeting_point(points[:3], directions[:3])[0]
    wrist = meeting_point(points[4:6], directions[4:6])[0]
    through = np.array([shoulder, shoulder, shoulder, points[3], wrist, wrist, points[6]])
    origin = shoulder + ((chain.base[:3, 3] - shoulder) @ directions[0]) * directions[0]
    rows, frame0, frame7 = dh_rows_from_lines(through, directions, np.sign(TABLE1_ALPHA), origin)
    if abs(rows[3, 2]) > distance:
        raise _refuse(chain, f"its elbow is offset {abs(rows[3, 2]):.6g} m along axis 4 (only offsets across axis 4, "
                             "as on the WAM and the Panda, are solved)", abs(rows[3, 2]))
    a3, a4, d3, d5 = rows[2, 0], rows[3, 0], rows[2, 2], rows[4, 2]
    # elbow offsets within the tolerance are the rounding of an arm without them: zero, so that the limit functions
    # that are squares on such an arm are taken as such (redkin.franka._kernels.halved)
    a3, a4 = (0.0 if abs(a3) <= distance else a3), (0.0 if abs(a4) <= distance else a4)
    if elbow_equation(a3, a4, d3, d5).amplitude <= _CLASS_TOLERANCE:
        raise _refuse(chain, "axis 4 passes through the shoulder or the wrist point, so |W - S| does not fix q4", 0.0)
    a = np.array([0.0, 0.0, a3, a4, 0.0, rows[5, 0], 0.0])
    d = np.array([rows[0, 2], 0.0, d3, 0.0, d5, rows[5, 2], 0.0])
    form = SerialChain(
        a=a, alpha=TABLE1_ALPHA, d=d, offset=rows[:, 3], lower=chain.lower, upper=chain.upper, **chain.motion_limits,
        base=frame0,
        tool=np.linalg.inv(frame7) @ chain.fk(np.zeros(7)), convention="dh", name=chain.name,
        source=f"{chain.source} (in the Franka-class DH form)", joint_names=chain.joint_names,
    )
    if snap:  # the snapped rows: a tool that makes the poses at q = 0 agree, and poses that differ by rounding only
        home = replace(form, tool=np.eye(4)).fk(np.zeros(7))
        form = replace(form, tool=np.linalg.inv(home) @ chain.fk(np.zeros(7)))
        q = np.random.default_rng(0).uniform(-np.pi, np.pi, (16, 7))
        error = float(np.max(np.abs(form.fk(q) - chain.fk(q))))
        if error > _SNAP_POSE:
            raise _refuse(chain, f"snapped to the class, its poses move by {error:.3g} m", error)
    else:
        certify_same_poses(chain, form, "Franka-class form")
    return FrankaGeometry(chain=chain, form=form, d1=float(d[0]), a3=float(a3), d3=float(d3), a4=float(a4),
                          d5=float(d5), a6=float(a[5]), d6=float(d[5]), snapped=snap)
