"""Feasible arm angles of nearly S-R-S arms on the real arm (:mod:`redkin.srs.nearly.feasible`).

Laws, on the Kinova Gen3 and Jaco2 (their continuous joints limited to +-2.9 rad, so that every joint's limits cut
the circle) and the ROS-Industrial iiwa:

- **the set equals dense sampling**: at every sampled arm angle farther than :data:`AT_AN_END` from the set's
  ends, the set holds it exactly when :func:`redkin.srs.nearly.ik` finds the branch's solution within the limits,
  or the branch has a second solution there within the limits (a witness found along the self-motion);
- **every end is a change**: just inside an end the branch is feasible where the solver finds it (near the
  stretched elbow it may miss it at a single arm angle; where its row lies outside the limits, a second solution
  within them is witnessed), just outside it is not (no exact solution: beyond a fold a certified row may be found);
- the narrow islands and gaps that a grid of 720 arm angles misses, found by the benchmark near a singular wrist
  or shoulder (``benchmarks/README.md``, issue 27), are in the set exactly, checked on a window sampled 10^-5 rad
  apart;
- **a straight wrist's gap is left out** (issue 38): on Gen3 poses with the wrist within 1e-4 rad of straight, the
  arm angles where the branch has no solution (by ``nearly.ik`` and on the self-motion) are not in the set;
- **between the neighbour's sets**: the set holds the neighbour's exact set for the limits tightened by its
  ``delta`` and lies within the one for the limits loosened by it, where both arms solve the branch everywhere;
- :func:`redkin.srs.nearly.self_motion_rates` equals the central differences of the polished solutions in the arm
  angle, and is the self-motion: the Jacobian maps it to zero;
- bad input raises ValueError.
"""

from __future__ import annotations

import functools
from pathlib import Path

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from redkin.errors import RedkinError
from redkin.srs import (
    BRANCHES,
    branch_solutions,
    feasible_arm_angles_nearly,
    feasible_arm_angles_nearly_all,
    nearly_srs,
)
from redkin.srs.branches import parse_branch
from redkin.srs.nearly import NearlySRS, arm_angle, branch_of, ik, self_motion_rates
from tests.support.nearly_witness import exact, witnessed

EXAMPLES = Path(__file__).resolve().parents[1] / "src" / "redkin" / "examples"
#: Sampled arm angles this close to an end [rad] may fall either side: ends are located to 1e-10 rad.
AT_AN_END = 1e-8
#: The limit given to the Gen3's and Jaco2's continuous joints [rad].
CONTINUOUS_LIMIT = 2.9
#: Arm angles at most where a second solution's witness is sought (:func:`_disagreements`).
WITNESSED = 5


@functools.cache
def _arm(name: str) -> NearlySRS:
    from redkin.urdf import load_urdf

    if name == "gen3":
        chain = load_urdf(EXAMPLES / "gen3.urdf", base="base_link", tip="end_effector_link")
    elif name == "jaco2":
        chain = load_urdf(EXAMPLES / "jaco2.urdf", base="j2s7s300_link_base", tip="j2s7s300_link_7")
    else:
        chain = load_urdf(EXAMPLES / "iiwa14_rosi.urdf")
    lower = np.where(np.isfinite(chain.lower), chain.lower, -CONTINUOUS_LIMIT)
    upper = np.where(np.isfinite(chain.upper), chain.upper, CONTINUOUS_LIMIT)
    return nearly_srs(chain.with_limits(lower, upper))


def _random_pose(name: str, seed: int) -> tuple[NearlySRS, np.random.Generator, np.ndarray]:
    """The arm, a generator seeded with ``seed``, and the pose of joint values uniform within the limits."""
    arm = _arm(name)
    rng = np.random.default_rng(seed)
    return arm, rng, arm.chain.fk(rng.uniform(arm.chain.lower, arm.chain.upper))


def _sampled(arm: NearlySRS, pose: np.ndarray, branch: str, psi: np.ndarray) -> np.ndarray:
    """Whether the branch's certified solution at each arm angle ``psi`` lies within the limits."""
    return ik(arm, np.broadcast_to(pose, psi.shape + (4, 4)), psi, branch).within_limits[:, 0]


def _disagreements(arm: NearlySRS, pose: np.ndarray, branch: str, psi: np.ndarray) -> np.ndarray:
    """The arm angles of sorted ``psi`` farther than :data:`AT_AN_END` from the set's ends where set and sampling
    differ, but for a single sample where the solver misses the branch between two within the limits (an isolated
    miss of nearly.ik near the stretched elbow, not a gap of the set), and for arm angles the set holds where
    ``nearly.ik``'s row lies outside the limits and the branch has a second solution within them (its witness,
    :func:`tests.support.nearly_witness.witnessed`, checked at up to :data:`WITNESSED` of them); a row within the
    limits outside the set counts only where it is exact (:func:`tests.support.nearly_witness.exact`: beyond a fold
    the certificate accepts rows that Newton's steps cannot take to rounding)."""
    feasible = feasible_arm_angles_nearly(arm, pose, branch).feasible
    held = np.asarray(feasible.contains(psi))
    solved = ik(arm, np.broadcast_to(pose, psi.shape + (4, 4)), psi, branch)
    within = solved.within_limits[:, 0]
    missed = ~solved.exists[:, 0] & np.roll(within, 1) & np.roll(within, -1)
    differ = _far_from_ends(psi, feasible) & (held != within) & ~missed
    for k in np.flatnonzero(differ & ~held):  # near a fold a certified row need not be exact
        differ[k] = exact(arm, pose, solved.q[k, 0], float(psi[k]))
    second = np.flatnonzero(differ & held)
    chosen = second[np.linspace(0, second.size - 1, min(second.size, WITNESSED)).astype(int)] if second.size else second
    if all(witnessed(arm, pose, branch, float(psi[k])) for k in chosen):
        differ[second] = False
    return psi[differ]


def _far_from_ends(psi: np.ndarray, *sets) -> np.ndarray:
    """Whether each arm angle of ``psi`` lies farther than :data:`AT_AN_END` from every end of the arc sets."""
    ends = np.array([end for arcs in sets for arc in arcs.arcs for end in arc])
    if ends.size == 0:
        return np.ones(len(psi), dtype=bool)
    return np.abs(np.angle(np.exp(1j * (psi[:, None] - ends[None])))).min(axis=1) > AT_AN_END


@settings(max_examples=12, deadline=None)
@given(name=st.sampled_from(["gen3", "jaco2", "iiwa14-rosi"]), seed=st.integers(0, 2**32 - 1),
       branch=st.sampled_from([str(b) for b in BRANCHES]))
def test_set_equals_dense_sampling(name, seed, branch):
    arm, rng, pose = _random_pose(name, seed)
    psi = np.sort(rng.uniform(-np.pi, np.pi, 6000))
    assert _disagreements(arm, pose, branch, psi).size == 0


@settings(max_examples=10, deadline=None)
@given(name=st.sampled_from(["gen3", "iiwa14-rosi"]), seed=st.integers(0, 2**32 - 1),
       branch=st.sampled_from([str(b) for b in BRANCHES]))
def test_every_end_is_a_change(name, seed, branch):
    arm, _, pose = _random_pose(name, seed)
    feasible = feasible_arm_angles_nearly(arm, pose, branch).feasible
    assume(not feasible.is_empty and not feasible.is_full)
    arcs = np.array(feasible.arcs)
    gaps = np.mod(np.roll(arcs[:, 0], -1) - arcs[:, 1], 2.0 * np.pi)
    widths = np.mod(arcs[:, 1] - arcs[:, 0], 2.0 * np.pi)
    step = 1e-6  # issue 27's resolution: where a branch begins at a fold near the stretched elbow, nearly.ik finds
    # it or not within about 2e-7 of its end (gen3, seed 27022, +++: found 1e-7 outside, missed 1e-8 inside)
    assume(gaps.min() > 4.0 * step and widths.min() > 4.0 * step)
    inside = np.concatenate([arcs[:, 0] + step, arcs[:, 1] - step])
    outside = np.concatenate([arcs[:, 0] - step, arcs[:, 1] + step])
    solved = ik(arm, np.broadcast_to(pose, inside.shape + (4, 4)), np.angle(np.exp(1j * inside)), branch)
    # where the solver finds the branch just inside, it is within the limits, or the branch has a second solution
    # there that is (near the stretched elbow nearly.ik may miss the branch at a single arm angle, and an end of where
    # it exists can sit at such a miss)
    outside_limits = solved.exists[:, 0] & ~solved.within_limits[:, 0]
    assert all(witnessed(arm, pose, branch, float(angle)) for angle in np.angle(np.exp(1j * inside[outside_limits])))
    outside = np.angle(np.exp(1j * outside))
    beyond = ik(arm, np.broadcast_to(pose, outside.shape + (4, 4)), outside, branch)
    assert not any(exact(arm, pose, beyond.q[k, 0], float(outside[k]))
                   for k in np.flatnonzero(beyond.within_limits[:, 0]))


#: Joint values whose pose holds an island or gap narrower than 2 pi / 720 (found by benchmarks/bench_nearly.py
#: --feasible before the extrema were located, and the last three before the ends of the branch's solution were
#: refined from), the branch and the arm angle it lies near.
NARROW = [
    ("iiwa14-rosi", [0.987214, -0.737526, 1.005361, 0.481701, 1.69648, -0.082825, -2.889126], "-++", -1.9796),
    ("iiwa14-rosi", [0.987214, -0.737526, 1.005361, 0.481701, 1.69648, -0.082825, -2.889126], "---", 1.1628),
    ("iiwa14-rosi", [-1.801814, 1.085819, 1.199488, 0.449969, -0.640954, 0.568607, 2.486787], "+-+", 2.9460),
    ("gen3", [-1.77754, -1.281876, 2.080123, -1.918479, -1.178805, -0.0299, 2.02687], "-+-", 1.4081),
    ("gen3", [-1.77754, -1.281876, 2.080123, -1.918479, -1.178805, -0.0299, 2.02687], "--+", -1.7088),
    ("gen3", [-0.553356, 0.740753, -0.969431, -1.556296, 2.504703, -1.070513, -2.047027], "-+-", 3.1307),
    ("gen3", [-1.112111, -0.573973, 1.5388, -0.024672, 1.646728, 0.068136, -1.972164], "---", 2.7770),
    # the branch gives way to another for 1.5e-3 rad (theta_6 passes 0) and comes back with q5 past its limit
    ("gen3", [0.980418, 1.074935, 0.617558, 1.036204, 1.808391, 0.38172, 0.025696], "-++", 1.9434),
    ("gen3", [-0.905855, -0.397723, 1.089756, 0.673095, -1.647377, 0.008121, -2.041717], "--+", 1.4502),
    ("gen3", [2.667899, 0.72756, -2.158559, -1.077697, -1.643822, -0.09874, 1.631771], "+--", -0.5316),
]


@pytest.mark.parametrize(("name", "q", "branch", "near"), NARROW)
def test_narrow_islands_and_gaps_are_found(name, q, branch, near):
    arm = _arm(name)
    pose = arm.chain.fk(np.array(q))
    psi = np.angle(np.exp(1j * np.linspace(near - 0.02, near + 0.02, 4001)))
    sampled = _sampled(arm, pose, branch, psi)
    runs = np.diff(np.flatnonzero(np.diff(sampled.astype(int)))) * (psi[1] - psi[0]) if sampled.any() else []
    assert np.any(np.asarray(runs) < 2.0 * np.pi / 720.0), "the case holds no narrow island or gap any more"
    assert _disagreements(arm, pose, branch, psi).size == 0


#: Branches near a singular shoulder (|sin theta_2| about 1e-3 to 1e-2) that exist at every arm angle within 4e-3 rad
#: of ``near`` (an independent Newton oracle from 64 starts agrees), where ``nearly.ik`` missed them at single
#: samples or for 6e-3 rad: the real arm's theta_1 and theta_3 turn half a turn within a few mrad of arm angle there,
#: far from any start but the neighbour's solution turned along the singular direction.
SINGULAR_SHOULDER = [
    ("gen3", [-2.711364407436, 0.001715011181, 1.858814741839, 1.66989263687, 1.23839686906, -0.02177368155,
              -1.472313984883], "--+", 0.0135),
    ("gen3", [-2.711364407436, 0.001715011181, 1.858814741839, 1.66989263687, 1.23839686906, -0.02177368155,
              -1.472313984883], "---", 0.0135),
    ("gen3", [-2.814406042831, -0.072070090415, 0.641388510347, -0.001750970291, -0.726619012081, -1.585927663997,
              -1.811680858941], "-++", -0.3167),
    ("iiwa14-rosi", [-0.677092811242, -0.00109299116, 1.482450176426, -0.069457768355, 2.162597539681,
                     -0.44391214823, -0.087784908952], "-+-", -3.1410),
]


@pytest.mark.parametrize(("name", "q", "branch", "near"), SINGULAR_SHOULDER)
def test_branches_near_a_singular_shoulder_are_found(name, q, branch, near):
    arm = _arm(name)
    pose = arm.chain.fk(np.array(q))
    psi = np.angle(np.exp(1j * np.linspace(near - 4e-3, near + 4e-3, 81)))
    solved = ik(arm, np.broadcast_to(pose, psi.shape + (4, 4)), psi, branch)
    assert solved.exists.all()
    reached = arm.chain.fk(solved.q[:, 0])
    assert np.abs(reached - pose).max() < 1e-8
    assert np.abs(np.angle(np.exp(1j * (arm_angle(arm, solved.q[:, 0]) - psi)))).max() < 1e-8
    assert np.all(branch_of(arm, solved.q[:, 0]) == BRANCHES.index(parse_branch(branch)))
    assert _disagreements(arm, pose, branch, psi).size == 0


#: Gen3 configurations (examples/gen3.urdf, its default tip) with the wrist within 1e-4 rad of straight, the branch,
#: and the gap where the branch has no solution (issue 38): 0.46 and 3.2 mrad wide, narrower than the grid of 720 arm
#: angles of the sampled method this module replaced, which claimed them feasible.  At their ends the self-motion
#: turns back.
STRAIGHT_WRIST_GAPS = [
    ([0.625477333023, 1.986069004848, 1.378428451226, -1.373964050047, -0.999168575444, -8.5434316e-05,
      -2.473673477172], "+-+", (1.95612, 1.95657)),
    ([1.581690519095, -0.602769142248, 2.393739422056, 0.449958465053, 0.525281269149, 0.000308023968,
      0.882251219064], "+-+", (0.64201, 0.64518)),
]


@pytest.mark.parametrize(("q", "branch", "gap"), STRAIGHT_WRIST_GAPS)
def test_a_straight_wrists_gap_is_left_out(q, branch, gap):
    from redkin.urdf import load_urdf

    arm = nearly_srs(load_urdf(EXAMPLES / "gen3.urdf"))
    pose = arm.chain.fk(np.array(q))
    feasible = feasible_arm_angles_nearly(arm, pose, branch).feasible
    psi = np.linspace(gap[0] - 1e-3, gap[1] + 1e-3, 4001)
    solved = ik(arm, np.broadcast_to(pose, psi.shape + (4, 4)), psi, branch)
    inside = (psi > gap[0]) & (psi < gap[1])
    assert not solved.exists[inside, 0].any(), "the branch has a solution in the gap now"
    assert solved.within_limits[~inside, 0].mean() > 0.9  # feasible on either side
    assert not np.any(np.asarray(feasible.contains(psi)) & inside)
    assert gap[1] - gap[0] < 2.0 * np.pi / 720.0  # narrower than the replaced method's grid
    for angle in psi[inside][::400]:  # no solution of the branch on the self-motion either
        assert len(branch_solutions(arm, pose, float(angle), branch)) == 0


def test_a_self_motion_shorter_than_the_seeds_spacing_is_found():
    """Near the stretched elbow the branches' self-motions span 0.25-0.28 rad of arm angle, between the eight seed arm
    angles (benchmarks/README.md, issue 38: the sets were empty and said complete): the finer seeds find them."""
    arm = _arm("gen3")
    q = np.array([2.286892365207979, -0.22270510750923256, 0.028099114095957667, 0.0013676772875753976,
                  1.392078981063007, 2.070530632846509, 1.690296486287782])
    pose = arm.chain.fk(q)
    results = feasible_arm_angles_nearly_all(arm, pose)
    assert results[0].complete and results[0].curves
    row = int(branch_of(arm, q))
    assert results[row].feasible.contains(float(arm_angle(arm, q)))  # the configuration's own arm angle
    psi = np.sort(np.random.default_rng(2).uniform(-np.pi, np.pi, 4000))
    for branch in ("-++", "+-+"):
        assert _disagreements(arm, pose, branch, psi).size == 0


@settings(max_examples=20, deadline=None)
@given(name=st.sampled_from(["gen3", "jaco2", "iiwa14-rosi"]), seed=st.integers(0, 2**32 - 1))
def test_self_motion_rates_are_the_derivative_of_the_solutions(name, seed):
    arm = _arm(name)
    rng = np.random.default_rng(seed)
    q0 = rng.uniform(arm.chain.lower, arm.chain.upper)
    pose, psi = arm.chain.fk(q0), float(arm_angle(arm, q0))
    h = 1e-6
    solutions = ik(arm, np.broadcast_to(pose, (3, 4, 4)), np.array([psi - h, psi, psi + h]))
    for row in np.flatnonzero(solutions.exists.all(axis=0)):
        q = solutions.q[:, row]
        assume(np.max(np.abs(q[2] - q[0])) < 1e-3)  # one sheet: no jump between the three
        rates = self_motion_rates(arm, q[1])
        assume(np.all(np.isfinite(rates)) and np.max(np.abs(rates)) < 1e3)
        assert np.allclose(rates, (q[2] - q[0]) / (2.0 * h), rtol=1e-5, atol=1e-5 * (1.0 + np.abs(rates).max()))
        assert np.max(np.abs(arm.chain.jacobian(q[1]) @ rates)) < 1e-9 * (1.0 + np.abs(rates).max())


def test_bad_input():
    arm = _arm("iiwa14-rosi")
    pose = arm.chain.fk(np.full(7, 0.3))
    with pytest.raises(ValueError, match=r"one \(4, 4\) pose"):
        feasible_arm_angles_nearly(arm, np.stack([pose, pose]))
    with pytest.raises(ValueError):
        feasible_arm_angles_nearly(arm, pose, "+x+")
    with pytest.raises(RedkinError):
        self_motion_rates(arm, np.full(6, 0.3))


@settings(max_examples=10, deadline=None)
@given(name=st.sampled_from(["gen3", "jaco2", "iiwa14-rosi"]), seed=st.integers(0, 2**32 - 1),
       branch=st.sampled_from([str(b) for b in BRANCHES]))
def test_the_set_lies_between_the_neighbours_tightened_and_loosened_sets(name, seed, branch):
    arm, rng, pose = _random_pose(name, seed)
    result = feasible_arm_angles_nearly(arm, pose, branch)
    psi = np.sort(rng.uniform(-np.pi, np.pi, 4000))
    assume(ik(arm, np.broadcast_to(pose, psi.shape + (4, 4)), psi, branch).exists.all())  # both arms solve everywhere
    far = _far_from_ends(psi, result.feasible, result.inner, result.outer)
    held = np.asarray(result.feasible.contains(psi))
    assert not np.any(far & np.asarray(result.inner.contains(psi)) & ~held)
    assert not np.any(far & held & ~np.asarray(result.outer.contains(psi)))
