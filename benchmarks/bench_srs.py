"""Speed of arm-angle IK and feasible arm-angle sets (paper 000), beside roboticstoolbox's ik_LM where it installs.

Run: ``python benchmarks/bench_srs.py``.  Times are the best of several rounds (the machine may be shared).  Peer (optional): ``pip install roboticstoolbox-python``;
the script says so and skips it when it is not installed.  Prints one table.
"""

from __future__ import annotations

import time

import numpy as np

from redkin.models import pa10_7c
from redkin.srs import feasible_arm_angles, feasible_pieces, ik_all_branches, srs_geometry
from timing import best_time  # benchmarks/timing.py (the script's folder is on sys.path)


def main() -> None:
    chain = pa10_7c()
    geometry = srs_geometry(chain)
    rng = np.random.default_rng(0)
    q_in = rng.uniform(chain.lower, chain.upper, (100_000, 7))
    poses = chain.fk(q_in)
    pose = poses[0]
    rows = []
    t = best_time(lambda: ik_all_branches(geometry, pose, 0.3), repeat=5, number=2000)
    rows.append(("one pose, all 8 branches at psi", f"{t * 1e6:9.1f} us"))
    t = best_time(lambda: feasible_pieces(geometry, pose, "+++"), repeat=5, number=2000)
    rows.append(("one pose, feasible set (arrays)", f"{t * 1e6:9.1f} us"))
    t = best_time(lambda: feasible_pieces(geometry, pose, "+++").arc_set(), repeat=5, number=2000)
    rows.append(("one pose, feasible set (ArcSet)", f"{t * 1e6:9.1f} us"))
    t = best_time(lambda: feasible_arm_angles(geometry, pose, "+++"), repeat=5, number=500)
    rows.append(("one pose, feasible + per-joint ArcSets", f"{t * 1e6:9.1f} us"))
    t = best_time(lambda: ik_all_branches(geometry, poses, 0.3), repeat=3)
    rows.append(("batch 100 000 poses x 8 branches", f"{8 * len(poses) / t:9.3g} solutions/s"))
    t = best_time(lambda: feasible_pieces(geometry, poses, "+++"), repeat=2)
    rows.append(("batch 100 000 feasible sets (arrays)", f"{t / len(poses) * 1e6:9.2f} us/pose"))
    try:
        import roboticstoolbox as rtb  # noqa: F401
        from spatialmath import SE3
    except Exception as exc:  # noqa: BLE001 - any import failure means: peer not available
        rows.append(("roboticstoolbox ik_LM", f"skipped: roboticstoolbox-python not importable ({type(exc).__name__})"))
    else:
        links = [rtb.RevoluteDH(d=d, a=0.0, alpha=al) for d, al in zip(chain.d, chain.alpha)]
        robot = rtb.DHRobot(links)
        targets = [SE3(p, check=False) for p in poses[:200]]
        start = time.perf_counter()
        ok = 0
        for target in targets:
            solution = robot.ik_LM(target)
            ok += bool(solution.success)
        t = (time.perf_counter() - start) / len(targets)
        rows.append(("roboticstoolbox ik_LM, one solution", f"{t * 1e6:9.1f} us ({ok}/{len(targets)} converged)"))
    width = max(len(r[0]) for r in rows)
    print(f"{'benchmark (PA10-7C, numpy ' + np.__version__ + ')':<{width}}  result")
    for name, value in rows:
        print(f"{name:<{width}}  {value}")


if __name__ == "__main__":
    main()
