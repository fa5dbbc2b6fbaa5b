"""The arm-angle explorer: its numbers obey the laws of the S-R-S functions it calls, and its page holds them."""

from __future__ import annotations

import json
import re

import numpy as np
import pytest

from redkin.circle import wrap_angle
from redkin.explore import explorer_data, explorer_html
from redkin.models import get_robot
from redkin.srs import BRANCHES, feasible_arm_angles, optimal_arm_angles, pose_from

DOWN = np.diag([-1.0, 1.0, -1.0])
CASES = {
    "pa10-7c": pose_from(np.array([0.65, 0.0, 0.5]), DOWN),
    "kuka-iiwa14": pose_from(np.array([0.45, -0.2, 0.55]), np.array([[0, 0, 1], [0, 1, 0], [-1, 0, 0.0]])),
}


@pytest.fixture(scope="module", params=sorted(CASES))
def case(request):
    chain = get_robot(request.param)
    pose = CASES[request.param]
    return chain, pose, explorer_data(chain, pose, "+-+", samples=181)


def test_every_branch_holds_the_exact_set_ends_and_marks(case):
    chain, pose, data = case
    assert [b.branch for b in data.branches] == [str(b) for b in BRANCHES] and data.initial == 2
    assert data.parameter.name == "psi" and data.parameter.domain == (-np.pi, np.pi) and data.parameter.wraps
    for curves in data.branches:
        psi = curves.values
        result = feasible_arm_angles(chain, pose, curves.branch)
        optimal = optimal_arm_angles(chain, pose, curves.branch, feasible=result.feasible).overall
        assert np.all(np.diff(psi) > 0) and psi[0] >= -np.pi and psi[-1] <= np.pi and curves.exists.all()
        assert np.array_equal(curves.arcs.reshape(-1, 2), np.array(result.feasible.arcs).reshape(-1, 2))
        assert curves.full == result.feasible.is_full
        for j in range(7):
            assert np.array_equal(curves.per_joint[j], np.array(result.per_joint[j + 1].arcs).reshape(-1, 2))
        sets = list(result.per_joint.values()) + [result.feasible]
        ends = [e for arcs in sets for iv in arcs.intervals for e in iv]
        assert set(ends) <= set(psi.tolist())  # exactly, not to the nearest grid point
        for mark in curves.marks:
            assert mark.kind in ("feasible", "optimal", "singular")
        optimum = [m for m in curves.marks if m.label == "optimal ψ ([000 eq. 40])"]
        unclamped = float(optimal.unclamped)
        assert len(optimum) == 1 and np.isclose(psi[optimum[0].index], wrap_angle(unclamped), rtol=0, atol=1e-15)
        if result.feasible.is_empty:
            assert not curves.feasible_at.any()
        else:
            clamped = wrap_angle(float(optimal.feasible))
            assert curves.feasible_at[curves.start] and abs(psi[curves.start] - clamped) < 1e-12


def test_the_offset_elbow_wam_without_limits_has_a_full_set_and_no_arc_ends():
    chain = get_robot("barrett-wam")  # paper 003's WAM: an offset elbow, no joint limits
    pose = pose_from(np.array([0.5, 0.2, 0.4]), DOWN)
    curves = explorer_data(chain, pose, samples=64).branches[0]
    assert np.abs(chain.frames(curves.q)[:, -1] - pose).max() < 1e-9
    assert curves.full and curves.feasible_at.all() and curves.within.all()
    assert not [m for m in curves.marks if m.kind == "feasible"]


def test_postures_reach_the_pose_and_are_the_chains_frames(case):
    chain, pose, data = case
    for curves in data.branches:
        frames = chain.frames(curves.q)
        assert np.abs(frames[:, -1] - pose).max() < 1e-9
        assert np.array_equal(curves.origins, frames[..., :3, 3])


def test_limit_flags_are_the_joint_values_and_agree_with_the_exact_sets(case):
    """The flags say whether the shown joint values are within the limits; away from the limits and the singular
    arm angles (where the IK picks one split of two joints) that is membership of the exact sets Psi_i."""
    chain, pose, data = case
    for curves in data.branches:
        q = curves.q
        result = feasible_arm_angles(chain, pose, curves.branch)
        assert np.array_equal(curves.within, (q >= chain.lower - 1e-9) & (q <= chain.upper + 1e-9))
        singular = np.zeros(len(curves.values), dtype=bool)
        singular[[m.index for m in curves.marks if m.kind == "singular"]] = True
        clear = (np.minimum(np.abs(q - chain.lower), np.abs(q - chain.upper)) > 1e-7) & ~singular[:, None]
        exact = np.stack([result.per_joint[j + 1].contains(curves.values) for j in range(7)], axis=1)
        assert np.array_equal(exact[clear], curves.within[clear])
        assert np.array_equal(curves.feasible_at, result.feasible.contains(curves.values, 1e-12))
        rows = ~singular & np.all(clear, axis=1)
        assert np.array_equal(curves.feasible_at[rows], curves.within[rows].all(axis=1))


def test_a_singular_arm_angle_is_marked_and_explained():
    chain = get_robot("pa10-7c")
    pose = pose_from(np.array([0.55, 0.0, 0.767]), np.array([[0, 0, 1], [0, 1, 0], [-1, 0, 0.0]]))
    curves = explorer_data(chain, pose, samples=64).branches[1]  # ++-: the paper's 6.2.1 set, singular at psi = 0
    marks = {m.label: m for m in curves.marks if m.kind == "singular"}
    assert set(marks) == {"shoulder singular ψ (θ2 = 0 or π)", "wrist singular ψ (θ6 = 0 or π)"}
    for mark in marks.values():
        assert abs(curves.values[mark.index]) < 1e-9 and "one split" in mark.note
        assert curves.feasible_at[mark.index]  # psi = 0 lies in the closed set Psi


def test_the_page_is_self_contained_and_holds_the_numbers(case):
    chain, _, data = case
    page = explorer_html(data, degrees=True)
    assert not re.search(r"""(src|href)\s*=\s*["']?(https?:)?//""", page)  # nothing loaded from anywhere
    assert "<script src" not in page and "<link" not in page and "@import" not in page
    payload = json.loads(re.search(r'<script id="explorer-data" type="application/json">(.*?)</script>', page, re.S)[1])
    assert payload["unit"] == "deg" and payload["robot"] == chain.name and len(payload["branches"]) == 8
    branch = payload["branches"][data.initial]
    curves = data.branches[data.initial]
    assert np.allclose(branch["q"], np.degrees(curves.q.T), atol=6e-4)
    assert np.allclose(branch["values"], np.degrees(curves.values), atol=6e-4)
    assert payload["parameter"]["symbol"] == "ψ" and [t[1] for t in payload["parameter"]["ticks"]] == [
        "-180", "-90", "0", "90", "180"]
    assert branch["within"][1] == "".join("1" if v else "0" for v in curves.within[:, 1])
    moving = [o for o in branch["origins"] if "path" in o]
    assert moving and all(len(o["path"]) == 3 * len(curves.values) for o in moving)
    radians = json.loads(re.search(r'type="application/json">(.*?)</script>', explorer_html(data), re.S)[1])
    assert radians["unit"] == "rad" and np.allclose(radians["branches"][0]["q"], data.branches[0].q.T, atol=6e-6)
    assert [t[1] for t in radians["parameter"]["ticks"]] == ["-π", "-π/2", "0", "π/2", "π"]
    assert not re.search(r"-0\.0[,\]]", json.dumps(branch["q"]))  # no -0


def test_an_empty_branch_is_a_value():
    chain = get_robot("pa10-7c")
    pose = pose_from(np.array([0.55, 0.0, 0.767]), np.array([[0, 0, 1], [0, 1, 0], [-1, 0, 0.0]]))
    data = explorer_data(chain, pose, samples=64)
    plus = data.branches[0]
    assert feasible_arm_angles(chain, pose, "+++").is_empty and not len(plus.arcs)
    assert not plus.feasible_at.any() and "empty" in explorer_html(data)


@pytest.mark.parametrize("kwargs, message", [
    ({"samples": 3}, "samples"), ({"samples": 10**6}, "samples"), ({"samples": 100.0}, "samples"),
    ({"branch": "++"}, "branch"), ({"weights": (1.0, float("nan"))}, "weights"),
])
def test_bad_input_is_a_value_error(kwargs, message):
    with pytest.raises(ValueError, match=message):
        explorer_data(get_robot("pa10-7c"), CASES["pa10-7c"], **kwargs)


def test_an_arm_without_a_closed_form_is_refused():
    with pytest.raises(ValueError, match="7 joints"):
        explorer_data(get_robot("planar-5"), CASES["pa10-7c"])
    with pytest.raises(ValueError, match="reach"):
        explorer_data(get_robot("pa10-7c"), pose_from(np.array([3.0, 0.0, 0.5]), DOWN))
