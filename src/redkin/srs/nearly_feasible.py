"""Feasible arm angles of a nearly S-R-S arm: where the real arm's polished solution stays within its limits.

On the real arm the joint values at an arm angle, ``q(psi)``, are the
polished solutions of :func:`redkin.srs.nearly.ik`; no closed form gives the
arm angles where a joint meets a limit.  Feasibility of joint ``i`` changes
only where ``q_i(psi)`` crosses a limit, and between two neighbouring
critical points of ``q_i(psi)`` (zeros of its rate ``dq_i/dpsi``,
:func:`redkin.srs.nearly.self_motion_rates`) it crosses each limit at most
once.  The set is found in five steps:

1. samples: a uniform grid, with the endpoints and midpoints of the exact
   neighbour's feasible arcs [000 eqs. 20-30] for its limits loosened by
   ``delta`` (the largest ``|q - q_N|`` met on the grid, doubled, plus
   1e-6 rad), so that every neighbour arc, however narrow, holds a sample,
   and the arm angles where the branch's solution begins or ends (located by
   bisection, on the side where it exists: near a singular wrist the branch
   gives way to another for a few milliradians and comes back with a joint
   past its limit);
2. refinement: an interval between neighbouring samples is halved while a
   limited joint turns, or its rate changes times the width, by more than
   :data:`_BEND` rad across it (near a singular wrist ``q_5`` and ``q_7``
   sweep half a turn over a few milliradians of arm angle);
3. critical points: where a limited joint's rate changes sign between
   neighbouring samples within ``2 _BEND`` of a limit, bisection on its
   sign locates the extremum of ``q_i`` to 1e-10 rad, and the extremum
   joins the samples (a joint that touches or passes its limit between two
   samples: the narrow islands and gaps of a grid; after step 2 an
   extremum lies within about ``_BEND`` of the samples beside it);
4. each flag (whether the branch's solution exists, and for each limited
   joint whether it lies within its limits where it exists) is located by
   bisection where it changes between neighbouring samples, to 1e-10 rad,
   on its own true side;
5. the set is the intersection of the flags' arcs.

Two solutions: where the samples are not one sheet (the branch's solution is
missing at a sample, or refinement ends at :data:`_NARROWEST` with a limited
joint jumping across: the arm angle turns back along the self-motion there,
and :func:`redkin.srs.nearly.ik` returns one of the branch's two solutions),
steps 3-5 give way to the self-motion's curves through the samples' solutions
(:func:`redkin.srs.nearly_self_motion.feasible_along`): the arm angles of
their points on the branch and within the limits, each end and fold located
to 1e-10 rad along the curve.

What is certified: every arm angle of the returned set that a sample or an
endpoint holds has a certified solution within the limits, and every
endpoint is a change of one flag, to 1e-10 rad.  The set is complete (no
arc of the real arm missed) when, after step 2, no limited joint's rate
changes sign twice between two neighbouring samples: then steps 3-4 see
every extremum and every crossing.  That needs the joint curves to bend
by less than :data:`_BEND` within an interval, which the refinement
measures at the samples only; it is not proved between them.  A polish
that does not settle counts as a solution that does not exist, and
refinement stops at intervals of :data:`_NARROWEST` rad (a solution that
jumps to another sheet of the branch) or at :data:`_MOST_SAMPLES` samples.

How far the real set lies from the neighbour's: where both arms have the
branch's solution at ``psi`` and they differ by at most ``d`` in every
joint, a real solution within the limits makes the neighbour's lie within
the limits loosened by ``d``, and a neighbour's solution within the limits
tightened by ``d`` makes the real one lie within the limits.  So the real
set lies between the neighbour's exact sets for the limits tightened and
loosened by ``d`` (:attr:`NearlyFeasible.inner`, :attr:`NearlyFeasible.outer`),
``d`` the largest difference over every sample, doubled, plus 1e-6 rad
(:attr:`NearlyFeasible.delta`: measured, not derived from the offsets, which
bound ``|q - q_N|`` only through the inverse of a Jacobian that grows
without bound near a singular wrist or shoulder).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from redkin._validation import check_pose
from redkin.circle import TWO_PI, ArcSet, wrap_angle
from redkin.errors import RedkinError
from redkin.srs import _nearly_kernels
from redkin.srs.branches import Branch, parse_branch
from redkin.srs.feasible import FeasibleArmAngles, feasible_arm_angles
from redkin.srs.geometry import srs_geometry
from redkin.srs.ik import solve
from redkin.srs.nearly import NearlySRS, ik, self_motion_rates
from redkin.srs.nearly_self_motion import SelfMotion, curves_through, feasible_along

#: Arm angles of the uniform grid.
_SAMPLES = 720
#: Width [rad] below which a change of feasibility or of a rate's sign is located.
_ENDPOINT_TOLERANCE = 1e-10
#: Largest turn [rad] of a limited joint between neighbouring samples, and largest change of its rate times their
#: distance, after refinement (step 2).
_BEND = 0.02
#: Narrowest interval [rad] that refinement halves.
_NARROWEST = 1e-8
#: Rounds at most of locating where the branch's solution begins or ends and refining from there (step 1-2).
_EDGE_ROUNDS = 5
#: Samples at most after refinement.
_MOST_SAMPLES = 50_000
#: Curves of the self-motion at most where the samples are not one sheet.
_MOST_CURVES = 16
#: Slack [rad] of the limit test, as :func:`redkin.srs._nearly_kernels.within_limits`'s.
_LIMIT_SLACK = _nearly_kernels.LIMIT_SLACK


class NearlyFeasible(NamedTuple):
    """The feasible arm angles of one pose and branch on a nearly S-R-S arm.

    Attributes
    ----------
    feasible : ArcSet
        Arm angles where a certified solution of the branch lies within the limits (where the branch has two, either:
        module docstring, "Two solutions").
    branch : Branch
    delta : float
        The largest ``|q - q_N|`` [rad] between the real arm's solution and the neighbour's at the same arm angle over
        every sample, doubled, plus 1e-6 rad.
    samples : int
        Arm angles at which the real arm was solved, the bisections included.
    inner, outer : ArcSet
        The neighbour's exact feasible sets [000 eqs. 20-30] for the limits tightened and loosened by ``delta``:
        ``inner`` within ``feasible`` within ``outer`` wherever both arms have the branch's solution and they differ
        by ``delta`` at most (module docstring, "How far the real set lies from the neighbour's").  Where the
        neighbour does not reach the pose, ``inner`` is empty and ``outer`` the whole circle.
    """

    feasible: ArcSet
    branch: Branch
    delta: float
    samples: int
    inner: ArcSet
    outer: ArcSet


def feasible_arm_angles_nearly(arm: NearlySRS, pose: ArrayLike, branch: str | Branch = "+++",
                               samples: int = _SAMPLES) -> NearlyFeasible:
    """The arm angles at which the real arm reaches ``pose`` on ``branch`` within its limits (module docstring).

    Raises
    ------
    ValueError
        For a malformed pose (one (4, 4) pose) or branch, or fewer than 8 samples.
    """
    pose = check_pose(pose)
    if pose.shape != (4, 4):
        raise RedkinError(f"pose must be one (4, 4) pose, got shape {pose.shape}")
    if samples < 8:
        raise RedkinError(f"samples must be at least 8, got {samples}")
    label = parse_branch(branch)
    grid = np.linspace(-np.pi, np.pi, samples, endpoint=False)
    curve = _Curve(arm, pose, label, grid)
    curve.add(_announced(_neighbour_sets(arm, pose, label, _delta(arm, pose, grid, curve.q, curve.exists, label))))
    for _ in range(_EDGE_ROUNDS):  # where the solution begins or ends (the refinement finds more): refined from there
        count = len(curve.psi)
        curve.add(curve.changes([0])[0])
        curve.refine()
        if len(curve.psi) == count:
            break
    if curve.one_sheet():
        curve.add(curve.extrema())
        feasible = curve.located()
    else:
        feasible = feasible_along(arm, pose, label, curve.curves())
    delta = _delta(arm, pose, curve.psi, curve.q, curve.exists, label)
    inner, outer = _neighbour_sets(arm, pose, label, -delta), _neighbour_sets(arm, pose, label, delta)
    return NearlyFeasible(feasible, label, delta, curve.count, ArcSet.empty() if inner is None else inner.feasible,
                          ArcSet.full() if outer is None else outer.feasible)


class _Curve:
    """The branch's certified solutions of one pose as functions of the arm angle: the samples so far, sorted, in
    ``[-pi, pi)`` (``psi``), their joint values, whether each exists and the limited joints' rates, and how many arm
    angles were solved."""

    def __init__(self, arm: NearlySRS, pose: np.ndarray, label: Branch, psi: np.ndarray) -> None:
        self.arm, self.pose, self.label = arm, pose, label
        chain = arm.chain
        self.limited = np.flatnonzero(~chain.covers_circle)
        self.lower, self.upper = chain.lower[self.limited], chain.upper[self.limited]
        self.count = 0
        self.psi = np.empty(0)
        self.q, self.exists, self.rates = np.empty((0, 7)), np.empty(0, dtype=bool), np.empty((0, len(self.limited)))
        self.add(psi)

    def solved(self, psi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Joint values (M, 7) at arm angles ``psi`` (M,) and whether each exists (certified)."""
        result = ik(self.arm, np.broadcast_to(self.pose, psi.shape + (4, 4)), psi, self.label)
        self.count += len(psi)
        return result.q[:, 0], result.exists[:, 0]

    def rates_of(self, q: np.ndarray, exists: np.ndarray) -> np.ndarray:
        """The limited joints' ``dq/dpsi`` (M, L) at solutions ``q`` (M, 7); NaN where none exists."""
        rates = np.full((len(q), len(self.limited)), np.nan)
        if exists.any():
            rates[exists] = self_motion_rates(self.arm, q[exists])[:, self.limited]
        return rates

    def add(self, psi: np.ndarray) -> None:
        """Solve at new arm angles ``psi`` (any) and merge them into the samples; those already held are skipped."""
        psi = np.setdiff1d(_wrapped(psi), self.psi)
        q, exists = self.solved(psi)
        order = np.argsort(np.concatenate([self.psi, psi]), kind="stable")
        self.psi = np.concatenate([self.psi, psi])[order]
        self.q = np.concatenate([self.q, q])[order]
        self.exists = np.concatenate([self.exists, exists])[order]
        self.rates = np.concatenate([self.rates, self.rates_of(q, exists)])[order]

    def following(self) -> tuple[np.ndarray, np.ndarray]:
        """Each sample's next one (cyclic) and the width to it."""
        return np.roll(np.arange(len(self.psi)), -1), np.diff(np.append(self.psi, self.psi[0] + TWO_PI))

    def refine(self) -> None:
        """Halve intervals until no limited joint turns, nor its rate changes times the width, by more than
        :data:`_BEND` across one (module docstring, step 2)."""
        while len(self.psi) < _MOST_SAMPLES:
            following, width = self.following()
            turn = np.abs(_wrapped(self.q[following][:, self.limited] - self.q[:, self.limited]))
            bend = np.abs(self.rates[following] - self.rates) * width[:, None]
            split = (self.exists & self.exists[following] & (width > _NARROWEST)
                     & np.any((turn > _BEND) | ~(bend <= _BEND), axis=1))  # an infinite rate bends
            split = np.flatnonzero(split)[:_MOST_SAMPLES - len(self.psi)]
            if split.size == 0:
                break
            self.add(self.psi[split] + 0.5 * width[split])

    def extrema(self) -> np.ndarray:
        """The arm angles of the limited joints' extrema between neighbouring samples that come within
        ``2 _BEND`` of a limit (module docstring, step 3): where a joint's rate changes sign, located by bisection on
        the sign to :data:`_ENDPOINT_TOLERANCE`."""
        following, width = self.following()
        rates, q = self.rates, self.q[:, self.limited]
        near = np.minimum(np.abs(_wrapped(q - self.lower)), np.abs(_wrapped(q - self.upper))) <= 2.0 * _BEND
        change = ((self.exists & self.exists[following])[:, None] & (near | near[following])
                  & (np.sign(rates) * np.sign(rates[following]) < 0.0))
        interval, joint = np.nonzero(change)
        low = self.psi[interval]
        high = low + width[interval]
        low_sign = np.sign(rates[interval, joint])
        while low.size and np.max(high - low) > _ENDPOINT_TOLERANCE:
            middle = 0.5 * (low + high)
            q_middle, exists_middle = self.solved(_wrapped(middle))
            sign = np.sign(self.rates_of(q_middle, exists_middle)[np.arange(len(middle)), joint])
            keep = exists_middle  # where the solution is lost, the bisection goes on between low and the middle
            same = sign == low_sign
            low = np.where(keep & same, middle, low)
            high = np.where(keep & ~same, middle, np.where(keep, high, middle))
        return low

    def located(self) -> ArcSet:
        """The arcs where every flag holds (the solution exists; each limited joint lies within its limits where a
        solution exists), each change of a flag between neighbouring samples located by bisection to
        :data:`_ENDPOINT_TOLERANCE` on the flag's true side (module docstring, steps 4-5)."""
        edge, which, low_true = self.changes(range(1 + len(self.limited)))
        flags = self.flags(self.q, self.exists)
        feasible = ArcSet.full()
        for flag in range(flags.shape[1]):
            mine = which == flag
            feasible = feasible.intersection(_arcs(edge[mine], low_true[mine], bool(flags[0, flag])))
        return feasible

    def changes(self, chosen) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Each change of the ``chosen`` flags (:meth:`flags`' columns) between neighbouring samples, located by
        bisection to :data:`_ENDPOINT_TOLERANCE`: its arm angle on the flag's true side (not wrapped), the flag,
        and whether the flag holds before it."""
        flags = self.flags(self.q, self.exists)
        changes, which = np.nonzero(flags != np.roll(flags, -1, axis=0))  # between psi[k] and psi[k + 1] (cyclic)
        kept = np.isin(which, list(chosen))
        changes, which = changes[kept], which[kept]
        low = self.psi[changes]
        high = low + self.following()[1][changes]
        low_true = flags[changes, which]
        while low.size and np.max(high - low) > _ENDPOINT_TOLERANCE:
            middle = 0.5 * (low + high)
            same = self.flags(*self.solved(_wrapped(middle)))[np.arange(len(middle)), which] == low_true
            low, high = np.where(same, middle, low), np.where(same, high, middle)
        return np.where(low_true, low, high), which, low_true

    def one_sheet(self) -> bool:
        """Whether the samples read as one sheet: the branch's solution exists at every sample, and refinement left
        no interval at :data:`_NARROWEST` across which a limited joint jumps (module docstring, "Two solutions")."""
        following, width = self.following()
        turn = np.abs(_wrapped(self.q[following][:, self.limited] - self.q[:, self.limited]))
        return bool(self.exists.all() and not np.any((width <= _NARROWEST)[:, None] & (turn > _BEND)))

    def curves(self) -> list[SelfMotion]:
        """The self-motion's curves through the samples' solutions
        (:func:`redkin.srs.nearly_self_motion.curves_through`), :data:`_MOST_CURVES` at most."""
        return curves_through(self.arm, self.pose, self.q[self.exists], _MOST_CURVES)

    def flags(self, q: np.ndarray, exists: np.ndarray) -> np.ndarray:
        """(M, 1 + L): whether each solution exists, and whether each limited joint lies within its limits modulo
        whole turns or no solution exists."""
        inside = self.arm.chain.joints_within_limits(q, _LIMIT_SLACK, wrap=True)[:, self.limited]
        return np.concatenate([exists[:, None], inside | ~exists[:, None]], axis=1)


def _arcs(edge: np.ndarray, low_true: np.ndarray, everywhere: bool) -> ArcSet:
    """The arcs where a flag holds from its changes: at ``edge`` it ends where ``low_true`` and begins elsewhere;
    without a change it holds ``everywhere`` or nowhere."""
    if edge.size == 0:
        return ArcSet.full() if everywhere else ArcSet.empty()
    marks = np.concatenate([edge[~low_true], edge[low_true]])
    kinds = np.concatenate([np.ones(np.count_nonzero(~low_true)), np.zeros(np.count_nonzero(low_true))])
    order = np.argsort(np.mod(marks, TWO_PI))
    marks, kinds = marks[order], kinds[order]
    first = int(np.argmax(kinds == 1.0))
    marks, kinds = np.roll(marks, -first), np.roll(kinds, -first)
    return ArcSet([(float(marks[k]), float(marks[k + 1])) for k in range(0, len(marks) - 1, 2)])


def _delta(arm: NearlySRS, pose: np.ndarray, psi: np.ndarray, q: np.ndarray, exists: np.ndarray,
           label: Branch) -> float:
    """The largest ``|q - q_N|`` [rad] of the certified solutions ``q`` (M, 7) at arm angles ``psi`` (M,), doubled,
    plus 1e-6 rad."""
    from redkin.srs.ik import reachable

    found = np.flatnonzero(exists)
    if found.size == 0 or not reachable(arm.geometry, pose):
        return 1e-6
    exact = solve(arm.geometry, pose, psi[found], arm.geometry.kernel_branch(label))[:, 0]
    return float(2.0 * np.max(np.abs(_wrapped(q[found] - exact))) + 1e-6)


def _neighbour_sets(arm: NearlySRS, pose: np.ndarray, label: Branch, change: float) -> FeasibleArmAngles | None:
    """The neighbour's exact feasible sets [000 eqs. 20-30] of the branch with its limits loosened by ``change``
    [rad] (tightened where negative); ``None`` where the neighbour does not reach the pose or a tightened joint's
    range closes."""
    from redkin.srs.ik import reachable

    neighbour = arm.neighbour
    lower, upper = neighbour.lower - change, neighbour.upper + change
    if np.any(lower > upper):
        return None
    geometry = srs_geometry(neighbour.with_limits(lower, upper))
    return feasible_arm_angles(geometry, pose, label) if reachable(geometry, pose) else None


def _announced(loosened: FeasibleArmAngles | None) -> np.ndarray:
    """The endpoints and midpoints of the neighbour's feasible arcs of each joint with its limits loosened
    (module docstring, step 1); none where the neighbour does not reach the pose."""
    if loosened is None:
        return np.empty(0)
    points = []
    for arcs in (*loosened.per_joint.values(), loosened.feasible):
        for start, end in arcs.arcs:
            points += [start, end, start + 0.5 * ((end - start) % TWO_PI)]
    return _wrapped(np.array(points)) if points else np.empty(0)


def _wrapped(angles: np.ndarray) -> np.ndarray:
    """Arm angles into ``[-pi, pi)`` (:func:`redkin.circle.wrap_angle`, as an array)."""
    return np.asarray(wrap_angle(angles))
