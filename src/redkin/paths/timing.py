"""A timed trajectory through a path's joint values, within each joint's velocity and acceleration limits.

The joint path interpolates the waypoints' joint values over their cumulative joint-space distance ``s`` (radians;
a waypoint that repeats the one before it is passed once): the cubic spline (not-a-knot ends, continuous in its
second derivative), unless it bends past a joint limit that the waypoints come close to; then the piecewise cubic
Hermite interpolant (PCHIP, Fritsch and Carlson 1980), which moves each joint monotonically where its values do and
never past the larger or smaller of two neighbouring values, so it keeps every limit the waypoints keep (its second
derivative steps at the waypoints, which makes it slower to run).  :attr:`Trajectory.interpolation` says which.

Along it, TOPP-RA (Pham and Pham, "A new approach to time-optimal path parameterization based on reachability
analysis", IEEE T-RO 2018; the ``toppra`` package, the ``timing`` extra) finds the fastest speed profile ``sd(s)``
that keeps every joint's ``|qd_i| = |q_i'(s) sd|`` and ``|qdd_i| = |q_i'(s) sdd + q_i''(s) sd^2|`` within its limits
at a grid of ``s``, starting and ending at rest.  Between the grid's points the path acceleration ``sdd`` is
constant.

TOPP-RA constrains the grid's points only; between them a joint's acceleration can exceed its limit where the
path bends.  :func:`time_path` therefore checks the trajectory at every sample of the control rate, refines the
grid where a sample exceeds a limit, and returns only a trajectory whose samples all keep ``|qd| <= velocity`` and
``|qdd| <= acceleration`` (its derivatives evaluated exactly, not by differences); the solver runs with limits
0.1 % (``_MARGIN``) inside the given ones, so that the check passes without many rounds.  The jerk is not limited
(the profile's acceleration steps at the grid's points); :attr:`Trajectory.jerk` reports it at the control rate for
controllers that filter it (libfranka's ``limitRate``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from itertools import pairwise

import numpy as np
from numpy.typing import ArrayLike

from redkin._extras import missing_extra
from redkin._validation import as_float_array, check_finite
from redkin.chain import SerialChain
from redkin.errors import RedkinError, SizeLimitError

#: The solver keeps each velocity and acceleration this fraction inside its limit, so that the samples between its
#: grid points (where it imposes nothing) stay within the limits themselves.
_MARGIN = 1e-3
#: The default control rate of the samples (Hz), as a robot's joint-position interface runs (Franka, KUKA FRI).
DEFAULT_RATE = 1000.0
#: Rounds of grid refinement (each halves the grid's intervals where a sample exceeded a limit) before giving up.
_REFINEMENTS = 8
#: A grid point this fraction of the interval before each inner knot, where PCHIP's acceleration steps (much
#: closer, and the solver's rounding in ``sd^2`` divided by the tiny interval swamps the acceleration).
_BEFORE_KNOT = 1e-3
#: A joint path this far past a limit (radians) is within it: PCHIP between two values at a limit computes the
#: limit to within a few units in the last place; the samples are clipped onto it.
_RANGE_ROUNDING = 1e-12
#: Grid points closer than this fraction of the path's length are one point (:func:`_grid`).
_GRID_SPACING = 1e-9
#: Waypoints closer than this in joint space (radians) are one point of the path.
_REPEAT = 1e-12
#: At most this many samples in a trajectory (1 kHz for almost three hours).
MAX_SAMPLES = 10_000_000


@dataclass(frozen=True)
class Trajectory:
    """Joint values, velocities and accelerations against time, sampled at a control rate.

    Attributes
    ----------
    t : numpy.ndarray, shape (M,)
        Seconds from the start: ``0, 1/rate, 2/rate, ...`` and the duration as the last sample.
    q, qd, qdd : numpy.ndarray, shape (M, n)
        Joint values (rad), velocities (rad/s) and accelerations (rad/s^2) at ``t``; at rest at both ends.
    duration : float
        Seconds.
    waypoint_times : numpy.ndarray, shape (N,)
        When the trajectory passes each waypoint of the path (there ``q`` is the waypoint's, exactly); use
        :meth:`at` to evaluate it there.
    rate : float
        Samples per second (Hz).
    joint_names : tuple of str
    velocity, acceleration : numpy.ndarray, shape (n,)
        The limits it keeps.
    interpolation : str
        The joint path between waypoints: ``"cubic"`` (the cubic spline) or ``"pchip"`` (where the spline would
        leave a joint's range; see the module's docstring), ``"cubic+pchip"`` where pieces between rests differ;
        ``"rest"`` for a path of one configuration.
    stop_spans : numpy.ndarray, shape (S, 2)
        Of a path with reconfiguration stops (:func:`redkin.paths.resolve_path` with ``allow_stops``): when the
        arm arrives at each stop and when it leaves it reconfigured (seconds).
    """

    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    duration: float
    waypoint_times: np.ndarray
    rate: float
    joint_names: tuple[str, ...]
    velocity: np.ndarray
    acceleration: np.ndarray
    interpolation: str
    _profile: _Sequence
    stop_spans: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))

    def at(self, times: ArrayLike) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(q, qd, qdd)`` at any ``times`` in ``[0, duration]`` (seconds), each of shape ``times.shape + (n,)``."""
        seconds = as_float_array(times, "times")
        check_finite(seconds, "times")
        if np.any(seconds < 0.0) or np.any(seconds > self.duration):
            raise RedkinError(f"times must lie in [0, {self.duration:g}] s")
        return self._profile.evaluate(seconds)

    @property
    def jerk(self) -> np.ndarray:
        """The joint jerk (rad/s^3) between consecutive samples, ``(M - 1, n)``: finite differences of ``qdd``
        (not limited: see the module's docstring)."""
        return np.diff(self.qdd, axis=0) / np.diff(self.t)[:, None]

    def joint_trajectory(self) -> dict:
        """The trajectory as a ROS ``trajectory_msgs/JointTrajectory`` message in JSON form: ``joint_names`` and
        ``points``, each with ``positions``, ``velocities``, ``accelerations`` and ``time_from_start``
        (``{"sec": ..., "nanosec": ...}``)."""
        seconds = np.floor(self.t).astype(int)
        nanoseconds = np.minimum(np.round((self.t - seconds) * 1e9).astype(int), 999_999_999)
        return {"joint_names": list(self.joint_names),
                "points": [{"positions": q, "velocities": qd, "accelerations": qdd,
                            "time_from_start": {"sec": sec, "nanosec": nsec}}
                           for q, qd, qdd, sec, nsec in zip(self.q.tolist(), self.qd.tolist(), self.qdd.tolist(),
                                                            seconds.tolist(), nanoseconds.tolist())]}


def time_path(chain: SerialChain, q: ArrayLike, *, rate: float = DEFAULT_RATE,
              velocity: ArrayLike | None = None, acceleration: ArrayLike | None = None,
              rests: Sequence[int] = ()) -> Trajectory:
    """The time-optimal trajectory along the joint path through ``q`` (the module's docstring) within the joints'
    velocity and acceleration limits, sampled at ``rate``.

    Parameters
    ----------
    chain : SerialChain
        The arm: its joint names, its position limits (kept along the path) and, unless given, its limits
        of motion (:attr:`~redkin.chain.SerialChain.velocity`, :attr:`~redkin.chain.SerialChain.acceleration`).
    q : array_like, shape (N, n)
        The path's joint values per waypoint (a :class:`~redkin.paths.PathResult`'s ``q``).
    rate : float
        Samples per second (Hz).
    velocity, acceleration : array_like, shape (n,) or scalar, optional
        Limits in rad/s and rad/s^2 instead of the chain's.
    rests : sequence of int
        Rows of ``q`` where the arm comes to rest (besides the first and last): the path is timed as separate
        pieces between them, each from rest to rest and padded with a rest to a whole number of samples, so that
        every sample lies on the one grid of ``rate`` (a path's reconfiguration stops).

    Returns
    -------
    Trajectory

    Raises
    ------
    RedkinError
        For malformed joint values or a waypoint outside a joint's range, a limit unknown (``inf``) or not
        positive, a rate not positive, or a trajectory of more than :data:`MAX_SAMPLES` samples; without the
        ``toppra`` package (the ``timing`` extra), one line saying how to install it.
    """
    values = as_float_array(q, "q")
    if values.ndim != 2 or values.shape[1] != chain.n or values.shape[0] == 0:
        raise RedkinError(f"q must have shape (N, {chain.n}) with N >= 1, got shape {values.shape}")
    check_finite(values, "q")
    outside = np.argwhere((values < chain.lower) | (values > chain.upper))
    if outside.size:
        waypoint, joint = outside[0].tolist()
        raise RedkinError(f"waypoint {waypoint}: joint {joint + 1} at {values[waypoint, joint]:.6g} rad is outside its "
                          f"range [{chain.lower[joint]:.6g}, {chain.upper[joint]:.6g}]")
    _check_rate(rate)
    limits = {key: _limit(chain, key, given) for key, given in (("velocity", velocity),
                                                                 ("acceleration", acceleration))}
    cuts = sorted({0, len(values) - 1, *(int(row) for row in rests)})
    if cuts[0] < 0 or cuts[-1] >= len(values):
        raise RedkinError(f"rests must be rows of q (0..{len(values) - 1}), got {list(rests)}")
    _check_least_duration(values, limits, rate)
    profiles: list[_Profile] = []
    times: list[np.ndarray] = []
    for first, last in pairwise(cuts) if len(cuts) > 1 else [(0, 0)]:
        rows = values[first : last + 1]
        distinct = np.r_[True, np.linalg.norm(np.diff(rows, axis=0), axis=1) > _REPEAT]
        profile = _piece(rows[distinct], limits, rate, chain)
        profiles.append(profile)
        times.append(profile.knot_times[np.cumsum(distinct) - 1][int(bool(times)):])  # a rest row once
    sequence = _Sequence.of(profiles, rate, chain)
    waypoint_times = np.concatenate([piece + offset for piece, offset in zip(times, sequence.offsets)])
    return _sampled(chain, sequence, rate, limits, waypoint_times)


def _piece(points: np.ndarray, limits: dict[str, np.ndarray], rate: float, chain: SerialChain) -> _Profile:
    """The profile from rest to rest through ``points``: along the cubic spline, or PCHIP where the spline leaves a
    joint's range."""
    if len(points) == 1:  # nothing to move: the arm rests at the one configuration
        return _Profile.resting(points[0])
    try:
        return _fastest(points, "cubic", limits, rate, chain)
    except _LeavesRange:  # the spline bends past a limit the waypoints come close to: PCHIP does not
        return _fastest(points, "pchip", limits, rate, chain)


class _LeavesRange(RedkinError):
    """A joint path that leaves a joint's range between two waypoints."""


def _sampled(chain: SerialChain, sequence: _Sequence, rate: float, limits: dict[str, np.ndarray],
             waypoint_times: np.ndarray) -> Trajectory:
    """The trajectory of ``sequence`` sampled at ``rate``."""
    samples = _sample_count(sequence.duration, rate)
    t = np.minimum(np.arange(samples) / rate, sequence.duration)
    t[-1] = sequence.duration
    positions, speeds, accelerations = sequence.evaluate(t)
    kinds = sorted({profile.path.kind for profile in sequence.profiles if profile.path is not None})
    return Trajectory(t=t, q=positions, qd=speeds, qdd=accelerations, duration=sequence.duration,
                      waypoint_times=waypoint_times, rate=float(rate), joint_names=chain.joint_names,
                      velocity=limits["velocity"], acceleration=limits["acceleration"],
                      interpolation="+".join(kinds) or "rest", _profile=sequence)


def check_timing(chain: SerialChain, rate: float) -> None:
    """Refuse, before a path is searched, what :func:`time_path` would refuse after: a rate not positive, an
    unknown velocity or acceleration limit."""
    _check_rate(rate)
    for key in ("velocity", "acceleration"):
        _limit(chain, key, None)


def _check_rate(rate: float) -> None:
    if not (np.isfinite(rate) and rate > 0.0):
        raise RedkinError(f"rate must be a positive number of samples per second, got {rate!r}")


def _limit(chain: SerialChain, key: str, given: ArrayLike | None) -> np.ndarray:
    values = getattr(chain, key) if given is None else np.broadcast_to(as_float_array(given, key), (chain.n,))
    unknown = np.flatnonzero(~np.isfinite(values))
    if unknown.size:
        raise RedkinError(f"{chain.name} has no {key} limit on {chain.joints_in_words(unknown.tolist())}: give them "
                          "(--limits FILE, or redkin.motion_limits in Python) to time the path")
    if not np.all(values > 0.0):
        raise RedkinError(f"{key} limits must be > 0, got {np.asarray(values).tolist()}")
    return np.array(values, dtype=float)


def _least_duration(values: np.ndarray, limits: dict[str, np.ndarray]) -> tuple[float, int]:
    """A lower bound [s] of every trajectory through the waypoints ``values`` (N, n) in order, from rest, within
    ``limits``, and the joint that sets it: a path moves each joint at least its moves between the waypoints,
    ``D_j``, which take ``D_j / v_j`` at the velocity limit; and from rest a joint reaches its farthest waypoint
    ``X_j`` from the first no sooner than ``sqrt(2 X_j / a_j)``."""
    moves = np.abs(np.diff(values, axis=0)).sum(axis=0)
    farthest = np.abs(values - values[0]).max(axis=0)
    with np.errstate(over="ignore"):
        least = np.maximum(moves / limits["velocity"], np.sqrt(2.0 * farthest / limits["acceleration"]))
    joint = int(np.argmax(least))
    return float(least[joint]), joint


def _check_least_duration(values: np.ndarray, limits: dict[str, np.ndarray], rate: float) -> None:
    """Refuse, before the time parametrisation, a trajectory that must have more than :data:`MAX_SAMPLES` samples
    at ``rate`` whatever its profile (:func:`_least_duration`)."""
    least, joint = _least_duration(values, limits)
    if least * rate + 1.0 > MAX_SAMPLES:
        raise SizeLimitError(
            f"at its limits ({limits['velocity'][joint]:.6g} rad/s, {limits['acceleration'][joint]:.6g} rad/s^2) "
            f"joint {joint + 1} alone needs at least {least:.6g} s for this path: more than {MAX_SAMPLES} samples at "
            f"{rate:g} Hz; check the limits, or lower the rate", "samples", least * rate + 1.0, MAX_SAMPLES)


def _sample_count(duration: float, rate: float) -> int:
    if not duration * rate + 1.0 <= MAX_SAMPLES:
        raise SizeLimitError(f"the trajectory lasts {duration:.6g} s: {duration * rate + 1.0:.6g} samples at "
                             f"{rate:g} Hz, more than {MAX_SAMPLES}; lower the rate, or check the limits", "samples",
                             duration * rate + 1.0, MAX_SAMPLES)
    samples = int(np.floor(duration * rate + 1e-9)) + 1
    samples += not np.isclose((samples - 1) / rate, duration, rtol=0.0, atol=1e-12)
    if samples > MAX_SAMPLES:
        raise SizeLimitError(f"the trajectory lasts {duration:.6g} s: {samples} samples at {rate:g} Hz, more than "
                             f"{MAX_SAMPLES}; lower the rate, or check the limits", "samples", samples, MAX_SAMPLES)
    return samples


@dataclass(frozen=True)
class _Profile:
    """A path ``q(s)`` and a speed profile along it, constant path acceleration between grid points ``s_k``:
    ``sd(s)^2`` linear in ``s`` on each interval, so the interval takes ``2 ds / (sd_k + sd_k+1)`` seconds."""

    path: _JointPath | None  # None at rest
    grid: np.ndarray
    speed: np.ndarray
    times: np.ndarray
    knot_times: np.ndarray
    rest: np.ndarray | None = None

    @classmethod
    def resting(cls, q: np.ndarray) -> _Profile:
        zero = np.zeros(1)
        return cls(path=None, grid=zero, speed=zero, times=zero, knot_times=zero, rest=q)

    @classmethod
    def along(cls, path, grid: np.ndarray, speed: np.ndarray, knots: np.ndarray) -> _Profile:
        with np.errstate(divide="ignore", invalid="ignore"):  # a speed of 0 inside: refused by the caller
            times = np.r_[0.0, np.cumsum(2.0 * np.diff(grid) / (speed[:-1] + speed[1:]))]
        return cls(path=path, grid=grid, speed=speed, times=times, knot_times=times[np.searchsorted(grid, knots)])

    @property
    def duration(self) -> float:
        return float(self.times[-1])

    def evaluate(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        if self.path is None:
            assert self.rest is not None
            shape = t.shape + self.rest.shape
            return np.broadcast_to(self.rest, shape).copy(), np.zeros(shape), np.zeros(shape)
        k = np.clip(np.searchsorted(self.times, t, side="right") - 1, 0, len(self.grid) - 2)
        ds = np.diff(self.grid)[k]
        sdd = (self.speed[k + 1] ** 2 - self.speed[k] ** 2) / (2.0 * ds)
        dt = t - self.times[k]
        sd = self.speed[k] + sdd * dt
        s = np.minimum(self.grid[k] + self.speed[k] * dt + 0.5 * sdd * dt**2, self.grid[k + 1])
        end = t >= self.times[k + 1]  # the last sample: the grid's end exactly (at rest), not its rounded value
        sd, s = np.where(end, self.speed[k + 1], sd), np.where(end, self.grid[k + 1], s)
        flat = s.reshape(-1)
        first, second = self.path(flat, 1), self.path(flat, 2)
        sd, sdd = sd.reshape(-1, 1), sdd.reshape(-1, 1)
        shape = t.shape + (first.shape[-1],)
        acceleration = first * sdd + second * sd**2
        return self.path(flat).reshape(shape), (first * sd).reshape(shape), acceleration.reshape(shape)


@dataclass(frozen=True)
class _Sequence:
    """Profiles one after another, each but the last padded with a rest to a whole number of samples at the rate
    (so that every piece starts on the rate's grid); ``offsets`` are their start times."""

    profiles: tuple[_Profile, ...]
    offsets: np.ndarray
    duration: float
    lower: np.ndarray
    upper: np.ndarray

    @classmethod
    def of(cls, profiles: list[_Profile], rate: float, chain: SerialChain) -> _Sequence:
        padded = [np.ceil(profile.duration * rate - 1e-9) / rate for profile in profiles[:-1]]
        offsets = np.r_[0.0, np.cumsum(padded)]
        return cls(tuple(profiles), offsets, float(offsets[-1] + profiles[-1].duration), chain.lower, chain.upper)

    def evaluate(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        piece = np.clip(np.searchsorted(self.offsets, t, side="right") - 1, 0, len(self.profiles) - 1)
        q, qd, qdd = (np.zeros(t.shape + self.lower.shape) for _ in range(3))
        for index, profile in enumerate(self.profiles):
            mask = piece == index
            local = np.minimum(t[mask] - self.offsets[index], profile.duration)
            q[mask], qd[mask], qdd[mask] = profile.evaluate(local)
            resting = t[mask] - self.offsets[index] > profile.duration  # the padding: at rest at the piece's end
            rows = np.flatnonzero(mask)[resting]
            qd[rows], qdd[rows] = 0.0, 0.0
        # within the range: a sample is at most _RANGE_ROUNDING past a limit (_exceeding), which is rounding
        return np.clip(q, self.lower, self.upper), qd, qdd


class _JointPath:
    """The joint path ``q(s)`` through ``points`` at ``knots``, ``kind`` ``"cubic"`` or ``"pchip"``, in the form
    TOPP-RA reads a geometric path (``path(s, order)``, ``path_interval``, ``dof``, ``waypoints``)."""

    def __init__(self, knots: np.ndarray, points: np.ndarray, kind: str) -> None:
        from scipy.interpolate import CubicSpline, PchipInterpolator

        self._curve = CubicSpline(knots, points, axis=0) if kind == "cubic" else PchipInterpolator(knots, points,
                                                                                                    axis=0)
        self.kind = kind
        self.path_interval = np.array([knots[0], knots[-1]])
        self.dof = points.shape[1]
        self.waypoints = (knots, points)

    def __call__(self, s: ArrayLike, order: int = 0) -> np.ndarray:
        return self._curve(s, order) if order else self._curve(s)


def _fastest(points: np.ndarray, kind: str, limits: dict[str, np.ndarray], rate: float,
             chain: SerialChain) -> _Profile:
    """TOPP-RA's profile along the ``kind`` path through ``points``, its grid refined until every sample at
    ``rate`` keeps the limits; :class:`_LeavesRange` where a sample leaves a joint's range."""
    try:
        import toppra
        import toppra.constraint as constraint
    except ImportError:
        raise RedkinError(missing_extra("timing a path needs toppra", "timing")) from None
    velocity, acceleration = limits["velocity"], limits["acceleration"]
    knots = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))]
    path = _JointPath(knots, points, kind)
    inner = 1.0 - _MARGIN
    constraints = [constraint.JointVelocityConstraint(np.c_[-velocity, velocity] * inner),
                   constraint.JointAccelerationConstraint(np.c_[-acceleration, acceleration] * inner)]
    grid = _grid(toppra.interpolator.propose_gridpoints(path), knots)
    if kind == "pchip":  # its second derivative steps at each inner knot: a grid point just before holds that side
        grid = _grid(np.r_[grid, knots[1:-1] - _BEFORE_KNOT * np.diff(knots)[:-1]], knots)
    for _ in range(_REFINEMENTS + 1):
        solver = toppra.algorithm.TOPPRA(constraints, path, gridpoints=grid)
        _, speed, _ = solver.compute_parameterization(0.0, 0.0)
        if speed is None:
            raise RedkinError("the time parametrisation found no profile that starts and ends at rest; the joint path "
                              "may turn back on itself: check the waypoints")
        profile = _Profile.along(path, grid, np.maximum(speed, 0.0), knots)
        if not np.isfinite(profile.duration):  # a speed that rounds to 0 inside the path, or NaN
            raise RedkinError(f"the time parametrisation found no profile of finite duration at these limits "
                              f"(the smallest: velocity {velocity.min():.6g} rad/s, acceleration "
                              f"{acceleration.min():.6g} rad/s^2), beyond its precision; check the limits")
        over = _exceeding(profile, velocity, acceleration, rate, chain)
        if not over.size:
            return profile
        grid = _grid(np.r_[grid, 0.5 * (grid[over] + grid[over + 1])], knots)
    raise RedkinError(f"the timed trajectory still exceeds a joint's limits between its grid points after "
                      f"{_REFINEMENTS} refinements; add waypoints where the path bends")


def _grid(points: np.ndarray, knots: np.ndarray) -> np.ndarray:
    """The sorted grid of ``points`` and the ``knots``, without a point within :data:`_GRID_SPACING` of the path's
    length of a knot or of the point before it: an interval that short (a proposed point a rounding away from a knot)
    makes the profile's constant acceleration ``(sd_1^2 - sd_0^2) / (2 ds)`` rounding divided by almost nothing, and
    halving it adds nothing."""
    least = _GRID_SPACING * knots[-1]
    points = np.unique(points)
    near = np.searchsorted(knots, points).clip(1, len(knots) - 1)
    off_knots = np.minimum(np.abs(points - knots[near - 1]), np.abs(points - knots[near])) > least
    grid = np.union1d(knots, points[off_knots])
    keep = np.r_[True, np.diff(grid) > least] | np.isin(grid, knots)
    return grid[keep]


def _exceeding(profile: _Profile, velocity: np.ndarray, acceleration: np.ndarray, rate: float,
               chain: SerialChain) -> np.ndarray:
    """The grid intervals in which a sample at ``rate`` (or an interval's ends) exceeds a limit of motion;
    :class:`_LeavesRange` where one leaves a joint's range."""
    t = np.union1d(np.arange(_sample_count(profile.duration, rate)) / rate, profile.times)
    t = t[t <= profile.duration]
    positions, speeds, accelerations = profile.evaluate(t)
    outside = (positions < chain.lower - _RANGE_ROUNDING) | (positions > chain.upper + _RANGE_ROUNDING)
    if outside.any():
        sample, joint = np.argwhere(outside)[0]
        raise _LeavesRange(f"the joint path leaves joint {joint + 1}'s range (at {positions[sample, joint]:.6g} rad)")
    bad = (np.abs(speeds) > velocity).any(axis=1) | (np.abs(accelerations) > acceleration).any(axis=1)
    intervals = np.clip(np.searchsorted(profile.times, t[bad], side="right") - 1, 0, len(profile.grid) - 2)
    return np.unique(intervals)
