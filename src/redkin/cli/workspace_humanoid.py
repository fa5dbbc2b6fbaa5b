"""``redkin workspace`` for the thesis 001 humanoid: its 3-D map of the best manipulability over the redundancy.

Called by :mod:`redkin.cli.workspace` when ROBOT is the humanoid's arm
(``humanoid-right``, ``humanoid-left`` or a chain of the same Table 2.1 form).
"""

from __future__ import annotations

import argparse

from redkin._validation import check_count, check_output_directory
from redkin.chain import SerialChain
from redkin.cli.common import UsageError, print_json
from redkin.cli.map_run import IMAGES_LEFT, open_client, print_run, require_map_libraries, run_on, run_summary
from redkin.torso_arm.maps import MAX_SWEEP_SAMPLES
from redkin.workspace.grid import MAX_RESOLUTION
from redkin.workspace.humanoid import DEFAULT_SAMPLES, VARIABLES, humanoid_grid, humanoid_map, mid_plane_maps
from redkin.workspace.store import MAP_NAME, no_space_errors

#: The images written beside the map: one per measure, its three mid-planes side by side.
SLICE_NAMES = ("best_manipulability", "best_dual_manipulability")


def run_humanoid(args: argparse.Namespace, chain: SerialChain) -> int:
    """The humanoid's map for the parsed ``redkin workspace`` arguments."""
    if args.orientations is not None:
        raise UsageError("--orientations is for arms with arm-angle IK; the humanoid's map takes --samples N1 NPHI "
                         "(theta_1 x phi samples of the redundancy)")
    resolution = check_count(args.resolution, "--resolution", 2, MAX_RESOLUTION)
    samples = DEFAULT_SAMPLES
    if args.samples is not None:  # argparse gives two (nargs=2)
        n1, n_phi = (check_count(n, "--samples", 1, MAX_SWEEP_SAMPLES) for n in args.samples)
        samples = (n1, n_phi)
    chunk = None if args.chunk is None else check_count(args.chunk, "--chunk", 1, resolution)
    grid = humanoid_grid(args.extent, resolution, samples, chunk)  # the extent refused before anything is written
    xr = require_map_libraries()
    client = open_client(args.scheduler)
    out = check_output_directory(args.out, "--out")
    result = run_on(client, len(grid.chunk_indices()), lambda client, progress: humanoid_map(
        chain, out / MAP_NAME, args.extent, grid.resolution, samples, chunk=grid.chunk, client=client,
        progress=progress), args.quiet)
    import matplotlib

    matplotlib.use("Agg")  # files only: no display needed
    from redkin.plot.torso_arm import save_mid_plane_maps

    images = [out / f"{name}.png" for name in SLICE_NAMES]
    # read back without Dask (chunks=None): the pictures need the values here, not from a cluster that may be gone
    with xr.open_zarr(result.path, chunks=None) as dataset, no_space_errors(out, IMAGES_LEFT):
        for name, image in zip(SLICE_NAMES, images):
            save_mid_plane_maps(mid_plane_maps(dataset, name), image, VARIABLES[name][0],
                                f"{chain.name}: {name} over theta_1 x phi = {samples[0]} x {samples[1]} samples")
    summary = run_summary(chain.name, result, images, args.scheduler,
                          {"manipulability": "m^3", "dual_manipulability": "m^6"}, {
        "positions": result.positions, "samples": list(result.samples),
        "postures": result.positions * result.samples[0] * result.samples[1],
        "reachable_positions": result.reachable_positions, "feasible_positions": result.feasible_positions,
        "max_manipulability": result.max_manipulability, "mean_manipulability": result.mean_manipulability,
        "max_dual_manipulability": result.max_dual_manipulability,
    })
    if args.json:
        print_json(summary)
    else:
        print(f"{chain.name}: {result.positions} wrist positions x {samples[0]} x {samples[1]} samples of "
              "(theta_1, phi), best manipulability within the limits of joints 1-5 (thesis 001)")
        print(f"reachable: {100 * result.reachable_positions:.1f}% of positions, within limits "
              f"{100 * result.feasible_positions:.1f}%; best w there: max {result.max_manipulability:.4g} m^3, "
              f"mean {result.mean_manipulability:.4g} m^3; dual arm max {result.max_dual_manipulability:.4g} m^6")
        print_run(summary)
    return 0
