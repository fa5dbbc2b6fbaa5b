"""D_e of paper 003 found from the geometry, whatever the description of the arm (issue 22, item 2).

The same Barrett WAM written as paper 003's DH rows (``barrett-wam7``), as a URDF whose joint frames are turned
(twists of +90 deg, zero poses at pi, frames turned every way), with reversed joints, and as modified DH: the
factorisation is found, ``D_e D_i`` equals the column minors ``det J_i`` of the description's own Jacobian, ``D_e``
vanishes exactly where that Jacobian loses rank, and the SC method moves the arm the same way in each description's
own joint values.  Offset elbows with ``a_3 != -a_4`` get ``sin(theta_4 - phi)``, S-R-S arms ``sin(theta_4)``; a
chain whose singularities do not go through one parameter is refused in one line.

A description is built here from a reference chain (standard DH rows, ``offset = 0``, ``sign = +1``) with zero
offsets ``c`` and joint senses ``s``: its joint values ``q`` are the reference's ``c + s q``.
"""

from __future__ import annotations

import re
import tempfile
import warnings
from functools import cache
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from redkin.chain import SerialChain
from redkin.cli.main import main
from redkin.models import barrett_wam, barrett_wam7, srs_chain
from redkin.srs import srs_geometry
from redkin.velocity import (
    ElbowSine,
    NumericalFactorisation,
    SingularityConsistent,
    SingularityConsistentController,
    WamFactorisation,
    column_minors,
    simulate,
    singularity_factorisation,
    wam_singularity_index,
)
from tests.support.srs_arms import offset_elbow_chain
from tests.support.urdf_reference import axis_angle, reference_fk, urdf

KINDS = ("dh", "mdh", "urdf")
WAM7 = barrett_wam7()

angles = st.floats(-np.pi, np.pi)
descriptions = st.fixed_dictionaries({
    "kind": st.sampled_from(KINDS),
    "offset": st.lists(st.one_of(angles, st.sampled_from([0.0, np.pi, -np.pi, np.pi / 2])), min_size=7, max_size=7),
    "sign": st.lists(st.sampled_from([1.0, -1.0]), min_size=7, max_size=7),
    "turns": st.lists(st.lists(angles, min_size=3, max_size=3), min_size=7, max_size=7),
})
seeds = st.integers(0, 2**32 - 1)


# ----------------------------------------------------------------------------- descriptions of one arm
def _transform(rotation=None, translation=(0.0, 0.0, 0.0)) -> np.ndarray:
    pose = np.eye(4)
    pose[:3, :3] = np.eye(3) if rotation is None else rotation
    pose[:3, 3] = translation
    return pose


def _rz(angle: float) -> np.ndarray:
    return _transform(axis_angle([0, 0, 1], angle))


def _link(a: float, alpha: float, d: float) -> np.ndarray:
    """``Tz(d) Tx(a) Rx(alpha)``: the fixed part of a standard DH row."""
    return _transform(translation=(0.0, 0.0, d)) @ _transform(axis_angle([1, 0, 0], alpha), (a, 0.0, 0.0))


def _rpy(rotation: np.ndarray) -> tuple[float, float, float]:
    """URDF roll, pitch, yaw of a rotation ``Rz(yaw) Ry(pitch) Rx(roll)``."""
    return (float(np.arctan2(rotation[2, 1], rotation[2, 2])),
            float(np.arctan2(-rotation[2, 0], np.hypot(rotation[0, 0], rotation[1, 0]))),
            float(np.arctan2(rotation[1, 0], rotation[0, 0])))


def _turn(angles_xyz) -> np.ndarray:
    """A rotation from three angles (about x, then y, then z of the fixed frame)."""
    x, y, z = angles_xyz
    return axis_angle([0, 0, 1], z) @ axis_angle([0, 1, 0], y) @ axis_angle([1, 0, 0], x)


def wam_urdf_text(reference: SerialChain, offset, sign, turns) -> str:
    """A URDF of ``reference`` whose joint ``k`` turns about ``sign_k`` times its DH axis, with ``q = 0`` at DH angle
    ``offset_k``, and whose link frames are turned by ``turns[k]`` (three angles) against the DH frames.

    Body ``k``'s URDF frame is ``F_{k-1} Rz(theta_k) G_k`` (``F`` the DH frames), so joint ``k``'s origin is
    ``G_{k-1}^T Tz Tx Rx(row k-1) Rz(offset_k) G_k`` and its axis ``G_k^T (0, 0, sign_k)``.
    """
    rows = list(zip(reference.a, reference.alpha, reference.d))
    frames = [np.eye(4)] + [_transform(_turn(t)) for t in turns]
    joints = []
    for k in range(8):
        before = reference.base if k == 0 else _link(*rows[k - 1])
        origin = frames[k].T @ before  # rotations only: the transpose is the inverse
        if k < 7:
            origin = origin @ _rz(offset[k]) @ frames[k + 1]
            axis = frames[k + 1][:3, :3].T @ [0.0, 0.0, sign[k]]
            joint = ("revolute", " ".join(repr(float(v)) for v in axis))
        else:
            origin = origin @ reference.tool
            joint = ("fixed", "")
        xyz = " ".join(repr(float(v)) for v in origin[:3, 3])
        rpy = " ".join(repr(v) for v in _rpy(origin[:3, :3]))
        joints.append((joint[0], xyz, rpy, joint[1]))
    return urdf(joints, name="wam-turned")


def _load(text: str) -> SerialChain:
    from redkin.urdf import load_urdf

    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "arm.urdf"
        path.write_text(text)
        return load_urdf(path)


def described(reference: SerialChain, kind: str, offset, sign, turns=((0.0, 0.0, 0.0),) * 7) -> SerialChain:
    """``reference`` (standard DH, offset 0, sign +1) written as standard DH, modified DH or a turned URDF, with
    joint values ``q`` whose reference values are ``offset + sign * q``."""
    offset, sign = np.asarray(offset, dtype=float), np.asarray(sign, dtype=float)
    if kind == "dh":
        return SerialChain(a=reference.a, alpha=reference.alpha, d=reference.d, offset=offset, sign=sign,
                           base=reference.base, tool=reference.tool, name="wam-dh")
    if kind == "mdh":  # Rz Tz Tx Rx Rz Tz ... regrouped as Rz Tz | Tx Rx Rz Tz | ...; the last Tx Rx into the tool
        tool = _link(reference.a[6], reference.alpha[6], 0.0) @ reference.tool
        return SerialChain(a=np.r_[0.0, reference.a[:6]], alpha=np.r_[0.0, reference.alpha[:6]], d=reference.d,
                           offset=offset, sign=sign, convention="mdh", base=reference.base, tool=tool, name="wam-mdh")
    return _load(wam_urdf_text(reference, offset, sign, turns))


def _description(reference: SerialChain, drawn: dict) -> tuple[SerialChain, np.ndarray, np.ndarray]:
    offset, sign = np.array(drawn["offset"]), np.array(drawn["sign"])
    chain = described(reference, drawn["kind"], offset, sign, drawn["turns"])
    q = np.random.default_rng(0).uniform(-np.pi, np.pi, (20, 7))
    np.testing.assert_allclose(chain.fk(q), reference.fk(offset + sign * q), rtol=0, atol=1e-12)  # the same arm
    return chain, offset, sign


def jhu_wam_urdf() -> str:
    """The WAM as jhu-lcsr's ``barrett_model`` writes it (``models/components.urdf.xacro``, expanded): every joint
    about its link's z, the frames turned by -+-+-+ quarter turns about x, the base 0.346 m below the shoulder;
    a tool point 0.06 m beyond the last joint, as ``barrett-wam7``.  Imported, its twists are +90 deg and its
    offsets pi."""
    half = repr(np.pi / 2)
    rows = [("0 0 0.346", "0 0 0", (-2.6, 2.6)), ("0 0 0", f"-{half} 0 0", (-1.985, 1.985)),
            ("0 0 0", f"{half} 0 0", (-2.8, 2.8)), ("0.045 0 0.55", f"-{half} 0 0", (-0.9, np.pi)),
            ("-0.045 -0.3 0", f"{half} 0 0", (-4.8, 1.3)), ("0 0 0", f"-{half} 0 0", (-1.5707, 1.5707)),
            ("0 0 0", f"{half} 0 0", (-2.95, 2.95))]
    body = "".join(
        f'<link name="link{k}"/><joint name="joint{k}" type="revolute"><parent link="link{k - 1}"/>'
        f'<child link="link{k}"/><origin xyz="{xyz}" rpy="{rpy}"/><axis xyz="0 0 1"/>'
        f'<limit lower="{lower!r}" upper="{upper!r}" effort="1" velocity="1"/></joint>'
        for k, (xyz, rpy, (lower, upper)) in enumerate(rows, start=1))
    tool = ('<link name="tool"/><joint name="tool_plate" type="fixed"><parent link="link7"/><child link="tool"/>'
            '<origin xyz="0 0 0.06" rpy="0 0 0"/></joint>')
    return f'<robot name="wam7-jhu"><link name="link0"/>{body}{tool}</robot>'


# ----------------------------------------------------------------------------- the laws
def assert_factors(chain: SerialChain, factorisation, q: np.ndarray) -> None:
    """``D_e D_i = det J_i`` (relative to the largest minor of each configuration, 1e-9, or to the largest of the
    batch, 1e-12, where every minor is rounding: hypothesis drew ``theta_4`` 5e-7 from pi on an arm with equal upper
    arm and forearm, where the wrist meets the shoulder and both factors vanish) and Cauchy-Binet
    ``det(J J^T) = D_e^2 D_s``: the Jacobian loses rank exactly where ``D_e = 0`` or ``D_s = sum D_i^2 = 0``."""
    jac = chain.jacobian(q)
    minors = column_minors(jac)
    d_e, d_i = factorisation.index(q), factorisation.factors(q, jac)
    scale = np.abs(minors).max(axis=-1, keepdims=True)
    assert np.all(np.abs(d_e[:, None] * d_i - minors) <= 1e-9 * scale + 1e-12 * scale.max())
    gram = np.linalg.det(jac @ np.swapaxes(jac, -1, -2))
    np.testing.assert_allclose(d_e**2 * np.sum(d_i**2, axis=-1), gram, rtol=1e-8, atol=1e-12 * scale.max() ** 2)


def assert_rank_lost_where_index_vanishes(chain: SerialChain, factorisation, q: np.ndarray) -> None:
    """At configurations with ``D_e = 0`` (away from the shoulder and wrist singularities) the Jacobian has rank 5:
    its smallest singular value is rounding, the next one is not."""
    assert np.abs(factorisation.index(q)).max() < 1e-12
    singular = np.linalg.svd(chain.jacobian(q), compute_uv=False)
    assert np.all(singular[:, -1] < 1e-12 * singular[:, 0])
    assert np.all(singular[:, -2] > 1e-6 * singular[:, 0])  # rank 5, not lower: the index has a simple zero


def index_zeros(factorisation, q: np.ndarray) -> np.ndarray:
    """``q`` with ``q_4`` moved (secant steps on the description's own index) onto a zero of ``D_e``."""
    q = np.array(q, dtype=float)
    before, now = q.copy(), q.copy()
    before[:, 3] -= 1e-3
    for _ in range(60):
        f_before, f_now = factorisation.index(before), factorisation.index(now)
        slope = f_now - f_before
        step = np.where(slope != 0.0, f_now * (now[:, 3] - before[:, 3]) / np.where(slope != 0.0, slope, 1.0), 0.0)
        before = now.copy()
        now[:, 3] -= np.clip(step, -0.5, 0.5)
    return now


# ----------------------------------------------------------------------------- the WAM in any description
@settings(deadline=None, max_examples=60)
@given(descriptions, seeds)
def test_the_wam_in_any_description_gets_the_closed_form_and_it_factors_its_own_minors(drawn, seed):
    chain, offset, sign = _description(WAM7, drawn)
    found = singularity_factorisation(chain)
    assert isinstance(found, WamFactorisation)
    assert found == WamFactorisation.from_chain(chain)
    rng = np.random.default_rng(seed)
    q_ref = rng.uniform(-np.pi, np.pi, (40, 7))
    q = sign * (q_ref - offset)
    assert_factors(chain, found, q)
    # the same index up to its sign: the same eps means the same region on every description
    reference = WamFactorisation.from_chain(WAM7)
    np.testing.assert_allclose(np.abs(found.index(q)), np.abs(reference.index(q_ref)), rtol=0, atol=1e-13)
    keep = np.abs(np.sin(q_ref[:, [1, 5]])).min(axis=-1) > 0.1  # away from the shoulder and wrist singularities
    assert keep.any()
    assert_rank_lost_where_index_vanishes(chain, found, index_zeros(found, q[keep]))


def test_the_jhu_lcsr_wam_urdf_is_barrett_wam7_with_turned_frames():
    """The import gives twists of +90 deg and offsets of pi (what the literal pattern refused); the factorisation is
    barrett-wam7's, in the same joint values."""
    chain = _load(jhu_wam_urdf())
    assert np.allclose(np.degrees(chain.alpha[:6]), 90.0) and np.allclose(chain.offset[:6], np.pi)
    q = np.random.default_rng(3).uniform(-np.pi, np.pi, (50, 7))
    shoulder = np.array([0.0, 0.0, 0.346])
    np.testing.assert_allclose(chain.fk(q)[:, :3, 3] - shoulder, WAM7.fk(q)[:, :3, 3], rtol=0, atol=1e-14)
    found = singularity_factorisation(chain)
    reference = singularity_factorisation(WAM7)
    assert isinstance(found, WamFactorisation)
    assert (found.a, found.d3, found.d5) == pytest.approx((reference.a, reference.d3, reference.d5), abs=1e-15)
    np.testing.assert_allclose(found.index(q), reference.index(q), rtol=0, atol=1e-15)
    np.testing.assert_allclose(found.factors(q), reference.factors(q), rtol=0, atol=1e-14)
    assert_factors(chain, found, q)


def test_the_closed_form_in_the_paper_003_rows_is_unchanged():
    """``WamFactorisation(a, d3, d5)`` still means paper 003's rows in their own angles (offset 0, sign +1)."""
    wam = barrett_wam()
    found = WamFactorisation.from_chain(wam)
    assert found == WamFactorisation(0.045, 0.55, 0.4)
    assert found.offset == (0.0,) * 7 and found.sign == (1.0,) * 7
    with pytest.raises(ValueError, match="sign must be 7 entries"):
        WamFactorisation(0.045, 0.55, 0.4, sign=[1, 1, 1, 0, 1, 1, 1])
    with pytest.raises(ValueError, match="offset must be 7"):
        WamFactorisation(0.045, 0.55, 0.4, offset=[0.0] * 6)


@settings(deadline=None, max_examples=40)
@given(st.floats(-0.2, 0.2), st.floats(0.1, 0.8), st.floats(0.1, 0.8), seeds)
def test_the_wam_index_is_minus_half_r_times_the_sine_of_theta4_minus_phi(a, d3, d5, seed):
    """``a (d3 + d5) cos t4 + (a^2 - d3 d5) sin t4 = -(R/2) sin(t4 - phi)`` with ``R``, ``phi`` of
    ``|x_sw|^2 = C + R cos(t4 - phi)`` for ``a_3 = a``, ``a_4 = -a`` (written out here: ``A = 2 (a3 a4 + d3 d5)``,
    ``B = 2 (a3 d5 - d3 a4)``)."""
    big_a, big_b = 2.0 * (-a * a + d3 * d5), 2.0 * (a * d5 + d3 * a)
    amplitude, phase = np.hypot(big_a, big_b), np.arctan2(big_b, big_a)
    q = np.random.default_rng(seed).uniform(-np.pi, np.pi, (30, 7))
    np.testing.assert_allclose(wam_singularity_index(q, a, d3, d5), -0.5 * amplitude * np.sin(q[:, 3] - phase),
                               rtol=0, atol=1e-15)


# ----------------------------------------------------------------------------- SC motion is the same
SCENARIO_Q0 = np.radians([10.0, 40.0, 20.0, 60.0, -30.0, 50.0, 0.0])
SCENARIO_EPS, SCENARIO_DURATION, SCENARIO_DT = 0.05, 1.0, 0.01


def _scenario_twist() -> np.ndarray:
    """Stretch barrett-wam7 from ``SCENARIO_Q0`` (shoulder -> tool at 0.3 m/s) while turning about y: D_e crosses 0
    once in the run."""
    reach = WAM7.fk(SCENARIO_Q0)[:3, 3] - WAM7.frames(SCENARIO_Q0)[2, :3, 3]
    return np.r_[0.3 * reach / np.linalg.norm(reach), 0.0, 0.2, 0.0]


@cache
def _reference_run(lean: bool):
    method = SingularityConsistent(SCENARIO_EPS, lean=lean)
    run = simulate(WAM7, SCENARIO_Q0, _scenario_twist(), SCENARIO_DURATION, method, dt=SCENARIO_DT,
                   index=singularity_factorisation(WAM7).index)
    assert np.count_nonzero(np.diff(np.sign(run.index)) != 0) == 1  # the run goes through the singularity
    return run


@settings(deadline=None, max_examples=25)
@given(descriptions, st.booleans())
def test_sc_tracking_moves_every_description_of_the_wam_alike(drawn, lean):
    """The SC run (the controller when ``lean``, the cofactor sums of [003 eqs. 15-22] otherwise) gives the same
    joint path in each description's own joint values, through the singularity, to 1e-9 rad."""
    chain, offset, sign = _description(WAM7, drawn)
    reference = _reference_run(lean)
    q0 = sign * (SCENARIO_Q0 - offset)
    run = simulate(chain, q0, _scenario_twist(), SCENARIO_DURATION, SingularityConsistent(SCENARIO_EPS, lean=lean),
                   dt=SCENARIO_DT, index=singularity_factorisation(chain).index)
    np.testing.assert_allclose(offset + sign * run.q, reference.q, rtol=0, atol=1e-9)
    np.testing.assert_allclose(run.realised, reference.realised, rtol=0, atol=1e-9)
    np.testing.assert_allclose(np.abs(run.index), np.abs(reference.index), rtol=0, atol=1e-12)


@settings(deadline=None, max_examples=25)
@given(descriptions, seeds)
def test_the_sc_controller_on_the_singular_set_steps_alike_in_every_description(drawn, seed):
    """On ``D_e = 0`` the controller takes the exact path with ``D_i``: the same joint velocity, mapped."""
    chain, offset, sign = _description(WAM7, drawn)
    reference = WamFactorisation.from_chain(WAM7)
    rng = np.random.default_rng(seed)
    q_ref = index_zeros(reference, rng.uniform(-2.0, 2.0, (1, 7)))[0]
    twist = rng.normal(size=6)
    expected = SingularityConsistentController(WAM7, q_ref, 0.1, direction=1.0)(q_ref, twist)
    found = singularity_factorisation(chain)
    q = sign * (q_ref - offset)
    # b_ep follows the sign D_e takes in the description (as it does from q0 by default): D_e there is kappa D_e here
    generic = np.array([0.3, 0.8, -0.4, 1.2, 0.5, -0.9, 0.2])
    kappa = np.sign(found.index(sign * (generic - offset)) / reference.index(generic))
    direction = float(kappa)
    step = SingularityConsistentController(chain, q, 0.1, direction=direction)(q, twist)
    scale = max(1.0, float(np.abs(expected.joint_velocity).max()))
    np.testing.assert_allclose(sign * step.joint_velocity, expected.joint_velocity, rtol=0, atol=1e-9 * scale)


# ----------------------------------------------------------------------------- other elbows
@settings(deadline=None, max_examples=40)
@given(st.lists(st.floats(0.1, 0.8), min_size=4, max_size=4), st.floats(-0.15, 0.15), st.floats(-0.15, 0.15),
       descriptions, seeds)
def test_an_offset_elbow_without_the_wam_pattern_gets_the_sine_of_theta4_minus_phi(lengths, a3, a4, drawn, seed):
    """``a_3 != -a_4``: ``D_e = sin(theta_4 - phi)`` (through ``NumericalFactorisation``), ``phi`` of the elbow
    equation ``|x_sw|^2 = C + R cos(theta_4 - phi)``; it factors every minor of the description's Jacobian."""
    if abs(a3 + a4) < 1e-3 or max(abs(a3), abs(a4)) < 1e-3:
        return  # the WAM pattern, or (nearly) an S-R-S elbow: other tests
    reference = offset_elbow_chain(*lengths, a3, a4)
    chain, offset, sign = _description(reference, drawn)
    found = singularity_factorisation(chain)
    assert isinstance(found, NumericalFactorisation) and isinstance(found.index_function, ElbowSine)
    with pytest.raises(ValueError, match="Barrett WAM DH pattern"):
        WamFactorisation.from_chain(chain)
    d_se, d_ew = lengths[1], lengths[2]
    phase = np.arctan2(2.0 * (a3 * d_ew - d_se * a4), 2.0 * (a3 * a4 + d_se * d_ew))
    rng = np.random.default_rng(seed)
    q_ref = rng.uniform(-np.pi, np.pi, (30, 7))
    q = sign * (q_ref - offset)
    np.testing.assert_allclose(np.abs(found.index(q)), np.abs(np.sin(q_ref[:, 3] - phase)), rtol=0, atol=1e-12)
    assert_factors(chain, found, q)
    keep = np.abs(np.sin(q_ref[:, [1, 5]])).min(axis=-1) > 0.1
    assert keep.any()
    on_set = index_zeros(found, q[keep])
    assert_rank_lost_where_index_vanishes(chain, found, on_set)
    # on the zero set D_i is the l'Hopital limit: continuous with its neighbours
    nudge = np.zeros(7)
    nudge[3] = 1e-6
    np.testing.assert_allclose(found.factors(on_set), found.factors(on_set + nudge), rtol=0,
                               atol=1e-4 * np.abs(found.factors(on_set + nudge)).max())


@settings(deadline=None, max_examples=25)
@given(st.lists(st.floats(0.1, 0.8), min_size=4, max_size=4), descriptions, seeds)
def test_an_srs_arm_in_any_description_keeps_the_sine_of_theta4(lengths, drawn, seed):
    """An S-R-S arm (a URDF among the descriptions): ``D_e = sin(theta_4)`` of its Table 1 form, up to sign."""
    reference = srs_chain(*lengths)
    chain, offset, sign = _description(reference, drawn)
    found = singularity_factorisation(chain)
    assert isinstance(found, NumericalFactorisation) and found.index_function.phase == 0.0
    q_ref = np.random.default_rng(seed).uniform(-np.pi, np.pi, (30, 7))
    q = sign * (q_ref - offset)
    np.testing.assert_allclose(np.abs(found.index(q)), np.abs(np.sin(q_ref[:, 3])), rtol=0, atol=1e-12)
    assert_factors(chain, found, q)


def test_an_srs_arm_as_a_urdf_with_turned_frames():
    reference = srs_chain(0.34, 0.4, 0.4, 0.126)
    turns = np.random.default_rng(5).uniform(-np.pi, np.pi, (7, 3))
    offset, sign = np.array([0.3, np.pi, -1.0, np.pi, 0.0, 2.0, 0.5]), np.array([1, -1, 1, -1, -1, 1, -1.0])
    chain = described(reference, "urdf", offset, sign, turns)
    text = wam_urdf_text(reference, offset, sign, turns)
    q = np.random.default_rng(6).uniform(-np.pi, np.pi, (20, 7))
    np.testing.assert_allclose(chain.fk(q[0]), reference_fk(text, q[0], "l8"), rtol=0, atol=1e-12)  # the URDF itself
    found = singularity_factorisation(chain)
    assert isinstance(found, NumericalFactorisation) and found.index_function.phase == 0.0
    assert_factors(chain, found, q)
    geometry = srs_geometry(chain)
    assert not geometry.offset_elbow


# ----------------------------------------------------------------------------- refusals
def _offset_wrist() -> SerialChain:
    """A WAM with an offset wrist (``a_5 = 0.03``): joints 5-7 do not meet."""
    wam = barrett_wam7()
    return SerialChain(a=[0, 0, 0.045, -0.045, 0.03, 0, 0], alpha=wam.alpha, d=wam.d, name="offset-wrist")


@settings(deadline=None, max_examples=10)
@given(st.lists(st.floats(-0.5, 0.5), min_size=7, max_size=7),
       st.lists(st.floats(0.3, np.pi - 0.3), min_size=7, max_size=7),
       st.lists(st.floats(0.05, 0.5), min_size=7, max_size=7))
def test_a_chain_whose_singularities_do_not_factor_is_refused_in_one_line(a, alpha, d):
    """An offset wrist, a planar chain (singular everywhere) and random 7R chains (no spherical shoulder or wrist,
    and no two consecutive axes parallel: with alpha = 0, 0, 1, 1, 0, 0, 0 -- axes 1-3 and 5-7 parallel --
    hypothesis found a chain whose every column minor sin(theta_4) does divide): one line, and no numpy warning on
    the way."""
    planar = SerialChain(a=[0.3] * 7, alpha=[0.0] * 7, d=[0.0] * 7, name="planar")
    for chain in (_offset_wrist(), planar, SerialChain(a=a, alpha=alpha, d=d, name="random-7r")):
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            with pytest.raises(ValueError) as refused:
                singularity_factorisation(chain)
        message = str(refused.value)
        assert "do not factor through one parameter" in message and len(message.splitlines()) == 1
        with pytest.raises(ValueError, match="Barrett WAM DH pattern") as not_wam:
            WamFactorisation.from_chain(chain)
        assert len(str(not_wam.value).splitlines()) == 1


# ----------------------------------------------------------------------------- the command line
NUMBER = re.compile(r"[-+]?\d+(?:\.\d*)?(?:e[-+]?\d+)?")


def _track(robot: str, capsys) -> tuple[list[float], list[float]]:
    """``redkin track ROBOT --method sc`` through the singularity: the numbers of the lines it prints about the final
    q and about D_e (compared with a tolerance: the text rounds them)."""
    twist = _scenario_twist()
    args = ["track", robot, "--q0", *map(repr, SCENARIO_Q0.tolist()), "--twist", *map(repr, twist.tolist()),
            "--duration", "1", "--dt", "0.01", "--method", "sc", "--eps", repr(SCENARIO_EPS)]
    assert main(args) == 0
    lines = capsys.readouterr().out.splitlines()
    final_q = next(line for line in lines if line.startswith("final q"))
    index = next(line for line in lines if line.startswith("D_e"))
    return [float(v) for v in NUMBER.findall(final_q)], [float(v) for v in NUMBER.findall(index.split("_e", 1)[1])]


def test_cli_track_sc_on_a_wam_urdf_with_turned_frames(tmp_path, capsys):
    """jhu-lcsr's frames (+90 deg twists, pi offsets) and a randomly turned URDF: `redkin track --method sc` runs
    and ends where barrett-wam7 does."""
    final_q, index = _track("barrett-wam7", capsys)
    assert index[0] < 0.0 < index[1]  # "D_e from ... to ...": the run crosses the singularity
    jhu = tmp_path / "wam7_jhu.urdf"
    jhu.write_text(jhu_wam_urdf())
    turned = tmp_path / "wam7_turned.urdf"
    turns = np.random.default_rng(11).uniform(-np.pi, np.pi, (7, 3))
    turned.write_text(wam_urdf_text(WAM7, np.zeros(7), np.ones(7), turns))
    for path in (jhu, turned):
        got_q, got_index = _track(str(path), capsys)
        np.testing.assert_allclose(got_q, final_q, rtol=0, atol=1e-12)
        np.testing.assert_allclose(got_index, index, rtol=0, atol=1e-12)
