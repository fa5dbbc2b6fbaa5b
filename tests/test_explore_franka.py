"""The explorer of a Franka-class arm: its parameter is q7, and its numbers are those of redkin.franka's functions.

The data's grid spans joint 7's range, its joint values are :func:`redkin.franka.ik` at those q7 (none where a
branch has no solution), its feasible flags are membership of :func:`redkin.franka.feasible_q7`'s arcs, whose ends
are grid points exactly, as are :func:`redkin.franka.optimal_q7`'s optima; the page and the command line name q7.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from redkin.cli.main import main
from redkin.errors import UnreachablePoseError
from redkin.explore import explorer_data, explorer_html
from redkin.franka import BRANCHES, feasible_q7, ik, optimal_q7
from redkin.models import get_robot
from redkin.srs import pose_from

EXAMPLES = Path(__file__).resolve().parents[1] / "src" / "redkin" / "examples"
#: The Panda's "ready" configuration: shoulder -, elbow -, wrist + (branch --+), q7 = pi/4.
READY = np.array([0.0, -np.pi / 4, 0.0, -3 * np.pi / 4, 0.0, np.pi / 2, np.pi / 4])
PANDA = get_robot("franka-panda")


@pytest.fixture(scope="module")
def ready():
    pose = PANDA.fk(READY)
    return pose, explorer_data(PANDA, pose, "--+", samples=181)


def _check_laws(chain, pose, data, samples):
    """Every law of the module docstring, for one arm and pose."""
    sets = feasible_q7(chain, pose)
    low, high = sets.domain
    assert data.parameter.name == "q7" and data.parameter.domain == sets.domain and not data.parameter.wraps
    assert [b.branch for b in data.branches] == [str(b) for b in BRANCHES]
    for index, curves in enumerate(data.branches):
        values = curves.values
        assert values[0] == low and values[-1] == high and np.all(np.diff(values) > 0)  # the grid spans the domain
        assert set(np.linspace(low, high, samples).tolist()) <= set(values.tolist())
        solutions = ik(chain, pose, values, curves.branch)
        exists = solutions.exists[:, 0]
        assert np.array_equal(curves.exists, exists)
        assert np.array_equal(curves.q[exists], solutions.q[exists, 0]) and np.isnan(curves.q[~exists]).all()
        frames = chain.frames(curves.q[exists])
        assert np.array_equal(curves.origins[exists], frames[..., :3, 3]) and np.isnan(curves.origins[~exists]).all()
        if exists.any():
            assert np.abs(frames[:, -1] - pose).max() < 1e-9
        q = curves.q
        assert np.array_equal(curves.within, exists[:, None] & (q >= chain.lower - 1e-9) & (q <= chain.upper + 1e-9))
        arcs = sets.arcs[index]
        assert np.array_equal(curves.arcs, arcs.reshape(-1, 2))
        assert np.array_equal(curves.feasible_at, [sets.contains(float(v), index) for v in values])
        feasible = {m.label: values[m.index] for m in curves.marks if m.kind == "feasible"}
        assert sorted(feasible.values()) == sorted(arcs.ravel().tolist())  # exactly, not to the nearest grid point
        for k, (start, end) in enumerate(arcs):
            assert feasible[f"Q7 arc {k + 1} starts"] == start and feasible[f"Q7 arc {k + 1} ends"] == end
        optimum = optimal_q7(chain, pose, curves.branch, feasible=sets)
        marked = {m.label: values[m.index] for m in curves.marks if m.kind == "optimal"}
        assert marked.get("optimal q7 ([F10])") == optimum.unclamped
        if optimum.feasible is not None:
            assert marked.get("optimal q7 clamped to Q7", optimum.unclamped) == optimum.feasible
            assert values[curves.start] == optimum.feasible and curves.feasible_at[curves.start]
        assert {m.kind for m in curves.marks} <= {"feasible", "optimal"} and curves.per_joint is None
        # away from the arc ends and from the limits, the exact set is what the joint values say
        ends = arcs.ravel()
        away = np.all(np.abs(values[:, None] - ends) > 1e-9, axis=1) if len(ends) else np.ones(len(values), bool)
        clear = np.all(np.minimum(np.abs(q - chain.lower), np.abs(q - chain.upper)) > 1e-7, axis=1)  # NaN: False
        assert np.array_equal(curves.feasible_at[away & clear], curves.within[away & clear].all(axis=1))
        assert not curves.feasible_at[away & ~exists].any()


def test_the_ready_pose_of_the_panda(ready):
    pose, data = ready
    _check_laws(PANDA, pose, data, 181)
    assert str(BRANCHES[data.initial]) == "--+"
    curves = data.branches[data.initial]
    assert curves.feasible_at[np.searchsorted(curves.values, np.pi / 4)]  # the ready q7 is feasible on its branch
    assert len(curves.arcs) and curves.exists.all()
    assert any(not b.exists.all() for b in data.branches)  # some branches vanish over part of the range


@settings(max_examples=8, deadline=None, derandomize=True)
@given(st.sampled_from(["franka-panda", "franka-fr3"]),
       st.lists(st.floats(0.02, 0.98), min_size=7, max_size=7))
def test_random_in_limit_poses(name, fractions):
    chain = get_robot(name)
    q = chain.lower + (chain.upper - chain.lower) * np.array(fractions)
    pose = chain.fk(q)
    data = explorer_data(chain, pose, samples=40)
    _check_laws(chain, pose, data, 40)
    assert any(curves.feasible_at.any() for curves in data.branches)  # q itself is feasible on one branch


def test_the_page_names_q7_and_holds_the_numbers(ready):
    _, data = ready
    page = explorer_html(data)
    assert "<title>q7 explorer: franka-panda</title>" in page and 'aria-label="q7"' in page
    for word in ("ψ", "Ψ", "arm angle", "θ"):
        assert word not in page, word
    payload = json.loads(re.search(r'<script id="explorer-data" type="application/json">(.*?)</script>', page, re.S)[1])
    assert payload["parameter"]["name"] == "q7" and payload["parameter"]["symbol"] == "q7"
    assert payload["parameter"]["domain"] == [-2.8973, 2.8973]
    assert [t[1] for t in payload["parameter"]["ticks"]] == ["-3π/4", "-π/2", "-π/4", "0", "π/4", "π/2", "3π/4"]
    for branch, curves in zip(payload["branches"], data.branches):
        assert np.allclose(branch["values"], curves.values, atol=6e-6)
        assert branch["exists"] == "".join("1" if v else "0" for v in curves.exists)
        for j in range(7):  # no solution: null, and the curve breaks there
            shown = np.array([np.nan if v is None else v for v in branch["q"][j]])
            assert np.array_equal(np.isnan(shown), ~curves.exists)
            assert np.allclose(shown[curves.exists], curves.q[curves.exists, j], atol=6e-6)
        assert branch["per_joint"] is None and branch["label"].startswith(f"{curves.branch}: Q7 = ")
    degrees = json.loads(re.search(r'type="application/json">(.*?)</script>', explorer_html(data, True), re.S)[1])
    assert [t[1] for t in degrees["parameter"]["ticks"]] == ["-135", "-90", "-45", "0", "45", "90", "135"]


def test_weights_and_an_unreachable_pose_are_refused():
    with pytest.raises(ValueError, match="weights"):
        explorer_data(PANDA, PANDA.fk(READY), weights=(0.5, 0.5))
    with pytest.raises(UnreachablePoseError, match="reach"):
        explorer_data(PANDA, pose_from(np.array([3.0, 0.0, 0.5]), np.diag([-1.0, 1.0, -1.0])))


def test_the_command_line_writes_the_q7_page(tmp_path, capsys):
    pose = PANDA.fk(READY)
    position = [f"{v:.17g}" for v in pose[:3, 3]]
    rotation = [f"{v:.17g}" for v in pose[:3, :3].ravel()]
    out = tmp_path / "panda.html"
    argv = ["explore", "franka-panda", "--position", *position, "--rotation", *rotation, "--branch", "--+"]
    assert main([*argv, "--out", str(out)]) == 0
    assert "feasible values of q7 on 2 of 8 branches" in capsys.readouterr().out
    assert "q7 explorer" in out.read_text()
    assert main([*argv, "--deg", "--json", "--force", "--out", str(out)]) == 0
    printed = json.loads(capsys.readouterr().out)
    sets = feasible_q7(PANDA, pose)
    assert printed["parameter"] == "q7" and printed["units"] == {"feasible": "deg", "domain": "deg"}
    assert np.allclose(printed["domain"], np.degrees(sets.domain), rtol=0, atol=1e-9)
    for index, label in enumerate(BRANCHES):
        assert np.allclose(np.array(printed["feasible"][str(label)]).reshape(-1, 2), np.degrees(sets.arcs[index]),
                           rtol=0, atol=1e-9)
        assert not any(printed["feasible_wraps"][str(label)])


def test_franka_s_own_urdf_gets_the_q7_page(tmp_path, capsys):
    """examples/fr3.urdf as a new user has it: the hand's TCP as the tool (its default tip), and the flange."""
    for tip in ([], ["--tip", "fr3_link8"]):
        out = tmp_path / f"fr3{len(tip)}.html"
        argv = ["explore", str(EXAMPLES / "fr3.urdf"), *tip, "--position", "0.4", "0.1", "0.4",
                "--rotation", "1", "0", "0", "0", "-1", "0", "0", "0", "-1", "--json", "--out", str(out)]
        assert main(argv) == 0
        printed = json.loads(capsys.readouterr().out)
        assert printed["parameter"] == "q7" and any(printed["feasible"].values())
