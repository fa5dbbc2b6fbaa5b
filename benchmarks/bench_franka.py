"""The Franka class (issue 24): IK at a given q7 and feasible q7 sets, beside frankik, GeoFIK and ssik 8.2.

Run: ``python benchmarks/bench_franka.py`` (``--quick``: every row on small sizes, about a minute).  Times are
the best of several rounds (the machine may be shared); the one-pose rows use rounds of about 10 ms for every
library.  Peers (optional, ``pip install -e ".[bench]"``): frankik 1.0.1 (He & Liu 2021, C++), geofikpy 0.0.4
(GeoFIK, C++) and ssik 8.2 (its prebuilt Panda, native C++); the script says so and skips a peer that is not
installed.  Prints one table.

Frames.  Every pose starts as the flange ``link8`` in ``link0``, the end frame of our ``franka-panda`` (Franka's
modified DH table), and is converted once, outside the timed region, into the frame each peer takes:

* frankik: ``ik_full`` takes the flange pose, while its ``fk`` returns the hand TCP;
* GeoFIK: the hand frame E (``panda_hand_tcp``) = flange turned by -pi/4 about z and moved 0.1034 m along it
  (:data:`HAND_IN_FLANGE`), position and row-first rotation as two lists of floats;
* ssik: ``panda_link8`` in ``panda_link0``, the flange.

:func:`frame_residuals` checks each of these claims by FK closure at start-up and the table prints the residuals.
All four use Franka's joint values, so every returned row is judged by our own forward kinematics
(``chain.fk``): a row passes when the norm of (position error in m, rotation error in rad) is at most 1e-9.

Each peer runs in its best documented configuration, named in its row; frankik and GeoFIK return only the
solutions inside their joint limits (NaN rows, or NaN joints in a row for GeoFIK, mark the others), redkin
returns every solution that exists, in or out of the limits.
"""

from __future__ import annotations

import argparse
import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import Any, NamedTuple

import numba
import numpy as np
from bench_srs import POSE_TOLERANCE, pose_errors  # the same FK check as the S-R-S benchmark
from timing import best_time, best_time_short_rounds  # benchmarks/timing.py (the script's folder is on sys.path)

from redkin import thread_count
from redkin.chain import SerialChain
from redkin.franka import feasible_q7, franka_geometry, ik
from redkin.models import get_robot

#: The hand frame E (``panda_hand_tcp``) in the flange frame ``link8``: -pi/4 about z, 0.1034 m along z (GeoFIK's
#: README, ``T8E``; frankik's ``fk`` returns the flange times this).
HAND_IN_FLANGE = np.array([
    [np.sqrt(0.5), np.sqrt(0.5), 0.0, 0.0],
    [-np.sqrt(0.5), np.sqrt(0.5), 0.0, 0.0],
    [0.0, 0.0, 1.0, 0.1034],
    [0.0, 0.0, 0.0, 1.0],
])
#: A returned row "is" a configuration q when every joint is within this of q's (angles compared modulo 2 pi).
JOINT_TOLERANCE = 1e-9
#: Half-width of the degenerate families: q2 near 0 (axes 1 and 3 aligned), q6 near 0 or pi (axes 5 and 7
#: parallel).
NEAR = 1e-6
#: Half-width of the constructed narrow arcs: every limit set this close around a known solution.
NARROW = 1e-4


@dataclass(frozen=True)
class Sizes:
    """How much each row computes; :data:`FULL` is issue 24's, :data:`QUICK` a minute's run."""

    one_pose: int  # poses of the one-pose rows (each timed at its own q7), mean over them
    batch: int  # poses of the batch row
    correctness: int  # random in-limit configurations of the completeness and wrong-row rows
    degenerate: int  # configurations of each degenerate family
    ssik_solve: int  # poses of ssik's solve(T) rows (about 0.2-12 ms each)
    feasible: int  # poses whose feasible sets are compared with dense sampling
    ssik_feasible: int  # of them, poses for ssik's in_limits() (about 26 ms each, 1.3 s to sample densely)
    samples: int  # q7 samples of the dense reference
    narrow: int  # constructed narrow arcs


FULL = Sizes(one_pose=100, batch=1_000_000, correctness=10_000, degenerate=1000, ssik_solve=200, feasible=1000,
             ssik_feasible=20, samples=100_000, narrow=100)
QUICK = Sizes(one_pose=10, batch=10_000, correctness=300, degenerate=50, ssik_solve=10, feasible=10, ssik_feasible=3,
              samples=10_000, narrow=10)

Row = tuple[str, str]


def main(argv: Sequence[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="small sizes: every row, in about a minute")
    rows = table(QUICK if parser.parse_args(argv).quick else FULL)
    width = max(len(r[0]) for r in rows)
    load = ", ".join(f"{v:.1f}" for v in os.getloadavg())
    header = (f"benchmark (franka-panda unless 'fr3:', numpy {np.__version__}, numba {numba.__version__}, redkin's "
              f"pool on {thread_count()} threads, load average {load})")
    print(f"{header:<{width}}  result")
    for name, value in rows:
        print(f"{name:<{width}}  {value}")


def table(sizes: Sizes) -> list[Row]:
    """Every row of the table, on the Panda: frames, one pose, the batch, correctness, feasible sets."""
    chain = get_robot("franka-panda")
    rng = np.random.default_rng(0)
    rows = frame_rows(chain, configurations(chain, 20, rng))
    solvers, skipped = at_q7_solvers(chain)
    rows += skipped + one_pose_rows(chain, solvers, configurations(chain, sizes.one_pose, rng), sizes.ssik_solve)
    rows += batch_rows(chain, configurations(chain, sizes.batch, rng))
    rows += correctness_rows(chain, solvers, rng, sizes)
    return rows + feasible_rows(chain, rng, sizes) + fr3_rows(rng, sizes)


def fr3_rows(rng: np.random.Generator, sizes: Sizes) -> list[Row]:
    """The FR3 (``franka-fr3``, franka_description's limits): redkin's one-pose and correctness rows and the
    feasible sets beside ssik's ``fr3`` charts under the same limits, on a tenth of the Panda's feasible poses.

    frankik's ``is_fr3`` and ssik's ``fr3_ik`` filter with other FR3 limits (q1 +-2.3093, ... in both), and GeoFIK
    knows only the Panda's, so no peer's IK at a given q7 is compared here.
    """
    chain = get_robot("franka-fr3")
    solver = redkin_at_q7(chain)
    q = configurations(chain, sizes.one_pose, rng)
    t = time_at_q7(chain, solver, chain.fk(q), q[:, 6])
    c = at_q7_correctness(chain, solver, configurations(chain, sizes.correctness, rng))
    rows = [
        (f"fr3: one pose, all solutions at q7: {solver.name}",
         f"{t.seconds * 1e6:9.2f} us per call, {t.solutions:.2f} solutions per call ({t.within_limits:.2f} in "
         f"limits), {t.per_solution * 1e6:.2f} us per solution ({len(q)} poses)"),
        (f"fr3: random in-limit q, own q7: {solver.name}",
         f"q found {c.found}/{sizes.correctness} (farthest {c.farthest:.1e} rad); wrong rows {c.wrong}/{c.rows} "
         f"(worst {c.worst:.1e})"),
    ]
    fewer = replace(sizes, feasible=max(1, sizes.feasible // 10), narrow=max(1, sizes.narrow // 10))
    return rows + feasible_rows(chain, rng, fewer, "fr3", "fr3: ")


# ------------------------------------------------------------------------------------------ poses and frames


def configurations(chain: SerialChain, count: int, rng: np.random.Generator, joint: int | None = None,
                   centre: float = 0.0) -> np.ndarray:
    """``count`` configurations uniform in the limits; with ``joint``, that joint within :data:`NEAR` of
    ``centre`` (q2 = 0: axes 1 and 3 aligned; q6 = 0 or pi: axes 5 and 7 parallel)."""
    q = rng.uniform(chain.lower, chain.upper, (count, chain.n))
    if joint is not None:
        q[:, joint] = centre + rng.uniform(-NEAR, NEAR, count)
    return q


def hand_poses(flange: np.ndarray) -> np.ndarray:
    """The hand frame E of frankik's ``fk`` and GeoFIK, from flange poses ``(..., 4, 4)``."""
    return flange @ HAND_IN_FLANGE


def frame_residuals(chain: SerialChain, q: np.ndarray) -> dict[str, float]:
    """Each peer's frame convention checked by FK closure on configurations ``q``.

    A peer's FK against our pose in its claimed frame (largest entry of the difference): frankik's ``fk`` and
    GeoFIK's ``franka_fk(q, "E")`` against the hand, ssik's ``panda_ik.fk`` against the flange.  A peer's IK,
    given the pose in its claimed frame at q's own q7: our FK of its rows against the flange (median of
    :func:`~bench_srs.pose_errors` over the rows: a wrong frame misses by centimetres, a rare wrong row near a
    singular configuration does not move the median).  A missing peer is left out.
    """
    flange = chain.fk(q)
    hand = hand_poses(flange)
    out: dict[str, float] = {}
    try:
        import frankik
    except ImportError:
        pass
    else:
        out["frankik fk = hand"] = max(float(np.abs(frankik.fk(qi) - h).max()) for qi, h in zip(q, hand))
        out["frankik ik_full(flange) rows, median"] = float(np.median(np.concatenate([
            pose_errors(chain, frankik_rows(frankik.ik_full(f, None, qi[6])), f) for qi, f in zip(q, flange)])))
    try:
        import geofikpy
    except ImportError:
        pass
    else:
        out["GeoFIK franka_fk(q, 'E') = hand"] = max(
            float(np.abs(np.asarray(geofikpy.franka_fk(qi, "E")) - h).max()) for qi, h in zip(q, hand))
        targets = geofik_targets(flange)
        out["GeoFIK franka_ik_q7(hand) rows, median"] = float(np.median(np.concatenate([
            pose_errors(chain, geofik_rows(geofikpy.franka_ik_q7(r, rotation, qi[6])), f)
            for qi, f, (r, rotation) in zip(q, flange, targets)])))
    try:
        from ssik.prebuilt.franka import panda_ik
    except ImportError:
        pass
    else:
        out["ssik panda_ik.fk = flange"] = max(float(np.abs(panda_ik.fk(qi) - f).max()) for qi, f in zip(q, flange))
    return out


def frame_rows(chain: SerialChain, q: np.ndarray) -> list[Row]:
    """The residuals of :func:`frame_residuals` as one row."""
    residuals = frame_residuals(chain, q)
    text = "; ".join(f"{name} {value:.1e}" for name, value in residuals.items()) or "no peer installed"
    return [(f"frames checked by FK closure ({len(q)} random q)", text)]


def wrapped_distance(rows: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Largest joint difference of each row from ``q``, angles compared modulo 2 pi."""
    return np.max(np.abs(np.mod(rows - q + np.pi, 2.0 * np.pi) - np.pi), axis=-1)


def nearest(rows: np.ndarray, q: np.ndarray) -> float:
    """:func:`wrapped_distance` of the nearest row (infinite when there is none)."""
    return float(wrapped_distance(rows, q).min()) if len(rows) else float("inf")


# ------------------------------------------------------------------------------------------ solvers at a given q7


class AtQ7(NamedTuple):
    """A solver of every solution of one pose at a given q7, in its own frame convention."""

    name: str
    configuration: str
    targets: Callable[[np.ndarray], list[Any]]  # flange poses (N, 4, 4) -> its own targets, converted once
    call: Callable[[Any, float], Any]  # the public call that is timed: (target, q7) -> its raw output
    rows: Callable[[Any], np.ndarray]  # raw output -> the returned solutions (k, 7), Franka's joint values


def frankik_rows(out: np.ndarray) -> np.ndarray:
    """frankik's ``ik_full`` output (4, 7): the rows without NaN."""
    return out[~np.isnan(out).any(axis=1)]


def geofik_targets(flange: np.ndarray) -> list[tuple[list[float], list[float]]]:
    """GeoFIK's inputs: the hand frame's position and row-first rotation, as lists of floats (pybind11 converts
    them faster than numpy arrays)."""
    return [(h[:3, 3].tolist(), h[:3, :3].ravel().tolist()) for h in hand_poses(flange)]


def geofik_rows(out: tuple[list[list[float]], int]) -> np.ndarray:
    """GeoFIK's ``(rows, count)``: the rows without NaN (a NaN joint is outside its limits, a NaN row no solution)."""
    rows = np.array(out[0])
    return rows[~np.isnan(rows).any(axis=1)]


def at_q7_solvers(chain: SerialChain) -> tuple[list[AtQ7], list[Row]]:
    """redkin (first) and the peers that are installed, and a row for each peer that is not."""
    solvers = [redkin_at_q7(chain)]
    skipped: list[Row] = []
    try:
        import frankik
    except ImportError as exc:
        skipped.append(("frankik ik_full", f"skipped: frankik not importable ({type(exc).__name__})"))
    else:
        solvers.append(AtQ7(
            f"frankik {frankik.__version__} ik_full", "ik_full(T_flange, None, q7) (C++; q_actual only picks q1 at "
            "q2 ~ 0); Panda limits", lambda poses: list(np.ascontiguousarray(poses)),
            lambda pose, q7: frankik.ik_full(pose, None, q7), frankik_rows))
    try:
        import geofikpy
    except ImportError as exc:
        skipped.append(("GeoFIK franka_ik_q7", f"skipped: geofikpy not importable ({type(exc).__name__})"))
    else:
        solvers.append(AtQ7(
            f"GeoFIK (geofikpy {geofikpy.__version__}) franka_ik_q7", "franka_ik_q7(r_E, R_E row-first, q7) (C++, "
            "q1_sing default); hand frame E", geofik_targets,
            lambda target, q7: geofikpy.franka_ik_q7(target[0], target[1], q7), geofik_rows))
    return solvers, skipped


def redkin_at_q7(chain: SerialChain) -> AtQ7:
    """redkin's ``ik`` on the chain's class geometry (derived once, cached on the chain): every branch that
    exists, in or out of the limits."""
    geometry = franka_geometry(chain)
    return AtQ7("redkin franka.ik", "ik(geometry, T_flange, q7): all 8 branches, public API with its checks",
                lambda poses: list(poses), lambda pose, q7: ik(geometry, pose, q7), lambda out: out.q[out.exists])


# ------------------------------------------------------------------------------------------ speed


class OnePose(NamedTuple):
    """Mean seconds per call, returned solutions per call and of them those within the chain's limits, of a solver
    over some poses at their own q7."""

    seconds: float
    solutions: float
    within_limits: float

    @property
    def per_solution(self) -> float:
        return self.seconds / max(self.solutions, 1e-300)


def time_at_q7(chain: SerialChain, solver: AtQ7, poses: np.ndarray, q7: np.ndarray) -> OnePose:
    """:class:`OnePose` of ``solver`` on ``poses`` (flange) at ``q7``, the targets converted beforehand."""
    pairs = list(zip(solver.targets(poses), q7.tolist()))
    seconds = best_time_short_rounds(lambda: [solver.call(target, value) for target, value in pairs]) / len(pairs)
    rows = [solver.rows(solver.call(target, value)) for target, value in pairs]
    return OnePose(seconds, float(np.mean([len(r) for r in rows])),
                   float(np.mean([np.sum(chain.within_limits(r)) for r in rows])))


def one_pose_rows(chain: SerialChain, solvers: list[AtQ7], q: np.ndarray, ssik_poses: int) -> list[Row]:
    """One pose, every solution at a given q7 (each pose at its own q7), per call and per returned solution; then
    ssik's ``solve(T)``, which picks q7 itself; then redkin's ratios to the peers."""
    poses = chain.fk(q)
    times = {solver.name: time_at_q7(chain, solver, poses, q[:, 6]) for solver in solvers}
    rows: list[Row] = []
    for solver in solvers:
        t = times[solver.name]
        rows.append((f"one pose, all solutions at q7: {solver.name}",
                     f"{t.seconds * 1e6:9.2f} us per call, {t.solutions:.2f} solutions per call "
                     f"({t.within_limits:.2f} in limits), "
                     f"{t.per_solution * 1e6:.2f} us per solution ({len(q)} poses)"))
        rows.append(("  configuration", solver.configuration))
    rows += ssik_solve_rows(chain, poses[:ssik_poses])
    ours = times[solvers[0].name]
    for solver in solvers[1:]:
        t = times[solver.name]
        rows.append((f"  redkin / {solver.name}", f"{ours.seconds / t.seconds:9.2f}x the time per call, "
                     f"{ours.per_solution / t.per_solution:.2f}x per returned solution"))
    return rows


def ssik_solve() -> Callable[[np.ndarray], list[Any]] | None:
    """ssik's Panda solver ``panda_ik.solve`` (flange poses), or None when ssik is not installed."""
    try:
        from ssik.prebuilt.franka import panda_ik
    except ImportError:
        return None
    return panda_ik.solve


def ssik_rows(solve: Callable[[np.ndarray], list[Any]], pose: np.ndarray) -> np.ndarray:
    """The joint vectors ``(k, 7)`` of ssik's ``Solution`` objects for ``pose``."""
    return np.array([solution.q for solution in solve(pose)]).reshape(-1, 7)


def ssik_solve_rows(chain: SerialChain, poses: np.ndarray) -> list[Row]:
    """ssik's Panda solver ``panda_ik.solve(T)`` (native C++, its defaults), which chooses q7 itself."""
    solve = ssik_solve()
    if solve is None:
        return [("ssik panda_ik.solve", "skipped: ssik not importable")]
    seconds = float(np.mean([best_time(lambda: solve(pose), repeat=3) for pose in poses]))
    solutions = [ssik_rows(solve, pose) for pose in poses]
    total = sum(len(s) for s in solutions)
    passed = sum(int(np.sum(pose_errors(chain, s, pose) <= POSE_TOLERANCE)) for s, pose in zip(solutions, poses))
    return [
        ("one pose, ssik panda_ik.solve(T), q7 its own",
         f"{seconds * 1e6:9.1f} us per call, {total / len(poses):.1f} solutions per call, "
         f"{seconds * len(poses) / max(total, 1) * 1e6:.2f} us per solution ({passed}/{total} pass at 1e-9; "
         f"{len(poses)} poses)"),
        ("  configuration", "solve(T_flange) with its defaults (native, respect_limits=True, rescue): one solution "
                            "per branch and in-limit q7 arc, q7 chosen by ssik; no call at a given q7"),
    ]


def batch_rows(chain: SerialChain, q: np.ndarray) -> list[Row]:
    """A batch of poses, each at its own q7, in one call of redkin's ``ik`` (the peers have no batch call: their
    one-pose rows give their rate on one thread)."""
    geometry = franka_geometry(chain)
    poses = chain.fk(q)
    t = best_time(lambda: ik(geometry, poses, q[:, 6]), repeat=3)
    solutions = ik(geometry, poses, q[:, 6])
    return [(f"batch {len(q):,} poses at their q7: redkin franka.ik".replace(",", " "),
             f"{int(solutions.exists.sum()) / t:9.3g} solutions/s ({8 * len(q) / t:.3g} branch slots/s, "
             f"{int(solutions.within_limits.sum()) / t:.3g} in limits/s; {thread_count()} threads)")]


# ------------------------------------------------------------------------------------------ correctness


class Correctness(NamedTuple):
    """Returned rows, rows that miss their pose by more than 1e-9 (and the worst miss), configurations found, and
    the largest distance of a configuration from the nearest row (infinite when a pose got no row)."""

    rows: int
    wrong: int
    worst: float
    found: int
    farthest: float


def at_q7_correctness(chain: SerialChain, solver: AtQ7, q: np.ndarray) -> Correctness:
    """Each configuration's pose solved at the configuration's own q7: the rows checked by our FK, and whether
    the configuration is among them (:data:`JOINT_TOLERANCE`)."""
    poses = chain.fk(q)
    rows = wrong = found = 0
    worst = farthest = 0.0
    for target, pose, qi in zip(solver.targets(poses), poses, q):
        solutions = solver.rows(solver.call(target, float(qi[6])))
        rows += len(solutions)
        distance = nearest(solutions, qi)
        found += distance <= JOINT_TOLERANCE
        farthest = max(farthest, distance)
        if len(solutions):
            errors = pose_errors(chain, solutions, pose)
            wrong += int(np.sum(errors > POSE_TOLERANCE))
            worst = max(worst, float(errors.max()))
    return Correctness(rows, wrong, worst, found, farthest)


#: The families of configurations of the correctness rows: (label, joint held near a value, the value).
FAMILIES = (
    ("random in-limit q", None, 0.0),
    ("|q2| <= 1e-6 (axes 1, 3 aligned)", 1, 0.0),
    ("|q6| <= 1e-6 (axes 5, 7 parallel)", 5, 0.0),
    ("|q6 - pi| <= 1e-6 (axes 5, 7 parallel)", 5, np.pi),
)


def correctness_rows(chain: SerialChain, solvers: list[AtQ7], rng: np.random.Generator, sizes: Sizes) -> list[Row]:
    """Completeness and wrong rows of every solver at a given q7, on random and degenerate configurations."""
    rows: list[Row] = []
    solve = ssik_solve()
    for label, joint, centre in FAMILIES:
        count = sizes.correctness if joint is None else sizes.degenerate
        q = configurations(chain, count, rng, joint, centre)
        for solver in solvers:
            c = at_q7_correctness(chain, solver, q)
            rows.append((f"{label}, own q7: {solver.name}",
                         f"q found {c.found}/{count} ({100 * c.found / count:.1f} %, farthest {c.farthest:.1e} rad); "
                         f"wrong rows {c.wrong}/{c.rows} (worst {c.worst:.1e})"))
        if solve is not None:
            poses = chain.fk(q[: sizes.ssik_solve])
            errors = np.concatenate([pose_errors(chain, ssik_rows(solve, pose), pose) for pose in poses])
            rows.append((f"{label}: ssik panda_ik.solve(T), q7 its own",
                         f"wrong rows {int(np.sum(errors > POSE_TOLERANCE))}/{len(errors)} (worst {errors.max():.1e};"
                         f" {len(poses)} poses)"))
    return rows


# ------------------------------------------------------------------------------------------ feasible q7 sets


def membership(arcs: Sequence[tuple[float, float]], t: np.ndarray) -> np.ndarray:
    """Whether each ``t`` lies in one of the closed ``arcs``."""
    ends = np.asarray(arcs, dtype=float).reshape(-1, 2)
    return np.any((t[:, None] >= ends[:, 0]) & (t[:, None] <= ends[:, 1]), axis=1)


def disagreements(arcs: Sequence[tuple[float, float]], inside: np.ndarray, t: np.ndarray,
                  margin: float = JOINT_TOLERANCE) -> int:
    """Samples ``t`` where the ``arcs`` and a dense mask ``inside`` disagree, farther than ``margin`` from every
    endpoint (so a missed or extra arc counts, a boundary located to ``margin`` does not)."""
    ends = np.asarray(arcs, dtype=float).ravel()
    far = np.min(np.abs(t[:, None] - ends), axis=1) > margin if ends.size else np.ones(t.shape, bool)
    return int(np.sum((membership(arcs, t) != inside) & far))


def count_disagreements(first: Sequence[Sequence[tuple[float, float]]],
                        second: Sequence[Sequence[tuple[float, float]]], t: np.ndarray,
                        margin: float = JOINT_TOLERANCE) -> int:
    """Samples ``t`` where two libraries' sets (lists of arcs per branch, branches labelled differently) contain
    ``t`` on different numbers of branches, farther than ``margin`` from every endpoint of both."""
    counts = [sum(membership(arcs, t).astype(int) for arcs in sets) for sets in (first, second)]
    ends = np.array([e for sets in (first, second) for arcs in sets for arc in arcs for e in arc])
    far = np.min(np.abs(t[:, None] - ends), axis=1) > margin if ends.size else np.ones(t.shape, bool)
    return int(np.sum((counts[0] != counts[1]) & far))


def in_limits_mask(chain: SerialChain, q: np.ndarray, exists: np.ndarray) -> np.ndarray:
    """Rows ``q (..., 7)`` that exist and lie in the limits (an angle counts when some turn of it does)."""
    return exists & chain.within_limits(np.where(exists[..., None], q, 0.0), wrap=True)


def ssik_arm(name: str) -> Any:
    """ssik's prebuilt arm ``name`` (``"panda"``, ``"fr3"``) as a ``Manipulator`` (its documented route to the
    charts), or None."""
    try:
        import ssik
    except ImportError:
        return None
    return ssik.Manipulator.from_prebuilt(name)


def ssik_sets(arm: Any, pose: np.ndarray, limits: np.ndarray) -> list[tuple[tuple[float, float], ...]]:
    """ssik's feasible q7 arcs under ``limits (7, 2)`` of every chart of ``pose`` (``chart.in_limits(limits)``),
    the manifold built from scratch."""
    return [chart.in_limits(limits) for chart in arm.self_motion(pose).charts]


def ssik_dense(arm: Any, chain: SerialChain, pose: np.ndarray, t: np.ndarray) -> tuple[list[Any], np.ndarray]:
    """ssik's arcs of ``pose`` under the chain's limits and its own charts ``q(t)`` sampled at ``t``, in those
    limits by our check: (arcs, mask (charts, M))."""
    charts = arm.self_motion(pose).charts
    inside = []
    for chart in charts:
        q = chart.q(t)
        inside.append(in_limits_mask(chain, q, ~np.isnan(q).any(axis=1)))
    return [chart.in_limits(chain.limits) for chart in charts], np.array(inside).reshape(len(charts), len(t))


def narrow_found(q: np.ndarray, sets: Sequence[Sequence[tuple[float, float]]]) -> bool:
    """Whether some branch's arcs contain q's q7 (to :data:`JOINT_TOLERANCE`)."""
    return any(lo - JOINT_TOLERANCE <= q[6] <= hi + JOINT_TOLERANCE for arcs in sets for lo, hi in arcs)


def redkin_sets(chain: SerialChain, pose: np.ndarray) -> tuple[np.ndarray, ...]:
    """redkin's feasible q7 arcs ``(K, 2)`` of every branch of ``pose`` (``feasible_q7`` on the chain's class)."""
    return feasible_q7(franka_geometry(chain), pose).arcs


def redkin_dense(chain: SerialChain, pose: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Dense reference of redkin's sets: its solutions of ``pose`` at every ``t`` that exist and lie in the
    limits, by our own check (:func:`in_limits_mask`), shape ``(8, M)``."""
    solutions = ik(franka_geometry(chain), pose, t)
    return in_limits_mask(chain, solutions.q, solutions.exists).T


def feasible_rows(chain: SerialChain, rng: np.random.Generator, sizes: Sizes, ssik_name: str = "panda",
                  prefix: str = "") -> list[Row]:
    """One pose's feasible q7 sets of every branch: time (redkin ``feasible_q7``, ssik ``in_limits()`` of its arm
    ``ssik_name`` under the chain's limits, on the same poses), each against dense sampling of q7, the two against
    each other, and narrow arcs; ``prefix`` starts each row's label."""
    q = configurations(chain, sizes.feasible, rng)
    poses = chain.fk(q)
    few = poses[: sizes.ssik_feasible]
    t = np.linspace(chain.lower[6], chain.upper[6], sizes.samples)
    samples = f"{len(t):,} q7 samples".replace(",", " ")
    narrow = configurations(chain, sizes.narrow, rng)
    geometry = franka_geometry(chain)
    ours = float(np.mean([best_time_short_rounds(lambda: feasible_q7(geometry, pose)) for pose in few]))
    rows = [(f"{prefix}one pose, feasible q7 sets of all 8 branches: redkin feasible_q7 ({len(few)} poses)",
             f"{ours * 1e6:9.2f} us per pose"),
            ("  configuration", "feasible_q7(geometry, T_flange), public API with its checks")]
    branches = sum(disagreements(arcs, inside, t) > 0 for pose in poses
                   for arcs, inside in zip(redkin_sets(chain, pose), redkin_dense(chain, pose, t)))
    rows.append((f"  redkin sets vs its IK at {samples}, limits by our check",
                 f"{branches} of {8 * len(poses)} pose-branches disagree ({len(poses)} poses)"))
    found = sum(narrow_found(qi, redkin_sets(chain.with_limits(qi - NARROW, qi + NARROW), chain.fk(qi)))
                for qi in narrow)
    rows.append((f"  redkin: limits +-{NARROW:g} rad around a known solution", f"arc found {found}/{len(narrow)}"))
    arm = ssik_arm(ssik_name)
    if arm is None:
        rows.append((f"{prefix}ssik chart.in_limits()", "skipped: ssik not importable"))
    else:
        theirs = float(np.mean([best_time(lambda: ssik_sets(arm, pose, chain.limits), repeat=3) for pose in few]))
        rows.append((f"{prefix}one pose, feasible q7 sets of every chart: ssik in_limits() ({len(few)} poses)",
                     f"{theirs * 1e3:9.2f} ms per pose"))
        rows.append(("  configuration", f"[c.in_limits(limits) for c in Manipulator.from_prebuilt({ssik_name!r})"
                                        ".self_motion(T).charts], limits the chain's (native C++ charts, a fresh "
                                        "manifold per pose)"))
        bad = 0
        for pose in few:
            arcs, inside = ssik_dense(arm, chain, pose, t)
            bad += sum(disagreements(a, m, t) > 0 for a, m in zip(arcs, inside))
        rows.append((f"  ssik arcs vs its own q(t) at {samples}", f"{bad} charts disagree ({len(few)} poses)"))
        found = sum(narrow_found(qi, ssik_sets(arm, chain.fk(qi), np.stack([qi - NARROW, qi + NARROW], axis=1)))
                    for qi in narrow)
        rows.append((f"  ssik: limits +-{NARROW:g} rad around a known solution", f"arc found {found}/{len(narrow)}"))
        apart = sum(count_disagreements(redkin_sets(chain, pose), ssik_sets(arm, pose, chain.limits), t) > 0
                    for pose in few)
        rows.append(("  redkin / ssik in_limits(), same poses",
                     f"{ours / theirs:9.4f}x the time; sets differ on {apart}/{len(few)} poses (branches "
                     f"containing each of {samples})"))
    return rows


if __name__ == "__main__":
    main()
