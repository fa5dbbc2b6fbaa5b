"""Thesis 001: the chain of Table 2.1 against [001 eq. 2.3] and the section 5.1 closed form (written here only)."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from redkin.models import HUMANOID_LENGTHS
from redkin.torso_arm import humanoid_arm
from redkin.torso_arm.geometry import WRIST_FRAME

L0, L1, L2, L3 = (HUMANOID_LENGTHS[k] for k in ("L0", "L1", "L2", "L3"))
L4 = 0.137


def eq_2_3(q):
    """[001 eq. 2.3] position and approach column (r13, r23, r33), transcription's parentheses repaired.

    In P_x and P_z the transcription closes the L3 term one parenthesis early
    ("...s4)) -(c3s1s2 + c1s3)s5)"); the repaired form keeps -(...)s5 inside it.
    """
    c1, c2, c3, c4, c5, c6, c7 = np.cos(q[:7])
    s1, s2, s3, s4, s5, s6, s7 = np.sin(q[:7])
    A = c2 * c4 * s1 + (c1 * c3 - s1 * s2 * s3) * s4
    B = c3 * s1 * s2 + c1 * s3
    C = -c4 * (c1 * c3 - s1 * s2 * s3) + c2 * s1 * s4
    r13 = c7 * (c5 * A + B * s5) - (-c6 * C - (c5 * B - A * s5) * s6) * s7
    px = L0 * c1 + L1 * B - L3 * (-c5 * A - B * s5) + L2 * (c5 * B - A * s5) + L4 * r13
    Ay = -c4 * s2 - c2 * s3 * s4
    Cy = c2 * c4 * s3 - s2 * s4
    r23 = c7 * (c5 * Ay + c2 * c3 * s5) - (-c6 * Cy - (c2 * c3 * c5 - Ay * s5) * s6) * s7
    py = L1 * c2 * c3 - L3 * (-c5 * Ay - c2 * c3 * s5) + L2 * (c2 * c3 * c5 - Ay * s5) + L4 * r23
    Az = c1 * c2 * c4 + (-c3 * s1 - c1 * s2 * s3) * s4
    Bz = c1 * c3 * s2 - s1 * s3
    Cz = -c4 * (-c3 * s1 - c1 * s2 * s3) + c1 * c2 * s4
    r33 = c7 * (c5 * Az + Bz * s5) - (-c6 * Cz - (c5 * Bz - Az * s5) * s6) * s7
    pz = -L0 * s1 + L1 * Bz - L3 * (-c5 * Az - Bz * s5) + L2 * (c5 * Bz - Az * s5) + L4 * r33
    return np.array([px, py, pz]), np.array([r13, r23, r33])


def section_5_1(q):
    """Section 5.1 wrist position X, Y, Z (as transcribed; its parentheses balance)."""
    c1, c2, c3, c4, c5 = np.cos(q[:5])
    s1, s2, s3, s4, s5 = np.sin(q[:5])
    m = L3 * c5 - L2 * s5
    k = L1 + L2 * c5 + L3 * s5
    inner = c2 * c4 * m + s2 * (-s3 * s4 * m + c3 * k)
    outer = L0 + c3 * s4 * m + s3 * k
    x = c1 * outer + inner * s1
    y = -c4 * s2 * m + c2 * (-s3 * s4 * m + c3 * k)
    z = c1 * inner - outer * s1
    return np.array([x, y, z])


angles = st.lists(st.floats(-np.pi, np.pi, allow_nan=False), min_size=8, max_size=8)


@settings(deadline=None, max_examples=60)
@given(angles)
def test_torso_arm_fk_matches_eq_2_3(values):
    q = np.array(values)
    pose = humanoid_arm("right", L4).chain.fk(q)
    position, approach = eq_2_3(q)
    scale = L0 + L1 + L2 + L3 + L4
    assert np.linalg.norm(pose[:3, 3] - position) <= 1e-9 * scale
    assert np.linalg.norm(pose[:3, 2] - approach) <= 1e-9


@settings(deadline=None, max_examples=60)
@given(angles)
def test_torso_arm_fk_wrist_matches_section_5_1(values):
    q = np.array(values)
    wrist = humanoid_arm().chain.frames(q)[WRIST_FRAME, :3, 3]
    assert np.linalg.norm(wrist - section_5_1(q)) <= 1e-9 * (L0 + L1 + L2 + L3)


def test_torso_arm_fk_left_is_mirror_with_theta1_negated():
    rng = np.random.default_rng(3)
    q = rng.uniform(-3, 3, (20, 8))
    mirror = np.diag([-1.0, 1.0, 1.0, 1.0])
    q_left = q * np.array([-1.0] + [1.0] * 7)
    right, left = humanoid_arm("right", L4).chain, humanoid_arm("left", L4).chain
    np.testing.assert_allclose(left.fk(q_left), mirror @ right.fk(q) @ mirror, atol=1e-12)
