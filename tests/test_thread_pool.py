"""Batches on redkin's thread pool (redkin._compiled.run_batch): the same numbers on any thread count and any
chunking, two Python threads running large batches at once, and a forked child after its parent used the pool.

Laws: every public batch function gives bit for bit the same arrays on one thread (the calling thread), on two
threads (the default chunks) and on three threads in odd chunks (a chunk of one item upwards); two threads of the
caller running batches at the same time each get what they get alone; a child forked (``multiprocessing``'s
``fork`` context) after the parent ran batches on the pool runs its own batches on a pool of its own.
"""

from __future__ import annotations

import dataclasses
import multiprocessing
import os
import threading

import numpy as np
import pytest

from redkin import _compiled
from redkin._compiled import set_threads
from redkin.models import kuka_iiwa14, pa10_7c
from redkin.srs import (
    BRANCHES,
    feasible_pieces,
    feasible_pieces_all_branches,
    ik,
    ik_all_branches,
    reachable,
    srs_geometry,
)
from redkin.srs.coefficients import arm_angle_coefficients
from redkin.srs.ik import theta_at
from redkin.torso_arm import elbow_angle, humanoid_arm, position_ik, shoulder_angle, theta1_from_shoulder_angle
from redkin.torso_arm import ik as torso_ik
from redkin.torso_arm.maps import best_over_redundancy, dual_arm_map, manipulability_map, plane_grid
from redkin.velocity import (
    WamFactorisation,
    adaptive_damped_least_squares,
    column_minors,
    damped_least_squares,
    pseudoinverse,
    singularity_consistent,
)
from redkin.virtual_arms import AnalyticModel, VirtualPoint
from tests.support.velocity_wam import EPS, WAM

COUNT = 1001  # not a multiple of any chunk count below


def arrays(value):
    """Every array in a result: arrays, numbers, and the fields of tuples and dataclasses, depth first."""
    if dataclasses.is_dataclass(value):
        for field in dataclasses.fields(value):
            yield from arrays(getattr(value, field.name))
    elif isinstance(value, tuple | list):
        for item in value:
            yield from arrays(item)
    elif value is not None and not isinstance(value, str):
        yield np.asarray(value)


def every_batch_function():
    """The results of each public function that runs a batch kernel, on COUNT items (a dict name -> result)."""
    rng = np.random.default_rng(11)
    chain = pa10_7c().with_limits(np.full(7, -2.5), np.full(7, 2.5))
    q = rng.uniform(-np.pi, np.pi, (COUNT, 7))
    poses, psi = chain.fk(q), rng.uniform(-np.pi, np.pi, COUNT)
    coefficients = arm_angle_coefficients(srs_geometry(chain), poses, -1)
    jac = WAM.jacobian(q)
    factor = WamFactorisation.from_chain(WAM)
    twist = rng.uniform(-1, 1, (COUNT, 6))
    arm = humanoid_arm("right")
    wrists = arm.chain.frames(rng.uniform(-0.5, 0.5, (COUNT, 8)))[:, 6, :3, 3]
    theta1 = rng.uniform(-0.5, 0.5, COUNT)
    shoulders = arm.shoulder(theta1)
    grid = plane_grid("z=0.3", (0.0, 1.0, -0.4, 0.8), 32)
    model = AnalyticModel(chain, [VirtualPoint.on_link(3), VirtualPoint.end()])
    return {
        "fk": chain.fk(q), "frames": chain.frames(q),
        "jacobian": chain.jacobian(q, frame=5, offset=rng.uniform(-0.1, 0.1, (COUNT, 3))),
        "ik_all_branches": ik_all_branches(chain, poses, psi), "ik": ik(chain, poses, psi, "-+-"),
        "reachable": reachable(chain, poses), "coefficients": coefficients,
        "theta_at": theta_at(coefficients, psi, BRANCHES[3]),
        "feasible_pieces": feasible_pieces(chain, poses, "+-+"),
        "feasible_pieces_all_branches": feasible_pieces_all_branches(chain, poses[:300]),
        "pseudoinverse": pseudoinverse(jac, twist), "dls": damped_least_squares(jac, twist, 0.05),
        "adaptive_dls": adaptive_damped_least_squares(jac, twist, 0.1, 0.1), "column_minors": column_minors(jac),
        "sc": singularity_consistent(jac, twist, factor.index(q), factor.factors(q), EPS),
        "position_ik": position_ik(arm, wrists, 0.2, 0.1),
        "torso_ik": torso_ik(arm, wrists, 0.2, 0.1, rotation=np.eye(3)),
        "shoulder_angle": shoulder_angle(theta1, wrists), "theta1": theta1_from_shoulder_angle(0.3, wrists),
        "elbow_angle": elbow_angle(arm, shoulders, (shoulders + wrists) / 2, wrists),
        "manipulability_map": manipulability_map(arm, grid, 0.2, 0.1), "dual_arm_map": dual_arm_map(grid, 0.2, 0.1),
        "best_over_redundancy": best_over_redundancy(arm, wrists[:300], samples=(3, 4)),
        "virtual_points": model.evaluate(q),
    }


@pytest.fixture
def chunking(monkeypatch):
    """Set the thread count and the chunking of run_batch for one test (every batch of PARALLEL_BATCH items or more
    on the pool); restored afterwards."""
    def configure(threads, per_thread=_compiled.CHUNKS_PER_THREAD, smallest=_compiled.MIN_CHUNK,
                  threshold=_compiled.PARALLEL_BATCH):
        set_threads(threads)
        monkeypatch.setattr(_compiled, "CHUNKS_PER_THREAD", per_thread)
        monkeypatch.setattr(_compiled, "MIN_CHUNK", smallest)
        monkeypatch.setattr(_compiled, "PARALLEL_BATCH", threshold)
        monkeypatch.setattr(_compiled, "POOL_SECONDS", 0.0)  # on the pool however short the batch
    yield configure
    set_threads(None)


def test_every_batch_function_is_bit_for_bit_the_same_on_any_threads_and_chunks(chunking):
    runs = {}
    for name, setting in {"one thread": (1,), "two threads": (2,),
                          "three threads, odd chunks": (3, 7, 1, 2)}.items():  # 21 chunks of 47-48 items; of 1 up
        chunking(*setting)
        runs[name] = every_batch_function()
    reference = runs.pop("one thread")
    for name, results in runs.items():
        for function, result in results.items():
            expected = list(arrays(reference[function]))
            got = list(arrays(result))
            assert len(got) == len(expected) > 0, function
            for one, other in zip(expected, got):
                np.testing.assert_array_equal(one, other, err_msg=f"{function} on {name}")


def test_two_python_threads_run_large_batches_at_the_same_time(chunking):
    """No launch lock: two threads of the caller run batches at once on the shared pool, each getting its serial
    numbers (a web server's or a Dask worker's threads)."""
    chain = kuka_iiwa14()
    rng = np.random.default_rng(12)
    q = rng.uniform(-np.pi, np.pi, (200_000, 7))
    poses = chain.fk(rng.uniform(-2.0, 2.0, (50_000, 7)))
    chunking(1)
    expected = {"fk": chain.fk(q), "ik": ik_all_branches(chain, poses, 0.4)}
    chunking(max(2, _compiled.default_threads()))
    start = threading.Barrier(2)
    results: dict[str, list] = {"fk": [], "ik": []}
    errors = []

    def work(name, function):
        try:
            start.wait(timeout=60)
            for _ in range(3):
                results[name].append(function())
        except BaseException as error:  # reported by the main thread
            errors.append(error)

    threads = [threading.Thread(target=work, args=("fk", lambda: chain.fk(q))),
               threading.Thread(target=work, args=("ik", lambda: ik_all_branches(chain, poses, 0.4)))]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join(timeout=300)
    assert not any(thread.is_alive() for thread in threads) and not errors
    for name, computed in results.items():
        assert len(computed) == 3
        for result in computed:
            np.testing.assert_array_equal(result, expected[name])


def _child(connection, chain, q, poses, expected_fk, expected_ik):
    """In the forked child: large batches, their equality with the parent's, and whose pool ran them."""
    try:
        fk, branches = chain.fk(q), ik_all_branches(chain, poses, 0.4)
        connection.send((bool(np.array_equal(fk, expected_fk) and np.array_equal(branches, expected_ik)),
                         _compiled._pool_key[0] == os.getpid()))
    finally:
        connection.close()


@pytest.mark.skipif("fork" not in multiprocessing.get_all_start_methods(), reason="needs the fork start method")
def test_a_forked_child_runs_large_batches_after_the_parent_used_the_pool(chunking):
    chunking(2)
    chain = kuka_iiwa14()
    rng = np.random.default_rng(13)
    q = rng.uniform(-np.pi, np.pi, (20_000, 7))
    poses = chain.fk(q)  # on the pool, in this process
    expected = ik_all_branches(chain, poses, 0.4)
    assert _compiled._pool_key[0] == os.getpid()
    context = multiprocessing.get_context("fork")
    receive, send = context.Pipe(duplex=False)
    child = context.Process(target=_child, args=(send, chain, q, poses, poses, expected))
    child.start()
    send.close()
    assert receive.poll(120), "the child sent nothing"
    equal, own_pool = receive.recv()
    child.join(60)
    assert child.exitcode == 0 and equal and own_pool
    np.testing.assert_array_equal(chain.fk(q), poses)  # the parent's pool still works
