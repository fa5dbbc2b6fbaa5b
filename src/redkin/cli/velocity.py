"""``redkin track``: simulate velocity IK along a commanded twist (paper 003)."""

from __future__ import annotations

import argparse
from dataclasses import replace

import numpy as np

from redkin._validation import check_output_file
from redkin.cli.common import (
    IMAGE_SUFFIXES,
    add_output_flags,
    add_robot_argument,
    angle_unit,
    angles_out,
    joint_vector,
    load_robot,
    print_json,
)
from redkin.velocity import METHOD_NAMES, SingularityConsistent, make_method, simulate, singularity_factorisation


def register(subparsers: argparse._SubParsersAction) -> None:
    track = subparsers.add_parser(
        "track", help="integrate velocity IK (sc, pinv, dls, dls-adaptive) along a constant commanded twist"
    )
    add_robot_argument(track)
    track.add_argument("--q0", nargs="+", type=float, required=True, metavar="Q", help="initial joint values")
    track.add_argument("--twist", nargs=6, type=float, required=True, metavar=("VX", "VY", "VZ", "WX", "WY", "WZ"),
                       help="commanded twist: m/s and rad/s (angular part in deg/s with --deg)")
    track.add_argument("--duration", type=float, required=True, metavar="T", help="simulated seconds")
    track.add_argument("--method", choices=METHOD_NAMES, default="sc")
    track.add_argument("--eps", type=float, default=0.1, metavar="D",
                       help="singular-region threshold: on |D_e| for sc, on sigma_min for dls-adaptive (default 0.1)")
    track.add_argument("--damping", type=float, default=0.05, metavar="L",
                       help="(maximum) damping for dls / dls-adaptive")
    track.add_argument("--dt", type=float, default=1e-3, help="RK4 step in seconds (default 0.001)")
    track.add_argument("--plot", metavar="PNG", help="save the six-panel figure here")
    add_output_flags(track)
    track.set_defaults(handler=_run_track)


def _run_track(args: argparse.Namespace) -> int:
    if args.plot:
        check_output_file(args.plot, "--plot", IMAGE_SUFFIXES)
    chain = load_robot(args)
    q0 = joint_vector(chain, args.q0, args.deg, name="--q0 values")
    twist = np.asarray(args.twist, dtype=float)
    if args.deg:
        twist[3:] = np.radians(twist[3:])
    if not np.all(np.isfinite(twist)):
        raise ValueError("--twist must be finite numbers")
    method = make_method(args.method, eps=args.eps, damping=args.damping)
    try:
        factorisation = singularity_factorisation(chain)
    except ValueError as exc:
        if isinstance(method, SingularityConsistent):
            raise ValueError(f"--method sc needs a singularity index D_e: {exc}") from None
        factorisation = None
    if isinstance(method, SingularityConsistent):
        method = replace(method, factorisation=factorisation)
    run = simulate(chain, q0, twist, args.duration, method, dt=args.dt,
                   index=None if factorisation is None else factorisation.index)
    speed = np.linalg.norm(run.joint_velocity, axis=1)
    crossings = None if run.index is None else int(np.count_nonzero(np.diff(np.sign(run.index)) != 0))
    if args.plot:
        import matplotlib.pyplot as plt

        from redkin.plot.velocity import tracking_figure

        fig = tracking_figure(run, args.eps, title=f"{chain.name}, method {args.method}")
        fig.savefig(args.plot, dpi=100)
        plt.close(fig)
    if args.json:
        angle = angle_unit(args.deg)
        print_json({
            "robot": chain.name, "method": args.method,
            "units": {"time": "s", "q": angle, "joint_velocity": f"{angle}/s", "max_joint_speed": f"{angle}/s",
                      "realised_twist": f"m/s (linear), {angle}/s (angular)",
                      "target_twist": f"m/s (linear), {angle}/s (angular)",
                      "position": "m", "index": "D_e, as the singularity factorisation defines it"},
            "time": run.time, "q": angles_out(run.q, args.deg),
            "joint_velocity": angles_out(run.joint_velocity, args.deg),
            "realised_twist": _twist_out(run.realised, args.deg), "target_twist": _twist_out(run.target, args.deg),
            "index": run.index, "position": run.position,
            "max_joint_speed": float(angles_out(speed.max(), args.deg)), "crossings": crossings,
        })
    else:
        print(f"{chain.name}, method {args.method}: {len(run.time) - 1} RK4 steps of {args.dt:g} s")
        print(f"start position  {np.array2string(run.position[0], precision=4)}")
        print(f"final position  {np.array2string(run.position[-1], precision=4)}")
        print(f"final q         {np.array2string(angles_out(run.q[-1], args.deg), precision=4)}")
        unit = "deg/s" if args.deg else "rad/s"
        print(f"max ||q_dot||   {float(angles_out(speed.max(), args.deg)):.4g} {unit}")
        if run.index is not None:  # crossings were counted
            print(f"D_e from {run.index[0]:.4g} to {run.index[-1]:.4g}, sign changes: {crossings}")
    return 0


def _twist_out(twists: np.ndarray, degrees: bool) -> np.ndarray:
    """Twists ``(..., 6)`` for output: the angular part in deg/s with ``--deg``."""
    out = np.array(twists, dtype=float)
    out[..., 3:] = angles_out(out[..., 3:], degrees)
    return out
