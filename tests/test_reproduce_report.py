"""The report framework: comparisons in words, numbers as printed, the page and summary.json."""

import json
import re

import matplotlib.pyplot as plt
import numpy as np
import pytest

import redkin
from redkin import reproduce
from redkin.cli.main import main
from redkin.reproduce.comparison import Comparison, Note
from redkin.reproduce.numbers import _scientific, column_format, fixed, printed_decimals
from redkin.reproduce.provenance import build_info
from redkin.reproduce.report import _PIXEL_RATIO, SectionWriter, _png_size, write_report


def test_comparison_verdicts():
    assert Comparison("x", 1.0, 1.0004, tolerance=5e-4).agrees
    differs = Comparison("x", 1.0, 2.0, note="misprint")
    assert differs.agrees is False and "DIFFERS" in differs.verdict() and "misprint" in differs.verdict()
    assert differs.difference == 1.0 and differs.outcome() == "DIFFERS by +1"
    assert Comparison("x", None, 2.0).agrees is None and Comparison("x", None, 2.0).difference is None
    assert "no value" in Comparison("x", None, 2.0).verdict()
    assert Comparison("x", "yes", "yes").agrees and Comparison("x", "yes", "yes").verdict() == "agrees"
    words = Comparison("x", "yes", "no, 3 mm short", note=Note("weights", "the paper's are not given"))
    assert words.agrees is False and words.verdict() == "DIFFERS; weights: the paper's are not given"
    assert words.explanation.reason == "weights" and Comparison("x", 1, 1).explanation is None
    assert Comparison("x", "yes", 2.0).agrees is None
    with pytest.raises(ValueError, match="tolerance"):  # a note passed in the tolerance's place
        Comparison("x", "yes", "yes", "a note")
    with pytest.raises(ValueError, match="note"):
        Comparison("x", 1.0, 1.0, 0.0, 3.0)


def test_paper_digits_plus_one_zero_without_sign():
    assert [printed_decimals(v) for v in (45.991, 45, 90.0, 0.15, -0.532, 1e-05, 2.5e-3)] == [3, 0, 0, 2, 3, 5, 4]
    assert fixed(4.06978e-15, 4) == "0" and fixed(-1e-13, 2) == "0"
    assert fixed(-0.00001, 3) == "0.000" and fixed(-0.0, 2) == "0"  # rounds to zero: never "-0"
    assert fixed(-2.74484, 4, sign=True) == "-2.7448" and fixed(2.74484, 4, sign=True) == "+2.7448"
    assert (_scientific(7.21771e-07) == "7.22 × 10⁻⁷" and _scientific(2.438e9) == "2.44 × 10⁹"
            and _scientific(1.5) == "1.50")


def test_one_format_per_column():
    mixed = [7.6e-7, 0.31, 0.0116]  # seven orders of magnitude: scientific for the whole column
    assert [column_format(mixed)(v) for v in mixed] == ["7.60 × 10⁻⁷", "3.10 × 10⁻¹", "1.16 × 10⁻²"]
    plain = [1.63, 1481.97, 0.887]  # three significant digits of the smallest, same decimals throughout
    assert [column_format(plain)(v) for v in plain] == ["1.630", "1481.970", "0.887"]
    with_zero = [6.3e-15, 0.295, -0.16]
    assert [column_format(with_zero)(v) for v in with_zero] == ["0", "0.295", "-0.160"]
    assert column_format([2.438e9, 0.310294])(0.310294) == "3.10 × 10⁻¹"
    assert column_format([1, 2.5, "n/a", None])(3) == "3" and column_format([None])(None) == "–"


def _small_report(tmp_path):
    writer = SectionWriter("tst", "Paper tst: a test section", "A. Author, a test paper.", tmp_path)
    misprint = Note("misprint in the paper", "a long explanation that must appear once")
    writer.heading("First part")
    writer.comparison("numbers", [
        Comparison("a lower [deg]", -43.246, -45.990843, 5e-4, misprint),
        Comparison("a upper [deg]", 43.246, 45.990843, 5e-4, misprint),
        Comparison("b [deg]", 0.0, 4.06978e-15, 5e-4),
        Comparison("c [deg]", 25.017, 25.0172073, 5e-4),
        Comparison("d [deg]", None, -9.22089),
    ], caption="Section 1: numbers", detail="The pose of section 1.")
    writer.heading("Second part")
    writer.table("plain", ["case", "error [m]", "steps"], [["a", 7.2e-7, 146], ["b", 0.310294, 197]], caption="Runs")
    fig, ax = plt.subplots(figsize=(2, 1))
    ax.plot([0, 1], [0, 1])
    writer.figure(fig, "line", "A line", "Its detail.")
    writer.page("extra", "<!DOCTYPE html><title>x</title>", "An attached page")
    write_report(tmp_path, [writer], "Test report", {"date": "today", "version": "9.9", "commit": "abc"})
    return (tmp_path / "index.html").read_text(), json.loads((tmp_path / "summary.json").read_text())


def test_page_puts_the_summary_first_and_explains_each_difference_once(tmp_path):
    page, summary = _small_report(tmp_path)
    assert '<meta name="viewport" content="width=device-width, initial-scale=1">' in page
    assert page.index('id="summary"') < page.index("Contents") < page.index('id="tst"')
    assert "today" in page and "9.9" in page and "abc" in page and 'href="summary.json"' in page
    assert summary["generated"] == {"date": "today", "version": "9.9", "commit": "abc"}
    assert summary["sections"]["tst"]["counts"] == {"agrees": 2, "differs": 2, "no_value": 1}
    counts = dict(re.findall(r'data-count="(\w+)">(\d+)<', page))
    assert counts == {"agrees": "2", "differs": "2", "no_value": "1"}
    assert page.count("a long explanation that must appear once") == 1  # as a note under the table
    assert page.count("misprint in the paper") == 3  # the note once, the summary's two links
    links = re.findall(r'<li><a href="#(tst-numbers-\d)">', page)
    assert links == ["tst-numbers-1", "tst-numbers-2"] and all(f'id="{a}"' in page for a in links)
    # a mark, never colour alone
    assert page.count("✗ <strong>DIFFERS</strong>") == 2 and page.count('agrees">✓ agrees') == 2
    assert "ours [deg]" in page and "Δ = ours − paper [deg]" in page and ">a lower<" in page  # unit in the header
    assert ">-45.9908<" in page and ">-2.7448<" in page and ">+2.7448<" in page and ">+0.0002<" in page
    assert "e-15" not in page and ">-0<" not in page and "-0.0000" not in page
    assert ">7.20 × 10⁻⁷<" in page and ">3.10 × 10⁻¹<" in page and ">146<" in page
    assert page.count('class="num"') >= 15
    assert 'href="#tst-first-part"' in page and 'href="#tst-second-part"' in page  # subsections in the contents
    assert page.count('href="#top"') == 2 and 'href="tst_extra.html"' in page


def test_figures_are_saved_at_twice_the_size_they_are_shown_and_linked(tmp_path):
    page, _ = _small_report(tmp_path)
    width, height = _png_size(tmp_path / "tst_line.png")
    shown = re.search(r'<a href="tst_line.png"><img src="tst_line.png" width="(\d+)" height="(\d+)"', page)
    assert shown and abs(int(shown[1]) * _PIXEL_RATIO - width) <= 1 and abs(int(shown[2]) * _PIXEL_RATIO - height) <= 1


def test_build_info_names_version_and_commit():
    info = build_info()
    assert (info["version"] == redkin.__version__ and info["commit"]
            and re.match(r"\d{4}-\d\d-\d\d \d\d:\d\d UTC", info["date"]))


def test_models_section_writes_page_and_summary(tmp_path):
    writers = reproduce.run(tmp_path, ["models"])
    page = (tmp_path / "index.html").read_text()
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert "Robot models" in page and "<table>" in page and "alpha_i [deg]" in page
    assert set(summary["sections"]) == {"models"}
    tables = summary["sections"]["models"]["tables"]
    assert tables["pa10-7c_parameters"]["rows"][1][2] == 90.0  # alpha_2 = pi/2 in degrees
    assert tables["barrett-wam_parameters"]["rows"][0][6] is None  # no limit
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
    blocker = tmp_path / "a-file"
    blocker.write_text("")
    for target in ("/proc/forbidden", str(blocker), str(blocker / "report")):
        assert main(["reproduce", "000", "--quiet", "--out", target]) == 2
        captured = capsys.readouterr()
        assert len(captured.err.strip().splitlines()) == 1 and "--out" in captured.err, captured.err
        assert "[000]" not in captured.err  # refused up front, not after the section ran


def test_data_files_are_saved_beside_the_page_linked_and_listed(tmp_path):
    writer = SectionWriter("tst", "Paper tst: a test section", "A. Author, a test paper.", tmp_path)
    path = writer.data("grid", {"x": np.linspace(0, 1, 5), "measure": np.eye(3)}, "The grid as arrays")
    write_report(tmp_path, [writer], "Test report", {"date": "today", "version": "9.9", "commit": "abc"})
    assert path == tmp_path / "tst_grid.npz"
    with np.load(path) as data:
        np.testing.assert_array_equal(data["x"], np.linspace(0, 1, 5))
        np.testing.assert_array_equal(data["measure"], np.eye(3))
    assert '<a href="tst_grid.npz">The grid as arrays</a>' in (tmp_path / "index.html").read_text()
    assert json.loads((tmp_path / "summary.json").read_text())["sections"]["tst"]["data"] == ["tst_grid.npz"]
