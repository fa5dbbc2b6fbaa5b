"""``redkin virtual-arms``: distributed trajectory generation with virtual arms (paper 004)."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from redkin._constants import VIRTUAL_ARMS_MAX_STEPS
from redkin._validation import MAX_LENGTH, check_count, check_magnitude
from redkin.cli.common import (
    IMAGE_SUFFIXES,
    UsageError,
    add_force_flag,
    add_output_flags,
    add_robot_argument,
    angle_unit,
    angles_out,
    format_values,
    joint_vector,
    load_robot,
    output_file,
    plural,
    print_json,
)

if TYPE_CHECKING:  # the parser is built without the virtual-arms package (scipy, the kernels): the handlers import it
    from redkin.virtual_arms import Obstacle, VirtualPoint
    from redkin.virtual_arms.subsystems import ForwardModel

_DEFAULT_Q0 = 0.5  # rad at every joint: a bent, non-singular start for the planar and spatial models
#: A goal counts as met when its point ends this close to it (metres); the runs end far closer (~1e-6 m).
_GOAL_TOLERANCE = 1e-3


def register(subparsers: argparse._SubParsersAction) -> None:
    parser = subparsers.add_parser(
        "virtual-arms", help="move the end point (and chosen virtual end points) to goals with the virtual-arm dynamics"
    )
    add_robot_argument(parser)
    parser.add_argument("--goal", nargs="+", type=float, required=True, metavar="X",
                        help="end-point goal: X Y for a planar arm, X Y Z otherwise (metres)")
    parser.add_argument("--point", action="append", default=[], metavar="POINT=X,Y[,Z]",
                        help="a virtual end point and its goal, e.g. joint:3=0.5,0.6 or link:2@0.5=0.1,0.3 "
                             "(repeatable)")
    parser.add_argument("--weight", action="append", type=float, default=None, metavar="W",
                        help="weights, one per point: the end point first, then each --point in order (repeatable)")
    parser.add_argument("--fix", default="", metavar="J,J",
                        help="clamped joints, 1-based, comma separated ([004 eq. 27])")
    parser.add_argument("--limits", action="store_true", help="keep the joints in the robot's ranges ([004 eq. 25])")
    parser.add_argument("--model", choices=("analytic", "learned"), default="analytic",
                        help="forward models of the subsystems (learned: one trained network per point)")
    parser.add_argument("--q0", nargs="+", type=float, metavar="Q",
                        help=f"initial joint values (default {_DEFAULT_Q0} rad at every joint)")
    parser.add_argument("--max-steps", type=int, default=5000,
                        help=f"integrator step budget (default 5000, at most {VIRTUAL_ARMS_MAX_STEPS})")
    parser.add_argument("--obstacle", action="append", default=[], metavar="X,Y,R",
                        help="a circular obstacle X,Y,R (planar arms) or a sphere X,Y,Z,R, metres (repeatable); "
                             "the planner of Fig. 8 then keeps the whole arm clear of it")
    parser.add_argument("--out", metavar="FILE",
                        help="save a stroboscopic drawing of the run (PNG, PDF, SVG), or an animation if FILE ends "
                             "in .gif (planar arms)")
    add_force_flag(parser)
    add_output_flags(parser)
    parser.set_defaults(handler=_run_virtual_arms)


def _coordinates(values, dims: int, name: str) -> np.ndarray:
    array = np.asarray(values, dtype=float)
    if array.shape != (dims,) or not np.all(np.isfinite(array)):
        raise UsageError(f"{name} needs {dims} finite coordinates for this robot, got {list(values)}")
    return check_magnitude(array, name, MAX_LENGTH, "m")


def _point_goal(text: str, dims: int) -> tuple[VirtualPoint, np.ndarray]:
    from redkin.virtual_arms import parse_point

    label, sep, coords = text.partition("=")
    if not sep:
        raise UsageError(f"--point must look like joint:3=X,Y, got {text!r}")
    try:
        values = [float(v) for v in coords.split(",")]
    except ValueError:
        raise UsageError(f"--point {text!r}: goal must be comma-separated numbers") from None
    return parse_point(label), _coordinates(values, dims, f"--point {label}")


def _fixed(text: str, joints: int) -> list[int]:
    if not text.strip():
        return []
    try:
        numbers = [int(v) for v in text.split(",")]
    except ValueError:
        raise UsageError(f"--fix must be 1-based joint numbers separated by commas, got {text!r}") from None
    bad = [j for j in numbers if not 1 <= j <= joints]
    if bad:
        raise UsageError(f"--fix joint numbers must be in 1..{joints}, got {bad[0]}")
    return [j - 1 for j in numbers]


def _obstacle(text: str, dims: int) -> Obstacle:
    from redkin.virtual_arms import Obstacle

    shape = "X,Y,R" if dims == 2 else "X,Y,Z,R"
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        raise UsageError(f"--obstacle must be {shape} (numbers, metres), got {text!r}") from None
    if len(values) != dims + 1 or not np.all(np.isfinite(values)):
        raise UsageError(f"--obstacle must be {shape} (finite numbers, metres) for this robot, got {text!r}")
    check_magnitude(values, f"--obstacle {text}", MAX_LENGTH, "m")
    if values[-1] <= 0.0:
        raise UsageError(f"--obstacle radius must be positive, got {values[-1]:g} in {text!r}")
    return Obstacle(np.array(values[:-1]), values[-1])


def _units(degrees: bool) -> dict:
    return {"q": angle_unit(degrees), "goal": "m", "error": "m", "error_alone": "m", "goal_tolerance": "m",
            "end_error": "m", "min_clearance": "m", "centre": "m", "radius": "m", "seconds": "s (wall clock)"}


def _run_virtual_arms(args: argparse.Namespace) -> int:
    from redkin.virtual_arms import (
        AnalyticModel,
        OutputFunction,
        VirtualPoint,
        generate_trajectory,
        learn_forward_model,
    )

    chain = load_robot(args)
    probe = AnalyticModel(chain, [VirtualPoint.end()])
    dims = probe.dims
    if args.out:
        output_file(args.out, "--out", IMAGE_SUFFIXES | {".gif"}, args.force)
        if dims != 2:
            raise UsageError("--out draws planar arms only; this robot's task space is 3-D")
    points = [VirtualPoint.end()]
    goals = [_coordinates(args.goal, dims, "--goal")]
    for text in args.point:
        point, goal = _point_goal(text, dims)
        point.check(chain)
        points.append(point)
        goals.append(goal)
    weights = None
    if args.weight is not None:
        if len(args.weight) != len(points):
            raise UsageError(f"--weight: give one per point ({len(points)}: end first), got {len(args.weight)}")
        weights = np.asarray(args.weight, dtype=float)
    if args.q0 is None:
        q0 = np.full(chain.n, _DEFAULT_Q0)  # radians whatever --deg says
    else:
        q0 = joint_vector(chain, args.q0, args.deg, name="--q0 values")
    output = OutputFunction.sine(chain.lower, chain.upper) if args.limits else None
    check_count(args.max_steps, "--max-steps", 1, VIRTUAL_ARMS_MAX_STEPS)
    obstacles = [_obstacle(text, dims) for text in args.obstacle]
    if obstacles:
        if len(points) > 1 or weights is not None:
            raise UsageError("--obstacle plans every virtual point's goal itself: drop --point and --weight")
        if args.model == "learned":
            raise UsageError("--obstacle uses analytic forward models only (the planner watches many points)")
        return _run_with_obstacles(args, chain, q0, goals[0], obstacles, output)
    model: ForwardModel
    if args.model == "learned":
        model, _ = learn_forward_model(chain, points, axes=probe.axes, seed=0)
    else:
        model = AnalyticModel(chain, points, probe.axes)
    fixed = _fixed(args.fix, chain.n)
    run = generate_trajectory(model, q0, np.array(goals), weights, output=output, fixed=fixed,
                              max_steps=args.max_steps)
    # errors measured on the real chain (for a learned model the networks' view may differ)
    truth = AnalyticModel(chain, points, probe.axes).evaluate(run.final_theta)[0]
    errors = np.linalg.norm(truth - np.array(goals), axis=-1)
    met = errors <= _GOAL_TOLERANCE
    alone = {int(k): _alone(chain, points[k], goals[k], probe.axes, run.final_theta, output, fixed, args.max_steps)
             for k in np.flatnonzero(~met)}
    note = _goals_note(run.status, points, errors, alone, fixed, output is not None)
    if args.out and args.json:  # the file before the JSON that names it; in text, after the result lines
        _save_plot(args.out, chain, run, truth)
    q_final = angles_out(run.final_theta, args.deg)
    if args.json:
        print_json({
            "robot": chain.name, "status": run.status, "message": run.message, "model": args.model,
            "q": q_final, "angles": angle_unit(args.deg), "units": _units(args.deg),
            "points": [{"point": p.label, "goal": g, "error": e, "met": bool(ok), "error_alone": alone.get(k)}
                       for k, (p, g, e, ok) in enumerate(zip(points, goals, errors, met))],
            "goal_tolerance": _GOAL_TOLERANCE, "all_goals_met": bool(met.all()), "note": note,
            "steps": run.steps, "seconds": run.seconds,
        })
        return 0
    unit = "deg" if args.deg else "rad"
    print(f"{chain.name}: {run.status} ({run.message}), {plural(run.steps, 'step')}, {run.seconds:.3f} s")
    print(f"q [{unit}]: " + format_values(q_final))
    for point, error, ok in zip(points, errors, met):
        print(f"  {point.label:>12}: error {error:.3e} m" + ("" if ok else "  (goal not met)"))
    if note:
        print(note)
    if args.out:
        _save_plot(args.out, chain, run, truth)
        print(f"wrote {args.out}")
    return 0


def _alone(chain, point: VirtualPoint, goal: np.ndarray, axes, start: np.ndarray, output, fixed: list[int],
           max_steps: int) -> float:
    """How close ``point`` gets to ``goal`` with no other goal to share the joints with: from where the run ended,
    the same clamped joints and limits (metres)."""
    from redkin.virtual_arms import AnalyticModel, generate_trajectory

    model = AnalyticModel(chain, [point], axes)
    run = generate_trajectory(model, start, goal[None], output=output, fixed=fixed, max_steps=max_steps)
    return float(np.linalg.norm(model.evaluate(run.final_theta)[0][0] - goal))


def _goals_note(status: str, points: Sequence[VirtualPoint], errors: np.ndarray, alone: dict,
                fixed: list[int], limits: bool) -> str | None:
    """One line on the goals that were not met, and why, or ``None`` when every goal was met.

    The status says how the dynamics stopped: ``converged`` is an equilibrium of [004 eqs. 9-13], where the
    weighted errors cannot decrease further, and not a promise that every goal was met.  A goal is out of
    reach when its point, alone, still ends away from it; otherwise the goals compete for the joints and the
    weights decide the trade.
    """
    if not alone:
        return None
    held = []
    if fixed:
        held.append(f"{'joint' if len(fixed) == 1 else 'joints'} {','.join(str(j + 1) for j in fixed)} fixed")
    if limits:
        held.append("within the joint limits")
    under = f" ({', '.join(held)})" if held else ""
    reasons = []
    for k, alone_error in alone.items():
        if alone_error > _GOAL_TOLERANCE:
            reasons.append(f"goal of {points[k].label} not met, {_distance(float(errors[k]))} away: out of its "
                           f"reach{under}, on its own it gets no closer than {_distance(alone_error)}")
    competing = [k for k, alone_error in alone.items() if alone_error <= _GOAL_TOLERANCE]
    if competing:
        names = " and ".join(f"{points[k].label} ({_distance(float(errors[k]))} away)" for k in competing)
        each = "it reaches its goal" if len(competing) == 1 else "each reaches its goal"
        reasons.append(f"goal{'s' if len(competing) > 1 else ''} of {names} not met: {each} on its own, so the "
                       "goals compete for the joints and the weights (--weight) decide how close each point gets")
    meaning = {"converged": "converged: the dynamics came to rest, where the weighted errors cannot decrease further",
               "stalled": "stalled: the integrator could not go on", "max_steps": "max_steps: the step budget ran out",
               "max_time": "max_time: the time budget ran out"}.get(status, status)
    return f"{meaning}; " + "; ".join(reasons)


def _distance(metres: float) -> str:
    return f"{100 * metres:.3g} cm" if metres < 1.0 else f"{metres:.3g} m"


def _run_with_obstacles(args: argparse.Namespace, chain, q0: np.ndarray, goal: np.ndarray, obstacles: list,
                        output) -> int:
    from redkin.virtual_arms import avoid_obstacles

    run = avoid_obstacles(chain, q0, goal, obstacles, output=output, fixed=_fixed(args.fix, chain.n),
                          period_steps=min(args.max_steps, 20))
    if args.out and args.json:  # the file before the JSON that names it; in text, after the result lines
        _save_plot(args.out, chain, run, None, obstacles)
    q_final = angles_out(run.final_theta, args.deg)
    if args.json:
        print_json({
            "robot": chain.name, "status": run.status, "message": run.message, "model": "analytic",
            "q": q_final, "angles": angle_unit(args.deg), "units": _units(args.deg), "goal": goal,
            "end_error": run.end_error, "min_clearance": run.min_clearance,
            "obstacles": [{"centre": ob.centre, "radius": ob.radius} for ob in obstacles],
            "periods": run.periods, "steps": run.steps, "seconds": run.seconds,
        })
        return 0
    unit = "deg" if args.deg else "rad"
    print(f"{chain.name}: {run.status} ({run.message}), {plural(run.periods, 'period')}, "
          f"{plural(run.steps, 'step')}, {run.seconds:.3f} s")
    print(f"q [{unit}]: " + format_values(q_final))
    print(f"  end error {run.end_error:.3e} m, minimum clearance {run.min_clearance:.4f} m")
    if args.out:
        _save_plot(args.out, chain, run, None, obstacles)
        print(f"wrote {args.out}")
    return 0


def _save_plot(path: str, chain, run, truth: np.ndarray | None, obstacles: Sequence[Obstacle] = ()) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from redkin.plot.virtual_arms import draw_strobe

    goals = run.goals if truth is not None else run.goal[None]
    fig, ax = plt.subplots(figsize=(6, 6))
    title = f"{chain.name}: {run.status}"
    if path.lower().endswith(".gif"):  # an animation of the run instead of the stroboscopic drawing
        from matplotlib.animation import PillowWriter

        print(f"redkin: writing {path}: {len(run.theta)} frames, a few seconds", file=sys.stderr, flush=True)
        from redkin.plot.virtual_arms import animate_planar

        animate_planar(fig, ax, chain, run.theta, goals, title=title, obstacles=obstacles).save(
            path, writer=PillowWriter(fps=20), dpi=80
        )
    else:
        draw_strobe(ax, chain, run.theta, goals, truth, title=title, obstacles=obstacles)
        ax.legend(fontsize=7)
        fig.savefig(path, dpi=100)
    plt.close(fig)
