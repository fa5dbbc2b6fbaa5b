"""Report section: exact reachability and redundancy maps of the PA10-7C and the iiwa, and paper 000's Gamma as one
line.

The maps are computed here with :func:`redkin.workspace.feasible_measures`
directly (numpy only, no Dask), the function every chunk of ``redkin
workspace`` calls, at a resolution that keeps the report quick.
"""

from __future__ import annotations

from collections.abc import Callable

import matplotlib.pyplot as plt
import numpy as np

from redkin.arms import arm
from redkin.models import kuka_iiwa14, pa10_7c
from redkin.plot.workspace import mid_plane_figure, plot_measure_line
from redkin.references import REFERENCES
from redkin.reproduce import Section, section_key
from redkin.reproduce import printed as P
from redkin.reproduce.comparison import Comparison, Note
from redkin.reproduce.report import SectionWriter
from redkin.srs import BRANCHES
from redkin.srs.geometry import SRSGeometry, srs_geometry
from redkin.workspace import (
    feasible_measures,
    reachability_index,
    redundancy_index,
    super_fibonacci_rotations,
    workspace_grid,
)

#: Grid points per axis of the report's maps (odd: the mid-planes pass through the shoulder).
_RESOLUTION = 15
#: Orientations per position of the report's maps (a super-Fibonacci set).
_ORIENTATIONS = 64
#: Margin of the box beyond the arm's longest reach from the shoulder, metres.
_MARGIN = 0.05
#: Paper 000, section 6.2.2: the tool held at this position (metres) and turned about z by gamma from
#: [000 eq. 41]'s rotation.
_GAMMA_POSITION = np.array([0.65, 0.0, 0.5])
#: The line's orientations, degrees (one per degree).
_GAMMA_GRID_DEG = np.arange(-180.0, 180.0, 1.0)
TOL = 5e-4  # half of the last printed digit (3 decimals, degrees)


def _reach_box(geometry: SRSGeometry) -> tuple[float, ...]:
    """``(xmin, xmax, ymin, ymax, zmin, zmax)``: the cube centred on the shoulder that holds every tool position."""
    shoulder = geometry.chain.base[:3, :3] @ np.array([0.0, 0.0, geometry.d_bs]) + geometry.chain.base[:3, 3]
    half = geometry.d_se + geometry.d_ew + geometry.d_wt + abs(geometry.a3) + abs(geometry.a4) + _MARGIN
    return tuple(float(v) for centre in shoulder for v in (centre - half, centre + half))


def _exact_map(geometry: SRSGeometry, resolution: int, orientations: int) -> dict[str, np.ndarray]:
    """The map of ``redkin workspace`` over :func:`_reach_box`, in memory: axes, rotations, measure and indices.

    Returns
    -------
    dict
        ``x, y, z`` (metres), ``rotation`` ``(N, 3, 3)``, ``measure`` ``(M, M, M, N, 8)`` in radians,
        ``reachability`` and ``redundancy`` ``(M, M, M)``.
    """
    grid = workspace_grid(_reach_box(geometry), resolution, orientations, chunk=resolution)
    rotations = super_fibonacci_rotations(orientations)
    positions = grid.chunk_positions((0, 0, 0))  # the whole grid is one chunk
    measure = feasible_measures(arm(geometry.chain), positions.reshape(-1, 3), rotations)
    measure = measure.reshape(positions.shape[:3] + measure.shape[1:])
    x, y, z = grid.axes
    return {"x": x, "y": y, "z": z, "rotation": rotations, "measure": measure,
            "reachability": reachability_index(measure), "redundancy": redundancy_index(measure)}


def _gamma_rotations(gamma: np.ndarray) -> np.ndarray:
    """Paper 000's tool orientation of section 6.2.2: [000 eq. 41]'s rotation turned about the base z axis by
    ``gamma``."""
    c, s = np.cos(gamma), np.sin(gamma)
    rotations = np.zeros(np.shape(gamma) + (3, 3))
    rotations[..., 0, 0], rotations[..., 0, 1], rotations[..., 1, 0], rotations[..., 1, 1] = -c, -s, -s, c
    rotations[..., 2, 2] = -1.0
    return rotations


def _gamma_line(geometry: SRSGeometry, gamma: np.ndarray) -> np.ndarray:
    """One line of the map: the measure at :data:`_GAMMA_POSITION` for the orientations ``gamma``, shape ``(K, 8)``."""
    return feasible_measures(arm(geometry.chain), _GAMMA_POSITION[None],
                             _gamma_rotations(np.asarray(gamma, dtype=float)))[0]


def _line_boundary(inside: Callable[[np.ndarray], np.ndarray], steps: int = 60) -> tuple[float, float]:
    """Largest turns ``-g``, ``+g`` with ``inside`` true, by bisection on ``[0, pi]`` for each sign at once.

    ``inside(gamma)`` maps an array of turns to booleans; it must hold at 0 and fail at ``+-pi``.
    """
    low, high = np.zeros(2), np.full(2, np.pi)
    sense = np.array([-1.0, 1.0])
    for _ in range(steps):
        middle = 0.5 * (low + high)
        ok = inside(sense * middle)
        low, high = np.where(ok, middle, low), np.where(ok, high, middle)
    return float(-low[0]), float(low[1])


def _map_rows(name: str, box: tuple[float, ...], result: dict[str, np.ndarray]) -> list:
    reach, redundancy = result["reachability"], result["redundancy"]
    reached = reach > 0.0
    measure = result["measure"]
    return [name, " ".join(f"{v:.3f}" for v in box), f"{reach.shape[0]}^3", measure.shape[3], measure.size,
            100.0 * reached.mean(), 100.0 * reach.mean(), float(redundancy[reached].mean()) if reached.any() else 0.0,
            float(redundancy.max())]


def _section_maps(writer: SectionWriter, arms: dict[str, SRSGeometry]) -> None:
    writer.heading("Exact maps of the PA10-7C and the KUKA iiwa 14")
    rows = []
    for name, geometry in arms.items():
        box = _reach_box(geometry)
        result = _exact_map(geometry, _RESOLUTION, _ORIENTATIONS)
        rows.append(_map_rows(name, box, result))
        writer.data(f"{name}_map", result, f"The {name} map as numpy arrays (.npz for numpy.load: x, y, z, rotation, "
                                           "measure, reachability, redundancy)")
        fig = mid_plane_figure([result[a] for a in "xyz"],
                               {"reachability": result["reachability"], "redundancy": result["redundancy"]},
                               f"{name}: exact reachability and redundancy, {_RESOLUTION}^3 positions x "
                               f"{_ORIENTATIONS} orientations x 8 branches")
        writer.figure(fig, f"{name}_map", f"{name}: reachability and redundancy on the mid-planes through the shoulder",
                      "Top: the fraction of the orientations with a feasible arm angle on some branch. Bottom: the "
                      "mean over those orientations of the best branch's feasible arm-angle measure / 2 pi.")
        writer.progress(0.1 + 0.4 * len(rows), name)
    writer.table(
        "maps", ["arm", "box [m]", "grid", "orientations", "pose-branch sets", "reachable positions [%]",
                 "reachable poses [%]", "mean redundancy where reachable", "max redundancy"], rows,
        "The maps: reachability and redundancy indices",
        f"The box is the cube centred on the shoulder whose half-width is the longest reach plus {_MARGIN} m. "
        "A position is reachable if some orientation has a non-empty feasible arm-angle set on some branch; "
        "reachable poses is the mean reachability index. The redundancy index is the mean, over the reachable "
        "orientations of a position, of the largest branch measure / 2 pi.",
    )
    (pa10, iiwa) = rows
    writer.text(
        f"The PA10-7C, with paper 000's Table 2 limits, holds its tool at {pa10[5]:.1f}% of its box's positions in "
        f"some orientation, and keeps {pa10[7]:.2f} of the circle of arm angles free there on average; the iiwa, "
        f"with its wider joint ranges, reaches {iiwa[5]:.1f}% and keeps {iiwa[7]:.2f}. Both maps have a hole around "
        "the shoulder. Near full stretch few orientations are reachable, but those leave most arm angles free: there "
        "the iiwa's redundancy is highest."
    )


def _section_gamma(writer: SectionWriter, geometry: SRSGeometry) -> None:
    writer.heading("§6.2.2's Gamma as one line of the PA10's map")
    gamma = np.radians(_GAMMA_GRID_DEG)
    line = _gamma_line(geometry, gamma)
    names = [str(b) for b in BRANCHES]
    plus = names.index("+++")
    low, high = _line_boundary(lambda g: _gamma_line(geometry, g)[:, plus] > 0.0)
    any_low, any_high = _line_boundary(lambda g: _gamma_line(geometry, g).max(axis=-1) > 0.0)
    others = [name for i, name in enumerate(names) if i != plus and np.any(line[:, i] > 0.0)]
    branch_note = Note("the paper follows branch +++; the map's reachability takes any branch",
                       "every other branch is empty all along this line, so the map's reachability ends where +++ ends"
                       if not others else f"branches {', '.join(others)} are non-empty on this line too")
    rows = [
        Comparison("Gamma lower [deg] (psi controlled): measure on +++ > 0", -P.SECTION_6_2_2_GAMMA,
                   float(np.degrees(low)), TOL),
        Comparison("Gamma upper [deg] (psi controlled): measure on +++ > 0", P.SECTION_6_2_2_GAMMA,
                   float(np.degrees(high)), TOL),
        Comparison("Gamma lower [deg]: map reachability (any branch)", -P.SECTION_6_2_2_GAMMA,
                   float(np.degrees(any_low)), TOL, branch_note),
        Comparison("Gamma upper [deg]: map reachability (any branch)", P.SECTION_6_2_2_GAMMA,
                   float(np.degrees(any_high)), TOL, branch_note),
        Comparison("measure on +++ at gamma = 0 [deg] (the pose of [000 eq. 41])",
                   round(2 * P.SECTION_6_1_PSI_BOUND, 3),
                   float(np.degrees(line[np.flatnonzero(_GAMMA_GRID_DEG == 0.0)[0], plus])), 1e-3,
                   Note("paper value derived: the width of section 6.1's Psi = [-45.991, 45.991]",
                        "2 x 45.991; tolerance 1e-3, twice the printed half digit")),
    ]
    writer.comparison(
        "gamma_line", rows, "Section 6.2.2: how far the tool turns with psi controlled, read off one line of the map",
        "The map's position x = (0.65, 0, 0.5) m with the orientations of [000 eq. 41] turned about z by gamma: the "
        "measure of the feasible arm-angle set per branch, as every map entry. Gamma is where the measure falls to 0, "
        "found by bisection on the map's measure function (feasible_measures) to machine precision. "
        "Gamma_0 = [-120, 120] deg (psi fixed at 0) asks whether psi = 0 lies in the set, which the measure does not "
        "say; section 000 compares it.",
    )
    writer.data("gamma_line", {"gamma": gamma, "measure": line},
                "The line as numpy arrays (.npz for numpy.load: gamma in rad, measure (360, 8) in rad)")
    fig, ax = plt.subplots(figsize=(7, 3.8))
    plot_measure_line(ax, _GAMMA_GRID_DEG, line, names, "tool turn gamma about z [deg]")
    for bound in (low, high):
        ax.axvline(np.degrees(bound), color="0.4", linestyle="--", linewidth=0.8)
    writer.figure(fig, "gamma_line", "The measure along the line of section 6.2.2 (PA10-7C)",
                  "Dashed: our Gamma, where the +++ measure reaches 0. At gamma = 0 the pose is [000 eq. 41]'s and the "
                  "set is section 6.1's.")
    writer.text(
        "The line reproduces the paper's Gamma to its printed digits: nothing here disagrees with paper 000. The map "
        "adds what the paper's single branch does not show: no other branch is feasible anywhere along this line."
        if not others else
        "The line reproduces the paper's Gamma on branch +++; other branches are feasible along the line too "
        f"({', '.join(others)}), so the map's reachability may reach further than the paper's Gamma."
    )


def build(writer: SectionWriter) -> None:
    writer.text(
        "Exact workspace maps (redkin.workspace, issue 14): for every position of a grid and every orientation of a "
        "near-uniform set, the measure of the feasible arm-angle set on each of the 8 branches, from paper 000's "
        "closed form ([000 eq. 30]) instead of sampled IK. Computed here in one process with feasible_measures, the "
        f"function each Dask chunk of redkin workspace calls, at a modest {_RESOLUTION}^3 positions x {_ORIENTATIONS} "
        "orientations; redkin workspace computes the same maps at any resolution, on Dask, into Zarr."
    )
    arms = {chain.name: srs_geometry(chain) for chain in (pa10_7c(), kuka_iiwa14())}
    _section_maps(writer, arms)
    _section_gamma(writer, arms["pa10-7c"])


SECTION = Section(
    key=section_key(__name__),
    title="Workspace maps: exact reachability and redundancy (paper 000's feasible sets over a grid)",
    reference=REFERENCES["000"] + " [000 eq. 30] and section 6.2.2.",
    build=build,
)
