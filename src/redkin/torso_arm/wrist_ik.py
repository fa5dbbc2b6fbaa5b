"""Wrist inverse kinematics of joints 6-8 (chapter 4, thesis 001, re-derived from Table 2.1).

[001 eqs. 4.6, 4.9] of the thesis do not follow from Table 2.1 (they contain no
theta_8).  Multiplying rows 6-8 of Table 2.1 gives the rotation from frame 5
to frame 8 (``c6 = cos theta_6`` etc., joint variables):

    R58 = [[-s6 c7 c8 - c6 s8,  -s6 c7 s8 + c6 c8,  s6 s7],
           [-s7 c8,             -s7 s8,            -c7   ],
           [ s6 s8 - c6 c7 c8,  -s6 c8 - c6 c7 s8,  c6 s7]]

hence ``cos theta_7 = -R58[1,2]``, ``theta_6 = atan2(s R58[0,2], s R58[2,2])``,
``theta_8 = atan2(-s R58[1,1], -s R58[1,0])`` with ``s = sgn(sin theta_7)``
(two branches).  At ``sin theta_7 = 0`` (axes 6 and 8 aligned: the wrist
singularity) only ``theta_6 + theta_8`` (``theta_7 = 0``) or ``theta_6 -
theta_8`` (``theta_7 = pi``) is defined; theta_8 = 0 is returned and the
singularity is reported.
"""

from __future__ import annotations

import numpy as np

from redkin.torso_arm.branches import WRIST_BRANCHES, wrap_angle

#: ``|sin theta_7|`` below this counts as the wrist singularity.
_WRIST_SINGULAR_TOLERANCE = 1e-9


def wrist_ik(r58: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Joints 6-8 of both wrist branches from the frame-5-to-frame-8 rotation ([001 eqs. 4.7, 4.10, 4.11],
    re-derived from the ``R58`` of the module docstring, which replaces [001 eqs. 4.6, 4.9]).

    Parameters
    ----------
    r58 : numpy.ndarray, shape (..., 3, 3)
        ``R5^T R8`` (trusted: the public entry point validates it).

    Returns
    -------
    q : numpy.ndarray, shape (..., 2, 3)
        Branches of :data:`WRIST_BRANCHES` (``sgn sin theta_7`` = +1, -1), angles in ``(-pi, pi]``.
    singular : numpy.ndarray of bool, shape (...)
        The wrist singularity ``sin theta_7 = 0``; both branches then coincide.
    """
    sin7 = np.hypot(r58[..., 0, 2], r58[..., 2, 2])
    singular = sin7 < _WRIST_SINGULAR_TOLERANCE
    cos7 = -r58[..., 1, 2]
    out = []
    for s in WRIST_BRANCHES:
        theta7 = np.arctan2(s * sin7, cos7)
        theta6 = np.arctan2(s * r58[..., 0, 2], s * r58[..., 2, 2])
        theta8 = np.arctan2(-s * r58[..., 1, 1], -s * r58[..., 1, 0])
        # singular, c7 = +-1: R58[0,0] = -c7 sin(t6 + c7 t8), R58[0,1] = cos(t6 + c7 t8); take theta_8 = 0
        locked6 = np.arctan2(-np.sign(cos7) * r58[..., 0, 0], r58[..., 0, 1])
        theta7 = np.where(singular, np.where(cos7 > 0, 0.0, np.pi), theta7)
        theta6 = np.where(singular, locked6, theta6)
        theta8 = np.where(singular, 0.0, theta8)
        out.append(np.stack([theta6, theta7, theta8], axis=-1))
    return wrap_angle(np.stack(out, axis=-2)), singular
