"""Issue 40: certified collision-free arm angles (``redkin.collision.collision_free_arm_angles``) beside what a user
would write without them: sample the arm angle densely and check each configuration with coal.

Run: ``python benchmarks/collision_free.py`` (about 2 minutes on 2 cores); ``--quick`` (about 30 s: 6 poses, one of
them sampled and timed, 4 checked, a 100-waypoint path); ``--poses N`` (20), ``--sampled K`` (3: poses timed with
sampling, the first K), ``--samples M`` (10^4 arm angles per pose), ``--checked J`` (20: poses whose samples are
checked against our sets, the first J; the timed ones are among them), ``--path W`` (1000: waypoints of the path
timed in the cell, :func:`time_path`; 0 for none).

The setup.  ``redkin.arm("kuka-iiwa14")`` (DH frames: the shoulder at frame 1 and 2's origin, 0.36 m up; the
elbow at frame 3 and 4's, 0.42 m further; the wrist at frame 5 and 6's, 0.40 m further; the flange 0.126 m beyond
it on frame 7).  Its body is seven capsules, one per moving link frame 1..7 (:func:`iiwa_body`), and no
self-collision pairs (every link pair ignored), so that ours and coal check the same 70 capsule-obstacle pairs.
The scene is ten primitives around the workspace (:func:`cell`): the floor (a plane through the base, solid
below), four boxes, three capsules and two spheres, margin 0.01 m.  Poses: the FK of 20 configurations drawn
uniformly within the limits (``numpy.random.default_rng(40)``), kept when that configuration's own body clears
the scene by the margin (so each pose has a free arm angle on its own branch; drawn ones that collide are
redrawn).

Ours: ``collision_free_arm_angles(arm, pose, body, scene)``, all eight branches, resolution 1e-6 rad; per pose the
best of 3 calls after a warm-up call (:func:`timing.best_time`), then the median and quartiles over the poses, and
the configurations it evaluated per call.

Sampled: for one pose, ``M = 10^4`` arm angles evenly spaced on the circle, the eight branches' joint values by one
batched ``arm.ik(pose, psi)``, the frames of the configurations within the limits by one batched
``arm.chain.frames``, and each configuration checked with coal 3.0 against the scene.  coal objects are built once
(``coal.Capsule(radius, length)`` along z: coal 3.0's second argument is the whole length of the segment, its
``halfLength`` is half of it; ``coal.Box`` by its edge lengths, ``coal.Sphere``, ``coal.Halfspace`` for the
floor); per configuration each link capsule's transform is set (the link frame times a fixed offset, computed for
all configurations at once with numpy) and then, two ways (the faster is the one compared):

* ``broadphase collide``: a ``coal.DynamicAABBTreeCollisionManager`` of the obstacles against one of the link
  capsules (``computeAABB``, ``update``), ``collide`` with a ``CollisionCallBackDefault`` whose request's
  ``security_margin`` is the margin: coal's documented configuration for many objects; a yes/no per configuration.
* ``pairwise distance``: one ``coal.ComputeDistance`` functor per capsule-obstacle pair built once, one
  ``DistanceRequest`` and ``DistanceResult`` reused (cleared before each pair); the least distance per
  configuration.  This is also the check of our sets below.

coal's broadphase ``distance`` (a ``DistanceCallBackDefault``) is not used: in coal 3.0 the closed-form shape pairs
(capsule-sphere, capsule-capsule, capsule-halfspace) overwrite the result's minimum instead of merging it, so the
query returns the last pair evaluated, not the closest (coal-library/coal PR #885, open).  The script measures that
on the first sampled pose and prints it.

Agreement, on the first ``--checked`` poses (the coal distances of the sampled poses reused): every sample within
the limits (``Solutions.within_limits``) that our free set contains must be clear in coal's pairwise distance
(least distance >= margin - 1e-9 m); and the samples that coal finds clear (>= margin + 1e-6 m) but our sets leave
out are counted, split by whether they lie within 1e-5 rad of one of our free arcs' ends (the ends are located to
the resolution, 1e-6 rad; a stretch narrower than the resolution or one whose clearance only grazes the margin may
be left out) or farther (should be 0).  Each flagged sample is printed with coal's distance again at
``gjk_tolerance`` 1e-12 and redkin's own signed distance.

A path in the cell (:func:`time_path`): ``resolve_path`` with the same body and scene along ``W`` poses of a
straight joint-space line whose configurations all clear the cell (:func:`clear_line`), step bound 0.2 rad.

Targets (issue 40): ours <= 0.5 ms per pose for all eight branches, >= 100 x faster than sampling, and a
1000-waypoint path in <= 0.5 s.  Times are
per call on a possibly shared machine: the load average is printed at the start and the end.
"""

from __future__ import annotations

import argparse
import time
from typing import Any, NamedTuple

import numpy as np
from timing import best_time, load_average, machine_lines  # benchmarks/timing.py (the script's folder is on sys.path)

import redkin
from redkin.arms.feasible_sets import Arcs
from redkin.arms.front_door import Arm
from redkin.chain import SerialChain
from redkin.collision import (
    BOX,
    CAPSULE,
    SPHERE,
    Body,
    BodyCapsule,
    FreeArmAngles,
    Scene,
    body_of,
    collision_free_arm_angles,
    free_arm_angles_of,
    posed,
    primitives,
    signed_distance,
)
from redkin.paths import resolve_path

#: Issue 40's targets: ours per pose, all 8 branches [s]; sampled / ours at least; a 1000-waypoint path [s].
TARGET_SECONDS, TARGET_RATIO, TARGET_PATH_SECONDS = 0.5e-3, 100.0, 0.5
#: The agreement thresholds [m] and the distance from our arc ends within which a left-out clear sample is expected.
INSIDE_SLACK, CLEAR_BY, NEAR_END = 1e-9, 1e-6, 1e-5
MARGIN = 0.01


def iiwa_body(chain: SerialChain) -> Body:
    """Seven capsules, one per moving link frame 1..7 of the iiwa14's DH chain, without self-collision pairs.

    APPROXIMATIONS FOR TIMING ONLY, not KUKA's geometry: each capsule runs along the arm's centre line between
    points placed by the zero configuration's frames (straight up: link 1 from z = 0.2 to the shoulder at 0.36 m,
    link 2 to 0.56, link 3 to the elbow at 0.78, link 4 to 0.98, link 5 to the wrist at 1.18, link 6 to 1.26,
    link 7 to the flange at 1.306), radii 0.08 to 0.05 m; the real links' offsets and bulges are left out.
    """
    capsules = [
        BodyCapsule("link 1", 1, [0, 0.16, 0], [0, 0, 0], 0.08),  # frame 1's y points down link 1
        BodyCapsule("link 2", 2, [0, 0, 0], [0, 0, 0.2], 0.08),
        BodyCapsule("link 3", 3, [0, 0.22, 0], [0, 0, 0], 0.07),
        BodyCapsule("link 4", 4, [0, 0, 0], [0, 0, 0.2], 0.07),
        BodyCapsule("link 5", 5, [0, 0.2, 0], [0, 0, 0], 0.065),
        BodyCapsule("link 6", 6, [0, 0, 0], [0, 0, 0.08], 0.06),
        BodyCapsule("link 7", 7, [0, 0, -0.046], [0, 0, 0], 0.05),
    ]
    links = [capsule.link for capsule in capsules]
    every_pair = [(first, second) for i, first in enumerate(links) for second in links[i + 1:]]
    body = body_of(capsules, chain, ignore=every_pair, notes=("approximate capsules for timing only",),
                   source="benchmarks/collision_free.py")
    assert len(body.pairs) == 0
    return body


def cell() -> Scene:
    """Ten obstacles around the iiwa14's workspace (base frame, metres), placed so that on most poses some arm
    angles are blocked and some free."""
    c, s = np.cos(0.4), np.sin(0.4)
    return Scene(
        ("floor", "table", "wall", "shelf", "crate", "post", "post 2", "bar", "lamp", "ball"),
        np.stack([
            primitives.plane([0, 0, 0], [0, 0, 1]),
            primitives.box([0.55, 0.0, 0.3], [0.4, 1.0, 0.06]),
            primitives.box([-0.45, 0.0, 0.8], [0.06, 1.4, 1.2]),
            primitives.box([0.1, 0.5, 0.9], [0.5, 0.25, 0.04], [[c, -s, 0], [s, c, 0], [0, 0, 1]]),
            primitives.box([0.0, -0.45, 0.25], [0.3, 0.3, 0.5]),
            primitives.capsule([0.35, 0.35, 0.0], [0.35, 0.35, 1.3], 0.04),
            primitives.capsule([-0.3, -0.35, 0.0], [-0.3, -0.35, 1.4], 0.05),
            primitives.capsule([0.4, -0.5, 1.1], [0.4, 0.5, 1.1], 0.03),
            primitives.sphere([0.3, -0.3, 0.85], 0.1),
            primitives.sphere([-0.25, 0.3, 0.6], 0.08),
        ]),
        MARGIN,
    )


def draw_poses(arm: Arm, body: Body, scene: Scene, count: int, seed: int = 40) -> np.ndarray:
    """``count`` poses: FK of configurations uniform within the limits whose own body clears the scene."""
    chain, rng, kept = arm.chain, np.random.default_rng(seed), []
    while len(kept) < count:
        q = rng.uniform(chain.lower, chain.upper)
        shapes = posed(body, chain.frames(q))
        if signed_distance(shapes[:, None], scene.shapes[None]).distance.min() >= scene.margin:
            kept.append(q)
    return chain.fk(np.array(kept))


def clear_line(arm: Arm, body: Body, scene: Scene, count: int, seed: int = 3) -> np.ndarray:
    """``count`` poses along a straight line in joint space between two configurations drawn within 0.8 of each
    joint's limits, redrawn until every configuration of the line clears the scene by the margin plus 0.02 m."""
    chain, rng = arm.chain, np.random.default_rng(seed)
    while True:
        first, last = rng.uniform(chain.lower * 0.8, chain.upper * 0.8, size=(2, chain.n))
        q = first + np.linspace(0.0, 1.0, count)[:, None] * (last - first)
        shapes = posed(body, chain.frames(q))
        least = signed_distance(shapes[:, :, None], scene.shapes[None, None]).distance.min(axis=(1, 2))
        if np.all(least >= scene.margin + 0.02):
            return chain.fk(q)


def time_path(arm: Arm, body: Body, scene: Scene, count: int) -> float:
    """Seconds of one ``resolve_path`` in the cell along :func:`clear_line`'s ``count`` poses (step 0.2 rad; after a
    50-waypoint warm-up), printed."""
    poses = clear_line(arm, body, scene, count)
    resolve_path(arm, poses[:50], 0.2, body=body, scene=scene)
    start = time.perf_counter()
    found = resolve_path(arm, poses, 0.2, body=body, scene=scene)
    seconds = time.perf_counter() - start
    print(f"   a path of {count} waypoints in the cell (resolve_path, step 0.2 rad, along a joint-space line whose "
          f"configurations clear the cell by 2 cm more than the margin): {seconds:.2f} s, {found.status}")
    return seconds


# ------------------------------------------------------------------------------------------------------------ coal
def _along(direction: np.ndarray) -> np.ndarray:
    """A rotation whose z column is ``direction`` (a capsule's axis in coal)."""
    z = direction / np.linalg.norm(direction)
    x = np.cross(z, (1.0, 0.0, 0.0) if abs(z[0]) < 0.9 else (0.0, 1.0, 0.0))
    x /= np.linalg.norm(x)
    return np.column_stack([x, np.cross(z, x), z])


class CoalCell:
    """The scene and the body's capsules as coal objects, built once; the checks of many configurations."""

    def __init__(self, coal: Any, body: Body, scene: Scene) -> None:
        self.coal, self.body, self.margin = coal, body, scene.margin
        self.obstacles = [self._obstacle(row) for row in scene.shapes]
        self.links = [coal.CollisionObject(coal.Capsule(float(r), float(np.linalg.norm(b - a))))
                      for a, b, r in zip(body.a, body.b, body.radius)]
        offsets = np.tile(np.eye(4), (len(body), 1, 1))  # link frame -> the capsule's coal frame (centre, z along)
        for i, (a, b) in enumerate(zip(body.a, body.b)):
            offsets[i, :3, :3], offsets[i, :3, 3] = _along(b - a), (a + b) / 2.0
        self.offsets = offsets
        self.functors = [[coal.ComputeDistance(link.collisionGeometry(), obstacle.collisionGeometry())
                          for obstacle in self.obstacles] for link in self.links]
        self.placed = [obstacle.getTransform() for obstacle in self.obstacles]

    def _obstacle(self, row: np.ndarray) -> Any:
        coal = self.coal
        kind, radius, p, q = row[0], float(row[1]), row[2:5], row[5:8]
        if kind == SPHERE:
            return coal.CollisionObject(coal.Sphere(radius), coal.Transform3s(np.eye(3), p))
        if kind == CAPSULE:
            return coal.CollisionObject(coal.Capsule(radius, float(np.linalg.norm(q - p))),
                                        coal.Transform3s(_along(q - p), (p + q) / 2.0))
        if kind == BOX:
            return coal.CollisionObject(coal.Box(*(2.0 * q)), coal.Transform3s(row[8:17].reshape(3, 3), p))
        return coal.CollisionObject(coal.Halfspace(q, float(q @ p)), coal.Transform3s())

    def transforms(self, frames: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Rotations ``(N, M, 3, 3)`` and translations ``(N, M, 3)`` of the link capsules at chain frames ``(N, n + 2,
        4, 4)``."""
        placed = frames[:, self.body.frame] @ self.offsets
        return np.ascontiguousarray(placed[..., :3, :3]), np.ascontiguousarray(placed[..., :3, 3])

    def least_distances(self, frames: np.ndarray, request: Any = None) -> np.ndarray:
        """Per configuration, the least distance over every capsule-obstacle pair (pairwise, reused request and
        result)."""
        coal = self.coal
        turns, shifts = self.transforms(frames)
        request = coal.DistanceRequest() if request is None else request
        result = coal.DistanceResult()
        least = np.empty(len(frames))
        for k in range(len(frames)):
            best = np.inf
            for turn, shift, functors in zip(turns[k], shifts[k], self.functors):
                pose = coal.Transform3s(turn, shift)
                for functor, placed in zip(functors, self.placed):
                    result.clear()
                    distance = functor(pose, placed, request, result)
                    if distance < best:
                        best = distance
            least[k] = best
        return least

    def _managers(self) -> tuple[Any, Any]:
        coal = self.coal
        obstacles, links = coal.DynamicAABBTreeCollisionManager(), coal.DynamicAABBTreeCollisionManager()
        for obstacle in self.obstacles:
            obstacles.registerObject(obstacle)
        for link in self.links:
            links.registerObject(link)
        obstacles.setup()
        links.setup()
        return obstacles, links

    def collide(self, frames: np.ndarray) -> np.ndarray:
        """Per configuration, whether some capsule is closer than the margin to some obstacle (broadphase)."""
        coal = self.coal
        turns, shifts = self.transforms(frames)
        obstacles, links = self._managers()
        hit = np.empty(len(frames), dtype=bool)
        for k in range(len(frames)):
            for turn, shift, link in zip(turns[k], shifts[k], self.links):
                link.setTransform(coal.Transform3s(turn, shift))
                link.computeAABB()
            links.update()
            callback = coal.CollisionCallBackDefault()
            callback.data.request.security_margin = self.margin
            obstacles.collide(links, callback)
            hit[k] = callback.data.result.isCollision()
        return hit

    def broadphase_distances(self, frames: np.ndarray) -> np.ndarray:
        """Per configuration, the broadphase ``distance`` with a ``DistanceCallBackDefault`` (wrong in coal 3.0,
        module docstring)."""
        coal = self.coal
        turns, shifts = self.transforms(frames)
        obstacles, links = self._managers()
        least = np.empty(len(frames))
        for k in range(len(frames)):
            for turn, shift, link in zip(turns[k], shifts[k], self.links):
                link.setTransform(coal.Transform3s(turn, shift))
                link.computeAABB()
            links.update()
            callback = coal.DistanceCallBackDefault()
            obstacles.distance(links, callback)
            least[k] = callback.data.result.min_distance
        return least


# --------------------------------------------------------------------------------------------------------- sampled
class Sampled(NamedTuple):
    """One pose's samples: arm angles ``(M,)``, which rows are within the limits ``(M, 8)``, the joint values of
    those ``(K, 7)``, their chain frames, and the seconds of IK and frames together."""

    psi: np.ndarray
    within: np.ndarray
    q: np.ndarray
    frames: np.ndarray
    seconds: float


def sample(arm: Arm, pose: np.ndarray, count: int) -> Sampled:
    """``count`` arm angles evenly spaced on the circle, all eight branches in one ``arm.ik`` call, and the frames of
    the configurations within the limits in one ``chain.frames`` call."""
    psi = -np.pi + 2.0 * np.pi * np.arange(count) / count
    start = time.perf_counter()
    solutions = arm.ik(pose, psi)
    within = solutions.within_limits
    q = solutions.q[within]
    frames = arm.chain.frames(q)
    return Sampled(psi, within, q, frames, time.perf_counter() - start)


def _inside(arcs: Arcs, psi: np.ndarray) -> np.ndarray:
    inside = np.zeros(psi.shape, dtype=bool)
    for (lo, hi), wraps in zip(arcs.bounds, arcs.wraps):
        inside |= ((psi >= lo) | (psi <= hi)) if wraps else ((psi >= lo) & (psi <= hi))
    return inside


def _to_ends(arcs: Arcs, psi: np.ndarray) -> np.ndarray:
    """Distance [rad] on the circle from each ``psi`` to the nearest end of ``arcs`` (inf without arcs)."""
    ends = arcs.bounds.ravel()
    if not len(ends):
        return np.full(psi.shape, np.inf)
    gap = np.abs((psi[:, None] - ends[None, :] + np.pi) % (2.0 * np.pi) - np.pi)
    return gap.min(axis=1)


class Agreement(NamedTuple):
    within: int  # samples (arm angle x branch) within the limits
    ours: int  # of those, in our free sets
    clear: int  # coal: least distance >= margin + CLEAR_BY
    grazing: int  # in our sets, coal's least distance within [margin - INSIDE_SLACK, margin + CLEAR_BY)
    false_free: int  # in our sets, coal closer than margin - INSIDE_SLACK
    missed_near: int  # coal clear, left out, within NEAR_END of one of our free arcs' ends
    missed_far: int  # coal clear, left out, farther
    outside_limits: int  # in our sets but not within the limits by arm.ik
    flagged: list[str]


def agree(arm: Arm, pose_index: int, result: FreeArmAngles, sampled: Sampled, least: np.ndarray, coal_cell: CoalCell,
          body: Body, scene: Scene) -> Agreement:
    """Compare our free sets with coal's least distances at the samples (module docstring)."""
    margin = scene.margin
    rows, columns = np.nonzero(sampled.within)  # the order of sampled.q
    psi = sampled.psi[rows]
    inside = np.zeros(len(rows), dtype=bool)
    near_end = np.zeros(len(rows), dtype=bool)
    outside_limits = 0
    for b, label in enumerate(result.branches):
        mine = columns == arm.branches.index(label)
        inside[mine] = _inside(result.free[b], psi[mine])
        near_end[mine] = _to_ends(result.free[b], psi[mine]) <= NEAR_END
        row_of_branch = arm.branches.index(label)
        outside_limits += int(np.sum(_inside(result.free[b], sampled.psi) & ~sampled.within[:, row_of_branch]))
    false_free = inside & (least < margin - INSIDE_SLACK)
    clear = least >= margin + CLEAR_BY
    missed = clear & ~inside
    flagged = []
    for k in np.nonzero(false_free | (missed & ~near_end))[0][:10].tolist():
        tight = coal_cell.coal.DistanceRequest()
        tight.gjk_tolerance = 1e-12
        again = coal_cell.least_distances(sampled.frames[k:k + 1], tight)[0]
        shapes = posed(body, sampled.frames[k])
        ours = signed_distance(shapes[:, None], scene.shapes[None]).distance.min()
        b = result.branches.index(arm.branches[columns[k]])
        kind = "in our set, coal not clear" if false_free[k] else "coal clear, left out"
        flagged.append(f"pose {pose_index} branch {arm.branches[columns[k]]} psi {psi[k]!r}: {kind}; least distance "
                       f"coal {least[k]:.9g}, coal gjk 1e-12 {again:.9g}, redkin {ours:.9g} (margin {margin}); "
                       f"nearest free-arc end {_to_ends(result.free[b], psi[k:k + 1])[0]:.3g} rad; "
                       f"q {np.array2string(sampled.q[k], precision=17, separator=', ')}")
    return Agreement(len(rows), int(inside.sum()), int(clear.sum()), int(np.sum(inside & ~false_free & ~clear)),
                     int(false_free.sum()),
                     int(np.sum(missed & near_end)), int(np.sum(missed & ~near_end)), outside_limits, flagged)


# ------------------------------------------------------------------------------------------------------------ main
def _quartiles(values: list[float]) -> tuple[float, float, float]:
    q1, q2, q3 = np.percentile(values, [25, 50, 75])
    return float(q1), float(q2), float(q3)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--poses", type=int, default=20, help="poses for our timing (default 20)")
    parser.add_argument("--sampled", type=int, default=3, help="of those, poses timed with sampling (default 3)")
    parser.add_argument("--samples", type=int, default=10_000, help="arm angles per sampled pose (default 10^4)")
    parser.add_argument("--checked", type=int, default=20,
                        help="poses whose samples are checked against our sets (default 20, >= --sampled)")
    parser.add_argument("--path", type=int, default=1000,
                        help="waypoints of the path timed in the cell (default 1000; 0: no path)")
    parser.add_argument("--quick", action="store_true", help="6 poses, 1 sampled, 4 checked, a 100-waypoint path "
                        "(about 30 s)")
    args = parser.parse_args()
    if args.quick:
        args.poses, args.sampled, args.checked, args.path = 6, 1, 4, min(args.path, 100)
    args.sampled = min(args.sampled, args.poses)
    args.checked = min(max(args.checked, args.sampled), args.poses)
    for line in machine_lines(["numpy", "numba", "coal"]):
        print(line)
    try:
        import coal
    except ImportError:
        coal = None
        print("- coal is not installed (pip install -e '.[collision]'): the sampled baseline and the agreement are "
              "skipped")

    arm = redkin.arm("kuka-iiwa14")
    body, scene = iiwa_body(arm.chain), cell()
    poses = draw_poses(arm, body, scene, args.poses)
    print(f"- kuka-iiwa14, {len(body)} capsules (approximate, for timing only), no self pairs; {len(scene)} obstacles "
          f"({', '.join(scene.names)}), margin {scene.margin} m; {args.poses} poses, seed 40")

    # ours: a warm-up call (kernels from numba's cache), then per pose the best of 3 after one more
    start = time.perf_counter()
    collision_free_arm_angles(arm, poses[0], body, scene)
    first = time.perf_counter() - start
    results, seconds = [], []
    for pose in poses:
        seconds.append(best_time(lambda pose=pose: collision_free_arm_angles(arm, pose, body, scene), repeat=3))
        results.append(collision_free_arm_angles(arm, pose, body, scene))
    evaluations = [r.evaluations for r in results]
    blocked = sum(any(s.cause == "collision" for stretches in r.blocked for s in stretches) for r in results)
    print()
    print(f"1. ours: collision_free_arm_angles, 8 branches, resolution 1e-6 rad ({len(poses)} poses; first call of "
          f"the process {first * 1e3:.0f} ms)")
    q1, q2, q3 = _quartiles([s * 1e3 for s in seconds])
    e1, e2, e3 = _quartiles(evaluations)
    print(f"   ms per pose: median {q2:.1f}, quartiles {q1:.1f} / {q3:.1f}, range {min(seconds) * 1e3:.1f} - "
          f"{max(seconds) * 1e3:.1f}")
    print(f"   evaluations per call: median {e2:.0f}, quartiles {e1:.0f} / {e3:.0f}, range {min(evaluations)} - "
          f"{max(evaluations)};  {np.mean([s / e for s, e in zip(seconds, evaluations)]) * 1e6:.1f} us per "
          "evaluation (mean)")
    print(f"   poses with a stretch blocked by an obstacle: {blocked} of {len(poses)}; complete: "
          f"{sum(r.complete for r in results)} of {len(poses)}")
    together = best_time(lambda: free_arm_angles_of(arm, poses, body, scene), repeat=3) / len(poses)
    same = all(np.array_equal(x.bounds, y.bounds) for batched, alone in
               zip(free_arm_angles_of(arm, poses, body, scene), results, strict=True)
               for x, y in zip(batched.free, alone.free, strict=True))
    print(f"   the {len(poses)} poses decided together (free_arm_angles_of, as Arm.feasible(poses, body=, scene=) and "
          f"paths in a cell call it): {together * 1e3:.1f} ms per pose, {q2 / (together * 1e3):.1f} x faster than "
          f"the median alone; the same arcs as one by one: {same}")
    path_seconds = time_path(arm, body, scene, args.path) if args.path else None
    if coal is None:
        print(f"\ntarget: ours <= {TARGET_SECONDS * 1e3:.1f} ms per pose: "
              f"{'met' if q2 * 1e-3 <= TARGET_SECONDS else 'MISSED'} (median {q2:.1f} ms)")
        return

    coal_cell = CoalCell(coal, body, scene)
    # the coal shapes are the redkin rows: least distance at a few configurations where all pairs are separated
    rng = np.random.default_rng(0)
    probe = arm.chain.frames(rng.uniform(arm.chain.lower, arm.chain.upper, (200, 7)))
    ours_least = signed_distance(posed(body, probe)[:, :, None], scene.shapes[None, None]).distance.reshape(200, -1)
    apart = ours_least.min(axis=1) > 0.0
    shape_gap = np.abs(coal_cell.least_distances(probe[apart]) - ours_least.min(axis=1)[apart]).max()
    wrong = np.abs(coal_cell.broadphase_distances(probe[apart]) - ours_least.min(axis=1)[apart])
    print()
    print(f"2. sampled with coal: {args.samples} arm angles x 8 branches per pose, one arm.ik call, the "
          "configurations within the limits checked")
    print(f"   coal shapes vs redkin rows: least distance equal to {shape_gap:.1e} m on {int(apart.sum())} separated "
          "random configurations")
    print(f"   coal broadphase distance (DistanceCallBackDefault): {int(np.sum(wrong > 1e-6))} of {int(apart.sum())} "
          f"of those configurations wrong by up to {wrong.max():.3f} m (coal PR #885): not used")
    print(f"   {'pose':>4} {'configs':>8} {'ik+frames ms':>12} {'collide ms':>11} {'distance ms':>12} "
          f"{'us/config':>10} {'ours ms':>8} {'ratio':>7}")
    sampled_runs: dict[int, tuple[Sampled, np.ndarray]] = {}
    rows = []
    for index in range(args.sampled):
        sampled = sample(arm, poses[index], args.samples)
        start = time.perf_counter()
        hit = coal_cell.collide(sampled.frames)
        collide = time.perf_counter() - start
        start = time.perf_counter()
        least = coal_cell.least_distances(sampled.frames)
        distance = time.perf_counter() - start
        sampled_runs[index] = (sampled, least)
        rows.append((index, len(sampled.q), sampled.seconds, collide, distance, hit, least))
    faster = "collide" if sum(r[3] for r in rows) <= sum(r[4] for r in rows) else "distance"
    ratios = []
    for index, configs, ik_seconds, collide, distance, _, _ in rows:
        total = ik_seconds + (collide if faster == "collide" else distance)
        ratios.append(total / seconds[index])
        print(f"   {index:>4} {configs:>8} {ik_seconds * 1e3:>12.1f} {collide * 1e3:>11.0f} {distance * 1e3:>12.0f} "
              f"{(collide if faster == 'collide' else distance) / configs * 1e6:>10.1f} {seconds[index] * 1e3:>8.1f} "
              f"{ratios[-1]:>6.1f}x")
    decisions = sum(int(np.sum(hit != (least < scene.margin))) for *_, hit, least in rows)
    check = "broadphase collide" if faster == "collide" else "pairwise distance"
    print(f"   ratio: (ik+frames + the faster check, {check}) / ours; the two checks disagree on {decisions} "
          "configurations")

    print()
    print(f"3. agreement on poses 0-{args.checked - 1}: coal's pairwise least distance at {args.samples} arm angles x "
          "8 branches against our free sets")
    print(f"   {'pose':>4} {'in limits':>9} {'in ours':>8} {'coal clear':>10} {'ours, < 1e-6 over':>17} "
          f"{'ours not clear':>14} {'left out near end':>17} {'left out, far':>13} {'ours out of limits':>18}")
    totals = np.zeros(8, dtype=int)
    flagged: list[str] = []
    for index in range(args.checked):
        if index in sampled_runs:
            sampled, least = sampled_runs[index]
        else:
            sampled = sample(arm, poses[index], args.samples)
            least = coal_cell.least_distances(sampled.frames)
        a = agree(arm, index, results[index], sampled, least, coal_cell, body, scene)
        counts = np.array([a.within, a.ours, a.clear, a.grazing, a.false_free, a.missed_near, a.missed_far,
                           a.outside_limits])
        totals += counts
        flagged += a.flagged
        print(f"   {index:>4} {a.within:>9} {a.ours:>8} {a.clear:>10} {a.grazing:>17} {a.false_free:>14} "
              f"{a.missed_near:>17} {a.missed_far:>13} {a.outside_limits:>18}")
    print(f"   {'all':>4} {totals[0]:>9} {totals[1]:>8} {totals[2]:>10} {totals[3]:>17} {totals[4]:>14} "
          f"{totals[5]:>17} {totals[6]:>13} {totals[7]:>18}")
    for line in flagged:
        print(f"   flagged: {line}")

    print()
    ratio = float(np.median(ratios))
    print(f"{'measurement':<58} {'value':>12} {'target':>10}")
    print(f"{'ours, ms per pose (8 branches), median':<58} {q2:>12.1f} {'<= 0.5':>10} "
          f"{'met' if q2 * 1e-3 <= TARGET_SECONDS else 'MISSED'}")
    print(f"{f'sampled ({args.samples} psi, coal {faster}), ms per pose, median':<58} "
          f"{np.median([r[2] + (r[3] if faster == 'collide' else r[4]) for r in rows]) * 1e3:>12.0f}")
    print(f"{'sampled / ours, median over the sampled poses':<58} {ratio:>11.1f}x {'>= 100x':>10} "
          f"{'met' if ratio >= TARGET_RATIO else 'MISSED'}")
    print(f"{'samples in our sets that coal finds not clear':<58} {totals[4]:>12} {'0':>10} "
          f"{'met' if totals[4] == 0 else 'MISSED'}")
    print(f"{'coal-clear samples left out, > 1e-5 rad from our ends':<58} {totals[6]:>12} {'0':>10} "
          f"{'met' if totals[6] == 0 else 'MISSED'}")
    if path_seconds is not None:
        print(f"{f'a path of {args.path} waypoints in the cell, s':<58} {path_seconds:>12.2f} "
              f"{'<= 0.5' if args.path == 1000 else '':>10} "
              f"{('met' if path_seconds <= TARGET_PATH_SECONDS else 'MISSED') if args.path == 1000 else ''}")
    print(f"- load average at the end (1, 5, 15 min): {load_average()}")


if __name__ == "__main__":
    main()
