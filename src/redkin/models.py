"""Named robot models, each with the source of its numbers.

Every model is a function returning a :class:`~redkin.chain.SerialChain`
(SI units, radians).  :func:`get_robot` resolves a model name or a robot
file path; :func:`robot_names` lists the names.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Callable

import numpy as np

from redkin.chain import SerialChain

HALF_PI = np.pi / 2.0


def srs_chain(
    d_bs: float,
    d_se: float,
    d_ew: float,
    d_wt: float,
    lower_deg: list[float] | None = None,
    upper_deg: list[float] | None = None,
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


def kuka_iiwa14() -> SerialChain:
    """KUKA LBR iiwa 14 R820 in the S-R-S form of paper 000 Table 1.

    Source: manufacturer's data sheet lengths d_bs = 0.36, d_se = 0.42,
    d_ew = 0.40, d_wt = 0.126 m and limits +-170, +-120, +-170, +-120, +-170,
    +-120, +-175 deg.  Joint senses follow Table 1, which may differ from the
    controller's own sign convention on some joints.
    """
    return srs_chain(
        0.36, 0.42, 0.40, 0.126,
        lower_deg=[-170, -120, -170, -120, -170, -120, -175],
        upper_deg=[170, 120, 170, 120, 170, 120, 175],
        name="kuka-iiwa14",
        source="KUKA LBR iiwa 14 R820 data sheet, in paper 000 Table 1 form",
    )


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


#: Thesis 001 section 5.1 link lengths in metres.
HUMANOID_LENGTHS = {"L0": 0.3975, "L1": 0.355, "L2": 0.150, "L3": 0.315}


def humanoid_right_arm(tool_length: float = 0.0) -> SerialChain:
    """Right arm of the 8-DOF dual-arm humanoid of thesis 001 (torso joint + 7-DOF arm).

    Source: thesis 001 (Hamada) Table 2.1, modified DH (eq. 2.1):

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
    tool = np.eye(4)
    tool[2, 3] = float(tool_length)
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
        tool=tool,
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
        raise ValueError(f"links must be a positive integer, got {links!r}")
    if not np.isfinite(length) or length <= 0:
        raise ValueError(f"length must be a positive number of metres, got {length!r}")
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
}


def robot_names() -> list[str]:
    """Names accepted by :func:`get_robot` (besides robot file paths)."""
    return list(MODELS)


def get_robot(name_or_path: str | Path, base: str | None = None, tip: str | None = None) -> SerialChain:
    """A model by name (see :func:`robot_names`), a chain read from a robot file, or one read from a URDF.

    Parameters
    ----------
    name_or_path : str or Path
        A model name, a ``.toml``/``.json`` robot file or a ``.urdf`` file.
    base, tip : str, optional
        For a URDF, the links the chain runs between (see :func:`redkin.urdf.load_urdf`).

    Raises
    ------
    ValueError
        For an unknown name, a missing file or a malformed file, or ``base``/``tip`` given for anything but a URDF.
    """
    key = str(name_or_path)
    path = Path(key)
    if path.suffix.lower() == ".urdf":
        from redkin.urdf import load_urdf

        return load_urdf(path, base, tip)
    if base is not None or tip is not None:
        raise ValueError(f"base and tip links apply to URDF files only, not to {key!r}")
    if key.lower() in MODELS:
        return MODELS[key.lower()]()
    if path.suffix.lower() in (".toml", ".json"):
        from redkin.robot_file import load_robot

        return load_robot(path)
    raise ValueError(
        f"unknown robot {key!r}: expected one of {', '.join(MODELS)}, a .toml/.json robot file or a .urdf file"
    )
