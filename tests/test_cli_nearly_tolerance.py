"""The nearly S-R-S tolerance (issue 27, item 1), set from Python and from the command line.

Laws, on the Kinova Gen3 (departures 11.75, 12.75 and 0.35 mm):

- a tolerance above its largest departure (13 mm) keeps it nearly S-R-S, one below (10 mm) makes it a general chain
  whose reason names the tolerance; the same in :func:`redkin.arms.classify.arm_angle_class`,
  :func:`redkin.closed_form.redundancy_parameter`, :func:`redkin.ik`, :func:`redkin.explore.explorer_data` and
  ``redkin robots [--show]``, ``ik --psi``, ``arm-angles`` and ``explore`` with ``--srs-tolerance``;
- the answers at a tolerance that keeps the class equal those at the default (the neighbour does not depend on it);
- no global state: a call with another tolerance leaves the default's class as it was;
- a tolerance that is not a finite number > 0 is a ValueError in Python and exit code 2 with one line on each
  command; ``redkin ik --srs-tolerance`` without ``--psi``/``--q7`` too (the numerical solver does not use it).
"""

from __future__ import annotations

import json

import numpy as np
import pytest

import redkin
from redkin.arms.classify import GENERAL, NEARLY_SRS, arm_angle_class
from redkin.cli.main import main
from redkin.closed_form import redundancy_parameter
from redkin.errors import NotArmAngleClassError
from redkin.explore import explorer_data
from redkin.srs import pose_from

POSITION, ROTATION = [0.3, 0.2, 0.5], [1, 0, 0, 0, -1, 0, 0, 0, -1]
POSE_ARGV = ["--position", *map(str, POSITION), "--rotation", *map(str, ROTATION)]
COMMANDS = {
    "ik": ["ik", "kinova-gen3", *POSE_ARGV, "--psi", "0.3"],
    "arm-angles": ["arm-angles", "kinova-gen3", *POSE_ARGV],
    "explore": ["explore", "kinova-gen3", *POSE_ARGV, "--out", "page.html"],
    "robots --show": ["robots", "--show", "kinova-gen3"],
}
BAD = ["0", "-0.01", "nan", "inf", "-inf", "abc", ""]


def _gen3():
    return redkin.get_robot("kinova-gen3")


def _pose() -> np.ndarray:
    return pose_from(np.array(POSITION, dtype=float), np.array(ROTATION, dtype=float).reshape(3, 3))


def _code(argv: list[str]) -> int:
    try:
        return main(argv)
    except SystemExit as stop:
        return int(stop.code or 0)


def test_the_class_follows_the_tolerance_in_python():
    chain = _gen3()
    assert arm_angle_class(chain, 0.013).kind == NEARLY_SRS
    kind, reason = arm_angle_class(chain, 0.01)
    assert kind == GENERAL and "0.01175 m (beyond the nearly S-R-S tolerance of 0.01 m)" in reason
    assert arm_angle_class(chain).kind == NEARLY_SRS  # no state left behind by the call above
    assert redundancy_parameter(chain, 0.013) == "psi"
    with pytest.raises(NotArmAngleClassError, match=r"tolerance of 0\.01 m"):
        redundancy_parameter(chain, 0.01)
    with pytest.raises(NotArmAngleClassError):
        redkin.ik(chain, _pose(), psi=0.3, srs_tolerance=0.01)
    with pytest.raises(NotArmAngleClassError):
        explorer_data(chain, _pose(), samples=16, srs_tolerance=0.01)


def test_answers_at_another_tolerance_equal_the_defaults():
    chain = _gen3()
    default = redkin.ik(chain, _pose(), psi=0.3)
    wider = redkin.ik(chain, _pose(), psi=0.3, srs_tolerance=0.05)
    np.testing.assert_array_equal(default.exists, wider.exists)
    np.testing.assert_allclose(default.q, wider.q, atol=1e-9)


@pytest.mark.parametrize("tolerance", [0.0, -1.0, float("nan"), float("inf"), "abc", None])
def test_a_bad_tolerance_is_a_value_error(tolerance):
    chain = _gen3()
    if tolerance is not None:
        with pytest.raises(ValueError, match="tolerance"):
            arm_angle_class(chain, tolerance)
        with pytest.raises(ValueError, match="tolerance"):
            redkin.ik(chain, _pose(), psi=0.3, srs_tolerance=tolerance)
        with pytest.raises(ValueError, match="tolerance"):
            explorer_data(chain, _pose(), samples=16, srs_tolerance=tolerance)
    with pytest.raises(ValueError, match="srs_tolerance applies to the closed forms"):
        redkin.ik(chain, _pose(), srs_tolerance=0.02)  # the numerical solver does not use it


def test_robots_show_and_list_follow_the_tolerance(capsys):
    assert main(["robots", "--show", "kinova-gen3", "--srs-tolerance", "0.013", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["class"] == NEARLY_SRS
    assert main(["robots", "--show", "kinova-gen3", "--srs-tolerance", "0.01", "--json"]) == 0
    shown = json.loads(capsys.readouterr().out)
    assert shown["class"] == GENERAL and "tolerance of 0.01 m" in shown["class_reason"]
    assert main(["robots", "--srs-tolerance", "0.01", "--json"]) == 0
    listed = {entry["name"]: entry["class"] for entry in json.loads(capsys.readouterr().out)["robots"]}
    assert listed["kinova-gen3"] == GENERAL and listed["kuka-iiwa14"] == "S-R-S"


def test_ik_and_arm_angles_follow_the_tolerance(capsys):
    assert main([*COMMANDS["ik"], "--srs-tolerance", "0.013", "--all", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["solutions"]
    assert main([*COMMANDS["arm-angles"], "--srs-tolerance", "0.013", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["class"] == NEARLY_SRS


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_a_tolerance_below_the_offsets_refuses_in_one_line(tmp_path, monkeypatch, capsys, command):
    monkeypatch.chdir(tmp_path)
    if command == "robots --show":
        return  # a class, not a refusal: test_robots_show_and_list_follow_the_tolerance
    assert _code([*COMMANDS[command], "--srs-tolerance", "0.01"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "0.01175 m" in err and "tolerance of 0.01 m" in err
    assert not list(tmp_path.glob("*.html"))


@pytest.mark.parametrize("command", sorted(COMMANDS))
@pytest.mark.parametrize("value", BAD)
def test_a_bad_tolerance_exits_2_with_one_line(tmp_path, monkeypatch, capsys, command, value):
    monkeypatch.chdir(tmp_path)
    assert _code([*COMMANDS[command], f"--srs-tolerance={value}"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "--srs-tolerance" in err and "Traceback" not in err
    assert not list(tmp_path.glob("*.html"))


def test_ik_without_a_parameter_refuses_the_tolerance(capsys):
    assert _code(["ik", "kinova-gen3", *POSE_ARGV, "--srs-tolerance", "0.02"]) == 2
    assert "--srs-tolerance" in capsys.readouterr().err
