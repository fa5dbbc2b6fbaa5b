"""Functions of the benchmark scripts on tiny inputs (the times they return are not checked against targets)."""

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))

import bench_srs
import bench_velocity

from redkin.models import barrett_wam, pa10_7c
from redkin.reproduce import printed
from redkin.velocity import WamFactorisation

WAM = barrett_wam()
FACTOR = WamFactorisation.from_chain(WAM)
Q0 = np.radians(printed.SECTION_4_Q0_DEG)  # paper 003 section 4
TWIST = np.array(printed.SECTION_4_TWIST)


def test_velocity_array_api_table_runs_on_a_batch():
    """Table 1 of bench_velocity.py: its batched column once stopped the script (LAPACK dgelss on a batch)."""
    batch = np.random.default_rng(0).uniform(-np.pi, np.pi, (3, 7))
    rows = bench_velocity.array_api_rows(WAM, FACTOR, Q0, TWIST, batch, calls=1)
    assert [row[0] for row in rows] == ["pinv", "dls", "dls-adaptive", "sc", "sc-exact"]
    assert all(np.isfinite(row[1:]).all() and min(row[1:]) > 0.0 for row in rows)


def test_velocity_places_have_the_advertised_singularity_index():
    """Table 1 of bench_velocity.py times the SC step outside the region, inside it and in the exact band."""
    places = bench_velocity.places(FACTOR, Q0)
    np.testing.assert_allclose([float(FACTOR.index(q)) for q in places.values()], [FACTOR.index(Q0), 0.05, 1e-4],
                               rtol=1e-9)


def test_srs_peer_check_counts_solutions_within_1e9_by_our_fk():
    """bench_srs.py judges every solver with chain.fk: 1e-10 rad off the last joint passes, 1e-8 rad fails."""
    chain = pa10_7c()
    q = np.random.default_rng(2).uniform(chain.lower, chain.upper, (4, 7))
    poses = chain.fk(q)
    assert bench_srs.pose_errors(chain, q, poses).max() < 1e-14
    moved = q + np.array([[0.0], [1e-10], [1e-8], [1e-6]]) * np.eye(7)[6]
    assert bench_srs.passes(chain, moved, poses) == 2


@pytest.mark.slow
def test_srs_feasible_rows_run_on_a_tiny_batch():
    """bench_srs.py's feasible-set rows: every call of the table runs, on one pose and on a batch of three."""
    from redkin.srs import srs_geometry

    chain = pa10_7c()
    geometry = srs_geometry(chain)
    poses = chain.fk(np.random.default_rng(3).uniform(chain.lower, chain.upper, (3, 7)))
    calls = bench_srs.feasible_calls(geometry, poses[0])
    assert len(calls) == 7 and all(call() is not None for _, call in calls)
    rows = bench_srs.feasible_batch_rows(geometry, poses)
    assert len(rows) == 4 and all("pose-branches/s" in value for _, value in rows)


def test_bench_workspace_times_a_whole_map(tmp_path):
    """bench_workspace.py times complete maps (a map it times must have computed every chunk)."""
    pytest.importorskip("zarr")
    import bench_workspace

    seconds, cpu = bench_workspace.timed_map(tmp_path, "tiny", 2, 2)
    assert seconds > 0.0 and cpu > 0.0
