"""Workspace maps: exact reachability and redundancy of an arm with arm-angle IK over a box of positions.

* :func:`workspace_map` -- compute a map chunk by chunk on Dask into a Zarr store (resumable); a nearly S-R-S
  arm is mapped with its exact neighbour's sets, and the store says so
* :func:`feasible_measures` -- measure of the feasible arm-angle set per pose and branch ([000 eq. 30])
* :func:`reachability_index`, :func:`redundancy_index` -- the per-position indices
* :func:`super_fibonacci_rotations` -- the deterministic near-uniform orientation set
* :func:`workspace_grid` -- the box of positions and its chunks

Dask, distributed, zarr and xarray come with the ``workspace`` extra (``pip install "redkin[workspace]"``, or
``pip install -e ".[workspace]"`` in a checkout) and are imported only when a map is computed or stored.
"""

from redkin.workspace.grid import MAX_RESOLUTION, WorkspaceGrid, workspace_grid
from redkin.workspace.measure import feasible_measures, reachability_index, redundancy_index
from redkin.workspace.orientations import MAX_ORIENTATIONS, super_fibonacci_rotations
from redkin.workspace.run import WorkspaceRun, workspace_map
from redkin.workspace.store import MAP_NAME

__all__ = [
    "MAP_NAME",
    "MAX_ORIENTATIONS",
    "MAX_RESOLUTION",
    "WorkspaceGrid",
    "WorkspaceRun",
    "feasible_measures",
    "reachability_index",
    "redundancy_index",
    "super_fibonacci_rotations",
    "workspace_grid",
    "workspace_map",
]
