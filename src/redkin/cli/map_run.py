"""How ``redkin workspace`` runs a map: the optional libraries checked, the scheduler connected, progress shown.

Progress goes to stderr: a bar redrawn in place (``\\r``) on a terminal, plain
lines elsewhere (a file, a pipe, a CI log), nothing with ``--quiet``.

Shared by the arm-angle maps (:mod:`redkin.cli.workspace`) and the humanoid's
(:mod:`redkin.cli.workspace_humanoid`).
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from typing import Any

from redkin.cli.common import Progress, UsageError

#: How long ``--scheduler`` waits for the scheduler to answer.
_CONNECT_TIMEOUT = "10s"
#: What a full disk leaves when the slices are drawn after the map (the end of its one line).
IMAGES_LEFT = "the map is complete; free space and run the same command again to draw the slices"


def require_map_libraries() -> Any:
    """The ``xarray`` module, after checking that xarray, dask and zarr (the ``workspace`` extra) import."""
    from redkin.workspace._optional import require

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


def run_on(client: Any, chunks: int, run: Callable[[Any, Any], Any], quiet: bool = False) -> Any:
    """``run(client, progress)`` with the run's progress on stderr (none with ``quiet`` or a single chunk); the
    client is closed afterwards."""
    progress = None if quiet or chunks <= 1 else _ChunkProgress(sys.stderr)
    try:
        return run(client, progress)
    finally:
        if progress is not None:
            progress.close()
        if client is not None:
            client.close()


class _ChunkProgress(Progress):
    """:class:`redkin.cli.common.Progress` as ``progress(done, total)`` of a map's chunks."""

    def __call__(self, done: int, total: int) -> None:  # type: ignore[override]
        super().__call__(done / total, f"{done}/{total} chunks")


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
    from redkin.workspace._optional import require

    distributed = require("distributed")
    try:
        return distributed.Client(address, timeout=_CONNECT_TIMEOUT)
    except (OSError, TimeoutError, ValueError) as exc:
        raise UsageError(f"cannot connect to --scheduler {address!r}: "
                         f"{str(exc).splitlines()[0] if str(exc) else type(exc).__name__}") from None
