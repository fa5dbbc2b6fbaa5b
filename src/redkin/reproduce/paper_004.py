"""Report section for paper 004: distributed trajectory generation with virtual arms (section 4, Figs. 6-8)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from redkin.chain import SerialChain
from redkin.models import pa10_7c, planar_arm
from redkin.plot.virtual_arms import (
    draw_joint_history,
    draw_strobe,
    draw_strobe_3d,
    fit_planar_view,
    legend_below,
)
from redkin.references import REFERENCES
from redkin.reproduce import Section, section_key
from redkin.reproduce import printed as P
from redkin.reproduce.comparison import Comparison, Note
from redkin.reproduce.report import SectionWriter
from redkin.virtual_arms import (
    AnalyticModel,
    Obstacle,
    ObstacleRun,
    OutputFunction,
    TrajectoryResult,
    VirtualPoint,
    arm_clearance,
    avoid_obstacles,
    generate_trajectory,
    joints_and_midpoints,
)

# Our choices: the paper prints neither the initial posture nor the goals of Figs. 6-7.
_THETA0_DEG = [30.0, 30.0, 30.0, 30.0, 30.0]
# 30 deg is outside Fig. 7's range of joint 5: joints 4, 5 start halfway
_THETA0_FIG7_DEG = [30.0, 30.0, 30.0, 15.0, 10.0]
_END_GOAL = [0.5, 0.6]  # reachable by joint 3 too (|goal| = 0.78 m < 0.8 m), as Fig. 6 (b) requires
# The joint ranges of Figs. 6, 7 are the paper's (printed.FIG_6_JOINT_RANGE_DEG, printed.FIG_7_JOINT_LIMITS_DEG);
# Fig. 8 keeps Fig. 6's.
# Fig. 8 and the spatial case: our choices (the paper prints no obstacle positions), (x, y, r) in metres.
_FIG8_OBSTACLES = [(0.75, 0.9, 0.1), (0.15, 0.8, 0.07)]
_FIG8_CLAMPS = [("(a) all joints work", []), ("(b) joint 1 fixed", [0]), ("(c) joints 1, 2 fixed", [0, 1])]
_PA10_THETA0_DEG = [0.0, 30.0, 0.0, 60.0, 0.0, 30.0, 0.0]
_PA10_GOAL = [0.5, 0.4, 0.3]
_PA10_SPHERE = (0.25, 0.12, 0.68, 0.06)  # where the elbow goes without it
_FIG7_CASE = f"Fig. 7 |theta4| <= {P.FIG_7_JOINT_LIMITS_DEG[3]:g}, |theta5| <= {P.FIG_7_JOINT_LIMITS_DEG[4]:g} deg"


@dataclass
class Case:
    """One run of the section with what the table reports about it."""

    name: str
    model: AnalyticModel
    run: TrajectoryResult
    output: OutputFunction
    lower: np.ndarray
    upper: np.ndarray


def _output(limits_deg) -> tuple[OutputFunction, np.ndarray, np.ndarray]:
    upper = np.radians(np.asarray(limits_deg, dtype=float))
    return OutputFunction.sine(-upper, upper), -upper, upper


def _run_cases(progress=lambda fraction, message: None) -> list[Case]:
    """Every run of the section: Fig. 6 (a)-(d), the weights in (c), a clamped joint, Fig. 7, literal [004 eq. 10]."""
    arm = planar_arm()
    q0 = np.radians(_THETA0_DEG)
    goal = np.array(_END_GOAL)
    full, low, high = _output([P.FIG_6_JOINT_RANGE_DEG] * arm.n)
    end_only = AnalyticModel(arm, [VirtualPoint.end()])
    two = AnalyticModel(arm, [VirtualPoint.end(), VirtualPoint.joint(3)])
    ten = AnalyticModel(arm, [VirtualPoint.end()] + joints_and_midpoints(arm))
    held = ten.evaluate(q0)[0].copy()
    held[0] = goal
    to_base = np.zeros_like(held)
    to_base[0] = goal
    heavy = np.ones(ten.count)
    heavy[0] = 100.0
    fig7, low7, high7 = _output(P.FIG_7_JOINT_LIMITS_DEG)
    plans: list[tuple[str, AnalyticModel, np.ndarray, Any, np.ndarray | None, dict[str, Any],
                      tuple[OutputFunction, np.ndarray, np.ndarray]]] = [
        ("Fig. 6 (a) end point only", end_only, q0, [goal], None, {}, (full, low, high)),
        ("Fig. 6 (b) joint 3 + end, same goal", two, q0, [goal, goal], None, {}, (full, low, high)),
        ("Fig. 6 (c) 9 points held, w_end = 1", ten, q0, held, None, {}, (full, low, high)),
        ("Fig. 6 (c) 9 points held, w_end = 100", ten, q0, held, heavy, {}, (full, low, high)),
        ("Fig. 6 (d) 9 points to base, w_end = 100", ten, q0, to_base, heavy, {}, (full, low, high)),
        ("Fig. 6 (a) with joint 1 clamped ([004 eq. 27])", end_only, q0, [goal], None, {"fixed": [0]},
         (full, low, high)),
        (_FIG7_CASE, end_only, np.radians(_THETA0_FIG7_DEG), [goal], None, {},
         (fig7, low7, high7)),
        ("Fig. 6 (a), literal [004 eq. 10] gain", end_only, q0, [goal], None, {"gain": "literal"}, (full, low, high)),
    ]
    cases = []
    for k, (name, model, start, goals, weights, options, (output, lower, upper)) in enumerate(plans):
        progress(k / len(plans), name)
        run = generate_trajectory(model, start, goals, weights, output=output, **options)
        cases.append(Case(name, model, run, output, lower, upper))
    return cases


def _limit_violations(case: Case) -> int:
    """Recorded joint vectors with some joint outside its range (strictly, no tolerance)."""
    theta = case.run.theta
    return int(np.count_nonzero(np.any((theta < case.lower) | (theta > case.upper), axis=1)))


def _clamped_motion(case: Case) -> float:
    """Largest motion of a clamped joint along the run, in radians (0 when none is clamped)."""
    fixed = case.run.fixed
    if not fixed.any():
        return 0.0
    return float(np.max(np.abs(case.run.theta[:, fixed] - case.run.theta[0, fixed])))


def _table_row(case: Case) -> list:
    run = case.run
    errors = run.final_errors
    virtual = float(np.max(errors[1:])) if len(errors) > 1 else None
    return [case.name, float(errors[0]), virtual, _limit_violations(case), _clamped_motion(case), run.steps,
            round(run.seconds, 3), run.status]


@dataclass
class _ObstacleCase:
    """One obstacle run with the unobstructed run it is compared with."""

    name: str
    chain: SerialChain
    run: ObstacleRun
    plain_clearance: float
    lower: np.ndarray
    upper: np.ndarray


def _run_obstacle_cases(progress=lambda fraction, message: None) -> list[_ObstacleCase]:
    """Fig. 8 (a)-(c) on the planar arm and the PA10 elbow kept clear of a sphere."""
    arm = planar_arm()
    q0 = np.radians(_THETA0_DEG)
    goal = np.array(_END_GOAL)
    obstacles = [Obstacle(np.array(row[:2]), row[2]) for row in _FIG8_OBSTACLES]
    output, lower, upper = _output([P.FIG_6_JOINT_RANGE_DEG] * arm.n)
    end_only = AnalyticModel(arm, [VirtualPoint.end()])
    cases = []
    for k, (name, fixed) in enumerate(_FIG8_CLAMPS):
        progress(k / 4, f"Fig. 8 {name}")
        plain = generate_trajectory(end_only, q0, [goal], output=output, fixed=fixed)
        run = avoid_obstacles(arm, q0, goal, obstacles, output=output, fixed=fixed)
        cases.append(_ObstacleCase(f"Fig. 8 {name}", arm, run, float(arm_clearance(arm, plain.theta, obstacles,
                                                                                    (0, 1)).min()), lower, upper))
    progress(3 / 4, "PA10 elbow and a sphere")
    pa10 = pa10_7c()
    q0 = np.radians(_PA10_THETA0_DEG)
    sphere = [Obstacle(np.array(_PA10_SPHERE[:3]), _PA10_SPHERE[3])]
    output = OutputFunction.sine(pa10.lower, pa10.upper)
    plain = generate_trajectory(AnalyticModel(pa10, [VirtualPoint.end()]), q0, [_PA10_GOAL], output=output)
    run = avoid_obstacles(pa10, q0, _PA10_GOAL, sphere, points=[VirtualPoint.joint(4)], output=output)
    cases.append(_ObstacleCase("PA10: elbow (joint 4) and a sphere", pa10, run,
                              float(arm_clearance(pa10, plain.theta, sphere, (0, 1, 2)).min()), pa10.lower, pa10.upper))
    return cases


def _obstacle_row(case: _ObstacleCase) -> list:
    run = case.run
    clamped = float(np.max(np.abs(run.theta[:, run.fixed] - run.theta[0, run.fixed]))) if run.fixed.any() else 0.0
    outside = int(np.count_nonzero(np.any((run.theta < case.lower) | (run.theta > case.upper), axis=1)))
    return [case.name, case.plain_clearance, run.end_error, run.min_clearance, clamped, outside, run.periods,
            run.steps, round(run.seconds, 3), run.status]


def _build_obstacles(writer: SectionWriter) -> None:
    """Fig. 8 (a)-(c) and the spatial PA10 case."""
    arm = planar_arm()
    writer.heading("Fig. 8: obstacles, with joints failing")
    writer.text(
        "Fig. 8: obstacles, with joints failing. The paper plans each virtual end point's goal from local "
        "information (the real end point: towards the goal plus repulsion from nearby obstacles; the others: "
        "repulsion) and refers to its ref. 11 for the law, which is not available: the planner of "
        "redkin.virtual_arms.obstacles is ours (docs/virtual-arms.md). Every period (at most 20 integrator steps of "
        "the [004 eqs. 9-13] network) the end point's goal moves up to 5 cm towards the goal, sliding round an "
        "obstacle closer than 10 cm; the joints and three points inside every link get repulsion goals within 10 cm; "
        "a guard keeps only the part of a period whose whole skeleton (every link segment, checked every 1 deg of "
        "joint motion) stays 1 cm clear. The paper prints no obstacle positions: we chose two circles, "
        f"(x, y, r) = {_FIG8_OBSTACLES[0]} and {_FIG8_OBSTACLES[1]} m, across the paths the unobstructed runs take "
        f"from the same start ({_THETA0_DEG[0]:g} deg at every joint) to the same goal {tuple(_END_GOAL)} m (the "
        "table's first numeric column: the unobstructed run's minimum clearance, negative = it cuts through the "
        "obstacle)."
    )
    cases = _run_obstacle_cases(writer.progress)
    fig, axes = plt.subplots(1, 3, figsize=(10, 4.4))
    for ax, case in zip(axes, cases[:3]):
        draw_strobe(ax, arm, case.run.theta, case.run.goal[None], frames=14, obstacles=case.run.obstacles,
                    title=f"{case.name.removeprefix('Fig. 8 ')}\n{case.run.status}, min clearance "
                          f"{case.run.min_clearance * 1000:.0f} mm")
    fit_planar_view(axes, arm, [c.run.theta for c in cases[:3]], [c.run.goal[None] for c in cases[:3]],
                    obstacles=cases[0].run.obstacles)
    legend_below(fig, axes[0], 0.07)
    writer.figure(fig, "fig8", "Fig. 8 recomputed: around two obstacles with 0, 1 and 2 joints failed",
                  "The arm at 14 instants of the obstacle-avoiding run (darker = later), the end-point path (dotted), "
                  "the goal (star) and the obstacles (grey); (b) joint 1 and (c) joints 1 and 2 clamped by "
                  "[004 eq. 27].")
    case = cases[3]
    fig = plt.figure(figsize=(7, 6))
    ax = fig.add_subplot(projection="3d")
    elbow = case.chain.frames(case.run.theta)[:, 3, :3, 3]
    draw_strobe_3d(ax, case.chain, case.run.theta, case.run.goal, case.run.obstacles, watched=elbow,
                   title=f"{case.name}: {case.run.status}, min clearance {case.run.min_clearance * 1000:.0f} mm")
    ax.legend(fontsize=7, loc="upper left")
    writer.figure(fig, "pa10_elbow", "The spatial case: the PA10-7C's elbow kept clear of a sphere",
                  f"From theta(0) = {_PA10_THETA0_DEG} deg, hand goal {tuple(_PA10_GOAL)} m, a sphere (x, y, z, r) = "
                  f"{_PA10_SPHERE} m where the elbow goes in the unobstructed run; the elbow (joint 4) is the only "
                  "virtual end point with repulsion goals, the guard checks the whole skeleton; joint limits through "
                  "[004 eq. 25].")
    writer.table(
        "obstacle_runs",
        ["case", "unobstructed min clearance [m]", "end error [m]", "min clearance [m]", "clamped motion [rad]",
         "limit violations", "periods", "steps", "wall time [s]", "status"],
        [_obstacle_row(c) for c in cases],
        "Obstacle runs",
        "The unobstructed run's minimum clearance (negative: it would collide), final end error on the chain, "
        "minimum clearance of the whole arm along the kept path (densified), largest motion of a clamped joint, "
        "recorded postures outside the joint ranges, planning periods, integrator steps (Radau, including the parts "
        "of periods the guard cut), wall time and status.",
    )
    words = Note("stated in words; only the qualitative outcome is comparable",
                 "the paper states this for Fig. 8 (a)-(c) and prints no numbers; our obstacles, start and goal are "
                 "our own choices")
    writer.comparison("fig8", [
        Comparison(f"{c.name}: reaches the goal without touching the obstacle", P.FIG_8_REACHES_GOAL_CLEAR,
                   "yes" if c.run.reached and c.run.min_clearance > 0.0 else "no", 0.0, words)
        for c in cases[:3]
    ], "Fig. 8: what the paper states, beside our runs")


_FIG6_CASES = ["Fig. 6 (a) end point only", "Fig. 6 (b) joint 3 + end, same goal",
               "Fig. 6 (c) 9 points held, w_end = 1", "Fig. 6 (c) 9 points held, w_end = 100",
               "Fig. 6 (d) 9 points to base, w_end = 100"]
_REACHED = 1e-4  # metres: the end point "reaches" its goal


def _fig6_comparison(case: Case) -> Comparison:
    """Paper: the end point reaches the goal; ours: whether it did, with the distance left."""
    error = float(case.run.final_errors[0])
    ours = "yes" if error <= _REACHED else f"no, {error * 1000:.1f} mm short"
    return Comparison(f"{case.name}: end point reaches its goal", P.FIG_6_END_REACHES_GOAL, ours, 0.0,
                      _REDUNDANT if error <= _REACHED else _OVER_CONSTRAINED)


_REDUNDANT = Note("redundant case: the goals can all be met, and the network meets them")
_OVER_CONSTRAINED = Note(
    "over-constrained goals with constant weights: the end point stops short",
    "the ten goals cannot all be met, and with constant weights the equilibrium of [004 eqs. 9-14] is the weighted "
    "least-squares posture, a compromise in which the end point stops short. The paper weights the points by their "
    "distance to the goal (its ref. 11, not given), which lets the end point arrive; the heavier end weight shows the "
    "trend (w_end = 100 ends much closer than 1).")


def build(writer: SectionWriter) -> None:
    arm = planar_arm()
    writer.heading("Figs. 6, 7: goals, weights and joint limits")
    writer.text(
        f"Setting (paper 004 section 4): the {arm.n}-link planar arm with {100 * float(arm.a[0]):g} cm links, every "
        f"joint range |theta_j| <= {P.FIG_6_JOINT_RANGE_DEG:g} deg applied through the sine output function "
        "([004 eq. 25]), analytic forward models in every subsystem. The paper "
        f"prints no initial posture and no goals; we chose theta(0) = {_THETA0_DEG} deg and the end goal "
        f"X* = ({_END_GOAL[0]}, {_END_GOAL[1]}) m for every case. That goal is reachable by joint 3 "
        f"({np.linalg.norm(_END_GOAL):.2f} m < {2 * float(arm.a[0]):g} m), so "
        "in Fig. 6 (b) both the end point and joint 3 can reach it. Fig. 6 (c) holds the nine virtual end points "
        "(joints 2-5 and the centres of links 1-5) at their initial positions; (d) pulls them to the base. The paper "
        "sets the weights W^i from the distance to the goal (its ref. 11, not given); we use constant weights and "
        "show their effect in (c): with w_end = 1 the end point stops short of its goal, with w_end = 100 it comes "
        "much closer while the virtual points give way. For Fig. 7 joints 4 and 5 start at "
        f"{_THETA0_FIG7_DEG[3]:g} and {_THETA0_FIG7_DEG[4]:g} deg because {_THETA0_DEG[4]:g} deg lies outside "
        f"|theta5| <= {P.FIG_7_JOINT_LIMITS_DEG[4]:g} deg."
    )
    cases = _run_cases(writer.progress)
    by_name = {c.name: c for c in cases}

    fig, axes = plt.subplots(2, 2, figsize=(10, 10))
    shown = [cases[0].name, cases[1].name, cases[3].name, cases[4].name]
    for ax, name, label in zip(axes.ravel(), shown, "abcd"):
        case = by_name[name]
        draw_strobe(ax, arm, case.run.theta, case.run.goals, case.run.positions[-1],
                    title=f"({label}) {name.removeprefix(f'Fig. 6 ({label}) ')}")
    fit_planar_view(axes.ravel(), arm, [by_name[name].run.theta for name in shown],
                    [by_name[name].run.goals for name in shown])
    legend_below(fig, axes[1, 0], 0.04)
    writer.figure(fig, "fig6", "Fig. 6 recomputed: (a) end point only, (b) joint 3 too, (c) nine points held, (d) "
                  "pulled to the base", "The arm drawn at 12 instants of the run (darker = later), the end-point path "
                  "(dotted), the end goal (star), virtual goals (x) and final virtual end points (o). (c) and (d) use "
                  "w_end = 100.")

    fig, axes = plt.subplots(1, 2, figsize=(10, 5))
    for ax, name in zip(axes, ["Fig. 6 (c) 9 points held, w_end = 1", "Fig. 6 (c) 9 points held, w_end = 100"]):
        case = by_name[name]
        draw_strobe(ax, arm, case.run.theta, case.run.goals, case.run.positions[-1],
                    title=f"{name.removeprefix('Fig. 6 (c) ')}: end error {case.run.final_errors[0] * 1000:.1f} mm")
    pair = [by_name[name] for name in ("Fig. 6 (c) 9 points held, w_end = 1", "Fig. 6 (c) 9 points held, w_end = 100")]
    fit_planar_view(axes, arm, [c.run.theta for c in pair], [c.run.goals for c in pair])
    legend_below(fig, axes[0], 0.07)
    writer.figure(fig, "weights", "The weights in the over-constrained case (c): end weight 1 and 100",
                  "The same ten goals with the end point's weight 1 (left) and 100 (right); every virtual point keeps "
                  "weight 1.")

    case = by_name[_FIG7_CASE]
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.6))
    draw_strobe(axes[0], arm, case.run.theta, case.run.goals, title=case.name)
    fit_planar_view(axes[:1], arm, [case.run.theta], [case.run.goals])
    axes[0].legend(fontsize=7, loc="best")
    draw_joint_history(axes[1], case.run.s, case.run.theta, case.lower, case.upper)
    fig.tight_layout()
    writer.figure(fig, "fig7",
                  f"Fig. 7 recomputed: Fig. 6 (a) with |theta4| <= {P.FIG_7_JOINT_LIMITS_DEG[3]:g} deg and "
                  f"|theta5| <= {P.FIG_7_JOINT_LIMITS_DEG[4]:g} deg",
                  "Left, the run ([004 eq. 25] keeps the joints in range); right, the joint angles against the "
                  "dynamics' time s with the limits dashed.")

    writer.table(
        "runs",
        ["case", "end error [m]", "max virtual error [m]", "limit violations", "clamped motion [rad]", "steps",
         "wall time [s]", "status"],
        [_table_row(c) for c in cases],
        "Every run of Figs. 6 and 7",
        "Per run: final end-point error, the largest final error of the other virtual end points, recorded postures "
        "outside the joint ranges, largest motion of a clamped joint, accepted integrator steps (Radau), wall time, "
        "status; '–': the run has no other virtual end point. In the over-constrained cases (c), (d) the errors "
        "cannot all vanish: the equilibrium is the weighted least-squares posture and lambda grows only like sqrt(s) "
        "([004 eq. 11]), so these runs end when the joints move less than 1e-6 rad while lambda doubles (the "
        "remaining motion is then below that too) or when |G' delta| falls below 1e-6, whichever comes first. The "
        "literal [004 eq. 10] gain grows without bound and stalls the integrator, as the last row shows; the other "
        "rows use the bounded gain law of redkin.virtual_arms.dynamics.",
    )
    writer.comparison("fig6", [_fig6_comparison(by_name[name]) for name in _FIG6_CASES],
                      "Fig. 6: the end point reaches its goal in every case, says the paper",
                      "Our final end-point error beside it (reached = within 1e-4 m).")
    _build_obstacles(writer)


SECTION = Section(
    key=section_key(__name__),
    title="Paper 004: distributed trajectory generation for redundant manipulators with virtual arms",
    reference=REFERENCES["004"],
    build=build,
)
