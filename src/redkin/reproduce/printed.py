"""The values paper 000 prints, each written once: the "paper" column of ``redkin reproduce`` and the tests read them.

Degrees and the paper's rounding (three decimals) unless a name says
otherwise.  They are the paper's numbers, not redkin's: nothing outside
:mod:`redkin.reproduce` and the tests may read them.
"""

from __future__ import annotations

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
