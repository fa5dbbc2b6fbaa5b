"""Path resolution on nearly S-R-S arms (redkin.paths with the real arm's arm angle, :class:`NearlyFamily`).

Laws, on the Kinova Gen3 (continuous joints limited to +-2.9 rad) and the ROS-Industrial iiwa, on paths of poses
made from a straight line in joint space whose configurations are the ones :func:`redkin.srs.nearly.ik` returns at
their own arm angles and branches (so a path of the solver's solutions exists; a line near a singular shoulder or
wrist may pass on a sheet the solver does not return, and is not asked for):

- a path is found; it reaches every pose (FK within :data:`FK_TOLERANCE`), keeps every limit and the step bound,
  and names its branch and arm angle truly: :func:`redkin.srs.nearly.ik` at that arm angle on that branch gives
  the same joint values;
- its clearance is at least the line's own, less the certificate's 1e-9 rad;
- no clearance is said optimal and no failure said proved: the sets are certified, not exact;
- a pose out of reach in the middle is a failure at that waypoint;
- the command line takes ``--srs-tolerance`` and refuses the arm (exit 2, one line) when it is not within it; its
  plot's legend calls the sets certified, not exact.
"""

from __future__ import annotations

import functools
import json
from pathlib import Path

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from redkin.cli.main import main
from redkin.paths import FK_TOLERANCE, path_family, resolve_path
from redkin.paths.family import NearlyFamily
from redkin.srs import BRANCHES
from redkin.srs.nearly import ik

EXAMPLES = Path(__file__).resolve().parents[1] / "src" / "redkin" / "examples"


@functools.cache
def _chain(name: str):
    from redkin.urdf import load_urdf

    if name == "gen3":
        chain = load_urdf(EXAMPLES / "gen3.urdf", base="base_link", tip="end_effector_link")
        return chain.with_limits(np.where(np.isfinite(chain.lower), chain.lower, -2.9),
                                 np.where(np.isfinite(chain.upper), chain.upper, 2.9))
    return load_urdf(EXAMPLES / "iiwa14_rosi.urdf")


def _joint_line(chain, rng, count):
    lower, upper = chain.lower + 0.3, chain.upper - 0.3
    a = rng.uniform(lower, upper)
    b = np.clip(a + rng.uniform(-0.5, 0.5, 7), lower, upper)
    q = a + (b - a) * np.linspace(0.0, 1.0, count)[:, None]
    return q, chain.fk(q)


def _clearance(chain, q):
    return np.minimum(q - chain.lower, chain.upper - q)[..., ~chain.covers_circle].min(axis=-1)


@settings(max_examples=4, deadline=None)
@given(st.integers(0, 2**31), st.sampled_from(["gen3", "iiwa14-rosi"]))
def test_a_path_that_exists_is_found_and_keeps_every_law(seed, name):
    chain = _chain(name)
    q, poses = _joint_line(chain, np.random.default_rng(seed), 6)
    family = path_family(chain)
    assert isinstance(family, NearlyFamily)
    branch, psi = family.parameter_of(q)
    line = np.stack([ik(family.nearly, poses[k], psi[k], BRANCHES[branch[k]]).q[0] for k in range(len(q))])
    assume(np.abs(np.angle(np.exp(1j * (line - q)))).max() < 1e-6)  # the solver's solutions are the line's
    step = 1.5 * np.abs(np.diff(q, axis=0)).max(axis=0) + 1e-3
    result = resolve_path(chain, poses, step)
    assert result.ok and result.parameter == "psi" and not result.optimal and result.bottleneck is None
    assert np.abs(chain.fk(result.q) - poses).max() <= FK_TOLERANCE
    assert chain.within_limits(result.q).all()
    assert np.all(np.abs(np.diff(result.q, axis=0)) <= result.step)
    assert result.clearance >= _clearance(chain, q).min() - 1e-9
    assert result.clearance == pytest.approx(_clearance(chain, result.q).min(), abs=1e-12)
    for k in range(len(poses)):  # the branch and arm angle named give the same joint values
        again = ik(family.nearly, poses[k], result.psi[k], result.branch[k])
        difference = np.angle(np.exp(1j * (again.q[0] - result.q[k])))
        assert again.exists[0] and np.abs(difference).max() < 1e-8


def test_a_pose_out_of_reach_is_a_failure_at_its_waypoint():
    chain = _chain("iiwa14-rosi")
    _, poses = _joint_line(chain, np.random.default_rng(3), 5)
    poses = poses.copy()
    poses[2, :3, 3] = [3.0, 0.0, 0.5]  # far beyond the arm's reach
    result = resolve_path(chain, poses, 0.5)
    assert not result.ok
    assert (result.failure.waypoint, result.failure.reason, result.failure.exact) == (2, "out-of-reach", True)
    assert chain.reach(poses).out.tolist() == [False, False, True, False, False]  # proved by the links' reach


def test_the_command_line(tmp_path, capsys):
    chain = _chain("iiwa14-rosi")
    _, poses = _joint_line(chain, np.random.default_rng(5), 4)
    np.save(tmp_path / "poses.npy", poses)
    robot = str(EXAMPLES / "iiwa14_rosi.urdf")
    assert main(["path", robot, "--poses", str(tmp_path / "poses.npy"), "--max-step", "0.5", "--json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["status"] == "ok" and report["parameter"] == "psi" and len(report["q"]) == 4
    assert report["optimal"] is False and "nearly S-R-S" in report["model"]
    assert main(["path", robot, "--poses", str(tmp_path / "poses.npy"), "--max-step", "0.5", "--plot",
                 str(tmp_path / "path.png")]) == 0
    assert "neighbour" in capsys.readouterr().out and (tmp_path / "path.png").stat().st_size > 0
    code = main(["path", robot, "--poses", str(tmp_path / "poses.npy"), "--max-step", "0.5", "--srs-tolerance",
                 "1e-5"])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1 and "S-R-S" in err


def test_the_plot_calls_the_sets_certified():
    import matplotlib

    matplotlib.use("Agg")
    from redkin.paths import feasible_along_path
    from redkin.plot.paths import path_plane_figure

    chain = _chain("iiwa14-rosi")
    _, poses = _joint_line(chain, np.random.default_rng(5), 3)
    result = resolve_path(chain, poses, 0.5)
    figure = path_plane_figure(feasible_along_path(chain, poses), result, exact=path_family(chain).exact)
    labels = [text.get_text() for legend in figure.legends for text in legend.get_texts()]
    assert "feasible arm angles (certified on the real arm)" in labels
