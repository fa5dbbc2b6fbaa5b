"""Speed of arm-angle IK and feasible arm-angle sets (paper 000), beside roboticstoolbox and ssik where they install.

Run: ``python benchmarks/bench_srs.py``.  Times are the best of several rounds (the machine may be shared); the
one-pose rows and the IK rows beside the peers use rounds of the same length, about 10 ms, for every library.
Peers (optional, ``pip install -e ".[bench]"``): roboticstoolbox-python (``ETS.ik_LM`` in C++, PA10 poses) and
ssik 8.2 (its native C++ IK and its feasible-swivel search, on the iiwa14 it ships prebuilt); the script says so
and skips a peer that is not installed.  Prints one table.

Each peer runs in its best documented configuration, named in its row, and every solver's joint values are
judged by our own forward kinematics (``chain.fk``): a solution passes when the norm of (position error in m,
rotation error in rad) is at most 1e-9.

ssik's iiwa14 is our ``kuka_iiwa14`` (KUKA's joint conventions: same joint values, base, tool and limits), so
both libraries get the same poses and joint values.  The arm angles of the two differ by a reference per branch,
so the sets are compared by the lengths of the eight branches' feasible sets (sorted), which do not depend on the
reference.
"""

from __future__ import annotations

import os
from collections.abc import Callable

import numba
import numpy as np
from timing import best_time, best_time_short_rounds  # benchmarks/timing.py (the script's folder is on sys.path)

from redkin import thread_count
from redkin.chain import SerialChain
from redkin.models import kuka_iiwa14, pa10_7c
from redkin.srs import (
    BRANCHES,
    SRSGeometry,
    arm_angle_of,
    feasible_arm_angles,
    feasible_pieces,
    ik_all_branches,
    srs_geometry,
)
from redkin.srs.coefficients import coefficients_for
from redkin.srs.feasible import (
    _all_branch_pieces,
    _overall_pieces,
    feasible_from_coefficients,
    feasible_pieces_all_branches,
)


def main() -> None:
    chain = pa10_7c()
    geometry = srs_geometry(chain)
    rng = np.random.default_rng(0)
    q_in = rng.uniform(chain.lower, chain.upper, (100_000, 7))
    poses = chain.fk(q_in)
    pose = poses[0]
    rows = []
    t_branches = best_time_short_rounds(lambda: ik_all_branches(geometry, pose, 0.3))
    passed = passes(chain, ik_all_branches(geometry, poses[:200], 0.3), poses[:200, None])
    rows.append(("one pose, all 8 branches at psi", f"{t_branches * 1e6:9.1f} us ({passed}/1600 pass at 1e-9)"))
    rows.extend(feasible_rows(geometry, pose))
    t = best_time(lambda: ik_all_branches(geometry, poses, 0.3), repeat=3)
    rows.append(("batch 100 000 poses x 8 branches", f"{8 * len(poses) / t:9.3g} solutions/s"))
    rows.extend(feasible_batch_rows(geometry, poses))
    rows.extend(rtb_rows(chain, poses[:200], t_branches))
    rows.extend(ssik_rows())
    width = max(len(r[0]) for r in rows)
    load = ", ".join(f"{v:.1f}" for v in os.getloadavg())
    header = (f"benchmark (PA10-7C unless stated, numpy {np.__version__}, numba {numba.__version__}, redkin's pool on "
              f"{thread_count()} threads, load average {load})")
    print(f"{header:<{width}}  result")
    for name, value in rows:
        print(f"{name:<{width}}  {value}")


def feasible_calls(geometry: SRSGeometry, pose: np.ndarray) -> list[tuple[str, Callable[[], object]]]:
    """The one-pose feasible-set calls, through the public API (validation and eqs. 4-19 included) and from
    coefficients computed beforehand (eqs. 20-30 alone, the compiled kernels of redkin.srs._feasible_kernels)."""
    branch = geometry.table1_branch("+++")
    one = coefficients_for(geometry, pose, branch.elbow)
    both = coefficients_for(geometry, pose[None], np.array([1, -1]))
    return [
        ("feasible set of one branch, arrays (feasible_pieces)", lambda: feasible_pieces(geometry, pose, "+++")),
        ("  same, coefficients precomputed (_overall_pieces)", lambda: _overall_pieces(one, branch, geometry)),
        ("feasible set of one branch, ArcSet (feasible_pieces(...).arc_set())",
         lambda: feasible_pieces(geometry, pose, "+++").arc_set()),
        ("feasible + per-joint ArcSets (feasible_arm_angles)", lambda: feasible_arm_angles(geometry, pose, "+++")),
        ("  same, coefficients precomputed (feasible_from_coefficients)",
         lambda: feasible_from_coefficients(one, branch, geometry)),
        ("all 8 branches' feasible sets, arrays (feasible_pieces_all_branches)",
         lambda: feasible_pieces_all_branches(geometry, pose)),
        ("  same, coefficients precomputed (_all_branch_pieces)", lambda: _all_branch_pieces(both, geometry)),
    ]


def feasible_rows(geometry: SRSGeometry, pose: np.ndarray) -> list[tuple[str, str]]:
    """One pose: each of :func:`feasible_calls`, in rounds of about 10 ms."""
    return [(f"one pose, {name}", f"{best_time_short_rounds(call) * 1e6:9.1f} us")
            for name, call in feasible_calls(geometry, pose)]


def feasible_batch_rows(geometry: SRSGeometry, poses: np.ndarray) -> list[tuple[str, str]]:
    """Batches of feasible sets in pose-branches per second, public and from precomputed coefficients."""
    branch = geometry.table1_branch("+++")
    one = coefficients_for(geometry, poses, branch.elbow)
    both = coefficients_for(geometry, poses[:, None], np.array([1, -1]))
    count = len(poses)
    rows = []
    for name, call, per_pose in (
        ("feasible_pieces, one branch", lambda: feasible_pieces(geometry, poses, "+++"), 1),
        ("  coefficients precomputed (_overall_pieces, serial)", lambda: _overall_pieces(one, branch, geometry), 1),
        ("feasible_pieces_all_branches, 8 branches", lambda: feasible_pieces_all_branches(geometry, poses), 8),
        ("  coefficients precomputed (_all_branch_pieces, serial)", lambda: _all_branch_pieces(both, geometry), 8),
    ):
        t = best_time(call, repeat=3)
        rows.append((f"batch {count:,} poses, {name}".replace(",", " "),
                     f"{per_pose * count / t:9.3g} pose-branches/s"))
    return rows


#: A solution passes when |(position error [m], rotation error [rad])| of our FK is at most this.
POSE_TOLERANCE = 1e-9


def pose_errors(chain: SerialChain, q: np.ndarray, poses: np.ndarray) -> np.ndarray:
    """Norm of (position error, rotation angle of the error) of ``chain.fk(q)`` against ``poses``."""
    reached = chain.fk(q)
    position = np.linalg.norm(reached[..., :3, 3] - poses[..., :3, 3], axis=-1)
    error = np.swapaxes(reached[..., :3, :3], -1, -2) @ poses[..., :3, :3]
    skew = np.stack([error[..., 2, 1] - error[..., 1, 2], error[..., 0, 2] - error[..., 2, 0],
                     error[..., 1, 0] - error[..., 0, 1]], axis=-1)
    angle = np.arctan2(np.linalg.norm(skew, axis=-1) / 2.0, (np.trace(error, axis1=-2, axis2=-1) - 1.0) / 2.0)
    return np.hypot(position, angle)


def passes(chain: SerialChain, q: np.ndarray, poses: np.ndarray) -> int:
    """How many of the solutions ``q`` reach their poses within :data:`POSE_TOLERANCE` by our FK."""
    return int(np.sum(pose_errors(chain, q, poses) <= POSE_TOLERANCE))


#: roboticstoolbox's C++ LM at its best: one search from a start drawn in the joint limits, Chan's damping with
#: k = 0.1, and ``tol`` on its residual E = |e|^2 / 2 set to our tolerance, |e| = 1e-9 (default 1e-6: |e| ~ 1.4e-3).
RTB_IK_LM = {"ilimit": 30, "slimit": 1, "tol": POSE_TOLERANCE**2 / 2, "joint_limits": False, "k": 0.1, "method": "chan"}


def rtb_rows(chain: SerialChain, poses: np.ndarray, t_branches: float) -> list[tuple[str, str]]:
    """roboticstoolbox's ``ETS.ik_LM`` (C++) on ``poses``, one solution per pose, beside our 8 branches of one pose."""
    try:
        import roboticstoolbox as rtb
    except Exception as exc:
        return [("roboticstoolbox ETS.ik_LM", f"skipped: roboticstoolbox-python not importable ({type(exc).__name__})")]
    links = [rtb.RevoluteDH(d=d, alpha=alpha, qlim=[lo, hi])
             for d, alpha, lo, hi in zip(chain.d, chain.alpha, chain.lower, chain.upper)]
    ets = rtb.DHRobot(links).ets()  # built once: DHRobot.ik_LM rebuilds it on every call
    starts = np.random.default_rng(2).uniform(chain.lower, chain.upper, (len(poses), chain.n))

    def solve_all():
        return [ets.ik_LM(target, q0=start, **RTB_IK_LM) for target, start in zip(poses, starts)]

    t_call = best_time_short_rounds(solve_all) / len(poses)
    solutions = solve_all()
    ok = pose_errors(chain, np.array([solution.q for solution in solutions]), poses) <= POSE_TOLERANCE
    agree = sum(bool(solution.success) == good for solution, good in zip(solutions, ok))
    passed = int(ok.sum())
    t_solution = t_call * len(poses) / max(passed, 1)
    settings = ", ".join(f"{key}={value!r}" for key, value in RTB_IK_LM.items())
    return [
        (f"roboticstoolbox {rtb.__version__} ETS.ik_LM (C++), one solution",
         f"{t_call * 1e6:9.1f} us per call, {t_solution * 1e6:.1f} us per passing solution "
         f"({passed}/{len(poses)} pass at 1e-9; rtb's success flag agrees on {agree})"),
        ("  configuration", f"{settings}, q0 uniform in the joint limits"),
        ("  redkin's 8 branches of one pose / one rtb solution",
         f"{t_branches / t_solution:9.2f}x the time ({t_branches / 8 / t_solution:.2f}x per solution)"),
    ]


def ssik_rows(poses: int = 10) -> list[tuple[str, str]]:
    """ssik's IK and feasible-swivel arcs of all eight branches beside ours on the same iiwa14 poses."""
    try:
        from ssik.core.tolerances import DEFAULT_TOLERANCE_POLICY
        from ssik.kinematics.predicates import _classify_srs_7r_geometric
        from ssik.prebuilt.kuka import iiwa14_ik
        from ssik.solvers.seven_r._swivel_limits import _branch_arcs, _enumerate_branches
    except Exception as exc:
        return [("ssik feasible-swivel search", f"skipped: ssik 8.2 not importable ({type(exc).__name__})")]
    body = iiwa14_ik._KB
    srs_class = _classify_srs_7r_geometric(body, DEFAULT_TOLERANCE_POLICY)
    chain = kuka_iiwa14()
    rng = np.random.default_rng(1)
    q_ssik = rng.uniform(-2.0, 2.0, (poses, 7))
    targets = [iiwa14_ik.fk(q) for q in q_ssik]
    assert np.allclose(chain.fk(q_ssik), np.array(targets), atol=1e-9), "iiwa14 models differ"

    def ssik_sets(target, limits):
        return [_branch_arcs(branch, limits) for branch in _enumerate_branches(body, srs_class, target)]

    def our_sets(arm, target):
        pieces = feasible_pieces_all_branches(arm, target)
        return [pieces.arc_set((k,)) for k in range(len(BRANCHES))]

    own_limits = [(lo, hi) for lo, hi in zip(chain.lower, chain.upper)]
    geometry = srs_geometry(chain)
    ik_rows, t_solution = ssik_ik_rows(chain, geometry, np.array(targets))
    t_ssik = sum(best_time(lambda: ssik_sets(t, own_limits), repeat=1) for t in targets) / poses
    t_ours = sum(best_time(lambda: our_sets(geometry, t), repeat=5, number=20) for t in targets) / poses
    gap = 0.0
    for target in targets:
        theirs = sorted(sum(b - a for a, b in arcs) for arcs in ssik_sets(target, own_limits))
        ours = sorted(arc_set.length for arc_set in our_sets(geometry, target))
        gap = max(gap, float(np.max(np.abs(np.array(theirs) - np.array(ours)))))
    rows = ik_rows + feasible_ratio_rows(geometry, targets, 8 * t_solution) + [
        ("ssik 8.2 feasible-swivel search, 8 branches", f"{t_ssik * 1e3:9.1f} ms per pose (iiwa14)"),
        ("redkin feasible sets, 8 branches, same poses",
         f"{t_ours * 1e6:9.1f} us per pose: {t_ssik / t_ours:.0f}x faster"),
        ("  largest difference of a branch's set length", f"{gap:9.1e} rad"),
    ]
    for half_width in (1e-2, 1e-3, 1e-4):  # limits tight around a known solution: its arc must be found
        found_ssik = found_ours = 0
        for q in q_ssik:
            tight = chain.with_limits(q - half_width, q + half_width)
            found_ssik += any(ssik_sets(iiwa14_ik.fk(q), [(v - half_width, v + half_width) for v in q]))
            state = arm_angle_of(tight, q)
            result = feasible_arm_angles(tight, chain.fk(q), str(state.branch_strings()))
            found_ours += result.feasible.contains(float(state.psi), tolerance=1e-12)
        rows.append((f"  limits +-{half_width:g} rad around a solution",
                     f"arc found: ssik {found_ssik}/{poses}, redkin {found_ours}/{poses}"))
    return rows


def ssik_ik_rows(
    chain: SerialChain, geometry: SRSGeometry, targets: np.ndarray
) -> tuple[list[tuple[str, str]], float]:
    """ssik's native C++ IK (every solution it returns for one pose) beside ``ik_all_branches`` on the same poses,
    and ssik's seconds per solution (NaN where its C++ extension is missing).

    Both sides are prepared once per arm: ssik's ``Solver``, our ``geometry``.  Ours runs at one arm angle
    (8 solutions) and at 16 (ssik's sweep, 128 solutions); the ratios are ours over ssik's time.
    """
    import ssik
    from ssik import _native
    from ssik.prebuilt.kuka import iiwa14_ik

    if not _native.native_available():
        return [("ssik native IK", "skipped: ssik's C++ extension is not shipped for this platform")], float("nan")
    solver = _native._solver(_native._load_ext(), iiwa14_ik._KB, iiwa14_ik.SOLVER_NAME)  # what solve(T) calls

    def solve(target):
        return solver.solve(target, 0)[0]  # respect_limits=0: no joint-limit filter (as ours)

    t_ssik, per_pose, passed = timed_solutions(chain, solve, targets)
    rows = [
        (f"ssik {ssik.__version__} native C++ IK, all solutions of one pose",
         f"{t_ssik * 1e6:9.1f} us per pose, {per_pose} solutions: {t_ssik / per_pose * 1e6:.2f} us per solution "
         f"({passed}/{per_pose * len(targets)} pass at 1e-9, iiwa14)"),
        ("  configuration", f"iiwa14_ik's prepared native Solver ({iiwa14_ik.SOLVER_NAME}), "
                            "solve(T, respect_limits=0): 16 swivel angles x 8 branches, no Solution objects"),
    ]
    for label, psi in (("one psi", 0.3), ("16 psi (as ssik)", np.linspace(-np.pi, np.pi, 16, endpoint=False))):
        t_ours, ours, passed = timed_solutions(chain, lambda target: ik_all_branches(geometry, target, psi), targets)
        rows.append((f"redkin ik_all_branches, same poses, {label}",
                     f"{t_ours * 1e6:9.1f} us per pose, {ours} solutions: {t_ours / ours * 1e6:.2f} us per solution "
                     f"({passed}/{ours * len(targets)} pass): {t_ours / t_ssik:.2f}x ssik's time per pose, "
                     f"{t_ours / ours / (t_ssik / per_pose):.2f}x per solution"))
    return rows, t_ssik / per_pose


def feasible_ratio_rows(geometry: SRSGeometry, targets: list[np.ndarray], t_eight: float) -> list[tuple[str, str]]:
    """Each of :func:`feasible_calls` on the ssik poses (mean over them) over ssik's time for 8 IK solutions."""
    calls = [feasible_calls(geometry, target) for target in targets]
    rows = [("ssik's C++ time for 8 solutions (8 x its time per solution)", f"{t_eight * 1e6:9.1f} us")]
    for k, (name, _) in enumerate(calls[0]):
        t = float(np.mean([best_time_short_rounds(per_target[k][1]) for per_target in calls]))
        rows.append((f"iiwa14 one pose, {name.strip()}", f"{t * 1e6:9.1f} us: {t / t_eight:.2f}x ssik's 8 solutions"))
    return rows


def timed_solutions(
    chain: SerialChain, solve: Callable[[np.ndarray], np.ndarray], targets: np.ndarray
) -> tuple[float, int, int]:
    """Mean seconds per pose of ``solve(target)``, its solutions per pose, and how many of all pass our FK check."""
    seconds = float(np.mean([best_time_short_rounds(lambda: solve(target)) for target in targets]))
    solutions = [np.reshape(solve(target), (-1, chain.n)) for target in targets]
    counts = {len(q) for q in solutions}
    assert len(counts) == 1, f"solutions per pose differ: {sorted(counts)}"
    return seconds, counts.pop(), sum(passes(chain, q, target) for q, target in zip(solutions, targets))


if __name__ == "__main__":
    main()
