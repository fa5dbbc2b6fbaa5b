"""Detection of the Franka class (redkin.franka.franka_geometry): in any description, and nothing almost of it.

Laws: the models and Franka's URDFs are accepted; the same arm written in other conventions (other zero offsets,
reversed joint senses, modified DH, common normals turned over, other base and tool frames, a URDF with turned
frames) and random arms of the class are accepted, and the solver's form gives the chain's FK at every q, with the
same elbow and wrist; an arm that misses the class by a little is refused with the offset that breaks it, in the
message and in ``distance``; the geometry (or the refusal) is derived once and cached on the chain.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from redkin.chain import SerialChain
from redkin.errors import NotArmAngleClassError, RedkinError
from redkin.franka import FrankaGeometry, _kernels, franka_geometry, ik
from redkin.models import get_robot
from tests.support.franka_arms import CONVENTIONS, MODELS, form_chain, other_conventions, random_arm, urdf_of

EXAMPLES = Path(__file__).resolve().parents[1] / "src" / "redkin" / "examples"
ROUND_TRIP = 1e-9
#: The FER's and FR3's lengths in the solver's form: d1, a3, d3, a4, d5, a6, d6 (Franka's modified DH rows).
FRANKA_FORM = (0.333, -0.0825, 0.316, 0.0825, 0.384, 0.088, 0.0)


def assert_form_is_the_chain(chain: SerialChain, rng: np.random.Generator) -> FrankaGeometry:
    """The chain is accepted and its form reaches the chain's pose at random q (any turn), in the same joint
    values, and IK of the chain's own poses comes back in its own joint values."""
    geometry = franka_geometry(chain)
    q = rng.uniform(-7.0, 7.0, (64, 7))
    assert np.abs(geometry.form.fk(q) - chain.fk(q)).max() < 1e-12
    assert np.array_equal(geometry.form.lower, chain.lower) and np.array_equal(geometry.form.upper, chain.upper)
    assert geometry.a6 != 0.0 and geometry.chain is chain
    solutions = ik(chain, chain.fk(q[:8]), q[:8, 6])
    assert np.all(solutions.exists.any(axis=-1))
    reached = chain.fk(solutions.q)
    assert np.abs(np.where(solutions.exists[..., None, None], reached - chain.fk(q[:8])[:, None], 0.0)).max() < 1e-9
    return geometry


def invariants(geometry: FrankaGeometry) -> np.ndarray:
    """What a rewriting cannot change: the elbow equation's mean and amplitude ``C, R`` ([F2]) and the sizes of
    ``a_3, d_3, a_4, d_5, a_6, d_6``."""
    arm = geometry.kernel_arm
    return np.r_[arm[7:9], np.abs([geometry.a3, geometry.d3, geometry.a4, geometry.d5, geometry.a6, geometry.d6])]


@pytest.mark.parametrize("name", MODELS)
def test_the_models_are_accepted(name):
    chain = get_robot(name)
    geometry = assert_form_is_the_chain(chain, np.random.default_rng(1))
    if name != "ufactory-xarm7":
        assert np.allclose([geometry.d1, geometry.a3, geometry.d3, geometry.a4, geometry.d5, geometry.a6,
                            geometry.d6], FRANKA_FORM, atol=1e-12)
    else:  # UFactory's table: a_6 = 0.076 m, the elbow 0.0525 and 0.0775 m
        assert abs(abs(geometry.a6) - 0.076) < 1e-12 and abs(geometry.d6) < 1e-12
        assert sorted(np.abs([geometry.a3, geometry.a4])) == pytest.approx([0.0525, 0.0775], abs=1e-12)


@pytest.mark.parametrize("file, tip", [("panda.urdf", None), ("fr3.urdf", "fr3_link8"), ("fr3.urdf", "fr3_hand_tcp"),
                                       ("fr3.urdf", None)])
def test_franka_urdfs_are_accepted(file, tip):
    chain = get_robot(EXAMPLES / file, tip=tip)
    geometry = assert_form_is_the_chain(chain, np.random.default_rng(2))
    assert np.allclose(invariants(geometry), invariants(franka_geometry(get_robot("franka-panda"))), atol=1e-12)


@pytest.mark.parametrize("convention", CONVENTIONS)
def test_the_panda_in_other_conventions(convention):
    rng = np.random.default_rng(3)
    panda = franka_geometry(get_robot("franka-panda")).form  # standard DH, zero offsets 0 or pi
    chain = other_conventions(panda, rng)[convention]
    geometry = assert_form_is_the_chain(chain, rng)
    assert np.allclose(invariants(geometry), invariants(franka_geometry(panda)), atol=1e-12)


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**31), zero_elbow=st.booleans(), zero_d6=st.booleans())
def test_random_arms_of_the_class_in_every_convention(seed, zero_elbow, zero_d6):
    """Random lengths and offsets (a_6 != 0 of either sign, d_6 possibly != 0, elbow offsets possibly 0)."""
    rng = np.random.default_rng(seed)
    chain = random_arm(rng, zero_elbow=zero_elbow, zero_d6=zero_d6)
    geometry = assert_form_is_the_chain(chain, rng)
    expected = np.r_[0, 0, np.abs([chain.a[2], chain.d[2], chain.a[3], chain.d[4], chain.a[5], chain.d[5]])]
    assert np.allclose(invariants(geometry)[2:], expected[2:], atol=1e-12)
    for name, other in other_conventions(chain, rng).items():
        again = assert_form_is_the_chain(other, rng)
        assert np.allclose(invariants(again), invariants(geometry), atol=1e-12), name


@settings(max_examples=10, deadline=None)
@given(seed=st.integers(0, 2**31))
def test_an_arm_without_elbow_offsets_has_none_in_every_convention(seed):
    """Rewriting an arm without elbow offsets leaves 1e-16 m of rounding in half the conventions; its form has none
    at all, so that the exact q7 sets take the limit functions that are squares on such an arm as squares
    (``_kernels.halved``: the full products' double roots were lifted off zero and crossings missed)."""
    rng = np.random.default_rng(seed)
    chain = random_arm(rng, zero_elbow=True)
    for name, other in {"dh": chain, **other_conventions(chain, rng)}.items():
        geometry = franka_geometry(other)
        assert geometry.a3 == 0.0 and geometry.a4 == 0.0, (name, geometry.a3, geometry.a4)
        halved = [bool(_kernels.halved(geometry.kernel_arm, f)) for f in range(_kernels.FUNCTIONS)]
        assert halved == [f not in (6, 7, 12) for f in range(_kernels.FUNCTIONS)], name
    assert not any(_kernels.halved(franka_geometry(get_robot("franka-panda")).kernel_arm, f) for f in range(14))


@settings(max_examples=8, deadline=None)
@given(seed=st.integers(0, 2**31))
def test_a_urdf_with_turned_frames_and_reversed_axes(seed, tmp_path_factory):
    from tests.support.urdf_reference import reference_fk

    rng = np.random.default_rng(seed)
    arm = random_arm(rng)
    turns, axes = rng.uniform(-np.pi, np.pi, 7), rng.choice([-1, 1], 7)
    text = urdf_of(arm, turns, axes)
    path = tmp_path_factory.mktemp("franka") / "arm.urdf"
    path.write_text(text)
    chain = get_robot(path)
    q = rng.uniform(-3.0, 3.0, (4, 7))
    for k in range(4):  # the URDF is the arm (its tip by the URDF definition), joints turning as the axes say
        assert np.allclose(reference_fk(text, q[k], "l8"), arm.fk(axes * q[k]), atol=1e-12)
    geometry = assert_form_is_the_chain(chain, rng)
    assert np.allclose(invariants(geometry), invariants(franka_geometry(arm)), atol=1e-12)


def _panda_rows(**changes) -> SerialChain:
    panda = get_robot("franka-panda")
    rows = dict(a=panda.a.copy(), alpha=panda.alpha.copy(), d=panda.d.copy())
    for key, (index, value) in changes.items():
        rows[key][index] = value
    return SerialChain(**rows, convention="mdh", tool=panda.tool, name="almost")


def _iiwa_like() -> SerialChain:
    """The Panda's lengths with axis 7 through the wrist point (a_6 = 0): an S-R-S wrist."""
    return form_chain(*FRANKA_FORM[:5], 0.0)


@pytest.mark.parametrize("chain, message, distance", [
    # Franka's modified DH rows: a_5 (row 6) offsets axis 6 from axis 5
    (_panda_rows(a=(5, 1e-4)), r"axes 5 and 6 miss each other by 0\.0001 m", 1e-4),
    (get_robot("kinova-gen3"), r"axes 1 and 3 miss each other by 0\.01175 m", 0.01175),
    (get_robot("kuka-iiwa14"), r"axes 6 and 7 meet \(no wrist offset\): an S-R-S wrist", 0.0),
    (_iiwa_like(), r"axes 6 and 7 meet \(no wrist offset\): an S-R-S wrist", 0.0),
    (_panda_rows(alpha=(6, np.radians(89.9))), r"axes 6 and 7 are 89\.9 deg apart, not 90", np.radians(0.1)),
    (_panda_rows(alpha=(3, np.radians(90.1))), r"axes 3 and 4 are 89\.9 deg apart, not 90", np.radians(0.1)),
    (SerialChain(a=np.zeros(6), alpha=np.full(6, np.pi / 2), d=np.ones(6), name="six"), r"it has 6 joints, not 7",
     0.0),
    (_panda_rows(d=(3, 0.02)), r"its elbow is offset 0\.02 m along axis 4", 0.02),
])
def test_almost_franka_arms_are_refused_with_the_offset_that_breaks_the_class(chain, message, distance):
    for _ in range(2):  # the refusal is cached and raised again the same way
        with pytest.raises(NotArmAngleClassError, match=message) as refusal:
            franka_geometry(chain)
        assert isinstance(refusal.value, ValueError)
        assert refusal.value.distance == pytest.approx(distance, rel=1e-6, abs=1e-15)
        assert "is not of the Franka class" in str(refusal.value)
    with pytest.raises(ValueError, match="not of the Franka class"):
        ik(chain, np.eye(4), 0.0)


def test_a_non_chain_is_refused():
    for thing in (None, "franka-panda", np.eye(4), franka_geometry(get_robot("franka-panda"))):
        with pytest.raises(RedkinError, match="chain must be a SerialChain"):
            franka_geometry(thing)


def test_the_geometry_is_cached_on_the_chain():
    chain = get_robot("franka-fr3")
    geometry = franka_geometry(chain)
    assert franka_geometry(chain) is geometry
    assert geometry.kernel_arm is geometry.kernel_arm and not geometry.kernel_arm.flags.writeable
    other = chain.with_limits(chain.lower, chain.upper)  # a new chain derives its own
    assert franka_geometry(other) is not geometry and franka_geometry(other) is franka_geometry(other)


@pytest.mark.parametrize("offset", [1e-6, 5e-6])
def test_a_franka_arm_off_by_rounding_is_snapped_and_says_how_far(offset):
    """A description whose axes miss the class by rounding (UFactory's xArm7 URDF prints pi/2 as 1.5708) is solved
    as the exact arm; its solutions reach the description's poses to about that rounding, and the class says so."""
    from redkin.arms.classify import arm_angle_class

    chain = _panda_rows(a=(5, offset))
    geometry = franka_geometry(chain)
    assert geometry.snapped
    reason = arm_angle_class(chain).reason
    assert "snapped to the exact arm from the description's rounding" in reason
    q = np.array([0.3, -0.5, 0.2, -2.0, 0.4, 1.8, 0.5])
    result = ik(chain, chain.fk(q), q[6])
    assert np.abs(chain.fk(result.q[result.exists]) - chain.fk(q)).max() < 20 * offset
    assert np.abs(result.q[result.exists] - q).max(axis=-1).min() < 1e3 * offset
