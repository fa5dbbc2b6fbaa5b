"""``redkin track``: simulate velocity IK along a commanded twist (paper 003)."""

from __future__ import annotations

import argparse
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from redkin._constants import VELOCITY_METHOD_NAMES
from redkin._validation import check_magnitude
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
from redkin.errors import RedkinError

if TYPE_CHECKING:  # the parser is built without the velocity package (and its kernels): the handler imports it
    from redkin.velocity import TrackingResult

#: Largest entry of a commanded twist (m/s, rad/s): far beyond any arm, far below where the integration overflows.
_MAX_SPEED = 1e6
#: The (maximum) damping of dls and dls-adaptive unless --damping gives it.
_DAMPING = 0.05


def register(subparsers: argparse._SubParsersAction) -> None:
    track = subparsers.add_parser(
        "track", help="integrate velocity IK (sc, pinv, dls, dls-adaptive) along a constant commanded twist"
    )
    add_robot_argument(track)
    track.add_argument("--q0", nargs="+", type=float, required=True, metavar="Q",
                       help="initial joint values (radians, or degrees with --deg)")
    track.add_argument("--twist", nargs=6, type=float, required=True, metavar=("VX", "VY", "VZ", "WX", "WY", "WZ"),
                       help="commanded twist: m/s and rad/s (angular part in deg/s with --deg)")
    track.add_argument("--duration", type=float, required=True, metavar="T", help="simulated seconds")
    track.add_argument("--method", choices=VELOCITY_METHOD_NAMES, default="sc",
                       help="velocity IK method: sc, singularity-consistent (paper 003; passes singularities "
                            "keeping the commanded direction, default); pinv, the pseudoinverse; dls, damped least "
                            "squares with --damping; dls-adaptive, damping that grows as sigma_min falls below --eps")
    track.add_argument("--eps", type=float, default=0.1, metavar="D",
                       help="singular-region threshold: on |D_e| for sc, on sigma_min for dls-adaptive (default 0.1)")
    track.add_argument("--damping", type=float, metavar="L",
                       help="(maximum) damping for dls / dls-adaptive (default 0.05)")
    track.add_argument("--dt", type=float, default=1e-3, help="RK4 step in seconds (default 0.001)")
    track.add_argument("--plot", metavar="PNG", help="save the six-panel figure here")
    add_force_flag(track)
    add_output_flags(track)
    track.add_argument("--series", action="store_true",
                       help="with --json: also print the whole time series (every RK4 step: time, q, joint "
                            "velocity, twists, D_e, position); without it --json prints the summary only")
    track.set_defaults(handler=_run_track)


def _run_track(args: argparse.Namespace) -> int:
    from redkin.velocity import SingularityConsistent, make_method, simulate, singularity_factorisation

    if args.series and not args.json:
        raise UsageError("--series adds the time series to the --json output: add --json")
    if args.plot:
        output_file(args.plot, "--plot", IMAGE_SUFFIXES, args.force)
    chain = load_robot(args)
    q0 = joint_vector(chain, args.q0, args.deg, name="--q0 values")
    twist = np.asarray(args.twist, dtype=float)
    if args.deg:
        twist[3:] = np.radians(twist[3:])
    if not np.all(np.isfinite(twist)):
        raise RedkinError("--twist must be finite numbers")
    check_magnitude(twist, "--twist (m/s, rad/s)", _MAX_SPEED)
    if args.damping is not None and args.method not in ("dls", "dls-adaptive"):  # it was ignored without a word
        raise UsageError(f"--damping is for --method dls or dls-adaptive; {args.method} has no damping")
    damping = _DAMPING if args.damping is None else args.damping
    for option, value in (("--eps", args.eps), ("--damping", damping)):  # the library says if not > 0
        if np.isfinite(value):
            check_magnitude(value, option, _MAX_SPEED)
    method = make_method(args.method, eps=args.eps, damping=damping)
    try:
        factorisation = singularity_factorisation(chain)
    except ValueError as exc:
        if isinstance(method, SingularityConsistent):
            raise RedkinError(f"--method sc needs a singularity index D_e: {exc}") from None
        factorisation = None
    if isinstance(method, SingularityConsistent):
        method = replace(method, factorisation=factorisation)
    run = simulate(chain, q0, twist, args.duration, method, dt=args.dt,
                   index=None if factorisation is None else factorisation.index)
    summary = _tracking_summary(run)
    if args.plot and args.json:  # the figure before the JSON; in text, after the result lines
        _save_tracking_figure(args.plot, run, args.eps, f"{chain.name}, method {args.method}")
    deg = args.deg
    angle = angle_unit(deg)
    if args.json:
        out = {
            "robot": chain.name, "method": args.method,
            "units": {"time": "s", "q": angle, "max_joint_speed": f"{angle}/s", "position": "m",
                      "twist": f"m/s (linear), {angle}/s (angular)", "final_error": f"m/s (linear), {angle}/s "
                      "(angular)", "max_error": f"m/s (linear), {angle}/s (angular)",
                      "singularity_index": "D_e, as the singularity factorisation defines it"},
            "steps": len(run.time) - 1, "dt": args.dt, "duration": float(run.time[-1]),
            "start": {"q": angles_out(run.q[0], deg), "position": run.position[0]},
            "final": {"time": float(run.time[-1]), "q": angles_out(run.q[-1], deg), "position": run.position[-1],
                      "commanded_twist": _twist_out(run.commanded[-1], deg),
                      "realised_twist": _twist_out(run.realised[-1], deg)},
            "final_error": _error_out(summary.final_error, deg), "max_error": _error_out(summary.max_error, deg),
            "error": "|J q_dot - commanded twist|: linear and angular parts (sc keeps the commanded direction but "
                     "may reverse or slow the motion at a singularity; dls trades accuracy for bounded speed)",
            "max_joint_speed": float(angles_out(summary.peak_speed, deg)), "max_joint_speed_time": summary.peak_time,
            "crossings": summary.crossings, "crossing_times": summary.crossing_times,
            "singularity_index": None if run.index is None else {
                "start": float(run.index[0]), "final": float(run.index[-1]),
                "min_abs": float(np.abs(run.index).min())},
        }
        if args.series:
            out["units"].update({"joint_velocity": f"{angle}/s", "realised_twist": f"m/s (linear), {angle}/s (angular)",
                                 "target_twist": f"m/s (linear), {angle}/s (angular)",
                                 "index": "D_e, as the singularity factorisation defines it"})
            out.update({"time": run.time, "q": angles_out(run.q, deg),
                        "joint_velocity": angles_out(run.joint_velocity, deg),
                        "realised_twist": _twist_out(run.realised, deg), "target_twist": _twist_out(run.target, deg),
                        "index": run.index, "position": run.position})
        print_json(out)
    else:
        print(f"{chain.name}, method {args.method}: {plural(len(run.time) - 1, 'RK4 step')} of {args.dt:g} s")
        print(f"start position  {format_values(run.position[0], 4)} m")
        print(f"final position  {format_values(run.position[-1], 4)} m")
        print(f"final q         {format_values(angles_out(run.q[-1], deg), 4)} {angle}")
        print(f"max ||q_dot||   {float(angles_out(summary.peak_speed, deg)):.4g} {angle}/s at t = "
              f"{summary.peak_time:.4g} s")
        final = _error_out(summary.final_error, deg)
        print(f"final error     {final['linear']:.3g} m/s, {final['angular']:.3g} {angle}/s "
              "(|J q_dot - commanded twist|)")
        if run.index is not None:  # crossings were counted
            times = ", ".join(f"{t:.4g}" for t in summary.crossing_times or [])
            print(f"D_e from {run.index[0]:.4g} to {run.index[-1]:.4g}, sign changes: {summary.crossings}"
                  + (f" (t = {times} s)" if times else ""))
        if args.plot:
            _save_tracking_figure(args.plot, run, args.eps, f"{chain.name}, method {args.method}")
            print(f"wrote {args.plot}")
    return 0


def _save_tracking_figure(file: str, run, eps: float, title: str) -> None:
    """The six-panel figure of :func:`redkin.plot.velocity.tracking_figure` for ``run``, saved to ``file``."""
    import matplotlib.pyplot as plt

    from redkin.plot.velocity import tracking_figure

    fig = tracking_figure(run, eps, title=title)
    fig.savefig(file, dpi=100)
    plt.close(fig)


@dataclass(frozen=True)
class _TrackingSummary:
    """What a run did, in radians: its peak joint speed and when, its twist errors, and where D_e changed sign."""

    peak_speed: float
    peak_time: float
    final_error: tuple[float, float]
    max_error: tuple[float, float]
    crossings: int | None
    crossing_times: list[float] | None


def _tracking_summary(run: TrackingResult) -> _TrackingSummary:
    """The summary of ``run`` that ``track`` prints: ||q_dot|| at its peak, the realised twist's distance from the
    command (linear, angular) at the end and at its largest, and the sign changes of D_e (their times
    interpolated linearly between the steps)."""
    speed = np.linalg.norm(run.joint_velocity, axis=1)
    peak = int(np.argmax(speed))
    error = run.realised - run.commanded
    linear, angular = np.linalg.norm(error[:, :3], axis=1), np.linalg.norm(error[:, 3:], axis=1)
    crossings = times = None
    if run.index is not None:
        d = np.asarray(run.index, dtype=float)
        changes = np.flatnonzero(np.diff(np.sign(d)) != 0)
        crossings = int(changes.size)
        times = []
        for k in changes:
            step = d[k] - d[k + 1]
            fraction = d[k] / step if step != 0 else 0.0
            times.append(float(run.time[k] + fraction * (run.time[k + 1] - run.time[k])))
    return _TrackingSummary(peak_speed=float(speed[peak]), peak_time=float(run.time[peak]),
                           final_error=(float(linear[-1]), float(angular[-1])),
                           max_error=(float(linear.max()), float(angular.max())),
                           crossings=crossings, crossing_times=times)


def _error_out(error: tuple[float, float], degrees: bool) -> dict[str, float]:
    return {"linear": error[0], "angular": float(angles_out(error[1], degrees))}


def _twist_out(twists: np.ndarray, degrees: bool) -> np.ndarray:
    """Twists ``(..., 6)`` for output: the angular part in deg/s with ``--deg``."""
    out = np.array(twists, dtype=float)
    out[..., 3:] = angles_out(out[..., 3:], degrees)
    return out
