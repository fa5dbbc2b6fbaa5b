"""The certified self-motion of nearly S-R-S arms and what is read off it (:mod:`redkin.srs.nearly.self_motion`).

Laws, on the Kinova Gen3 and Jaco2 (continuous joints limited to +-2.9 rad) and the ROS-Industrial iiwa, at random
poses and on purpose near a straight wrist (``q6`` near 0), a straight shoulder (``q2`` near 0) and the stretched
elbow:

- **a curve of solutions**: every point of :func:`self_motion` reaches the pose (our FK), its tangent is a unit
  vector the Jacobian maps to zero, neighbouring points lie within a step, a closed curve ends at its start (modulo
  whole turns), and ``rates`` is the derivative of the arm angle along the tangent (central differences);
- **every step is what it says**: points of the true arc inside a step, found in the test by Newton's steps on
  independently written equations (our FK and Jacobian in numpy, the step's hyperplanes), lie on the step's branch,
  within the limits where the step says so, and within the step's arm-angle bound of the point its certificate
  starts from (C5);
- **the third derivatives are within ``K``** (C3): each rotation row's at most 1, each position row's within the
  lever arm, all 343 within ``K``, and along a predictor within C2's directional bounds, on the self-motion and away
  from it;
- **joint 1 does not move the arm angle** (C5 rests on it): turning joint 1 by any angle leaves the arm angle as it
  was, and the certificate's ``beta`` bounds ``|A^-1|`` (numpy's inverse) to within ``7^(1/16)``;
- **every arm angle of the feasible set has a solution**: at arm angles drawn inside every arc of every branch's set
  (ends included, to 1e-9), :func:`branch_solutions` gives a solution of the branch within the limits, checked with
  our FK, arm angle, branch and limits;
- **a straight wrist's gap is kept** (issue 38): on Gen3 poses where the wrist is within 1e-4 rad of straight, the
  branch has no solution in a gap narrower than a grid of 2880 arm angles resolves; the set leaves it out;
- **a seed on a followed curve is known at once**: the curve passes through each of its own points (so
  :func:`whole_self_motion` follows no curve twice), and asking many solutions together answers as asking each alone;
- ``branch_solutions`` on the pose with two solutions on one branch returns both, certified, each once, nearly.ik's
  row first;
- bad input raises ValueError.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from redkin import _compiled
from redkin._compiled import set_threads
from redkin.srs import BRANCHES, branch_solutions, feasible_arm_angles_nearly_all, self_motion, self_motions
from redkin.srs.branches import parse_branch
from redkin.srs.nearly import arm_angle, branch_of, ik
from redkin.srs.nearly import self_motion as self_motion_module
from redkin.srs.nearly.self_motion import _passes
from tests.test_srs_nearly_feasible import _arm

#: The Gen3 pose with two solutions on one branch (benchmarks/README.md, issue 27, pose 643 of the sequence).
TWO_SOLUTIONS = [-0.661847496495, -0.001169086142, 1.449071562504, -0.085238499031, 2.113904835201, -0.443021865056,
                 -0.083355566602]
#: The self-motion's longest step [rad] in the first law.
STEP = 0.05
#: Where a random configuration is drawn: anywhere, or with one joint near a singular value.
NEAR = ["anywhere", "straight wrist", "straight shoulder", "stretched elbow"]


def _wrapped(angles: np.ndarray) -> np.ndarray:
    return np.angle(np.exp(1j * np.asarray(angles)))


def _configuration(name: str, seed: int, near: str) -> tuple[object, np.ndarray]:
    """The arm and joint values within its limits, drawn with ``seed`` anywhere or ``near`` a singular value of the
    user's joint (q6 or q2 within 1e-3 rad of 0, q4 within 1e-2 of the real arm's stretched elbow)."""
    arm = _arm(name)
    rng = np.random.default_rng(seed)
    q = rng.uniform(arm.chain.lower, arm.chain.upper)
    small = rng.choice([-1.0, 1.0]) * 10.0 ** rng.uniform(-6, -3)
    neighbour = arm.neighbour
    if near == "straight wrist":
        q[5] = neighbour.sign[5] * (np.round((neighbour.offset[5] + neighbour.sign[5] * q[5]) / np.pi) * np.pi
                                    - neighbour.offset[5]) + small
    elif near == "straight shoulder":
        q[1] = neighbour.sign[1] * (np.round((neighbour.offset[1] + neighbour.sign[1] * q[1]) / np.pi) * np.pi
                                    - neighbour.offset[1]) + small
    elif near == "stretched elbow":
        q[3] = neighbour.sign[3] * (arm.real_phase - neighbour.offset[3]) + 10.0 * small
    return arm, np.clip(q, arm.chain.lower, arm.chain.upper)


def _newton(arm, pose: np.ndarray, start: np.ndarray, normal: np.ndarray, level: float) -> np.ndarray:
    """The solution of the pose on the hyperplane ``normal . q = level`` near ``start``: Newton's steps written in
    the test (our FK, the geometric Jacobian, the rotation error's skew part)."""
    q = start.copy()
    for _ in range(30):
        reached = arm.chain.fk(q)
        turn = pose[:3, :3] @ reached[:3, :3].T
        error = np.concatenate([pose[:3, 3] - reached[:3, 3],
                                0.5 * np.array([turn[2, 1] - turn[1, 2], turn[0, 2] - turn[2, 0],
                                                turn[1, 0] - turn[0, 1]]), [level - normal @ q]])
        if np.abs(error).max() < 1e-14:
            break
        q = q + np.linalg.solve(np.vstack([arm.chain.jacobian(q), normal]), error)
    return q


@settings(max_examples=12, deadline=None)
@given(name=st.sampled_from(["gen3", "jaco2", "iiwa14-rosi"]), seed=st.integers(0, 2**32 - 1),
       near=st.sampled_from(NEAR))
def test_a_self_motion_is_a_curve_of_solutions(name, seed, near):
    arm, q = _configuration(name, seed, near)
    pose = arm.chain.fk(q)
    curve = self_motion(arm, pose, q, step=STEP)
    assert len(curve.psi) > 10
    assert np.abs(arm.chain.fk(curve.q) - pose).max() < 1e-12
    np.testing.assert_allclose(np.linalg.norm(curve.tangents, axis=-1), 1.0, atol=1e-12)
    assert np.abs(np.einsum("mij,mj->mi", arm.chain.jacobian(curve.q), curve.tangents)).max() < 1e-8
    assert np.linalg.norm(np.diff(curve.q, axis=0), axis=-1).max() <= 1.01 * STEP
    if curve.closed:
        assert np.abs(_wrapped(curve.q[-1] - curve.q[0])).max() < 1e-9
    np.testing.assert_allclose(_wrapped(arm_angle(arm, curve.q) - curve.psi), 0.0, atol=1e-12)
    epsilon = 1e-6
    ahead = arm_angle(arm, curve.q + epsilon * curve.tangents)
    behind = arm_angle(arm, curve.q - epsilon * curve.tangents)
    differences = _wrapped(ahead - behind) / (2.0 * epsilon)
    np.testing.assert_allclose(curve.rates, differences, atol=1e-4 * (1.0 + np.abs(differences).max()))


@settings(max_examples=9, deadline=None)
@given(name=st.sampled_from(["gen3", "jaco2", "iiwa14-rosi"]), seed=st.integers(0, 2**32 - 1),
       near=st.sampled_from(NEAR))
def test_every_step_is_what_it_says(name, seed, near):
    arm, q = _configuration(name, seed, near)
    pose = arm.chain.fk(q)
    curve = self_motion(arm, pose, q)
    rng = np.random.default_rng(seed)
    steps = len(curve.psi) - 1
    chosen = np.union1d(rng.choice(steps, min(steps, 60), replace=False),
                        np.flatnonzero((curve.inside != 1) | (curve.branches < 0)))  # every step at an event
    chosen = np.union1d(chosen, np.clip(np.concatenate([chosen - 1, chosen + 1]), 0, steps - 1))[:400]
    for k in chosen:
        start, tangent = curve.q[k], curve.tangents[k]
        length = float((curve.q[k + 1] - start) @ tangent)
        inner = np.array([_newton(arm, pose, start + s * length * tangent, tangent, tangent @ start + s * length)
                          for s in (0.25, 0.5, 0.75, 1.0)])
        assert np.abs(arm.chain.fk(inner) - pose).max() < 1e-12
        if curve.branches[k] >= 0:
            assert np.all(branch_of(arm, inner) == curve.branches[k])
        if curve.inside[k] == 1:
            assert np.all(arm.chain.within_limits(inner, wrap=True))
        assert np.all(np.abs(_wrapped(arm_angle(arm, inner) - curve.psi[curve.anchors[k]])) <= curve.spread[k] + 1e-12)


@settings(max_examples=8, deadline=None)
@given(name=st.sampled_from(["gen3", "jaco2", "iiwa14-rosi"]), seed=st.integers(0, 2**32 - 1),
       near=st.sampled_from(NEAR))
@example(name="gen3", seed=0, near="straight wrist")
@example(name="jaco2", seed=40221, near="stretched elbow")  # a fresh draw: an arc 2.2e-12 rad wide at q4's limit
def test_every_arm_angle_of_the_feasible_set_has_a_solution(name, seed, near):
    arm, q = _configuration(name, seed, near)
    pose = arm.chain.fk(q)
    results = feasible_arm_angles_nearly_all(arm, pose)
    curves = results[0].curves
    rng = np.random.default_rng(seed)
    for row, result in enumerate(results):
        arcs = np.array(result.feasible.arcs).reshape(-1, 2)
        if len(arcs) == 0:
            continue
        widths = 2.0 * np.pi if result.feasible.is_full else np.mod(arcs[:, 1] - arcs[:, 0], 2.0 * np.pi)
        within = arcs[:, 0, None] + np.asarray(widths).reshape(-1, 1) * rng.uniform(0, 1, (len(arcs), 3))
        inward = np.minimum(1e-9, np.asarray(widths) / 3.0)  # near each end, inside the arc however narrow
        angles = np.concatenate([arcs[:, 0] + inward, arcs[:, 1] - inward, within.ravel()])
        for angle in _wrapped(angles):
            solutions = branch_solutions(arm, pose, float(angle), BRANCHES[row], curves)
            good = (np.all(np.abs(arm.chain.fk(solutions) - pose) < 1e-9, axis=(-2, -1))
                    & (np.abs(_wrapped(arm_angle(arm, solutions) - angle)) < 1e-9)
                    & (branch_of(arm, solutions) == row) & arm.chain.within_limits(solutions, wrap=True))
            assert good.any(), f"no solution of {BRANCHES[row]} within the limits at psi = {angle!r}"


@settings(max_examples=6, deadline=None)
@given(name=st.sampled_from(["gen3", "jaco2", "iiwa14-rosi"]), seed=st.integers(0, 2**32 - 1),
       near=st.sampled_from(NEAR))
def test_a_curve_passes_through_its_own_points_asked_together_or_alone(name, seed, near):
    arm, q = _configuration(name, seed, near)
    curve = self_motions(arm, arm.chain.fk(q))[0]
    rng = np.random.default_rng(seed)
    steps = np.flatnonzero(curve.branches >= 0)
    own = rng.choice(steps, min(40, len(steps)), replace=False)
    assert _passes(curve, curve.psi[own], curve.branches[own], curve.q[own]).all()
    moved = curve.q[own].copy()
    moved[1::2] += 0.05 * rng.choice([-1.0, 1.0], (len(own) // 2, 7))  # every other one off the curve
    together = _passes(curve, curve.psi[own], curve.branches[own], moved)
    alone = [_passes(curve, curve.psi[own[n:n + 1]], curve.branches[own[n:n + 1]], moved[n:n + 1])[0]
             for n in range(len(own))]
    assert together.tolist() == alone
    assert together[::2].all() and not together.all()


@settings(max_examples=6, deadline=None)
@given(name=st.sampled_from(["gen3", "jaco2", "iiwa14-rosi"]), seed=st.integers(0, 2**32 - 1),
       near=st.sampled_from(NEAR))
@example(name="gen3", seed=3, near="anywhere")
def test_curves_followed_ahead_together_are_the_curves_followed_one_after_another(name, seed, near):
    arm, q = _configuration(name, seed, near)
    pose = arm.chain.fk(q)
    found = {}
    try:
        for threads in (1, 2, 2):  # the second run on two threads after the first timed the batch: on the pool
            set_threads(threads)
            found[threads] = self_motion_module.whole_self_motion(arm, pose)
    finally:
        set_threads(None)
    with pytest.MonkeyPatch.context() as patch:  # every seed followed alone, where the one before it left off
        patch.setattr(self_motion_module, "_traced_ahead", lambda *args: {})
        alone = self_motion_module.whole_self_motion(arm, pose)
    for curves, complete in found.values():
        assert complete == alone[1] and len(curves) == len(alone[0])
        for curve, reference in zip(curves, alone[0], strict=True):
            for field, value in curve._asdict().items():
                np.testing.assert_array_equal(value, getattr(reference, field), err_msg=field)


def test_no_seed_is_followed_ahead_where_the_kernels_run_as_python(monkeypatch):
    """As Python every batch runs in the calling thread, so a seed followed ahead that an earlier curve covers would
    be work lost: none is followed ahead (the kernels still run compiled here, numba being loaded)."""
    arm, q = _configuration("gen3", 3, "anywhere")
    pose = arm.chain.fk(q)
    curves, complete = self_motion_module.whole_self_motion(arm, pose)

    def refused(*args):
        raise AssertionError("a seed was followed ahead while the kernels run as Python")

    monkeypatch.setattr(self_motion_module, "_traced_ahead", refused)
    monkeypatch.setattr(_compiled, "_numba_loaded", False)
    with _compiled.interpreted():
        assert _compiled.running_as_python()
        again, complete_again = self_motion_module.whole_self_motion(arm, pose)
    assert complete_again == complete and len(again) == len(curves)
    for curve, reference in zip(again, curves, strict=True):
        np.testing.assert_array_equal(curve.q, reference.q)


def test_a_curve_longer_than_the_pieces_followed_ahead_is_followed_whole(monkeypatch):
    arm, q = _configuration("gen3", 3, "anywhere")
    pose = arm.chain.fk(q)
    curves, complete = self_motion_module.whole_self_motion(arm, pose)
    assert complete and min(len(curve.psi) for curve in curves) > 20
    monkeypatch.setattr(self_motion_module, "_AHEAD_POINTS", 20)  # every piece ahead full: each followed again
    again, complete_again = self_motion_module.whole_self_motion(arm, pose)
    assert complete_again and len(again) == len(curves)
    for curve, reference in zip(again, curves, strict=True):
        np.testing.assert_array_equal(curve.q, reference.q)
        assert curve.closed == reference.closed


def test_two_solutions_on_one_branch():
    arm = _arm("gen3")
    pose = arm.chain.fk(np.array(TWO_SOLUTIONS))
    branch = "-++"
    curves = self_motions(arm, pose)
    psi = np.linspace(-np.pi, np.pi, 360, endpoint=False)
    row = ik(arm, np.broadcast_to(pose, psi.shape + (4, 4)), psi, branch)
    twice = 0
    for k in np.flatnonzero(row.exists[:, 0])[::3]:
        solutions = branch_solutions(arm, pose, float(psi[k]), branch, curves)
        assert np.abs(arm.chain.fk(solutions) - pose).max() < 1e-9
        assert np.abs(_wrapped(arm_angle(arm, solutions) - psi[k])).max() < 1e-9
        assert np.all(branch_of(arm, solutions) == BRANCHES.index(parse_branch(branch)))
        assert np.abs(_wrapped(solutions[0] - row.q[k, 0])).max() < 1e-5  # nearly.ik's row first (as located)
        apart = np.abs(_wrapped(solutions[:, None] - solutions[None])).max(axis=-1)
        assert np.all(apart[~np.eye(len(solutions), dtype=bool)] > 1e-5)  # each solution once
        twice += len(solutions) > 1
    assert twice > 0, "the pose has no arm angle with two solutions on the branch any more"


def test_bad_input():
    arm = _arm("gen3")
    q = np.array(TWO_SOLUTIONS)
    pose = arm.chain.fk(q)
    with pytest.raises(ValueError, match="does not reach the pose"):
        self_motion(arm, pose, q + 0.1)
    with pytest.raises(ValueError, match="step"):
        self_motion(arm, pose, q, step=0.0)
    with pytest.raises(ValueError):
        self_motion(arm, pose, np.stack([q, q]))
    with pytest.raises(ValueError):
        self_motion(arm, np.stack([pose, pose]), q)
    with pytest.raises(ValueError):
        branch_solutions(arm, pose, 0.1, "+x+")
    with pytest.raises(ValueError):
        self_motions(arm, np.stack([pose, pose]))


@settings(max_examples=200, deadline=None)
@given(st.floats(-3.0, 3.0), st.floats(-0.2, 0.2), st.floats(-0.01, 0.01), st.floats(0.0, 0.01), st.floats(0.0, 1e-3),
       st.floats(0.0, 0.02), st.floats(0.0, 1.0), st.floats(0.0, 1.0))
def test_the_narrower_tube_holds_every_arc_the_certificate_allows(a, d, e, radius, near, extra, bend, share):
    """:func:`tube_range` [C4]: an arc whose point at ``s`` lies within ``r(s)`` of the predictor's ``a + s d + s^2
    e`` (``s`` in [0, 1]), ``r(s)`` at most ``radius`` and at most a convex ``R(s)`` from ``near`` to ``far``, stays
    inside the interval it gives; and where the predictor moves away from a boundary its start side is padded by
    ``near`` alone, not by ``radius``."""
    from redkin.srs.nearly._self_motion_kernels import tube_range

    far = near + extra
    s = np.linspace(0.0, 1.0, 201)
    convex = near + (far - near) * (bend * s**2 + (1.0 - bend) * s)  # convex, from near to far
    allowed = np.minimum(radius, convex) * share
    predictor = a + s * d + s**2 * e
    low, high = tube_range(a, d, e, radius, near, far)
    assert np.all(predictor + allowed <= high + 1e-15) and np.all(predictor - allowed >= low - 1e-15)
    if d > far + 2.0 * abs(e):  # moving up, away from what lies below the start
        assert low >= a - min(near, radius) - 1e-15


@settings(max_examples=6, deadline=None)
@given(name=st.sampled_from(["gen3", "jaco2", "iiwa14-rosi"]), seed=st.integers(0, 2**32 - 1),
       away=st.sampled_from([0.0, 0.3, 2.0]))
def test_the_third_derivatives_are_within_their_bound(name, seed, away):
    """C3's ``K``: along joints ``i <= j <= m`` each rotation row's third derivative is at most 1 in norm and each
    position row's at most ``c`` times the end point's distance from joint ``m``'s axis, and the Frobenius norm of
    all 343 is at most ``K``; C2's bounds of ``F'''[d, d, d]`` and ``F'''[d, d, .]`` along a predictor
    (``third_along``) hold; by the test's own ``F`` (our FK in numpy) and mixed central differences, on the
    self-motion (``M = I``) and ``away`` from it."""
    from itertools import permutations, product

    from redkin.srs.nearly import _self_motion_kernels as kernels

    arm, q = _configuration(name, seed, "anywhere")
    pose = arm.chain.fk(q)
    point = q + away * np.random.default_rng(seed).normal(size=7)
    scale, step = arm.kernel_bounds[kernels.SCALE], 1e-3
    triples = [(i, j, m) for i in range(7) for j in range(i, 7) for m in range(j, 7)]
    signs = np.array(list(product([1.0, -1.0], repeat=3)))
    identity = np.eye(7)
    moves = np.array([[a * identity[i] + b * identity[j] + c * identity[m] for a, b, c in signs]
                      for i, j, m in triples])
    frames = arm.chain.fk(point + step * moves)
    turn = frames[..., :3, :3] @ pose[:3, :3].T
    equations = np.concatenate([scale * (frames[..., :3, 3] - pose[:3, 3]),
                                0.5 * np.stack([turn[..., 2, 1] - turn[..., 1, 2], turn[..., 0, 2] - turn[..., 2, 0],
                                                turn[..., 1, 0] - turn[..., 0, 1]], axis=-1)], axis=-1)
    third = np.einsum("s,tsk->tk", signs.prod(axis=1), equations) / (8.0 * step**3)
    joints = arm.chain.frames(point)  # joint m's axis: frame m - 1's z (standard DH) or frame m's (modified)
    first = 0 if arm.chain._standard else 1
    end = arm.chain.fk(point)[:3, 3]
    reach = []
    for m in range(7):
        axis, origin = joints[m + first, :3, 2], joints[m + first, :3, 3]
        offset = end - origin
        reach.append(np.linalg.norm(offset - (offset @ axis) * axis))
    assert np.all(np.linalg.norm(third[:, 3:], axis=1) <= 1.0 + 1e-5)
    assert np.all(np.linalg.norm(third[:, :3], axis=1) <= scale * np.array([reach[m] for _, _, m in triples]) + 1e-5)
    copies = np.array([len(set(permutations(triple))) for triple in triples])
    assert np.sqrt(np.sum(copies * np.sum(third * third, axis=1))) <= arm.kernel_bounds[kernels.THIRD]
    tensor = np.zeros((6, 7, 7, 7))
    for entry, triple in zip(third, triples, strict=True):
        for order in set(permutations(triple)):
            tensor[(slice(None), *order)] = entry
    rng = np.random.default_rng(seed)
    for n in range(27):  # C2's bounds along a predictor: d = s t + s^2 kappa / 2, s up to the reach
        if n < 7:  # along one joint, straight: the rotation rows' bound is reached on the self-motion
            tangent, bend = identity[n], np.zeros(7)
        else:
            tangent = rng.normal(size=7) * rng.uniform(0.0, 1.0, 7) ** 2
            tangent /= np.linalg.norm(tangent)
            bend = rng.normal(size=7) * rng.uniform(0.0, 2.0)
        reach = rng.uniform(0.01, 0.3)
        along, across = kernels.third_along(arm.kernel_bounds, tangent, bend, reach)
        for fraction in (0.5, 1.0):
            d = fraction * reach * tangent + 0.5 * (fraction * reach) ** 2 * bend
            mapped = np.einsum("rijm,i,j->rm", tensor, d, d)
            assert np.linalg.norm(mapped @ d) <= along * (1.0 + 1e-6) + 1e-12
            assert np.linalg.norm(mapped, 2) <= across * (1.0 + 1e-6) + 1e-12


@settings(max_examples=20, deadline=None)
@given(name=st.sampled_from(["gen3", "jaco2", "iiwa14-rosi"]), seed=st.integers(0, 2**32 - 1),
       near=st.sampled_from(NEAR), turn=st.floats(-3.0, 3.0))
def test_joint_one_does_not_move_the_arm_angle(name, seed, near, turn):
    """C5 bounds the arm angle's change by joints 2-4 alone: turning the whole arm about joint 1's axis turns the
    reference plane with it (and joints 5-7 do not move the wrist)."""
    arm, q = _configuration(name, seed, near)
    moved = q.copy()
    moved[0] += turn
    moved[4:] = np.random.default_rng(seed).uniform(-3.0, 3.0, 3)
    assert abs(_wrapped(arm_angle(arm, moved) - arm_angle(arm, q))) <= 1e-11


@settings(max_examples=6, deadline=None)
@given(name=st.sampled_from(["gen3", "jaco2", "iiwa14-rosi"]), seed=st.integers(0, 2**32 - 1),
       near=st.sampled_from(NEAR))
def test_the_bend_and_the_turning_are_the_curves(name, seed, near):
    """C2-C3: ``kappa`` of a point's state is the curve's second derivative in arc length (the curve's points on the
    hyperplanes ``t . (q - x) = +-eps``, found by the test's own Newton steps, central differences), and ``Omega_t``
    bounds how ``A^-1 F'`` changes along the tangent (``F'`` at ``x +- eps t``, ``A^-1`` by numpy)."""
    from redkin.srs.nearly import _self_motion_kernels as kernels

    arm, q = _configuration(name, seed, near)
    pose = arm.chain.fk(q)
    point, tangent, gradient, state = np.empty(7), np.empty(7), np.empty(7), np.empty(kernels.STATE)
    work = kernels.scratch()
    target = np.ascontiguousarray(pose)
    assert kernels.started(q.copy(), target, arm.kernel_real, arm.kernel_model, arm.kernel_bounds, work, point,
                           tangent, gradient, state)
    bend = state[kernels.BEND:kernels.BEND + 7]
    epsilon = 1e-4
    ahead, behind = (_newton(arm, pose, point + s * tangent, tangent, tangent @ point + s) for s in (epsilon, -epsilon))
    second = (ahead + behind - 2.0 * point) / epsilon**2
    assert np.abs(second - bend).max() <= 1e-3 * (1.0 + np.abs(bend).max()) + 1e-2 * epsilon * state[kernels.OMEGA] ** 2
    scale = arm.kernel_bounds[kernels.SCALE]

    def derivative(at: np.ndarray) -> np.ndarray:
        kernels.residual(np.ascontiguousarray(at), target, arm.kernel_real, scale, work)
        return work[3][:6].copy()

    inverse = np.linalg.inv(np.vstack([derivative(point), tangent]))
    largest = np.linalg.norm(inverse, 2)
    assert largest * (1.0 - 1e-9) <= state[kernels.BETA] <= largest * 7.0 ** (1.0 / 16.0) * (1.0 + 1e-9)
    change = (derivative(point + 1e-6 * tangent) - derivative(point - 1e-6 * tangent)) / 2e-6
    assert np.linalg.norm(inverse[:, :6] @ change, 2) <= state[kernels.TURNING] * (1.0 + 1e-4) + 1e-6
