"""The small PA10 workspace map that the Dask and the fault tests share: its sizes, and its arrays read back.

``tests/conftest.py`` computes it once per session on the local scheduler (the ``small_map`` fixture), the
reference every distributed, interrupted or resumed run must equal bit for bit.
"""

from __future__ import annotations

EXTENT = [-0.9, 0.9, -0.9, 0.9, -0.5, 1.3]
SIZES = {"resolution": 6, "orientations": 16, "chunk": 2}  # 27 chunks of 2x2x2 positions
CHUNKS = 27
VALUES = ("measure", "reachability", "redundancy")
VARIABLES = (*VALUES, "rotation", "x", "y", "z", "chunk_complete")


def arrays(path) -> dict:
    """Every variable of a map's store, read back as numpy arrays.

    Read without Dask (``chunks=None``): a test that has a distributed client open would otherwise send the read to
    its workers, and one left restarting by a fault test once hung the suite there (``Client.gather``).
    """
    import xarray as xr

    with xr.open_zarr(path, chunks=None) as dataset:
        return {name: dataset[name].values for name in VARIABLES}
