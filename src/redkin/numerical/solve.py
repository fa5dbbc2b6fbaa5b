"""Numerical pose IK for any serial chain, within its joint limits, every answer certified by our own FK.

The method (docs/numerical-ik.md, [N1]-[N5]): damped Gauss-Newton
(Levenberg-Marquardt) steps on the pose error with the damping ``E + 1e-12``
of the error's half square, the joints at a limit pinned out of the step,
and restarts from the seed and then from random joint vectors within the
limits until ``count`` distinct solutions are certified or ``restarts``
starts are spent.  A solution counts only when our FK of the returned joint
vector matches the target within ``tolerance``; a pose with none is a value
(``found`` false, the best residual in ``error``), never NaN and never an
inaccurate joint vector among the solutions.  A pose beyond the links' reach
(:meth:`redkin.chain.SerialChain.reach`, by more than the position tolerance)
has no solution: it is not searched, only its first start descended for
``closest``, and ``reach`` says why.

The starts come from one integer per pose drawn from ``rng``: a pose's
answer depends on the pose, the seed, the settings and that integer only,
not on the other poses, the thread count or the chunking of a batch.
"""

from __future__ import annotations

from functools import lru_cache
from math import prod
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from redkin._compiled import kernel_array, run_batch
from redkin._validation import as_float_array, check_count, check_finite, check_pose
from redkin.chain import Reach, SerialChain
from redkin.errors import RedkinError, SizeLimitError
from redkin.numerical import _kernels

#: Default tolerance of the certificate: position error [m] and rotation angle [rad].
TOLERANCE = 1e-9
#: Default budget of starts per pose (the seed, then random joint vectors).
RESTARTS = 200
#: Default separation of distinct solutions: they differ by more than this in some joint [rad].
SEPARATION = 0.1
#: The value of ``NumericalSolutions.method``.
_METHOD = "numerical"
#: Largest number of starts per pose, and of solutions asked per pose.
_MAX_RESTARTS = 100_000
_MAX_COUNT = 1000
#: Largest number of joint values of the solutions of one call (800 MB).
_MAX_VALUES = 100_000_000


class NumericalSolutions(NamedTuple):
    """Certified solutions of target poses found numerically.

    Attributes
    ----------
    q : numpy.ndarray, shape (..., count, n)
        Solutions in the chain's joint values, within its limits, each certified (zeros where ``found`` is false).
        With a seed, ordered by the largest joint distance to it; else in the order found.
    found : numpy.ndarray of bool, shape (..., count)
    closest : numpy.ndarray, shape (..., n)
        The first solution where one was found; otherwise the joint vector of the smallest error met (within the
        limits, **not** a solution).
    error : numpy.ndarray, shape (..., 2)
        Position error [m] and rotation angle [rad] of ``closest`` against the target.
    starts : numpy.ndarray of int, shape (...)
        How many starts were used (1 where ``reach.out``: the pose was not searched).
    method : str
        ``"numerical"``.
    reach : Reach
        The poses against the links' reach (:meth:`redkin.chain.SerialChain.reach` with the position tolerance):
        where ``reach.out`` the pose has no solution, proven before any search.  Always set by :func:`ik`; last, with
        a default, so that a result may be rebuilt from its first six fields.
    """

    q: np.ndarray
    found: np.ndarray
    closest: np.ndarray
    error: np.ndarray
    starts: np.ndarray
    method: str = _METHOD
    reach: Reach | None = None


def ik(
    chain: SerialChain,
    pose: ArrayLike,
    *,
    q0: ArrayLike | None = None,
    count: int = 1,
    tolerance: float | tuple[float, float] = TOLERANCE,
    restarts: int = RESTARTS,
    separation: float = SEPARATION,
    rng: int | np.random.Generator | np.ndarray | None = None,
) -> NumericalSolutions:
    """Joint values within the limits that put the chain's tool at target poses [N1]-[N5].

    Parameters
    ----------
    chain : SerialChain
        Any chain of revolute joints.
    pose : array_like, shape (..., 4, 4)
        Target poses of the tool in the base frame.  A rotation block orthonormal to within 1e-6 is accepted and
        replaced by its nearest rotation.
    q0 : array_like, shape (..., n), optional
        Seeds, broadcast against the poses' batch shape.  The first start is the seed (clipped to the limits), and
        every step also moves towards it inside the self-motion [N5], so that a solution near the seed is returned
        as the nearest one of its self-motion; joints are then taken by whole turns to the representative nearest
        the seed.
    count : int
        Distinct solutions wanted per pose (they differ by more than ``separation`` in some joint).
    tolerance : float or (float, float)
        The certificate: the largest position error [m] and rotation angle [rad] of our FK of a solution against
        the target (one number for both).
    restarts : int
        The budget of starts per pose; one for a pose beyond the links' reach (``reach.out`` of the result).
    separation : float
        Radians; see ``count``.
    rng : int or numpy.random.Generator or numpy.ndarray, optional
        Where the random starts come from (one integer drawn per pose, :func:`start_streams`); ``None`` is seed 0,
        so that a call is reproducible: pose ``i`` of the batch (in C order) then starts from stream ``i``.  An
        integer array of the batch's size gives those integers themselves (to solve some poses of a batch again
        from their own starts).

    Returns
    -------
    NumericalSolutions

    Raises
    ------
    ValueError
        For a malformed pose or seed (shape, NaN, a rotation that is not orthonormal), ``count`` (at most 1000) or
        ``restarts`` (at most 100 000) not a whole number from 1, a tolerance or separation that is not a positive
        finite number; :class:`~redkin.errors.SizeLimitError` for more than 10^8 joint values of solutions in one
        call.
    """
    prepared = batch(chain, pose, q0, count, tolerance, restarts, separation, rng)
    out = Outputs.of(prepared, chain.n)
    with np.errstate(over="ignore"):  # SplitMix64 wraps by design: run as Python, numpy's integers would warn
        failed = run_batch(_kernels.solve, prepared.size, *prepared.inputs(chain), *out)
    return prepared.solutions(failed, out)


class Batch(NamedTuple):
    """Poses to solve, validated and laid out as the kernels take them (:func:`batch`): the batch ``shape`` and
    ``size`` poses, solutions ``asked`` per pose and the budget of ``restarts``; the checked ``pose`` and ``q0`` as
    given (to word an error the kernel finds); the kernels' ``poses`` (size, 4, 4), ``seeds`` (size, n),
    ``streams`` (size,) and ``settings``; ``reach`` (4,): the centre of the chain's reach bound and the largest
    distance from it that may hold a solution, whose ``radius`` and ``measure`` the result's :class:`Reach` keeps."""

    shape: tuple[int, ...]
    asked: int
    restarts: int
    pose: np.ndarray
    q0: np.ndarray | None
    poses: np.ndarray
    seeds: np.ndarray
    streams: np.ndarray
    settings: np.ndarray
    reach: np.ndarray
    radius: float
    measure: str

    @property
    def size(self) -> int:
        """How many poses."""
        return len(self.poses)

    def inputs(self, chain: SerialChain) -> tuple:
        """The arguments of :func:`redkin.numerical._kernels.solve` before its outputs."""
        return (self.poses, self.seeds, self.q0 is not None, self.streams, chain._links, chain._ends, chain._standard,
                chain._bounds, self.settings, self.restarts, self.reach)

    def solutions(self, failed: int, out: Outputs) -> NumericalSolutions:
        """The kernels' answers ``out`` as :class:`NumericalSolutions`, or the error of a pose or seed they refused
        (``failed`` of them)."""
        if failed:
            if self.q0 is not None:
                check_finite(self.q0, "q0")  # words the error the kernel found: the seeds, then the poses
            check_pose(self.pose)
            raise RedkinError("pose must be finite with a proper rotation block and last row [0, 0, 0, 1]")
        shape, n = self.shape, out.q.shape[-1]
        distances = out.distance.reshape(shape)
        limit = float(self.reach[3])
        return NumericalSolutions(out.q.reshape(shape + (self.asked, n)), out.found.reshape(shape + (self.asked,)),
                                  out.closest.reshape(shape + (n,)), out.error.reshape(shape + (2,)),
                                  out.used.reshape(shape),
                                  reach=Reach(distances, 0.0, self.radius, distances > limit, self.measure))


class Outputs(NamedTuple):
    """The arrays :func:`redkin.numerical._kernels.solve` writes, in its order."""

    q: np.ndarray
    found: np.ndarray
    closest: np.ndarray
    error: np.ndarray
    used: np.ndarray
    distance: np.ndarray

    @classmethod
    def of(cls, prepared: Batch, n: int) -> Outputs:
        """Empty outputs for the poses of ``prepared`` on a chain of ``n`` joints."""
        size, count = prepared.size, prepared.asked
        return cls(np.empty((size, count, n)), np.empty((size, count), dtype=bool), np.empty((size, n)),
                   np.empty((size, 2)), np.empty(size, dtype=np.int64), np.empty(size))


def batch(chain: SerialChain, pose: ArrayLike, q0: ArrayLike | None, count: int,
          tolerance: float | tuple[float, float], restarts: int, separation: float,
          rng: int | np.random.Generator | np.ndarray | None) -> Batch:
    """The arguments of :func:`ik`, validated (its Raises) and laid out as the kernels take them."""
    n = chain.n
    pose = as_float_array(pose, "pose")
    if pose.ndim < 2 or pose.shape[-2:] != (4, 4):
        raise RedkinError(f"pose must have shape (..., 4, 4), got shape {pose.shape}")
    if not (type(count) is int and 1 <= count <= _MAX_COUNT):
        count = check_count(count, "count", 1, _MAX_COUNT)
    if not (type(restarts) is int and 1 <= restarts <= _MAX_RESTARTS):
        restarts = check_count(restarts, "restarts", 1, _MAX_RESTARTS)
    settings = _settings(tolerance, separation)
    shape = pose.shape[:-2]
    seeds = _NO_SEED if q0 is None else as_float_array(q0, "q0")
    if q0 is not None:
        if seeds.ndim < 1 or seeds.shape[-1] != n:
            raise RedkinError(f"q0 must have shape (..., {n}) for {chain.name!r} ({n} joints), got shape "
                              f"{seeds.shape}")
        if seeds.ndim > 1:
            try:
                shape = np.broadcast_shapes(shape, seeds.shape[:-1])
            except ValueError:
                raise RedkinError(f"q0 of shape {seeds.shape} does not broadcast against the pose batch "
                                  f"{pose.shape[:-2]}") from None
    size = prod(shape)
    if size * count * n > _MAX_VALUES:
        raise SizeLimitError(f"{size} poses x count {count} x {n} joints is {size * count * n:.3g} joint values; at "
                             f"most {_MAX_VALUES:.0e} are computed in one call: split the batch",
                             name="pose", value=size * count * n, maximum=_MAX_VALUES)
    poses = kernel_array(pose, shape + (4, 4)).reshape(size, 4, 4)
    centre, radius, slack, measure = chain._reach_table  # the bound of SerialChain.reach, tested in the kernel
    limit = radius + slack + float(settings[_kernels.POSITION_TOLERANCE])
    return Batch(shape, count, restarts, pose, None if q0 is None else seeds, poses,
                 kernel_array(np.zeros(n) if q0 is None else seeds, shape + (n,)).reshape(size, n),
                 start_streams(rng, size), settings, np.array([centre[0], centre[1], centre[2], limit]), radius,
                 measure)


def start_streams(rng: int | np.random.Generator | np.ndarray | None, size: int) -> np.ndarray:
    """The integer ``(size,)`` each of ``size`` poses draws its starts from (:func:`ik`'s ``rng``).

    Raises
    ------
    ValueError
        For an array of integers of another size, or of negative values.
    """
    if rng is None:
        return np.arange(size, dtype=np.uint64)
    if isinstance(rng, np.ndarray):
        if rng.shape != (size,) or not np.issubdtype(rng.dtype, np.integer) or (rng < 0).any():
            raise RedkinError(f"rng as an array must hold one integer >= 0 per pose ({size}), got {rng.dtype} of "
                              f"shape {rng.shape}")
        return rng.astype(np.uint64)
    generator = rng if isinstance(rng, np.random.Generator) else np.random.default_rng(rng)
    return generator.integers(0, np.iinfo(np.int64).max, size=size, dtype=np.int64).astype(np.uint64)


#: ``q0`` not given (a placeholder: the kernel reads no seed then).
_NO_SEED = np.zeros(0)


def _settings(tolerance: float | tuple[float, float], separation: float) -> np.ndarray:
    """The kernel's ``settings`` array, validated; the same array for the same plain numbers (most calls)."""
    try:
        return _settings_cached(tolerance, separation)
    except TypeError:  # an unhashable tolerance (a list): validated afresh
        return np.array([*_tolerance(tolerance), _positive(separation, "separation")])


@lru_cache(maxsize=64)
def _settings_cached(tolerance: float | tuple[float, float], separation: float) -> np.ndarray:
    return np.array([*_tolerance(tolerance), _positive(separation, "separation")])


def _positive(value: float, name: str) -> float:
    number = float(value)
    if number > 0.0 and number < np.inf:
        return number
    if not (np.isfinite(number) and number > 0.0):
        raise RedkinError(f"{name} must be a positive finite number, got {value!r}")
    return number


def _tolerance(value: float | tuple[float, float]) -> tuple[float, float]:
    if isinstance(value, float):
        return _positive(value, "tolerance"), _positive(value, "tolerance")
    pair = np.atleast_1d(np.asarray(value, dtype=float))
    if pair.shape not in ((1,), (2,)):
        raise RedkinError(f"tolerance must be one number or a (metres, radians) pair, got {value!r}")
    position, rotation = (float(pair[0]), float(pair[-1]))
    return _positive(position, "tolerance (position)"), _positive(rotation, "tolerance (rotation)")
