"""The nodes of path resolution's graph (redkin.paths.graph): their joint values are redkin.srs.ik's, bit for bit
(clipped into the limits), read from each waypoint's coefficients in one compiled pass."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from redkin import franka
from redkin.models import get_robot
from redkin.paths.family import ArmAngleFamily, Q7Family
from redkin.srs import BRANCHES, ik
from redkin.srs.geometry import srs_geometry


@pytest.mark.parametrize("robot", ["kuka-iiwa14", "pa10-7c", "barrett-wam7"])
def test_node_values_are_the_closed_form_ik_of_their_waypoint_and_branch(robot):
    chain = get_robot(robot)
    geometry = srs_geometry(chain)
    rng = np.random.default_rng(3)
    q = rng.uniform(np.maximum(chain.lower, -3.0), np.minimum(chain.upper, 3.0), (12, 7))
    poses = chain.fk(q)
    _, arm = ArmAngleFamily(geometry).arm(poses, np.full(7, 0.1))
    waypoint, branch = rng.integers(0, 12, 300), rng.integers(0, 8, 300)
    psi = rng.uniform(-np.pi, np.pi, 300)
    values, clearance = arm.rows(waypoint, branch, psi)
    limited = ~chain.covers_circle
    for n in range(300):
        expected = ik(chain, poses[waypoint[n]], psi[n], str(BRANCHES[branch[n]]))
        np.testing.assert_array_equal(values[n], np.where(limited, np.clip(expected, chain.lower, chain.upper),
                                                          expected))
        assert clearance[n] == np.min(np.minimum(expected - chain.lower, chain.upper - expected)[limited])


@pytest.mark.parametrize("robot", ["franka-fr3", "franka-panda", "ufactory-xarm7"])
def test_franka_nodes_are_the_closed_form_at_q7_of_their_waypoint_and_branch(robot):
    chain = get_robot(robot)
    rng = np.random.default_rng(4)
    q = rng.uniform(np.maximum(chain.lower, -3.0), np.minimum(chain.upper, 3.0), (12, 7))
    poses = chain.fk(q)
    family = Q7Family(franka.franka_geometry(chain))
    _, arm = family.arm(poses, np.full(7, 0.1))
    waypoint, branch = rng.integers(0, 12, 300), rng.integers(0, 8, 300)
    q7 = rng.uniform(chain.lower[6], chain.upper[6], 300)
    values, clearance = arm.rows(waypoint, branch, q7)
    limited = ~chain.covers_circle
    for n in range(300):
        expected = franka.ik(chain, poses[waypoint[n]], q7[n], str(BRANCHES[branch[n]]))
        if not expected.exists[0]:
            assert clearance[n] == -np.inf
            continue
        row = expected.q[0]
        np.testing.assert_array_equal(values[n], np.where(limited, np.clip(row, chain.lower, chain.upper), row))
        assert clearance[n] == np.min(np.minimum(row - chain.lower, chain.upper - row)[limited])


def test_the_parameter_of_a_configuration_is_its_own_branch_and_q7():
    chain = get_robot("franka-fr3")
    rng = np.random.default_rng(6)
    q = rng.uniform(chain.lower, chain.upper, (50, 7))
    family = Q7Family(franka.franka_geometry(chain))
    branch, q7 = family.parameter_of(q)
    np.testing.assert_array_equal(q7, q[:, 6])
    for n in range(50):
        again = franka.ik(chain, chain.fk(q[n]), q7[n], str(BRANCHES[branch[n]]))
        assert again.exists[0] and np.abs(again.q[0] - q[n]).max() < 1e-9


def _line_poses(robot, seed, count):
    """The chain, its S-R-S geometry and ``count`` poses along a joint-space line 0.2 rad inside its limits."""
    chain = get_robot(robot)
    rng = np.random.default_rng(seed)
    lower, upper = np.maximum(chain.lower + 0.2, -3.0), np.minimum(chain.upper - 0.2, 3.0)
    a, b = rng.uniform(lower, upper), rng.uniform(lower, upper)
    return chain, srs_geometry(chain), chain.fk(a + (b - a) * np.linspace(0.0, 1.0, count)[:, None])


@pytest.mark.parametrize(("robot", "step"), [("kuka-iiwa14", 0.05), ("pa10-7c", 0.03), ("barrett-wam7", 0.1)])
def test_connect_keeps_every_node_and_leaves_no_interval_of_a_piece_wider_than_its_share_of_the_bound(robot, step):
    from redkin.paths import graph as graphs
    from redkin.paths.graph import _MIN_SPACING
    from redkin.srs.feasible import feasible_pieces_all_branches

    chain, geometry, poses = _line_poses(robot, 1, 20)
    _, arm = ArmAngleFamily(geometry).arm(poses, np.full(7, step))
    waypoint, branch, piece, psi, _, _ = graphs.piece_samples(feasible_pieces_all_branches(geometry, poses), 0.1)
    before = graphs.build(arm, np.append(waypoint, 0), np.append(branch, 2), np.append(piece, -1),
                          np.append(psi, 0.3), 20)  # and one node alone, as q0's
    after = graphs.connect(arm, before, 0.25)
    assert len(after.psi) > len(before.psi)
    old = set(zip(before.waypoint.tolist(), before.piece.tolist(), before.psi.tolist()))
    assert old <= set(zip(after.waypoint.tolist(), after.piece.tolist(), after.psi.tolist()))
    order = np.lexsort((after.psi, after.piece, after.waypoint))
    np.testing.assert_array_equal(order, np.arange(len(order)))
    np.testing.assert_array_equal(after.offsets, np.searchsorted(after.waypoint, np.arange(21)))
    same = (after.piece[1:] == after.piece[:-1]) & (after.piece[1:] >= 0)
    moves = arm.moves(after.q[1:], after.q[:-1])[same].max(axis=-1)
    narrow = np.diff(after.psi)[same] <= 2 * _MIN_SPACING
    assert np.all((moves <= 0.25 * step) | narrow)
    np.testing.assert_array_equal(after.q, arm.rows(after.waypoint, after.branch, after.psi)[0])
    assert np.all(after.clearance >= 0) and np.all(chain.within_limits(after.q))


@pytest.mark.parametrize(("robot", "seed"), [("kuka-iiwa14", 1), ("kuka-iiwa14", 2), ("barrett-wam7", 3)])
def test_the_path_does_not_depend_on_the_joint_that_keys_the_sweep(robot, seed, monkeypatch):
    """The sweep's window of candidates is a filter on one joint: whichever joint keys it (a tight bound on one
    joint makes it the cheapest key, :func:`redkin.paths.search.key_joint`), the best path is the same, exact ties
    going to the lower node index."""
    from redkin.paths import resolve_path, search

    chain = get_robot(robot)
    rng = np.random.default_rng(seed)
    lower, upper = chain.lower + 0.2, chain.upper - 0.2
    a = rng.uniform(lower, upper)
    q = a + 0.3 * (rng.uniform(lower, upper) - a) * np.linspace(0.0, 1.0, 12)[:, None]
    step = 1.5 * np.abs(np.diff(q, axis=0)).max(axis=0) + 1e-3
    results = []
    for key in range(7):
        monkeypatch.setattr(search, "key_joint", lambda graph, step, circle, key=key: key)
        results.append(resolve_path(chain, chain.fk(q), step))
    for result in results[1:]:
        np.testing.assert_array_equal(result.q, results[0].q)
        assert result.clearance == results[0].clearance and result.motion == results[0].motion


@pytest.mark.parametrize("robot", ["kuka-iiwa14", "pa10-7c", "barrett-wam7"])
def test_initial_samples_are_sorted_hold_every_piece_and_share_only_equal_samples(robot):
    """The samples come sorted as a graph's nodes, every piece gives its two ends and its middle, and the nodes that
    share a sample (same waypoint, elbow sign and arm angle) get the same joint values as each computed alone, bit
    for bit."""
    from redkin.paths import graph as graphs
    from redkin.srs.feasible import feasible_pieces_all_branches

    _, geometry, poses = _line_poses(robot, 6, 15)
    family = ArmAngleFamily(geometry)
    waypoint, branch, piece, psi, shared, bounds = graphs.piece_samples(
        feasible_pieces_all_branches(geometry, poses), 0.3, family.sample_groups())
    np.testing.assert_array_equal(np.lexsort((psi, piece, waypoint)), np.arange(len(psi)))
    assert np.all((psi >= bounds[piece, 0]) & (psi <= bounds[piece, 1]))
    for k in range(len(bounds)):
        mine = psi[piece == k]
        assert mine[0] == bounds[k, 0] and mine[-1] == bounds[k, 1] and 0.5 * bounds[k].sum() in mine
    assert np.all(shared <= np.arange(len(psi))) and np.all(shared[shared] == shared)
    elbow = geometry.kernel_branches[:, 1]
    np.testing.assert_array_equal(waypoint[shared], waypoint)
    np.testing.assert_array_equal(psi[shared], psi)
    np.testing.assert_array_equal(elbow[branch[shared]], elbow[branch])
    if robot == "kuka-iiwa14":  # here an elbow sign's branches keep most of their pieces in common
        assert np.mean(shared != np.arange(len(psi))) > 0.3
    _, arm = family.arm(poses, np.full(7, 0.1))
    together, alone = arm.rows(waypoint, branch, psi, shared), arm.rows(waypoint, branch, psi)
    np.testing.assert_array_equal(together[0], alone[0])
    np.testing.assert_array_equal(together[1], alone[1])


def test_each_waypoint_s_kept_nodes_are_sorted_by_their_key_short_runs_and_long():
    from redkin.paths import _dp_kernels

    rng = np.random.default_rng(9)
    sizes = rng.integers(0, 60, 40)  # runs under and over the insertion sort's length, and empty ones
    offsets = np.concatenate([[0], np.cumsum(sizes)]).astype(np.int64)
    key = rng.choice(rng.normal(size=30), offsets[-1])  # ties too
    kept = rng.random(offsets[-1]) < 0.7
    kept_offsets = np.concatenate([[0], np.cumsum(kept)])[offsets]
    order, sorted_key = np.empty(kept.sum(), dtype=np.int64), np.empty(kept.sum())
    _dp_kernels.sort_by_key(0, len(sizes), offsets, kept, kept_offsets, key, order, sorted_key)
    for w in range(len(sizes)):
        mine = order[kept_offsets[w]:kept_offsets[w + 1]]
        np.testing.assert_array_equal(np.sort(mine), np.flatnonzero(kept[offsets[w]:offsets[w + 1]]) + offsets[w])
        np.testing.assert_array_equal(sorted_key[kept_offsets[w]:kept_offsets[w + 1]], key[mine])
        assert np.all(np.diff(key[mine]) >= 0)


def test_connect_refuses_a_graph_too_large_to_compute():
    """A step bound so small that the graph would outgrow what fits in memory is refused in words, before it is
    built (a bound of 1e-9 rad asked for terabytes)."""
    from redkin.errors import RedkinError
    from redkin.paths import graph as graphs
    from redkin.srs.feasible import feasible_pieces_all_branches

    _, geometry, poses = _line_poses("kuka-iiwa14", 1, 20)
    _, arm = ArmAngleFamily(geometry).arm(poses, np.full(7, 1e-9))
    waypoint, branch, piece, psi, _, _ = graphs.piece_samples(feasible_pieces_all_branches(geometry, poses), 0.1)
    with pytest.raises(RedkinError, match=rf"needs more than {graphs._MOST_NODES:,} nodes .*\(a size too large to "
                                          r"compute\)"):
        graphs.connect(arm, graphs.build(arm, waypoint, branch, piece, psi, 20), 0.25)


def test_a_graph_whose_first_samples_are_too_many_is_refused_before_it_is_made():
    """The first samples count against the same limit: 782 000 waypoints (about 300 nodes each on the iiwa14) ran
    out of memory in silence; here 20 waypoints sampled every 1e-6 rad."""
    from redkin.errors import SizeLimitError
    from redkin.paths import graph as graphs
    from redkin.srs.feasible import feasible_pieces_all_branches

    _, geometry, poses = _line_poses("kuka-iiwa14", 1, 20)
    pieces = feasible_pieces_all_branches(geometry, poses)
    assert len(graphs.piece_samples(pieces, 1e-3)[0]) <= graphs._MOST_NODES
    with pytest.raises(SizeLimitError, match=r"a path of 20 waypoints needs [\d,]+ nodes in its graph") as raised:
        graphs.piece_samples(pieces, 1e-6)
    assert raised.value.value > graphs._MOST_NODES


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**31), before=st.integers(1, 30), after=st.integers(1, 30),
       circle=st.lists(st.booleans(), min_size=7, max_size=7), unbounded=st.integers(-1, 6))
def test_the_closest_pair_across_a_step_is_the_least_largest_relative_move(seed, before, after, circle, unbounded):
    """The pair that names a blocked step's joint (``redkin.paths.failure._closest_pair``, a k-d tree) is a pair of
    least largest relative move over every pair, the shorter way round on joints that turn without end; a joint
    without a bound counts for nothing."""
    from redkin.paths.failure import _closest_pair
    from redkin.paths.graph import Arm, joint_moves

    rng = np.random.default_rng(seed)
    step = rng.uniform(0.01, 0.5, 7)
    if unbounded >= 0:
        step[unbounded] = np.inf
    arm = Arm(get_robot("kuka-iiwa14"), step, np.array(circle))
    one, other = rng.uniform(-4.0, 4.0, (before, 7)), rng.uniform(-4.0, 4.0, (after, 7))
    turns = np.where(circle, 2.0 * np.pi * rng.integers(-1, 2, 7), 0.0)  # the near pair a turn apart, or not
    other[rng.integers(after)] = one[rng.integers(before)] + turns + rng.normal(0.0, 0.01, 7)
    ratios = (joint_moves(one[:, None], other[None], np.array(circle)) / step).max(axis=-1)
    first, second = _closest_pair(arm, one, other)
    assert ratios[first, second] <= ratios.min() * (1.0 + 1e-9) + 1e-12
