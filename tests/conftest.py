"""Fixtures shared across the test modules: the arms they build, the full reproduction report, the Dask clusters;
and the hypothesis profiles of the suite.

Each session fixture is built once per session; tests must not change them (chains are read-only in use:
``with_limits`` and friends return new chains).

Hypothesis (docs/testing.md): the profile ``redkin``, loaded here, is what ``python -m pytest`` runs, locally and
in CI alike: derandomized (each test draws the same examples on every run, on every machine), no example database,
no deadline, and each test's own ``max_examples``.  ``python -m pytest --hypothesis-profile=explore`` draws fresh
random examples instead, and keeps the failing ones in ``.hypothesis/examples`` so that they replay; a failure
found that way goes into the suite as an ``@example(...)``.

Dask: no test may leave a default client or scheduler behind (:func:`_no_default_dask_scheduler`); a test that
needs a cluster asks for one (``client``, ``own_client``) and passes it explicitly.
"""

from __future__ import annotations

import contextlib
import os
import shlex
import shutil
import sys
import tempfile
import warnings
from collections.abc import Iterator
from pathlib import Path

import pytest
from hypothesis import HealthCheck, settings
from hypothesis.database import DirectoryBasedExampleDatabase

from redkin.chain import SerialChain
from redkin.cli.main import main
from redkin.velocity import WamFactorisation
from tests.support import velocity_wam

#: The suite's own profile (module docstring): the same examples on every run; a failure is a finding, never luck.
#: ``too_slow`` is a health check on the time taken to draw examples, which a loaded machine can fail: suppressed,
#: as in hypothesis's own "ci" profile (which this replaces; hypothesis loads that one where ``CI`` is set).
_HYPOTHESIS_DEFAULT = settings.get_profile("default")
settings.register_profile("redkin", _HYPOTHESIS_DEFAULT, derandomize=True, database=None, deadline=None,
                          print_blob=True, suppress_health_check=[HealthCheck.too_slow])
#: Fresh random examples on each run; failures are kept in ``.hypothesis/examples`` and tried first next time.
settings.register_profile("explore", _HYPOTHESIS_DEFAULT, derandomize=False, deadline=None, print_blob=True,
                          database=DirectoryBasedExampleDatabase(Path(__file__).resolve().parents[1] / ".hypothesis"
                                                                 / "examples"),
                          suppress_health_check=[HealthCheck.too_slow])
# hypothesis's pytest plugin loads the profile named by --hypothesis-profile after this conftest is imported
settings.load_profile("redkin")


def _source_constants_only_when_exploring() -> None:
    """Keep the numbers written in our own modules out of the derandomized draws.

    Hypothesis sometimes draws a constant found in the source of any local module imported so far (its "local
    constants": ``0.02``, ``1e-9``, ``-90.0`` of src/ and tests/), so with ``derandomize`` a test's examples still
    changed when any module changed (an edit to ``redkin/srs/conventions.py`` changed what the circle tests draw) or
    when fewer modules were imported (one module run alone).  Under a derandomized profile the pool is empty, and a
    test's examples depend on the test and its strategies only; ``explore`` keeps the pool, a good source of edge
    cases.  Hypothesis has no setting for this: ``providers._get_local_constants`` is its internal function, and
    ``tests/test_hypothesis_profile.py`` checks that the draws do not change when a module of new constants loads.
    """
    try:
        from hypothesis.internal.conjecture import providers
        from hypothesis.internal.constants_ast import Constants
    except ImportError:  # another hypothesis: the test of the law says so
        return
    real = getattr(providers, "_get_local_constants", None)
    if real is None:
        return
    none = Constants()

    def local_constants() -> Constants:
        return none if settings.default.derandomize else real()

    providers._get_local_constants = local_constants


_source_constants_only_when_exploring()


@pytest.fixture(scope="session")
def wam() -> SerialChain:
    """The Barrett WAM of paper 003 (offset elbow); the same object as ``tests.support.velocity_wam.WAM``."""
    return velocity_wam.WAM


@pytest.fixture(scope="session")
def wam_factor() -> WamFactorisation:
    """The WAM's D_e factorisation (paper 003 sec. 3.3); the same object as ``tests.support.velocity_wam.FACTOR``."""
    return velocity_wam.FACTOR


#: The README's command for the whole report, which :func:`full_report` runs as written (tests/test_readme_commands.py).
FULL_REPORT_COMMAND = "redkin reproduce --out report"


@pytest.fixture(scope="session")
def full_report():
    """The folder of ``redkin reproduce`` with every section (index.html, summary.json, figures, explorers).

    Built once per session, by the first test that asks (about a minute), with the README's command line
    :data:`FULL_REPORT_COMMAND` run from an empty folder; read by the section, browser and README tests, which must
    not change it; removed when the session ends.
    """
    folder = Path(tempfile.mkdtemp(prefix="redkin-report-"))
    here = Path.cwd()
    os.chdir(folder)
    try:
        code = main(shlex.split(FULL_REPORT_COMMAND)[1:])
    finally:
        os.chdir(here)
    assert code == 0, f"{FULL_REPORT_COMMAND}: exit code {code}"
    yield folder / "report"
    shutil.rmtree(folder, ignore_errors=True)


@contextlib.contextmanager
def local_cluster_client() -> Iterator:
    """A ``distributed.Client(set_as_default=False)`` of a new LocalCluster of 2 single-threaded worker processes on
    loopback, closed with its cluster at the end of the ``with`` block.

    Not the default client: Dask work goes to it only where the test passes it (``workspace_map(client=...)``,
    ``client.compute``), and nothing else in the process (an ``xarray`` read, another test) reaches its workers.
    """
    distributed = pytest.importorskip("distributed")
    with warnings.catch_warnings():
        # the scheduler's HTTP server (health checks, even without a dashboard) tries port 8787 first, and takes
        # another with a warning where the session's cluster has it
        warnings.filterwarnings("ignore", "Port 8787 is already in use", UserWarning)
        cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                                           dashboard_address=None)
    with cluster, distributed.Client(cluster, timeout="60s", set_as_default=False) as client:
        client.wait_for_workers(2, timeout=60)
        yield client


@pytest.fixture(scope="session")
def client():
    """The session's Dask cluster (:func:`local_cluster_client`), shared by the Dask tests and closed at its end.

    It is not the default client: pass it.  A test must leave its workers as it found them; one that kills or
    restarts workers takes ``own_client`` instead.
    """
    with local_cluster_client() as client:
        yield client


@pytest.fixture
def own_client():
    """A Dask cluster of the test's own (:func:`local_cluster_client`), for a test that kills or restarts workers."""
    with local_cluster_client() as client:
        yield client


def default_dask_scheduler() -> list[str]:
    """What Dask would use in this process without being told: a default ``distributed`` client, a ``scheduler``
    in Dask's configuration (empty: none, Dask's local schedulers per collection)."""
    found = []
    if "distributed" in sys.modules:  # no client exists unless distributed was imported
        try:
            found.append(f"default client {sys.modules['distributed'].default_client()!r}")
        except ValueError:  # "No clients found"
            pass
    if "dask" in sys.modules and sys.modules["dask"].config.get("scheduler", None) is not None:
        found.append(f"dask.config scheduler={sys.modules['dask'].config.get('scheduler')!r}")
    return found


@pytest.fixture(autouse=True)
def _own_mesh_cache(tmp_path_factory, monkeypatch):
    """Each test keeps its mesh covers (redkin.collision.mesh_cache) in a folder of its own: a cover another test
    left must not stand in for the work a test means to do (reading the file, failing without trimesh), and the
    suite writes nothing under the user's home."""
    monkeypatch.setenv("REDKIN_CACHE_DIR", str(tmp_path_factory.mktemp("redkin-cache")))


@pytest.fixture(autouse=True)
def _no_default_dask_scheduler(request):
    """Fail the test that leaves a default Dask client or scheduler set, which would take every later test's Dask
    work (CI hung twice on a store read sent to a cluster whose workers a test had restarted)."""
    yield
    left = default_dask_scheduler()
    if left:  # cleared, so that the tests after it do not fail too
        with contextlib.suppress(ValueError):
            sys.modules["distributed"].default_client().close()
        sys.modules["dask"].config.refresh()
        pytest.fail(f"{request.node.nodeid} left a default Dask scheduler set: {'; '.join(left)}", pytrace=False)


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
