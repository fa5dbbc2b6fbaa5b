"""``redkin reproduce`` and the report's words: counts with their nouns and verbs in the right number, and no
``-0.0`` in its text."""

from __future__ import annotations

import json

from redkin.cli.main import main
from redkin.reproduce.comparison import Comparison
from redkin.reproduce.page import render_page
from redkin.reproduce.report import SectionWriter, _no_negative_zero


def test_reproduce_says_one_section_and_one_value_in_the_singular(tmp_path, monkeypatch, capsys):
    import redkin.reproduce

    writer = SectionWriter("models", "Models", "", tmp_path, None)
    writer.tables["t"] = {"agreement": [False, True]}
    monkeypatch.setattr(redkin.reproduce, "run", lambda out, papers, progress=None: {"models": writer})
    assert main(["reproduce", "models", "--out", str(tmp_path / "r"), "--quiet"]) == 0
    out = capsys.readouterr().out
    assert "(1 section, 1 paper value that we do not reproduce, explained in the report)" in out, out


def test_a_negative_zero_in_the_reports_text_reads_zero(tmp_path):
    writer = SectionWriter("models", "Models", "", tmp_path)
    writer.text("Sample q = [18.6, 43.9, -8.6, 53.6, -0.0, -7.2, 17.3] deg; -0 and -0.000, but x-0.0 and -0.05 stay.")
    writer.table("t", ["value"], [[-0.0], [1.5]])
    (_, paragraph), _ = writer.blocks
    assert paragraph == ("Sample q = [18.6, 43.9, -8.6, 53.6, 0.0, -7.2, 17.3] deg; 0 and 0.000, but x-0.0 and -0.05 "
                         "stay.")
    assert json.dumps(writer.tables["t"]["rows"]) == "[[0.0], [1.5]]"
    assert _no_negative_zero("(-0.0)") == "(0.0)" and _no_negative_zero("1e-0.0") == "1e-0.0"


def test_the_summary_agrees_in_number(tmp_path):
    """'1 agrees with ours and 1 differs, for a reason given below' -- not '1 agree ... 1 differ, each ...'."""
    writer = SectionWriter("000", "Paper 000: test", "ref", tmp_path)
    writer.comparison("c", [Comparison("a [deg]", 1.0, 1.0, tolerance=0.1),
                            Comparison("b [deg]", 1.0, 2.0, tolerance=0.1, note="a reason")])
    page = render_page([writer], "Report", {"date": "today", "version": "0", "commit": "abc"})
    assert "<strong>1 agrees</strong>" in page and "<strong>1 differs</strong>, for a reason given below" in page
