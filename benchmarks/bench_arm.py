"""Issue 39: the front door ``redkin.arm(file)`` against the class functions it wraps, one pose, in one run.

For each arm, the same pose and value of the parameter: :meth:`redkin.Arm.ik` against ``srs.ik_all_branches``
(iiwa14, psi), ``franka.ik`` (Panda, q7) and ``srs.nearly.ik`` (Gen3, psi), each on the geometry converted once; and
:meth:`redkin.Arm.feasible` against ``srs.feasible_pieces_all_branches`` (iiwa14) and ``franka.feasible_q7_batch``
(Panda).  The goal: at most 1.2 x the class function plus 2 us.  ``redkin.ik`` (the chain and the parameter by name)
is shown beside them.  Timing: :func:`timing.best_time_short_rounds`, the two callables of a row timed alternately
three times and the least of each kept, so that both meet the same load.

    python benchmarks/bench_arm.py
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from timing import best_time_short_rounds, machine_lines  # benchmarks/timing.py (the script's folder is on sys.path)

import redkin
from redkin import franka, srs
from redkin.srs import nearly

#: One configuration within every arm's limits; the pose is its FK.
CONFIGURATION = np.array([0.3, 0.5, -0.2, 1.2, 0.4, -0.6, 0.2])


def paired(first: Callable[[], object], second: Callable[[], object]) -> tuple[float, float]:
    """Seconds per call of each, timed alternately three times, the least of each."""
    times = [(best_time_short_rounds(first), best_time_short_rounds(second)) for _ in range(3)]
    return min(t[0] for t in times), min(t[1] for t in times)


def rows() -> list[tuple[str, str, float, float, float]]:
    """``(arm, question, class function us, arm us, redkin.ik us)`` per row (``nan``: no such front door)."""
    table = []
    for file, name, value in (("iiwa14.urdf", "psi", 0.3), ("panda.urdf", "q7", 0.2), ("gen3.urdf", "psi", 0.3)):
        arm = redkin.arm(file)
        pose = arm.fk(np.where(CONFIGURATION > arm.chain.upper, arm.chain.upper, CONFIGURATION))
        if name == "q7":
            geometry = franka.franka_geometry(arm.chain)
            kernel: Callable[[], object] = lambda: franka.ik(geometry, pose, value)  # noqa: E731
        elif arm.kind == redkin.arms.classify.NEARLY_SRS:
            neighbour = nearly.nearly_srs(arm.chain)
            kernel = lambda: nearly.ik(neighbour, pose, value)  # noqa: E731
        else:
            exact = srs.srs_geometry(arm.chain)
            kernel = lambda: srs.ik_all_branches(exact, pose, value)  # noqa: E731
        front = best_time_short_rounds(lambda: redkin.ik(arm.chain, pose, **{name: value}))
        base, ours = paired(kernel, lambda: arm.ik(pose, value))
        table.append((file, f"ik at {name}, 8 branches", base * 1e6, ours * 1e6, front * 1e6))
    for file in ("iiwa14.urdf", "panda.urdf"):
        arm = redkin.arm(file)
        pose = arm.fk(CONFIGURATION)
        if arm.parameter is not None and arm.parameter.name == "q7":
            geometry = franka.franka_geometry(arm.chain)
            kernel = lambda: franka.feasible_q7_batch(geometry, pose)  # noqa: E731
        else:
            exact = srs.srs_geometry(arm.chain)
            kernel = lambda: srs.feasible_pieces_all_branches(exact, pose[None])  # noqa: E731
        base, ours = paired(kernel, lambda: arm.feasible(pose))
        table.append((file, "feasible sets, 8 branches", base * 1e6, ours * 1e6, float("nan")))
    return table


def main() -> None:
    for line in machine_lines(["numpy", "numba"]):
        print(line)
    print("one pose, microseconds per call")
    print(f"{'arm':<14} {'question':<26} {'class fn':>9} {'arm':>9} {'ratio':>6} {'goal':>6} {'redkin.ik':>10}")
    for file, question, base, ours, front in rows():
        goal = 1.2 * base + 2.0
        print(f"{file:<14} {question:<26} {base:9.1f} {ours:9.1f} {ours / base:6.2f} "
              f"{'met' if ours <= goal else 'MISSED':>6} {front:10.1f}")


if __name__ == "__main__":
    main()
