"""Report section for thesis 001 (Hamada): FK agreement, IK round trips, Figs. 5.1-5.6, corrected equations."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from numpy.typing import ArrayLike

from redkin.models import HUMANOID_LENGTHS, humanoid_right_arm
from redkin.plot.torso_arm import draw_manipulability_map
from redkin.references import REFERENCES
from redkin.reproduce import Section, section_key
from redkin.reproduce import printed as P
from redkin.reproduce.comparison import Comparison, Note
from redkin.reproduce.report import SectionWriter
from redkin.torso_arm import BRANCHES, humanoid_arm, ik, redundancy_parameters
from redkin.torso_arm.branches import wrap_angle
from redkin.torso_arm.geometry import WRIST_FRAME
from redkin.torso_arm.maps import best_dual_arm_map, best_manipulability_map, plane_grid, region_above

#: Joint limits of the thesis's right arm ([001 section 5.1], as the model holds them), degrees, (8, 2).
_LIMITS_DEG = np.degrees(humanoid_right_arm().limits)

_CORRECTIONS = [
    ("2.3 (P_x, P_z)", "the L3 term closes one parenthesis early",
     "P_x = L0 c1 + L1 B - L3(-c5 A - B s5) + L2(c5 B - A s5) + L4 r13, A = c2c4s1 + (c1c3 - s1s2s3)s4, "
     "B = c3s1s2 + c1s3 (P_z likewise)"),
    ("3.1", "unsigned angle at h' = W/2: not monotone in theta_1, several roots",
     "psi = atan2(n.(s0 x s), s0.s), signed rotation about n = W/|W| (section 3.2's words); inverse "
     "theta_1 = atan2(-sgn(n_y) v_x, -sgn(n_y) v_z), v = n x u(psi); [001 eq. 3.1] kept as an option returning "
     "every root"),
    ("3.4-3.6", "every point of the elbow circle satisfies them: no reference",
     "explicit reference: theta_4 = 0 of the principal branch, i.e. root of alpha1 cos(phi) + alpha2 sin(phi) "
     "= rho with f.(z2 x u) > 0, or a fixed vector; 'no reference' reported"),
    ("3.12", "sense of rotation left open (+/-)",
     "E(phi) = h + r(cos(phi) e1 + sin(phi) n x e1): right-handed about S->W (the lower sign with the thesis's I_b)"),
    ("3.19", "only the principal root",
     "sin(theta_5 + delta) = k: theta_5 = asin(k) - delta or pi - asin(k) - delta (computed with atan2)"),
    ("3.22", f"asin gives only cos(theta_3) >= 0 (range is {_LIMITS_DEG[2, 0]:g}..{_LIMITS_DEG[2, 1]:g} deg)",
     "theta_3 = atan2(u'_x, +-|(u'_y, u'_z)|), branch flag"),
    ("3.20-3.24", "divide by sin(theta_1) and cos(theta_3)",
     "theta_2 = atan2(sgn(c3) u'_z, sgn(c3) u'_y), u' = Ry(-theta_1)(E - S)/L1"),
    ("3.25", "dimensionally inconsistent, divides by cos(theta_3)",
     "in frame 3 the forearm is (m s4, c, m c4), m = L3 c5 - L2 s5: theta_4 = atan2(sgn(m) f3_x, sgn(m) f3_z)"),
    ("3.26", f"forces |theta_4| <= 90 deg against a +-{_LIMITS_DEG[3, 1]:g} deg limit", "full-circle atan2 above"),
    ("4.6, 4.9", "do not follow from Table 2.1 (no theta_8)",
     "R58 = [[-s6c7c8 - c6s8, -s6c7s8 + c6c8, s6s7], [-s7c8, -s7s8, -c7], [s6s8 - c6c7c8, -s6c8 - c6c7s8, c6s7]]"),
    ("4.7-4.11", "single branch, no singularity",
     "theta_7 = atan2(+-|(R02, R22)|, -R12), theta_6 = atan2(sR02, sR22), theta_8 = atan2(-sR11, -sR10); "
     "sin(theta_7) = 0 reported"),
    ("3.2 text / 3.3 text", "'angle Eh'E'' is called the shoulder angle", "it is the elbow angle phi at the centre h"),
]


def _eq_2_3_position(q: np.ndarray, L: dict, L4: float) -> np.ndarray:
    """[001 eq. 2.3] position with the repaired parentheses (independent check, not the library path)."""
    c1, c2, c3, c4, c5, c6, c7 = np.cos(q[..., :7]).T
    s1, s2, s3, s4, s5, s6, s7 = np.sin(q[..., :7]).T
    L0, L1, L2, L3 = L["L0"], L["L1"], L["L2"], L["L3"]
    out = []
    for A, B, C, lead in (
        (c2 * c4 * s1 + (c1 * c3 - s1 * s2 * s3) * s4, c3 * s1 * s2 + c1 * s3,
         -c4 * (c1 * c3 - s1 * s2 * s3) + c2 * s1 * s4, L0 * c1),
        (-c4 * s2 - c2 * s3 * s4, c2 * c3, c2 * c4 * s3 - s2 * s4, 0.0 * c1),
        (c1 * c2 * c4 + (-c3 * s1 - c1 * s2 * s3) * s4, c1 * c3 * s2 - s1 * s3,
         -c4 * (-c3 * s1 - c1 * s2 * s3) + c1 * c2 * s4, -L0 * s1),
    ):
        r = c7 * (c5 * A + B * s5) - (-c6 * C - (c5 * B - A * s5) * s6) * s7
        out.append(lead + L1 * B - L3 * (-c5 * A - B * s5) + L2 * (c5 * B - A * s5) + L4 * r)
    return np.stack(out, axis=-1)


def _section_5_1(q: np.ndarray, L: dict) -> np.ndarray:
    c1, c2, c3, c4, c5 = np.cos(q[..., :5]).T
    s1, s2, s3, s4, s5 = np.sin(q[..., :5]).T
    m = L["L3"] * c5 - L["L2"] * s5
    k = L["L1"] + L["L2"] * c5 + L["L3"] * s5
    inner = c2 * c4 * m + s2 * (-s3 * s4 * m + c3 * k)
    outer = L["L0"] + c3 * s4 * m + s3 * k
    return np.stack([c1 * outer + inner * s1, -c4 * s2 * m + c2 * (-s3 * s4 * m + c3 * k), c1 * inner - outer * s1],
                    axis=-1)


def _power(value: float) -> str:
    """A power of ten as the report writes it: ``1e7``, ``1e-2``."""
    return f"1e{round(np.log10(value))}"


def build(writer: SectionWriter) -> None:
    rng = np.random.default_rng(1)
    tool = 0.1
    arm = humanoid_arm("right", tool)
    chain = arm.chain
    q = rng.uniform(-np.pi, np.pi, (2000, 8))
    frames = chain.frames(q)
    scale = sum(HUMANOID_LENGTHS.values()) + tool
    fk_error = np.abs(frames[:, -1, :3, 3] - _eq_2_3_position(q, HUMANOID_LENGTHS, tool)).max() / scale
    w_error = np.abs(frames[:, WRIST_FRAME, :3, 3] - _section_5_1(q, HUMANOID_LENGTHS)).max() / scale
    writer.text(
        "Thesis 001 models the right arm with the torso joint (Table 2.1, modified DH; "
        + ", ".join(f"{name} = {1000 * length:g}" for name, length in HUMANOID_LENGTHS.items())
        + f" mm; a tool L4 = {tool:g} m is added here). The library's forward kinematics is the "
        "DH chain; [001 eq. 2.3] and the section 5.1 wrist formula are evaluated here only as independent checks."
    )
    writer.heading("Forward kinematics against the thesis's closed forms")
    writer.comparison("fk_agreement", [
        Comparison("max |FK - [001 eq. 2.3]| / sum of lengths, 2000 random q", P.SECTION_2_4_FK_DIFFERENCE,
                   float(fk_error), 1e-9,
                   Note("[001 eq. 2.3] with the parentheses of P_x, P_z repaired",
                        "as transcribed it does not parse; see the corrections table")),
        Comparison("max |wrist - section 5.1 X,Y,Z| / sum of lengths", P.SECTION_5_1_WRIST_DIFFERENCE,
                   float(w_error), 1e-9,
                   "the section 5.1 closed form agrees with the chain as transcribed"),
    ], caption="Forward kinematics: the DH product of Table 2.1 against [001 eq. 2.3] and section 5.1",
        detail="The thesis states that its closed forms are the chain's kinematics; the printed value 0 is that "
               "claim, compared relative to the sum of the link lengths.")
    writer.progress(0.1, "fk")

    rows = []
    for side in ("right", "left"):
        side_arm = humanoid_arm(side, tool)
        lower, upper = np.maximum(side_arm.chain.lower, -np.pi), np.minimum(side_arm.chain.upper, np.pi)
        sample = rng.uniform(lower, upper, (2000, 8))
        for reference in ("theta4", "vector"):
            psi, phi, defined = redundancy_parameters(side_arm, sample, reference)
            pose = side_arm.chain.fk(sample[defined])
            sol = ik(side_arm, pose[:, :3, 3], psi[defined], phi[defined], rotation=pose[:, :3, :3],
                     reference=reference)
            fk_err = np.abs(side_arm.chain.fk(sol.q) - pose[:, None]).max(axis=(-2, -1))
            joint_err = np.abs(wrap_angle(sol.q - sample[defined][:, None])).max(axis=-1)
            owner = np.argmin(joint_err, axis=-1)
            for b, flags in enumerate(BRANCHES):
                mine = owner == b
                rows.append([side, reference, " ".join("+" if f > 0 else "-" for f in flags), int(defined.sum()),
                             int(mine.sum()), float(joint_err[mine, b].max()) if mine.any() else 0.0,
                             float(fk_err[:, b].max()), float(sol.within_limits[:, b].mean())])
    writer.heading("IK round trips")
    writer.table("ik_round_trip", ["arm", "phi reference", "branch (th3, th5, th7)", "postures with a reference",
                                   "recovered by this branch", "max joint error [rad]",
                                   "max FK error (pose matrix entries)", "fraction within limits"], rows,
                 caption="IK(FK(q)) for 2000 random postures inside the limits, per arm",
                 detail="(psi, phi) measured from q; every branch's FK equals the pose, and the original joints are "
                        "recovered by exactly the branch whose flags they carry. Postures without a theta_4 = 0 "
                        "reference are excluded from that row (reported as 'no reference').")
    writer.progress(0.3, "ik")

    right = humanoid_arm("right")
    # the thesis's plotted w: lengths in mm (1e9 mm^3 per m^3 for one arm, 1e18 mm^6 per m^6 for both), divided
    divisor = _power(P.SECTION_5_1_MANIPULABILITY_DIVISOR)
    one_arm = 1e9 / P.SECTION_5_1_MANIPULABILITY_DIVISOR
    both_arms = 1e18 / P.SECTION_5_1_MANIPULABILITY_DIVISOR
    slices = [
        ("5.1", "Right-Arm Manipulability (X <= 0)", "x=-0.2", (-0.4, 1.0, -0.9, 0.9)),
        ("5.2", "Right-Arm Manipulability (Y >= 0)", "y=0.3", (-0.3, 1.1, -0.9, 0.9)),
        ("5.3", "Right-Arm Manipulability (Z <= 0)", "z=-0.3", (-0.3, 1.1, -0.6, 1.1)),
    ]
    writer.heading("Manipulability maps (Figs. 5.1-5.6)")
    writer.text(
        "Figs. 5.1-5.6 are not in the transcription (only their captions, which name half-spaces X <= 0, Y >= 0, "
        "Z <= 0). We recompute maps on the planes x = -0.2 m, y = 0.3 m and z = -0.3 m, inside those half-spaces, "
        "and, because w depends on the redundancy which the thesis does not state, plot the best w over the "
        "redundancy within the joint limits of joints 1-5 (theta_1 swept over its limits x phi over the full circle, "
        f"24 x 24 samples). Units: the thesis divides w by {divisor} with lengths in mm, so its plotted value is "
        f"w_mm / {divisor} = {one_arm:g} w_SI for one arm (w in m^3; our Figs. 5.1-5.3 are in these units, "
        f"{_power(1 / one_arm)} m^3) and {_power(both_arms)} w_SI "
        "for our dual-arm measure (m^6; Figs. 5.4-5.6 and the table give it in SI). Dual arm: the "
        "thesis gives no definition; ours is sqrt(det(J J^T)) of the stacked 6 x 9 Jacobian of both wrists w.r.t. "
        "the shared theta_1 and both arms' joints 2-5, in the symmetric posture (left arm = mirror image of the right "
        "in the torso mid-plane), indexed by the right wrist. Both wrists at one point is impossible within the limits "
        "(theta_3 >= -5 deg keeps each wrist >= 17 mm on its own side of the mid-plane)."
    )
    landmarks: dict[str, ArrayLike] = {
        "neck": [0.0, 0.0, 0.0], "R shoulder": right.shoulder(0.0), "L shoulder": -right.shoulder(0.0),
    }
    summary = []
    for index, dual in enumerate((False, True)):
        for k, (fig_no, title, plane, extent) in enumerate(slices):
            grid = plane_grid(plane, extent, 60)
            if dual:
                result = best_dual_arm_map(grid, (20, 20))
                name, unit, factor = f"fig_5_{k + 4}", "m^6", 1.0
                title = title.replace("Right-Arm", "Dual-Arm")
                fig_no = f"5.{k + 4}"
            else:
                result = best_manipulability_map(right, grid, (24, 24))
                name, unit, factor = f"fig_5_{k + 1}", f"{_power(1 / one_arm)} m^3 (thesis units)", one_arm
            fig, ax = plt.subplots(figsize=(6, 5))
            top = float(np.nanmax(result.values)) if result.valid.any() else 0.0
            draw_manipulability_map(ax, result, landmarks, unit=unit, scale=factor, threshold=0.5 * top * factor)
            writer.figure(fig, name, f"Fig. {fig_no} recomputed: {title}, plane {plane}",
                          "White contour: w = half the maximum; red: the neck and shoulders projected onto the plane.")
            region = region_above(result, 0.5 * top)
            summary.append([fig_no, plane, float(result.valid.mean()), top, float(region.area)])
            writer.progress(0.3 + 0.11 * (3 * index + k + 1), name)
    writer.table("maps", ["figure", "plane", "fraction of grid reachable within limits",
                          "max w [m^3 one arm, m^6 both]", "area with w >= max/2 [m^2]"], summary,
                 caption="Our recomputed maps, best over the redundancy within limits",
                 detail=f"The thesis prints no values to compare. w in SI: m^3 for one arm (Figs. 5.1-5.3: {one_arm:g} "
                        f"times these in thesis units), m^6 for both arms (5.4-5.6: {_power(both_arms)} times).")
    writer.comparison("map_values", [
        Comparison("Figs. 5.1-5.6 values", None, "see table 'maps'", 0.0,
                   "the figures are missing from the transcription; no number can be compared"),
    ], caption="Figs. 5.1-5.6: what can be compared")
    writer.heading("Equations we corrected")
    writer.table("corrections", ["equation", "problem", "corrected form used"], [list(c) for c in _CORRECTIONS],
                 caption="Every equation of thesis 001 we had to correct, and the form implemented",
                 detail="Each corrected form is tested in tests/test_torso_arm_*.py.")


SECTION = Section(
    key=section_key(__name__),
    title="Thesis 001: the 8-DOF dual-arm humanoid (shoulder/elbow-angle IK, wrist IK, manipulability maps)",
    reference=REFERENCES["001"],
    build=build,
)
