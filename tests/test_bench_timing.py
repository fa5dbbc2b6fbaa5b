"""bench_timing.py (issue 41) on tiny inputs: the structure of what its measurements return (not their times)."""

import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("toppra")

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))

import bench_timing

from redkin.models import franka_panda

IIWA = bench_timing.iiwa14()


def test_the_iiwa_carries_the_stated_acceleration_assumption_and_the_curves_keep_the_limits():
    assert np.all(IIWA.acceleration == bench_timing.ASSUMED_IIWA_ACCELERATION)
    q = bench_timing.long_curve(IIWA, 20)
    assert q.shape == (20, 7) and IIWA.within_limits(q).all()
    panda = franka_panda()
    rng = np.random.default_rng(0)
    assert all(panda.within_limits(bench_timing.random_curve(panda, rng, 15)).all() for _ in range(5))
    with pytest.raises(ValueError, match="leaves the limits"):
        bench_timing.joint_curve(IIWA, 5, IIWA.upper, np.ones(7), np.zeros(7), 1.0)


def test_long_path_checks_and_toppra_comparison_on_20_waypoints():
    """Measurements 1-3 on 20 waypoints (step bound 0.3 rad: the curve moves 0.06 rad per waypoint): the seconds
    are positive, every check passes, toppra's default run and its refined runs (one halving at most here) have
    their grids, durations and limit ratios."""
    long = bench_timing.measure_long_path(IIWA, 20, repeat=1, max_step=0.3)
    assert long.result.ok and long.poses.shape == (20, 4, 4) and long.result.trajectory.rate == bench_timing.RATE
    seconds = [long.first_resolve, long.first_timing, long.resolve, long.timing, long.combined]
    assert all(np.isfinite(seconds)) and min(seconds) > 0.0
    assert len(bench_timing.long_path_lines(long)) == 7

    checks = bench_timing.check_trajectory(IIWA, long.poses, long.result.trajectory)
    assert len(checks) == 6 and all(check.passed for check in checks), checks
    assert len(bench_timing.check_lines(checks)) == 7

    comparison = bench_timing.compare_with_toppra(IIWA, long.result.q, "tiny", repeat=1, cap=1)
    assert comparison.waypoints == 20 and comparison.ours.duration > 0.0 and comparison.ours_seconds > 0.0
    assert len(comparison.refined) <= 1 and comparison.reference in [comparison.default, *comparison.refined]
    for run in [comparison.default, *comparison.refined]:
        assert run.gridpoints >= 2 and run.duration > 0.0 and run.seconds > 0.0
        assert run.velocity > 0.0 and run.acceleration > 0.0
    if comparison.refined:  # every interval halved
        assert comparison.refined[0].gridpoints == 2 * comparison.default.gridpoints - 1
    assert any("the fair comparison" in line for line in bench_timing.comparison_lines(comparison))


def test_finite_differences_of_a_parabola_are_its_derivatives():
    """Central differences at any spacing are exact on a parabola: velocity 2 a t, acceleration 2 a."""
    t = np.r_[np.arange(6) * 1e-3, 5.4e-3]
    q = 3.0 * t[:, None] ** 2
    velocity, acceleration, step = bench_timing.finite_differences(t, q)
    np.testing.assert_allclose(acceleration, 6.0, rtol=1e-6)
    np.testing.assert_allclose(velocity[:-1, 0], 6.0 * t[1:-2], rtol=1e-9)
    assert step.shape == (5, 1) and step.max() == pytest.approx(1e-3)


def test_objective_comparison_on_two_short_lines():
    """Measurement 4 on 2 random Panda lines of 20-30 waypoints: one duration, seconds and no error per line and
    objective, and the time objective never longer."""
    objectives = bench_timing.compare_objectives(franka_panda(), 2, (20, 30))
    assert len(objectives.waypoints) == 2 and all(20 <= n <= 30 for n in objectives.waypoints)
    for values in (objectives.default, objectives.fastest, objectives.default_seconds, objectives.fastest_seconds):
        assert len(values) == 2
    assert objectives.errors == [] and objectives.violations == 0
    assert objectives.gains.shape == (int(objectives.found.sum()),) and np.all(objectives.gains >= 0.0)
    assert any(line.startswith("time objective longer") for line in bench_timing.objective_lines(objectives))
