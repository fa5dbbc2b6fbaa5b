"""Named robot models, each with the source of its numbers.

Every model is a function returning a :class:`~redkin.chain.SerialChain`
(SI units, radians).  :func:`get_robot` resolves a model name or a robot
file path; :func:`robot_names` lists the names.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import replace
from pathlib import Path

import numpy as np

from redkin._validation import check_nonnegative
from redkin.chain import SerialChain
from redkin.circle import HALF_PI
from redkin.errors import RedkinError


def srs_chain(
    d_bs: float,
    d_se: float,
    d_ew: float,
    d_wt: float,
    lower_deg: Sequence[float] | None = None,
    upper_deg: Sequence[float] | None = None,
    name: str = "srs",
    source: str = "",
) -> SerialChain:
    """A 7-DOF S-R-S arm in the form of paper 000 Table 1 (standard DH).

    alpha = (-pi/2, pi/2, -pi/2, pi/2, -pi/2, pi/2, 0), d = (d_bs, 0, d_se, 0,
    d_ew, 0, d_wt), a = 0.  At q = 0 the arm points straight up the base z
    axis and the tool frame is aligned with the base frame.
    """
    lower = None if lower_deg is None else np.radians(lower_deg)
    upper = None if upper_deg is None else np.radians(upper_deg)
    return SerialChain(
        a=np.zeros(7),
        alpha=[-HALF_PI, HALF_PI, -HALF_PI, HALF_PI, -HALF_PI, HALF_PI, 0.0],
        d=[d_bs, 0.0, d_se, 0.0, d_ew, 0.0, d_wt],
        convention="dh",
        lower=lower,
        upper=upper,
        name=name,
        source=source,
    )


def pa10_7c() -> SerialChain:
    """Mitsubishi PA10-7C.

    Source: paper 000 (Shimizu et al.), Table 1 (DH form) with section 6 link
    lengths d_bs = 0.317, d_se = 0.45, d_ew = 0.48, d_wt = 0.07 m, and the
    Table 2 joint limits assumed in that paper's simulations (degrees):
    +-90, +-45, +-120, [0, 135], +-90, +-90, +-120.
    """
    return srs_chain(
        0.317, 0.45, 0.48, 0.07,
        lower_deg=[-90, -45, -120, 0, -90, -90, -120],
        upper_deg=[90, 45, 120, 135, 90, 90, 120],
        name="pa10-7c",
        source="paper 000 Table 1, section 6 lengths, Table 2 limits",
    )


#: Joint ranges of the KUKA LBR iiwa 7 R800 and 14 R820 (degrees, symmetric): KUKA's data sheet and URDFs.
_IIWA_RANGE_DEG = [170, 120, 170, 120, 170, 120, 175]
#: Joint speed limits of the LBR iiwa 14 R820 and 7 R800 (degrees per second): KUKA's data sheet, as KUKA's URDF
#: (kroshu/kuka_robot_descriptions) and lbr-stack's descriptions write them.
_IIWA14_SPEED_DEG = [85, 85, 100, 75, 130, 135, 135]
_IIWA7_SPEED_DEG = [98, 98, 100, 130, 140, 180, 180]
#: KUKA's joint senses on paper 000's Table 1 rows: at the zero pose KUKA's A4 turns about -y of the base,
#: Table 1's joint 4 about +y; every other joint turns the same way.
_KUKA_IIWA_SIGNS = [1, 1, 1, -1, 1, 1, 1]


def kuka_iiwa14() -> SerialChain:
    """KUKA LBR iiwa 14 R820 in KUKA's joint conventions.

    Source: KUKA's URDF of the arm (kroshu/kuka_robot_descriptions,
    ``kuka_lbr_iiwa_support/urdf/lbr_iiwa14_r820_macro.xacro``; the same frames
    as ``examples/iiwa14.urdf``) and the data sheet "LBR iiwa 7 R800, LBR iiwa
    14 R820" (KUKA Roboter): shoulder 0.36 m above the base (0.1575 +
    0.2025), upper arm 0.42 m (0.2045 + 0.2155), forearm 0.40 m (0.1845 +
    0.2155), flange 0.126 m beyond the wrist (0.081 to link 7, 0.045 to the
    flange: the data sheet's flange height of 1306 mm at the zero pose; the
    URDF puts its ``flange`` link 0.071 beyond link 7 instead), joint ranges
    +-170, +-120, +-170, +-120, +-170, +-120, +-175 deg, joint speed limits
    85, 85, 100, 75, 130, 135, 135 deg/s (the data sheet's; the same in that
    URDF, ``velocity="${radians(85)}"`` ..., at commit 7766e92, and in
    lbr-stack/lbr_fri_ros2_stack ``lbr_description/urdf/iiwa14/joint_limits.yaml``;
    that package's MoveIt ``config/lbr_iiwa14_r820_joint_limits.yaml`` sets
    6.283 rad/s on every joint, which is not the robot's).

    At ``q = 0`` the arm stands straight up and the flange frame is the base
    frame lifted by 1.306 m; the axes are z, y, z, -y, z, y, z of the base
    (A4 turns about -y).  Written as paper 000's Table 1 rows with joint 4
    reversed (``sign = -1``); :func:`kuka_iiwa14_table1` is the Table 1 form
    itself.
    """
    return _kuka_lbr_iiwa(0.36, 0.42, _IIWA14_SPEED_DEG, "kuka-iiwa14", "KUKA LBR iiwa 14 R820: KUKA's URDF joint "
                          "frames, data-sheet lengths, ranges and speeds")


def kuka_iiwa7() -> SerialChain:
    """KUKA LBR iiwa 7 R800 in KUKA's joint conventions.

    Source: the data sheet "LBR iiwa 7 R800, LBR iiwa 14 R820" (KUKA
    Roboter): shoulder 0.34 m above the base, upper arm and forearm 0.40 m,
    flange 0.126 m beyond the wrist (flange height 1266 mm at the zero pose),
    joint ranges +-170, +-120, +-170, +-120, +-170, +-120, +-175 deg, joint
    speed limits 98, 98, 100, 130, 140, 180, 180 deg/s (the data sheet's, as
    lbr-stack/lbr_fri_ros2_stack writes them, ``lbr_description/urdf/iiwa7/joint_limits.yaml``
    at commit 218d723); joint frames and senses of KUKA's iiwa URDFs
    (kroshu/kuka_robot_descriptions,
    ``kuka_lbr_iiwa_support/urdf/lbriiwa7_macro.xacro``: origins 0.1375 +
    0.2025, 0.1845 + 0.2155, 0.1845 + 0.2155, 0.081; that file narrows the
    ranges to 90 % of the data sheet's and puts 6.283 rad/s on every joint,
    neither of which is used here).  Axes and zero pose as :func:`kuka_iiwa14`.
    """
    return _kuka_lbr_iiwa(0.34, 0.40, _IIWA7_SPEED_DEG, "kuka-iiwa7", "KUKA LBR iiwa 7 R800: KUKA's URDF joint "
                          "frames, data-sheet lengths, ranges and speeds")


def kuka_iiwa14_table1() -> SerialChain:
    """KUKA LBR iiwa 14 R820 in the S-R-S form of paper 000 Table 1.

    Source: as :func:`kuka_iiwa14` (d_bs = 0.36, d_se = 0.42, d_ew = 0.40,
    d_wt = 0.126 m, ranges +-170, +-120, +-170, +-120, +-170, +-120, +-175
    deg, speeds 85, 85, 100, 75, 130, 135, 135 deg/s).  The same arm with
    joint 4 turning the other way from KUKA's: ``q_table1 = q_kuka * (1, 1,
    1, -1, 1, 1, 1)``.  Kept so that results computed in this form keep their
    numbers; send :func:`kuka_iiwa14`'s joint values to a robot.
    """
    return replace(kuka_iiwa14(), sign=np.ones(7), name="kuka-iiwa14-table1",
                   source="KUKA LBR iiwa 14 R820 data sheet, in paper 000 Table 1 form (joint 4 reversed from KUKA's)")


def _kuka_lbr_iiwa(d_bs: float, d_se: float, speed_deg: Sequence[float], name: str, source: str) -> SerialChain:
    """An LBR iiwa (forearm 0.40 m, flange 0.126 m) in KUKA's conventions: Table 1 rows, joint 4 reversed, with the
    joint speed limits ``speed_deg`` (deg/s)."""
    table1 = srs_chain(d_bs, d_se, 0.40, 0.126, lower_deg=[-v for v in _IIWA_RANGE_DEG], upper_deg=_IIWA_RANGE_DEG)
    return replace(table1, sign=np.array(_KUKA_IIWA_SIGNS, dtype=float), name=name, source=source,
                   velocity=np.radians(speed_deg))


def barrett_wam(d3: float = 0.55, d5: float = 0.4, d7: float = 0.06, a: float = 0.045) -> SerialChain:
    """Barrett WAM (7-DOF), standard DH.

    Source: paper 003 (Miyata et al.) Table 1 and section 4: alpha =
    (-pi/2, pi/2, -pi/2, pi/2, -pi/2, pi/2, 0), a = (0, 0, a, -a, 0, 0, 0),
    d = (0, 0, d3, 0, d5, 0, d7) with d3 = 0.55, d5 = 0.4, d7 = 0.06,
    a = 0.045 m.  The paper gives no joint limits, so none are set.
    """
    return SerialChain(
        a=[0.0, 0.0, a, -a, 0.0, 0.0, 0.0],
        alpha=[-HALF_PI, HALF_PI, -HALF_PI, HALF_PI, -HALF_PI, HALF_PI, 0.0],
        d=[0.0, 0.0, d3, 0.0, d5, 0.0, d7],
        convention="dh",
        name="barrett-wam",
        source="paper 003 Table 1 and section 4 lengths",
    )


def barrett_wam7() -> SerialChain:
    """Barrett WAM (7-DOF) in Barrett's own DH frames, lengths and joint ranges.

    Source: Barrett Technology, "WAM Arm User's Manual" (document D1001,
    version AH.00, 2008), Table 5 "7-DOF WAM frame parameters" (standard DH,
    Spong's variant) and Table 6 "Joint Limits":

    ====  =====  =======  ======  ==============================
    i     alpha  a        d       range (rad)
    ====  =====  =======  ======  ==============================
    1     -pi/2  0        0       [-2.6, 2.6]
    2     +pi/2  0        0       [-2.0, 2.0]
    3     -pi/2  0.045    0.55    [-2.8, 2.8]
    4     +pi/2  -0.045   0       [-0.9, 3.1]
    5     -pi/2  0        0.3     [-4.76, 1.24]
    6     +pi/2  0        0       [-1.6, 1.6]
    7     0      0        0.06    [-3.0, 3.0]
    ====  =====  =======  ======  ==============================

    Frame 0 is at the shoulder, where joints 1-3 meet (0.346 m above the
    mounting face); the tool frame is the tool plate.  libbarrett
    (``config/wam7w.conf``) uses the same rows with d7 = 0.0609 m to its tool
    plate.  Paper 003's WAM (:func:`barrett_wam`) has a 0.4 m forearm where
    Barrett's is 0.3 m, so the two are separate models.
    """
    return SerialChain(
        a=[0.0, 0.0, 0.045, -0.045, 0.0, 0.0, 0.0],
        alpha=[-HALF_PI, HALF_PI, -HALF_PI, HALF_PI, -HALF_PI, HALF_PI, 0.0],
        d=[0.0, 0.0, 0.55, 0.0, 0.3, 0.0, 0.06],
        convention="dh",
        lower=[-2.6, -2.0, -2.8, -0.9, -4.76, -1.6, -3.0],
        upper=[2.6, 2.0, 2.8, 3.1, 1.24, 1.6, 3.0],
        name="barrett-wam7",
        source="Barrett WAM Arm User's Manual D1001 AH.00, Table 5 (DH) and Table 6 (joint limits)",
    )


def franka_panda() -> SerialChain:
    """Franka Emika Panda (FER), in Franka's modified DH frames and joint limits.

    Source: Franka Control Interface documentation, "Robot and interface
    specifications" (https://frankaemika.github.io/docs/control_parameters.html):
    modified DH (Craig) and the joint limits q_min, q_max; the same frames and
    limits as Franka's URDF (frankaemika/franka_description,
    ``robots/fer/kinematics.yaml`` and ``robots/fer/joint_limits.yaml``;
    frankaemika/franka_ros, ``franka_description/robots/panda_arm.xacro`` and
    ``robots/panda/joint_limits.yaml``) and ``examples/panda.urdf``:

    ======  ==========  =======  =====  ===================  ===========
    i       alpha_i-1   a_i-1    d_i    range (rad)          max (rad/s)
    ======  ==========  =======  =====  ===================  ===========
    1       0           0        0.333  [-2.8973, 2.8973]    2.175
    2       -pi/2       0        0      [-1.7628, 1.7628]    2.175
    3       +pi/2       0        0.316  [-2.8973, 2.8973]    2.175
    4       +pi/2       0.0825   0      [-3.0718, -0.0698]   2.175
    5       -pi/2       -0.0825  0.384  [-2.8973, 2.8973]    2.61
    6       +pi/2       0        0      [-0.0175, 3.7525]    2.61
    7       +pi/2       0.088    0      [-2.8973, 2.8973]    2.61
    flange  0           0        0.107
    ======  ==========  =======  =====  ===================  ===========

    The speeds are the URDF's velocity limits (``robots/fer/joint_limits.yaml``
    at franka_description commit b299b39), kept as the chain's ``velocity``;
    the acceleration limits 15, 7.5, 10, 12.5, 15, 20, 20 rad/s^2 and jerk
    limits 7500, 3750, 5000, 6250, 7500, 10000, 10000 rad/s^3 are the Panda's
    in the Franka Control Interface documentation ("Limits for Panda"; the
    same in libfranka's ``rate_limiting.h``, ``kMaxJointAcceleration`` and
    ``kMaxJointJerk``, less its 1e-3 margin).
    The tool frame is the flange (``panda_link8``), without
    the hand; Franka's hand frame is the flange turned by -pi/4 about z, and
    its TCP 0.1034 m along the hand's z (as on the FR3, whose
    ``examples/fr3.urdf`` has both).  The arm is of the Franka class: a spherical
    shoulder, an offset elbow, axes 5 and 6 meeting and axis 7 offset 0.088 m
    from axis 6; its pose IK is in closed form at a given q7
    (:mod:`redkin.franka`, docs/franka.md).
    """
    return _franka_arm(
        lower=[-2.8973, -1.7628, -2.8973, -3.0718, -2.8973, -0.0175, -2.8973],
        upper=[2.8973, 1.7628, 2.8973, -0.0698, 2.8973, 3.7525, 2.8973],
        velocity=[2.175, 2.175, 2.175, 2.175, 2.61, 2.61, 2.61],
        acceleration=[15.0, 7.5, 10.0, 12.5, 15.0, 20.0, 20.0],
        jerk=[7500.0, 3750.0, 5000.0, 6250.0, 7500.0, 10000.0, 10000.0],
        name="franka-panda",
        source="Franka Control Interface docs: modified DH table and joint limits (as franka_description, fer)",
    )


def franka_fr3() -> SerialChain:
    """Franka Research 3 (FR3), in Franka's modified DH frames and joint limits.

    Source: Franka's URDF (frankaemika/franka_description, 2025:
    ``robots/fr3/kinematics.yaml``, ``robots/fr3/joint_limits.yaml`` and
    ``robots/common/franka_arm.xacro``; the same frames as ``examples/fr3.urdf``)
    and the FR3 limits of the Franka Control Interface documentation
    (https://frankaemika.github.io/docs/control_parameters.html).  The link
    lengths are the FER's (:func:`franka_panda`); the limits differ:

    ======  ==========  =======  =====  ===================  ===========
    i       alpha_i-1   a_i-1    d_i    range (rad)          max (rad/s)
    ======  ==========  =======  =====  ===================  ===========
    1       0           0        0.333  [-2.7437, 2.7437]    2.62
    2       -pi/2       0        0      [-1.7837, 1.7837]    2.62
    3       +pi/2       0        0.316  [-2.9007, 2.9007]    2.62
    4       +pi/2       0.0825   0      [-3.0421, -0.1518]   2.62
    5       -pi/2       -0.0825  0.384  [-2.8065, 2.8065]    5.26
    6       +pi/2       0        0      [0.5445, 4.5169]     4.18
    7       +pi/2       0.088    0      [-3.0159, 3.0159]    5.26
    flange  0           0        0.107
    ======  ==========  =======  =====  ===================  ===========

    The speeds are the URDF's velocity limits (``robots/fr3/joint_limits.yaml``
    at franka_description commit b299b39), kept as the chain's ``velocity``
    (the FR3's controller further lowers them near the position limits);
    the acceleration limit 10 rad/s^2 and jerk limit 5000 rad/s^3 on every
    joint are the FR3's in the Franka Control Interface documentation
    ("Limits for Franka Research 3"; libfranka's ``rate_limiting.h`` for the
    FR3).
    The older franka_ros package (2024) carried narrower FR3 ranges
    (``franka_description/robots/fr3/joint_limits.yaml``: +-2.3093, +-1.5133,
    ...); these are the current ones.  The tool frame is the flange
    (``fr3_link8``), without the hand; ``examples/fr3.urdf`` adds the hand
    (``fr3_hand``, the flange turned by -pi/4 about z) and its TCP
    (``fr3_hand_tcp``, 0.1034 m along the hand's z).  The arm is of the
    Franka class: a spherical shoulder, an offset elbow, axes 5 and 6 meeting
    and axis 7 offset 0.088 m from axis 6; its pose IK is in closed form at a
    given q7 (:mod:`redkin.franka`, docs/franka.md).
    """
    return _franka_arm(
        lower=[-2.7437, -1.7837, -2.9007, -3.0421, -2.8065, 0.5445, -3.0159],
        upper=[2.7437, 1.7837, 2.9007, -0.1518, 2.8065, 4.5169, 3.0159],
        velocity=[2.62, 2.62, 2.62, 2.62, 5.26, 4.18, 5.26],
        acceleration=[10.0] * 7,
        jerk=[5000.0] * 7,
        name="franka-fr3",
        source="franka_description (2025): robots/fr3 kinematics and joint limits, in Franka's modified DH",
    )


def _franka_arm(lower: Sequence[float], upper: Sequence[float], velocity: Sequence[float],
                acceleration: Sequence[float], jerk: Sequence[float], name: str, source: str) -> SerialChain:
    """Franka's modified DH rows to the flange (the same for the FER and the FR3), with the given limits."""
    return SerialChain(
        a=[0.0, 0.0, 0.0, 0.0825, -0.0825, 0.0, 0.088],
        alpha=[0.0, -HALF_PI, HALF_PI, HALF_PI, -HALF_PI, HALF_PI, HALF_PI],
        d=[0.333, 0.0, 0.316, 0.0, 0.384, 0.0, 0.0],
        convention="mdh",
        lower=lower,
        upper=upper,
        velocity=velocity,
        acceleration=acceleration,
        jerk=jerk,
        tool=_translation_z(0.107),
        name=name,
        source=source,
    )


def kinova_gen3() -> SerialChain:
    """Kinova Gen3 (7-DOF), in Kinova's DH frames with the lengths of Kinova's URDF.

    Source: Kinova's URDF (Kinovarobotics/ros2_kortex,
    ``kortex_description/arms/gen3/7dof/urdf/gen3_macro.xacro``: joint origins,
    axes and limits) written in the classic DH form of the "KINOVA Gen3 Ultra
    lightweight robot User Guide" (base frame turned by pi about x, every twist
    pi/2 but the last, pi; joints 2-7 offset by pi):

    ====  =====  ==============================  ===========  ============
    i     alpha  d                               theta        range (rad)
    ====  =====  ==============================  ===========  ============
    1     pi/2   -(0.15643 + 0.12838)            q1           continuous
    2     pi/2   -(0.005375 + 0.006375)          q2 + pi      [-2.24, 2.24]
    3     pi/2   -(0.21038 + 0.21038)            q3 + pi      continuous
    4     pi/2   -(0.006375 + 0.006375)          q4 + pi      [-2.57, 2.57]
    5     pi/2   -(0.20843 + 0.10593)            q5 + pi      continuous
    6     pi/2   -(0.00017505 + 0.00017505)      q6 + pi      [-2.09, 2.09]
    7     pi     -(0.10593 + 0.061525)           q7 + pi      continuous
    ====  =====  ==============================  ===========  ============

    All ``a = 0``.  The User Guide rounds these lengths to 0.1 mm and puts
    d6 = 0; the URDF's wrist offset of 2 x 0.17505 mm is kept here.  The URDF
    prints pi/2 as 1.5708 and pi as 3.1416 (and CAD residues below 1e-14);
    the right angles are taken exact: the file's literal numbers put the end
    pose up to 1e-5 m and 2.5e-5 rad away (sampled).  The ranges are those the URDF took
    from the User Guide in 2024.  The speed limits are the URDF's
    ``velocity`` (ros2_kortex commit 1fdbef3): 1.3963 rad/s (80 deg/s) on
    joints 1-4 and 1.2218 rad/s (70 deg/s) on joints 5-7; the package's
    ``config/joint_limits.yaml`` gives its controllers 0.8727 rad/s on every
    joint, which is not used.  The tool frame is ``end_effector_link``.  At
    ``q = 0`` the arm stands straight up.  A general chain (joints 1-3 do not
    meet).
    """
    return SerialChain(
        a=np.zeros(7),
        alpha=[HALF_PI] * 6 + [np.pi],
        d=[-(0.15643 + 0.12838), -(0.005375 + 0.006375), -(0.21038 + 0.21038), -(0.006375 + 0.006375),
           -(0.20843 + 0.10593), -(0.00017505 + 0.00017505), -(0.10593 + 0.061525)],
        convention="dh",
        offset=[0.0] + [np.pi] * 6,
        lower=[-np.inf, -2.24, -np.inf, -2.57, -np.inf, -2.09, -np.inf],
        upper=[np.inf, 2.24, np.inf, 2.57, np.inf, 2.09, np.inf],
        velocity=[1.3963] * 4 + [1.2218] * 3,
        base=np.diag([1.0, -1.0, -1.0, 1.0]),  # Rx(pi)
        name="kinova-gen3",
        source="Kinova Gen3 7-DOF: kortex_description URDF lengths and limits in the User Guide's DH form",
    )


def ufactory_xarm7() -> SerialChain:
    """UFactory xArm7, in UFactory's modified DH frames and joint limits.

    Source: UFactory, "Kinematic and Dynamic Parameters of UFACTORY xArm
    Series" (xArm7 modified D-H parameters), and UFactory's URDF
    (xArm-Developer/xarm_ros2, ``xarm_description/urdf/xarm7/xarm7.urdf.xacro``:
    the same frames, and its default joint limits):

    ====  ==========  ======  ======  =====================
    i     alpha_i-1   a_i-1   d_i     range (rad)
    ====  ==========  ======  ======  =====================
    1     0           0       0.267   [-2 pi, 2 pi]
    2     -pi/2       0       0       [-2.059, 2.0944]
    3     +pi/2       0       0.293   [-2 pi, 2 pi]
    4     +pi/2       0.0525  0       [-0.19198, 3.927]
    5     +pi/2       0.0775  0.3425  [-2 pi, 2 pi]
    6     +pi/2       0       0       [-1.69297, pi]
    7     -pi/2       0.076   0.097   [-2 pi, 2 pi]
    ====  ==========  ======  ======  =====================

    The URDF gives every joint a speed limit of 3.14 rad/s (``velocity="3.14"``
    in ``xarm7.urdf.xacro``, xarm_ros2 commit 3654ba7), kept as the chain's
    ``velocity``; the MoveIt config's 2.14 rad/s (``xarm_moveit_config/config/xarm7/joint_limits.yaml``)
    is not used.
    The +-2 pi joints (+-360 deg on the data sheet) span two full turns: every
    angle lies in range twice, and the stops at +-2 pi still hold
    (:meth:`SerialChain.within_limits`; closed forms return the angle nearest
    the middle of the range or a seed, :meth:`SerialChain.nearest_in_range`).
    The URDF prints pi/2 as 1.5708; the right angles are taken exact (the
    literal numbers put the flange up to 6e-6 m and 2e-5 rad away, sampled).  The
    tool frame is the flange (``link_eef``).  Of the Franka class, as the
    Panda: a spherical shoulder, an offset elbow, axes 5 and 6 meeting and
    axis 7 offset 0.076 m from axis 6, so it has the closed form at a given
    q7 (:mod:`redkin.franka`, docs/franka.md).
    """
    two_pi = 2.0 * np.pi
    return SerialChain(
        a=[0.0, 0.0, 0.0, 0.0525, 0.0775, 0.0, 0.076],
        alpha=[0.0, -HALF_PI, HALF_PI, HALF_PI, HALF_PI, HALF_PI, -HALF_PI],
        d=[0.267, 0.0, 0.293, 0.0, 0.3425, 0.0, 0.097],
        convention="mdh",
        lower=[-two_pi, -2.059, -two_pi, -0.19198, -two_pi, -1.69297, -two_pi],
        upper=[two_pi, 2.0944, two_pi, 3.927, two_pi, np.pi, two_pi],
        velocity=[3.14] * 7,
        name="ufactory-xarm7",
        source="UFactory xArm7 modified DH parameters and xarm_description URDF limits",
    )


def _translation_z(length: float) -> np.ndarray:
    """The transform ``Tz(length)``."""
    pose = np.eye(4)
    pose[2, 3] = length
    return pose


#: Thesis 001 section 5.1 link lengths in metres.
HUMANOID_LENGTHS = {"L0": 0.3975, "L1": 0.355, "L2": 0.150, "L3": 0.315}


def humanoid_right_arm(tool_length: float = 0.0) -> SerialChain:
    """Right arm of the 8-DOF dual-arm humanoid of thesis 001 (torso joint + 7-DOF arm).

    Source: thesis 001 (Hamada) Table 2.1, modified DH [001 eq. 2.1]:

    ====  ==========  =======  =====  ================
    i     alpha_i-1   a_i-1    d_i    theta_i
    ====  ==========  =======  =====  ================
    1     -pi/2       0        0      -pi/2 + theta_1
    2     -pi/2       0        L0     -pi/2 + theta_2
    3     -pi/2       0        0      -pi/2 - theta_3
    4     -pi/2       0        L1     -pi/2 + theta_4
    5     +pi/2       0        0      +pi/2 + theta_5
    6     +pi/2       L2       L3     -pi/2 - theta_6
    7     +pi/2       0        0      +theta_7
    8     -pi/2       0        0      -theta_8
    E     0           0        L4     0
    ====  ==========  =======  =====  ================

    with L0 = 397.5, L1 = 355, L2 = 150, L3 = 315 mm (section 5.1) and
    L4 = ``tool_length`` (metres; the thesis leaves it open).  Joint limits of
    section 5.1 for joints 1-5 (degrees): [-90, 90], [-85, 175], [-5, 185],
    [-150, 150], [-80, 80]; the thesis gives none for joints 6-8.  The base
    frame has the torso axis along +y; the right shoulder is at
    ``(L0, 0, 0)`` when theta_1 = 0.
    """
    lengths = HUMANOID_LENGTHS
    inf = np.inf
    return SerialChain(
        a=[0.0, 0.0, 0.0, 0.0, 0.0, lengths["L2"], 0.0, 0.0],
        alpha=[-HALF_PI, -HALF_PI, -HALF_PI, -HALF_PI, HALF_PI, HALF_PI, HALF_PI, -HALF_PI],
        d=[0.0, lengths["L0"], 0.0, lengths["L1"], 0.0, lengths["L3"], 0.0, 0.0],
        convention="mdh",
        offset=[-HALF_PI, -HALF_PI, -HALF_PI, -HALF_PI, HALF_PI, -HALF_PI, 0.0, 0.0],
        sign=[1, 1, -1, 1, 1, -1, 1, -1],
        lower=np.radians([-90, -85, -5, -150, -80, -inf, -inf, -inf]),
        upper=np.radians([90, 175, 185, 150, 80, inf, inf, inf]),
        tool=_translation_z(check_nonnegative(tool_length, "tool_length")),  # a length: -1 m was accepted
        name="humanoid-right",
        source="thesis 001 Table 2.1 (modified DH), section 5.1 lengths and limits",
    )


def humanoid_left_arm(tool_length: float = 0.0) -> SerialChain:
    """Left arm of the thesis 001 humanoid: the right arm mirrored in the sagittal plane.

    The thesis models only the right arm.  The left arm here is its mirror
    image in the plane x = 0 (which contains the torso axis).  Arm joints
    2-8 turn in the mirrored sense, so equal arm joints give mirror postures;
    the torso joint is shared and keeps its world sense, so the left arm at
    ``(theta_1, q_2, ..., q_8)`` is the mirror image of the right arm at
    ``(-theta_1, q_2, ..., q_8)``.  Its shoulder is at ``(-L0, 0, 0)`` when
    theta_1 = 0.
    """
    left = humanoid_right_arm(tool_length).mirrored(normal=(1.0, 0.0, 0.0), flip_joints=[0])
    return replace(
        left,
        name="humanoid-left",
        source="thesis 001 Table 2.1 mirrored in the plane x = 0 (torso joint shared)",
    )


def planar_arm(links: int = 5, length: float = 0.4) -> SerialChain:
    """A planar arm of ``links`` revolute joints with equal link ``length`` (metres).

    Source: paper 004 (Tsuji et al.) section 4 uses 5 links of 40 cm.  Joints
    turn about the base z axis; the arm lies along +x at q = 0; no limits.
    """
    if int(links) != links or links < 1:
        raise RedkinError(f"links must be a positive integer, got {links!r}")
    if not np.isfinite(length) or length <= 0:
        raise RedkinError(f"length must be a positive number of metres, got {length!r}")
    n = int(links)
    return SerialChain(
        a=np.full(n, float(length)),
        alpha=np.zeros(n),
        d=np.zeros(n),
        convention="dh",
        name=f"planar-{n}",
        source="paper 004 section 4 (5 links of 0.4 m)",
    )


MODELS: dict[str, Callable[[], SerialChain]] = {
    "pa10-7c": pa10_7c,
    "kuka-iiwa14": kuka_iiwa14,
    "barrett-wam": barrett_wam,
    "humanoid-right": humanoid_right_arm,
    "humanoid-left": humanoid_left_arm,
    "planar-5": planar_arm,
    "kuka-iiwa14-table1": kuka_iiwa14_table1,
    "kuka-iiwa7": kuka_iiwa7,
    "barrett-wam7": barrett_wam7,
    "franka-panda": franka_panda,
    "franka-fr3": franka_fr3,
    "kinova-gen3": kinova_gen3,
    "ufactory-xarm7": ufactory_xarm7,
}


def robot_names() -> list[str]:
    """Names accepted by :func:`get_robot` (besides robot file paths)."""
    return list(MODELS)


def get_robot(name_or_path: str | Path, base: str | None = None, tip: str | None = None, *,
              xacro_args: Mapping[str, str | int | float | bool] | None = None,
              package_paths: str | os.PathLike | Iterable[str | os.PathLike] = ()) -> SerialChain:
    """A model by name (see :func:`robot_names`), a chain read from a robot file, or one read from a URDF.

    Parameters
    ----------
    name_or_path : str or Path
        A model name, a ``.toml``/``.json`` robot file, a ``.urdf`` or ``.xacro`` file, or an MJCF ``.xml`` file.
        A file that does not exist, written ``NAME`` or ``examples/NAME``, reads redkin's shipped example ``NAME``
        if there is one (``examples/iiwa14.urdf`` from any folder; see :mod:`redkin.examples`).
    base, tip : str, optional
        For a URDF, the links the chain runs between (see :func:`redkin.urdf.load_urdf`); for an MJCF file, the
        bodies (the tip may be a site) (see :func:`redkin.mjcf.load_mjcf`).
    xacro_args : mapping of str to str, optional
        For a ``.xacro``, its arguments, ``NAME -> VALUE`` (see :func:`redkin.urdf.load_urdf`).
    package_paths : path or iterable of paths, optional
        For a ``.xacro``, folders searched first for the ROS packages of its ``$(find PKG)``.

    Raises
    ------
    ValueError
        For an unknown name, a missing file or a malformed file, ``base``/``tip`` given for anything but a URDF or
        an MJCF file, and ``xacro_args``/``package_paths`` given for anything but a ``.xacro``.
    """
    key = str(name_or_path)
    path = Path(key)
    if path.suffix.lower() in (".urdf", ".xacro"):
        from redkin.urdf import load_urdf

        return load_urdf(path, base, tip, xacro_args=xacro_args, package_paths=package_paths)
    places = [package_paths] if isinstance(package_paths, (str, os.PathLike)) else list(package_paths)
    if xacro_args or places:
        raise RedkinError(f"xacro arguments and package paths apply to .xacro files only, not to {key!r}")
    if path.suffix.lower() in (".xml", ".mjcf"):
        from redkin.mjcf import load_mjcf

        return load_mjcf(path, base, tip)
    if base is not None or tip is not None:
        raise RedkinError(f"base and tip links apply to URDF and MJCF files only, not to {key!r}")
    if key.lower() in MODELS:
        return MODELS[key.lower()]()
    if path.suffix.lower() in (".toml", ".json"):
        from redkin.robot_file import load_robot

        return load_robot(path)
    from redkin.examples import names

    shipped = [name for name in names() if name.split(".")[0] == key.lower()]  # "sawyer" for sawyer.urdf
    hint = f" (redkin ships the example {' and '.join(shipped)})" if shipped else ""
    raise RedkinError(
        f"unknown robot {key!r}{hint}: expected one of {', '.join(MODELS)}, a .toml/.json robot file, a .urdf/.xacro "
        "file or an MJCF .xml file"
    )
