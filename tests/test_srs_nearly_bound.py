"""How far a nearly S-R-S arm's solution lies from its neighbour's (:mod:`redkin.srs.nearly.bound`).

Laws, on the Kinova Gen3 and Jaco2 and the ROS-Industrial iiwa (as :mod:`tests.test_srs_nearly_feasible` loads
them), at random poses and at the degenerate ones on purpose (the elbow near its stretch, ``q_2`` or ``q_6`` near
0, the wrist near axis 1):

- **the equations are the real arm's**: their residual is our FK's pose error and the arm-angle error, computed
  here with scipy's rotation vector and :func:`redkin.srs.nearly.arm_angle`, and their Jacobian is the chain's
  geometric Jacobian over central differences of the arm angle;
- **at the neighbour's solution the residual is the offsets'**: the two chains' pose difference, within the model
  error, and no arm-angle error;
- **the bound holds**: wherever it is finite, Newton's steps from the neighbour's solution (written here, on those
  independent equations) reach a solution of the real arm within it;
- **the set lies between the neighbour's sets** for the limits tightened and loosened by the largest bound, where
  the bound is finite at every arm angle of a dense grid;
- **the model error is the largest pose difference**: no random configuration differs by more;
- bad input raises ValueError; a pose the neighbour cannot reach has no bound.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from redkin.circle import ArcSet
from redkin.errors import RedkinError
from redkin.srs import BRANCHES, feasible_arm_angles_nearly, neighbour_distance
from redkin.srs.branches import parse_branch
from redkin.srs.conventions import ROUNDING_ROTATION, model_error
from redkin.srs.nearly import NearlySRS, arm_angle
from redkin.srs.nearly.bound import _equations
from redkin.srs.nearly.feasible import _neighbour_sets
from tests.test_srs_nearly_feasible import _arm, _far_from_ends

ARMS = ["gen3", "jaco2", "iiwa14-rosi"]
#: The configurations drawn: uniform within the limits, then one joint moved to a degenerate place.
KINDS = ["uniform", "stretched elbow", "q6 near 0", "q2 near 0", "wrist near axis 1"]
#: A case: an arm, a seed for its configuration and arm angles, the kind of configuration and a branch.
CASES = dict(name=st.sampled_from(ARMS), seed=st.integers(0, 2**32 - 1), kind=st.sampled_from(KINDS),
             branch=st.sampled_from([str(b) for b in BRANCHES]))
#: Central-difference step of the arm angle's gradient [rad].
STEP = 1e-6


def _configuration(arm: NearlySRS, rng: np.random.Generator, kind: str) -> np.ndarray:
    """Joint values within the limits, then moved to the degenerate place ``kind`` (:data:`KINDS`) and a little off."""
    chain = arm.chain
    q = rng.uniform(chain.lower, chain.upper)
    if kind == "stretched elbow":
        q[3] = chain.sign[3] * (arm.real_phase - arm.neighbour.offset[3]) + rng.normal(0.0, 0.02)
    elif kind == "q6 near 0":
        q[5] = rng.normal(0.0, 0.02)
    elif kind == "q2 near 0":
        q[1] = rng.normal(0.0, 0.02)
    elif kind == "wrist near axis 1":  # q_2 that points the shoulder-wrist line nearest axis 1
        turns = np.linspace(-np.pi, np.pi, 721)
        trial = np.repeat(q[None], len(turns), axis=0)
        trial[:, 1] = turns
        directions, points = arm.neighbour.joint_axes(trial)
        line = points[:, 5] - points[:, 1]
        cosine = np.abs(np.sum(line * directions[:, 0], axis=-1)) / np.linalg.norm(line, axis=-1)
        q[1] = turns[np.argmax(cosine)] + rng.normal(0.0, 0.01)
    return q


def _residual(arm: NearlySRS, q: np.ndarray, pose: np.ndarray, psi: float) -> np.ndarray:
    """The 7 equations' residual, written here: position error, world rotation vector ``log(R_t R^T)``, arm-angle
    error (wrapped)."""
    reached = arm.chain.fk(q)
    rotation = Rotation.from_matrix(pose[:3, :3] @ reached[:3, :3].T).as_rotvec()
    turn = np.angle(np.exp(1j * (psi - float(arm_angle(arm, q)))))
    return np.concatenate([pose[:3, 3] - reached[:3, 3], rotation, [turn]])


def _jacobian(arm: NearlySRS, q: np.ndarray) -> np.ndarray:
    """The chain's geometric Jacobian over the arm angle's gradient by central differences (wrapped)."""
    shifts = STEP * np.eye(7)
    turns = np.angle(np.exp(1j * (arm_angle(arm, q + shifts) - arm_angle(arm, q - shifts))))
    return np.vstack([arm.chain.jacobian(q), turns / (2.0 * STEP)])


def _newton(arm: NearlySRS, q: np.ndarray, pose: np.ndarray, psi: float) -> np.ndarray | None:
    """Newton's steps on :func:`_residual` from ``q``; the solution, or ``None`` where they do not settle to 1e-11."""
    for _ in range(40):
        residual = _residual(arm, q, pose, psi)
        if np.linalg.norm(residual) < 1e-11:
            return q
        q = q + np.linalg.solve(_jacobian(arm, q), residual)
    return None


def _neighbours(arm: NearlySRS, pose: np.ndarray, branch: str, change: float) -> ArcSet:
    """The neighbour's exact feasible set with its limits loosened by ``change`` (tightened where negative)."""
    sets = _neighbour_sets(arm, pose, parse_branch(branch), change)
    return ArcSet.empty() if sets is None else sets.feasible


def _case(name: str, seed: int, kind: str) -> tuple[NearlySRS, np.random.Generator, np.ndarray]:
    arm = _arm(name)
    rng = np.random.default_rng(seed)
    return arm, rng, arm.chain.fk(_configuration(arm, rng, kind))


@settings(max_examples=30, deadline=None)
@given(name=st.sampled_from(ARMS), seed=st.integers(0, 2**32 - 1), kind=st.sampled_from(KINDS))
def test_the_equations_are_the_real_arms(name, seed, kind):
    arm, rng, pose = _case(name, seed, kind)
    q = rng.uniform(arm.chain.lower, arm.chain.upper, (4, 7))
    psi = rng.uniform(-np.pi, np.pi, 4)
    residual, jacobian = _equations(arm, q, np.ascontiguousarray(np.broadcast_to(pose, (4, 4, 4))), psi)
    for k in range(4):
        np.testing.assert_allclose(residual[k], _residual(arm, q[k], pose, psi[k]), atol=1e-12)
        np.testing.assert_allclose(jacobian[k], _jacobian(arm, q[k]), atol=1e-6 * max(1.0, np.abs(jacobian[k]).max()))


@settings(max_examples=30, deadline=None)
@given(**CASES)
def test_at_the_neighbours_solution_the_residual_is_the_offsets(name, seed, kind, branch):
    arm, rng, pose = _case(name, seed, kind)
    psi = rng.uniform(-np.pi, np.pi, 8)
    start = neighbour_distance(arm, pose, psi, branch).neighbour
    if np.isnan(start).any():  # beyond the neighbour's reach: a stretched elbow past the neighbour's
        assert np.isnan(start).all()
        return
    residual = _equations(arm, start, np.ascontiguousarray(np.broadcast_to(pose, (8, 4, 4))), psi)[0]
    assert np.all(np.linalg.norm(residual[:, :3], axis=-1) <= arm.position_error * (1.0 + 1e-9))
    assert np.all(np.linalg.norm(residual[:, 3:6], axis=-1) <= arm.rotation_error + 1e-12)
    np.testing.assert_allclose(residual[:, 6], 0.0, atol=1e-9)
    mine, theirs = arm.chain.fk(start), arm.neighbour.fk(start)
    np.testing.assert_allclose(residual[:, :3], theirs[:, :3, 3] - mine[:, :3, 3], atol=1e-12)


@settings(max_examples=45, deadline=None)
@given(**CASES)
def test_the_real_solution_lies_within_the_bound(name, seed, kind, branch):
    arm, rng, pose = _case(name, seed, kind)
    psi = rng.uniform(-np.pi, np.pi, 6)
    distance = neighbour_distance(arm, pose, psi, branch)
    assert np.all(np.isinf(distance.bound) | (distance.bound == 2.0 * distance.first_step))
    for k in np.flatnonzero(np.isfinite(distance.bound)):
        solution = _newton(arm, distance.neighbour[k], pose, float(psi[k]))
        assert solution is not None, f"Newton's steps from the neighbour's solution at psi = {psi[k]!r} do not settle"
        apart = np.linalg.norm(np.angle(np.exp(1j * (solution - distance.neighbour[k]))))
        assert apart <= distance.bound[k]


@settings(max_examples=24, deadline=None)
@given(name=st.sampled_from(ARMS), seed=st.integers(0, 2**32 - 1), branch=st.sampled_from([str(b) for b in BRANCHES]))
def test_the_set_lies_between_the_neighbours_sets_for_the_bound(name, seed, branch):
    arm, rng, pose = _case(name, seed, "uniform")
    grid = np.linspace(-np.pi, np.pi, 3600, endpoint=False)
    bound = neighbour_distance(arm, pose, grid, branch).bound
    if not np.all(np.isfinite(bound)):
        return  # near a singular wrist, shoulder or the stretched elbow somewhere: no bound to test
    largest = float(bound.max())
    feasible = feasible_arm_angles_nearly(arm, pose, branch).feasible
    inner, outer = (_neighbours(arm, pose, branch, sign * largest) for sign in (-1.0, 1.0))
    psi = np.sort(rng.uniform(-np.pi, np.pi, 4000))
    far = _far_from_ends(psi, feasible, inner, outer)
    held = np.asarray(feasible.contains(psi))
    assert not np.any(far & np.asarray(inner.contains(psi)) & ~held)
    assert not np.any(far & held & ~np.asarray(outer.contains(psi)))


@settings(max_examples=20, deadline=None)
@given(name=st.sampled_from(ARMS), seed=st.integers(0, 2**32 - 1))
def test_the_model_error_is_the_largest_pose_difference(name, seed):
    arm = _arm(name)
    q = np.random.default_rng(seed).uniform(-np.pi, np.pi, (2000, 7))
    mine, theirs = arm.chain.fk(q), arm.neighbour.fk(q)
    assert np.linalg.norm(mine[:, :3, 3] - theirs[:, :3, 3], axis=-1).max() <= arm.position_error * (1.0 + 1e-9)
    relative = np.einsum("nji,njk->nik", mine[:, :3, :3], theirs[:, :3, :3])
    assert np.linalg.norm(Rotation.from_matrix(relative).as_rotvec(), axis=-1).max() <= arm.rotation_error + 1e-12
    assert model_error(arm.chain, arm.neighbour) == (arm.position_error, arm.rotation_error)


def test_a_neighbour_that_keeps_the_axes_turns_the_tool_by_rounding_only_and_says_so():
    """The Gen3 of the User Guide's DH form and the Jaco2 URDF differ from their neighbours in offsets only: every
    sampled rotation difference is rounding (below ROUNDING_ROTATION) and the line says "not in orientation"; the
    Gen3 URDF's axes are rounded (pi/2 written 1.5708), so its tool turns, and the line gives the angle."""
    from redkin.models import kinova_gen3
    from redkin.srs import nearly_srs

    q = np.random.default_rng(0).uniform(-np.pi, np.pi, (500, 7))
    seen = []
    for arm in (nearly_srs(kinova_gen3()), _arm("jaco2"), _arm("gen3")):
        mine, theirs = arm.chain.fk(q), arm.neighbour.fk(q)
        relative = np.einsum("nji,njk->nik", mine[:, :3, :3], theirs[:, :3, :3])
        turned = np.linalg.norm(Rotation.from_matrix(relative).as_rotvec(), axis=-1).max()
        rounding = turned < ROUNDING_ROTATION
        assert (arm.rotation_error < ROUNDING_ROTATION) == rounding, arm.chain.name
        assert ("not in orientation (to rounding)" in arm.describe()) == rounding
        assert (f"{np.degrees(arm.rotation_error):.3g} deg" in arm.describe()) == (not rounding)
        seen.append(rounding)
    assert seen == [True, True, False]


def test_a_pose_the_neighbour_cannot_reach_has_no_bound():
    arm = _arm("gen3")
    far = arm.chain.fk(np.zeros(7))
    far[:3, 3] *= 10.0
    distance = neighbour_distance(arm, far, [0.0, 1.0], "+++")
    assert np.all(np.isinf(distance.bound)) and np.all(np.isnan(distance.neighbour))


@pytest.mark.parametrize("pose, psi, branch", [
    (np.eye(3), 0.0, "+++"),
    (np.diag([1.0, 1.0, 2.0, 1.0]), 0.0, "+++"),
    (np.eye(4), np.nan, "+++"),
    (np.eye(4), 0.0, "+0+"),
])
def test_bad_input_raises_value_error(pose, psi, branch):
    with pytest.raises(ValueError):
        neighbour_distance(_arm("iiwa14-rosi"), pose, psi, branch)


def test_a_chain_that_is_not_a_nearly_srs_arm_is_refused():
    with pytest.raises(RedkinError, match="NearlySRS"):
        neighbour_distance(_arm("gen3").chain, np.eye(4), 0.0, "+++")  # type: ignore[arg-type]


def test_the_model_error_is_kept_on_disk_and_read_back_exactly(tmp_path, monkeypatch):
    """``model_error`` searches once per pair of chains and reads its result back after, bit for bit, without the
    search; another pair of chains (the Jaco2's), a kept file that does not read back, or a cache folder that cannot
    be written costs only the search again (redkin._disk_cache)."""
    import redkin.srs.conventions as conventions
    from redkin._disk_cache import cache_folder

    monkeypatch.setenv("REDKIN_CACHE_DIR", str(tmp_path / "cache"))
    gen3, jaco2 = _arm("gen3"), _arm("jaco2")
    first = model_error(gen3.chain, gen3.neighbour)
    kept = list(cache_folder("model-errors").glob("*.json"))
    assert len(kept) == 1
    searches = []
    search = conventions._searched_model_error
    monkeypatch.setattr(conventions, "_searched_model_error", lambda *chains: searches.append(1) or search(*chains))
    assert model_error(gen3.chain, gen3.neighbour) == first and not searches  # read back, not searched
    assert model_error(jaco2.chain, jaco2.neighbour) != first and len(searches) == 1  # its own search
    kept[0].write_text("[0.5")  # does not read back: searched again, the same numbers
    assert model_error(gen3.chain, gen3.neighbour) == first and len(searches) == 2
    (tmp_path / "file").write_text("")
    monkeypatch.setenv("REDKIN_CACHE_DIR", str(tmp_path / "file"))  # a file: no folder can be made there
    assert model_error(gen3.chain, gen3.neighbour) == first and len(searches) == 3
