"""The report framework: HTML page, summary.json, comparisons in words."""

import json

import pytest

from redkin import reproduce
from redkin.cli.main import main
from redkin.reproduce.report import Comparison


def test_comparison_verdicts():
    assert Comparison("x", 1.0, 1.0004, tolerance=5e-4).agrees
    differs = Comparison("x", 1.0, 2.0, note="misprint")
    assert differs.agrees is False and "DIFFERS" in differs.verdict() and "misprint" in differs.verdict()
    assert Comparison("x", None, 2.0).agrees is None
    assert "no value" in Comparison("x", None, 2.0).verdict()
    assert Comparison("x", "yes", "yes").agrees and Comparison("x", "yes", "yes").verdict() == "agrees"
    words = Comparison("x", "yes", "no, 3 mm short", note="weights")
    assert words.agrees is False and words.verdict() == "DIFFERS; weights"
    assert Comparison("x", "yes", 2.0).agrees is None
    with pytest.raises(ValueError, match="tolerance"):  # a note passed in the tolerance's place
        Comparison("x", "yes", "yes", "a note")


def test_models_section_writes_page_and_summary(tmp_path):
    writers = reproduce.run(tmp_path, ["models"])
    page = (tmp_path / "index.html").read_text()
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert "Robot models" in page and "<table>" in page
    assert set(summary["sections"]) == {"models"}
    tables = summary["sections"]["models"]["tables"]
    assert tables["pa10-7c_parameters"]["rows"][1][2] == 90.0  # alpha_2 = pi/2 in degrees
    for figure in writers["models"].figures:
        assert (tmp_path / figure).stat().st_size > 1000


def test_unknown_section_and_bad_out(tmp_path, capsys):
    with pytest.raises(ValueError, match="unknown section"):
        reproduce.run(tmp_path, ["999"])
    target = tmp_path / "file"
    target.write_text("x")
    assert main(["reproduce", "models", "--out", str(target)]) == 2
    assert "not a directory" in capsys.readouterr().err


def test_unwritable_out_fails_before_any_section_runs(capsys, tmp_path):
    from redkin.cli.main import main

    blocker = tmp_path / "a-file"
    blocker.write_text("")
    for target in ("/proc/forbidden", str(blocker), str(blocker / "report")):
        assert main(["reproduce", "000", "--quiet", "--out", target]) == 2
        captured = capsys.readouterr()
        assert len(captured.err.strip().splitlines()) == 1 and "--out" in captured.err, captured.err
        assert "[000]" not in captured.err  # refused up front, not after the section ran
