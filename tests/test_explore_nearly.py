"""The explorer of nearly S-R-S arms (:mod:`redkin.explore.grid` over :meth:`redkin.arms.Arm.analyse`): its numbers
are the real arm's, and its page states the model error and what it cannot draw.

Laws, on the Kinova Gen3 (joints limited to +-2.9 rad so that sets have ends) and the Jaco2:

- every posture shown reaches the pose on the real arm (1e-9 m, 1e-9 rad) at its arm angle (1e-9 rad); where no
  certified solution was found the values are NaN and the branch says how many;
- the feasible arcs are :func:`redkin.srs.feasible_arm_angles_nearly`'s, their ends grid points exactly, the flags
  membership of them; away from the limits (1e-7 rad) a grid point is in the set exactly when every joint is within;
- the optimal marks stand on :func:`redkin.srs.optimal_arm_angles_nearly`'s optima; a singular mark on an aligned
  configuration of the real arm;
- no per-joint sets; the page holds the neighbour and the model error and says that the per-joint sets are not drawn;
- the command line writes the page; in Chromium the slider moves the arm without errors (slow, browser).
"""

from __future__ import annotations

import functools
import json
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import redkin
from redkin.explore import explorer_data, explorer_html
from redkin.srs import (
    BRANCHES,
    alignment_angles,
    feasible_arm_angles_nearly,
    nearly_srs,
    optimal_arm_angles_nearly,
    pose_from,
)
from redkin.srs.nearly import arm_angle
from tests.test_report_browser import DECISION, MISSING, WIDTHS, Page, _explorer_state, browser  # noqa: F401

EXAMPLES = Path(__file__).resolve().parents[1] / "src" / "redkin" / "examples"
POSITION, ROTATION = [0.3, 0.2, 0.5], [1, 0, 0, 0, -1, 0, 0, 0, -1]


@functools.cache
def _chain(name: str):
    if name == "gen3":
        return redkin.get_robot("kinova-gen3").with_limits(np.full(7, -2.9), np.full(7, 2.9))
    from redkin.urdf import load_urdf

    return load_urdf(EXAMPLES / "jaco2.urdf")


def _pose() -> np.ndarray:
    return pose_from(np.array(POSITION, dtype=float), np.array(ROTATION, dtype=float).reshape(3, 3))


@pytest.fixture(scope="module", params=["gen3", "jaco2"])
def case(request):
    chain = _chain(request.param)
    return chain, _pose(), explorer_data(chain, _pose(), "+-+", samples=181)


def _pose_errors(reached: np.ndarray, target: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    position = np.linalg.norm(reached[..., :3, 3] - target[:3, 3], axis=-1)
    relative = target[:3, :3].T @ reached[..., :3, :3]
    sine = np.linalg.norm(relative - np.swapaxes(relative, -1, -2), axis=(-2, -1)) / (2.0 * np.sqrt(2.0))
    return position, np.arctan2(sine, (np.trace(relative, axis1=-2, axis2=-1) - 1.0) / 2.0)


def test_postures_are_certified_solutions_of_the_real_arm(case):
    chain, pose, data = case
    arm = nearly_srs(chain)
    assert data.parameter.name == "psi" and data.parameter.wraps and "real" in data.method
    for curves in data.branches:
        shown = curves.exists
        assert shown.mean() > 0.9
        position, rotation = _pose_errors(chain.fk(curves.q[shown]), pose)
        assert position.max() <= 1e-9 and rotation.max() <= 1e-9
        turned = np.angle(np.exp(1j * (arm_angle(arm, curves.q[shown]) - curves.values[shown])))
        assert np.abs(turned).max() <= 1e-9
        assert np.isnan(curves.q[~shown]).all() and np.isnan(curves.origins[~shown]).all()
        assert not curves.within[~shown].any()
        if (~shown).any():
            assert any("No certified solution" in note for note in curves.notes)
        np.testing.assert_array_equal(curves.origins[shown], chain.frames(curves.q[shown])[..., :3, 3])


def test_sets_flags_and_marks_are_the_real_arms(case):
    chain, pose, data = case
    arm = nearly_srs(chain)
    for curves, branch in zip(data.branches, BRANCHES):
        feasible = feasible_arm_angles_nearly(arm, pose, branch).feasible
        np.testing.assert_array_equal(curves.arcs, np.array(feasible.arcs, dtype=float).reshape(-1, 2))
        assert curves.per_joint is None and curves.full == feasible.is_full
        assert {e for arc in feasible.intervals for e in arc} <= set(curves.values.tolist())
        np.testing.assert_array_equal(curves.feasible_at, feasible.contains(curves.values, 1e-12))
        q = curves.q
        clear = curves.exists & np.all(np.minimum(np.abs(q - chain.lower), np.abs(q - chain.upper)) > 1e-7, axis=1)
        np.testing.assert_array_equal(curves.feasible_at[clear], curves.within[clear].all(axis=1))
        optimal = optimal_arm_angles_nearly(arm, pose, branch, feasible=feasible).overall
        marks = {m.label: curves.values[m.index] for m in curves.marks if m.kind == "optimal"}
        assert abs(marks["optimal ψ ([000 eq. 40] on the real arm)"] - np.angle(np.exp(1j * optimal.unclamped))) < 1e-15
        if optimal.feasible is not None and "optimal ψ clamped to Ψ" in marks:
            assert abs(marks["optimal ψ clamped to Ψ"] - np.angle(np.exp(1j * optimal.feasible))) < 1e-15


def test_a_singular_mark_holds_the_aligned_configuration():
    chain = _chain("gen3")
    arm = nearly_srs(chain)
    theta = arm.geometry.theta_of_q(np.array([0.3, 0.7, -0.4, 1.2, 0.5, -0.9, 0.2]))
    theta[1] = 0.0  # axes 1 and 3 parallel: the Gen3's twists are right angles
    q = arm.geometry.q_of_theta(theta)
    pose = chain.fk(q)
    data = explorer_data(chain, pose, samples=91)
    found = 0
    for curves in data.branches:
        for mark in (m for m in curves.marks if m.kind == "singular"):
            shown = curves.q[mark.index]
            assert curves.exists[mark.index] and "parallel" in mark.note
            assert abs(alignment_angles(arm, shown)[0 if "shoulder" in mark.label else 1]) <= 1e-9
            assert np.abs(chain.fk(shown) - pose).max() <= 1e-9
            found += "shoulder" in mark.label
    assert found >= 2  # the configuration's own branch and the one of the other sign of theta_2 meet there


def test_the_page_states_the_model_error_and_what_it_does_not_draw(case):
    _, _, data = case
    assert any("nearly S-R-S" in text and " mm" in text for text in data.remarks)
    page = explorer_html(data, degrees=True)
    for text in data.remarks:
        assert text.split(":")[0] in page
    assert "not computed on nearly S-R-S arms" in page and "joint i within its limits" not in page
    payload = json.loads(re.search(r'<script id="explorer-data" type="application/json">(.*?)</script>', page, re.S)[1])
    branch = payload["branches"][data.initial]
    assert branch["per_joint"] is None and len(branch["q"]) == 7
    assert not re.search(r"""(src|href)\s*=\s*["']?(https?:)?//""", page)


def test_the_command_line_writes_the_page(tmp_path, capsys):
    from redkin.cli.main import main

    out = tmp_path / "gen3.html"
    argv = ["explore", "kinova-gen3", "--position", *map(str, POSITION), "--rotation", *map(str, ROTATION)]
    assert main([*argv, "--out", str(out), "--json"]) == 0
    printed = json.loads(capsys.readouterr().out)
    assert printed["parameter"] == "psi" and len(printed["feasible"]) == 8
    assert "its exact S-R-S neighbour drops" in out.read_text()


def test_an_unreachable_pose_is_refused():
    with pytest.raises(ValueError, match="reach"):
        explorer_data(_chain("gen3"), pose_from(np.array([3.0, 0.0, 0.5]), np.eye(3)), samples=32)


browser_test = pytest.mark.skipif(DECISION == "skip", reason=str(MISSING))


@browser_test
@pytest.mark.slow
@pytest.mark.parametrize("width", WIDTHS)
def test_the_gen3_page_in_a_browser(browser, tmp_path, width):  # noqa: F811
    out = tmp_path / "gen3.html"
    subprocess.run([sys.executable, "-m", "redkin.cli.main", "explore", "kinova-gen3", "--position",
                    *map(str, POSITION), "--rotation", *map(str, ROTATION), "--out", str(out)],
                   check=True, capture_output=True)
    view = Page(browser, out.as_uri(), width)
    page = view.page
    before = _explorer_state(page)
    assert len(before[1]) == 7 and page.locator(".curves svg").count() == 7
    page.focus("#parameter")
    for _ in range(30):
        page.keyboard.press("ArrowLeft")
    after = _explorer_state(page)
    assert after[0] != before[0] and after[1] != before[1]
    data = json.loads(page.text_content("#explorer-data"))
    branch = data["branches"][data["initial"]]
    index = int(page.input_value("#parameter"))
    assert after[1] == [f"{branch['q'][j][index]:.5f}" for j in range(7)]  # the page prints redkin's numbers
    assert "nearly S-R-S" in page.text_content("body")
    page.select_option("#branch", "5")
    assert page.input_value("#branch") == "5"
    assert view.sideways() <= 0 and not view.errors
