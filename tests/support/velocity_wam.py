"""Shared pieces of the velocity tests on the Barrett WAM: the arm, its D_e, the section 4 scenario, random inputs,
path comparison (module constants and strategies: hypothesis reads them when the tests are collected)."""

import numpy as np
from hypothesis import strategies as st

from redkin.models import barrett_wam
from redkin.reproduce import printed
from redkin.velocity import WamFactorisation

WAM = barrett_wam()
FACTOR = WamFactorisation.from_chain(WAM)
# paper 003 section 4: the threshold D_eps, the start of the tracking scenario and the commanded twist
EPS = printed.SECTION_4_D_EPS
Q0 = np.radians(printed.SECTION_4_Q0_DEG)
TWIST = np.array(printed.SECTION_4_TWIST)
# q4 where D_e = a (d3 + d5) cos q4 + (a^2 - d3 d5) sin q4 vanishes
Q4_ZERO = float(np.arctan2(-FACTOR.a * (FACTOR.d3 + FACTOR.d5), FACTOR.a**2 - FACTOR.d3 * FACTOR.d5))

angles = st.floats(-np.pi, np.pi)
configurations = st.lists(angles, min_size=7, max_size=7).map(np.array)
twists = st.lists(st.floats(-1.0, 1.0), min_size=6, max_size=6).map(np.array)


def assert_same(reference, other):
    """Two velocity solutions agree: joint velocities to 1e-10 (relative to their size), target twists to 1e-12."""
    scale = max(1.0, float(np.max(np.abs(reference.joint_velocity))))
    np.testing.assert_allclose(other.joint_velocity, reference.joint_velocity, rtol=0, atol=1e-10 * scale)
    np.testing.assert_allclose(other.target_twist, reference.target_twist, rtol=0, atol=1e-12)


def well_conditioned(q):
    """Away from the shoulder/wrist singularities (D_s small), where every path loses digits alike."""
    return abs(np.sin(q[1])) > 0.05 and abs(np.sin(q[5])) > 0.05
