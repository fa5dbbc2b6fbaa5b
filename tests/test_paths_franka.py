"""Path resolution on Franka-class arms (redkin.paths with q7 as the parameter): every returned path reaches its
poses, keeps the limits and the bound, names its branch and q7 truly; a clearance said optimal is not beaten at its
bottleneck by any sampled q7 of any branch; failures are proved by the exact q7 sets; the command line says q7."""

import json

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from redkin import franka
from redkin.cli.main import main
from redkin.franka.ik import reach as franka_reach
from redkin.models import get_robot
from redkin.paths import FK_TOLERANCE, OPTIMALITY_MARGIN, Q7Family, path_family, resolve_path, resolve_paths
from redkin.srs import BRANCHES

ROBOTS = ["franka-fr3", "franka-panda", "ufactory-xarm7"]


def _joint_line(chain, rng, count):
    lower, upper = np.maximum(chain.lower + 0.2, -3.0), np.minimum(chain.upper - 0.2, 3.0)
    a, b = rng.uniform(lower, upper), rng.uniform(lower, upper)
    q = a + (b - a) * np.linspace(0.0, 1.0, count)[:, None]
    return q, chain.fk(q)


def _clearance(chain, q):
    return np.minimum(q - chain.lower, chain.upper - q)[..., ~chain.covers_circle].min(axis=-1)


def _assert_lawful(chain, poses, result):
    assert result.ok and result.parameter == "q7" and result.q.shape == (len(poses), 7)
    assert np.abs(chain.fk(result.q) - poses).max() <= FK_TOLERANCE
    assert chain.within_limits(result.q).all()
    assert np.all(np.abs(np.diff(result.q, axis=0)) <= result.step)
    np.testing.assert_array_equal(result.psi, result.q[:, 6])
    for k in range(len(poses)):  # the branch named is the branch whose solution at that q7 it is
        q7 = result.psi[k] + np.array([0.0, -1e-12, 1e-12])
        again = franka.ik(chain, np.broadcast_to(poses[k], (3, 4, 4)), q7, result.branch[k])
        difference = again.q[:, 0] - result.q[k]  # a joint whose range holds every angle may be a turn away
        difference = np.where(chain.covers_circle, np.mod(difference + np.pi, 2 * np.pi) - np.pi, difference)
        # at q7 itself; or, where q7 is the end of an arc at which the branch appears and the path turned joint 7 by
        # a whole turn (its range holds two: the xArm7 at q7 = -5.636883757285389 + 2 pi, a fresh draw), next to it
        found = again.exists[:, 0] & (np.abs(difference).max(axis=-1) < 1e-9)
        assert found[0] or (found[1:].any() and not franka.ik(chain, poses[k], result.psi[k]).exists.any())
    assert result.clearance == pytest.approx(_clearance(chain, result.q).min(), abs=1e-12)


def _densest_clearance(chain, pose, samples=4000):
    """The largest clearance of any in-limit solution of ``pose`` on a dense q7 grid of all branches (the closed
    form alone, no feasible set)."""
    q7 = np.linspace(chain.lower[6], chain.upper[6], samples)
    solutions = franka.ik(chain, np.broadcast_to(pose, (samples, 4, 4)), q7)
    q = solutions.q[solutions.exists]
    return _clearance(chain, q).max(initial=-np.inf)


@settings(max_examples=6, deadline=None)
@given(st.integers(0, 2**31), st.sampled_from(ROBOTS), st.floats(1.2, 3.0))
@example(1_077_647_943, "ufactory-xarm7", 2.0)  # a fresh draw: a waypoint at an arc's end, joint 7 turned
def test_a_path_that_exists_is_found_keeps_every_law_and_a_proved_clearance_is_not_beaten(seed, robot, slack):
    chain = get_robot(robot)
    q, poses = _joint_line(chain, np.random.default_rng(seed), 10)
    step = slack * np.abs(np.diff(q, axis=0)).max(axis=0) + 1e-3
    result = resolve_path(chain, poses, step)
    _assert_lawful(chain, poses, result)
    assert result.clearance >= _clearance(chain, q).min() - 1e-6  # at least the line the poses came from
    if result.optimal:
        assert _densest_clearance(chain, poses[result.bottleneck]) <= result.clearance + OPTIMALITY_MARGIN


def test_the_family_of_each_class():
    assert path_family(get_robot("franka-fr3")).parameter == "q7"
    assert path_family(get_robot("kuka-iiwa14")).parameter == "psi"
    nearly = path_family(get_robot("kinova-gen3"))
    assert nearly.parameter == "psi" and not nearly.exact
    with pytest.raises(ValueError, match=r"general chain .*beyond the nearly S-R-S tolerance of 0\.0001 m"):
        path_family(get_robot("kinova-gen3"), srs_tolerance=1e-4)


def test_the_start_configuration_and_many_paths_at_once():
    chain = get_robot("franka-fr3")
    rng = np.random.default_rng(8)
    lines = [_joint_line(chain, rng, 8) for _ in range(3)]
    step = max(2.0 * np.abs(np.diff(q, axis=0)).max() for q, _ in lines) + 1e-3
    starts = np.stack([q[0] for q, _ in lines])
    together = resolve_paths(chain, np.stack([poses for _, poses in lines]), step, q0=starts)
    for (q, poses), result in zip(lines, together):
        _assert_lawful(chain, poses, result)
        assert np.all(np.abs(result.q[0] - q[0]) <= step)
        alone = resolve_path(chain, poses, step, q0=q[0])
        np.testing.assert_array_equal(alone.q, result.q)


def test_a_pose_out_of_reach_is_a_failure_proved_at_its_waypoint():
    chain = get_robot("franka-fr3")
    _, poses = _joint_line(chain, np.random.default_rng(2), 6)
    poses = poses.copy()
    poses[3, :3, 3] = [2.0, 0.0, 0.5]  # two metres away
    result = resolve_path(chain, poses, 0.5)
    assert not result.ok
    assert (result.failure.waypoint, result.failure.reason, result.failure.exact) == (3, "out-of-reach", True)
    assert result.parameter == "q7"  # a failed path names its parameter too (it said psi)
    family = Q7Family(franka.franka_geometry(chain))  # the reach agrees with the exact sets: empty there
    assert not family.pieces(poses[3:4]).feasible.any()
    assert franka_reach(chain, poses).out.tolist() == [False, False, False, True, False, False]


def test_the_command_line_names_q7(tmp_path, capsys):
    chain = get_robot("franka-fr3")
    q, poses = _joint_line(chain, np.random.default_rng(4), 6)
    file = tmp_path / "poses.npy"
    np.save(file, poses)
    step = float(2.0 * np.abs(np.diff(q, axis=0)).max() + 1e-3)
    assert main(["path", "franka-fr3", "--poses", str(file), "--max-step", str(step), "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["parameter"] == "q7" and "psi" not in report
    np.testing.assert_allclose(report["q7"], np.array(report["q"])[:, 6])
    assert report["branch"][0] in [str(b) for b in BRANCHES]
    assert main(["path", "franka-fr3", "--poses", str(file), "--max-step", str(step)]) == 0
    out = capsys.readouterr().out
    header = next(line for line in out.splitlines() if line.split()[:2] == ["k", "branch"])
    assert "q7" in header and "clearance" in out and "starts on branch" in out
    assert main(["path", "franka-fr3", "--poses", str(file), "--max-step", str(step), "--plot",
                 str(tmp_path / "plane.png")]) == 0
    assert (tmp_path / "plane.png").stat().st_size > 0


def test_the_q7_plane_shades_the_exact_sets_and_draws_the_path_unwrapped():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from redkin.paths import feasible_along_path
    from redkin.plot.paths import path_plane_figure

    chain = get_robot("ufactory-xarm7")  # q7 in +-2 pi: drawn as the joint has it, never folded into +-180 deg
    q, poses = _joint_line(chain, np.random.default_rng(5), 8)
    result = resolve_path(chain, poses, 2.0 * np.abs(np.diff(q, axis=0)).max() + 1e-3)
    pieces = feasible_along_path(chain, poses)
    assert pieces.start.shape[:2] == (8, 8)
    fig = path_plane_figure(pieces, result)
    axes = [ax for ax in fig.axes if ax.get_visible()]
    assert axes[0].get_ylabel() == "q7 [deg]"
    for ax in axes:
        branch = ax.get_title().split()[-1]
        for line in ax.get_lines():
            if line.get_gid() == "path":
                x, y = line.get_data()
                keep = np.isfinite(x)
                on = np.array([b == branch for b in result.branch])
                np.testing.assert_allclose(y[keep], np.degrees(result.q[on, 6]))
    plt.close(fig)


def test_judge_path_judges_a_franka_path_as_the_baselines_are():
    from redkin.paths import judge_path

    chain = get_robot("franka-fr3")
    q, poses = _joint_line(chain, np.random.default_rng(12), 8)
    step = 2.0 * np.abs(np.diff(q, axis=0)).max() + 1e-3
    result = resolve_path(chain, poses, step)
    assert judge_path(chain, result.q, step, poses).ok
    jumped = result.q.copy()
    jumped[5:, 0] += 0.5  # a joint-1 jump: the poses are missed and the bound broken at waypoint 5
    judged = judge_path(chain, jumped, step, poses)
    assert not judged.ok and judged.first_failure == 5
