"""``redkin explore``: writes the page, or refuses with one line and exit code 2 before any work."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from redkin.cli.main import main

POSE = ["--position", "0.65", "0", "0.5", "--rotation", "-1", "0", "0", "0", "1", "0", "0", "0", "-1"]
EXAMPLES = Path(__file__).resolve().parents[1] / "src" / "redkin" / "examples"


def test_writes_one_page_and_says_so(tmp_path, capsys):
    out = tmp_path / "deeper" / "pa10.html"
    assert main(["explore", "pa10-7c", *POSE, "--branch", "+-+", "--deg", "--out", str(out)]) == 0
    page = out.read_text()
    assert page.startswith("<!DOCTYPE html>") and '"unit":"deg"' in page and '"initial":2' in page
    assert "feasible arm angles on" in capsys.readouterr().out


def test_json_names_its_units(tmp_path, capsys):
    out = tmp_path / "iiwa.html"
    assert main(["explore", str(EXAMPLES / "iiwa14.urdf"), *POSE, "--json", "--out", str(out)]) == 0
    printed = json.loads(capsys.readouterr().out)
    assert printed["units"] == {"feasible": "rad", "domain": "rad"} and printed["out"] == str(out)
    assert printed["parameter"] == "psi" and len(printed["feasible"]) == 8
    assert all(count > 721 for count in printed["grid_points"].values()) and out.stat().st_size > 10_000


@pytest.mark.parametrize("change", [
    ["pa10-7c", *POSE, "--out", "page.png"],                        # not a page
    ["pa10-7c", *POSE, "--out", "/proc/forbidden/page.html"],       # unwritable
    ["pa10-7c", *POSE, "--out", "a-directory"],                     # a directory
    ["pa10-7c", *POSE],                                             # no --out
    ["no-such-robot", *POSE, "--out", "page.html"],
    ["planar-5", *POSE, "--out", "page.html"],                      # no closed form: 5 joints
    [str(EXAMPLES / "sawyer.urdf"), *POSE, "--out", "page.html"],   # 7R, neither S-R-S nor of the Franka class
    ["pa10-7c", "--position", "3", "0", "0.5", *POSE[4:], "--out", "page.html"],          # out of reach
    ["pa10-7c", *POSE[:4], "--rotation", "2", "0", "0", "0", "1", "0", "0", "0", "-1", "--out", "page.html"],
    ["pa10-7c", "--position", "nan", "0", "0.5", *POSE[4:], "--out", "page.html"],
    ["pa10-7c", *POSE, "--branch", "++", "--out", "page.html"],
])
def test_bad_input_exits_2_with_one_line_and_writes_nothing(tmp_path, monkeypatch, capsys, change):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "a-directory").mkdir()
    assert _exit_code(["explore", *change]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err, err
    assert not list(tmp_path.glob("*.html")) and not list(tmp_path.glob("*.png"))


def _exit_code(argv: list[str]) -> int:
    try:
        return main(argv)
    except SystemExit as exc:  # argparse's own refusals
        return exc.code
