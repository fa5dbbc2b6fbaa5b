"""A path's clearance raised beyond its samples: sequential linear programming over the parameter of every waypoint.

Where the step bound binds between waypoints, the best clearance lies between the samples of every waypoint at
once, and the refinement of :mod:`redkin.paths.graph` (a window around the path found) stops short of it.  Here the
branches stay as found and each waypoint's parameter moves inside its feasible arc (its piece and the pieces that
touch it): the joint values are linearised in the parameter (central differences of the closed form,
:meth:`redkin.paths.graph.Arm.rows`) and the linear program

    maximise t  subject to  clearance_i + g_i . delta_i >= t          (every waypoint i, every limited joint)
                            |q_{i+1} - q_i + g_{i+1} delta_{i+1} - g_i delta_i| <= step - margin   (every joint)
                            |delta_i| <= trust,  parameter + delta inside its piece

is solved (HiGHS, :func:`scipy.optimize.linprog`).  A step is kept only where the joint values it gives, computed
again in closed form, keep every limit, the bound (and ``q0``/``q_end``'s) exactly and raise the smallest
clearance; the trust region then grows, and otherwise shrinks.  The margin is what the linearisation was seen to
miss, scaled with the square of the trust region, so that it vanishes as the region shrinks.  The path
returned is never worse than the path given, and never breaks a law it kept.
"""

from __future__ import annotations

import numpy as np

from redkin.circle import wrap_angle
from redkin.paths.graph import _CLIP_TOLERANCE, Arm

#: Rounds of linear programming at most.
_ROUNDS = 40
#: The first trust region (radians of the parameter at every waypoint).
_FIRST_TRUST = 1e-2
#: The derivative's half-step (radians of the parameter).
_DIFFERENCE = 1e-7


def raised(arm: Arm, branch: np.ndarray, parameter: np.ndarray, piece: np.ndarray, start: np.ndarray | None,
           end: np.ndarray | None) -> np.ndarray:
    """The parameters of a path with its smallest clearance raised (module docstring), or ``parameter`` itself.

    Parameters
    ----------
    arm : Arm
        Along the path's waypoints ``0 .. N - 1``.
    branch, parameter : numpy.ndarray, shape (N,)
        The path found: branch index and parameter per waypoint (lawful: limits, bound).
    piece : numpy.ndarray, shape (N, 2)
        The ends of each waypoint's feasible arc (equal ends: the waypoint does not move).
    start, end : numpy.ndarray of shape (7,), or None
        ``q0`` and ``q_end``: the first (last) waypoint stays within one step of them.
    """
    count = len(parameter)
    waypoint = np.arange(count)
    q, clearance = arm.rows(waypoint, branch, parameter)
    best = float(clearance.min())
    if count == 0 or not np.isfinite(best):
        return parameter
    trust, curvature, again = _FIRST_TRUST, 0.0, False
    for _ in range(_ROUNDS):
        delta = _step(arm, waypoint, branch, parameter, piece, q, start, end, trust, curvature * trust**2)
        if delta is not None:
            candidate = parameter + delta
            values, room = arm.rows(waypoint, branch, candidate)
            excess = _excess(arm, values, start, end)
            if excess <= 0.0 and room.min() >= -_CLIP_TOLERANCE and room.min() > best:
                parameter, q, best = candidate, values, float(room.min())
                trust, again = 2.0 * trust, False
                continue
            if excess > 0.0 and not again:  # the linearisation missed this much: the same region, with a margin
                curvature = max(curvature, 2.0 * excess / trust**2)
                again = True
                continue
        trust, again = 0.25 * trust, False
        if trust < 1e-12:
            break
    return parameter


def _excess(arm: Arm, q: np.ndarray, start: np.ndarray | None, end: np.ndarray | None) -> float:
    """How far the joint values overstep the bound at worst (radians; <= 0: they keep it), ``q0``/``q_end`` included."""
    worst = (arm.moves(q[1:], q[:-1]) - arm.step).max(initial=-np.inf)
    for fixed, row in ((start, q[0]), (end, q[-1])):
        if fixed is not None:
            worst = max(worst, float((arm.moves(row, fixed) - arm.step).max()))
    return float(worst)


def _step(arm: Arm, waypoint: np.ndarray, branch: np.ndarray, parameter: np.ndarray, piece: np.ndarray,
          q: np.ndarray, start: np.ndarray | None, end: np.ndarray | None, trust: float,
          margin: float) -> np.ndarray | None:
    """One linear program of the module docstring: the move of every waypoint's parameter, or ``None`` where it has
    no solution (a step nearer its bound than ``margin`` that the trust region cannot shorten)."""
    import scipy.sparse as sparse  # here, not at the top: every command that classifies an arm imports this package
    from scipy.optimize import linprog  # through redkin.paths, and scipy.optimize costs about 0.3 s of each start

    count = len(parameter)
    chain = arm.chain
    below = np.clip(parameter - _DIFFERENCE, piece[:, 0], piece[:, 1])
    above = np.clip(parameter + _DIFFERENCE, piece[:, 0], piece[:, 1])
    width = np.where(above > below, above - below, 1.0)
    gradient = (arm.rows(waypoint, branch, above)[0] - arm.rows(waypoint, branch, below)[0]) / width[:, None]
    lowest = np.minimum(np.maximum(piece[:, 0] - parameter, -trust), 0.0)  # 0: a parameter at its piece's end
    highest = np.maximum(np.minimum(piece[:, 1] - parameter, trust), 0.0)
    reach = np.maximum(-lowest, highest)  # the largest move of each waypoint's parameter
    limited = np.flatnonzero(~arm.circle)
    rows: list[np.ndarray] = []
    columns: list[np.ndarray] = []
    values: list[np.ndarray] = []
    bounds: list[np.ndarray] = []

    def add(column_sets: list[tuple[np.ndarray, np.ndarray]], t: float, bound: np.ndarray) -> None:
        """Rows ``sum(value * delta[column]) + t * x_t <= bound``, one per entry of ``bound``."""
        first = sum(len(b) for b in bounds)
        index = first + np.arange(len(bound))
        for column, value in column_sets:
            rows.append(index)
            columns.append(column)
            values.append(value)
        if t:
            rows.append(index)
            columns.append(np.full(len(bound), count))
            values.append(np.full(len(bound), t))
        bounds.append(bound)

    if limited.size:  # t <= clearance of every limited joint, linearised; rows that cannot bind left out
        i, j = np.repeat(np.arange(count), limited.size), np.tile(limited, count)
        slope = gradient[i, j]
        below_room, above_room = q[i, j] - chain.lower[j], chain.upper[j] - q[i, j]
        swing = np.abs(slope) * reach[i]
        ceiling = min((below_room + swing).min(), (above_room + swing).min())  # no t beyond the least row's best
        for room, sign in ((below_room, -1.0), (above_room, 1.0)):
            binds = room - swing <= ceiling  # a row above the ceiling wherever its waypoint moves never binds
            add([(i[binds], sign * slope[binds])], 1.0, room[binds])
    if count > 1:  # every step within the bound, linearised; steps the trust region cannot break left out
        i, j = np.repeat(np.arange(count - 1), 7), np.tile(np.arange(7), count - 1)
        moved = _turn(arm, q[i + 1, j] - q[i, j], j)
        room = arm.step[j] - margin
        tight = np.abs(moved) + np.abs(gradient[i + 1, j]) * reach[i + 1] + np.abs(gradient[i, j]) * reach[i] > room
        i, j, moved, room = i[tight], j[tight], moved[tight], room[tight]
        add([(i + 1, gradient[i + 1, j]), (i, -gradient[i, j])], 0.0, room - moved)
        add([(i + 1, -gradient[i + 1, j]), (i, gradient[i, j])], 0.0, room + moved)
    for fixed, k in ((start, 0), (end, count - 1)):
        if fixed is not None:
            j = np.arange(7)
            i = np.full(7, k)
            moved = _turn(arm, q[k] - fixed, j)
            room = arm.step - margin
            add([(i, gradient[k])], 0.0, room - moved)
            add([(i, -gradient[k])], 0.0, room + moved)
    bound = np.concatenate(bounds)
    used = np.zeros(count + 1, dtype=bool)
    used[np.concatenate(columns)] = True
    lowest, highest = np.where(used[:count], lowest, 0.0), np.where(used[:count], highest, 0.0)  # in no row: stays
    matrix = sparse.csr_matrix((np.concatenate(values), (np.concatenate(rows), np.concatenate(columns))),
                               shape=(len(bound), count + 1))
    limits = [(float(a), float(b)) for a, b in zip(lowest, highest)] + [(None, None)]
    cost = np.zeros(count + 1)
    cost[count] = -1.0
    solution = linprog(cost, A_ub=matrix, b_ub=bound, bounds=limits, method="highs")
    if solution.status != 0:
        return None
    return np.asarray(solution.x[:count])


def _turn(arm: Arm, difference: np.ndarray, joint: np.ndarray) -> np.ndarray:
    """Differences of joint values, taken the shorter way round for the joints compared on the circle."""
    return np.where(arm.circle[joint], wrap_angle(difference), difference)
