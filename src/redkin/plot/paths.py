"""Figures of path resolution (issue 26): the (waypoint, arm angle) plane of each branch, or the (waypoint, q7)
plane of a Franka-class arm.

The exact feasible arm angles (or values of q7) of every waypoint are shaded (the pieces of
:func:`redkin.paths.feasible_along_path`), the global path of
:func:`redkin.paths.resolve_path` is drawn through them with its branch
changes marked, the baselines beside it with their first failure, and a
path that does not exist is marked at its failing waypoint and joint.  In a cell
the shaded sets are the certified collision-free ones, and the stretches the
obstacles (or the arm's own links) remove are drawn in a colour per cause
(:func:`redkin.paths.removed_along_path`), so a failing path shows which pair
took every value at its waypoint.  Plotting only: every set and path is computed
by the caller.
"""

from __future__ import annotations

from collections.abc import Sequence

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.collections import PolyCollection
from matplotlib.lines import Line2D
from matplotlib.patches import Patch
from matplotlib.ticker import MaxNLocator

from redkin.circle import TWO_PI
from redkin.errors import RedkinError
from redkin.paths import BaselinePath, PathResult, Removed
from redkin.srs.branches import BRANCHES
from redkin.srs.feasible import FeasiblePieces

#: Colour and width of the global path's line; the baselines take the colours after it.
_PATH_COLOUR, _PATH_WIDTH = "k", 1.8
_BASELINE_COLOURS = ("C1", "C3", "C4", "C5", "C6")
_FEASIBLE_COLOUR = "C2"
#: The colours of the causes of removed stretches, in order of first appearance (not the feasible green nor the
#: failure's red; the last one also stands for every cause beyond them), and of an undecided stretch.
_CAUSE_COLOURS = ("C0", "C1", "C4", "C5", "C6", "C8", "C9")
_UNDECIDED_COLOUR = "C7"


def _wrapped_degrees(psi: np.ndarray, wraps: bool = True) -> np.ndarray:
    """Arm angles in degrees in ``[-180, 180)`` (``wraps``), or a joint value (q7) in degrees as it is."""
    values = np.asarray(psi, dtype=float)
    return np.degrees(np.mod(values + np.pi, TWO_PI) - np.pi if wraps else values)


def _broken(x: np.ndarray, y: np.ndarray, keep: np.ndarray, wraps: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """The points ``keep``, with a NaN between neighbours that are not consecutive waypoints or that wrap across
    +-180 deg (a line is not drawn through the gap)."""
    x, y = x[keep], y[keep]
    gap = (np.diff(x) != 1) | ((np.abs(np.diff(y)) > 180.0) & wraps)
    at = np.flatnonzero(gap) + 1
    return np.insert(x.astype(float), at, np.nan), np.insert(y, at, np.nan)


def _feasible_rectangles(pieces: FeasiblePieces, branch: int, wraps: bool = True) -> np.ndarray:
    """One rectangle (4 corners, degrees) per feasible piece of ``branch`` and waypoint, (M, 4, 2); a piece that
    wraps past 180 deg split in two (``wraps``: arm angles; q7's pieces are drawn as they are)."""
    start, end = pieces.start[:, branch], pieces.end[:, branch]
    waypoint, slot = np.nonzero(pieces.feasible[:, branch] & (end > start))
    lo, hi = start[waypoint, slot], end[waypoint, slot]
    shift = np.floor((lo + np.pi) / TWO_PI) * TWO_PI if wraps else np.zeros_like(lo)  # the start into [-pi, pi)
    lo, hi = lo - shift, hi - shift
    past = (hi > np.pi) & wraps
    x = np.concatenate([waypoint, waypoint[past]]).astype(float)
    y0 = np.degrees(np.concatenate([lo, np.full(past.sum(), -np.pi)]))
    y1 = np.degrees(np.concatenate([np.where(wraps, np.minimum(hi, np.pi), hi), hi[past] - TWO_PI]))
    corners_x = np.stack([x - 0.5, x + 0.5, x + 0.5, x - 0.5], axis=-1)
    corners_y = np.stack([y0, y0, y1, y1], axis=-1)
    return np.stack([corners_x, corners_y], axis=-1)


def _removed_rectangles(removed: Sequence[Sequence[Sequence[Removed]]], branch: int,
                        wraps: bool) -> dict[str, list[np.ndarray]]:
    """Per cause, one rectangle (4 corners, degrees) per stretch of ``branch`` that the cell removes at each waypoint
    (``removed[k][branch]``); a stretch through +-180 deg split in two (``wraps``)."""
    rectangles: dict[str, list[np.ndarray]] = {}
    for k, stretches in enumerate(row[branch] for row in removed):
        for start, end, cause in stretches:
            spans = [(start, end)] if start <= end or not wraps else [(start, np.pi), (-np.pi, end)]
            for lo, hi in spans:
                y0, y1 = np.degrees(lo), np.degrees(hi)
                rectangles.setdefault(cause, []).append(np.array([[k - 0.5, y0], [k + 0.5, y0], [k + 0.5, y1],
                                                                  [k - 0.5, y1]]))
    return rectangles


def _cause_colours(removed: Sequence[Sequence[Sequence[Removed]]]) -> dict[str, str]:
    """A colour per cause of the removed stretches, in order of first appearance (undecided ones grey; causes beyond
    :data:`_CAUSE_COLOURS` share its last colour)."""
    colours: dict[str, str] = {}
    for row in removed:
        for stretches in row:
            for stretch in stretches:
                if stretch.cause not in colours:
                    named = sum(cause != "undecided" for cause in colours)
                    colours[stretch.cause] = (_UNDECIDED_COLOUR if stretch.cause == "undecided" else
                                              _CAUSE_COLOURS[min(named, len(_CAUSE_COLOURS) - 1)])
    return colours


def _shown_branches(pieces: FeasiblePieces, result: PathResult, baselines: Sequence[BaselinePath],
                    removed: Sequence[Sequence[Sequence[Removed]]] = ()) -> list[int]:
    """The branches with a feasible arm angle somewhere along the path, a stretch the cell removes, or used by a
    path drawn (at least one)."""
    used = set(result.branch) | {b for baseline in baselines for b in baseline.branch if b}
    shown = [b for b, name in enumerate(map(str, BRANCHES))
             if pieces.feasible[:, b].any() or name in used or any(row[b] for row in removed)]
    return shown or [0]


def _plot_branch_plane(ax, pieces: FeasiblePieces, branch: int, result: PathResult,
                       baselines: Sequence[BaselinePath] = (), removed: Sequence[Sequence[Sequence[Removed]]] = (),
                       colours: dict[str, str] | None = None) -> None:
    """One branch's (waypoint, arm angle) plane: feasible arm angles shaded, the stretches a cell removes in their
    causes' ``colours``, the paths drawn on it.

    The artists carry ids (``get_gid()``): ``"feasible"`` (the shading), ``"removed: <cause>"``, ``"path"``,
    ``"branch change"``, ``"no path"``, each baseline's method and ``"<method> fails"``.

    Parameters
    ----------
    ax : matplotlib Axes
    pieces : FeasiblePieces
        Of shape ``(N, 8, 24)`` (:func:`redkin.paths.feasible_along_path`).
    branch : int
        Index into :data:`redkin.srs.BRANCHES`.
    result : PathResult
        The global path (drawn where it is on this branch, a diamond where it changes branch), or a failure
        (a vertical line at its waypoint).
    baselines : sequence of BaselinePath
        Drawn where they are on this branch, a cross at each one's first failure.
    removed : sequence, optional
        Per waypoint and branch, the stretches a cell removes (:func:`redkin.paths.removed_along_path`).
    colours : dict, optional
        The colour of each cause in ``removed``.
    """
    name = str(BRANCHES[branch])
    count = pieces.start.shape[0]
    wraps = result.parameter == "psi"
    rectangles = list(_feasible_rectangles(pieces, branch, wraps))
    ax.add_collection(PolyCollection(rectangles, facecolors=_FEASIBLE_COLOUR, alpha=0.35, linewidths=0, gid="feasible"))
    for cause, cause_rectangles in _removed_rectangles(removed, branch, wraps).items():
        ax.add_collection(PolyCollection(cause_rectangles, facecolors=(colours or {}).get(cause, _UNDECIDED_COLOUR),
                                         alpha=0.55, linewidths=0, gid=f"removed: {cause}"))
    waypoints = np.arange(count)
    for baseline, colour in zip(baselines, _BASELINE_COLOURS):
        on = np.array([b == name for b in baseline.branch]) & np.isfinite(baseline.psi)
        y = _wrapped_degrees(np.where(on, baseline.psi, 0.0))
        ax.plot(*_broken(waypoints, y, on), color=colour, linewidth=1.0, linestyle="--", gid=baseline.method)
        k = baseline.first_failure
        if k is not None and on[k]:
            ax.plot([k], [y[k]], "X", color=colour, markersize=8, markeredgecolor="k", markeredgewidth=0.5,
                    gid=f"{baseline.method} fails")
        elif k is not None and not np.isfinite(baseline.psi[k]):  # no arm angle there: the whole column
            ax.axvline(k, color=colour, linestyle=":", linewidth=1.2, gid=f"{baseline.method} fails")
    if result.ok:
        on = np.array([b == name for b in result.branch])
        y = _wrapped_degrees(result.psi, wraps)
        ax.plot(*_broken(waypoints, y, on, wraps), color=_PATH_COLOUR, linewidth=_PATH_WIDTH, gid="path")
        change = np.r_[False, np.array(result.branch[1:]) != np.array(result.branch[:-1])]
        ends = on & (change | np.r_[change[1:], False])  # both sides of a change
        ax.plot(waypoints[ends], y[ends], "D", color="k", markerfacecolor="w", markersize=5, gid="branch change")
    elif result.failure is not None:
        failure = result.failure
        ax.axvline(failure.waypoint, color="C3", linewidth=1.5, gid="no path")
        ax.text(failure.waypoint, 175 if wraps else 0.0, f" {_failure_words(failure)}", color="C3", fontsize=7,
                va="top")
    ax.set_xlim(-0.5, count - 0.5)
    if wraps:
        ax.set_ylim(-180, 180)
        ax.set_yticks([-180, -90, 0, 90, 180])
    else:
        ax.autoscale_view(scalex=False)
    ax.xaxis.set_major_locator(MaxNLocator(integer=True))
    ax.set_title(f"branch {name}", fontsize=9)


def _failure_words(failure) -> str:
    """A failure's reason, with its joint or, in a cell, the pair that blocks it."""
    if failure.pair is not None:
        return f"{failure.reason}, {failure.pair[0]} meets {failure.pair[1]}"
    return failure.reason + ("" if failure.joint is None else f", joint {failure.joint}")


def _legend_causes(colours: dict[str, str]) -> dict[str, str]:
    """The causes the legend names, each with its colour: those with a colour of their own, then the ones that share
    the last colour as one entry ("other pairs"), then the undecided stretches."""
    shown: dict[str, str] = {}
    shared = _CAUSE_COLOURS[-1]
    for cause, colour in colours.items():
        if cause != "undecided" and (colour != shared or list(colours.values()).count(shared) == 1):
            shown[cause] = colour
    if list(colours.values()).count(shared) > 1:
        shown["other pairs"] = shared
    if "undecided" in colours:
        shown["undecided"] = _UNDECIDED_COLOUR
    return shown


def path_plane_figure(pieces: FeasiblePieces, result: PathResult, baselines: Sequence[BaselinePath] = (),
                      title: str = "", exact: bool = True,
                      removed: Sequence[Sequence[Sequence[Removed]]] = ()) -> plt.Figure:
    """The (waypoint, arm angle) plane of every branch that has a feasible arm angle along the path, a stretch a
    cell removes, or a path drawn, one panel each, with a legend that names each baseline's first failure, the
    global path's clearance or failure (waypoint, reason, joint or, in a cell, the pair) and each cause of the
    stretches the cell removes.

    Parameters
    ----------
    pieces : FeasiblePieces
        Of shape ``(N, 8, 24)`` (:func:`redkin.paths.feasible_along_path`).
    result : PathResult
        :func:`redkin.paths.resolve_path` on the same poses.
    baselines : sequence of BaselinePath
        At most five (:func:`redkin.paths.fixed_psi_path`, :func:`redkin.paths.clamped_optimum_path`,
        :func:`redkin.paths.greedy_path`, :func:`redkin.paths.judge_path`).
    title : str
    exact : bool
        Whether the sets are a closed form's; ``False`` for a nearly S-R-S arm's certified sets (the legend says
        which).
    removed : sequence, optional
        In a cell: per waypoint and branch, the stretches the cell removes (:func:`redkin.paths.removed_along_path`),
        with ``pieces`` the collision-free ones (:func:`redkin.paths.feasible_along_path` with the cell).
    """
    if len(baselines) > len(_BASELINE_COLOURS):
        raise RedkinError(f"at most {len(_BASELINE_COLOURS)} baselines in one figure, got {len(baselines)}")
    shown = _shown_branches(pieces, result, baselines, removed)
    colours = _cause_colours(removed)
    columns = 1 if len(shown) <= 3 else 2
    rows = -(-len(shown) // columns)
    fig, axes = plt.subplots(rows, columns, figsize=(6.0 * columns, 1.2 + 2.0 * rows), sharex=True, sharey=True,
                             squeeze=False)
    for ax, branch in zip(axes.ravel(), shown):
        _plot_branch_plane(ax, pieces, branch, result, baselines, removed, colours)
    for ax in axes.ravel()[len(shown):]:
        ax.set_visible(False)
    what = "arm angle psi" if result.parameter == "psi" else "q7"
    for ax in axes[:, 0]:
        ax.set_ylabel(f"{what} [deg]")
    for ax in axes[-1]:
        ax.set_xlabel("waypoint")
    sets = "collision-free, certified" if removed else ("exact" if exact else "certified on the real arm")
    handles: list = [Patch(color=_FEASIBLE_COLOUR, alpha=0.35,
                           label=f"feasible {'arm angles' if result.parameter == 'psi' else 'q7'} ({sets})")]
    if result.ok:
        clearance = f"clearance {np.degrees(result.clearance):.3g} deg"
        handles.append(Line2D([], [], color=_PATH_COLOUR, linewidth=_PATH_WIDTH, label=f"global path ({clearance})"))
        if len(set(result.branch)) > 1:
            handles.append(Line2D([], [], marker="D", color="k", markerfacecolor="w", linestyle="none",
                                  label="global path changes branch"))
    elif result.failure is not None:
        handles.append(Line2D([], [], color="C3", linewidth=1.5,
                              label=f"no path: waypoint {result.failure.waypoint}, {_failure_words(result.failure)}"))
    handles += [Patch(color=colour, alpha=0.55, label=f"removed: {cause}") for cause, colour in
                _legend_causes(colours).items()]
    for baseline, colour in zip(baselines, _BASELINE_COLOURS):
        k = baseline.first_failure
        what = "keeps every limit and the bound" if k is None else f"fails at waypoint {k}: {baseline.reason}"
        if k is not None and baseline.joint is not None:
            what += f", joint {baseline.joint}"
        handles.append(Line2D([], [], color=colour, linestyle="--", marker=None if k is None else "X",
                              markeredgecolor="k", markeredgewidth=0.5, label=f"{baseline.method} ({what})"))
    if title:
        fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.legend(handles=handles, loc="upper center", ncol=2 if len(handles) > 3 else len(handles), fontsize=8,
               frameon=False, bbox_to_anchor=(0.5, 0.0))  # below the panels: save with bbox_inches="tight"
    return fig
