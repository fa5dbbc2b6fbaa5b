"""The (waypoint, arm angle) plane of path resolution (redkin.plot.paths): the shading is the exact feasible set
of every waypoint and branch, the path is drawn where it is, the baselines' and the path's failures are marked."""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pytest

from redkin.circle import arc_length
from redkin.models import get_robot
from redkin.paths import (
    cell_along_path,
    clamped_optimum_path,
    feasible_along_path,
    fixed_psi_path,
    greedy_path,
    removed_along_path,
    resolve_path,
)
from redkin.plot.paths import path_plane_figure
from redkin.srs import BRANCHES

NAMES = [str(b) for b in BRANCHES]


@pytest.fixture(scope="module")
def iiwa_case():
    """The path of docs/paths.md: the global path changes branch through a wrist singularity, the per-pose
    baselines break the bound."""
    chain = get_robot("kuka-iiwa14")
    q0 = np.array([0.3, 0.6, -0.2, -1.2, 0.4, 0.8, 0.1])
    q1 = np.array([-0.5, 0.9, 0.4, -0.7, -0.3, -0.6, 0.9])
    poses = chain.fk(q0 + (q1 - q0) * np.linspace(0.0, 1.0, 20)[:, None])
    result = resolve_path(chain, poses, 0.1)
    start = (float(result.psi[0]), result.branch[0])
    baselines = [fixed_psi_path(chain, poses, 0.1, *start), clamped_optimum_path(chain, poses, 0.1, start[1]),
                 greedy_path(chain, poses, 0.1)]
    return chain, poses, result, baselines


def _panels(fig):
    return {ax.get_title().removeprefix("branch "): ax for ax in fig.axes if ax.get_visible()}


def _artists(ax, gid):
    return [a for a in [*ax.lines, *ax.collections] if a.get_gid() == gid]


def test_the_shading_is_the_exact_feasible_set_of_each_waypoint(iiwa_case):
    chain, poses, result, baselines = iiwa_case
    pieces = feasible_along_path(chain, poses)
    fig = path_plane_figure(pieces, result, baselines)
    panels = _panels(fig)
    assert set(panels) == {name for b, name in enumerate(NAMES) if pieces.feasible[:, b].any()}
    for name, ax in panels.items():
        (shading,) = _artists(ax, "feasible")
        height = np.zeros(len(poses))
        for path in shading.get_paths():
            corners = path.vertices[:4]
            k = int(round(corners[:, 0].mean()))
            assert corners[:, 0].min() == pytest.approx(k - 0.5) and corners[:, 0].max() == pytest.approx(k + 0.5)
            assert -180.0 <= corners[:, 1].min() <= corners[:, 1].max() <= 180.0
            height[k] += np.ptp(corners[:, 1])
        expected = [np.degrees(pieces.arc_set((k, NAMES.index(name))).length) for k in range(len(poses))]
        np.testing.assert_allclose(height, expected, rtol=0, atol=1e-9)
        assert ax.get_ylim() == (-180.0, 180.0)
    plt.close(fig)


def test_the_path_is_drawn_on_its_branches_with_the_changes_marked(iiwa_case):
    chain, poses, result, baselines = iiwa_case
    assert len(set(result.branch)) == 2  # through the wrist singularity
    fig = path_plane_figure(feasible_along_path(chain, poses), result, baselines)
    change = next(k for k in range(1, len(poses)) if result.branch[k] != result.branch[k - 1])
    for name, ax in _panels(fig).items():
        lines = _artists(ax, "path")
        on = [k for k, b in enumerate(result.branch) if b == name]
        if not on:
            assert not lines or np.isnan(lines[0].get_xdata()).all()
            continue
        x, y = lines[0].get_xdata(), lines[0].get_ydata()
        drawn = ~np.isnan(y)
        np.testing.assert_array_equal(x[drawn], on)
        np.testing.assert_allclose(y[drawn], np.degrees(result.psi[on]), atol=1e-12)
        (marks,) = _artists(ax, "branch change")
        assert set(marks.get_xdata().tolist()) == {change - 1, change} & set(on)
    plt.close(fig)


def test_each_baseline_is_drawn_and_its_first_failure_marked_and_named(iiwa_case):
    chain, poses, result, baselines = iiwa_case
    fig = path_plane_figure(feasible_along_path(chain, poses), result, baselines)
    legend = [t.get_text() for t in fig.legends[0].get_texts()]
    assert any(text.startswith("global path (clearance") for text in legend)
    for baseline in baselines:
        k = baseline.first_failure
        assert k is not None  # every per-pose choice fails on this path
        assert f"{baseline.method} (fails at waypoint {k}: {baseline.reason}, joint {baseline.joint})" in legend
        panel = _panels(fig)[baseline.branch[k]]
        (cross,) = _artists(panel, f"{baseline.method} fails")
        assert cross.get_xdata().tolist() == [k]
        assert cross.get_ydata()[0] == pytest.approx(np.degrees(np.mod(baseline.psi[k] + np.pi, 2 * np.pi) - np.pi))
    plt.close(fig)


def test_a_failure_is_marked_at_its_waypoint_on_every_panel():
    chain = get_robot("kuka-iiwa14")
    q = np.array([0.2, 0.8, 0.1, -1.4, 0.3, 0.9, 0.0]) + np.linspace(-0.2, 0.2, 9)[:, None] * np.array(
        [1.0, 0.5, -0.5, 0.0, 0.5, 0.5, 1.0])
    q[6:, 3] = -2.2  # the elbow beyond its limit from waypoint 6 on
    poses = chain.fk(q)
    result = resolve_path(chain, poses, 1.0)
    pieces = feasible_along_path(chain, poses)
    assert not pieces.feasible[6:].any()
    fig = path_plane_figure(pieces, result, [greedy_path(chain, poses, 1.0)])
    for ax in _panels(fig).values():
        (line,) = _artists(ax, "no path")
        assert line.get_xdata()[0] == 6
        assert not _artists(ax, "path")
        assert any(t.get_text() == " empty, joint 4" for t in ax.texts)
    legend = [t.get_text() for t in fig.legends[0].get_texts()]
    assert "no path: waypoint 6, empty, joint 4" in legend
    assert "greedy (fails at waypoint 6: no-solution)" in legend
    plt.close(fig)


def test_a_waypoint_out_of_reach_has_an_empty_column():
    chain = get_robot("pa10-7c")
    q = np.array([0.1, 0.5, 0.2, 1.2, -0.3, 0.6, 0.2]) + np.linspace(0.0, 0.2, 5)[:, None]
    poses = chain.fk(q)
    poses[3, :3, 3] *= 10.0
    pieces = feasible_along_path(chain, poses)
    assert pieces.feasible.shape == (5, 8, 24) and not pieces.feasible[3].any() and np.isnan(pieces.start[3]).all()
    np.testing.assert_array_equal(pieces.feasible[:3], feasible_along_path(chain, poses[:3]).feasible)
    result = resolve_path(chain, poses, 0.5)
    assert (result.failure.waypoint, result.failure.reason) == (3, "out-of-reach")
    fig = path_plane_figure(pieces, result)
    for ax in _panels(fig).values():
        assert _artists(ax, "no path")[0].get_xdata()[0] == 3
    plt.close(fig)


def test_too_many_baselines_are_refused(iiwa_case):
    chain, poses, result, baselines = iiwa_case
    with pytest.raises(ValueError, match="at most 5 baselines"):
        path_plane_figure(feasible_along_path(chain, poses), result, baselines * 2)



@pytest.fixture(scope="module")
def cell_case():
    """Twelve iiwa14 waypoints past a post, with a ball at the hand of waypoint 5: every arm angle of waypoints
    4-6 collides (the hand's link meets the ball on every branch), so no path exists."""
    from redkin.collision import BodyCapsule, body_of, scene_of

    chain = get_robot("kuka-iiwa14")
    qs = np.linspace([0.3, 0.6, -0.2, -1.2, 0.4, 0.8, 0.1], [-0.5, 0.9, 0.4, -0.7, -0.3, -0.6, 0.9], 12)
    poses = chain.fk(qs)
    body = body_of([BodyCapsule("link_3", 3, (0, 0, -0.2), (0, 0, 0), 0.06),
                    BodyCapsule("link_4", 4, (0, 0, 0), (0, 0.2, 0), 0.06),
                    BodyCapsule("link_7", 7, (0, 0, 0.05), (0, 0, 0.05), 0.06)], chain)
    hand = chain.frames(qs[5])[7, :3, 3]
    scene = scene_of({"margin": 0.01, "obstacles": [
        {"name": "post", "type": "capsule", "a": [0.4, 0.3, 0], "b": [0.4, 0.3, 1.2], "radius": 0.05},
        {"name": "ball", "type": "sphere", "center": hand.tolist(), "radius": 0.03}]})
    return chain, poses, body, scene, resolve_path(chain, poses, 0.2, body=body, scene=scene)


def _heights(ax, gid, count):
    """Per waypoint, the total height (degrees) of the rectangles of the collection ``gid`` on ``ax``."""
    height = np.zeros(count)
    for collection in _artists(ax, gid):
        for path in collection.get_paths():
            corners = path.vertices[:4]
            height[int(round(corners[:, 0].mean()))] += np.ptp(corners[:, 1])
    return height


def test_in_a_cell_the_free_and_removed_stretches_fill_the_limit_sets(cell_case):
    """Each panel's collision-free shading and the stretches drawn as removed by the cell together cover exactly the
    waypoint's limit-feasible arm angles (to the sets' resolution), and every branch whose limits leave arm angles
    somewhere is drawn."""
    chain, poses, body, scene, result = cell_case
    limits = feasible_along_path(chain, poses)
    removed = removed_along_path(chain, poses, body, scene)
    fig = path_plane_figure(feasible_along_path(chain, poses, body=body, scene=scene), result, removed=removed)
    panels = _panels(fig)
    assert set(panels) == {name for b, name in enumerate(NAMES) if limits.feasible[:, b].any()}
    for name, ax in panels.items():
        b = NAMES.index(name)
        causes = {stretch.cause for row in removed for stretch in row[b]}
        drawn = sum(_heights(ax, f"removed: {cause}", len(poses)) for cause in causes)
        expected = [np.degrees(limits.arc_set((k, b)).length) for k in range(len(poses))]
        np.testing.assert_allclose(_heights(ax, "feasible", len(poses)) + drawn, expected, rtol=0, atol=1e-3)
    plt.close(fig)


def test_a_removed_stretch_collides_where_it_says(cell_case):
    """At the middle of each stretch named ``"<link> meets <obstacle>"``, that pair is closer than the margin; at
    the failing waypoint the ball takes every arm angle the limits leave, and the figure names the pair."""
    import redkin
    from redkin.collision.clearance import pair_table

    chain, poses, body, scene, result = cell_case
    removed = removed_along_path(chain, poses, body, scene)
    arm = redkin.arm(chain)
    checked = 0
    for k, row in enumerate(removed):
        for b, stretches in enumerate(row):
            for start, end, cause in stretches:
                if cause == "undecided":
                    continue
                middle = start + arc_length(start, end) / 2.0
                solution = arm.ik(poses[k], middle, branches=NAMES[b])
                assert solution.exists.all()
                table, pairs = pair_table(chain, body, scene, solution.q.reshape(1, 7))
                link, obstacle = cause.split(" meets ")
                distance = table[0, [i for i, pair in enumerate(pairs.names) if pair == (link, obstacle)]].min()
                assert distance < scene.margin
                checked += 1
    assert checked > 20
    assert not result.ok and result.failure.reason == "collision" and result.failure.pair == ("link_7", "ball")
    failing = result.failure.waypoint
    limits = feasible_along_path(chain, poses)
    for b in range(len(NAMES)):
        ball = [s for s in removed[failing][b] if s.cause == "link_7 meets ball"]
        assert sum(arc_length(start, end) for start, end, _ in ball) == pytest.approx(
            limits.arc_set((failing, b)).length, abs=1e-5)
    fig = path_plane_figure(feasible_along_path(chain, poses, body=body, scene=scene), result, removed=removed)
    labels = [text.get_text() for legend in fig.legends for text in legend.get_texts()]
    assert f"no path: waypoint {failing}, collision, link_7 meets ball" in labels
    assert "removed: link_7 meets ball" in labels and "removed: link_4 meets post" in labels
    plt.close(fig)


def test_cell_along_path_is_both_functions_from_one_computation(cell_case):
    """``cell_along_path`` gives exactly the collision-free pieces of ``feasible_along_path`` in the cell and the
    stretches of ``removed_along_path`` (which it now computes), from one computation of the sets; the same on
    the Franka class (q7, the Panda's built-in body, its pieces not of the 24 of the arm angle)."""
    from redkin.collision import builtin_body, scene_of

    chain, poses, body, scene, _ = cell_case
    panda = get_robot("franka-panda")
    q = np.linspace([0.3, -0.4, 0.2, -2.0, 0.1, 1.8, 0.7], [0.0, -0.2, 0.4, -1.7, 0.3, 1.6, 0.9], 4)
    ball = scene_of({"margin": 0.01, "obstacles": [{"name": "ball", "type": "sphere", "center": [0.5, -0.3, 0.3],
                                                     "radius": 0.1}]})
    for arm, waypoints, shapes, cell in ((chain, poses, body, scene),
                                         (panda, panda.fk(q), builtin_body("franka-panda", panda), ball)):
        both = cell_along_path(arm, waypoints, shapes, cell)
        alone = feasible_along_path(arm, waypoints, body=shapes, scene=cell)
        for field in ("start", "end", "feasible"):
            np.testing.assert_array_equal(getattr(both.free, field), getattr(alone, field))
        assert both.removed == removed_along_path(arm, waypoints, shapes, cell)
        assert both.free.feasible.any() and any(row for per_pose in both.removed for row in per_pose)
