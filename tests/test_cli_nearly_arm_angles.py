"""``redkin arm-angles`` on nearly S-R-S arms: the feasible, singular and optimal arm angles of the real arm, printed
as for exact arms (text and ``--json``), equal to the API's, and ``--target``/``--weights`` taken, not refused."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from redkin.cli.main import main
from redkin.models import get_robot
from redkin.srs import (
    BRANCHES,
    feasible_arm_angles_nearly,
    nearly_srs,
    optimal_arm_angles_nearly,
    pose_from,
    singular_arm_angles_nearly,
)

EXAMPLES = Path(__file__).resolve().parents[1] / "src" / "redkin" / "examples"
POSITION, ROTATION = [0.3, 0.2, 0.5], [1, 0, 0, 0, -1, 0, 0, 0, -1]
ARGV = ["--position", *map(str, POSITION), "--rotation", *map(str, ROTATION)]


def _pose() -> np.ndarray:
    return pose_from(np.array(POSITION, dtype=float), np.array(ROTATION, dtype=float).reshape(3, 3))


def _json(capsys, argv: list[str]) -> dict:
    assert main(argv + ["--json"]) == 0
    return json.loads(capsys.readouterr().out)


def _code(argv: list[str]) -> int:
    """The exit code of ``redkin argv``: the parser's own exit, or main's return."""
    try:
        return main(argv)
    except SystemExit as stop:
        return int(stop.code or 0)


def test_json_equals_the_api_in_degrees(capsys):
    data = _json(capsys, ["arm-angles", "kinova-gen3", *ARGV, "--branch", "+-+", "--deg", "--weights", "1", "0.5",
                          "--target", "10", "20", "30", "40", "50", "60", "70"])
    arm = nearly_srs(get_robot("kinova-gen3"))
    feasible = feasible_arm_angles_nearly(arm, _pose(), "+-+")
    singular = singular_arm_angles_nearly(arm, _pose(), "+-+")
    optimal = optimal_arm_angles_nearly(arm, _pose(), "+-+", target=np.radians([10, 20, 30, 40, 50, 60, 70]),
                                        weights=(1.0, 0.5), feasible=feasible.feasible)
    assert data["class"] == "nearly S-R-S" and "11.75 mm" in data["remarks"][0] and data["branch"] == "+-+"
    assert data["units"]["angles"].startswith("deg")
    np.testing.assert_allclose(np.radians(data["feasible"]).reshape(-1, 2),
                               np.array(feasible.feasible.arcs).reshape(-1, 2), atol=1e-12)
    assert data["feasible_wraps"] == [bool(lo > hi) for lo, hi in feasible.feasible.arcs]
    assert data["complete"] is feasible.complete is True
    assert np.allclose(np.radians(data["singular"]["shoulder"]), singular.shoulder)
    nearest = data["singular"]["wrist_nearest"]
    assert np.allclose(np.radians([nearest["psi"], nearest["angle"]]), singular.wrist_nearest)
    for part in ("shoulder", "wrist", "overall"):
        expected = getattr(optimal, part)
        assert np.isclose(np.radians(data["optimal"][part]["unclamped"]), expected.unclamped)
        assert (data["optimal"][part]["feasible"] is None) == (expected.feasible is None)
        if expected.feasible is not None:
            assert np.isclose(np.radians(data["optimal"][part]["feasible"]), expected.feasible)
    assert "per_joint" not in data  # not computed on nearly S-R-S arms


def test_text_prints_every_part(capsys):
    assert main(["arm-angles", "kinova-gen3", *ARGV]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0] == "kinova-gen3, branch +++; the redundancy parameter is psi, angles in rad"
    assert lines[1].startswith("kinova-gen3 is nearly S-R-S: its exact S-R-S neighbour drops")
    assert lines[2] == "The per-joint sets are not computed on nearly S-R-S arms."
    assert lines[3].startswith("Psi (feasible): [")
    assert lines[4] == "Psi (feasible) of every branch:"
    assert [line.split(":")[0] for line in lines[5:13]] == [f"  branch {b}" for b in BRANCHES]
    assert lines[13].startswith("singular shoulder: [") and "wrist: [" in lines[13]
    assert any(line.startswith("nearest wrist alignment: ") for line in lines)
    for part in ("shoulder", "wrist", "overall"):
        assert any(line.startswith(f"optimal {part}: ") and "-> feasible" in line for line in lines)


def test_a_urdf_nearly_arm(capsys):
    data = _json(capsys, ["arm-angles", str(EXAMPLES / "jaco2.urdf"), "--position", "0.4", "0.1", "0.4",
                          "--rotation", *map(str, ROTATION)])
    assert data["class"] == "nearly S-R-S" and set(data["optimal"]) == {"shoulder", "wrist", "overall"}


@pytest.mark.parametrize("extra, word", [(["--weights", "0", "0"], "weights"), (["--weights", "-1", "1"], "weights"),
                                         (["--target", "0", "0", "0", "0", "0", "0", "nan"], "--target"),
                                         (["--branch", "+x+"], "branch")])
def test_bad_input_exits_2_with_one_line(capsys, extra, word):
    assert _code(["arm-angles", "kinova-gen3", *ARGV, *extra]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and word in err
