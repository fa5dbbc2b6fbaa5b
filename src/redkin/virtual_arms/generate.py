"""Running the trajectory-generation mode (paper 004 section 3.2) with a stiff scipy integrator."""

from __future__ import annotations

import time
from bisect import bisect_right
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike
from scipy.integrate import BDF, LSODA, Radau

from redkin._constants import VIRTUAL_ARMS_MAX_STEPS as MAX_STEPS  # largest step budget of one run
from redkin._validation import MAX_LENGTH, check_count, check_magnitude, check_positive, check_vectors
from redkin.errors import RedkinError
from redkin.virtual_arms.dynamics import GAIN_LAWS, Dynamics, State
from redkin.virtual_arms.output_function import OutputFunction
from redkin.virtual_arms.subsystems import ForwardModel, OneByOne, Together

_SOLVERS = {"Radau": Radau, "BDF": BDF, "LSODA": LSODA}


@dataclass
class TrajectoryResult:
    """A run of the trajectory-generation dynamics, recorded at every accepted integrator step.

    Attributes
    ----------
    s, theta, lam, energy, error : numpy.ndarray
        Time, joint vectors ``(K, m)``, Lagrange multiplier, ``V`` of [004 eq. 14] and
        ``sum_k E^k`` along the run.
    positions : numpy.ndarray, shape (K, p, l)
        Virtual end points as the subsystems' own models see them (NaN for a dropped subsystem).
    status : {"converged", "stalled", "max_steps", "max_time"}
        ``"stalled"``: the integrator could not go on (step size collapsed or it
        failed); the run stops where it stalled and says so.
    message : str
    steps, evaluations : int
        Accepted integrator steps and right-hand-side evaluations.
    seconds : float
        Wall-clock time of the run.
    gain : str
        Gain law (``"bounded"``, ``"consistent"`` or ``"literal"``).
    goals, weights : numpy.ndarray, shape (p, l)
    active : numpy.ndarray of bool, shape (p,)
        Subsystems still working at the end.
    fixed : numpy.ndarray of bool, shape (m,)
    """

    s: np.ndarray
    theta: np.ndarray
    lam: np.ndarray
    energy: np.ndarray
    error: np.ndarray
    positions: np.ndarray
    status: str
    message: str
    steps: int
    evaluations: int
    seconds: float
    gain: str
    goals: np.ndarray
    weights: np.ndarray
    active: np.ndarray
    fixed: np.ndarray
    labels: list[str] = field(default_factory=list)

    @property
    def converged(self) -> bool:
        return self.status == "converged"

    @property
    def stalled(self) -> bool:
        return self.status == "stalled"

    @property
    def final_theta(self) -> np.ndarray:
        return self.theta[-1]

    @property
    def final_errors(self) -> np.ndarray:
        """Distance of every virtual end point to its goal at the end, in the models' view (NaN if dropped)."""
        return np.linalg.norm(self.positions[-1] - self.goals, axis=-1)


def _weights(weights: ArrayLike | None, count: int, dims: int) -> np.ndarray:
    if weights is None:
        return np.ones((count, dims))
    w = np.asarray(weights, dtype=float)
    if w.shape == (count,):
        w = np.repeat(w[:, None], dims, axis=1)
    if w.shape != (count, dims):
        raise RedkinError(f"weights must have shape ({count},) or ({count}, {dims}), got {w.shape}")
    if not np.all(np.isfinite(w)) or np.any(w < 0):
        raise RedkinError("weights must be finite and non-negative (W^i = diag(w) with w >= 0)")
    return w


def _half_lambda_state(record: Sequence[tuple[float, State]]) -> State | None:
    """The last recorded state whose ``lambda`` is at most half the latest one (``None`` before a doubling).

    ``record`` holds ``(s, state)`` pairs in the order of the run; ``lambda``
    never decreases along it [004 eq. 11], so the search bisects.
    """
    if len(record) < 2:
        return None
    half = bisect_right(record, 0.5 * float(record[-1][1].lam), key=lambda item: float(item[1].lam))
    return record[half - 1][1] if half else None


def _settled(record: Sequence[tuple[float, State]], posture_tol: float) -> float | None:
    """Joint motion over the last doubling of ``lambda`` if it is at most ``posture_tol``, else ``None``.

    Late in a run ``theta`` follows the minimiser ``theta_lambda`` of ``V`` at
    fixed ``lambda`` [004 eq. 14], and ``theta_lambda = theta* + c / lambda +
    O(1 / lambda^2)`` (a penalty path).  Over a doubling of ``lambda`` the
    joints therefore move by about ``|theta_lambda - theta*|``: when that
    motion is below ``posture_tol`` the remaining motion to the equilibrium
    is too (:func:`_half_lambda_state`).
    """
    earlier = _half_lambda_state(record) if posture_tol > 0.0 else None
    if earlier is None:
        return None
    motion = float(np.linalg.norm(record[-1][1].theta - earlier.theta))
    return motion if motion <= posture_tol else None


def _errors_settled(record: Sequence[tuple[float, State]], error_rtol: float) -> tuple[float, float] | None:
    """``(relative change of sum_k E^k, joint motion)`` over the last doubling of ``lambda`` if the change is at
    most ``error_rtol``.

    When the goals conflict (an over-constrained run) ``sum_k E^k`` cannot
    vanish: along the penalty path it falls to its least-squares minimum
    ``E*`` like ``E* + O(1 / lambda^2)``, while the joints still drift towards
    the posture closest to ``theta(0)`` by ``O(1 / lambda)`` and ``lambda``
    grows only like ``sqrt(s)``.  Reaching ``posture_tol`` would need
    ``lambda`` of 10^7 and more, where the path is so narrow (its width in
    ``u`` falls like ``1 / lambda``) that whether the implicit integrator's
    Newton iteration still converges depends on the rounding of the linear
    algebra.  This test ends such runs where the errors, the run's purpose,
    have stopped changing; the joint motion over that doubling, returned
    too, bounds how far the posture still is from the limit.  In a run whose
    goals are met ``sum_k E^k`` falls by about 4 per doubling, so the test
    never fires there.
    """
    earlier = _half_lambda_state(record) if error_rtol > 0.0 else None
    if earlier is None:
        return None
    latest = record[-1][1]
    total = float(latest.error.sum())
    change = abs(total - float(earlier.error.sum())) / total if total > 0.0 else np.inf
    if change > error_rtol:
        return None
    return change, float(np.linalg.norm(latest.theta - earlier.theta))


def generate_trajectory(
    model: ForwardModel,
    theta0: ArrayLike,
    goals: ArrayLike,
    weights: ArrayLike | None = None,
    *,
    output: OutputFunction | None = None,
    fixed: Sequence[int] = (),
    gain: str = "bounded",
    evaluation: str = "together",
    drop: Mapping[int, float] | None = None,
    eta: float = 1.0,
    lambda0: float = 1.0,
    gradient_tol: float = 1e-6,
    posture_tol: float = 1e-6,
    error_rtol: float = 1e-6,
    s_max: float = 1.0e15,
    max_steps: int = 5000,
    min_step: float = 1e-9,
    rtol: float = 1e-6,
    atol: float = 1e-9,
    method: str = "Radau",
) -> TrajectoryResult:
    """Integrate the trajectory-generation dynamics [004 eqs. 9-13] from ``theta0`` until equilibrium.

    Parameters
    ----------
    model : ForwardModel
        Joint model of the ``p`` virtual end points (analytic or learned);
        with ``evaluation="one_by_one"`` each subsystem uses its own single-point
        model from ``model.split()``.
    theta0 : array_like, shape (m,)
        Initial joint vector ``theta(0)``.
    goals : array_like, shape (p, l)
        Goals ``X^k*`` of the virtual end points.
    weights : array_like, shape (p,) or (p, l), optional
        Diagonals of ``W^k`` (default all ones).
    output : OutputFunction, optional
        Output function ``G`` [004 eq. 13]; default identity (no limits); use
        :meth:`OutputFunction.sine` for joint limits [004 eq. 25].
    fixed : sequence of int
        Clamped joints, 0-based [004 eq. 27]: their ``u`` is not integrated.
    gain : {"bounded", "consistent", "literal"}
        Law of [004 eqs. 10-11] (see :mod:`redkin.virtual_arms.dynamics`).
    evaluation : {"together", "one_by_one"}
    drop : mapping of int to float, optional
        Subsystem index -> time ``s`` at which it stops working.
    eta, lambda0 : float
        Time constant of [004 eqs. 9, 11], and ``lambda(0) > 0``.
    gradient_tol : float
        Converged when ``|G' delta|`` over the free joints is at most this
        (the goals are met, or the errors are stationary to that accuracy).
    posture_tol : float
        Also converged when the joint vector moved at most this (radians, 2-norm)
        while ``lambda`` doubled: see :func:`_settled`.  This ends over-constrained
        runs whose goals are met and the joints settle first; ``0`` turns it off.
    error_rtol : float
        Also converged when ``sum_k E^k`` changed by at most this fraction while
        ``lambda`` doubled: this ends over-constrained runs, whose errors cannot
        vanish (see :func:`_errors_settled`; the message reports the joint motion
        left); ``0`` turns it off.
    s_max, max_steps : float, int
        Give up (status ``"max_time"``/``"max_steps"``) after this time or these
        steps (at most :data:`MAX_STEPS`: every step is recorded).
    min_step : float
        Ten consecutive step sizes below ``min_step * max(1, s)`` count as a stalled integrator.
    rtol, atol : float
        Integrator tolerances.  Late in a run the path ``g = 0`` is narrow
        (see :mod:`redkin.virtual_arms.dynamics`), and Radau's Newton iteration
        can fail on it at every step size, depending on the rounding of the
        linear algebra (BLAS threads, the last bits of ``theta(0)``).  On the
        over-constrained Fig. 6 runs perturbed by 1e-12 rad, under 1 and 2
        BLAS threads, ``rtol = 1e-5`` failed once in 80 before the errors
        settled (and about one run in three before ``|G' delta| <= 1e-6``);
        ``1e-6`` never failed.
    method : {"Radau", "BDF", "LSODA"}
        Stiff scipy integrator.

    Returns
    -------
    TrajectoryResult
    """
    if gain not in GAIN_LAWS:
        raise RedkinError(f"gain must be one of {sorted(GAIN_LAWS)}, got {gain!r}")
    if evaluation not in ("together", "one_by_one"):
        raise RedkinError(f"evaluation must be 'together' or 'one_by_one', got {evaluation!r}")
    if method not in _SOLVERS:
        raise RedkinError(f"method must be one of {sorted(_SOLVERS)}, got {method!r}")
    m, p, dims = model.joints, model.count, model.dims
    theta0 = check_vectors(theta0, m, "theta0").reshape(m)
    goals = check_vectors(goals, dims, "goals")
    check_magnitude(goals, "goals", MAX_LENGTH, "m")  # a finite but absurd goal (1e308) would overflow the rates
    if goals.shape != (p, dims):
        raise RedkinError(f"goals must have shape ({p}, {dims}) (one goal per virtual end point), got {goals.shape}")
    weight = _weights(weights, p, dims)
    for name, value in (("eta", eta), ("lambda0", lambda0), ("gradient_tol", gradient_tol), ("s_max", s_max)):
        check_positive(value, name)
    max_steps = check_count(max_steps, "max_steps", 1, MAX_STEPS)
    for name, value in (("posture_tol", posture_tol), ("error_rtol", error_rtol)):
        if not np.isfinite(value) or value < 0:
            raise RedkinError(f"{name} must be finite and >= 0, got {value!r}")
    output = OutputFunction.identity(m) if output is None else output
    free = np.ones(m, dtype=bool)
    for j in fixed:
        if int(j) != j or not 0 <= j < m:
            raise RedkinError(f"fixed joints must be 0-based indices in 0..{m - 1}, got {j!r}")
        free[int(j)] = False
    drop = dict(drop or {})
    for k, when in drop.items():
        if not 0 <= int(k) < p or not np.isfinite(when) or when < 0:
            raise RedkinError(f"drop must map subsystem indices 0..{p - 1} to times s >= 0, got {k!r}: {when!r}")
    evaluator = Together(model) if evaluation == "together" else OneByOne(model.split())
    active = np.ones(p, dtype=bool)
    dynamics = Dynamics(evaluator, goals, weight, active, theta0, output, free, float(eta), GAIN_LAWS[gain])

    started = time.perf_counter()
    y = dynamics.initial(float(lambda0))
    record: list[tuple[float, State]] = [(0.0, dynamics.state(y))]
    steps = evaluations = tiny_steps = 0
    status, message = "max_time", f"reached s_max = {s_max:g} before equilibrium"
    events = sorted({float(t) for t in drop.values() if t < s_max} | {float(s_max)})
    s = 0.0
    if float(record[0][1].free_gradient) <= gradient_tol or not free.any():
        status, message = "converged", "already at equilibrium at s = 0"
        events = []
    for boundary in events:
        for k, when in drop.items():  # subsystems that fail before this segment stop sending
            if when <= s:
                active[int(k)] = False
        options = {} if method == "LSODA" else {"vectorized": True}
        solver = _SOLVERS[method](dynamics.rates, s, y, boundary, rtol=rtol, atol=atol, **options)
        done = False
        while solver.status == "running":
            with np.errstate(all="ignore"):
                problem = solver.step()
            evaluations = solver.nfev
            if solver.status == "failed" or not np.all(np.isfinite(solver.y)):
                status, message, done = "stalled", f"integrator failed at s = {solver.t:.6g}: {problem}", True
                break
            steps += 1
            s, y = solver.t, solver.y.copy()
            current = dynamics.state(y)
            record.append((s, current))
            if current.free_gradient <= gradient_tol:
                status, message, done = "converged", f"|G' delta| = {current.free_gradient:.3g} at s = {s:.6g}", True
                break
            motion = _settled(record, posture_tol)
            if motion is not None:
                status, done = "converged", True
                message = f"settled: joints moved {motion:.3g} rad while lambda doubled (s = {s:.6g})"
                break
            stationary = _errors_settled(record, error_rtol)
            if stationary is not None:
                status, done = "converged", True
                message = (f"errors settled: sum of E^k changed by {stationary[0]:.2g} (relative) while lambda "
                           f"doubled; joints moved {stationary[1]:.3g} rad (s = {s:.6g})")
                break
            tiny = solver.step_size is not None and solver.step_size < min_step * max(1.0, s)
            tiny_steps = tiny_steps + 1 if tiny else 0
            if tiny_steps >= 10:  # one tiny step can be a recovered Newton failure; ten in a row is a stall
                status, done = "stalled", True
                message = f"step size collapsed to {solver.step_size:.3g} at s = {s:.6g} (gain A = {current.gain:.3g})"
                break
            if steps >= max_steps:
                status, message, done = "max_steps", f"{max_steps} steps without equilibrium (s = {s:.6g})", True
                break
        if done:
            break
    seconds = time.perf_counter() - started
    states = [st for _, st in record]
    return TrajectoryResult(
        s=np.array([t for t, _ in record]),
        theta=np.array([st.theta for st in states]),
        lam=np.array([float(st.lam) for st in states]),
        energy=np.array([float(st.energy) for st in states]),
        error=np.array([st.error.sum() for st in states]),
        positions=np.array([st.positions for st in states]),
        status=status,
        message=message,
        steps=steps,
        evaluations=evaluations,
        seconds=seconds,
        gain=gain,
        goals=goals,
        weights=weight,
        active=active.copy(),
        fixed=~free,
        labels=[getattr(pt, "label", str(i)) for i, pt in enumerate(getattr(model, "points", range(p)))],
    )
