"""Compile every kernel ahead of use: ``redkin compile``, for a Docker image, a cluster's workers or a CI cache.

A kernel compiles on its first call in a fresh install and is cached (:mod:`redkin._compiled`); a process that
calls everything once, section by section, leaves a cache from which every later process loads in milliseconds.
:func:`warm_up` is that process's work: each public function that runs a compiled kernel, called once on one item
and once on a batch past :data:`redkin._compiled.PARALLEL_BATCH`, with standard and modified DH, every arm class
(S-R-S, offset elbow, Franka, nearly S-R-S), the numerical IK, a short path, both torso arms and the distances
between shapes.
``benchmarks/cold_start.py`` times it on a fresh cache.  numba compiles serially within a process, so
``redkin compile`` runs the sections in one process per core (:func:`warm_up`'s ``processes``).

To share the cache, point ``NUMBA_CACHE_DIR`` at one folder before the first ``import redkin`` in every process
that should use it (a read-only install writes nowhere else; Dask workers on one machine or a shared file system
then load instead of compiling each): run ``NUMBA_CACHE_DIR=/opt/redkin-cache redkin compile`` once, and give the
workers the same variable.  The cache holds machine code for this CPU: copy it only between machines of one kind.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence

import numpy as np

from redkin.errors import RedkinError

#: Items of the batch calls (past the pool's threshold, so a batch takes the multi-threaded path too).
_BATCH = 1000


def _chain(rng: np.random.Generator) -> None:
    from redkin import models

    for arm in (models.pa10_7c(), models.franka_panda()):  # standard and modified DH
        one, many = rng.uniform(-1, 1, 7), rng.uniform(-1, 1, (_BATCH, 7))
        for q in (one, many):
            arm.fk(q), arm.frames(q), arm.jacobian(q), arm.jacobian(q, frame=4, offset=[0.0, 0.0, 0.1])
            arm.manipulability(q), arm.nearest_in_range(q), arm.nearest_in_range(q, near=q)


def _srs_ik(rng: np.random.Generator) -> None:
    from redkin import models, srs
    from redkin.srs.coefficients import coefficients_for

    for arm in (models.pa10_7c().with_limits(np.full(7, -2.5), np.full(7, 2.5)), models.barrett_wam7()):
        poses = arm.fk(rng.uniform(-1, 1, (_BATCH, 7)))
        poses = poses[srs.reachable(arm, poses)]
        for target in (poses[0], poses):
            srs.ik(arm, target, 0.1, "+-+"), srs.ik_all_branches(arm, target, 0.1), srs.reachable(arm, target)
            coefficients_for(srs.srs_geometry(arm), target, 1)
        srs.arm_angle_of(arm, rng.uniform(-1, 1, (_BATCH, 7)))


def _srs_sets(rng: np.random.Generator) -> None:
    from redkin import models, srs

    arm = models.pa10_7c().with_limits(np.full(7, -2.5), np.full(7, 2.5))
    poses = arm.fk(rng.uniform(-1, 1, (_BATCH, 7)))
    for target in (poses[0], poses):
        srs.feasible_pieces(arm, target, "+-+"), srs.feasible_pieces_all_branches(arm, target)
        srs.feasible_arm_angles_batch(arm, target, "+-+")
    result = srs.feasible_arm_angles(arm, poses[0], "+-+")
    assert result.feasible is not None and len(result.per_joint) == 7  # the sets are made on first access
    srs.joint_extrema(arm, poses[0], "+-+"), srs.singular_arm_angles(arm, poses[0], "+-+")
    srs.optimal_arm_angles(arm, poses[0], "+-+")
    srs.arm_angle_path(arm, poses[:20], "+-+")


def _franka(rng: np.random.Generator) -> None:
    from redkin import franka, models

    arm = models.franka_fr3()
    q = rng.uniform(arm.lower, arm.upper, (_BATCH, 7))
    poses = arm.fk(q)
    franka.ik(arm, poses[0], q[0, 6]), franka.ik(arm, poses, q[:, 6]), franka.ik(arm, poses[0], q[0, 6], "+-+")
    franka.feasible_q7(arm, poses[0]), franka.feasible_q7_batch(arm, poses[:20])
    franka.optimal_q7(arm, poses[0], "+-+")
    from redkin import arms, collision  # the certified collision-free q7 sets' level test

    body = collision.body_of([collision.BodyCapsule("forearm", 4, [0, 0, 0], [0, 0, 0.2], 0.05)], arm)
    # q[0]: a set; a ball at the forearm, so that intervals are decided by the proved bounds (without a pair to check
    # every interval is free unproved) and the ends of its stretches by the bounds along the pair's normal
    ball = {"name": "ball", "type": "sphere", "center": arm.frames(q[0])[4, :3, 3].tolist(), "radius": 0.05}
    collision.collision_free_q7(arms.arm(arm), poses[0], body, collision.scene_of({"obstacles": [ball]}))


def _nearly_srs(rng: np.random.Generator) -> None:
    from redkin import models, srs
    from redkin.srs import nearly

    arm = srs.nearly_srs(models.kinova_gen3())
    q = rng.uniform(-1, 1, (_BATCH, 7))
    poses, psi = arm.chain.fk(q), nearly.arm_angle(arm, q)
    nearly.ik(arm, poses[0], psi[0]), nearly.ik(arm, poses, psi, "+-+")
    nearly.ik_continued(arm, poses, psi, np.full(len(psi), 2), np.zeros(len(psi), dtype=np.int64))  # a path's nodes
    srs.neighbour_distance(arm, poses[0], psi[0], "+-+"), srs.neighbour_distance(arm, poses[0], psi, "+-+")
    srs.feasible_arm_angles_nearly(arm, poses[0], "+-+")
    srs.branch_solutions(arm, poses[0], float(psi[0]), "+-+")


def _nearly_self_motion(rng: np.random.Generator) -> None:
    """The certified self-motion from a solution, alone: its kernels without :func:`_nearly_srs`'s IK, so that a
    second process compiles them while the first compiles the IK (``redkin path`` on a nearly S-R-S arm)."""
    from redkin import models, srs

    arm = srs.nearly_srs(models.kinova_gen3())
    q = rng.uniform(-1, 1, 7)
    srs.self_motion(arm, arm.chain.fk(q), q)


def _numerical(rng: np.random.Generator) -> None:
    from redkin import models, numerical

    arm = models.kinova_gen3()
    q = rng.uniform(-1, 1, (_BATCH, 7))
    poses = arm.fk(q)
    numerical.ik(arm, poses[0]), numerical.ik(arm, poses[0], q0=q[0], rng=1), numerical.ik(arm, poses, q0=q, count=2)


def _paths(rng: np.random.Generator) -> None:
    from redkin import models, paths

    arm = models.kuka_iiwa14()
    q = np.radians([10.0, 40.0, 0.0, -70.0, 0.0, 50.0, 0.0]) + np.linspace(0.0, 0.2, 8)[:, None]
    poses = arm.fk(q)
    paths.resolve_path(arm, poses, 0.2, thorough=True)  # both stages
    # the baselines beside it (redkin path --plot)
    paths.fixed_psi_path(arm, poses, 0.2, 0.0), paths.clamped_optimum_path(arm, poses, 0.2)
    paths.greedy_path(arm, poses, 0.2)
    franka = models.franka_fr3()
    q = np.array([0.3, -0.5, 0.2, -2.0, 0.4, 1.8, 0.5]) + np.linspace(0.0, 0.2, 8)[:, None]
    paths.resolve_path(franka, franka.fk(q), 0.2, thorough=True)


def _path_search(rng: np.random.Generator) -> None:
    """The path graph's dynamic programming alone (:func:`redkin.paths.search.run`), on a small graph of random
    nodes: what a second process compiles beside a nearly S-R-S arm's path (:func:`_nearly_self_motion`)."""
    from redkin import models
    from redkin.paths.graph import Arm, Graph
    from redkin.paths.search import run

    nodes = 12
    q = rng.uniform(-1, 1, (nodes, 7))
    graph = Graph(np.arange(0, nodes + 1, 4), np.zeros(nodes, dtype=np.int64), np.zeros(nodes, dtype=np.int64),
                  np.zeros(nodes), q, np.ones(nodes))
    arm = Arm(models.kinova_gen3(), np.full(7, 2.0), np.zeros(7, dtype=bool))
    run(arm, graph, np.array([0, 3]), np.ones(nodes), np.zeros(nodes))


def _torso_arm(rng: np.random.Generator) -> None:
    from redkin import torso_arm
    from redkin.torso_arm import maps

    right = torso_arm.humanoid_arm("right")
    wrists = right.chain.frames(rng.uniform(-0.5, 0.5, (_BATCH, 8)))[:, 6, :3, 3]
    for wrist in (wrists[0], wrists):
        torso_arm.position_ik(right, wrist, 0.2, 0.1)
        torso_arm.ik(right, wrist, 0.2, 0.1, rotation=np.eye(3))
        theta1 = np.zeros(np.shape(wrist)[:-1])
        torso_arm.shoulder_angle(theta1, wrist), torso_arm.theta1_from_shoulder_angle(0.2, wrist)
        shoulder = right.shoulder(theta1)
        torso_arm.elbow_angle(right, shoulder, (shoulder + wrist) / 2, wrist)
    plane = (0.0, 1.0, -0.4, 0.8)
    for side in ("right", "left"):
        maps.manipulability_map(torso_arm.humanoid_arm(side), maps.plane_grid("z=0.3", plane, 40), 0.2, 0.1)
        maps.best_manipulability_map(torso_arm.humanoid_arm(side), maps.plane_grid("z=0.3", plane, 4),
                                     samples=(4, 4))
    maps.dual_arm_map(maps.plane_grid("z=0.3", plane, 40), 0.2, 0.1)
    maps.best_dual_arm_map(maps.plane_grid("z=0.3", plane, 4), samples=(4, 4))


def _velocity(rng: np.random.Generator) -> None:
    from redkin import models, velocity

    wam = models.barrett_wam()
    factor = velocity.WamFactorisation.from_chain(wam)
    twist = np.array([0.15, 0.0, 0.0, 0.0, 0.1, 0.0])
    for q in (rng.uniform(-1, 1, 7), rng.uniform(-1, 1, (_BATCH, 7))):
        jac = wam.jacobian(q)
        velocity.pseudoinverse(jac, twist), velocity.damped_least_squares(jac, twist, 0.1)
        velocity.adaptive_damped_least_squares(jac, twist, 0.1, 0.1)
        velocity.column_minors(jac)
        velocity.singularity_consistent(jac, twist, factor.index(q), factor.factors(q), 0.1)
        factors = factor.factors(q)
        velocity.lean_singularity_consistent(jac, twist, factor.index(q), lambda: factors, 0.1)  # noqa: B023
    q = np.radians([30.0, 20.0, 50.0, 70.0, 40.0, 100.0, 0.0])
    velocity.SingularityConsistentController(wam, q, eps=0.1)(q, twist)
    velocity.PseudoinverseController(wam)(q, twist)
    velocity.singularity_factorisation(models.barrett_wam7())


def _virtual_arms(rng: np.random.Generator) -> None:
    from redkin import models, virtual_arms

    model = virtual_arms.AnalyticModel(models.pa10_7c(), [virtual_arms.VirtualPoint.end()])
    model.evaluate(np.zeros(7)), model.evaluate(rng.uniform(-1, 1, (_BATCH, 7)))
    planar = virtual_arms.AnalyticModel(models.planar_arm(), [virtual_arms.VirtualPoint.end()])
    virtual_arms.generate_trajectory(planar, np.radians([30.0] * 5), [[0.6, 1.2]])


def _pa10_cell():
    """The PA10 with a forearm and a hand capsule, in a scene of a box and a ball (:func:`_collision_distances`,
    :func:`_collision`)."""
    from redkin import collision, models

    chain = models.pa10_7c()
    body = collision.body_of([collision.BodyCapsule("forearm", 4, [0, 0, 0], [0, 0, 0.2], 0.05),
                              collision.BodyCapsule("hand", 7, [0, 0, 0], [0, 0, 0.1], 0.05)], chain)
    scene = collision.Scene(("box", "ball"), np.stack([collision.box([0.5, 0, 0], [0.2, 0.3, 0.4]),
                                                       collision.sphere([0, 0.5, 0], 0.1)]), 0.01)
    return chain, body, scene


def _collision_distances(rng: np.random.Generator) -> None:
    """The distances between shapes and a body's clearance in a scene, without an arm class's sets: what a second
    process compiles beside a Franka-class arm's path in a cell (:func:`_path_search` too)."""
    from redkin import collision
    from redkin.collision.clearance import pair_table

    bodies = [collision.sphere(rng.uniform(-1, 1, 3), 0.1), collision.capsule([0, 0, 0], [0, 0, 0.4], 0.05)]
    obstacles = [collision.box([0.5, 0, 0], [0.2, 0.3, 0.4]), collision.plane([0, 0, -1], [0, 0, 1]),
                 collision.sphere([0, 0.5, 0], 0.1), collision.capsule([1, 0, 0], [1, 1, 0], 0.02)]
    pairs = np.array([[body, obstacle] for body in bodies for obstacle in obstacles])
    collision.signed_distance(pairs[0, 0], pairs[0, 1])
    many = np.resize(pairs, (_BATCH, 2, collision.WIDTH))
    collision.signed_distance(many[:, 0], many[:, 1])
    chain, body, scene = _pa10_cell()  # the clearance of a body in a scene: its listed pairs in one pass
    collision.clearance(chain, body, scene, rng.uniform(-1, 1, (4, 7)))
    pair_table(chain, body, scene, rng.uniform(-1, 1, (4, 7)))  # every pair's distance (a path's steps in a cell)


def _collision(rng: np.random.Generator) -> None:
    from redkin import arms, collision

    _collision_distances(rng)
    chain, body, scene = _pa10_cell()  # the certified collision-free arm angles' compiled steps
    pose = chain.fk(np.array([0.1, 0.5, 0.0, 1.3, 0.0, 0.6, 0.0]))  # within its limits: arcs to decide
    collision.collision_free_arm_angles(arms.arm(chain), pose, body, scene, "+++")
    collision.collision_free_ik(chain, body, scene, pose)  # the numerical search that measures its candidates
    from redkin.collision.mesh_cover import _along  # the mesh fit's kernel, without the mesh extra's reach

    _along(rng.normal(size=(20, 3)), np.array([0.0, 0.0, 1.0]))


#: The sections of :func:`warm_up`, in order: name and the calls that compile its kernels.
_SECTIONS: tuple[tuple[str, Callable[[np.random.Generator], None]], ...] = (
    ("chain", _chain),
    ("srs ik", _srs_ik),
    ("srs sets", _srs_sets),
    ("franka", _franka),
    ("nearly self-motion", _nearly_self_motion),
    ("nearly S-R-S", _nearly_srs),
    ("numerical ik", _numerical),
    ("path search", _path_search),
    ("paths", _paths),
    ("torso arm", _torso_arm),
    ("velocity", _velocity),
    ("virtual arms", _virtual_arms),
    ("collision distances", _collision_distances),
    ("collision", _collision),
)

#: The sections' names, in their order: ``redkin compile --section NAME`` compiles one of them.
SECTION_NAMES: tuple[str, ...] = tuple(name for name, _ in _SECTIONS)


def warm_up(progress: Callable[[str], None] | None = None, processes: int = 1,
            compiled: Callable[[str], None] | None = None,
            sections: Sequence[str] | None = None) -> list[tuple[str, float, float]]:
    """Call every compiled path once (compiling and caching what is not cached yet); return each section's seconds.

    Parameters
    ----------
    progress : callable, optional
        ``progress(section)`` before each section of :data:`_SECTIONS` (with ``processes > 1``: as each is handed
        to a process).
    processes : int, optional
        How many processes compile at once (default 1: this process, section after section).  With more, the
        sections go to that many new processes, the longest first, each taking the next as it finishes one;
        they write one cache (numba replaces its files whole), this process checks the cache's stamps first
        (:func:`redkin._compiled.prepare_cache`), and a kernel several sections call may be compiled by more
        than one.  Compiling is serial within a process, so on a machine with several cores this divides the
        wall time; the processes' own compile notices are not said.
    compiled : callable, optional
        ``compiled(kernel)`` for each kernel compiled (its module and function), in whichever process.
    sections : sequence of str, optional
        Only these sections (names of :data:`SECTION_NAMES`), in their order there; default all.

    Returns
    -------
    list of (str, float, float)
        Per section, in the order of :data:`_SECTIONS`: its name, wall-clock seconds and its process's CPU
        seconds (compiling is serial; on a busy machine CPU time is the steadier measure).

    Raises
    ------
    ValueError
        For ``processes`` < 1 or an unknown section.
    """
    if processes < 1:
        raise RedkinError(f"processes must be at least 1, got {processes}")
    unknown = sorted(set(sections or ()) - set(SECTION_NAMES))
    if unknown:
        raise RedkinError(f"unknown section {unknown[0]!r}; the sections are {', '.join(SECTION_NAMES)}")
    chosen = [k for k, name in enumerate(SECTION_NAMES) if sections is None or name in sections]
    if processes == 1:
        results = [_section_seconds(SECTION_NAMES[k], progress) for k in chosen]
    else:
        import multiprocessing
        from concurrent.futures import ProcessPoolExecutor

        from redkin._compiled import prepare_cache

        prepare_cache()  # every cache folder's stamp checked here, before the processes write to it
        order = sorted(chosen, key=lambda k: -_handed_out_by(SECTION_NAMES[k]))
        with ProcessPoolExecutor(processes, mp_context=multiprocessing.get_context("spawn"),
                                 initializer=_quiet) as pool:
            futures = {}
            for k in order:
                if progress is not None:
                    progress(SECTION_NAMES[k])
                futures[k] = pool.submit(_section_seconds, SECTION_NAMES[k])
            results = [futures[k].result() for k in chosen]
    if compiled is not None:
        for *_, kernels in results:
            for kernel in kernels:
                compiled(kernel)
    return [(name, wall, cpu) for name, wall, cpu, _ in results]


#: Each section's CPU seconds on a fresh cache after the sections before it (``redkin compile --json``, 2 cores,
#: 2026-12-04; the nearly S-R-S sections and the path search 2026-12-07, the search alone): only the order in which
#: several processes take them, the longest first (a section not listed last).
_EXPECTED = {"chain": 5.2, "srs ik": 9.4, "srs sets": 5.2, "franka": 25.9, "nearly self-motion": 18.7,
             "nearly S-R-S": 23.2, "numerical ik": 10.1, "paths": 6.6, "path search": 3.2, "torso arm": 7.7,
             "velocity": 8.9, "virtual arms": 2.1, "collision distances": 6.8, "collision": 6.8}


#: Sections whose kernels a longer section calls again on the way (its own calls compile them if they are not
#: cached yet): with several processes each is handed out just before that one, so that the longer one loads them
#: instead of compiling them a second time at once.
_CALLED_AGAIN_BY = {"nearly self-motion": "nearly S-R-S", "collision distances": "collision", "path search": "paths"}


def _handed_out_by(section: str) -> float:
    """The seconds by which :func:`warm_up` hands ``section`` to its processes, the longest first: its own expected
    seconds, or those of the section that calls it again (:data:`_CALLED_AGAIN_BY`) where larger (listed before that
    one in :data:`_SECTIONS`, it then goes first of the two)."""
    return max(_EXPECTED.get(section, 0.0), _EXPECTED.get(_CALLED_AGAIN_BY.get(section, ""), 0.0))


def expected_seconds(sections: Sequence[str]) -> float:
    """About how many seconds compiling ``sections`` takes on a fresh cache (:data:`_EXPECTED`; a floor where
    another section compiled some of their kernels first)."""
    return sum(_EXPECTED.get(name, 0.0) for name in sections)


def _quiet() -> None:
    """A compiling process of :func:`warm_up` does not say its compile notice (the processes would interleave)."""
    from redkin._compiled import set_compile_notice

    set_compile_notice(False)


def _section_seconds(name: str, progress: Callable[[str], None] | None = None) -> tuple[str, float, float, list[str]]:
    """Run the section ``name`` of :data:`_SECTIONS` (its own random inputs, ``default_rng`` of its place), saying
    ``progress(name)`` first: its name, wall-clock and this process's CPU seconds, and the kernels it compiled."""
    from redkin._compiled import on_compile

    index = [section for section, _ in _SECTIONS].index(name)
    if progress is not None:
        progress(name)
    kernels: list[str] = []
    remove = on_compile(kernels.append)
    wall, cpu = time.perf_counter(), time.process_time()
    try:
        _SECTIONS[index][1](np.random.default_rng(index))
    finally:
        remove()
    return name, time.perf_counter() - wall, time.process_time() - cpu, kernels
