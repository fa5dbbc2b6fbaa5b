"""One arm, one API: a robot loaded and classified once, asked every question in the same shapes.

:func:`arm` reads a model name, a robot file (URDF, xacro, MJCF, redkin's TOML) or takes a
:class:`~redkin.chain.SerialChain`, names its class once (:func:`redkin.arms.classify.arm_angle_class`) and
converts it once to the form its kernels take (:mod:`redkin.arms.registry`); :class:`Arm` then answers at the speed
of the class's own functions, with one result type per question for every class::

    arm = redkin.arm("fr3.urdf")                 # arm.kind 'Franka (q7)', arm.parameter.name 'q7'
    q = np.array([0.1, -0.4, 0.2, -2.0, 0.3, 1.6, 0.5])
    t, branch = arm.parameter_of(q), arm.branch_of(q)
    solutions = arm.ik(arm.fk(q), t)             # Solutions: q (8, 7), exists (8,), within_limits (8,) ...
    solutions.q[arm.branches.index(branch)]      # q again
    arm.feasible(arm.fk(q)).arcs(branch)         # the feasible q7 of that branch at that pose

Without a value of the parameter, :meth:`Arm.ik` solves numerically on every class (and is the only IK of a general
chain).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np
from numpy.typing import ArrayLike

if TYPE_CHECKING:
    from redkin.collision.body import Body
    from redkin.collision.scene import Scene

from redkin.arms.analysis import Analysis, as_arcs
from redkin.arms.feasible_sets import FeasibleSets
from redkin.arms.parameter import Parameter
from redkin.arms.protocol import ArmKind
from redkin.arms.solutions import NUMERICAL, Solutions
from redkin.chain import SerialChain
from redkin.circle import TWO_PI
from redkin.errors import RedkinError, UnreachablePoseError

#: Where :func:`arm` keeps the arm of a chain per nearly S-R-S tolerance (the chain's arrays are read-only, so it
#: never goes stale).
_CACHE_KEY = "_redkin_arms"


class Optimal(NamedTuple):
    """The limit-avoiding values of the parameter (:meth:`Arm.optimal`).

    Attributes
    ----------
    value : numpy.ndarray, shape (..., B)
        Within the branch's feasible set (``nan`` where that is empty, or the pose out of reach).
    unclamped : numpy.ndarray, shape (..., B)
        Over every value at which the branch exists (``nan`` where none).
    branches : tuple of str
    """

    value: np.ndarray
    unclamped: np.ndarray
    branches: tuple[str, ...]


class Singular(NamedTuple):
    """The values of the parameter at which the shoulder or the wrist is singular (:meth:`Arm.singular`).

    Attributes
    ----------
    shoulder, wrist : numpy.ndarray of object, shape (..., B)
        Each a sorted tuple of values (empty where none, or the pose out of reach).
    branches : tuple of str
    """

    shoulder: np.ndarray
    wrist: np.ndarray
    branches: tuple[str, ...]


@dataclass(frozen=True, eq=False)
class Arm:
    """A robot arm classified and converted once (module docstring); build it with :func:`arm`.

    Attributes
    ----------
    chain : SerialChain
    kind : str
        The class: :data:`redkin.arms.classify.SRS`, ``OFFSET_ELBOW``, ``FRANKA``, ``NEARLY_SRS`` or ``GENERAL`` of
        :mod:`redkin.arms.classify`.
    parameter : Parameter or None
        The redundancy parameter; ``None`` for a general chain.
    branches : tuple of str
        The branch labels of :meth:`ik`'s rows (``"+++"`` ... ``"---"``); empty for a general chain.
    implementation : ArmKind
        The class's implementation (:mod:`redkin.arms.registry`), which the questions below ask; path resolution
        reads its ``family``.
    words : callable
        Words :attr:`reason` on first use (:func:`redkin.arms.classify.class_and_reason`).
    """

    chain: SerialChain
    kind: str
    parameter: Parameter | None
    branches: tuple[str, ...]
    implementation: ArmKind = field(repr=False)
    words: Callable[[], str] = field(repr=False)

    @cached_property
    def reason(self) -> str:
        """Why it is of that class, in one line, worded on first use: the words of a nearly S-R-S arm measure how
        far its poses differ from its neighbour's (:func:`redkin.srs.conventions.model_error`), a search that
        most questions do not need."""
        return self.words()

    # ------------------------------------------------------------- the chain
    def fk(self, q: ArrayLike, *, out: np.ndarray | None = None) -> np.ndarray:
        """The tool's pose ``(..., 4, 4)`` of joint values ``(..., n)``, into ``out`` where given
        (:meth:`redkin.chain.SerialChain.fk`)."""
        return self.chain.fk(q, out=out)

    def jacobian(self, q: ArrayLike, *, out: np.ndarray | None = None) -> np.ndarray:
        """The geometric Jacobian ``(..., 6, n)``, into ``out`` where given
        (:meth:`redkin.chain.SerialChain.jacobian`)."""
        return self.chain.jacobian(q, out=out)

    def within_limits(self, q: ArrayLike, tolerance: float = 0.0) -> np.ndarray:
        """Whether joint values lie within the limits (:meth:`redkin.chain.SerialChain.within_limits`)."""
        return self.chain.within_limits(q, tolerance)

    # ------------------------------------------------------------- IK
    def ik(self, poses: ArrayLike, t: ArrayLike | str | None = None, *, branches: str | Sequence[str] | None = None,
           q0: ArrayLike | None = None, body: Body | None = None, scene: Scene | None = None,
           **solver: Any) -> Solutions:
        """Every branch's solution (or ``branches``') of target poses at values ``t`` of the redundancy parameter.

        Parameters
        ----------
        poses : array_like, shape (..., 4, 4)
            Target poses of the tool in the base frame.
        t : array_like or "optimal", optional
            The parameter's values, broadcast against the poses' batch shape: the arm angle psi [000 eq. 6] or q7
            (:attr:`parameter`).  ``"optimal"``: each branch's limit-avoiding value (:meth:`optimal`).  Omitted:
            the numerical solver (:func:`redkin.numerical.ik`, keywords ``solver``), its solutions put in the rows
            of their branches, each with its own parameter value.
        branches : str or sequence of str, optional
            The rows wanted (labels of :attr:`branches`); default all.
        q0 : array_like, shape (..., n), optional
            Joint values to stay near: the numerical solver's seeds, and each joint of a closed form's row moved by
            whole turns to its value nearest ``q0`` where the joint's range allows.  Where a branch can have two
            solutions at one value (a nearly S-R-S arm next to a stretched elbow or a straight shoulder), the row
            is the one nearest ``q0`` of :meth:`every_solution`'s (which follows each pose's self-motion: 0.1-1 s a
            pose).
        body, scene : Body and Scene, optional
            A cell: every row is marked with its clearance and closest pair, and whether it keeps the scene's margin
            from every obstacle and between the body's links (:attr:`Solutions.clearance`,
            :attr:`Solutions.collision_free`).  Without ``t``, only such solutions are returned
            (:func:`redkin.collision.collision_free_ik`, keywords ``solver`` too); with ``"optimal"``, each branch's
            row is at its limit-avoiding value inside the certified collision-free set (:meth:`optimal` in the
            cell); at values of ``t`` the rows are marked, and :meth:`feasible` with the same two gives the
            collision-free values.  Where a branch can have two solutions at one value, a row that is not clear
            within the limits is replaced by one of :meth:`every_solution`'s that is, where there is one (so an arm
            angle of a certified collision-free set gets its free solution; rule:
            :func:`redkin.arms.branch_choice.preferred`).

        Returns
        -------
        Solutions
            ``q`` ``(..., B, n)``; a pose out of reach is a row that does not exist, with its ``reason``.

        Raises
        ------
        ValueError
            For a malformed pose, value, branch or seed; ``t`` on a general chain; a body without a scene or the
            reverse.
        """
        rows = self._rows(branches)
        cell = _cell(body, scene, "collision-free solutions")
        if t is None:
            return self._marked(self._numerical(poses, rows, q0, solver, cell), cell)
        if solver:
            raise RedkinError(f"{', '.join(sorted(solver))}: keywords of the numerical solver, which runs without t")
        self._need_parameter("solutions at a value of the redundancy parameter")
        if isinstance(t, str):
            if t != "optimal":
                raise RedkinError(f"t must be values of {self._name()} or 'optimal', got {t!r}")
            result = self._at_optimal(poses, rows, body, scene)
        else:
            from redkin._validation import as_float_array

            result = self.implementation.solve(poses, as_float_array(t, "t"), rows)
        seeds = None
        if q0 is not None:
            from redkin._validation import check_vectors

            seeds = np.broadcast_to(check_vectors(q0, self.chain.n, "q0"), result.q.shape[:-2] + (self.chain.n,))
            moved = self.chain.nearest_in_range(result.q, near=np.broadcast_to(seeds[..., None, :], result.q.shape))
            result = _replace(result, q=np.where(result.exists[..., None], moved, result.q))
        return self._preferred(poses, self._marked(result, cell), seeds, cell)

    def _marked(self, result: Solutions, cell: tuple[Body, Scene] | None) -> Solutions:
        """``result`` with each row's clearance, closest pair and collision-free mark in the ``cell`` (unchanged
        without one)."""
        if cell is None:
            return result
        from redkin.collision.clearance import Clearance, clearance

        body, scene = cell
        measured = clearance(self.chain, body, scene, np.where(result.exists[..., None], result.q, 0.0))
        distance = np.where(result.exists, measured.distance, np.nan)
        return _replace(result, clearance=Clearance(distance, np.where(result.exists, measured.link, ""),
                                                    np.where(result.exists, measured.against, "")),
                        collision_free=result.exists & (distance >= scene.margin))

    def _preferred(self, poses: ArrayLike, result: Solutions, q0: np.ndarray | None,
                   cell: tuple[Body, Scene] | None) -> Solutions:
        """``result`` (marked in the ``cell``) with each row the branch's solution that
        :func:`redkin.arms.branch_choice.preferred` picks among :meth:`every_solution`'s, on a class whose branch may
        have several at one value (a nearly S-R-S arm; the others return ``result``): every row of a pose in reach
        where ``q0`` is given, else the rows that are not clear of the cell within the limits.  It follows the
        pose's self-motion, once for each value of the parameter asked (0.1-1 s a pose)."""
        if self.implementation.one_per_branch or (q0 is None and cell is None):
            return result
        from redkin._validation import check_pose
        from redkin.arms.branch_choice import candidates, preferred
        from redkin.collision.clearance import clearance

        batch = result.exists.shape[:-1]
        flat_poses = np.broadcast_to(check_pose(poses), batch + (4, 4)).reshape(-1, 4, 4)
        need = ~np.broadcast_to(np.asarray(result.reach.out, dtype=bool), batch)[..., None] & np.ones_like(
            result.exists)
        if q0 is None:
            assert result.collision_free is not None
            need &= ~(result.collision_free & result.within_limits)
        if not need.any():
            return result
        count, n = len(result.branches), self.chain.n
        q, exists = result.q.reshape(-1, count, n).copy(), result.exists.reshape(-1, count).copy()
        within = result.within_limits.reshape(-1, count).copy()
        values = result.parameter.reshape(-1, count)
        seeds = None if q0 is None else q0.reshape(-1, n)
        rows = np.array([self.branches.index(label) for label in result.branches])
        flat_need = need.reshape(-1, count) & ~np.isnan(values)
        for k in np.flatnonzero(flat_need.any(axis=1)):
            near = None if seeds is None else seeds[k]
            for value in np.unique(values[k, flat_need[k]]):  # one self-motion for the rows at one value
                asked = np.flatnonzero(flat_need[k] & (values[k] == value))
                for b, found in zip(asked, self.implementation.every_solutions(flat_poses[k], float(value),
                                                                               rows[asked])):
                    if not len(found):
                        continue
                    moved, inside = candidates(self.chain, found, near)
                    clear = None if cell is None else clearance(self.chain, *cell, moved).distance >= cell[1].margin
                    pick = preferred(moved, inside, clear, near)
                    q[k, b], exists[k, b], within[k, b] = moved[pick], True, inside[pick]
        chosen = _replace(result, q=q.reshape(result.q.shape), exists=exists.reshape(batch + (count,)),
                          within_limits=within.reshape(batch + (count,)))
        return self._marked(chosen, cell)

    def _at_optimal(self, poses: ArrayLike, rows: np.ndarray | None, body: Body | None = None,
                    scene: Scene | None = None) -> Solutions:
        from redkin._validation import check_pose

        poses = check_pose(poses)
        best = self.optimal(poses, None if rows is None else [self.branches[r] for r in rows], body=body,
                            scene=scene).value
        parts = [self.implementation.solve(poses, np.nan_to_num(best[..., k]), np.array([r]))
                 for k, r in enumerate(range(len(self.branches)) if rows is None else rows)]
        exists = np.concatenate([part.exists for part in parts], axis=-1) & ~np.isnan(best)
        first = parts[0]
        return Solutions(np.concatenate([part.q for part in parts], axis=-2), exists,
                         np.concatenate([part.within_limits for part in parts], axis=-1) & exists,
                         tuple(part.branches[0] for part in parts), first.method, best, first._out, first._reach,
                         "no feasible value of the parameter on this branch")

    def _numerical(self, poses: ArrayLike, rows: np.ndarray | None, q0: ArrayLike | None,
                   solver: dict[str, Any], cell: tuple[Body, Scene] | None = None) -> Solutions:
        if cell is None:
            from redkin.numerical import ik as numerical_ik

            found = numerical_ik(self.chain, poses, q0=q0, **solver)
        else:
            from redkin.collision.free_ik import collision_free_ik

            free = collision_free_ik(self.chain, *cell, poses, q0=q0, **solver)
            found = free.solver._replace(q=free.q, found=free.found)
        clear = "" if cell is None else "collision-free "
        reach = found.reach
        assert reach is not None  # numerical.ik always sets it
        if self.parameter is None:
            if rows is not None:
                raise RedkinError(f"{self.chain.name!r} has no branches ({self.reason})")
            labels = tuple(str(k + 1) for k in range(found.found.shape[-1]))
            return Solutions(found.q, found.found, found.found.copy(), labels, NUMERICAL,
                             np.full(found.found.shape, np.nan), lambda: reach.out, lambda: reach,
                             f"no further {clear}solution found")
        shape, n, count = found.found.shape[:-1], self.chain.n, len(self.branches)
        q = np.zeros(shape + (count, n))
        exists = np.zeros(shape + (count,), dtype=bool)
        value = np.full(shape + (count,), np.nan)
        if found.found.any():  # each solution into its branch's row, the first found (nearest the seed) kept
            solutions = found.q[found.found]  # in C order: pose by pose, each pose's in the order found
            branch, parameter = self.implementation.read(np.ascontiguousarray(solutions))
            pose = np.ravel_multi_index(np.nonzero(found.found)[:-1], shape) if shape else np.zeros(len(branch), int)
            slot = pose * count + branch
            _, first = np.unique(slot, return_index=True)
            q.reshape(-1, n)[slot[first]] = solutions[first]
            exists.reshape(-1)[slot[first]] = True
            value.reshape(-1)[slot[first]] = parameter[first]
        result = Solutions(q, exists, exists.copy(), self.branches, NUMERICAL, value, lambda: reach.out,
                           lambda: reach, f"no {clear}solution of the branch found")
        return result if rows is None else _rows_of(result, rows)

    # ------------------------------------------------------------- the redundancy
    def feasible(self, poses: ArrayLike, branches: str | Sequence[str] | None = None, *, body: Body | None = None,
                 scene: Scene | None = None) -> FeasibleSets:
        """The feasible sets of every branch (or ``branches``) at each pose: the values of the parameter at which
        the branch's solution exists and lies within every joint limit ([000 eq. 30] on S-R-S arms, [F8]-[F9] on
        the Franka class; certified, not proved complete, on nearly S-R-S arms).

        With ``body`` and ``scene``: the certified collision-free sets of :func:`redkin.collision.free_sets_of`
        (:func:`redkin.collision.collision_free_arm_angles` on S-R-S and offset-elbow arms,
        :func:`redkin.collision.collision_free_q7` on the Franka class, read off the certified self-motion on nearly
        S-R-S arms) instead, within the limits and clear of every obstacle and between the body's links by the
        scene's margin (``exact`` false: ends located to 1e-6 rad).
        """
        self._need_parameter("feasible sets")
        assert self.parameter is not None
        if body is not None or scene is not None:
            return self._free(poses, branches, body, scene)
        rows = self._rows(branches)
        poses = np.asarray(poses, dtype=float)  # the class's own function checks them
        if poses.ndim < 2 or poses.shape[-2:] != (4, 4):
            from redkin._validation import check_pose

            check_pose(poses)  # the words of a malformed shape
        shape = poses.shape[:-2]
        start, end, feasible = self.implementation.pieces(poses.reshape(-1, 4, 4))
        labels = self.branches
        if rows is not None:
            start, end, feasible = start[:, rows], end[:, rows], feasible[:, rows]
            labels = tuple(self.branches[r] for r in rows)
        if shape != (len(start),):
            start, end, feasible = (part.reshape(shape + part.shape[1:]) for part in (start, end, feasible))
        return FeasibleSets(start, end, feasible, labels, self.parameter.name, self.parameter.wraps,
                            self.implementation.exact)

    def _free(self, poses: ArrayLike, branches: str | Sequence[str] | None, body: Body | None,
              scene: Scene | None) -> FeasibleSets:
        """:meth:`feasible` in a cell: each pose's certified collision-free arcs as pieces."""
        from redkin.paths.family import as_pieces

        free = self._free_per_pose(poses, branches, body, scene)
        assert self.parameter is not None
        labels = self.labels(branches)
        sets = [[[(lo, hi + TWO_PI if wraps else hi) for (lo, hi), wraps
                  in zip(arcs.bounds.tolist(), arcs.wraps.tolist(), strict=True)] for arcs in one.free]
                for one in free.values()]
        pieces = as_pieces(sets, len(labels))
        shape = np.asarray(poses).shape[:-2] + pieces.start.shape[1:]
        return FeasibleSets(pieces.start.reshape(shape), pieces.end.reshape(shape), pieces.feasible.reshape(shape),
                            labels, self.parameter.name, self.parameter.wraps, False)

    def optimal(self, poses: ArrayLike, branches: str | Sequence[str] | None = None, *,
                target: ArrayLike | None = None, weights: ArrayLike | None = None, body: Body | None = None,
                scene: Scene | None = None) -> Optimal:
        """The limit-avoiding value of the parameter of each pose and branch ([000 eqs. 36-40] on S-R-S and nearly
        S-R-S arms, [F10] on the Franka class).

        Parameters
        ----------
        poses : array_like, shape (..., 4, 4)
        branches : str or sequence of str, optional
        target : array_like, shape (7,), optional
            The joint values to stay nearest (default: the middle of each range).
        weights : array_like, shape (2,), optional
            The shoulder's and the wrist's weight [000 eq. 40] (default 0.5, 0.5); arm-angle classes only.
        body, scene : Body and Scene, optional
            Together: ``value`` is taken within the certified
            collision-free set of :meth:`feasible` with them instead of the feasible set -- the arm angle of that set
            nearest the unclamped optimum, as [000] clamps into the feasible set; on the Franka class [F10]'s
            minimiser over the free intervals.  ``unclamped`` is the same minimiser over every value (on q7 the
            better of the whole range's search and the free intervals', so it may move by the search's tolerance).
        """
        goal, pair = self._goal(target, weights)
        free: dict[tuple[int, ...], Any] = {}
        if body is not None or scene is not None:
            free = self._free_per_pose(poses, branches, body, scene)

        def answer(pose: np.ndarray, row: int, place: tuple[int, ...]) -> tuple[float, float]:
            within = free[place[:-1]].free[place[-1]] if free else None
            return self.implementation.optimal(pose, row, goal, pair, within)

        value, unclamped = self._per_pose("a limit-avoiding value", poses, branches, answer, (np.nan, np.nan))
        return Optimal(value.astype(float), unclamped.astype(float), self.labels(branches))

    def _free_per_pose(self, poses: ArrayLike, branches: str | Sequence[str] | None, body: Body | None,
                       scene: Scene | None) -> dict[tuple[int, ...], Any]:
        """Each pose's certified collision-free sets (:func:`redkin.collision.free_sets_of`), by the pose's index (in
        C order)."""
        from redkin._validation import check_pose
        from redkin.collision.free_sets import free_sets_of

        cell = _cell(body, scene, "collision-free sets")
        assert cell is not None  # its callers pass a body or a scene
        self._need_parameter("collision-free sets")
        checked = check_pose(poses)
        sets = free_sets_of(self, checked.reshape(-1, 4, 4), *cell, self.labels(branches))
        return dict(zip(np.ndindex(checked.shape[:-2]), sets, strict=True))

    def joint_sets(self, pose: ArrayLike, branch: str) -> dict[int, np.ndarray]:
        """Per joint (1-based), the arcs ``(k, 2)`` of the parameter at which one pose's branch keeps that joint
        within its limits ([000 eq. 29]); an arc with ``start > end`` passes through ``+-pi``.  S-R-S and
        offset-elbow arms only: the other classes refuse in words."""
        from redkin._validation import check_pose

        self._need_parameter("per-joint feasible sets")
        pose = check_pose(pose)
        if pose.shape != (4, 4):
            raise RedkinError(f"pose must be one (4, 4) pose, got shape {pose.shape}")
        rows = self._rows(branch)
        assert rows is not None
        return {joint: as_arcs(arcs)
                for joint, arcs in self.implementation.joint_sets(pose, int(rows[0])).items()}

    def singular(self, poses: ArrayLike, branches: str | Sequence[str] | None = None) -> Singular:
        """The singular values of the parameter of each pose and branch ([000 eqs. 31-34]; on nearly S-R-S arms
        where the real arm's axes 1 and 3, 5 and 7 align).  The Franka class has none here: it refuses."""
        shoulder, wrist = self._per_pose("singular values", poses, branches,
                                         lambda pose, row, _: self.implementation.singular(pose, row), ((), ()))
        return Singular(shoulder, wrist, self.labels(branches))

    def _per_pose(self, what: str, poses: ArrayLike, branches: str | Sequence[str] | None, answer: Any,
                  unreachable: tuple[Any, Any]) -> tuple[np.ndarray, np.ndarray]:
        """``answer(pose, row, place)`` of each pose and branch (``place``: the pose's index and the branch's column
        in the result), and ``unreachable`` where it raises :class:`redkin.errors.UnreachablePoseError`."""
        from redkin._validation import check_pose

        self._need_parameter(what)
        rows = self._rows(branches)
        poses = check_pose(poses)
        picked = range(len(self.branches)) if rows is None else rows
        first = np.empty(poses.shape[:-2] + (len(picked),), dtype=object)
        second = np.empty_like(first)
        for index in np.ndindex(poses.shape[:-2]):
            for k, r in enumerate(picked):
                try:
                    first[index + (k,)], second[index + (k,)] = answer(poses[index], int(r), index + (k,))
                except UnreachablePoseError:
                    first[index + (k,)], second[index + (k,)] = unreachable
        return first, second

    def analyse(self, pose: ArrayLike, branches: str | Sequence[str] | None = None, *,
                target: ArrayLike | None = None, weights: ArrayLike | None = None) -> Analysis:
        """Everything one pose's redundancy holds (:class:`redkin.arms.analysis.Analysis`): the feasible set of every
        branch and, for each branch asked (default all), the per-joint sets and singular values where the class has
        them and the limit-avoiding values (``target`` and ``weights`` as :meth:`optimal` takes them); what
        ``redkin arm-angles`` prints and ``redkin explore`` draws.

        Raises
        ------
        ValueError
            For a malformed pose (one ``(4, 4)``), branch, target or weights (weights on the Franka class), a pose
            out of reach where the class proves it so, or a general chain.
        """
        from redkin._validation import check_pose

        self._need_parameter("an analysis of the redundancy at a pose")
        pose = check_pose(pose)
        if pose.shape != (4, 4):
            raise RedkinError(f"pose must be one (4, 4) pose, got shape {pose.shape}")
        goal, pair = self._goal(target, weights)
        rows = self._rows(branches)
        return self.implementation.analyse(pose, np.arange(len(self.branches)) if rows is None else rows, goal, pair)

    def every_solution(self, pose: ArrayLike, t: float, branch: str) -> np.ndarray:
        """Every solution ``(K, n)`` of one pose ``(4, 4)`` and branch at the parameter's value ``t``: at most one on
        an exact class; on a nearly S-R-S arm near a stretched elbow or a straight shoulder, possibly two."""
        from redkin._validation import as_float_array, check_finite, check_pose

        self._need_parameter("every solution at a value of the redundancy parameter")
        pose = check_pose(pose)
        if pose.shape != (4, 4):
            raise RedkinError(f"pose must be one (4, 4) pose, got shape {pose.shape}")
        if not isinstance(branch, str):
            raise RedkinError(f"branch must be one of {', '.join(self.branches)}, got {branch!r}")
        rows = self._rows(branch)
        assert rows is not None  # a str names one branch
        value = as_float_array(t, "t")
        if value.shape != ():
            raise RedkinError(f"t must be one value of the redundancy parameter, got shape {value.shape}")
        check_finite(value, "t")
        return self.implementation.every_solutions(pose, float(value), rows)[0]

    def parameter_of(self, q: ArrayLike) -> np.ndarray:
        """The parameter's value of configurations ``q`` ``(..., n)``: the arm angle [000 eq. 6], or q7."""
        return self._read_batch(q)[1]

    def branch_of(self, q: ArrayLike) -> np.ndarray:
        """The branch labels of configurations ``q`` ``(..., n)``, an array of str of shape ``(...)``."""
        index = self._read_batch(q)[0]
        return np.asarray(self.branches, dtype=object)[index]

    def _read_batch(self, q: ArrayLike) -> tuple[np.ndarray, np.ndarray]:
        from redkin._validation import check_vectors

        self._need_parameter("a configuration's branch and parameter")
        q = check_vectors(q, self.chain.n, "q")
        branch, value = self.implementation.read(np.ascontiguousarray(q.reshape(-1, self.chain.n)))
        return branch.reshape(q.shape[:-1]), value.reshape(q.shape[:-1])

    # ------------------------------------------------------------- arguments
    def _goal(self, target: ArrayLike | None,
              weights: ArrayLike | None) -> tuple[np.ndarray | None, tuple[float, float] | None]:
        """The target joint values and the weights of a limit-avoiding value, checked."""
        from redkin._validation import MAX_LENGTH, check_magnitude, check_vectors
        from redkin.srs.optimal import check_weights

        goal = None if target is None else check_magnitude(check_vectors(target, self.chain.n, "target"), "target",
                                                           MAX_LENGTH, "rad")
        if goal is not None and goal.shape != (self.chain.n,):
            raise RedkinError(f"target must be one vector of {self.chain.n} joint values, got shape {goal.shape}")
        return goal, None if weights is None else check_weights(weights)

    def _rows(self, branches: str | Sequence[str] | None) -> np.ndarray | None:
        if branches is None:
            return None
        if not isinstance(branches, str) and not (isinstance(branches, Sequence | np.ndarray)):
            raise RedkinError(f"branches must be a branch label or a list of them, got {branches!r}")
        labels = [branches] if isinstance(branches, str) else list(branches)
        if not self.branches:
            raise RedkinError(f"{self.chain.name!r} has no branches ({self.reason})")
        rows = []
        for label in labels:
            if str(label) not in self.branches:
                raise RedkinError(f"branch must be one of {', '.join(self.branches)}, got {label!r}")
            rows.append(self.branches.index(str(label)))
        if not rows:
            raise RedkinError("branches must name at least one branch")
        return np.array(rows, dtype=np.int64)

    def labels(self, branches: str | Sequence[str] | None = None) -> tuple[str, ...]:
        """The labels of ``branches`` (default every branch of the arm), each checked to be one of the arm's.

        Raises
        ------
        RedkinError
            For an unknown branch, none named, or an arm without branches.
        """
        rows = self._rows(branches)
        return self.branches if rows is None else tuple(self.branches[r] for r in rows)

    def _name(self) -> str:
        return "the redundancy parameter" if self.parameter is None else self.parameter.name

    def _need_parameter(self, what: str) -> None:
        if self.parameter is None:
            raise RedkinError(f"{what} need a redundancy parameter: {self.chain.name!r} has none ({self.reason}); "
                              f"ik without t solves it numerically")


def _cell(body: Body | None, scene: Scene | None, what: str) -> tuple[Body, Scene] | None:
    """The cell ``(body, scene)`` of a call that takes one, ``None`` where it has neither.

    Raises
    ------
    RedkinError
        For one without the other (``what`` needs both), or either of another type (a file's name, say), naming
        the function that reads it.
    """
    if body is None and scene is None:
        return None
    if body is None or scene is None:
        raise RedkinError(f"{what} need both the arm's body and the scene")
    from redkin.collision.body import Body
    from redkin.collision.scene import Scene

    if not isinstance(body, Body):
        raise RedkinError(f"body must be a redkin.collision.Body (redkin.collision.read_body reads a body file, "
                          f"builtin_body a named model's), got {type(body).__name__}")
    if not isinstance(scene, Scene):
        raise RedkinError(f"scene must be a redkin.collision.Scene (redkin.collision.read_scene reads a scene file), "
                          f"got {type(scene).__name__}")
    return body, scene


def _replace(result: Solutions, **fields: Any) -> Solutions:
    from dataclasses import replace

    return replace(result, **fields)


def _rows_of(result: Solutions, rows: np.ndarray) -> Solutions:
    value = result.parameter[..., rows]
    return Solutions(result.q[..., rows, :], result.exists[..., rows], result.within_limits[..., rows],
                     tuple(result.branches[r] for r in rows), result.method, value, result._out, result._reach,
                     result._missing)


def arm(source: str | Path | SerialChain, *, base: str | None = None, tip: str | None = None,
        srs_tolerance: float | None = None, xacro_args: dict[str, str] | None = None,
        package_paths: Sequence[str] | None = None) -> Arm:
    """An :class:`Arm` of a model name, a robot file or a chain, classified and converted once.

    Parameters
    ----------
    source : str, path or SerialChain
        A model name (``redkin robots``), a robot file (URDF, xacro, MJCF, redkin's TOML; a shipped example by its
        name) or a chain.
    base, tip : str, optional
        The links (MJCF: bodies or sites) the chain runs between, in a file with several.
    srs_tolerance : float, optional
        The largest departure from an exact S-R-S neighbour of an arm solved as nearly S-R-S (metres, radians off
        perpendicular; default :data:`redkin.srs.nearly.TOLERANCE_DEFAULT`).
    xacro_args, package_paths
        For a xacro file: its arguments, and folders holding the ``package://`` packages it names.

    Raises
    ------
    ValueError
        For an unknown model, a malformed file, or a tolerance that is not a finite number > 0.
    """
    from redkin.arms.classify import check_tolerance
    from redkin.arms.registry import kind_of
    from redkin.srs.nearly import TOLERANCE_DEFAULT

    if isinstance(source, SerialChain):
        if base is not None or tip is not None or xacro_args is not None or package_paths is not None:
            raise RedkinError("base, tip, xacro_args and package_paths read a file: a SerialChain takes none")
        chain = source
    elif isinstance(source, (str, Path)):
        from redkin.models import get_robot

        chain = get_robot(source, base, tip, xacro_args=xacro_args, package_paths=tuple(package_paths or ()))
    else:
        raise RedkinError(f"source must be a model name, a robot file or a SerialChain, got {type(source).__name__}")
    tolerance = TOLERANCE_DEFAULT if srs_tolerance is None else check_tolerance(srs_tolerance)
    cache = chain.__dict__.setdefault(_CACHE_KEY, {})
    if tolerance not in cache:
        kind, reason = kind_of(chain, tolerance)
        cache[tolerance] = Arm(chain, kind.kind, kind.parameter, kind.branches, kind, reason)
    return cache[tolerance]
