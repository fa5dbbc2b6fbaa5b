"""``redkin workspace``: exact reachability and redundancy map of an arm over a box, on Dask, into Zarr."""

from __future__ import annotations

import argparse

from redkin._constants import WORKSPACE_MAP_NAME, WORKSPACE_MAX_ORIENTATIONS, WORKSPACE_MAX_RESOLUTION
from redkin._validation import check_count, check_output_directory
from redkin.cli.cell import add_cell_arguments, load_cell
from redkin.cli.common import (
    UsageError,
    add_output_flags,
    add_robot_argument,
    add_srs_tolerance_argument,
    load_robot,
    plural,
    print_json,
)
from redkin.cli.map_run import IMAGES_LEFT, open_client, print_run, require_map_libraries, run_on, run_summary

#: The images written beside the map: one per index, its three mid-planes side by side.
SLICE_NAMES = ("reachability", "redundancy")


def register(subparsers: argparse._SubParsersAction) -> None:
    command = subparsers.add_parser(
        "workspace",
        help="exact reachability and redundancy map of an arm over a box, from the exact feasible sets of its "
             "redundancy parameter (the arm angle of paper 000, q7 of the Franka class; on Dask; a nearly S-R-S arm "
             "with its exact neighbour's sets)",
    )
    add_robot_argument(command)
    command.add_argument("--out", required=True, metavar="DIR",
                         help=f"output directory: DIR/{WORKSPACE_MAP_NAME} (resumed if it holds the same map) and PNG "
                              "slices")
    command.add_argument("--extent", nargs=6, type=float, required=True,
                         metavar=("XMIN", "XMAX", "YMIN", "YMAX", "ZMIN", "ZMAX"), help="box of tool positions [m]")
    command.add_argument("--resolution", type=int, required=True, metavar="M",
                         help=f"grid points per axis, ends included (2..{WORKSPACE_MAX_RESOLUTION})")
    command.add_argument("--orientations", type=int, metavar="N",
                         help="tool orientations per position, a super-Fibonacci set on SO(3) "
                              f"(1..{WORKSPACE_MAX_ORIENTATIONS}); required for an arm with a redundancy parameter")
    command.add_argument("--samples", type=int, nargs=2, metavar=("N1", "NPHI"),
                         help="the thesis 001 humanoid (humanoid-right, humanoid-left) instead: its best "
                              "manipulability over N1 x NPHI samples of theta_1 and phi (default 24 24)")
    command.add_argument("--chunk", type=int, metavar="C",
                         help="grid points per axis of a chunk (default: about 262144 poses per chunk)")
    command.add_argument("--scheduler", metavar="ADDRESS",
                         help="a dask.distributed scheduler (tcp://host:port) whose workers can write DIR "
                              "(default: Dask's local scheduler, nothing to start)")
    command.add_argument("--quiet", action="store_true",
                         help="no progress on stderr (by default a bar on a terminal, plain lines elsewhere)")
    add_srs_tolerance_argument(command)
    add_cell_arguments(command, "the map holds the certified collision-free sets instead, reachability inside the "
                                "cell (S-R-S and offset-elbow arms, chunks of about 4096 poses by default; "
                                "the Franka class over q7, chunks of about 64 poses)")
    add_output_flags(command, degrees=False)
    command.set_defaults(handler=run)


def run(args: argparse.Namespace) -> int:
    from redkin.cli.workspace_humanoid import run_humanoid
    from redkin.workspace.grid import workspace_grid
    from redkin.workspace.humanoid import humanoid_of
    from redkin.workspace.measure import whole_range
    from redkin.workspace.run import cell_chunk, map_model, workspace_map
    from redkin.workspace.store import MODEL_CERTIFIED, no_space_errors

    chain = load_robot(args)
    if humanoid_of(chain) is not None:
        if args.srs_tolerance is not None:
            raise UsageError("--srs-tolerance is for nearly S-R-S arms; the thesis 001 humanoid is not one")
        if args.scene is not None:
            raise UsageError("--scene maps an arm with certified collision-free sets; the thesis 001 humanoid has none")
        return run_humanoid(args, chain)
    if args.samples is not None:
        raise UsageError("--samples is for the thesis 001 humanoid; any other arm takes --orientations N")
    mapped, nearly = map_model(chain, args.srs_tolerance)  # the refusal of a general chain, before anything is written
    assert mapped.parameter is not None  # map_model refuses an arm without one
    if args.orientations is None:
        raise UsageError(f"{chain.name!r} has a redundancy parameter ({mapped.parameter.name}): its map needs "
                         f"--orientations N (tool orientations per position, 1..{WORKSPACE_MAX_ORIENTATIONS})")
    resolution = check_count(args.resolution, "--resolution", 2, WORKSPACE_MAX_RESOLUTION)
    orientations = check_count(args.orientations, "--orientations", 1, WORKSPACE_MAX_ORIENTATIONS)
    chunk = None if args.chunk is None else check_count(args.chunk, "--chunk", 1, resolution)
    cell = load_cell(args, chain)
    if cell is not None and chunk is None:
        chunk = cell_chunk(resolution, orientations, mapped, nearly)
    grid = workspace_grid(args.extent, resolution, orientations, chunk)
    xr = require_map_libraries()
    client = open_client(args.scheduler)
    out = check_output_directory(args.out, "--out")
    result = run_on(client, len(grid.chunk_indices()), lambda client, progress: workspace_map(
        chain, out / WORKSPACE_MAP_NAME, args.extent, resolution, orientations, chunk=grid.chunk, client=client,
        progress=progress, srs_tolerance=args.srs_tolerance, body=None if cell is None else cell[0],
        scene=None if cell is None else cell[1]), args.quiet)
    import matplotlib

    matplotlib.use("Agg")  # files only: no display needed
    from redkin.plot.workspace import save_mid_plane_slices

    images = [out / f"{name}.png" for name in SLICE_NAMES]
    # read back without Dask (chunks=None): the pictures need the values here, not from a cluster that may be gone
    with xr.open_zarr(result.path, chunks=None) as dataset, no_space_errors(out, IMAGES_LEFT):
        for name, image in zip(SLICE_NAMES, images):
            save_mid_plane_slices(dataset, name, image)
    summary = run_summary(chain.name, result, images, args.scheduler,
                          {"mean_redundancy": f"1 (feasible {mapped.parameter.name} measure / its range, "
                                              f"{whole_range(mapped):.6g} rad)"}, {
        "positions": result.positions, "orientations": result.orientations,
        "pose_branch_evaluations": result.pose_branch_evaluations,
        "reachable_positions": result.reachable_positions, "reachable_poses": result.reachable_poses,
        "mean_redundancy": result.mean_redundancy, "model": result.model, "model_error": result.model_error or None,
        "cell": None if cell is None else {"scene": cell[1].source, "obstacles": list(cell[1].names),
                                           "margin": cell[1].margin, "body": cell[0].source, "capsules": len(cell[0]),
                                           "self_pairs": len(cell[0].pairs)},
    })
    if args.json:
        print_json(summary)
    else:
        whose = (" of its exact S-R-S neighbour" if result.model_error else
                 " of the real nearly S-R-S arm, certified" if result.model == MODEL_CERTIFIED else "")
        print(f"{chain.name}: {result.positions} positions x {result.orientations} orientations x 8 branches "
              f"= {result.pose_branch_evaluations} {'feasible' if whose.endswith('certified') else 'exact feasible'} "
              f"sets{whose}")
        if cell is not None:
            print(f"in the cell {cell[1].source}: {plural(len(cell[1]), 'obstacle')} and "
                  f"{plural(len(cell[0].pairs), 'pair')} of the arm's own capsules at margin {cell[1].margin:g} m "
                  f"({plural(len(cell[0]), 'capsule')}, {cell[0].source}): the certified collision-free sets")
        if result.model_error:
            print(f"nearly S-R-S: {result.model_error}")
            print("the map holds the neighbour's exact feasible sets, not the real arm's (they differ near the sets' "
                  "ends and near singular wrists)")
        print(f"reachable: {100 * result.reachable_positions:.1f}% of positions, "
              f"{100 * result.reachable_poses:.1f}% of poses; mean redundancy there {result.mean_redundancy:.3f}")
        print_run(summary)
    return 0

