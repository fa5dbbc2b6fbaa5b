"""The report and the explorer as a person sees them: headless Chromium, driven by Playwright.

Playwright is launched on Debian's ``/usr/bin/chromium`` (``.ci/run`` installs
it); it never downloads a browser of its own.  The report is the session's full
report (the ``full_report`` fixture of tests/conftest.py).  Every browser test
here is marked slow: the first builds the whole report.

Without Chromium or Playwright the browser tests skip locally, with the reason
and the install line (also shown as a warning, which ``-q`` prints); under
``CI=true`` they fail instead, so that a broken install step cannot pass as
"2 skipped".  :func:`browser_decision` makes that choice and is tested below.
"""

from __future__ import annotations

import importlib
import json
import os
import subprocess
import sys
import warnings
from collections.abc import Callable, Mapping
from pathlib import Path

import pytest

CHROMIUM = Path("/usr/bin/chromium")
WIDTHS = (1400, 420)  # a desktop and a phone


def missing_browser(chromium: Path = CHROMIUM, import_module: Callable = importlib.import_module) -> str | None:
    """Why the browser tests cannot run here, with the line that installs what is missing; ``None`` if they can."""
    if not (chromium.is_file() and os.access(chromium, os.X_OK)):
        return f"Chromium not found at {chromium}: apt-get install chromium (Debian's package; .ci/run installs it)"
    try:
        import_module("playwright.sync_api")
    except ImportError:
        return "playwright is not installed: pip install -e '.[test]'"
    return None


def browser_decision(environ: Mapping[str, str], missing: str | None) -> str:
    """``"run"`` when nothing is missing; else ``"fail"`` under CI (``CI`` set to true, 1 or yes, as CI services
    set it) and ``"skip"`` on a developer's machine."""
    if missing is None:
        return "run"
    return "fail" if environ.get("CI", "").strip().lower() in ("true", "1", "yes") else "skip"


MISSING = missing_browser()
DECISION = browser_decision(os.environ, MISSING)
if DECISION == "skip":
    warnings.warn(f"the browser tests of {Path(__file__).name} are skipped: {MISSING}", pytest.PytestWarning,
                  stacklevel=1)
#: Every browser test: slow, and skipped (locally) or failed (CI) with the reason when the browser is missing.
browser_test = pytest.mark.skipif(DECISION == "skip", reason=str(MISSING))


def test_browser_decision_fails_in_ci_and_skips_locally_with_the_install_line(tmp_path):
    missing = missing_browser(chromium=tmp_path / "chromium")
    assert missing == (f"Chromium not found at {tmp_path / 'chromium'}: apt-get install chromium (Debian's package; "
                       ".ci/run installs it)")
    for environ, expected in (({"CI": "true"}, "fail"), ({"CI": "1"}, "fail"), ({"CI": "True"}, "fail"),
                              ({}, "skip"), ({"CI": "false"}, "skip"), ({"CI": ""}, "skip")):
        assert browser_decision(environ, missing) == expected, environ
    assert browser_decision({"CI": "true"}, None) == "run" and browser_decision({}, None) == "run"


def test_missing_browser_names_playwright_when_chromium_is_there(tmp_path, monkeypatch):
    chromium = tmp_path / "chromium"
    chromium.write_text("#!/bin/sh\n")
    chromium.chmod(0o755)

    def no_playwright(name):
        raise ModuleNotFoundError(f"No module named {name!r}")

    assert missing_browser(chromium, no_playwright) == "playwright is not installed: pip install -e '.[test]'"
    assert missing_browser(chromium, lambda name: None) is None
    monkeypatch.setenv("CI", "true")
    assert browser_decision(os.environ, missing_browser(tmp_path / "none", lambda name: None)) == "fail"


@browser_test
def test_the_browser_is_there_when_ci_needs_it():
    """Under CI=true a missing Chromium or Playwright fails here, by name, besides each browser test's error."""
    if DECISION == "fail":
        pytest.fail(f"the browser tests cannot run under CI: {MISSING}", pytrace=False)


@pytest.fixture(scope="module")
def browser():
    if DECISION == "fail":
        pytest.fail(f"the browser tests cannot run under CI: {MISSING}", pytrace=False)
    sync_api = importlib.import_module("playwright.sync_api")
    with sync_api.sync_playwright() as playwright:
        chromium = playwright.chromium.launch(executable_path=str(CHROMIUM))
        yield chromium
        chromium.close()


class Page:
    """A page at one width, with the console errors and uncaught exceptions it produced."""

    def __init__(self, browser, url: str, width: int) -> None:
        self.errors: list[str] = []
        self.page = browser.new_page(viewport={"width": width, "height": 900})
        self.page.on("console", lambda message: self.errors.append(message.text) if message.type == "error" else None)
        self.page.on("pageerror", lambda error: self.errors.append(str(error)))
        self.page.goto(url, wait_until="load")

    def sideways(self) -> int:
        """How far the page body scrolls sideways (0 when it fits the window)."""
        return self.page.evaluate("document.documentElement.scrollWidth - window.innerWidth")


@browser_test
@pytest.mark.slow
@pytest.mark.parametrize("width", WIDTHS)
def test_report_reads_at_desktop_and_phone_width(browser, width, full_report):
    report = full_report
    view = Page(browser, (report / "index.html").as_uri(), width)
    page = view.page
    images = page.evaluate("""async () => {
        const results = [];
        for (const img of document.images) {
            try { await img.decode(); results.push([img.getAttribute('src'), img.naturalWidth]); }
            catch (e) { results.push([img.getAttribute('src'), 0]); }
        }
        return results;
    }""")
    assert len(images) >= 15 and all(natural > 0 for _, natural in images), images
    assert view.sideways() <= 0
    assert not view.errors
    summary = json.loads((report / "summary.json").read_text())
    shown = page.evaluate("""() => Array.from(document.querySelectorAll('#counts tbody tr')).map(row => [
        row.dataset.section,
        Object.fromEntries(Array.from(row.querySelectorAll('[data-count]')).map(c => [c.dataset.count, +c.textContent]))
    ])""")
    compared = {key: s["counts"] for key, s in summary["sections"].items() if any(s["counts"].values())}
    assert dict(shown) == compared and len(compared) == 5  # 000, 001, 003, 004 and workspace compare values
    differing = sum(ok is False for s in summary["sections"].values() for t in s["tables"].values()
                    for ok in t.get("agreement", []))
    links = page.evaluate("() => Array.from(document.querySelectorAll('#differs a')).map(a => a.getAttribute('href'))")
    assert len(links) == differing > 0
    targets = page.evaluate("""() => Array.from(document.querySelectorAll('#differs a, nav a'))
        .map(a => a.getAttribute('href')).filter(h => !document.getElementById(h.slice(1)))""")
    assert not targets  # every link of the summary and the contents has its target
    first = page.evaluate("() => document.querySelector('h2').textContent")
    assert first.startswith("Summary")


def _explorer_state(page) -> tuple[str, list[str]]:
    return (page.get_attribute("#arm", "points"),
            page.evaluate("() => Array.from(document.querySelectorAll('#joints td.value')).map(c => c.textContent)"))


@browser_test
@pytest.mark.slow
@pytest.mark.parametrize("width", WIDTHS)
def test_report_explorer_slider_moves_the_arm(browser, width, full_report):
    view = Page(browser, (full_report / "000_explore_6_1.html").as_uri(), width)
    page = view.page
    before = _explorer_state(page)
    assert len(before[1]) == 7 and page.locator(".curves svg").count() == 7
    page.focus("#parameter")
    for _ in range(40):
        page.keyboard.press("ArrowRight")
    after = _explorer_state(page)
    assert after[0] != before[0] and after[1] != before[1]
    data = json.loads(page.text_content("#explorer-data"))
    branch = data["branches"][data["initial"]]
    index = int(page.input_value("#parameter"))
    assert index == branch["start"] + 40
    assert after[1] == [f"{branch['q'][j][index]:.3f}" for j in range(7)]  # the page prints redkin's numbers
    box = page.locator("#arm-view").bounding_box()
    page.mouse.move(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
    page.mouse.down()
    page.mouse.move(box["x"] + box["width"] / 2 + 60, box["y"] + box["height"] / 2 + 20, steps=4)
    page.mouse.up()
    turned = _explorer_state(page)
    assert turned[0] != after[0] and turned[1] == after[1]  # the view turns, the posture stays
    assert view.sideways() <= 0 and not view.errors


@browser_test
@pytest.mark.slow
def test_cli_explorer_of_the_iiwa_switches_branches(browser, tmp_path):
    out = tmp_path / "iiwa.html"
    subprocess.run([sys.executable, "-m", "redkin.cli.main", "explore", "kuka-iiwa14", "--position", "0.45", "-0.2",
                    "0.55", "--rotation", "0", "0", "1", "0", "1", "0", "-1", "0", "0", "--out", str(out)],
                   check=True, capture_output=True)
    view = Page(browser, out.as_uri(), 420)
    page = view.page
    before = _explorer_state(page)
    page.select_option("#branch", "3")
    after = _explorer_state(page)
    assert after != before and page.input_value("#branch") == "3"
    assert page.text_content("#parameter-value").endswith(" rad")
    page.locator("#marks button").first.click()
    assert view.sideways() <= 0 and not view.errors


@browser_test
@pytest.mark.slow
def test_cli_explorer_in_a_cell_draws_the_obstacles_and_names_the_pair(browser, tmp_path):
    """In a cell the page draws the obstacles and the body, opens where the arm is clear, and says which pair meets
    at an arm angle the obstacles remove."""
    from redkin.reproduce.cell_case import cell

    _, _, _, poses = cell()
    pose = poses[len(poses) // 2]
    scene, body, out = tmp_path / "cell.yaml", tmp_path / "body.yaml", tmp_path / "cell.html"
    scene.write_text("margin: 0.01\nobstacles:\n"
                     "  - {name: post, type: capsule, a: [0.33, -0.26, 0], b: [0.33, -0.26, 1.1], radius: 0.04}\n"
                     "  - {name: board, type: box, center: [0.95, 0.2, 0.36], size: [0.3, 0.5, 0.02]}\n")
    body.write_text("capsules:\n  link_3: [{a: [0, 0, -0.2], b: [0, 0, 0], radius: 0.07}]\n"
                    "  link_4: [{a: [0, 0, 0], b: [0, 0.2, 0], radius: 0.07}]\n")
    subprocess.run([sys.executable, "-m", "redkin.cli.main", "explore", "kuka-iiwa14", "--position",
                    *map(repr, pose[:3, 3].tolist()), "--rotation", *map(repr, pose[:3, :3].ravel().tolist()),
                    "--scene", str(scene), "--body", str(body), "--out", str(out)], check=True, capture_output=True)
    view = Page(browser, out.as_uri(), 420)
    page = view.page
    assert page.locator("#arm-view .obstacle").count() == 1 + 12  # the post, the board's twelve edges
    assert page.locator("#arm-view .body").count() == 2 and page.locator("#arm-view .hit").count() == 0
    assert "Clear of the obstacles" in page.text_content("#status")
    assert page.locator(".curves rect.blocked").count() > 0
    data = json.loads(page.text_content("#explorer-data"))
    branch = data["branches"][data["initial"]]
    lo, hi, cause = next(b for b in branch["cell"]["blocked"] if "meets post" in b[2] and b[1] - b[0] > 1e-3)
    inside = next(i for i, v in enumerate(branch["values"]) if lo < v < hi)
    page.fill("#parameter", str(inside))
    page.dispatch_event("#parameter", "input")
    status = page.text_content("#status")
    assert " meets post" in status and f"Removed: {cause}." in status
    assert page.locator("#arm-view .hit").count() >= 1
    assert view.sideways() <= 0 and not view.errors


@browser_test
@pytest.mark.slow
def test_path_playback_in_a_cell_draws_the_obstacles_the_capsules_and_the_distance(browser, tmp_path):
    """``redkin path --playback --scene``: the page draws the post, the board's edges and the arm's capsules, they
    move with the time slider, and the status says the least distance at the slider's time, the page's own number."""
    import numpy as np

    from redkin.models import get_robot

    chain = get_robot("kuka-iiwa14")
    qs = np.linspace([0.3, 0.6, -0.2, -1.2, 0.4, 0.8, 0.1], [-0.5, 0.9, 0.4, -0.7, -0.3, -0.6, 0.9], 10)
    poses, scene, limits, out = (tmp_path / name for name in ("poses.npy", "cell.yaml", "limits.yaml", "p.html"))
    np.save(poses, chain.fk(qs))
    scene.write_text("margin: 0.01\nobstacles:\n"
                     "  - {name: post, type: capsule, a: [0.4, 0.3, 0], b: [0.4, 0.3, 1.2], radius: 0.05}\n"
                     "  - {name: board, type: box, center: [0.95, 0.2, 0.36], size: [0.3, 0.5, 0.02]}\n")
    limits.write_text("acceleration: 10\n")
    subprocess.run([sys.executable, "-m", "redkin.cli.main", "path", "kuka-iiwa14", "--poses", str(poses),
                    "--max-step", "0.2", "--scene", str(scene), "--limits", str(limits), "--playback", str(out)],
                   check=True, capture_output=True)
    view = Page(browser, out.as_uri(), 420)
    page = view.page
    data = json.loads(page.text_content("#playback-data"))
    assert page.locator("#arm-view .obstacle").count() == 1 + 12  # the post, the board's twelve edges
    assert page.locator("#arm-view .body").count() == len(data["cell"]["links"])
    hand = page.locator("#arm-view .body").last.get_attribute("points")  # link_7: it moves (link_0 does not)
    status = page.text_content("#status")
    pair = data["cell"]["pairs"][data["cell"]["closest"][0]]
    assert f"the least distance is {data['cell']['distance'][0]:.4f} m ({pair[0]} and {pair[1]})" in status
    last = len(data["t"]) - 1
    page.fill("#time", str(last))
    page.dispatch_event("#time", "input")
    assert page.locator("#arm-view .body").last.get_attribute("points") != hand
    assert f"{data['cell']['distance'][last]:.4f} m" in page.text_content("#status")
    assert view.sideways() <= 0 and not view.errors


@browser_test
@pytest.mark.slow
def test_cli_explorer_of_the_panda_slides_over_q7(browser, tmp_path):
    """The Franka class's page: a q7 slider over joint 7's range; where a branch has no solution, no arm and a
    status that says so."""
    out = tmp_path / "panda.html"
    half = "0.7071068"  # the Panda's ready pose (flange), branch +++: no solution over part of q7's range
    subprocess.run([sys.executable, "-m", "redkin.cli.main", "explore", "franka-panda", "--position", "0.30689",
                    "0", "0.59028", "--rotation", half, f"-{half}", "0", f"-{half}", f"-{half}", "0", "0", "0", "-1",
                    "--branch", "+++", "--out", str(out)], check=True, capture_output=True)
    view = Page(browser, out.as_uri(), 420)
    page = view.page
    data = json.loads(page.text_content("#explorer-data"))
    branch = data["branches"][data["initial"]]
    assert data["parameter"]["name"] == "q7" and branch["name"] == "+++" and "0" in branch["exists"]
    assert page.text_content("#parameter-value").startswith("q7 = ")
    assert page.locator(".curves svg").count() == 7 and page.locator("#arm").count() == 1
    page.fill("#parameter", str(branch["exists"].index("0")))  # a q7 at which +++ has no solution
    page.dispatch_event("#parameter", "input")
    assert page.locator("#arm").count() == 0 and "has no solution at this q7" in page.text_content("#status")
    assert page.evaluate("() => Array.from(document.querySelectorAll('#joints td.value')).map(c => c.textContent)") \
        == ["—"] * 7
    page.select_option("#branch", "6")  # --+, the ready configuration's branch: a solution at every q7
    assert page.locator("#arm").count() == 1 and "Q7" in page.text_content("#status")
    assert view.sideways() <= 0 and not view.errors



@browser_test
@pytest.mark.slow
@pytest.mark.parametrize("width", WIDTHS)
def test_path_playback_moves_the_arm_along_the_trajectory_and_marks_the_stop(browser, width, tmp_path):
    """``redkin path --playback``: the time slider moves the arm and the joint table to the trajectory's numbers,
    play runs the time forward, and the stop is shaded on every joint's curve and named while the arm rests."""
    import numpy as np

    from tests.test_path_stops import STEP, _sweep, _write_narrow_robot

    robot, poses, limits, out = (tmp_path / name for name in ("narrow.toml", "sweep.npy", "limits.yaml", "p.html"))
    _write_narrow_robot(robot)
    np.save(poses, _sweep(3.0, 22))
    limits.write_text("velocity: 1.5\nacceleration: 10\n")
    subprocess.run([sys.executable, "-m", "redkin.cli.main", "path", str(robot), "--poses", str(poses), "--max-step",
                    str(STEP), "--allow-stops", "--limits", str(limits), "--playback", str(out)],
                   check=True, capture_output=True)
    view = Page(browser, out.as_uri(), width)
    page = view.page
    data = json.loads(page.text_content("#playback-data"))
    assert len(data["stops"]) == 1 and page.locator("#curves svg").count() == 7
    assert page.locator("#curves rect.stop").count() == 7
    arm = page.get_attribute("#arm", "points")
    last = len(data["t"]) - 1
    page.fill("#time", str(last))
    page.dispatch_event("#time", "input")
    assert page.get_attribute("#arm", "points") != arm
    values = page.evaluate("() => Array.from(document.querySelectorAll('#joints td.value')).map(c => c.textContent)")
    assert values[0::2] == [f"{data['q'][j][last]:.3f}" for j in range(7)]
    stop = data["stops"][0]
    inside = next(k for k, t in enumerate(data["t"]) if stop["start"] < t < stop["end"])
    page.fill("#time", str(inside))
    page.dispatch_event("#time", "input")
    assert page.text_content("#status").startswith("Stopped: stop at waypoint")
    page.fill("#time", "0")
    page.dispatch_event("#time", "input")
    page.click("#play")
    page.wait_for_function("() => Number(document.getElementById('time').value) > 3")
    page.click("#play")
    posture = page.get_attribute("#arm", "points")
    box = page.locator("#arm-view").bounding_box()
    page.mouse.move(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
    page.mouse.down()
    page.mouse.move(box["x"] + box["width"] / 2 + 60, box["y"] + box["height"] / 2 + 20, steps=4)
    page.mouse.up()
    assert page.get_attribute("#arm", "points") != posture  # the view turns (the explorer's own drag handler)
    assert page.text_content("#play") == "Play" and view.sideways() <= 0 and not view.errors
