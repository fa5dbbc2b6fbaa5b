"""Compiled kernels of the Franka class: the closed form at a given q7 and the limit polynomials in q7.

Equations [F1]-[F9] are derived in docs/franka.md; the arm is the DH form of
:mod:`redkin.franka.geometry` (twists of paper 000 Table 1, ``a = (0, 0, a_3,
a_4, 0, a_6, 0)``, ``d = (d_1, 0, d_3, 0, d_5, d_6, 0)``), read from the
table :attr:`~redkin.franka.geometry.FrankaGeometry.kernel_arm`.

The same functions serve two purposes.  With real numbers they solve the
arm (:func:`solve`).  With complex numbers they evaluate, at a sample q7,
the conjugate solutions that the square roots of [F3] and [F5] give when
their arguments are negative: the product over the conjugates of a limit
function is then a trigonometric polynomial in q7 ([F8]), whose roots
(:func:`limit_roots`) are every q7 at which a joint reaches a limit on some
branch.  Quantities are scaled (``lambda`` below) so that every factor is a
polynomial, without divisions.
"""

from __future__ import annotations

from math import atan2, cos, sin

import numpy as np

from redkin import _array_copy
from redkin._compiled import kernel
from redkin._pose_kernels import BAD_POSE, OK, pose_defect
from redkin.franka.geometry import (
    A3,
    A4,
    A6,
    AMPLITUDE,
    D1,
    D3,
    D5,
    D6,
    MEAN,
    PHASE,
    TABLE_BRANCHES,
    TABLE_ENDS,
    TABLE_JOINTS,
    TABLE_SIZE,
)
from redkin.srs._ik_kernels import MEMBERSHIP_TOLERANCE, chain_values, in_limits

#: Length of the work vector of :func:`solve_q7`.
WORK = 24
#: How far past +-1 the cosine of [F3] or the sine of [F4] may be rounded back (a stretched elbow, a wrist at the
#: edge of its reach): relative to the lengths, 1e-12 is rounding, not a miss.
_REACH_TOLERANCE = 1e-12
#: Degree in q7 of the limit polynomial of each joint (1..6) and of the existence polynomials ([F8]); the
#: tests check them against a higher-degree fit on random arms and poses.  Half of it for the functions that are
#: squares on an arm without elbow offsets (:func:`halved`, :func:`degree_of`).
DEGREES = np.array([8, 8, 8, 8, 8, 8, 2, 2, 4, 4, 4, 4, 2, 4])
#: Number of limit functions: two limits of joints 1-6, then the existence of the elbow and of the wrist.
FUNCTIONS = 14
#: Length of :func:`limit_factors`' ``extra``: the divisor of [F8], the elbow's and the wrist's existence [F9],
#: ``Sigma`` and ``|V_xy|^2``.
EXTRA = 5
#: Samples of q7 of each limit function: enough for the largest degree (``2 D + 1``), and a few more.
SAMPLES = 20
#: How far from the unit circle a root ``z = exp(i theta_7)`` of a limit polynomial may lie and still be taken as
#: a candidate q7: a double root (a joint touching its limit) moves off the circle by about the square root of the
#: rounding, a triple one by its cube root, and the eigenvalues of a cluster of roots lie up to 3.5e-3 off it (five
#: within 0.1 rad, a fresh draw).  A candidate that is no real crossing only splits an interval in two.
_CIRCLE_TOLERANCE = 1e-2
#: The longest Newton step of :func:`polished_angle` [rad], and how many it takes at most.
_NEWTON_STEP = 1e-2
_NEWTON_STEPS = 12
#: Cells :func:`isolated_roots` may visit before it hands a polynomial to the eigenvalue route, and the half width
#: below which a cell that may hold a root is taken as one (two roots closer than this are one candidate).
_CELL_BUDGET = 2000
_SMALLEST_CELL = 1e-9
#: The rounding of a value of a trigonometric polynomial, relative to the largest it can take (a few units of the
#: last place of its terms): :func:`monotone_root` stops there (as :func:`isolated_roots` gives it).
_VALUE_ROUNDING = 1e-15
#: Values of a limit polynomial this small, relative to the largest it can take, count as zero: a double root
#: (on arms whose elbow has no offsets the elbow's two roots give squared factors) rounds to a near miss.
_NEAR_ZERO = 1e-12
#: The rounding of a level polynomial's coefficients relative to the size of the terms they sum
#: (:func:`level_polynomial`'s ``terms``, about 100 units of the last place): values below it count as zero too.
#: Where the terms cancel, a double root is lifted off zero by their rounding, not by the polynomial's: on arms
#: without elbow offsets the limit functions of joints 1-3, 5 and 6 are squares and their terms cancel 1e4-fold,
#: so every crossing of those joints is a double root lifted by up to 1e-11 of the polynomial's size.
_TERM_ROUNDING = 1e-14
#: How close to a limit a real branch's joint must be at a polynomial's root to be polished on (radians of the
#: joint, and of q7 for the polish's reach).
_POLISH_REACH = 1e-4
#: A secant step this small [rad] ends :func:`secant_crossing`.
_SETTLED_STEP = 1e-9
#: Half width of the bracket about a breakpoint in which an arc's end is first sought (:func:`crossing`).
_ROOT_BRACKET = 1e-12
#: How far outside an interval a root of a level polynomial still counts as in it (:func:`levels_crossed`): above
#: the roots' error from the polynomial's rounded coefficients [rad].
LEVEL_SLACK = 1e-9
#: ``exp(-i k 2 pi j / SAMPLES)`` for ``k = 0 .. 16``: the discrete Fourier transform of the samples.
_TWIDDLES = np.exp(-2j * np.pi * np.outer(np.arange(9), np.arange(SAMPLES)) / SAMPLES)
#: A sample grid on which a divisor of [F8] comes this close to zero (relative to its largest sample) is shifted by
#: half a step, so that the division stays well conditioned.
_SMALL_DIVISOR = 1e-6


@kernel
def halved(arm, f):
    """Whether limit function ``f`` (:data:`DEGREES`' order) is taken over the conjugate solutions of one elbow
    root only: on an arm without elbow offsets (``a_3 = a_4 = 0``) the other root, ``-theta_4`` [F3], gives the same
    ``theta_1``, ``theta_2`` and ``theta_6``, and ``theta_3``, ``theta_5`` plus ``pi`` (each factor of [F8] times
    +-1), and the same wrist existence [F9]: the product over all four is the square of the product over two, whose
    double roots rounding lifts off zero or splits.  Joint 4 (``+-theta_4``) and the elbow's existence are not."""
    return arm[A3] == 0.0 and arm[A4] == 0.0 and f != 6 and f != 7 and f != 12


@kernel
def degree_of(arm, f):
    """The degree in q7 of limit function ``f`` on this arm: :data:`DEGREES`, or half of it where :func:`halved`."""
    return DEGREES[f] // 2 if halved(arm, f) else DEGREES[f]


@kernel
def wrist_and_frame_six(t07, theta7, arm):
    """Frame 6's axes ``x6, y6, z6`` and the wrist point W (3-tuples) at ``theta_7`` [F1].

    ``R_06 = R_07 Rz(-theta_7)``; the origin of frame 6 is that of frame 7,
    and W lies ``-a_6`` along ``x_6`` and ``-d_6`` along ``y_6`` from it.
    """
    c, s = cos(theta7), sin(theta7)
    x6 = (c * t07[0, 0] - s * t07[0, 1], c * t07[1, 0] - s * t07[1, 1], c * t07[2, 0] - s * t07[2, 1])
    y6 = (s * t07[0, 0] + c * t07[0, 1], s * t07[1, 0] + c * t07[1, 1], s * t07[2, 0] + c * t07[2, 1])
    z6 = (t07[0, 2], t07[1, 2], t07[2, 2])
    w = (t07[0, 3] - arm[A6] * x6[0] - arm[D6] * y6[0], t07[1, 3] - arm[A6] * x6[1] - arm[D6] * y6[1],
         t07[2, 3] - arm[A6] * x6[2] - arm[D6] * y6[2])
    return x6, y6, z6, w


@kernel
def elbow_cosine(w, arm):
    """``cos(theta_4 - phi) = (|W - S|^2 - C) / R`` [F2], with the shoulder ``S = (0, 0, d_1)``."""
    distance2 = w[0] * w[0] + w[1] * w[1] + (w[2] - arm[D1]) * (w[2] - arm[D1])
    return (distance2 - arm[MEAN]) / arm[AMPLITUDE]


@kernel
def elbow_trig(kappa, root, arm):
    """``cos theta_4, sin theta_4`` from ``cos(theta_4 - phi) = kappa`` and ``sin(theta_4 - phi) = root`` [F3]."""
    cp, sp = cos(arm[PHASE]), sin(arm[PHASE])
    return kappa * cp - root * sp, root * cp + kappa * sp


@kernel
def shoulder_in_frame_four(c4, s4, arm):
    """``S_4x, S_4z``: the shoulder point in frame 4 (its y component is ``-d_4 = 0``) [F4]."""
    return -arm[A3] * c4 + arm[D3] * s4 - arm[A4], -(arm[A3] * s4 + arm[D3] * c4)


@kernel
def shoulder_seen_from_six(x6, y6, z6, t07, arm):
    """``V = Rx(alpha_6) R_06^T (S - O_6) + (a_6, 0, d_6)``, ``O_6`` the origin of frames 6 and 7: the shoulder
    point as frame 5 sees it once turned by ``theta_6`` (``V = Rz(-theta_6) S_5``) [F5]."""
    rx, ry, rz = -t07[0, 3], -t07[1, 3], arm[D1] - t07[2, 3]
    sx = x6[0] * rx + x6[1] * ry + x6[2] * rz
    sy = y6[0] * rx + y6[1] * ry + y6[2] * rz
    sz = z6[0] * rx + z6[1] * ry + z6[2] * rz
    return sx + arm[A6], -sz, sy + arm[D6]


@kernel
def wrist_six_trig(c5, s5, scale5, s4x, s4z, vx, vy, arm):
    """``(cos theta_6, sin theta_6)`` times ``lambda_6`` from ``V_xy = Rz(-theta_6) S_5xy`` [F6], where
    ``S_5 = (c_5 S_4x, d_5 - S_4z, -s_5 S_4x)`` and ``c_5, s_5`` are scaled by ``scale5`` (``lambda_6 = scale5
    |V_xy|^2``)."""
    px, py = c5 * s4x, (arm[D5] - s4z) * scale5
    return px * vx + py * vy, py * vx - px * vy


@kernel
def link_rotation(c, s, scale, twist_sign, out):
    """``scale * Rz(theta) Rx(alpha)`` with ``cos, sin theta = c / scale, s / scale`` and ``sin alpha = twist_sign``
    (``cos alpha = 0``), into ``out`` (3, 3)."""
    out[0, 0], out[0, 1], out[0, 2] = c, 0.0, twist_sign * s
    out[1, 0], out[1, 1], out[1, 2] = s, 0.0, -twist_sign * c
    out[2, 0], out[2, 1], out[2, 2] = 0.0, twist_sign * scale, 0.0


@kernel
def shoulder_matrix(x6, y6, z6, r34, r45, r56, out):
    """``M = R_06 (R_34 R_45 R_56)^T Rx(-alpha_3) = Rz(theta_1) Ry(theta_2) Rz(theta_3)`` [F7], into ``out`` (3, 3)
    (scaled by the product of the scales of the three link rotations).  ``r34`` is overwritten with ``R_36``."""
    for i in range(3):  # R_36 row by row, in place of R_34's row (no temporary arrays)
        a0 = r34[i, 0] * r45[0, 0] + r34[i, 1] * r45[1, 0] + r34[i, 2] * r45[2, 0]
        a1 = r34[i, 0] * r45[0, 1] + r34[i, 1] * r45[1, 1] + r34[i, 2] * r45[2, 1]
        a2 = r34[i, 0] * r45[0, 2] + r34[i, 1] * r45[1, 2] + r34[i, 2] * r45[2, 2]
        for j in range(3):
            r34[i, j] = a0 * r56[0, j] + a1 * r56[1, j] + a2 * r56[2, j]
    for i in range(3):
        for j in range(3):  # (R_06 R_36^T)[i, j]
            out[i, j] = x6[i] * r34[j, 0] + y6[i] * r34[j, 1] + z6[i] * r34[j, 2]
    # times Rx(-alpha_3) with alpha_3 = -pi/2: columns (x, y, z) -> (x, z, -y)
    for i in range(3):
        column1, column2 = out[i, 1], out[i, 2]
        out[i, 1], out[i, 2] = column2, -column1


@kernel
def shoulder_angles(m, sigma):
    """``theta_1, theta_2, theta_3`` of ``M = Rz(theta_1) Ry(theta_2) Rz(theta_3)`` with ``sign(sin theta_2) =
    sigma`` [F7]; ``theta_2`` and ``theta_3`` are read after turning back by ``theta_1``, so that FK holds also at
    ``theta_2 = 0`` (where ``theta_1`` is arbitrary)."""
    theta1 = atan2(sigma * m[1, 2], sigma * m[0, 2])
    c1, s1 = cos(theta1), sin(theta1)
    theta2 = atan2(c1 * m[0, 2] + s1 * m[1, 2], m[2, 2])
    theta3 = atan2(-s1 * m[0, 0] + c1 * m[1, 0], -s1 * m[0, 1] + c1 * m[1, 1])
    return theta1, theta2, theta3


@kernel
def elbow_excess(kappa):
    """How far ``|kappa|`` [F2] lies beyond what [F3] admits (with the rounding slack :data:`_REACH_TOLERANCE`):
    positive exactly where the elbow cannot span ``|W - S|``."""
    return abs(kappa) - (1.0 + _REACH_TOLERANCE)


@kernel
def elbow_of(kappa, sign, arm):
    """The elbow root of ``sign`` [F3] (``kappa`` rounded back into ``[-1, 1]``): ``cos theta_4, sin theta_4`` and
    the shoulder in frame four ``S_4x, S_4z`` [F4]."""
    kappa_b = min(1.0, max(-1.0, kappa))
    c4, s4 = elbow_trig(kappa_b, sign * np.sqrt(1.0 - kappa_b * kappa_b), arm)
    s4x, s4z = shoulder_in_frame_four(c4, s4, arm)
    return c4, s4, s4x, s4z


@kernel
def wrist_excess(vz, s4x, arm):
    """How far ``|V_z|`` lies beyond ``|S_4x|`` in [F5] ``-S_4x sin theta_5 = V_z`` (with the rounding slack):
    positive exactly where the wrist cannot turn S onto ``V``."""
    return abs(vz) - (abs(s4x) * (1.0 + _REACH_TOLERANCE) + _REACH_TOLERANCE * arm[D5])


@kernel
def solve_q7(t07, q7, arm, branches, joints, q, exists, scratch, work):
    """Every requested branch at one value ``q7`` of the chain's joint 7 [F1]-[F7]: joint values into ``q`` (B, 7),
    ``exists`` (B,).

    ``branches`` (B, 3) holds the signs (shoulder, elbow, wrist) in the
    solver's senses; ``joints`` maps DH angles to the chain's values
    (:func:`redkin.srs._ik_kernels.chain_values`), except q7, which is
    returned as given, to the last bit (``theta_7 = q7 + offset``, here
    alone: so every caller evaluates a branch at ``q7`` alike, and a q7 at
    the end of a feasible arc, where a branch's existence turns on rounding,
    is one where it exists); ``scratch`` (8, 3, 3) and ``work`` (:data:`WORK`,) are
    work space (no allocation per call).  The elbow and wrist of each
    pair of signs (and the shoulder's matrix ``M``) are computed once and
    shared by its two shoulder branches.  A branch that does not exist (the
    elbow cannot span ``|W - S|``, or the wrist cannot turn S onto ``V``)
    gets zeros and ``exists = False``.
    """
    theta7 = q7 + joints[0, 6]
    x6, y6, z6, w = wrist_and_frame_six(t07, theta7, arm)
    kappa = elbow_cosine(w, arm)
    vx, vy, vz = shoulder_seen_from_six(x6, y6, z6, t07, arm)
    theta = work[:7]  # the DH angles of one branch
    angles = work[7:19].reshape((4, 3))  # theta_4, theta_5, theta_6 of each (elbow, wrist) pair
    state = work[19:23]  # 0: not computed, 1: exists, 2: does not
    state[:] = 0.0
    r34, r45, r56 = scratch[0], scratch[1], scratch[2]
    for b in range(branches.shape[0]):
        exists[b] = False
        for k in range(7):
            q[b, k] = 0.0
        pair = (0 if branches[b, 1] > 0.0 else 2) + (0 if branches[b, 2] > 0.0 else 1)
        if state[pair] == 0.0:
            state[pair] = 2.0
            if elbow_excess(kappa) > 0.0:
                continue
            c4, s4, s4x, s4z = elbow_of(kappa, branches[b, 1], arm)
            if wrist_excess(vz, s4x, arm) > 0.0:
                continue
            s5 = 0.0 if s4x == 0.0 else min(1.0, max(-1.0, -vz / s4x))
            c5 = branches[b, 2] * np.sqrt(1.0 - s5 * s5)
            c6, s6 = wrist_six_trig(c5, s5, 1.0, s4x, s4z, vx, vy, arm)
            theta6 = atan2(s6, c6)
            link_rotation(c4, s4, 1.0, 1.0, r34)
            link_rotation(c5, s5, 1.0, -1.0, r45)
            link_rotation(cos(theta6), sin(theta6), 1.0, 1.0, r56)
            shoulder_matrix(x6, y6, z6, r34, r45, r56, scratch[4 + pair])
            angles[pair, 0], angles[pair, 1], angles[pair, 2] = atan2(s4, c4), atan2(s5, c5), theta6
            state[pair] = 1.0
        if state[pair] != 1.0:
            continue
        theta[0], theta[1], theta[2] = shoulder_angles(scratch[4 + pair], branches[b, 0])
        theta[3], theta[4], theta[5] = angles[pair, 0], angles[pair, 1], angles[pair, 2]
        theta[6] = theta7
        chain_values(theta, joints, q[b])
        q[b, 6] = q7  # the parameter as given (a range wider than 2 pi holds it twice)
        exists[b] = True


@kernel
def limit_factors(t07, theta7, arm, factors, extra, scratch):
    """The parts of the limit functions [F8]-[F9] at one ``theta_7`` that do not depend on the limits, into
    ``factors`` (6, 4, 3) complex and ``extra`` (:data:`EXTRA`,) (:func:`expanded_limits` expands them).

    For joint ``j`` (1-6) and each of the four conjugate solutions (both roots of [F3], both of [F5]; complex where
    a root's argument is negative), ``factors[j - 1, s]`` holds ``(alpha, beta, gamma)`` such that ``alpha cos L +
    beta sin L + gamma`` vanishes exactly where that solution has ``theta_j = L`` or ``L + pi`` (``theta_2 = +-L``
    for joint 2); joint 4 has one per elbow root, then two factors 1.  ``extra``: the divisor ``Sigma^2 |V_xy|^4``
    (``Sigma = prod S_4x`` over the two elbows), then [F9]'s ``1 - kappa^2`` (the elbow's existence) and the wrist's
    existence (over the first elbow root alone where :func:`halved`), then ``Sigma`` and ``|V_xy|^2``.  ``scratch``
    (4, 3, 3) complex.
    """
    x6, y6, z6, w = wrist_and_frame_six(t07, theta7, arm)
    kappa = elbow_cosine(w, arm)
    vx, vy, vz = shoulder_seen_from_six(x6, y6, z6, t07, arm)
    vxy2 = vx * vx + vy * vy
    wrist_existence = 1.0 + 0.0j
    sigma = 1.0 + 0.0j
    root4 = np.sqrt(complex(1.0 - kappa * kappa))
    r34, r45, r56, m = scratch[0], scratch[1], scratch[2], scratch[3]
    for elbow in range(2):
        c4, s4 = elbow_trig(kappa, (1.0 - 2.0 * elbow) * root4, arm)
        s4x, s4z = shoulder_in_frame_four(c4, s4, arm)
        if elbow == 0 or not halved(arm, np.int64(13)):
            wrist_existence *= s4x * s4x - vz * vz
        sigma *= s4x
        factors[3, elbow, 0], factors[3, elbow, 1], factors[3, elbow, 2] = s4, -c4, 0.0
        factors[3, 2 + elbow, 0], factors[3, 2 + elbow, 1], factors[3, 2 + elbow, 2] = 0.0, 0.0, 1.0
        tau = np.sqrt(s4x * s4x - vz * vz)
        for wrist in range(2):
            c5, s5, scale5 = (1.0 - 2.0 * wrist) * tau, -vz + 0.0j, s4x
            c6, s6 = wrist_six_trig(c5, s5, scale5, s4x, s4z, vx, vy, arm)
            scale6 = scale5 * vxy2
            link_rotation(c4, s4, 1.0, 1.0, r34)
            link_rotation(c5, s5, scale5, -1.0, r45)
            link_rotation(c6, s6, scale6, 1.0, r56)
            shoulder_matrix(x6, y6, z6, r34, r45, r56, m)
            solution = 2 * elbow + wrist
            factors[0, solution, 0], factors[0, solution, 1], factors[0, solution, 2] = m[1, 2], -m[0, 2], 0.0
            factors[1, solution, 0], factors[1, solution, 1] = -scale5 * scale6, 0.0
            factors[1, solution, 2] = m[2, 2]
            factors[2, solution, 0], factors[2, solution, 1], factors[2, solution, 2] = m[2, 1], m[2, 0], 0.0
            factors[4, solution, 0], factors[4, solution, 1], factors[4, solution, 2] = s5, -c5, 0.0
            factors[5, solution, 0], factors[5, solution, 1], factors[5, solution, 2] = s6, -c6, 0.0
    extra[0] = sigma.real * sigma.real * vxy2 * vxy2
    extra[1] = 1.0 - kappa * kappa
    extra[2] = wrist_existence.real
    extra[3] = sigma.real
    extra[4] = vxy2


@kernel
def factor_count(arm, joint):
    """How many factors of [F8] the limit function of ``joint`` (0-5) multiplies: four conjugate solutions, two for
    joint 4 (one per elbow root) and where :func:`halved` (the first elbow root's two)."""
    return 2 if joint == 3 or halved(arm, 2 * joint) else 4


@kernel
def factor_product(factors, joint, count, product):
    """The product of the first ``count`` factors of ``joint`` (:func:`limit_factors`) as a polynomial in ``cos L``
    (joint 2, ``gamma + alpha cos L``) or in ``sin L`` over ``cos L`` (``alpha cos L + beta sin L``): its coefficients
    into ``product`` (5,), zeros past ``count``."""
    product[0] = 1.0
    for i in range(1, 5):
        product[i] = 0.0
    for solution in range(count):  # times (a + b x): the new coefficient of x^i is a P_i + b P_(i - 1)
        if joint == 1:
            a, b = factors[joint, solution, 2], factors[joint, solution, 0]
        else:
            a, b = factors[joint, solution, 0], factors[joint, solution, 1]
        for i in range(solution + 1, 0, -1):
            product[i] = a * product[i] + b * product[i - 1]
        product[0] = a * product[0]


@kernel
def expanded_limits(factors, extra, arm, expanded):
    """One sample's limit functions of joints 1-6 [F8] as combinations of their limits' basis (:func:`level_basis`),
    from its :func:`limit_factors`: ``expanded`` (6, 5), real.

    The product of a joint's factors is a polynomial in ``cos L`` and ``sin L``: homogeneous of degree 4 in both for
    joints 1, 3, 5 and 6 (coefficients of ``cos^(4 - i) L sin^i L``), of degree 2 for joint 4 (``cos^(2 - i) L
    sin^i L``, then zeros), and in ``cos L`` alone for joint 2 (``cos^i L``).  Its real part, divided by the divisor
    for joints 1-3 and 6, gives ``expanded[j - 1, i]``: each a trigonometric polynomial in ``theta_7`` of the
    joint's degree (:data:`DEGREES`), since the products are, whatever ``L``, and the basis functions of ``L`` are
    independent.  Where :func:`halved`, the product over the first elbow root's two solutions, of degree 2 in
    ``cos L`` and ``sin L``, divided by ``Sigma |V_xy|^2`` for joints 1-3 and 6: its square is the product over all
    four divided by the divisor, and its degree in ``theta_7`` half the joint's.
    """
    product = np.empty(5, dtype=np.complex128)
    for joint in range(6):
        if factor_count(arm, joint) == 2:  # each count a constant where the product is inlined (its loops unrolled)
            factor_product(factors, joint, np.int64(2), product)
        else:
            factor_product(factors, joint, np.int64(4), product)
        scale = 1.0
        if joint < 3 or joint == 5:
            scale = extra[3] * extra[4] if halved(arm, 2 * joint) else extra[0]
        for i in range(5):
            expanded[joint, i] = product[i].real / scale


@kernel
def level_basis(limits, arm, basis):
    """The values at each joint's lower and upper limit (``limits`` (3, 7): lower and upper DH limits and whether
    the joint is limited) that :func:`expanded_limits`' coefficients multiply: ``basis`` (2, 6, 5)."""
    for k in range(2):
        for joint in range(6):
            c, s = cos(limits[k, joint]), sin(limits[k, joint])
            if factor_count(arm, joint) == 2:  # each count a constant where the row is inlined, as in expanded_limits
                basis_row(c, s, joint, np.int64(2), basis, k)
            else:
                basis_row(c, s, joint, np.int64(4), basis, k)


@kernel
def basis_row(c, s, joint, count, basis, k):
    """One joint's row of :func:`level_basis` at a limit of cosine ``c`` and sine ``s``: ``c^i`` for joint 2 (index
    1), else ``c^(count - i) s^i`` (zeros past ``count``), into ``basis[k, joint]`` (5,)."""
    for i in range(5):  # powers as products in one order: the same bits compiled and as Python
        value = 1.0
        if joint == 1:
            for _ in range(i):
                value *= c
        elif i <= count:
            for _ in range(count - i):
                value *= c
            for _ in range(i):
                value *= s
        else:
            value = 0.0
        basis[k, joint, i] = value


@kernel
def level_polynomial(spectra, basis, arm, f, polynomial):
    """The coefficients of limit function ``f`` (< 12: joint ``f // 2 + 1``, its lower or upper limit) into
    ``polynomial`` (2 D + 1,) (``g_-D .. g_D``, :func:`trig_coefficients`' layout, ``D``: :func:`degree_of`), from the
    pose's :func:`limit_spectra` and the limits' :func:`level_basis`; returns the largest ``|g_k|`` and ``terms``,
    the largest value the summed terms can give (``|g_0| + 2 sum_k |g_k|`` before they cancel), which bounds the
    coefficients' rounding (:data:`_TERM_ROUNDING`)."""
    joint, degree = f // 2, degree_of(arm, f)
    largest, terms = 0.0, 0.0
    for k in range(degree + 1):
        total, size = 0.0 + 0.0j, 0.0
        for i in range(5):
            term = spectra[joint, i, k] * basis[f % 2, joint, i]
            total += term
            size += abs(term.real) + abs(term.imag)  # within sqrt(2) of |term|, without a square root
        polynomial[degree + k] = total
        polynomial[degree - k] = np.conj(total)
        largest = max(largest, abs(total))
        terms += size if k == 0 else 2.0 * size
    return largest, terms


@kernel
def component_bounds(spectra, arm, bounds):
    """What each component of one pose's :func:`limit_spectra` (``spectra`` (6, 5, 9): joint, basis index ``i``,
    ``s_0 .. s_D``) adds to the bounds of a level polynomial built from it (:func:`level_polynomial`, whose
    coefficients are ``g_k = sum_i s_ik b_i`` with every basis entry ``|b_i| <= 1``), into ``bounds`` (6, 5, 3):
    the first three of :func:`row_bounds` of the component's row: ``|s_0| + 2 sum_k |s_k|`` (of the largest value,
    :func:`zero_floor`), ``sum_k (|Re s_k| + |Im s_k|)``, twice for ``k > 0`` (of the terms,
    :func:`level_polynomial`) and ``2 sum_k k^3 |s_k|`` (of ``B3``, :func:`global_bounds`).
    A level polynomial's are at most ``sum_i |b_i|`` times these (the triangle inequality); the components past
    :func:`factor_count` (zeros: :func:`expanded_limits`) are skipped."""
    for joint in range(6):
        degree = degree_of(arm, 2 * joint)
        for i in range(factor_count(arm, joint) + 1):
            size, terms, bound3, _ = row_bounds(spectra[joint, i, :degree + 1])
            bounds[joint, i, 0], bounds[joint, i, 1], bounds[joint, i, 2] = size, terms, bound3


@kernel
def component_values(spectra, arm, theta, values):
    """Each component of one pose's :func:`limit_spectra` (``spectra`` (6, 5, 9)) as a trigonometric polynomial in
    ``theta_7`` (:func:`trig_value`) at ``theta``: its value, slope and curvature into ``values`` (6, 5, 3); those
    of a level polynomial are ``sum_i b_i`` times these (:func:`level_polynomial`: ``g_k = sum_i s_ik b_i``), whatever
    its level.  Components past :func:`factor_count` (zeros) are skipped, here and in :func:`level_rootless`."""
    for joint in range(6):
        degree = degree_of(arm, 2 * joint)
        for i in range(factor_count(arm, joint) + 1):
            value, slope, curve, _ = trig_value(spectra[joint, i, :degree + 1], theta)
            values[joint, i, 0], values[joint, i, 1], values[joint, i, 2] = value, slope, curve


@kernel
def level_rootless(basis, f, arm, values, bounds, radius):
    """Whether the level polynomial of limit function ``f`` (:func:`level_polynomial`, from the limits' ``basis``)
    has no root within ``radius`` of ``theta``, from its components' :func:`component_values` at ``theta`` and
    :func:`component_bounds`, without building it: :func:`rootless_cell` with ``B3`` and the floor's sizes bounded
    by the components' (the triangle inequality: at least the polynomial's own, so the test is as sound and a
    little stricter).  The value is ``sum_i b_i S_i(theta)`` where :func:`trig_value` of the polynomial sums the
    same terms in another order: both round by a few units of the last place of ``terms``, a tenth of the floor or
    less."""
    joint, side = f // 2, f % 2
    value, slope, curve, size, terms, bound3 = 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    for i in range(factor_count(arm, joint) + 1):
        b = basis[side, joint, i]
        value += b * values[joint, i, 0]
        slope += b * values[joint, i, 1]
        curve += b * values[joint, i, 2]
        size += abs(b) * bounds[joint, i, 0]
        terms += abs(b) * bounds[joint, i, 1]
        bound3 += abs(b) * bounds[joint, i, 2]
    return rootless_cell(value, slope, curve, radius, bound3, zero_floor(size, terms))


@kernel
def trig_coefficients(values, degree, phase, coefficients):
    """The coefficients ``g_k`` (``|k| <= degree``) of a trigonometric polynomial sampled at :data:`SAMPLES` equal
    steps from ``phase`` (``values``), by the samples' discrete Fourier transform, into ``coefficients``
    (2 degree + 1,) (``g_-degree .. g_degree``); returns the largest ``|g_k|``."""
    n = values.shape[0]
    largest = 0.0
    for k in range(degree + 1):
        total = 0.0 + 0.0j
        for j in range(n):
            total += values[j] * _TWIDDLES[k, j]
        total *= complex(cos(k * phase), -sin(k * phase)) / n
        coefficients[degree + k] = total
        coefficients[degree - k] = np.conj(total)  # a real function: g_-k is the conjugate of g_k
        largest = max(largest, abs(total))
    return largest


@kernel
def coefficient_roots(coefficients, largest, terms, out, simple):
    """The real roots ``theta_7`` of the trigonometric polynomial of ``coefficients`` (``g_-D .. g_D``,
    :func:`trig_coefficients`' layout, whose largest size is ``largest``, summed from terms of size ``terms``:
    :func:`global_bounds`) into ``out``, and whether each is a simple
    root alone in its cell into ``simple`` (:func:`isolated_roots`; the eigenvalue route's are not); returns how many
    ([F8]).

    The real roots are isolated by subdivision (:func:`isolated_roots`); where that needs more cells than it may
    use (a cluster of nearly coincident roots), they are the roots of ``sum_k g_k z^(k + D)`` near the unit circle
    (:func:`circle_roots`)."""
    if largest == 0.0:
        return 0
    half = coefficients[coefficients.shape[0] // 2:]
    count = isolated_roots(half, terms, -np.pi, np.pi, 4 * half.shape[0], out, simple)
    if count >= 0:
        return count
    count = circle_roots(coefficients, largest, out)
    simple[:count] = False
    return count


@kernel
def global_bounds(half, terms):
    """From ``half = (g_0, ..., g_D)``: ``B3`` and ``B4``, bounds of the third and fourth derivatives of ``G`` on
    the whole circle (``Bn = 2 sum k^n |g_k|``), and the floor below which a value of ``G`` counts as zero:
    :data:`_NEAR_ZERO` of ``G``'s largest possible value, or :data:`_TERM_ROUNDING` of ``terms``, the size of the
    terms its coefficients were summed from (:func:`level_polynomial`; 0 for coefficients computed directly),
    whichever is larger."""
    size, _, bound3, bound4 = row_bounds(half)
    return bound3, bound4, zero_floor(size, terms)


@kernel
def row_bounds(half):
    """The sizes of a trigonometric polynomial's ``half = (g_0, ..., g_D)``: its largest possible value ``|g_0| + 2
    sum_k |g_k|``, the same with ``|Re g_k| + |Im g_k|`` for ``|g_k|`` (the size of the terms a polynomial summed
    from it rounds by, :func:`component_bounds`), and ``B3`` and ``B4``, bounds of its third and fourth derivatives
    on the whole circle (``Bn = 2 sum_k k^n |g_k|``)."""
    size, terms = abs(half[0]), abs(half[0].real) + abs(half[0].imag)
    bound3, bound4 = 0.0, 0.0
    for k in range(1, half.shape[0]):
        bound3 += 2.0 * k * k * k * abs(half[k])
        bound4 += 2.0 * k * k * k * k * abs(half[k])
        size += 2.0 * abs(half[k])
        terms += 2.0 * (abs(half[k].real) + abs(half[k].imag))
    return size, terms, bound3, bound4


@kernel
def zero_floor(size, terms):
    """The floor below which a value of ``G`` counts as zero, from ``size``, the largest value ``G`` can take
    (``|g_0| + 2 sum_k |g_k|``), and ``terms``, the size of the terms its coefficients were summed from:
    :data:`_NEAR_ZERO` of the one or :data:`_TERM_ROUNDING` of the other, whichever is larger."""
    return max(size * _NEAR_ZERO, terms * _TERM_ROUNDING)


@kernel
def rootless_cell(value, slope, curve, radius, bound3, floor):
    """Whether ``G`` has no root in ``[m - radius, m + radius]``, from its value, slope and curvature at ``m`` and
    ``bound3`` and ``floor`` of :func:`global_bounds`: ``|G(m)| > r |G1(m)| + r^2 |G2(m)| / 2 + r^3 B3 / 6 + floor``
    (Taylor's theorem, :func:`isolated_roots`)."""
    return abs(value) > (radius * abs(slope) + radius * radius / 2.0 * abs(curve)
                         + radius * radius * radius / 6.0 * bound3 + floor)


@kernel
def trig_value(half, theta):
    """``G(theta) = g_0 + 2 Re sum_k g_k e^(i k theta)`` and its first three derivatives, from ``half = (g_0, ...,
    g_D)``, in real arithmetic: with ``2 g_k = a_k + i b_k``, ``P_k = a_k cos k theta - b_k sin k theta`` and
    ``Q_k = a_k sin k theta + b_k cos k theta``, ``G = g_0 + sum P_k``, ``G1 = -sum k Q_k``, ``G2 = -sum k^2 P_k``
    and ``G3 = sum k^3 Q_k`` (``cos k theta``, ``sin k theta`` by a rotation from ``k - 1``'s)."""
    c, s = cos(theta), sin(theta)
    ck, sk = 1.0, 0.0
    value, slope, curve, third = half[0].real, 0.0, 0.0, 0.0
    for k in range(1, half.shape[0]):
        ck, sk = c * ck - s * sk, s * ck + c * sk
        a, b = 2.0 * half[k].real, 2.0 * half[k].imag
        p, r = a * ck - b * sk, a * sk + b * ck
        value += p
        slope -= k * r
        curve -= k * k * p
        third += k * k * k * r
    return value, slope, curve, third


@kernel
def isolated_roots(half, terms, low, high, cells, out, simple):
    """The real roots of ``G`` in ``[low, high]`` (``half = (g_0, ..., g_D)``, summed from terms of size ``terms``:
    :func:`global_bounds`; the circle from ``-pi`` to ``pi``, or a stretch of it) by subdivision from ``cells``
    equal cells, into ``out``, and into ``simple`` whether each is the one root of a monotone cell (rather than the
    middle of a cell that may hold several); returns how many, or -1 where :data:`_CELL_BUDGET` cells did not
    settle them or more candidates than ``out`` holds came up.

    A cell ``[m - r, m + r]`` holds no root where ``|G(m)| > r |G1(m)| +
    r^2 |G2(m)| / 2 + r^3 B3 / 6`` (plus :func:`global_bounds`' floor,
    so that a double root, which rounding may lift off zero, is kept), and at most one where ``|G1(m)| > r |G2(m)| + r^2
    |G3(m)| / 2 + r^3 B4 / 6`` plus ``G1``'s rounding (``G`` is then monotone:
    near a double root lifted off zero, whose least value may lie at a cell's end, the slopes are small enough for
    their rounding to decide), with ``Gn`` the
    n-th derivative and ``Bn = 2 sum k^n |g_k|`` a bound of it on the whole
    circle (Taylor's theorem: only the last term takes the global bound, so
    a pair of complex roots near the circle is passed at cells about as wide
    as its distance from it).  A
    monotone cell whose ends differ in sign holds exactly one, found by
    safeguarded Newton steps; other cells are halved, down to a half width
    of :data:`_SMALLEST_CELL`, where a cell that may hold a root (a double
    root: a joint touching its limit) gives its middle.
    """
    bound3, bound4, floor = global_bounds(half, terms)
    noise = floor * (_VALUE_ROUNDING / _NEAR_ZERO)  # G's rounding: a thousandth of the floor
    slope_noise = 0.0  # G1's rounding: _VALUE_ROUNDING of the largest value it can take
    for k in range(1, half.shape[0]):
        slope_noise += 2.0 * k * abs(half[k])
    slope_noise *= _VALUE_ROUNDING
    stack = np.empty((_CELL_BUDGET + 64, 2))
    size = 0
    for c in range(cells):
        stack[size, 0] = low + (high - low) * c / cells
        stack[size, 1] = low + (high - low) * (c + 1) / cells
        size += 1
    count = 0
    visited = 0
    while size > 0:
        size -= 1
        low, high = stack[size, 0], stack[size, 1]
        visited += 1
        if visited > _CELL_BUDGET:
            return -1
        middle, radius = 0.5 * (low + high), 0.5 * (high - low)
        value, slope, curve, third = trig_value(half, middle)
        if rootless_cell(value, slope, curve, radius, bound3, floor):
            continue
        square, cube = radius * radius / 2.0, radius * radius * radius / 6.0
        if abs(slope) > radius * abs(curve) + square * abs(third) + cube * bound4 + slope_noise:  # monotone
            # G at the ends, by Taylor's theorem where that settles its sign, else evaluated
            left = value - radius * slope + square * curve
            if abs(left) <= cube * bound3 + floor:
                left = trig_value(half, low)[0]
            right = value + radius * slope + square * curve
            if abs(right) <= cube * bound3 + floor:
                right = trig_value(half, high)[0]
            if left == 0.0 or right == 0.0 or (left < 0.0) != (right < 0.0):
                if count == out.shape[0]:
                    return -1
                out[count], simple[count] = monotone_root(half, low, high, left, noise), True
                count += 1
            continue
        if radius < _SMALLEST_CELL:
            if count == out.shape[0]:
                return -1
            out[count], simple[count] = middle, False
            count += 1
            continue
        if size + 2 > stack.shape[0]:
            return -1
        stack[size, 0], stack[size, 1] = low, middle
        stack[size + 1, 0], stack[size + 1, 1] = middle, high
        size += 2
    return count


@kernel
def monotone_root(half, low, high, left, noise):
    """The root of ``G`` in ``[low, high]``, where ``G`` is monotone and ``G(low)``, of the sign of ``left``, differs
    in sign from ``G(high)``: Newton steps kept inside a shrinking bracket (bisection where a step leaves it), until
    ``|G|`` is at most ``noise`` (its rounding) or the bracket as small as ``theta``'s."""
    theta = 0.5 * (low + high)
    for _ in range(100):
        value, slope, _, _ = trig_value(half, theta)
        if abs(value) <= noise or high - low <= 4e-16 * max(1.0, abs(theta)):
            return theta
        if (value < 0.0) == (left < 0.0):
            low = theta
        else:
            high = theta
        step = theta - value / slope if slope != 0.0 else low - 1.0
        theta = step if low < step < high else 0.5 * (low + high)
    return theta


@kernel
def circle_roots(coefficients, largest, out):
    """The roots ``theta`` of ``sum_k g_k z^(k + D)`` within :data:`_CIRCLE_TOLERANCE` of the unit circle
    ``z = e^(i theta)``: the companion matrix's eigenvalues, each angle polished by Newton steps on ``G`` itself
    (:func:`polished_angle`)."""
    top = coefficients.shape[0] - 1
    while top > 0 and abs(coefficients[top]) <= 1e-13 * largest:
        top -= 1
    bottom = 0
    while bottom < top and abs(coefficients[bottom]) <= 1e-13 * largest:
        bottom += 1
    size = top - bottom
    if size < 1:
        return 0
    companion = np.zeros((size, size), dtype=np.complex128)
    for i in range(size - 1):
        companion[i + 1, i] = 1.0
    for i in range(size):
        companion[i, size - 1] = -coefficients[bottom + i] / coefficients[top]
    roots = np.linalg.eigvals(companion)
    half = coefficients[coefficients.shape[0] // 2:]
    count = 0
    for z in roots:
        if abs(abs(z) - 1.0) <= _CIRCLE_TOLERANCE:
            out[count] = polished_angle(half, atan2(z.imag, z.real))
            count += 1
    return count


@kernel
def polished_angle(half, theta):
    """Newton steps on ``G`` (``half = (g_0, ..., g_D)``, :func:`trig_value`) from ``theta``, each shorter than
    :data:`_NEWTON_STEP` and lowering ``|G|`` (else the angle reached is kept: a complex pair near the circle has no
    real root to go to).  The eigenvalues of a cluster of roots lie about 3e-3 from them (five real roots within
    0.1 rad), where ``G`` evaluated on the circle locates them to its rounding."""
    value, slope, _, _ = trig_value(half, theta)
    for _ in range(_NEWTON_STEPS):
        if slope == 0.0:
            break
        step = value / slope
        if not abs(step) < _NEWTON_STEP:
            break
        after, after_slope, _, _ = trig_value(half, theta - step)
        if not abs(after) < abs(value):
            break
        theta, value, slope = theta - step, after, after_slope
    return theta


@kernel
def limit_spectra(t07, arm, spectra, existence):
    """The limit functions [F8]-[F9] of one pose as Fourier coefficients: ``spectra`` (6, 5, 9) complex, the
    coefficients ``g_0 .. g_D`` of each column of :func:`expanded_limits` (joint ``j``'s degree ``D``), and
    ``existence`` (2, 17) complex, those of [F9]'s elbow and wrist existence functions (``g_-D .. g_D``,
    :func:`trig_coefficients`' layout).

    From :func:`limit_factors` at :data:`SAMPLES` equal steps of ``theta_7`` (from 0, or from half a step where a
    divisor, ``Sigma`` or ``|V_xy|^2``, nearly vanishes on that grid) by :func:`trig_coefficients` (exact for a
    trigonometric polynomial of that degree).  A limit function at any limits is then :func:`level_polynomial`.
    """
    scratch = np.empty((4, 3, 3), dtype=np.complex128)
    factors = np.empty((6, 4, 3), dtype=np.complex128)
    expanded = np.empty((SAMPLES, 6, 5))
    extra = np.empty((SAMPLES, EXTRA))
    phase = 0.0
    for _ in range(2):  # the grid, and once more moved by half a step if a divisor nearly vanishes on it
        for j in range(SAMPLES):
            limit_factors(t07, phase + 2.0 * np.pi * j / SAMPLES, arm, factors, extra[j], scratch)
            expanded_limits(factors, extra[j], arm, expanded[j])
        small = False
        for column in (3, 4):  # Sigma and |V_xy|^2
            largest = np.abs(extra[:, column]).max()
            small = small or np.abs(extra[:, column]).min() <= _SMALL_DIVISOR * largest
        if not small:
            break
        phase = np.pi / SAMPLES
    values = np.empty(SAMPLES)
    full = np.empty(2 * 8 + 1, dtype=np.complex128)
    for joint in range(6):
        degree = degree_of(arm, 2 * joint)
        for i in range(5):
            _array_copy.copy_into(values, expanded[:, joint, i])
            trig_coefficients(values, degree, phase, full[:2 * degree + 1])
            _array_copy.copy_into(spectra[joint, i, :degree + 1], full[degree:2 * degree + 1])
    for k in range(2):
        _array_copy.copy_into(values, extra[:, 1 + k])
        degree = degree_of(arm, 12 + k)
        trig_coefficients(values, degree, phase, existence[k, :2 * degree + 1])


@kernel
def limit_spectra_of(start, stop, t07, arm, spectra, existence):
    """:func:`limit_spectra` of the poses ``start .. stop - 1`` of ``t07`` (P, 4, 4) into ``spectra`` (P, 6, 5, 9)
    and ``existence`` (P, 2, 17): what :func:`levels_crossed` reads."""
    for p in range(start, stop):
        limit_spectra(t07[p], arm, spectra[p], existence[p])


@kernel
def levels_crossed(start, stop, pose, t07, spectra, arm, levels, lo, hi, signs, joints, out):
    """For each interval ``[lo[i], hi[i]]`` of q7 (the chain's value) at the pose ``t07[pose[i]]``, ``i`` in ``start
    .. stop - 1`` (a batch of :func:`redkin._compiled.run_batch`; the poses' :func:`limit_spectra` in ``spectra``),
    whether the branch of solver signs ``signs[i]`` may
    leave the band its levels ``levels[i]`` (3, 7) set (two DH angles per joint, laid out as the limits of
    :func:`level_basis`, and whether to test the joint) for a joint 1-6 somewhere in the interval, into ``out``
    (N,) (docs/collisions.md, "The Franka class").

    It may not where (i) the bands keep the branch away from its jumps [F5]-[F7]: ``sin theta_2`` away from 0 over
    joint 2's band, ``S_4x`` [F4] away from 0 over joint 4's, and ``|V_xy|`` [F6] above what it can lose over the
    interval (``V`` turns with ``theta_7`` about an axis through ``O_6``, at most ``|S - O_6|`` per radian); and (ii)
    each level polynomial [F8] has no root within :data:`LEVEL_SLACK` of the interval (first by the cell test of
    :func:`isolated_roots` on the whole interval, from the pose's components without building the polynomial:
    :func:`level_rootless`), or every such root (isolated by
    :func:`isolated_roots` on that stretch, or as :func:`coefficient_roots` isolates the limits where that does not
    settle) belongs to another of the four conjugate solutions: the branch exists there and its joint lies more than
    half the band's width from that level.  Then each joint of the branch,
    continuous on the interval (where the branch exists on all of it), stays inside its band if it is inside at one
    q7 of it.
    """
    offset7 = joints[0, 6]
    roots = np.empty(2 * 8)
    simple = np.empty(2 * 8, dtype=np.bool_)
    coefficients = np.empty(2 * 8 + 1, dtype=np.complex128)
    basis = np.empty((2, 6, 5))
    q = np.empty((1, 7))
    exists = np.empty(1, dtype=np.bool_)
    scratch = np.empty((8, 3, 3))
    work = np.empty(WORK)
    bounds = np.empty((6, 5, 3))
    values = np.empty((6, 5, 3))
    bounded = -1  # the pose whose component_bounds are in bounds
    for i in range(start, stop):
        out[i] = True
        p = pose[i]
        middle = offset7 + 0.5 * (lo[i] + hi[i])
        width2 = 0.5 * abs(levels[i, 1, 1] - levels[i, 0, 1])
        if abs(sin(0.5 * (levels[i, 0, 1] + levels[i, 1, 1]))) <= width2:
            continue  # theta_2 may reach 0 or pi, where theta_1 and theta_3 jump
        middle4 = 0.5 * (levels[i, 0, 3] + levels[i, 1, 3])
        s4x, _ = shoulder_in_frame_four(cos(middle4), sin(middle4), arm)
        if abs(s4x) <= np.hypot(arm[A3], arm[D3]) * 0.5 * abs(levels[i, 1, 3] - levels[i, 0, 3]):
            continue  # S_4x may vanish, where theta_5 is free
        x6, y6, z6, _w = wrist_and_frame_six(t07[p], middle, arm)
        vx, vy, _vz = shoulder_seen_from_six(x6, y6, z6, t07[p], arm)
        lever = np.sqrt(t07[p, 0, 3] ** 2 + t07[p, 1, 3] ** 2 + (arm[D1] - t07[p, 2, 3]) ** 2)
        if np.hypot(vx, vy) <= lever * 0.5 * (hi[i] - lo[i]) + LEVEL_SLACK:
            continue  # V_xy may vanish, where theta_6 is free
        level_basis(levels[i], arm, basis)
        if p != bounded:
            component_bounds(spectra[p], arm, bounds)
            bounded = p
        component_values(spectra[p], arm, middle, values)
        reach = 0.5 * (hi[i] - lo[i]) + LEVEL_SLACK
        crossed = False
        for f in range(12):
            joint = f // 2
            if levels[i, 2, joint] == 0.0:
                continue
            if level_rootless(basis, f, arm, values, bounds, reach):
                continue  # no conjugate solution's joint meets this level near the interval
            level = levels[i, f % 2, joint]
            width = 0.5 * abs(levels[i, 1, joint] - levels[i, 0, joint])
            degree = degree_of(arm, f)
            polynomial = coefficients[:2 * degree + 1]
            largest, terms = level_polynomial(spectra[p], basis, arm, f, polynomial)
            half = polynomial[degree:]
            count = isolated_roots(half, terms, middle - reach, middle + reach, np.int64(2), roots, simple)
            if count < 0:
                count = coefficient_roots(polynomial, largest, terms, roots, simple)
            for r in range(count):
                q7 = roots[r] - offset7
                value = q7 + 2.0 * np.pi * np.ceil((lo[i] - LEVEL_SLACK - q7) / (2.0 * np.pi))
                if value > hi[i] + LEVEL_SLACK:
                    continue
                solve_q7(t07[p], value, arm, signs[i:i + 1], joints, q, exists, scratch, work)
                theta = joints[0, joint] + joints[1, joint] * q[0, joint]
                gap = abs((theta - level + np.pi) % (2.0 * np.pi) - np.pi)
                if not exists[0] or gap <= 0.5 * width:
                    crossed = True
                    break
            if crossed:
                break
        out[i] = crossed


@kernel
def feasible_q7(t07, arm, limits, joints, branches, domain, arcs, counts):
    """The exact feasible q7 set of every branch of one pose: arcs ``[start, end]`` of q7 (the chain's value)
    into ``arcs`` (B, K, 2) and their number into ``counts`` (B,); a branch with more than K arcs has its first K
    written and all counted.  Returns the number of breakpoints used.

    The breakpoints are the ends of ``domain`` (the q7 range) and every
    root in it of the limit polynomials ([F8], [F9]; every value of q7 at
    which some branch's joint meets a limit, a branch appears or vanishes,
    or a joint jumps at a singular configuration).  Between two breakpoints
    no branch changes its status, so one evaluation at the midpoint decides
    each interval; adjacent feasible intervals are merged.
    """
    offset7 = joints[0, 6]
    spectra = np.empty((6, 5, 9), dtype=np.complex128)
    existence = np.empty((2, 2 * 8 + 1), dtype=np.complex128)
    limit_spectra(t07, arm, spectra, existence)
    basis = np.empty((2, 6, 5))
    level_basis(limits, arm, basis)
    polynomial = np.empty(2 * 8 + 1, dtype=np.complex128)
    roots = np.empty(2 * 8)  # a polynomial's candidates: at most its 2 D roots, or cell middles up to this room
    simple = np.empty(roots.shape[0], dtype=np.bool_)
    most = FUNCTIONS * roots.shape[0]
    angles = np.empty(most * (1 + 2 * branches.shape[0]))  # the candidates, then at most 2 B polished at each
    sources = np.empty(angles.shape[0], dtype=np.int64)
    crowded = np.empty(most, dtype=np.bool_)  # each candidate's: to be polished (a cluster, or a neighbour near)
    found = np.int64(0)
    for f in range(FUNCTIONS):
        if f < 12:
            joint = f // 2
            if limits[2, joint] == 0.0:
                continue
            if f % 2 == 1 and (joint == 1 or joint == 4) and limits[0, joint] == -limits[1, joint]:
                continue  # cos(theta_2), and theta_5 up to its sign, give the same polynomial for L and -L
        degree = degree_of(arm, f)
        if f < 12:
            largest, terms = level_polynomial(spectra, basis, arm, f, polynomial)
            count = coefficient_roots(polynomial[:2 * degree + 1], largest, terms, roots, simple)
        else:  # the elbow's and the wrist's existence
            own = existence[f - 12, :2 * degree + 1]
            largest = 0.0
            for k in range(degree + 1):
                largest = max(largest, abs(own[degree + k]))
            count = coefficient_roots(own, largest, 0.0, roots, simple)
        for r in range(count):
            angles[found], sources[found], crowded[found] = roots[r], f, not simple[r]
            found += 1
    crowded_roots(angles, found, 2.0 * _POLISH_REACH, domain + offset7, crowded)
    found = polished_crossings(t07, arm, branches, joints, angles, sources, found, crowded)
    lower, upper = domain[0], domain[1]
    turns = int(np.ceil((upper - lower) / (2.0 * np.pi))) + 1
    unsorted = np.empty(found * (turns + 1) + 2)
    named = np.full(unsorted.shape[0], -1, dtype=np.int64)  # each breakpoint's source (-1: exact)
    size = 0
    unsorted[size] = lower
    size += 1
    for r in range(found):
        q7 = angles[r] - offset7
        k = np.ceil((lower - q7) / (2.0 * np.pi))
        value = q7 + 2.0 * np.pi * k
        while value < upper:
            if value > lower:
                unsorted[size], named[size] = value, sources[r]
                size += 1
            value += 2.0 * np.pi
    unsorted[size] = upper
    size += 1
    order = np.argsort(unsorted[:size], kind="mergesort")
    points, point_sources = unsorted[order], named[order]
    count = size - 1
    status = np.zeros((count, branches.shape[0]), dtype=np.bool_)
    q = np.empty((branches.shape[0], 7))
    exists = np.empty(branches.shape[0], dtype=np.bool_)
    real_scratch = np.empty((8, 3, 3))
    work = np.empty(WORK)
    for i in range(count):
        if points[i + 1] > points[i]:
            solve_q7(t07, 0.5 * (points[i] + points[i + 1]), arm, branches, joints, q, exists, real_scratch,
                     work)
            for b in range(branches.shape[0]):
                status[i, b] = exists[b] and in_limits(q[b], joints)
    for b in range(branches.shape[0]):
        counts[b] = 0
        previous = np.int64(-1)  # the last interval of positive width, and its status
        for i in range(count):
            if points[i + 1] <= points[i]:
                continue
            if status[i, b] and (previous < 0 or not status[previous, b]):
                if counts[b] < arcs.shape[1]:  # an arc past the room is counted, not located
                    arcs[b, counts[b], 0] = points[i] if previous < 0 else crossing(
                        t07, arm, branches[b:b + 1], joints, points, point_sources, previous, i, status[previous, b],
                        real_scratch, work)
                counts[b] += 1
            if not status[i, b] and previous >= 0 and status[previous, b] and counts[b] <= arcs.shape[1]:
                arcs[b, counts[b] - 1, 1] = crossing(t07, arm, branches[b:b + 1], joints, points, point_sources,
                                                     previous, i, status[previous, b], real_scratch, work)
            previous = i
        if previous >= 0 and status[previous, b] and counts[b] <= arcs.shape[1]:
            arcs[b, counts[b] - 1, 1] = points[count]
    return size


@kernel
def status_gap(t07, q7, arm, branch, joints, kind, target, q, exists, scratch, work):
    """The quantity whose sign change at ``q7`` is a change of the status of ``branch`` (1, 3) that :func:`crossing`
    looks for: for ``kind`` < 6, joint ``kind``'s value minus ``target`` (a limit widened by ``in_limits``' slack,
    modulo 2 pi); 6, the elbow's :func:`elbow_excess`; 7, the wrist's :func:`wrist_excess` on the branch's elbow.
    NaN where it is not defined (the branch, or for 7 its elbow, does not exist).  ``q``, ``exists``, ``scratch``
    and ``work`` are :func:`solve_q7`'s for one branch."""
    if kind < 6:
        solve_q7(t07, q7, arm, branch, joints, q, exists, scratch, work)
        if not exists[0]:
            return np.nan
        return np.mod(q[0, kind] - target + np.pi, 2.0 * np.pi) - np.pi
    x6, y6, z6, w = wrist_and_frame_six(t07, q7 + joints[0, 6], arm)
    kappa = elbow_cosine(w, arm)
    if kind == 6:
        return elbow_excess(kappa)
    if elbow_excess(kappa) > 0.0:
        return np.nan
    s4x = elbow_of(kappa, branch[0, 1], arm)[2]
    vz = shoulder_seen_from_six(x6, y6, z6, t07, arm)[2]
    return wrist_excess(vz, s4x, arm)


@kernel
def secant_crossing(t07, start, gap, arm, branch, joints, kind, target, q, exists, scratch, work):
    """Where :func:`status_gap` (``kind``, ``target``) of ``branch`` vanishes near ``start`` (where it is ``gap``), by
    secant steps from ``start`` and ``start + 1e-10``; NaN where they leave :data:`_POLISH_REACH` of ``start`` or
    meet a q7 where the gap is not defined.

    The steps stop after one of at most :data:`_SETTLED_STEP`, whose point is not evaluated: the secant's error is
    then about the product of the last two errors (1e-18 rad from a start 1e-9 off), below the rounding.  The
    result is a breakpoint, which only splits an interval: where it is wrong (a gap not smooth there),
    :func:`crossing` bisects, and the set is the same.
    """
    x0, g0 = start, gap
    x1 = start + 1e-10
    g1 = status_gap(t07, x1, arm, branch, joints, kind, target, q, exists, scratch, work)
    for _ in range(12):
        if np.isnan(g1) or g1 == g0:
            return np.nan
        x2 = x1 - g1 * (x1 - x0) / (g1 - g0)
        if abs(x2 - start) > _POLISH_REACH:
            return np.nan
        if abs(x2 - x1) <= _SETTLED_STEP:
            return x2
        x0, g0 = x1, g1
        x1 = x2
        g1 = status_gap(t07, x1, arm, branch, joints, kind, target, q, exists, scratch, work)
    return np.nan


@kernel
def polished_crossings(t07, arm, branches, joints, angles, sources, found, crowded):
    """Add to the candidates ``angles[:found]`` (from the limit polynomials ``sources``), at each one marked
    ``crowded`` (not a simple root alone in its cell, or near another: :func:`crowded_roots`), the status changes
    of the real branches themselves (:func:`secant_crossing`), with source -1: where a branch has its joint within
    :data:`_POLISH_REACH` of a limit (widened by ``in_limits``' slack) at a candidate of that joint's polynomial,
    and where the elbow, or the wrist of either elbow, stops existing near a candidate of [F9]'s existence
    polynomials.  Returns the new count.

    A polynomial's root is only as accurate as its coefficients, which can
    be 1e-8 in q7 where the product's other factors are small; an arc
    narrower than that could lie between two crowded candidates and never
    be sampled.  The branch's own joint value, and the existence tests of
    :func:`solve_q7`, are exact to rounding, and so is the change found on
    them.  A simple root with no other candidate, and no end of the q7
    range, within twice the reach needs none: the midpoints on either side lie beyond the
    reach, so the one change near it lies between them, where
    :func:`crossing` finds it.
    """
    scratch = np.empty((8, 3, 3))
    work = np.empty(WORK)
    q = np.empty((branches.shape[0], 7))
    exists = np.empty(branches.shape[0], dtype=np.bool_)
    one = np.empty((1, 7))
    one_exists = np.empty(1, dtype=np.bool_)
    total = found
    for r in range(found):
        if not crowded[r]:
            continue
        start = angles[r] - joints[0, 6]  # the candidate's q7 (the angles are theta_7)
        if sources[r] >= 12:  # the elbow's existence (one test), or the wrist's on either elbow
            kind = 6 + sources[r] - 12
            for b in range(branches.shape[0] if kind == 7 else 1):
                earlier = False  # the wrist's test depends on the elbow alone: the first branch of each elbow
                for e in range(b):
                    earlier = earlier or branches[e, 1] == branches[b, 1]
                if earlier:
                    continue
                gap = status_gap(t07, start, arm, branches[b:b + 1], joints, kind, 0.0, one, one_exists, scratch,
                                 work)
                if np.isnan(gap) or abs(gap) > _POLISH_REACH:
                    continue
                x = secant_crossing(t07, start, gap, arm, branches[b:b + 1], joints, kind, 0.0, one, one_exists,
                                    scratch, work)
                if not np.isnan(x):
                    angles[total], sources[total] = x + joints[0, 6], -1
                    total += 1
            continue
        joint = sources[r] // 2
        solve_q7(t07, start, arm, branches, joints, q, exists, scratch, work)
        for b in range(branches.shape[0]):
            if not exists[b]:
                continue
            for row in (3, 4):  # the joint's lower and upper limit (joint 2's polynomial serves both)
                # where the status changes: the limit widened by in_limits' slack
                limit = joints[row, joint] + (MEMBERSHIP_TOLERANCE if row == 4 else -MEMBERSHIP_TOLERANCE)
                gap = np.mod(q[b, joint] - limit + np.pi, 2.0 * np.pi) - np.pi
                if abs(gap) > _POLISH_REACH:
                    continue
                x = secant_crossing(t07, start, gap, arm, branches[b:b + 1], joints, joint, limit, one, one_exists,
                                    scratch, work)
                if not np.isnan(x):
                    angles[total], sources[total] = x + joints[0, 6], -1
                    total += 1
    return total


@kernel
def crowded_roots(angles, found, width, ends, crowded):
    """Mark in ``crowded`` (found,) each of the candidates ``angles[:found]`` (``theta_7``, on the circle) that has
    another, or one of the other breakpoints ``ends`` (the ends of the q7 range, as ``theta_7``), within ``width``
    (the others keep their marks)."""
    order = np.argsort(angles[:found])
    for r in range(found):
        for end in ends:
            crowded[r] = crowded[r] or abs(np.mod(angles[r] - end + np.pi, 2.0 * np.pi) - np.pi) <= width
    for k in range(found - 1 if found > 1 else 0):
        a, b = order[k], order[k + 1]
        if angles[b] - angles[a] <= width:
            crowded[a], crowded[b] = True, True
    if found > 1 and angles[order[0]] + 2.0 * np.pi - angles[order[found - 1]] <= width:
        crowded[order[0]], crowded[order[found - 1]] = True, True


@kernel
def changed_near(t07, arm, branch, joints, centre, low, high, status_low, q, exists, scratch, work):
    """Where one branch's status changes within :data:`_ROOT_BRACKET` of ``centre`` (clipped to ``[low, high]``): the
    end of the bracket on the feasible side (an arc's ends are themselves feasible) where the status is
    ``status_low`` at its lower end and not at its upper one; NaN otherwise."""
    near_low = max(low, centre - _ROOT_BRACKET)
    near_high = min(high, centre + _ROOT_BRACKET)
    solve_q7(t07, near_low, arm, branch, joints, q, exists, scratch, work)
    if (exists[0] and in_limits(q[0], joints)) != status_low:
        return np.nan
    solve_q7(t07, near_high, arm, branch, joints, q, exists, scratch, work)
    if (exists[0] and in_limits(q[0], joints)) == status_low:
        return np.nan
    return near_low if status_low else near_high


@kernel
def crossing(t07, arm, branch, joints, points, sources, left, right, status_low, scratch, work):
    """Where one branch's status (exists and within the limits) changes between the midpoints of intervals
    ``left`` (where it is ``status_low``) and ``right`` of ``points``: the end on the feasible side, to the rounding
    of q7 (an arc's ends are themselves feasible).

    The change is at the breakpoint between them (``points[right]``) or
    near it: first sought within :data:`_ROOT_BRACKET` of it (a polished
    root, ``sources`` -1, is exact), then of the zero of the status gap its
    polynomial ``sources[right]`` names (:func:`status_gap`: the joint's
    nearer limit, or the elbow's or the wrist's existence) that secant steps
    from it find; where neither holds a change (a cluster of roots, the
    eigenvalue route), the span between the midpoints is bisected.
    """
    low = 0.5 * (points[left] + points[left + 1])
    high = 0.5 * (points[right] + points[right + 1])
    q = np.empty((1, 7))
    exists = np.empty(1, dtype=np.bool_)
    centre = points[right]
    end = changed_near(t07, arm, branch, joints, centre, low, high, status_low, q, exists, scratch, work)
    if not np.isnan(end):
        return end
    source = sources[right]
    if source >= 0:
        kind, target = 6 + source - 12, 0.0
        if source < 12:  # the joint's nearer limit, widened by in_limits' slack
            kind = source // 2
            solve_q7(t07, centre, arm, branch, joints, q, exists, scratch, work)
            below = abs(np.mod(q[0, kind] - joints[3, kind] + np.pi, 2.0 * np.pi) - np.pi)
            above = abs(np.mod(q[0, kind] - joints[4, kind] + np.pi, 2.0 * np.pi) - np.pi)
            target = joints[3, kind] - MEMBERSHIP_TOLERANCE if below <= above else (
                joints[4, kind] + MEMBERSHIP_TOLERANCE)
        gap = status_gap(t07, centre, arm, branch, joints, kind, target, q, exists, scratch, work)
        if not np.isnan(gap):
            zero = secant_crossing(t07, centre, gap, arm, branch, joints, kind, target, q, exists, scratch, work)
            if low < zero < high:
                end = changed_near(t07, arm, branch, joints, zero, low, high, status_low, q, exists, scratch, work)
                if not np.isnan(end):
                    return end
    while high - low > 4e-16 * max(1.0, abs(low)):
        middle = 0.5 * (low + high)
        if middle <= low or middle >= high:
            break
        solve_q7(t07, middle, arm, branch, joints, q, exists, scratch, work)
        if (exists[0] and in_limits(q[0], joints)) == status_low:
            low = middle
        else:
            high = middle
    return low if status_low else high


# ----------------------------------------------------------------- batches
# A batch kernel computes items start..stop - 1 (redkin._compiled.run_batch hands out the chunks).
@kernel
def seventh_frame(pose, ends, frame):
    """Frame 7 of the solver's form in its frame 0 for a target ``pose`` (4, 4) of the chain's tool: ``base^-1 pose
    tool^-1`` (``ends`` (2, 4, 4)), into ``frame`` (4, 4)."""
    for r in range(4):
        for c in range(4):
            total = 0.0
            for k in range(4):
                inner = 0.0
                for m in range(4):
                    inner += pose[k, m] * ends[1, m, c]
                total += ends[0, r, k] * inner
            frame[r, c] = total


@kernel
def seventh_frames(start, stop, poses, ends, frames):
    """:func:`seventh_frame` of the poses ``start .. stop - 1`` of ``poses`` (N, 4, 4) into ``frames`` (N, 4, 4): the
    one form of ``base^-1 pose tool^-1`` the feasible sets, the paths and the solver all read, so that they agree to
    the last bit where a branch's existence turns on rounding (the end of an arc).  Returns how many of them are
    not poses (:func:`redkin._pose_kernels.pose_defect`; the caller words the error)."""
    bad = 0
    for n in range(start, stop):
        bad += pose_defect(poses[n]) != OK
        seventh_frame(poses[n], ends, frames[n])
    return bad


@kernel
def solve_pose(pose, q7, arm, ends, branches, joints, q, exists, within, frame, scratch, work):
    """One target pose (4, 4) of the chain at one value of q7: its checks, then :func:`solve_q7` into ``q`` (B, 7),
    ``exists`` and ``within`` (B,) (exists and lies within the limits).  Returns :data:`OK`, or :data:`BAD_POSE`
    for a pose that is not finite or not a proper rigid transform, or a q7 that is not finite (the caller words
    the error).  ``frame`` (4, 4), ``scratch`` (8, 3, 3) and ``work`` (:data:`WORK`,) are work space."""
    if pose_defect(pose) != OK or not np.isfinite(q7):
        return BAD_POSE
    seventh_frame(pose, ends, frame)
    solve_q7(frame, q7, arm, branches, joints, q, exists, scratch, work)
    for b in range(branches.shape[0]):
        within[b] = exists[b] and in_limits(q[b], joints)
    return OK


@kernel
def unpacked(table):
    """The tables :func:`solve_pose` reads, as views of the one array ``table``
    (:attr:`redkin.franka.geometry.FrankaGeometry.kernel_table`): ``arm`` (10,), ``ends`` (2, 4, 4), ``branches``
    (8, 3) and ``joints`` (5, 7)."""
    return (table[:TABLE_ENDS], table[TABLE_ENDS:TABLE_BRANCHES].reshape((2, 4, 4)),
            table[TABLE_BRANCHES:TABLE_JOINTS].reshape((8, 3)), table[TABLE_JOINTS:TABLE_SIZE].reshape((5, 7)))


@kernel
def solve_single(pose, q7, table, first, count, q, flags):
    """:func:`solve_pose` for one pose and one q7 (a float) on the ``count`` branches from row ``first`` of the
    branches in ``table`` (:func:`unpacked`) into ``q`` (count, 7) and ``flags`` (2, count): whether each exists,
    and whether it lies within the limits.  Returns the status."""
    arm, ends, branches, joints = unpacked(table)
    return solve_pose(pose, q7, arm, ends, branches[first:first + count], joints, q, flags[0], flags[1],
                      np.empty((4, 4)), np.empty((8, 3, 3)), np.empty(WORK))


@kernel
def solve_poses(start, stop, poses, q7, arm, ends, branches, joints, q, exists, within):
    """:func:`solve_pose` for items ``start .. stop - 1``: ``poses`` (N, 4, 4), ``q7`` (N,) into ``q`` (N, B, 7),
    ``exists`` and ``within`` (N, B).  Returns how many items failed their checks."""
    frame = np.empty((4, 4))
    scratch = np.empty((8, 3, 3))
    work = np.empty(WORK)
    failed = 0
    for n in range(start, stop):
        if solve_pose(poses[n], q7[n], arm, ends, branches, joints, q[n], exists[n], within[n], frame,
                      scratch, work) != OK:
            failed += 1
    return failed


@kernel
def solve_branch_rows(start, stop, poses, pose_of, q7, rows, arm, ends, branches, joints, q, exists):
    """One branch per item, for items ``start .. stop - 1``: item ``k`` is pose ``poses[pose_of[k]]`` (trusted) at
    q7 ``q7[k]`` on the branch of row ``rows[k]`` of ``branches`` (8, 3), its solution [F1]-[F7] into ``q[k]`` (7,)
    and whether it exists into ``exists[k]``: what :func:`solve_pose` gives for that branch alone.  A run of items
    of one pose (a pose's sets ask hundreds) reads its :func:`seventh_frame` once."""
    frame = np.empty((4, 4))
    scratch = np.empty((8, 3, 3))
    work = np.empty(WORK)
    for k in range(start, stop):
        row = rows[k]
        if k == start or pose_of[k] != pose_of[k - 1]:
            seventh_frame(poses[pose_of[k]], ends, frame)
        solve_q7(frame, q7[k], arm, branches[row:row + 1], joints, q[k:k + 1], exists[k:k + 1],
                 scratch, work)


@kernel
def feasible_poses(start, stop, t07, arm, limits, joints, branches, domain, arcs, counts):
    """:func:`feasible_q7` for items ``start .. stop - 1``: ``t07`` (N, 4, 4) into ``arcs`` (N, B, K, 2) and
    ``counts`` (N, B).  An item with more than K arcs on a branch is left with every count set to minus the most
    arcs of its branches (the caller computes it again with that room)."""
    for n in range(start, stop):
        feasible_q7(t07[n], arm, limits, joints, branches, domain, arcs[n], counts[n])
        most = 0
        for b in range(branches.shape[0]):
            most = max(most, counts[n, b])
        if most > arcs.shape[2]:
            counts[n, :] = -most
