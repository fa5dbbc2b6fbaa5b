"""Serial chains of revolute joints described by DH or modified DH rows.

A :class:`SerialChain` holds one row per joint and the joint-to-DH map
``theta_i = offset_i + sign_i * q_i`` (thesis 001 Table 2.1 writes its theta
column as ``-pi/2 + theta_1``, ``-pi/2 - theta_3``, ...).  Two conventions:

* ``"dh"`` (standard, Denavit-Hartenberg):
  ``A_i = Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i)``, joint ``i`` turns about
  the z axis of frame ``i-1`` (paper 000 Table 1, paper 003 Table 1).
* ``"mdh"`` (modified, Craig): ``A_i = Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(theta_i)
  Tz(d_i)``, joint ``i`` turns about the z axis of frame ``i``
  [001 eq. 2.1]).  Row ``i`` stores ``alpha_{i-1}`` and ``a_{i-1}``.

The end pose is ``base @ A_1 ... A_n @ tool``.  Every kinematic function is
batched over leading axes: ``q`` has shape ``(..., n)``.

The kinematics are computed by the compiled kernels of
:mod:`redkin._chain_kernels` (numba), one configuration and batches alike;
the methods here validate their inputs and call them.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, fields, replace
from functools import cached_property
from typing import Any, Literal, NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from redkin import _chain_kernels as kernels
from redkin._compiled import kernel_array, run_batch
from redkin._validation import (
    MAX_LENGTH,
    as_float_array,
    check_finite,
    check_magnitude,
    check_output_array,
    check_pose,
    check_vectors,
)
from redkin.circle import TWO_PI
from redkin.errors import RedkinError

Convention = Literal["dh", "mdh"]
#: The limits of motion a chain carries, and their units.
_MOTION_UNITS = {"velocity": "rad/s", "acceleration": "rad/s^2", "jerk": "rad/s^3"}
_NO_OFFSET = np.zeros((1, 3))
#: Slack of the reach bound, relative to the chain's size (``|c| + r`` of :attr:`SerialChain.reach_bound`): rounding
#: in FK is about 1e-15 of it, so a distance beyond the bound by more than this is no rounding.
_REACH_ROUNDING = 1e-9


class Reach(NamedTuple):
    """Target poses against an arm's reach: a distance that every joint vector keeps within ``[lower, upper]``.

    :meth:`SerialChain.reach` measures any chain against its links' lengths; the closed forms measure their class's
    own distance (the shoulder-wrist distance of S-R-S arms [000 eq. 11], of the Franka class over every q7), and
    know a minimum.  A pose whose distance lies outside the range has no solution, whatever a solver tries.

    Attributes
    ----------
    distance : numpy.ndarray, shape (...)
        Metres: what ``measure`` names, per pose.
    lower, upper : float
        Metres: the range of that distance over all joint values (``lower`` 0 where no minimum is known).
    out : numpy.ndarray of bool, shape (...)
        Proven out of reach: the distance lies outside the range by more than rounding (and than the tolerance a
        solver certifies its solutions to, where it gave one).
    measure : str
        What ``distance`` is, in words that read before "is 9.86 m": ``"the shoulder-wrist distance"``.
    """

    distance: np.ndarray
    lower: float
    upper: float
    out: np.ndarray
    measure: str

    @property
    def miss(self) -> np.ndarray:
        """Metres by which each distance lies outside ``[lower, upper]`` (beyond ``upper``, or short of ``lower``);
        0 within."""
        return np.maximum(np.maximum(self.distance - self.upper, self.lower - self.distance), 0.0)


def _frozen(values: ArrayLike | None, n: int, name: str, default: float | None = None) -> np.ndarray:
    if values is None:
        values = np.full(n, default)
    array = as_float_array(values, name).reshape(-1)
    if array.shape != (n,):
        raise RedkinError(f"{name} must have {n} entries (one per joint), got {array.size}")
    array = array.copy()
    array.setflags(write=False)
    return array


@dataclass(frozen=True, eq=False, init=False)
class SerialChain:
    """A serial chain of revolute joints.

    Parameters
    ----------
    a, alpha, d : array_like, shape (n,)
        Link length, link twist (radians) and link offset of each row.
        In the ``"mdh"`` convention row ``i`` holds ``a_{i-1}`` and ``alpha_{i-1}``.
    convention : {"dh", "mdh"}
        Standard or modified (Craig) Denavit-Hartenberg.
    offset, sign : array_like, shape (n,), optional
        ``theta_i = offset_i + sign_i * q_i``; defaults 0 and +1.  A sign must be +1 or -1.
    lower, upper : array_like, shape (n,), optional
        Joint limits on ``q`` in radians; default ``-inf`` and ``+inf``.
        Only a joint with both limits infinite (a continuous joint) is
        unlimited: a finite range is a range however wide, and one wider than
        ``2 pi`` (a Sawyer's +-270 deg wrist) holds some angles twice.
    base, tool : array_like, shape (4, 4), optional
        Fixed transforms before the first and after the last row.
    name : str
        Display name.
    source : str
        Where the numbers come from.
    joint_names : sequence of str, optional
        One name per joint (a URDF's joint names); default ``joint 1`` .. ``joint n``.
    velocity : array_like, shape (n,), optional
        Joint speed limits ``|dq_i/dt| <= velocity_i`` in rad/s, each finite and positive, or ``inf`` where
        unknown; default all unknown.  Kinematics never read them; a path's default step bound does
        (:func:`redkin.paths.step_bound`), and so does its timing (:func:`redkin.paths.time_path`).
    acceleration, jerk : array_like, shape (n,), optional
        Joint acceleration limits ``|d2q_i/dt2| <= acceleration_i`` (rad/s^2) and jerk limits (rad/s^3), as
        ``velocity``: finite and positive, or ``inf`` where unknown (the default).  A URDF carries neither; a
        limits file (:func:`redkin.motion_limits.read_motion_limits`) or a maker's data sheet does.
    """

    # The fields are what the constructor stores (read-only float arrays, 4x4 matrices, a tuple of names); it takes
    # array-likes and None for the defaults, so it is written out rather than generated (dataclass init=False).
    a: np.ndarray
    alpha: np.ndarray
    d: np.ndarray
    convention: Convention
    offset: np.ndarray
    sign: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    base: np.ndarray
    tool: np.ndarray
    name: str
    source: str
    joint_names: tuple[str, ...]
    velocity: np.ndarray
    acceleration: np.ndarray
    jerk: np.ndarray
    _standard: bool = field(init=False, repr=False)
    _links: np.ndarray = field(init=False, repr=False)
    _ends: np.ndarray = field(init=False, repr=False)
    _bounds: np.ndarray = field(init=False, repr=False)

    def __init__(
        self,
        a: ArrayLike,
        alpha: ArrayLike,
        d: ArrayLike,
        convention: Convention = "dh",
        offset: ArrayLike | None = None,
        sign: ArrayLike | None = None,
        lower: ArrayLike | None = None,
        upper: ArrayLike | None = None,
        base: ArrayLike | None = None,
        tool: ArrayLike | None = None,
        name: str = "chain",
        source: str = "",
        joint_names: Sequence[str] = (),
        velocity: ArrayLike | None = None,
        acceleration: ArrayLike | None = None,
        jerk: ArrayLike | None = None,
    ) -> None:
        if convention not in ("dh", "mdh"):
            raise RedkinError(f"convention must be 'dh' or 'mdh', got {convention!r}")
        object.__setattr__(self, "convention", convention)
        object.__setattr__(self, "name", name)
        object.__setattr__(self, "source", source)
        a = as_float_array(a, "a").reshape(-1)
        n = a.size
        if n == 0:
            raise RedkinError("a chain needs at least one joint, got 0 rows")
        values = {
            "a": _frozen(a, n, "a"),
            "alpha": _frozen(alpha, n, "alpha"),
            "d": _frozen(d, n, "d"),
            "offset": _frozen(offset, n, "offset", 0.0),
            "sign": _frozen(sign, n, "sign", 1.0),
            "lower": _frozen(lower, n, "lower", -np.inf),
            "upper": _frozen(upper, n, "upper", np.inf),
            "velocity": _frozen(velocity, n, "velocity", np.inf),
            "acceleration": _frozen(acceleration, n, "acceleration", np.inf),
            "jerk": _frozen(jerk, n, "jerk", np.inf),
        }
        for key in ("a", "alpha", "d", "offset", "sign"):
            check_finite(values[key], key)
        for key in ("a", "d"):  # finite but absurd lengths (1e308 m) would overflow in the products
            check_magnitude(values[key], key, MAX_LENGTH, "m")
        if not np.all(np.isin(values["sign"], (-1.0, 1.0))):
            raise RedkinError(f"sign entries must be +1 or -1, got {values['sign'].tolist()}")
        if np.any(np.isnan(values["lower"])) or np.any(np.isnan(values["upper"])):
            raise RedkinError("joint limits must not be NaN")
        bad = np.flatnonzero(values["lower"] > values["upper"])
        if bad.size:
            i = int(bad[0])
            raise RedkinError(
                f"joint {i + 1}: lower limit {values['lower'][i]:g} exceeds upper limit {values['upper'][i]:g}"
            )
        for key, unit in _MOTION_UNITS.items():
            if not np.all(values[key] > 0.0):  # NaN fails too
                raise RedkinError(f"{key} limits must be > 0 {unit}, or inf where unknown, got {values[key].tolist()}")
        for key, given in (("base", base), ("tool", tool)):
            matrix = np.eye(4) if given is None else check_pose(given, key)
            if matrix.shape != (4, 4):
                raise RedkinError(f"{key} must have shape (4, 4), got {matrix.shape}")
            matrix = matrix.copy()  # its translation within MAX_LENGTH: check_pose
            matrix.setflags(write=False)
            values[key] = matrix
        names = tuple(str(v) for v in joint_names) or tuple(f"joint {i + 1}" for i in range(n))
        if len(names) != n:
            raise RedkinError(f"joint_names must have {n} entries (one per joint), got {len(names)}")
        for key, value in values.items():
            object.__setattr__(self, key, value)
        object.__setattr__(self, "joint_names", names)
        # what the kernels read (redkin._chain_kernels): one row per joint, and base and tool
        links = np.stack([self.offset, self.sign, self.a, self.d, *_cos_sin(self.alpha)], axis=-1)
        object.__setattr__(self, "_standard", self.convention == "dh")
        object.__setattr__(self, "_links", np.ascontiguousarray(links))
        object.__setattr__(self, "_ends", np.ascontiguousarray(np.stack([self.base, self.tool])))
        object.__setattr__(self, "_bounds", np.ascontiguousarray(np.stack([self.lower, self.upper])))

    # ------------------------------------------------------------------ basics
    @property
    def n(self) -> int:
        """Number of joints."""
        return int(self.a.size)

    @property
    def limits(self) -> np.ndarray:
        """Joint limits as an array of shape ``(n, 2)`` (lower, upper)."""
        return np.stack([self.lower, self.upper], axis=-1)

    @property
    def limited(self) -> np.ndarray:
        """Boolean mask of joints with a hard stop (a finite limit); only a continuous joint is unlimited."""
        return np.isfinite(self.lower) | np.isfinite(self.upper)

    @property
    def covers_circle(self) -> np.ndarray:
        """Boolean mask of joints whose range holds every angle modulo ``2 pi`` (width ``>= 2 pi``, or unlimited).

        Such a joint constrains no angle taken modulo ``2 pi`` (the feasible arm angles, [000 eq. 20]), yet its
        value must still be chosen inside the range (:meth:`nearest_in_range`).
        """
        return (self.upper - self.lower) >= TWO_PI

    @property
    def middle(self) -> np.ndarray:
        """The middle of each joint's range: half a turn inside the finite end of a half-open range, 0 for an
        unlimited joint (the default target of :meth:`nearest_in_range`)."""
        return np.array([kernels.range_middle(lo, hi) for lo, hi in zip(self.lower.tolist(), self.upper.tolist())])

    def with_limits(self, lower: ArrayLike, upper: ArrayLike) -> SerialChain:
        """A copy of this chain with other joint limits."""
        return self._replaced(lower=lower, upper=upper)

    def with_velocity(self, velocity: ArrayLike | None) -> SerialChain:
        """A copy of this chain with other joint speed limits (rad/s, ``inf`` where unknown; ``None``: none known)."""
        return self._replaced(velocity=velocity)

    def with_motion_limits(self, **limits: ArrayLike | None) -> SerialChain:
        """A copy of this chain with other limits of motion: any of ``velocity`` (rad/s), ``acceleration``
        (rad/s^2) and ``jerk`` (rad/s^3), each ``inf`` where unknown (``None``: none known); the others kept."""
        unknown = sorted(set(limits) - set(_MOTION_UNITS))
        if unknown:
            raise RedkinError(f"limits of motion are {', '.join(_MOTION_UNITS)}; got {', '.join(unknown)}")
        return self._replaced(**limits)

    @property
    def motion_limits(self) -> dict[str, np.ndarray]:
        """The limits of motion by name (``velocity``, ``acceleration``, ``jerk``), ``inf`` where unknown."""
        return {key: getattr(self, key) for key in _MOTION_UNITS}

    @property
    def velocity_known(self) -> np.ndarray:
        """Boolean mask of joints with a known speed limit (a finite :attr:`velocity`)."""
        return np.isfinite(self.velocity)

    @property
    def own_joint_names(self) -> np.ndarray:
        """Boolean mask of joints with a name of their own, not the default ``"joint k"`` (1-based) that the named
        models and chains built without names carry."""
        return np.array([name != f"joint {k + 1}" for k, name in enumerate(self.joint_names)], dtype=bool)

    def joints_in_words(self, joints: Sequence[int]) -> str:
        """Joints (0-based indices) in words: ``"joint 2"`` or ``"joints 2, 5 (A5)"``, 1-based, each with its name
        where the chain has one of its own (:attr:`own_joint_names`)."""
        own = self.own_joint_names
        named = [f"{k + 1} ({self.joint_names[k]})" if own[k] else f"{k + 1}" for k in joints]
        return ("joints " if len(named) > 1 else "joint ") + ", ".join(named)

    def with_tool(self, tool: ArrayLike) -> SerialChain:
        """A copy of this chain with another tool transform."""
        return self._replaced(tool=tool)

    def with_base(self, base: ArrayLike) -> SerialChain:
        """A copy of this chain with another base transform."""
        return self._replaced(base=base)

    def _replaced(self, **changes: ArrayLike | None) -> SerialChain:
        """``dataclasses.replace`` through the constructor, which takes array-likes where the fields hold arrays."""
        arguments: dict[str, Any] = {f.name: getattr(self, f.name) for f in fields(self) if f.init}
        return SerialChain(**{**arguments, **changes})

    @cached_property
    def reach_bound(self) -> tuple[np.ndarray, float]:
        """A point ``c`` on joint 1's axis (base frame) and a radius ``r``: at every joint vector, the tool point
        lies within ``r`` of ``c``.

        Between the turns of consecutive joints the chain is a fixed transform; let ``t_k`` be the translation of the
        one after joint ``k`` (the last one with the tool), in the frame of joint ``k``'s turn: ``(a_k, 0, d_k)``
        (standard DH: ``Tz(d_k) Tx(a_k) Rx(alpha_k)``; modified DH: ``Tz(d_k) Rx(alpha_k) Tx(a_k)`` with the next
        row's ``a``, ``alpha``).  A turn about an axis through the origin keeps lengths, so by the triangle
        inequality the tool point lies within ``r = |t_1 - (t_1 . z) z| + |t_2| + ... + |t_n|`` of ``c``, the point
        ``(t_1 . z) z`` on joint 1's axis (which joint 1 does not move).  The bound is reached where the translations
        line up (a stretched S-R-S arm: ``d_se + d_ew + d_wt`` from the shoulder).
        """
        a, alpha, d, n = self.a, self.alpha, self.d, self.n
        steps = []
        for k in range(n):
            if self._standard:
                step = _translation(0.0, 0.0, d[k]) @ _translation(a[k], 0.0, 0.0) @ _twist(alpha[k])
            elif k + 1 < n:
                step = _translation(0.0, 0.0, d[k]) @ _twist(alpha[k + 1]) @ _translation(a[k + 1], 0.0, 0.0)
            else:
                step = _translation(0.0, 0.0, d[k])
            steps.append(step)
        steps[-1] = steps[-1] @ self.tool
        first = self.base if self._standard else self.base @ _twist(alpha[0]) @ _translation(a[0], 0.0, 0.0)
        along = float(steps[0][2, 3])
        centre = first[:3, 3] + along * first[:3, 2]
        radius = float(np.hypot(steps[0][0, 3], steps[0][1, 3]) + sum(np.linalg.norm(s[:3, 3]) for s in steps[1:]))
        centre.setflags(write=False)
        return centre, radius

    def reach(self, pose: ArrayLike, tolerance: float = 0.0) -> Reach:
        """Target poses against :attr:`reach_bound`: the tool point's distance from its point on joint 1's axis.

        Parameters
        ----------
        pose : array_like, shape (..., 4, 4)
            Target poses of the tool in the base frame (only their positions are read).
        tolerance : float
            Metres a target may lie beyond the bound and still count as reached: the position tolerance of a
            solver's certificate.

        Returns
        -------
        Reach
            ``lower`` 0 (no minimum known for a general chain); ``out`` where the distance exceeds the radius by
            more than ``tolerance`` and rounding (:data:`_REACH_ROUNDING` of the chain's size).

        Raises
        ------
        RedkinError
            For poses that are not ``(..., 4, 4)`` arrays with finite positions, or a negative tolerance.
        """
        pose = as_float_array(pose, "pose")
        if pose.ndim < 2 or pose.shape[-2:] != (4, 4):
            raise RedkinError(f"pose must have shape (..., 4, 4), got shape {pose.shape}")
        check_finite(pose[..., :3, 3], "pose position")
        if not tolerance >= 0.0:
            raise RedkinError(f"tolerance must be a number of metres >= 0, got {tolerance!r}")
        centre, radius, slack, measure = self._reach_table
        offset = pose[..., :3, 3] - centre
        distance = np.sqrt(np.sum(offset * offset, axis=-1))
        return Reach(distance, 0.0, radius, distance > radius + slack + tolerance, measure)

    @cached_property
    def _reach_table(self) -> tuple[np.ndarray, float, float, str]:
        """What :meth:`reach` reads: :attr:`reach_bound`, its rounding slack and the words of its measure."""
        centre, radius = self.reach_bound
        x, y, z = (f"{round(float(v), 6) + 0.0:.6f}".rstrip("0").rstrip(".") for v in centre)  # to the micrometre
        return (centre, radius, _REACH_ROUNDING * (radius + float(np.linalg.norm(centre))),
                f"the tool point's distance from ({x}, {y}, {z}) m on joint 1's axis")

    def check_q(self, q: ArrayLike, name: str = "q") -> np.ndarray:
        """Validate joint vectors: finite, shape ``(..., n)``; return them as floats."""
        return check_vectors(q, self.n, name)

    def _flat(self, q: ArrayLike) -> tuple[np.ndarray, tuple[int, ...]]:
        """Validated joint vectors as the kernels take them (C-contiguous float64, ``(N, n)``) and their
        leading shape."""
        q = self.check_q(q)
        return np.ascontiguousarray(q.reshape(-1, self.n)), q.shape[:-1]

    def dh_angles(self, q: np.ndarray) -> np.ndarray:
        """The DH angles ``theta = offset + sign * q``."""
        return self.offset + self.sign * q

    # ------------------------------------------------------------- public API
    def fk(self, q: ArrayLike, *, out: np.ndarray | None = None) -> np.ndarray:
        """End pose ``base @ A_1(q_1) ... A_n(q_n) @ tool``.

        Parameters
        ----------
        q : array_like, shape (..., n)
            Joint angles in radians.
        out : numpy.ndarray, shape (..., 4, 4), optional
            A C-contiguous float64 array to write the poses into, returned: a loop over batches of one size into
            one buffer skips a fresh output's allocation and page faults every call.

        Returns
        -------
        numpy.ndarray, shape (..., 4, 4)

        Raises
        ------
        RedkinError
            For joint values of the wrong length or not finite, or an ``out`` that cannot hold the poses (a
            ``ValueError``).
        """
        flat, lead = self._flat(q)
        shape = lead + (4, 4)
        result = np.empty(shape) if out is None else check_output_array(out, shape)
        tool = result.reshape(flat.shape[0], 1, 4, 4)  # the tool frame alone, a view of the result
        run_batch(kernels.frames, flat.shape[0], flat, self._links, self._ends, self._standard, tool)
        return result

    def frames(self, q: ArrayLike) -> np.ndarray:
        """Poses of frames ``0..n`` and the tool frame.

        Returns
        -------
        numpy.ndarray, shape (..., n + 2, 4, 4)
            Index 0 is the base frame, index ``k`` the frame after joint ``k``
            (``1 <= k <= n``), index ``n + 1`` the tool frame (the end pose).
        """
        flat, lead = self._flat(q)
        out = np.empty((flat.shape[0], self.n + 2, 4, 4))
        run_batch(kernels.frames, flat.shape[0], flat, self._links, self._ends, self._standard, out)
        return out.reshape(lead + (self.n + 2, 4, 4))

    def joint_axes(self, q: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        """World directions and points of the joint axes.

        Returns
        -------
        directions, points : numpy.ndarray, shape (..., n, 3)
            Unit axis direction of each joint (for ``sign = -1`` the joint turns
            about the negative direction) and a point on the axis.
        """
        return self.joint_axes_in(self.frames(q))

    def joint_axes_in(self, frames: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The joint axes (as :meth:`joint_axes`) read from frames already computed by :meth:`frames`.

        Parameters
        ----------
        frames : numpy.ndarray, shape (..., n + 2, 4, 4)
            (or ``(..., n + 1, 4, 4)`` without the tool frame).

        Returns
        -------
        directions, points : numpy.ndarray, shape (..., n, 3)
        """
        axis_frames = frames[..., : self.n, :, :] if self._standard else frames[..., 1 : self.n + 1, :, :]
        return axis_frames[..., :3, 2], axis_frames[..., :3, 3]

    def jacobian(
        self,
        q: ArrayLike,
        frame: int | None = None,
        offset: ArrayLike | None = None,
        *,
        out: np.ndarray | None = None,
    ) -> np.ndarray:
        """Geometric Jacobian in the base (world) frame, linear rows first ([001 eq. 5.1], [003 eq. 1]).

        Parameters
        ----------
        q : array_like, shape (..., n)
            Joint angles in radians.
        frame : int, optional
            ``None`` (default) for the tool frame, or ``k`` in ``0..n`` for the
            frame after joint ``k``; joints after ``k`` give zero columns.
        offset : array_like, shape (3,) or (..., 3), optional
            A point fixed in that frame, in that frame's coordinates; the
            linear rows are then the velocity of that point.
        out : numpy.ndarray, shape (..., 6, n), optional
            A C-contiguous float64 array to write the Jacobians into, returned (as in :meth:`fk`).

        Returns
        -------
        numpy.ndarray, shape (..., 6, n)
            ``[v; omega] = J q_dot``.

        Raises
        ------
        RedkinError
            For joint values of the wrong length or not finite, a frame that is not ``None`` or in ``0..n``, an
            offset that is not 3-vectors, or an ``out`` that cannot hold the Jacobians (a ``ValueError``).
        """
        flat, lead = self._flat(q)
        if frame is not None and (int(frame) != frame or not 0 <= frame <= self.n):
            raise RedkinError(f"frame must be None or an integer in 0..{self.n}, got {frame!r}")
        offsets = _NO_OFFSET
        if offset is not None:
            local = check_vectors(offset, 3, "offset")
            offsets = local.reshape(1, 3) if local.ndim == 1 else np.broadcast_to(local, lead + (3,)).reshape(-1, 3)
            offsets = np.ascontiguousarray(offsets)
        active = self.n if frame is None else int(frame)
        shape = lead + (6, self.n)
        result = np.empty(shape) if out is None else check_output_array(out, shape)
        run_batch(kernels.jacobian, flat.shape[0], flat, self._links, self._ends, self._standard, active, frame is None,
                  offsets, result.reshape(flat.shape[0], 6, self.n))
        return result

    def manipulability(
        self,
        q: ArrayLike,
        rows: Sequence[int] | slice | None = None,
        columns: Sequence[int] | slice | None = None,
        frame: int | None = None,
        offset: ArrayLike | None = None,
    ) -> np.ndarray:
        """Yoshikawa manipulability ``sqrt(det(J J^T))`` of a sub-Jacobian.

        Parameters
        ----------
        q : array_like, shape (..., n)
        rows : sequence of int or slice, optional
            Rows of the 6 x n geometric Jacobian to keep (0-2 linear, 3-5
            angular); default all six.  [001 eq. 5.3] uses ``rows=[0, 1, 2]``.
        columns : sequence of int or slice, optional
            Joint columns (0-based) to keep; default all.  Thesis 001 uses joints
            1-5, i.e. ``columns=range(5)``.
        frame, offset :
            As in :meth:`jacobian`.

        Returns
        -------
        numpy.ndarray, shape (...)
            Zero when the kept Jacobian has more rows than columns.
        """
        jac = self.jacobian(q, frame=frame, offset=offset)
        jac = jac[..., _index(rows, 6, "rows"), :][..., _index(columns, self.n, "columns")]
        return yoshikawa(jac)

    def within_limits(self, q: ArrayLike, tolerance: float = 0.0, wrap: bool = False) -> np.ndarray:
        """Whether each joint vector respects the limits.

        Parameters
        ----------
        q : array_like, shape (..., n)
        tolerance : float
            Slack in radians allowed beyond each limit.
        wrap : bool
            If true, ``q_i`` counts as within limits when any ``q_i + 2 pi k`` is
            (for angles reported modulo ``2 pi``, e.g. by closed-form IK).

        Returns
        -------
        numpy.ndarray of bool, shape (...)
        """
        return np.all(self.joints_within_limits(q, tolerance, wrap), axis=-1)

    def joints_within_limits(self, q: ArrayLike, tolerance: float = 0.0, wrap: bool = False) -> np.ndarray:
        """Per-joint version of :meth:`within_limits`, shape ``(..., n)``."""
        q = self.check_q(q)
        if not wrap:
            return (q >= self.lower - tolerance) & (q <= self.upper + tolerance)
        anywhere = self.covers_circle
        lower = np.where(anywhere, 0.0, self.lower)
        width = np.where(anywhere, 0.0, self.upper - self.lower)
        return (np.mod(q - lower + tolerance, TWO_PI) <= width + 2.0 * tolerance) | anywhere

    def nearest_in_range(self, q: ArrayLike, near: ArrayLike | None = None) -> np.ndarray:
        """The same angles, each shifted by a multiple of ``2 pi`` into its joint's range.

        A joint whose range is wider than ``2 pi`` holds some angles twice
        (or more); of those representatives the one nearest ``near`` is
        returned, or without ``near`` the one nearest the middle of the range.
        A value with no representative in range (it violates the limits) is
        returned as the representative nearest ``near``, or without ``near``
        wrapped to ``(-pi, pi]``; so is a value of an unlimited joint.  A
        value already in place comes back bit for bit.

        Parameters
        ----------
        q : array_like, shape (..., n)
            Joint angles, e.g. a closed-form solution known modulo ``2 pi``.
        near : array_like, shape (..., n), optional
            Seeds (the previous configuration of a path, a controller's state).

        Returns
        -------
        numpy.ndarray, shape (..., n)
        """
        flat, lead = self._flat(q)
        targets = flat
        if near is not None:
            seeds = np.broadcast_to(self.check_q(near, "near"), lead + (self.n,))
            targets = np.ascontiguousarray(seeds.reshape(-1, self.n))
        out = np.empty_like(flat)
        lower, upper = kernel_array(self.lower), kernel_array(self.upper)  # one compiled type: the fields are frozen
        flat, targets = kernel_array(flat), kernel_array(targets)
        kernels.representatives(flat, lower, upper, targets, near is not None, out)
        missing = np.isnan(out)
        if np.any(missing):  # out of range: the representative nearest the seed, or in (-pi, pi]
            free = np.empty_like(flat)
            unlimited = np.full(self.n, np.inf)
            kernels.representatives(flat, -unlimited, unlimited, targets, near is not None, free)
            out[missing] = free[missing]
        return out.reshape(lead + (self.n,))

    def mirrored(self, normal: ArrayLike = (1.0, 0.0, 0.0), flip_joints: Sequence[int] = ()) -> SerialChain:
        """The mirror image of this chain in the plane through the base origin with ``normal``.

        The mirrored chain at joints ``q`` reaches ``M fk(q) M'`` where ``M`` is
        the reflection of world coordinates and ``M'`` the reflection of the
        tool's local coordinates that keeps the result a proper rotation, so
        the same ``q`` gives the mirror posture.  Every joint then turns in the
        mirrored sense; ``flip_joints`` (0-based) negates the sign of joints
        that should keep their world sense (e.g. a torso joint shared with the
        unmirrored arm).
        """
        m = check_vectors(normal, 3, "normal").reshape(3)
        m = m / np.linalg.norm(m)
        world = np.eye(4)
        world[:3, :3] -= 2.0 * np.outer(m, m)
        local = np.diag([1.0, 1.0, -1.0, 1.0])  # conjugating DH factors by z -> -z
        sign = self.sign.copy()
        offset = self.offset.copy()
        for j in flip_joints:
            if not 0 <= int(j) < self.n:
                raise RedkinError(f"flip_joints entries must be in 0..{self.n - 1}, got {j}")
            sign[int(j)] = -sign[int(j)]
        return replace(
            self,
            alpha=-self.alpha,
            d=-self.d,
            sign=sign,
            offset=offset,
            lower=np.where(np.isin(np.arange(self.n), list(flip_joints)), -self.upper, self.lower),
            upper=np.where(np.isin(np.arange(self.n), list(flip_joints)), -self.lower, self.upper),
            base=world @ self.base @ local,
            tool=local @ self.tool @ world,
            name=f"{self.name} (mirrored)",
        )


def yoshikawa(jacobian: ArrayLike) -> np.ndarray:
    """Yoshikawa manipulability ``sqrt(det(J J^T))`` of Jacobians ``(..., m, k)``.

    Computed as the product of singular values, which is exact where
    ``det(J J^T)`` would lose digits; zero when ``m > k``.
    """
    jac = as_float_array(jacobian, "jacobian")
    if jac.ndim < 2:
        raise RedkinError(f"jacobian must have shape (..., m, k), got {jac.shape}")
    m, k = jac.shape[-2:]
    if m > k:
        return np.zeros(jac.shape[:-2])
    return np.prod(np.linalg.svd(jac, compute_uv=False), axis=-1)


def _translation(x: float, y: float, z: float) -> np.ndarray:
    matrix = np.eye(4)
    matrix[:3, 3] = x, y, z
    return matrix


def _twist(alpha: float) -> np.ndarray:
    """``Rx(alpha)`` as a 4x4 transform."""
    matrix = np.eye(4)
    c, s = np.cos(alpha), np.sin(alpha)
    matrix[1:3, 1:3] = [[c, -s], [s, c]]
    return matrix


def _cos_sin(alpha: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``cos, sin`` of the DH twists, quarter turns exact (so that 0 stays 0 in every frame)."""
    c, s = np.cos(alpha), np.sin(alpha)
    c, s = np.where(np.abs(s) < 1e-15, np.sign(c), c), np.where(np.abs(s) < 1e-15, 0.0, s)
    return np.where(np.abs(c) < 1e-15, 0.0, c), np.where(np.abs(c) < 1e-15, np.sign(s), s)


def _index(selection: Sequence[int] | slice | None, size: int, name: str):
    if selection is None:
        return slice(None)
    if isinstance(selection, slice):
        return selection
    idx = np.asarray(list(selection), dtype=int)
    if idx.size == 0 or np.any(idx < 0) or np.any(idx >= size):
        raise RedkinError(f"{name} must be indices in 0..{size - 1}, got {list(selection)}")
    return idx
