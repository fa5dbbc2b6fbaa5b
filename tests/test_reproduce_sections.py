"""The main job: every section of the report runs, and disagrees with the papers only where explained.

All tests read one full report (tests/report_builds.py), built once per session.
"""

import json

from report_builds import full_report


def _summary():
    return json.loads((full_report() / "summary.json").read_text())


def _tables(key):
    return _summary()["sections"][key]["tables"]


def _rows(table):
    return [dict(zip(table["columns"], row)) for row in table["rows"]]


def _differing(tables):
    return [row for t in tables.values() for row, ok in zip(t["rows"], t.get("agreement", [])) if ok is False]


def test_paper_000_section_agrees_except_the_6_2_2_misprint():
    tables = _tables("000")
    differing = [row[0] for row in _differing(tables)]
    # 6.2.2's misprinted feasible set (three rows) and 6.2.1's set, printed for branch +++ but belonging to ++-
    assert sorted(differing) == ["Psi lower [deg]", "Psi upper [deg]", "Psi, branch +++", "psi_w^opt clamped to Psi [deg]"]
    agreeing = sum(ok is True for table in tables.values() for ok in table.get("agreement", []))
    assert agreeing >= 60
    for row in _differing(tables):
        assert "misprint" in row[-1] or "belongs to branch ++-" in row[-1]
    page = (full_report() / "index.html").read_text()
    assert page.count("<img") >= 3
    for name in ("6_1", "6_2_1", "6_2_2"):  # an explorer for each case, linked from the page
        assert f'href="000_explore_{name}.html"' in page
        assert (full_report() / f"000_explore_{name}.html").stat().st_size > 10_000


def test_differences_are_ours_minus_the_paper():
    for section in _summary()["sections"].values():
        for table in section["tables"].values():
            if "agreement" not in table:
                continue
            for quantity, paper, ours, difference, verdict in table["rows"]:
                numbers = all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in (paper, ours))
                assert (difference is None) is not numbers, quantity
                if numbers:
                    assert abs(difference - (ours - paper)) < 1e-12


def test_counts_in_summary_json_equal_the_verdicts():
    for key, section in _summary()["sections"].items():
        verdicts = [ok for t in section["tables"].values() for ok in t.get("agreement", [])]
        assert section["counts"] == {"agrees": verdicts.count(True), "differs": verdicts.count(False),
                                     "no_value": verdicts.count(None)}, key


def test_paper_001_section_has_no_disagreement():
    tables = _tables("001")
    assert not _differing(tables)
    for row in _rows(tables["ik_round_trip"]):
        assert row["max joint error [rad]"] < 1e-8 and row["max FK error (pose matrix entries)"] < 1e-8, row


def test_paper_003_section_meets_every_claim():
    tables = _tables("003")
    assert tables["claims"]["agreement"] == [True] * len(tables["claims"]["rows"])
    methods = {row["method"]: row for row in _rows(tables["methods"])}
    sc = next(row for name, row in methods.items() if name.startswith("sc"))
    assert sc["crossings of D_e = 0"] == 1
    page = (full_report() / "index.html").read_text()
    assert "True" not in page and "False" not in page  # Python's booleans never reach a sentence
    assert "feasible arm angles along the Fig. 1 path" in page  # the offset-elbow arm-angle subsection
    assert (full_report() / "003_wam_arm_angles.png").exists()


def test_paper_004_section_differs_only_where_the_goals_conflict():
    tables = _tables("004")
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
