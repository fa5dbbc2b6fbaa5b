"""How ``redkin workspace`` runs a map: the optional libraries checked, the scheduler connected, progress shown.

Shared by the arm-angle maps (:mod:`redkin.cli.workspace`) and the humanoid's
(:mod:`redkin.cli.workspace_humanoid`).
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from typing import Any

from redkin.cli.common import UsageError, progress_bar
from redkin.workspace._optional import require

#: How long ``--scheduler`` waits for the scheduler to answer.
_CONNECT_TIMEOUT = "10s"


def require_map_libraries() -> Any:
    """The ``xarray`` module, after checking that xarray, dask and zarr (the ``workspace`` extra) import."""
    try:
        xr, _, _ = (require(name) for name in ("xarray", "dask", "zarr"))
    except ImportError as exc:
        raise UsageError(str(exc)) from None
    return xr


def open_client(scheduler: str | None) -> Any:
    """A client of the cluster at ``scheduler``, or ``None`` for Dask's local scheduler (UsageError if none answers)."""
    try:
        return None if scheduler is None else _connect(scheduler)
    except ImportError as exc:
        raise UsageError(str(exc)) from None


def run_on(client: Any, chunks: int, run: Callable[[Any, Any], Any]) -> Any:
    """``run(client, progress)``, with a progress bar on stderr when there is more than one chunk; the client is
    closed afterwards."""
    progress = (lambda done, total: progress_bar(done / total)) if chunks > 1 else None
    try:
        return run(client, progress)
    finally:
        if progress is not None:
            print(file=sys.stderr)
        if client is not None:
            client.close()


def run_summary(chain_name: str, result: Any, images: list, scheduler: str | None, units: dict,
                fields: dict) -> dict:
    """The ``--json`` summary of a map run: robot, store, images and scheduler, the map's own ``fields``, then
    the chunks computed and resumed and the time."""
    return {
        "robot": chain_name, "map": str(result.path), "images": [str(image) for image in images],
        "scheduler": scheduler or "local", "units": {"seconds": "s", "fractions": "1", **units}, **fields,
        "chunks": result.chunks, "chunks_computed": result.computed, "chunks_resumed": result.chunks - result.computed,
        "seconds": result.seconds,
    }


def print_run(summary: dict) -> None:
    """The lines every map run prints after its own: chunks and scheduler, the store, the slice images."""
    print(f"chunks: {summary['chunks']} ({summary['chunks_computed']} computed, {summary['chunks_resumed']} resumed) "
          f"on {summary['scheduler']} in {summary['seconds']:.1f} s")
    print(f"map: {summary['map']}  (xarray.open_zarr)")
    print("slices: " + ", ".join(summary["images"]))


def _connect(address: str) -> Any:
    """A ``distributed.Client`` of the scheduler at ``address`` (UsageError if none answers)."""
    distributed = require("distributed")
    try:
        return distributed.Client(address, timeout=_CONNECT_TIMEOUT)
    except (OSError, TimeoutError, ValueError) as exc:
        raise UsageError(f"cannot connect to --scheduler {address!r}: "
                         f"{str(exc).splitlines()[0] if str(exc) else type(exc).__name__}") from None
