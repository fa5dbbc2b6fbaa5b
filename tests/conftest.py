"""Fixtures shared across the test modules: the arms they build and the full reproduction report.

Each is built once per session; tests must not change them (chains are read-only in use:
``with_limits`` and friends return new chains).
"""

from __future__ import annotations

import shutil
import tempfile
from pathlib import Path

import pytest

from redkin import reproduce
from redkin.chain import SerialChain
from redkin.velocity import WamFactorisation
from tests.support import velocity_wam


@pytest.fixture(scope="session")
def wam() -> SerialChain:
    """The Barrett WAM of paper 003 (offset elbow); the same object as ``tests.support.velocity_wam.WAM``."""
    return velocity_wam.WAM


@pytest.fixture(scope="session")
def wam_factor() -> WamFactorisation:
    """The WAM's D_e factorisation (paper 003 sec. 3.3); the same object as ``tests.support.velocity_wam.FACTOR``."""
    return velocity_wam.FACTOR


@pytest.fixture(scope="session")
def full_report():
    """The folder of ``redkin reproduce`` with every section (index.html, summary.json, figures, explorers).

    Built once per session, by the first test that asks (about a minute), and read by the section and browser
    tests, which must not change it; removed when the session ends.
    """
    folder = Path(tempfile.mkdtemp(prefix="redkin-report-"))
    reproduce.run(folder)
    yield folder
    shutil.rmtree(folder, ignore_errors=True)


@pytest.fixture(scope="session")
def client():
    """A dask.distributed LocalCluster of 2 single-threaded worker processes on loopback, shared by the Dask
    tests of the session and closed at its end."""
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster, timeout="60s") as client:
        client.wait_for_workers(2, timeout=60)
        yield client


@pytest.fixture(scope="session")
def pa10() -> SerialChain:
    """The PA10-7C model, for the tests of its workspace map."""
    from redkin.models import get_robot

    return get_robot("pa10-7c")


@pytest.fixture(scope="session")
def small_map(pa10, tmp_path_factory) -> dict:
    """The arrays of :mod:`tests.support.small_map`'s map in one uninterrupted run on the local scheduler, computed
    once for the Dask and the fault tests."""
    from redkin.workspace import workspace_map
    from tests.support import small_map as sizes

    run = workspace_map(pa10, tmp_path_factory.mktemp("reference") / "map.zarr", sizes.EXTENT, **sizes.SIZES)
    assert run.computed == run.chunks == sizes.CHUNKS
    return sizes.arrays(run.path)
