"""What path resolution returns: a path through every waypoint, or the first waypoint where none exists."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from redkin.collision.steps import StepClearance
    from redkin.paths.timing import Trajectory

#: Why no path exists, by :attr:`PathFailure.reason`; ``{parameter}`` is the redundancy parameter in words
#: (:data:`_PARAMETER_WORDS`, :meth:`PathFailure.reason_text`).
REASONS = {
    "out-of-reach": "the pose is out of the arm's reach",
    "empty": "no {parameter} satisfies every joint limit on any branch",
    "collision": "no {parameter} within the joint limits keeps the body clear of the obstacles on any branch",
    "step": "no feasible configuration lies within the step bound of one reachable from the start",
    "start": "no feasible configuration lies within the step bound of the start configuration",
    "end": "no configuration reachable from the start meets the end condition",
    "winding": "a joint whose range exceeds 2 pi would have to turn past its range",
    "steps": "no step into this waypoint that the searched graph allows is proved clear of the obstacles",
}
#: The redundancy parameter of :attr:`PathResult.parameter` in words.
_PARAMETER_WORDS = {"psi": "arm angle", "q7": "value of q7"}


@dataclass(frozen=True)
class PathFailure:
    """The first waypoint at which no path exists, and why.

    Attributes
    ----------
    waypoint : int
        Index of the waypoint (0-based).
    reason : str
        One of :data:`REASONS`: ``"out-of-reach"``, ``"empty"``, ``"collision"``, ``"step"``, ``"start"``,
        ``"end"``, ``"winding"`` or ``"steps"`` (in a cell: every step into the waypoint that the sampled graph
        allows runs into an obstacle or is not proved clear, :mod:`redkin.paths.clear_steps`).
    joint : int or None
        The blocking joint (1-based): for ``"empty"`` the joint whose own feasible set is empty, or whose set
        empties the intersection of the joints before it, on the most branches; for ``"step"``, ``"start"`` and
        ``"end"`` the joint that must move most (relative to its bound) on the closest pair of configurations.
        ``None`` for ``"out-of-reach"``.
    exact : bool
        True where the failure is proved: by the arm's reach (``"out-of-reach"``, on every class), by the exact
        feasible sets (``"empty"``), or by a joint the poses fix that must move more than its bound (``"step"``,
        ``"start"``: an S-R-S arm's elbow); False where it is a statement about the sampled graph (see
        docs/paths.md).
    needed : float or None
        For a step failure: how far ``joint`` must move at least on the closest pair (radians); its bound is
        :attr:`PathResult.step` of that joint.
    per_branch : dict
        For ``"empty"``: the blocking joint of each branch (``"+++"`` -> joint, ``None`` where the branch is
        blocked by rounding alone).
    pair : tuple of str or None
        For ``"collision"``: the body's link and the obstacle (or other link) that remove the most arm angles over
        the branches; for ``"steps"``: the pair found too close on the most of the steps left out into the
        waypoint.
    parameter : str
        The arm's redundancy parameter, as :attr:`PathResult.parameter`: ``"psi"`` or ``"q7"``.
    """

    waypoint: int
    reason: str
    joint: int | None
    exact: bool
    needed: float | None = None
    per_branch: dict[str, int | None] = field(default_factory=dict)
    pair: tuple[str, str] | None = None
    parameter: str = "psi"

    @property
    def reason_text(self) -> str:
        """:data:`REASONS`' words for the reason, with the arm's parameter named (:data:`_PARAMETER_WORDS`)."""
        return REASONS[self.reason].format(parameter=_PARAMETER_WORDS[self.parameter])

    @property
    def message(self) -> str:
        """One line: the waypoint, the reason and the joint (or the link and the obstacle)."""
        text = f"no path: waypoint {self.waypoint}: {self.reason_text}"
        if self.pair is not None:
            text += f" ({self.pair[0]} meets {self.pair[1]} on most of them)"
        if self.joint is not None:
            text += f" (joint {self.joint}"
            text += f" must move {self.needed:.6g} rad)" if self.needed is not None else " blocks it)"
        return text


@dataclass(frozen=True)
class PathResult:
    """Joint values along a path of poses, or why there are none.

    Attributes
    ----------
    status : str
        ``"ok"`` or ``"no-path"``.
    q : numpy.ndarray, shape (N, 7)
        Joint values per waypoint (each within its limits, each joint moving at most ``step`` between
        waypoints, each reaching its pose within 1e-9); shape ``(0, 7)`` for ``"no-path"``.
    branch : list of str
        Branch per waypoint (``"+-+"``: signs of q2, q4, q6 in the chain's senses).
    psi : numpy.ndarray, shape (N,)
        The redundancy parameter per waypoint (:attr:`parameter`): the arm angle, or q7 on a Franka-class arm.
    clearance : float
        The smallest distance of any joint (with a range narrower than ``2 pi``) to a limit along the path,
        radians; ``inf`` where no joint has one; NaN for ``"no-path"``.
    motion : float
        The total joint motion, ``sum_k sum_i |q_{k+1, i} - q_{k, i}|`` (plus the move from ``q0``), radians.
    step : numpy.ndarray, shape (7,)
        The bound on each joint's move between waypoints.
    failure : PathFailure or None
    nodes : int
        Size of the graphs searched (arm-angle samples over all waypoints, branches and rounds).
    optimal : bool
        Whether ``clearance`` is proved the largest any path through these poses can keep, to within
        :data:`redkin.paths.OPTIMALITY_MARGIN` (1e-7 rad): the exact feasible sets of waypoint ``bottleneck``,
        with every limit moved that much further in than ``clearance``, are empty on every branch.
    bottleneck : int or None
        The waypoint that proves it (``None`` where not proved).
    parameter : str
        What ``psi`` holds: ``"psi"``, the arm angle (S-R-S and offset-elbow arms), or ``"q7"``, joint 7's value
        (the Franka class).
    trajectory : Trajectory or None
        The timed trajectory through ``q`` (:func:`redkin.paths.time_path`), where the path was resolved with
        ``timing``; ``None`` otherwise.
    stops : tuple of Stop
        Where the path was resolved with ``allow_stops``: the reconfiguration stops that join its continuous
        segments, fewest first (:mod:`redkin.paths.stops`); empty for a continuous path.
    steps : StepClearance or None
        In a cell: what is proved of each step between waypoints (:func:`redkin.collision.step_clearance`; after a
        stop, from its departure configuration); every step of a path returned is certified clear.  ``None``
        without a cell.
    trajectory_steps : StepClearance or None
        In a cell, for a timed path: what is proved of the steps between the :attr:`trajectory`'s samples (the
        controller's commands at its rate, the spline through the waypoints, not the linear steps of
        :attr:`steps`); a step may be blocked where the spline swings wide of the chord.  ``None`` otherwise.
    cell_clearance : float or None
        In a cell: the least signed distance over the waypoints between the body and the obstacles or its own
        checked links (metres, at least the scene's margin); what the objective ``"obstacle-clearance"`` makes
        largest.  ``None`` without a cell.
    """

    status: str
    q: np.ndarray
    branch: list[str]
    psi: np.ndarray
    clearance: float
    motion: float
    step: np.ndarray
    failure: PathFailure | None
    nodes: int
    optimal: bool = False
    bottleneck: int | None = None
    parameter: str = "psi"
    trajectory: Trajectory | None = None
    stops: tuple[Stop, ...] = ()
    steps: StepClearance | None = None
    cell_clearance: float | None = None
    trajectory_steps: StepClearance | None = None

    @property
    def ok(self) -> bool:
        """Whether a path was found."""
        return self.status == "ok"


#: Why the arm stops, by :attr:`Stop.reason`.
STOP_REASONS = {"branch": "the arm changes branch", "jump": "the redundancy parameter jumps on one branch"}


@dataclass(frozen=True)
class Stop:
    """A reconfiguration at one waypoint: the tool at rest, the arm moving from one configuration to another.

    Attributes
    ----------
    waypoint : int
    reason : str
        ``"branch"`` (the branch changes) or ``"jump"`` (the same branch, the parameter jumps).
    branch_before, branch_after : str
    parameter_before, parameter_after : float
        The redundancy parameter (arm angle or q7, :attr:`PathResult.parameter`) on arrival and departure.
    joint : int
        The joint (1-based) that moves most between the two configurations.
    move : float
        How far it moves (radians).
    motion : str
        ``"self-motion"`` (the tool stays at the pose; see the module's docstring) or ``"free-space"``.
    path : numpy.ndarray, shape (M, n)
        The joint values of the reconfiguration, from the arrival configuration (first row) to the departure one.
    steps : StepClearance or None
        In a cell: what is proved of the steps along :attr:`path` (the joints moving linearly between its rows); a
        reconfiguration is not searched around the obstacles, so a step may be blocked (:attr:`message` says so).
        ``None`` without a cell.
    """

    waypoint: int
    reason: str
    branch_before: str
    branch_after: str
    parameter_before: float
    parameter_after: float
    joint: int
    move: float
    motion: str
    path: np.ndarray
    steps: StepClearance | None = None

    @property
    def message(self) -> str:
        """One line: where, why, and how the arm reconfigures (in a cell, whether its motion is proved clear)."""
        change = (f"from branch {self.branch_before} to {self.branch_after}" if self.reason == "branch" else
                  f"on branch {self.branch_before}, {self.parameter_before:.6g} -> {self.parameter_after:.6g}")
        cell = ""
        if self.steps is not None:
            cell = ("; proved clear of the obstacles" if self.steps.certified.all() else
                    "; NOT proved clear of the obstacles" + (f": {self.steps.link[self.steps.blocked][0]} meets "
                                                              f"{self.steps.against[self.steps.blocked][0]}"
                                                              if self.steps.blocked.any() else ""))
        return (f"stop at waypoint {self.waypoint}: {STOP_REASONS[self.reason]} ({change}; joint {self.joint} moves "
                f"{self.move:.6g} rad, {self.motion}{cell})")
