"""The main job: every section of the report runs, and disagrees with the papers only where explained.

All tests read one full report (the ``full_report`` fixture of tests/conftest.py), built once per session;
they are marked slow.
"""

import json

import numpy as np
import pytest

from redkin.circle import arc_length
from redkin.models import get_robot
from redkin.srs import BRANCHES, feasible_arm_angles, pose_from, reachable
from redkin.workspace import super_fibonacci_rotations

pytestmark = pytest.mark.slow


def _summary(report):
    return json.loads((report / "summary.json").read_text())


def _tables(report, key):
    return _summary(report)["sections"][key]["tables"]


def _rows(table):
    return [dict(zip(table["columns"], row)) for row in table["rows"]]


def _differing(tables):
    return [row for t in tables.values() for row, ok in zip(t["rows"], t.get("agreement", [])) if ok is False]


def test_paper_000_section_agrees_except_the_6_2_2_misprint(full_report):
    tables = _tables(full_report, "000")
    differing = [row[0] for row in _differing(tables)]
    # 6.2.2's misprinted feasible set (three rows) and 6.2.1's set, printed for branch +++ but belonging to ++-
    assert sorted(differing) == ["Psi lower [deg]", "Psi upper [deg]", "Psi, branch +++",
                                 "psi_w^opt clamped to Psi [deg]"]
    agreeing = sum(ok is True for table in tables.values() for ok in table.get("agreement", []))
    assert agreeing >= 60
    for row in _differing(tables):
        assert "misprint" in row[-1] or "belongs to branch ++-" in row[-1]
    page = (full_report / "index.html").read_text()
    assert page.count("<img") >= 3
    for name in ("6_1", "6_2_1", "6_2_2"):  # an explorer for each case, linked from the page
        assert f'href="000_explore_{name}.html"' in page
        assert (full_report / f"000_explore_{name}.html").stat().st_size > 10_000


def test_paper_000_6_2_2_walked_as_paths_beside_the_global_path(full_report):
    """The 6.2.2 extension: on the paper's sweep and on the constructed line the global path's row is
    resolve_path's own path (judged lawful: no failure, its clearance, steps within the bound); on the line
    Gamma_0 and Gamma fail where the global path does not; no paper value, and the text says so."""
    from redkin.paths import resolve_path
    from redkin.reproduce import paper_000

    rows = _rows(_tables(full_report, "000")["s6_2_2_paths"])
    walks = {}
    for row in rows:
        walks.setdefault(row["path"].split(":")[0], []).append(row)
    assert sorted(walks) == ["constructed", "sweep"] and all(len(w) == 4 for w in walks.values())
    chain = get_robot("pa10-7c")
    a, b = np.radians(paper_000._LINE_START_DEG), np.radians(paper_000._LINE_END_DEG)
    q_line = a + (b - a) * np.linspace(0.0, 1.0, paper_000._LINE_WAYPOINTS)[:, None]
    line = chain.fk(q_line)
    own = np.degrees(np.minimum(q_line - chain.lower, chain.upper - q_line).min())
    for walk, step in (("constructed", paper_000._LINE_STEP_DEG), ("sweep", paper_000._SWEEP_STEP_DEG)):
        fixed, clamped, _, ours = walks[walk]
        assert fixed["arm angle chosen by"].startswith("Gamma_0")
        assert clamped["arm angle chosen by"].startswith("Gamma:")
        assert ours["arm angle chosen by"].startswith("global path")
        assert ours["first failure"].startswith("none") and ours["largest step / bound"] <= 1.0 + 1e-9
        assert ours["largest step [deg]"] == pytest.approx(ours["largest step / bound"] * step, abs=1e-12)
        assert fixed["first failure"].startswith("waypoint") and ours["smallest clearance [deg]"] > 0.0
    fixed, clamped, _, ours = walks["constructed"]
    assert clamped["first failure"].startswith("waypoint") and clamped["largest step / bound"] > 1.0
    result = resolve_path(chain, line, np.radians(paper_000._LINE_STEP_DEG))
    assert ours["smallest clearance [deg]"] == pytest.approx(np.degrees(result.clearance), abs=1e-9)
    assert ours["smallest clearance [deg]"] > own  # farther from the limits than the line the poses came from
    fixed, clamped, _, ours = walks["sweep"]
    assert fixed["first failure"].startswith("waypoint 0: limit")  # psi = 0 is infeasible beyond Gamma_0
    assert clamped["waypoints within limits"] == ours["waypoints within limits"] == "295 of 295"
    assert ours["smallest clearance [deg]"] >= clamped["smallest clearance [deg]"]
    page = (full_report / "index.html").read_text()
    assert "extension beyond paper 000 (issue 26): the paper prints no value" in page
    for name in ("paths_sweep", "paths_line"):
        assert (full_report / f"000_{name}.png").exists() and f"000_{name}.png" in page


def test_paper_000_paths_timed_within_their_limits_and_the_seam_with_one_stop(full_report):
    """Issue 41's case: the sweep, the line and the seam timed within the stated assumed limits (every sample at
    most the limit), the seam failing without stops and passing with the one stop the text names."""
    from redkin.paths import resolve_path
    from redkin.reproduce import paper_000

    rows = {row["path"]: row for row in _rows(_tables(full_report, "000")["s6_2_2_timed"])}
    assert sorted(rows) == ["constructed line", "seam, with stops", "sweep"]
    for row in rows.values():
        assert 0.9 < row["max |qd| / limit"] <= 1.0 and 0.9 < row["max |qdd| / limit"] <= 1.0
        assert row["duration [s]"] > 0 and row["samples"] == int(np.ceil(row["duration [s]"] * 1000.0 - 1e-9)) + 1
    assert rows["seam, with stops"]["stops"] == 1 and rows["sweep"]["stops"] == rows["constructed line"]["stops"] == 0
    chain = get_robot("pa10-7c")
    q = np.tile(np.radians(paper_000._SEAM_POSTURE_DEG), (paper_000._SEAM_WAYPOINTS, 1))
    q[:, 0] = np.linspace(*paper_000._SEAM_JOINT1, paper_000._SEAM_WAYPOINTS)
    (stop,) = resolve_path(chain, chain.fk(q), np.radians(paper_000._SEAM_STEP_DEG), allow_stops=True).stops
    page = (full_report / "index.html").read_text()
    assert "Without stops: no path: waypoint" in page and stop.message in page and "assumed" in page


def test_differences_are_ours_minus_the_paper(full_report):
    for section in _summary(full_report)["sections"].values():
        for table in section["tables"].values():
            if "agreement" not in table:
                continue
            for quantity, paper, ours, difference, _verdict in table["rows"]:
                numbers = all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in (paper, ours))
                assert (difference is None) is not numbers, quantity
                if numbers:
                    assert abs(difference - (ours - paper)) < 1e-12


def test_counts_in_summary_json_equal_the_verdicts(full_report):
    for key, section in _summary(full_report)["sections"].items():
        verdicts = [ok for t in section["tables"].values() for ok in t.get("agreement", [])]
        assert section["counts"] == {"agrees": verdicts.count(True), "differs": verdicts.count(False),
                                     "no_value": verdicts.count(None)}, key


def test_paper_001_section_has_no_disagreement(full_report):
    tables = _tables(full_report, "001")
    assert not _differing(tables)
    for row in _rows(tables["ik_round_trip"]):
        assert row["max joint error [rad]"] < 1e-8 and row["max FK error (pose matrix entries)"] < 1e-8, row


def test_paper_003_section_meets_every_claim(full_report):
    tables = _tables(full_report, "003")
    assert tables["claims"]["agreement"] == [True] * len(tables["claims"]["rows"])
    methods = {row["method"]: row for row in _rows(tables["methods"])}
    sc = next(row for name, row in methods.items() if name.startswith("sc"))
    assert sc["crossings of D_e = 0"] == 1
    page = (full_report / "index.html").read_text()
    assert "True" not in page and "False" not in page  # Python's booleans never reach a sentence
    assert "feasible arm angles along the Fig. 1 path" in page  # the offset-elbow arm-angle subsection
    assert (full_report / "003_wam_arm_angles.png").exists()


def test_paper_004_section_differs_only_where_the_goals_conflict(full_report):
    tables = _tables(full_report, "004")
    fig6 = tables["fig6"]
    for row, ok in zip(fig6["rows"], fig6["agreement"]):
        over_constrained = "(c)" in row[0] or "(d)" in row[0]
        assert ok is (not over_constrained), row
        if over_constrained:
            assert "over-constrained" in row[-1]
    assert tables["fig8"]["agreement"] == [True] * 3
    for row in _rows(tables["runs"]):
        assert row["limit violations"] == 0 and row["clamped motion [rad]"] == 0.0
        assert row["status"] == ("stalled" if "literal" in row["case"] else "converged"), row
    for row in _rows(tables["obstacle_runs"]):
        assert row["status"] == "reached" and row["min clearance [m]"] > 0.0 > row["unobstructed min clearance [m]"]
        assert row["limit violations"] == 0 and row["clamped motion [rad]"] == 0.0


def _map_arrays(report, name):
    with np.load(report / f"workspace_{name}_map.npz") as data:
        return dict(data)


def test_workspace_section_map_entries_equal_direct_feasible_arm_angles(full_report):
    """Sampled entries of the report's maps against feasible_arm_angles; the indices and the table from their
    definitions."""
    tables = _tables(full_report, "workspace")
    assert not _differing(tables)
    rows = {row["arm"]: row for row in _rows(tables["maps"])}
    assert sorted(rows) == ["kuka-iiwa14", "pa10-7c"]
    rng = np.random.default_rng(14)
    for name, row in rows.items():
        arm, arrays = get_robot(name), _map_arrays(full_report, name)
        measure = arrays["measure"]
        m, n = row["orientations"], measure.shape[0]
        assert measure.shape == (n, n, n, m, 8) and row["grid"] == f"{n}^3" and row["pose-branch sets"] == measure.size
        np.testing.assert_array_equal(arrays["rotation"], super_fibonacci_rotations(m))
        best = measure.max(axis=-1)
        reachable_count = (best > 0).sum(axis=-1)
        np.testing.assert_array_equal(arrays["reachability"], reachable_count / m)
        np.testing.assert_allclose(arrays["redundancy"],
                                   best.sum(axis=-1) / (2 * np.pi * np.maximum(reachable_count, 1)), rtol=1e-12)
        reached = arrays["reachability"] > 0
        assert row["reachable positions [%]"] == pytest.approx(100 * reached.mean())
        assert row["reachable poses [%]"] == pytest.approx(100 * arrays["reachability"].mean())
        assert row["mean redundancy where reachable"] == pytest.approx(arrays["redundancy"][reached].mean())
        assert 5 < row["reachable positions [%]"] < 60 and 0 < row["mean redundancy where reachable"] < 1
        inside, outside = np.argwhere(best > 0), np.argwhere(best == 0)
        samples = np.concatenate([inside[rng.choice(len(inside), 12, replace=False)],
                                  outside[rng.choice(len(outside), 4, replace=False)]])
        for i, j, k, o in samples:
            pose = pose_from(np.array([arrays["x"][i], arrays["y"][j], arrays["z"][k]]), arrays["rotation"][o])
            for column, branch in enumerate(BRANCHES):
                expected = 0.0
                if reachable(arm, pose):
                    expected = feasible_arm_angles(arm, pose, branch).feasible.length  # arcs may wrap past pi
                assert measure[i, j, k, o, column] == pytest.approx(expected, abs=1e-9), (name, i, j, k, o, branch)
    page = (full_report / "index.html").read_text()
    for name in rows:
        assert f'href="workspace_{name}_map.npz"' in page and (full_report / f"workspace_{name}_map.png").exists()


def test_workspace_section_gamma_line_equals_the_6_2_2_computation(full_report):
    """The line's Gamma is section 000's Gamma (found there with feasible_arm_angles), and the line's measure is
    positive exactly inside it."""
    ours = {row["quantity"]: row["ours"] for row in _rows(_tables(full_report, "workspace")["gamma_line"])}
    paper_000 = {row["quantity"]: row["ours"] for row in _rows(_tables(full_report, "000")["s6_2_2"])}
    for side in ("lower", "upper"):
        gamma = paper_000[f"Gamma {side} [deg] (psi controlled)"]
        assert ours[f"Gamma {side} [deg] (psi controlled): measure on +++ > 0"] == pytest.approx(gamma, abs=1e-9)
        assert ours[f"Gamma {side} [deg]: map reachability (any branch)"] == pytest.approx(gamma, abs=1e-9)
    with np.load(full_report / "workspace_gamma_line.npz") as data:
        gamma, measure = data["gamma"], data["measure"]
    plus = [str(b) for b in BRANCHES].index("+++")
    bound = np.radians(ours["Gamma upper [deg] (psi controlled): measure on +++ > 0"])
    np.testing.assert_array_equal(measure[:, plus] > 0, np.abs(gamma) < bound)
    np.testing.assert_array_equal(np.delete(measure, plus, axis=1), 0.0)  # the other branches are empty all along
    arm = get_robot("pa10-7c")
    eq_41 = pose_from(np.array([0.65, 0.0, 0.5]), np.diag([-1.0, 1.0, -1.0]))
    width = feasible_arm_angles(arm, eq_41, "+++").feasible.length
    assert measure[np.flatnonzero(gamma == 0.0)[0], plus] == pytest.approx(width, abs=1e-12)
    assert ours["measure on +++ at gamma = 0 [deg] (the pose of [000 eq. 41])"] == pytest.approx(np.degrees(width),
                                                                                                 abs=1e-9)


def test_models_section_has_the_franka_case_over_q7(full_report):
    """The FR3 case: its rows are redkin.franka.feasible_q7's arcs (degrees), with a figure and an explorer; no
    paper value, and the text says so."""
    from redkin.franka import BRANCHES as Q7_BRANCHES
    from redkin.franka import feasible_q7
    from redkin.reproduce.models_section import _FRANKA_READY

    arm = get_robot("franka-fr3")
    sets = feasible_q7(arm, arm.fk(_FRANKA_READY))
    rows = _rows(_tables(full_report, "models")["franka_q7_sets"])
    for label, arcs in zip(Q7_BRANCHES, sets.arcs):
        mine = [row for row in rows if row["branch"] == str(label)]
        if not len(arcs):
            assert [row["arc"] for row in mine] == ["none"]
            continue
        assert [row["arc"] for row in mine] == list(range(1, len(arcs) + 1))
        np.testing.assert_allclose([[row["start [deg]"], row["end [deg]"]] for row in mine], np.degrees(arcs),
                                   rtol=0, atol=1e-12)
    assert any(len(arcs) for arcs in sets.arcs)
    page = (full_report / "index.html").read_text()
    assert "extension beyond paper 000" in page and 'href="models_franka_explore.html"' in page
    assert (full_report / "models_franka_q7_curves.png").exists()
    assert '"name":"q7"' in (full_report / "models_franka_explore.html").read_text()


def test_models_section_has_the_worked_cell(full_report):
    """The iiwa14 in a cell: each branch's widths are those of collision_free_arm_angles at the middle waypoint
    (independently summed here), the path of the limits alone runs into the post, and the path in the cell keeps the
    margin at every waypoint, measured here, with every step proved clear."""
    from redkin.arms import arm
    from redkin.collision import clearance, collision_free_arm_angles, step_clearance
    from redkin.paths import resolve_path
    from redkin.reproduce.cell_case import _MAX_STEP, cell

    chain, body, scene, poses = cell()
    free = collision_free_arm_angles(arm(chain), poses[len(poses) // 2], body, scene)
    rows = _rows(_tables(full_report, "models")["cell_sets"])
    assert [row["branch"] for row in rows] == list(free.branches)
    for row, limits, clear in zip(rows, free.limits, free.free):
        for arcs, column in ((limits, "width [deg]"), (clear, "free width [deg]")):
            width = sum(arc_length(lo, hi) for lo, hi in arcs.bounds.tolist())
            assert row[column] == pytest.approx(np.degrees(width), abs=1e-9)
    assert any(row["free width [deg]"] < row["width [deg]"] - 1.0 for row in rows)  # the post removes arm angles
    plain, inside = _rows(_tables(full_report, "models")["cell_paths"])
    expected = resolve_path(chain, poses, _MAX_STEP, body=body, scene=scene)
    assert plain["least distance [m]"] < 0.0 and "post" in plain["closest pair"]
    measured = clearance(chain, body, scene, expected.q).distance
    assert inside["least distance [m]"] == pytest.approx(float(measured.min()), abs=1e-12)
    assert measured.min() >= scene.margin - 1e-12
    assert step_clearance(chain, body, scene, expected.q).certified.all()
    assert inside["steps proved clear"] == f"{len(poses) - 1} of {len(poses) - 1}"
    page = (full_report / "index.html").read_text()
    assert "the elbow swings around the post" in page
    assert (full_report / "models_cell_sets.png").exists() and (full_report / "models_cell_arm.png").exists()
    assert (full_report / "models_cell_path_plane.png").exists()
    assert "collision-free arm angles along the line" in page
