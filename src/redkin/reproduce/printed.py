"""The values the papers print, each written once: the "paper" column of ``redkin reproduce`` and the tests read them.

One section per paper: 000 (sections 6.1, 6.2.1, 6.2.2), thesis 001 (sections 2.4, 5.1), 003 (section 4) and 004
(section 4, Figs. 6-8).  Paper 000's values are in degrees with the paper's rounding (three decimals) unless a
name says otherwise; the other sections give each value's units in its comment.  Besides printed results, a
paper's own example inputs are here (003's start posture, commanded twist and threshold; 004's joint ranges) when
the report and the tests both use them; inputs a paper does not print (our choices) are not.  A yes/no claim of a
paper is written as the word the report's paper column shows ("yes").

They are the papers' numbers, not redkin's: nothing outside :mod:`redkin.reproduce` and the tests may read them.
The link lengths and joint limits the papers print belong to the robot models of :mod:`redkin.models` and are
read from there.
"""

from __future__ import annotations

# ------------------------------------------------------------------ paper 000 (Shimizu et al.)

#: [000 section 6.1], tool at x = (0.65, 0, 0.5) m, R = diag(-1, 1, -1), branch +++: the half-widths of the
#: per-joint feasible sets Psi_i (symmetric about 0; ``None``: the whole circle) and of Psi.
SECTION_6_1_JOINT_BOUNDS: dict[int, float | None] = {1: None, 2: 45.991, 3: 111.734, 5: 108.926, 6: 62.154, 7: None}
SECTION_6_1_PSI_BOUND = 45.991
#: [000 section 6.1]: the joint values at psi = 0, psi_min and psi_max (psi_max: the signs of psi_min's turned).
SECTION_6_1_THETA_AT_ZERO = (0.0, 25.666, 0.0, 82.872, 0.0, 71.463, 0.0)
SECTION_6_1_THETA_AT_PSI_MIN = (43.992, 45.0, -71.419, 82.872, 42.572, 82.193, -27.693)

#: [000 section 6.2.1], tool at x = (0.55, 0, 0.767) m, R = [[0,0,1],[0,1,0],[-1,0,0]]: (a, b, c) of the
#: shoulder's ``cos theta_2`` entry ([000 eq. 31]) and of the wrist's ``cos theta_6`` entry ([000 eq. 33]), and the
#: half-width of the feasible set the paper prints (it belongs to branch ++-).
SECTION_6_2_1_SHOULDER_COEFFICIENTS = (0.0, -0.532, -0.468)
SECTION_6_2_1_WRIST_COEFFICIENTS = (0.0, 0.468, 0.532)
SECTION_6_2_1_PSI_BOUND = 63.277

#: [000 section 6.2.2], tool at x = (0.65, 0, 0.5) m turned by pi/2 about z, targets (0, 90, 0, -, 0, 90, 0):
#: the printed half-width of Psi (a misprint, see the report), the optima of [000 eqs. 37, 39, 40], the joint
#: values at psi = 0 and at psi^opt, and the tool rotations reachable with psi fixed at 0 (Gamma_0) and
#: with psi controlled (Gamma), as half-widths.
SECTION_6_2_2_PSI_BOUND = 43.246
SECTION_6_2_2_SHOULDER_OPTIMUM = 0.0
SECTION_6_2_2_WRIST_OPTIMUM = 54.479
SECTION_6_2_2_OPTIMUM = 25.017
SECTION_6_2_2_THETA_AT_ZERO = (0.0, 25.666, 0.0, 82.872, 0.0, 71.463, -90.0)
SECTION_6_2_2_THETA_AT_OPTIMUM = (-32.325, 32.687, 46.864, 82.872, -24.101, 74.814, -73.709)
SECTION_6_2_2_GAMMA_FIXED = 120.0
SECTION_6_2_2_GAMMA = 147.693

# ------------------------------------------------------------------ thesis 001 (Hamada)

#: [001 section 2.4]: [001 eq. 2.3] is the product of the Table 2.1 transforms (the chain's forward kinematics), and
#: [001 section 5.1]: its wrist position X, Y, Z comes from that forward kinematics.  The thesis's claims, written as
#: the difference from the chain (relative to the sum of the link lengths): none.
SECTION_2_4_FK_DIFFERENCE = 0.0
SECTION_5_1_WRIST_DIFFERENCE = 0.0
#: [001 section 5.1]: Figs. 5.1-5.6 plot the manipulability w divided by this (w computed with lengths in mm:
#: mm^3 for one arm).
SECTION_5_1_MANIPULABILITY_DIVISOR = 1e7

# ------------------------------------------------------------------ paper 003 (Miyata et al.)

#: [003 section 4], Barrett WAM: the start posture q, degrees.
SECTION_4_Q0_DEG = (30.0, 20.0, 50.0, 70.0, 40.0, 100.0, 0.0)
#: [003 section 4]: the commanded end-point speed along x (m/s) and angular speed about y (rad/s); the paper prints
#: them again as what Fig. 1 (b), (c) show outside the singular region.
SECTION_4_LINEAR_SPEED = 0.15
SECTION_4_ANGULAR_SPEED = 0.1
#: [003 section 4]: the commanded twist (v_x, v_y, v_z, omega_x, omega_y, omega_z), m/s and rad/s.
SECTION_4_TWIST = (SECTION_4_LINEAR_SPEED, 0.0, 0.0, 0.0, SECTION_4_ANGULAR_SPEED, 0.0)
#: [003 section 4]: the threshold D_eps of the singular region |D_e| <= D_eps (printed as "D_e = 0.1"), in the
#: units of D_e (m^2).
SECTION_4_D_EPS = 0.1
#: [003 section 4]: the self-motion coefficient b_sm of [003 eq. 9] (no redundant motion: the minimum-norm joint
#: velocity); a scalar along n_sm, whose units the paper leaves open (0 in any).
SECTION_4_B_SM = 0.0
#: [003 section 4], its text on Fig. 1 (the figure's values are not in the transcription): D_e changes sign (the arm
#: passes the singularity); the rotation about +y keeps its sign through it; inside the singular region the end
#: point still moves only along x.
SECTION_4_PASSES_SINGULARITY = "yes"
SECTION_4_ROTATION_KEEPS_SIGN = "yes"
SECTION_4_TRANSLATION_ONLY_ALONG_X = "yes"

# ------------------------------------------------------------------ paper 004 (Tsuji et al.)

#: [004 section 4], Fig. 6: every joint's range, |theta_j| <= this, degrees.
FIG_6_JOINT_RANGE_DEG = 180.0
#: [004 section 4], Fig. 7: Fig. 6 (a) with |theta_4| <= 30 and |theta_5| <= 20 deg; the half-range of each
#: joint of the 5-link arm, degrees.
FIG_7_JOINT_LIMITS_DEG = (FIG_6_JOINT_RANGE_DEG,) * 3 + (30.0, 20.0)
#: [004 section 4]: in every case of Fig. 6 (a)-(d) the real end point reaches its goal.
FIG_6_END_REACHES_GOAL = "yes"
#: [004 section 4]: in every case of Fig. 8 (a)-(c) the arm reaches the goal without touching the obstacles.
FIG_8_REACHES_GOAL_CLEAR = "yes"
