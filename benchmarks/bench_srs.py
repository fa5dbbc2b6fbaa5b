"""Speed of arm-angle IK and feasible arm-angle sets (paper 000), beside roboticstoolbox's ik_LM and ssik where they install.

Run: ``python benchmarks/bench_srs.py``.  Times are the best of several rounds (the machine may be shared).
Peers (optional, ``pip install -e ".[bench]"``): roboticstoolbox-python (``ik_LM``, PA10 poses) and ssik 8.2
(its feasible-swivel search, on the iiwa14 it ships prebuilt); the script says so and skips a peer that is not
installed.  Prints one table.

ssik's iiwa14 is our ``kuka_iiwa14`` with joint 4 turned the other way (same base, tool and symmetric limits), so
both libraries get the same poses.  The arm angles of the two differ by a reference per branch, so the sets are
compared by the lengths of the eight branches' feasible sets (sorted), which do not depend on the reference.
"""

from __future__ import annotations

import time

import numpy as np

from redkin.models import kuka_iiwa14, pa10_7c
from redkin.srs import BRANCHES, arm_angle_of, feasible_arm_angles, feasible_pieces, ik_all_branches, srs_geometry
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
    rows.extend(ssik_rows())
    width = max(len(r[0]) for r in rows)
    header = f"benchmark (PA10-7C unless stated, numpy {np.__version__})"
    print(f"{header:<{width}}  result")
    for name, value in rows:
        print(f"{name:<{width}}  {value}")


#: ssik's iiwa14 joint values are ours with joint 4 negated.
IIWA_SSIK_SIGNS = np.array([1.0, 1.0, 1.0, -1.0, 1.0, 1.0, 1.0])


def ssik_rows(poses: int = 10) -> list[tuple[str, str]]:
    """ssik's feasible-swivel arcs of all eight branches beside ours on the same iiwa14 poses."""
    try:
        from ssik.core.tolerances import DEFAULT_TOLERANCE_POLICY
        from ssik.kinematics.predicates import _classify_srs_7r_geometric
        from ssik.prebuilt.kuka import iiwa14_ik
        from ssik.solvers.seven_r._swivel_limits import _branch_arcs, _enumerate_branches
    except Exception as exc:  # noqa: BLE001 - any import failure means: peer not available
        return [("ssik feasible-swivel search", f"skipped: ssik 8.2 not importable ({type(exc).__name__})")]
    body = iiwa14_ik._KB
    srs_class = _classify_srs_7r_geometric(body, DEFAULT_TOLERANCE_POLICY)
    chain = kuka_iiwa14()
    rng = np.random.default_rng(1)
    q_ssik = rng.uniform(-2.0, 2.0, (poses, 7))
    targets = [iiwa14_ik.fk(q) for q in q_ssik]
    assert np.allclose(chain.fk(q_ssik * IIWA_SSIK_SIGNS), np.array(targets), atol=1e-9), "iiwa14 models differ"

    def ssik_sets(target, limits):
        return [_branch_arcs(branch, limits) for branch in _enumerate_branches(body, srs_class, target)]

    def our_sets(arm, target):
        return [feasible_pieces(arm, target, str(branch)).arc_set() for branch in BRANCHES]

    own_limits = [(lo, hi) for lo, hi in zip(chain.lower, chain.upper)]
    geometry = srs_geometry(chain)
    t_ssik = sum(best_time(lambda: ssik_sets(t, own_limits), repeat=1) for t in targets) / poses
    t_ours = sum(best_time(lambda: our_sets(geometry, t), repeat=5, number=20) for t in targets) / poses
    gap = 0.0
    for target in targets:
        theirs = sorted(sum(b - a for a, b in arcs) for arcs in ssik_sets(target, own_limits))
        ours = sorted(arc_set.length for arc_set in our_sets(geometry, target))
        gap = max(gap, float(np.max(np.abs(np.array(theirs) - np.array(ours)))))
    rows = [
        ("ssik 8.2 feasible-swivel search, 8 branches", f"{t_ssik * 1e3:9.1f} ms per pose (iiwa14)"),
        ("redkin feasible sets, 8 branches, same poses", f"{t_ours * 1e6:9.1f} us per pose: {t_ssik / t_ours:.0f}x faster"),
        ("  largest difference of a branch's set length", f"{gap:9.1e} rad"),
    ]
    for half_width in (1e-2, 1e-3, 1e-4):  # limits tight around a known solution: its arc must be found
        found_ssik = found_ours = 0
        for q in q_ssik:
            q_ours = q * IIWA_SSIK_SIGNS
            tight = chain.with_limits(q_ours - half_width, q_ours + half_width)
            found_ssik += any(ssik_sets(iiwa14_ik.fk(q), [(v - half_width, v + half_width) for v in q]))
            state = arm_angle_of(tight, q_ours)
            result = feasible_arm_angles(tight, chain.fk(q_ours), str(state.branch_strings()))
            found_ours += result.feasible.contains(float(state.psi), tolerance=1e-12)
        rows.append((f"  limits +-{half_width:g} rad around a solution", f"arc found: ssik {found_ssik}/{poses}, redkin {found_ours}/{poses}"))
    return rows


if __name__ == "__main__":
    main()
