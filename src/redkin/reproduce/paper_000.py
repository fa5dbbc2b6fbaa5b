"""Report section for paper 000 (Shimizu et al.): section 6 recomputed on the PA10-7C."""

from __future__ import annotations

import dataclasses

import matplotlib.pyplot as plt
import numpy as np

from redkin.circle import ArcSet
from redkin.explore import explorer_data, explorer_html
from redkin.models import pa10_7c
from redkin.paths import (
    BaselinePath,
    PathResult,
    clamped_optimum_path,
    feasible_along_path,
    fixed_psi_path,
    greedy_path,
    judge_path,
    resolve_path,
)
from redkin.plot.arm import draw_arm_3d, set_equal_3d
from redkin.plot.paths import path_plane_figure
from redkin.plot.srs import plot_joint_curves, plot_reachable_rotations
from redkin.references import REFERENCES
from redkin.reproduce import Section, section_key
from redkin.reproduce import printed as P
from redkin.reproduce.comparison import Comparison, Note
from redkin.reproduce.report import SectionWriter
from redkin.srs import (
    arm_angle_of,
    arm_angle_path,
    feasible_arm_angles,
    ik,
    optimal_arm_angles,
    pose_from,
    singular_arm_angles,
)
from redkin.srs.geometry import srs_geometry

TOL = 5e-4  # half of the last printed digit (3 decimals, degrees)
PSI = np.linspace(-np.pi, np.pi, 1441)
#: The bound on each joint's move per waypoint of the section 6.2.2 sweep walked as a path (1 deg of tool
#: rotation per waypoint), degrees.
_SWEEP_STEP_DEG = 2.0
#: The constructed path beside it: a straight joint-space line of the PA10 between these configurations
#: (degrees, branch +++ all along), its waypoints and its bound (degrees per waypoint).
_LINE_START_DEG = (47.0, 5.0, -79.0, 106.0, 51.0, 36.0, 52.0)
_LINE_END_DEG = (-7.0, 11.0, 111.0, 123.0, -51.0, 22.0, 82.0)
_LINE_WAYPOINTS = 40
_LINE_STEP_DEG = 5.0
#: Limits of motion assumed to time the paths (the paper gives none, and we hold no maker's figure of the PA10's):
#: rad/s and rad/s^2 on every joint.
_ASSUMED_SPEED, _ASSUMED_ACCELERATION = 1.0, 5.0
#: The seam that needs one reconfiguration: the tool swept about the base as joint 1 turns from and to these values
#: (radians) with the rest of the arm at _SEAM_POSTURE_DEG, past joint 1's +-90 deg; waypoints, bound (deg).
_SEAM_JOINT1 = (-1.4, 2.6)
_SEAM_POSTURE_DEG = (0.0, 30.0, 0.0, 90.0, 0.0, 40.0, 0.0)
_SEAM_WAYPOINTS = 66
_SEAM_STEP_DEG = 5.0


def _deg(value):
    return None if value is None else float(np.degrees(value))


def _gamma_pose(gamma: float) -> np.ndarray:
    rotation = np.array([[-np.cos(gamma), -np.sin(gamma), 0.0], [-np.sin(gamma), np.cos(gamma), 0.0], [0.0, 0.0, -1.0]])
    return pose_from(np.array([0.65, 0.0, 0.5]), rotation)


def _boundary(predicate, low: float, high: float, steps: int = 60) -> float:
    """Largest gamma in [low, high] with predicate true, by bisection (predicate true at low, false at high)."""
    for _ in range(steps):
        middle = 0.5 * (low + high)
        low, high = (middle, high) if predicate(middle) else (low, middle)
    return low


def _arc_text(arc_set: ArcSet) -> str:
    if arc_set.is_empty:
        return "empty"
    return " U ".join(f"[{np.degrees(lo):.3f}, {np.degrees(hi):.3f}]" for lo, hi in arc_set.arcs)


def _explorer_link(writer: SectionWriter, chain, pose: np.ndarray, name: str, label: str, **options) -> None:
    """Write the arm-angle explorer of ``pose`` beside the report (angles in degrees) and link it."""
    writer.page(name, explorer_html(explorer_data(chain, pose, **options), degrees=True), label)


def _section_6_1(writer: SectionWriter, chain) -> None:
    writer.heading("§6.1: feasible arm angles and postures ([000 eq. 41])")
    pose = pose_from(np.array([0.65, 0.0, 0.5]), np.diag([-1.0, 1.0, -1.0]))
    result = feasible_arm_angles(chain, pose, "+++")
    rows = []
    printed = {joint: (-bound, bound) if bound is not None else (-180, 180)
               for joint, bound in P.SECTION_6_1_JOINT_BOUNDS.items()}
    for joint, (lo, hi) in printed.items():
        ours = result.per_joint[joint]
        arcs = [(-np.pi, np.pi)] if ours.is_full else ours.arcs
        rows.append(Comparison(f"Psi_{joint} lower [deg]", lo, _deg(arcs[0][0]) if arcs else None, TOL,
                               "" if len(arcs) == 1 else f"ours: {_arc_text(ours)}"))
        rows.append(Comparison(f"Psi_{joint} upper [deg]", hi, _deg(arcs[0][1]) if arcs else None, TOL))
    lo, hi = result.feasible.arcs[0]
    rows += [Comparison("Psi lower [deg]", -P.SECTION_6_1_PSI_BOUND, _deg(lo), TOL),
             Comparison("Psi upper [deg]", P.SECTION_6_1_PSI_BOUND, _deg(hi), TOL)]
    paper_theta = {
        "psi = 0": (0.0, list(P.SECTION_6_1_THETA_AT_ZERO)),
        "psi_min": (lo, list(P.SECTION_6_1_THETA_AT_PSI_MIN)),
        "psi_max": (hi, [v if k in (1, 3, 5) else -v for k, v in enumerate(P.SECTION_6_1_THETA_AT_PSI_MIN)]),
    }
    postures = {}
    for name, (psi, values) in paper_theta.items():
        q = ik(chain, pose, psi, "+++")
        postures[name] = q
        for i, value in enumerate(values):
            rows.append(Comparison(f"theta_{i + 1} at {name} [deg]", value, float(np.degrees(q[i])), TOL))
    writer.comparison(
        "s6_1", rows, "Section 6.1: feasible sets and joint values",
        "x = (0.65, 0, 0.5) m, R = diag(-1, 1, -1), branch +++ (theta2, theta4, theta6 > 0). psi is right-handed "
        "about shoulder -> wrist and the reference is theta3 = 0 with theta1o = atan2(y_sw, x_sw).",
    )
    theta = ik(chain, np.broadcast_to(pose, PSI.shape + (4, 4)), PSI, "+++")
    geometry = srs_geometry(chain)
    fig, axes = plt.subplots(6, 1, figsize=(7, 11), sharex=True)
    plot_joint_curves(axes, PSI, theta, geometry.theta_lower, geometry.theta_upper, result.per_joint, result.feasible)
    writer.figure(fig, "theta_of_psi_6_1", "theta_i(psi) for the pose of [000 eq. 41] (Figs. 3, 4 style)",
                  "Limits dashed, Psi_i shaded green, the overall feasible set Psi shaded blue.")
    fig = plt.figure(figsize=(6, 5))
    ax = fig.add_subplot(111, projection="3d")
    for (name, q), color in zip(postures.items(), ("C0", "C1", "C2")):
        draw_arm_3d(ax, chain, q, color=color, label=name)
    set_equal_3d(ax, np.concatenate([chain.frames(q)[:, :3, 3] for q in postures.values()]))
    ax.legend(fontsize=8, loc="upper left")
    writer.figure(fig, "postures_6_1", "Postures at psi = 0, psi_min and psi_max (paper Fig. 6)",
                  "The pose of [000 eq. 41]; each posture drawn through its frame origins, with the tool frame.")
    _explorer_link(writer, chain, pose, "explore_6_1",
                   "Explore §6.1 live: the arm angle on a slider, all eight branches")


def _section_6_2_1(writer: SectionWriter, chain) -> None:
    writer.heading("§6.2.1: singular arm angles")
    pose = pose_from(np.array([0.55, 0.0, 0.767]), np.array([[0, 0, 1], [0, 1, 0], [-1, 0, 0.0]]))
    singular = singular_arm_angles(chain, pose, "+++")
    a, b, c = singular.shoulder_coefficients
    aw, bw, cw = singular.wrist_coefficients
    plus = feasible_arm_angles(chain, pose, "+++").feasible
    other = feasible_arm_angles(chain, pose, "++-").feasible
    rows = [
        *(Comparison(name, printed, value, TOL) for name, printed, value in zip(
            ("a_s32", "b_s32", "c_s32", "a_w33", "b_w33", "c_w33"),
            P.SECTION_6_2_1_SHOULDER_COEFFICIENTS + P.SECTION_6_2_1_WRIST_COEFFICIENTS, (a, b, c, aw, bw, cw))),
        Comparison("[000 eq. 31] residual", 0.0, singular.shoulder_residual, 1e-12, "shoulder singularity exists"),
        Comparison("[000 eq. 33] residual", 0.0, singular.wrist_residual, 1e-12, "wrist singularity exists"),
        Comparison("shoulder singular psi [deg]", 0.0, _deg(singular.shoulder[0]), TOL),
        Comparison("wrist singular psi [deg]", 0.0, _deg(singular.wrist[0]), TOL),
        Comparison("Psi, branch +++", f"[{-P.SECTION_6_2_1_PSI_BOUND}, {P.SECTION_6_2_1_PSI_BOUND}]", _arc_text(plus),
                   note=Note("the printed set belongs to branch ++- (theta6 < 0)",
                             "the +++ branch is empty here (theta5 exceeds its limit for every psi); the next two "
                             "rows compare the printed set with branch ++-")),
        Comparison("Psi, branch ++- (theta6 < 0) lower [deg]", -P.SECTION_6_2_1_PSI_BOUND,
                   _deg(other.arcs[0][0]) if not other.is_empty else None, TOL),
        Comparison("Psi, branch ++- (theta6 < 0) upper [deg]", P.SECTION_6_2_1_PSI_BOUND,
                   _deg(other.arcs[0][1]) if not other.is_empty else None, TOL),
    ]
    writer.comparison("s6_2_1", rows, "Section 6.2.1: singularity coefficients and the feasible set",
                      "x = (0.55, 0, 0.767) m, R = [[0,0,1],[0,1,0],[-1,0,0]].")
    _explorer_link(writer, chain, pose, "explore_6_2_1", "Explore §6.2.1 live (branch +++ is empty; choose ++- "
                  "for the printed set)")


def _section_6_2_2(writer: SectionWriter, chain) -> None:
    writer.heading("§6.2.2: optimal arm angles and reachable tool rotations")
    pose = _gamma_pose(np.pi / 2)
    target = np.radians([0, 90, 0, 0, 0, 90, 0])
    feasible = feasible_arm_angles(chain, pose, "+++").feasible
    optimal = optimal_arm_angles(chain, pose, "+++", target=target, weights=(0.5, 0.5), feasible=feasible)
    default = optimal_arm_angles(chain, pose, "+++", weights=(0.5, 0.5), feasible=feasible)
    theta0 = ik(chain, pose, 0.0, "+++")
    psi_opt = optimal.overall.feasible
    if psi_opt is None:  # the paper's pose has a feasible optimum; a changed pose or limits must say so
        raise RuntimeError("the optimal arm angle of the paper's pose has no feasible arm angle to clamp to")
    theta_opt = ik(chain, pose, psi_opt, "+++")
    lo, hi = feasible.arcs[0]
    misprint = Note("misprint in the paper: its own Gamma = 147.693 needs psi = 45.991 to be feasible",
                    "the printed [-43.246, 43.246] is a misprint: turning the tool about z leaves x_sw as in 6.1, so "
                    "theta2 reaches its 45 deg limit at psi = +-45.991 exactly as there, and the paper's own "
                    "Gamma = 147.693 = 120 + 27.693 needs psi = 45.991 (where theta7 = 27.693 in 6.1) to be feasible")
    rows = [
        Comparison("Psi lower [deg]", -P.SECTION_6_2_2_PSI_BOUND, _deg(lo), TOL, misprint),
        Comparison("Psi upper [deg]", P.SECTION_6_2_2_PSI_BOUND, _deg(hi), TOL, misprint),
        Comparison("psi_s^opt [deg] ([000 eq. 37])", P.SECTION_6_2_2_SHOULDER_OPTIMUM,
                   _deg(optimal.shoulder.unclamped), TOL,
                   Note("targets theta^d = (0, 90, 0, -, 0, 90, 0) deg", "the paper does not state them")),
        Comparison("psi_w^opt [deg] ([000 eq. 39])", P.SECTION_6_2_2_WRIST_OPTIMUM, _deg(optimal.wrist.unclamped), TOL),
        Comparison("psi^opt [deg] ([000 eq. 40], r_s = r_w = 0.5)", P.SECTION_6_2_2_OPTIMUM,
                   _deg(optimal.overall.unclamped), TOL),
        Comparison("psi_w^opt clamped to Psi [deg]", P.SECTION_6_2_2_PSI_BOUND, _deg(optimal.wrist.feasible), TOL,
                   Note("the paper clamps to its misprinted bound",
                        "ours is clamped to the end of our feasible set (45.991), see the misprint note")),
        Comparison("psi^opt with default targets (limit midpoints) [deg]", None, _deg(default.overall.unclamped),
                   note="for comparison: with limit-midpoint targets the optimum moves"),
    ]
    for i, value in enumerate(P.SECTION_6_2_2_THETA_AT_ZERO):
        rows.append(Comparison(f"theta_{i + 1} at psi = 0 [deg]", value, float(np.degrees(theta0[i])), TOL))
    for i, value in enumerate(P.SECTION_6_2_2_THETA_AT_OPTIMUM):
        rows.append(Comparison(f"theta_{i + 1} at psi^opt [deg]", value, float(np.degrees(theta_opt[i])), TOL))
    rows.append(Comparison("max |theta| at psi = 0 [deg]", max(map(abs, P.SECTION_6_2_2_THETA_AT_ZERO)),
                           float(np.degrees(np.abs(theta0).max())), TOL))
    rows.append(Comparison("max |theta| at psi^opt [deg]",
                           max(abs(v) for k, v in enumerate(P.SECTION_6_2_2_THETA_AT_OPTIMUM) if k != 3),
                           float(np.degrees(np.abs(np.delete(theta_opt, 3)).max())), TOL,
                           "elbow theta4 = 82.872 is excluded, as in the paper's statement"))
    # reachable tool rotations: psi fixed at 0 (Gamma_0) versus controlled by [000 eq. 40] and clamped (Gamma)
    def fixed_ok(g: float) -> bool:
        return bool(feasible_arm_angles(chain, _gamma_pose(g), "+++").feasible.contains(0.0))

    def controlled_ok(g: float) -> bool:
        return not feasible_arm_angles(chain, _gamma_pose(g), "+++").is_empty

    gamma0 = _boundary(fixed_ok, 0.0, np.pi)
    gamma = _boundary(controlled_ok, 0.0, np.pi)
    gamma0_neg = -_boundary(lambda g: fixed_ok(-g), 0.0, np.pi)
    gamma_neg = -_boundary(lambda g: controlled_ok(-g), 0.0, np.pi)
    rows += [
        Comparison("Gamma_0 lower [deg] (psi = 0)", -P.SECTION_6_2_2_GAMMA_FIXED, _deg(gamma0_neg), TOL),
        Comparison("Gamma_0 upper [deg] (psi = 0)", P.SECTION_6_2_2_GAMMA_FIXED, _deg(gamma0), TOL),
        Comparison("Gamma lower [deg] (psi controlled)", -P.SECTION_6_2_2_GAMMA, _deg(gamma_neg), TOL,
                   "boundary where the feasible set becomes empty, found by bisection on our exact sets"),
        Comparison("Gamma upper [deg] (psi controlled)", P.SECTION_6_2_2_GAMMA, _deg(gamma), TOL),
    ]
    writer.comparison("s6_2_2", rows, "Section 6.2.2: feasible set, optimal arm angles, reachable rotations",
                      "x = (0.65, 0, 0.5) m, R as [000 eq. 41] turned by gamma = 90 deg about z, branch +++.")
    gammas = np.radians(np.arange(-179.0, 180.0, 1.0))
    poses = np.array([_gamma_pose(g) for g in gammas])
    controlled = arm_angle_path(chain, poses, "+++", target=target)
    fixed = arm_angle_path(chain, poses, "+++", fixed_psi=0.0)
    fig, ax = plt.subplots(figsize=(7, 4))
    plot_reachable_rotations(ax, gammas, [f.feasible for f in controlled.feasible], controlled.psi,
                             controlled.reachable, 0.0, fixed.reachable)
    writer.figure(fig, "reachable_gamma", "Feasible arm angles over the tool rotation gamma (section 6.2.2)",
                  "Green: the feasible arm angles; red: psi fixed at 0 (Gamma_0); blue: psi from [000 eq. 40] clamped "
                  "to the feasible set (Gamma).")
    _explorer_link(writer, chain, pose, "explore_6_2_2",
                   "Explore §6.2.2 live (optimal arm angle for the targets above)", target=target)
    _section_6_2_2_paths(writer, chain, target, gamma)


def _failure_words(path: BaselinePath) -> str:
    """Where ``path`` first fails, why, the joint and by how much (degrees), or that it does not."""
    k = path.first_failure
    if k is None:
        return "none: every limit and the bound kept"
    text = f"waypoint {k}: {path.reason}"
    if path.joint is not None:
        text += f", joint {path.joint}"
    if path.excess is not None and path.reason in ("limit", "step"):
        text += f" by {np.degrees(path.excess):.4f} deg"
    return text


def _walk_rows(walk: str, step_deg: float, paths: list[BaselinePath]) -> list[list]:
    """One table row per way of choosing the arm angle: where it first fails, how many waypoints keep the limits,
    the smallest clearance and the largest step."""
    return [[walk, path.method, _failure_words(path), f"{int(path.within_limits.sum())} of {len(path.q)}",
             float(np.degrees(np.nanmin(path.clearance))), float(np.nanmax(path.jump) * step_deg),
             float(np.nanmax(path.jump))] for path in paths]


def _walk(chain, poses: np.ndarray, step_deg: float, start: tuple[float, str], target: np.ndarray,
          result: PathResult) -> list[BaselinePath]:
    """Gamma_0 (the arm angle held at ``start``), Gamma (the clamped optimum of [000 eq. 40] for ``target``),
    greedy tracking and the global path, all judged alike (:func:`redkin.paths.judge_path`)."""
    step = np.radians(step_deg)
    psi, branch = start
    fixed = fixed_psi_path(chain, poses, step, psi, branch)
    clamped = clamped_optimum_path(chain, poses, step, branch, target=target)
    paths = [dataclasses.replace(fixed, method=f"Gamma_0: psi held at {np.degrees(psi):.3f} deg"),
             dataclasses.replace(clamped, method="Gamma: psi^opt [000 eq. 40] clamped per pose"),
             dataclasses.replace(greedy_path(chain, poses, step), method="greedy seeded tracking")]
    if result.ok:
        paths.append(judge_path(chain, result.q, step, poses, "global path (redkin.paths.resolve_path)",
                                result.psi, result.branch))
    return paths


def _walk_words(name: str, result: PathResult, paths: list[BaselinePath]) -> str:
    """One sentence per path of a walk, from its numbers."""
    words = [path.method.split(":")[0] + (" keeps every limit and the bound" if path.ok else
                                          f" fails at {_failure_words(path)}") for path in paths[:3]]
    text = f"On the {name}: " + "; ".join(words) + ". "
    if not result.ok:
        assert result.failure is not None
        return text + f"No global path exists: {result.failure.message}."
    changes = [k for k in range(1, len(result.branch)) if result.branch[k] != result.branch[k - 1]]
    text += (f"The global path keeps every limit and the bound with a smallest clearance of "
             f"{np.degrees(result.clearance):.3f} deg")
    if result.optimal:
        text += (f", proved the largest any path keeps (the exact feasible sets of waypoint {result.bottleneck}, "
                 "with every limit moved that far in, are empty on every branch)")
    if changes:
        text += ", changing branch " + ", ".join(f"{result.branch[k - 1]} -> {result.branch[k]} at waypoint {k}"
                                                for k in changes)
        text += " (through a singular configuration: the joints stay within the bound)"
    return text + "."


def _section_6_2_2_paths(writer: SectionWriter, chain, target: np.ndarray, gamma: float) -> None:
    """The 6.2.2 sweep and a constructed line walked as paths: Gamma_0 and Gamma beside the global path."""
    writer.heading("§6.2.2 extended: the arm angle chosen over the whole path (redkin)")
    writer.text(
        "Section 6.2.2 chooses the arm angle one pose at a time: held at 0 (Gamma_0) or set to the optimum of "
        "[000 eq. 40] clamped to the feasible set (Gamma). Walked as a path, a choice must also be continuous: here "
        "no joint may move more than a bound between waypoints. redkin.paths.resolve_path chooses the branch and "
        "arm angle of every waypoint together, inside the exact feasible sets, as far from the limits as the path "
        "allows (the largest smallest clearance, then the least motion; docs/paths.md). This is redkin's extension "
        "beyond paper 000 (issue 26): the paper prints no value for it, so the rows below have nothing to compare "
        "with. Greedy seeded tracking (at each waypoint the in-limit solution nearest the last, as ssik ranks them) "
        "is shown beside them. Each path is judged alike: every pose reached within 1e-9, every joint within its "
        "Table 2 limits, no joint moving more than the bound."
    )
    limit = int(np.floor(np.degrees(gamma)))
    sweep = np.array([_gamma_pose(g) for g in np.radians(np.arange(-limit, limit + 1, 1.0))])
    sweep_result = resolve_path(chain, sweep, np.radians(_SWEEP_STEP_DEG))
    sweep_paths = _walk(chain, sweep, _SWEEP_STEP_DEG, (0.0, "+++"), target, sweep_result)
    a, b = np.radians(_LINE_START_DEG), np.radians(_LINE_END_DEG)
    q_line = a + (b - a) * np.linspace(0.0, 1.0, _LINE_WAYPOINTS)[:, None]
    line = chain.fk(q_line)
    own = np.degrees(judge_path(chain, q_line, np.radians(_LINE_STEP_DEG), line).clearance.min())
    state = arm_angle_of(chain, a)
    line_result = resolve_path(chain, line, np.radians(_LINE_STEP_DEG))
    line_paths = _walk(chain, line, _LINE_STEP_DEG, (float(state.psi), str(state.branch_strings())), target,
                       line_result)
    rows = (_walk_rows(f"sweep: gamma = -{limit} .. {limit} deg", _SWEEP_STEP_DEG, sweep_paths)
            + _walk_rows("constructed: a joint-space line", _LINE_STEP_DEG, line_paths))
    writer.table(
        "s6_2_2_paths", ["path", "arm angle chosen by", "first failure", "waypoints within limits",
                         "smallest clearance [deg]", "largest step [deg]", "largest step / bound"], rows,
        caption="Section 6.2.2 walked as paths: Gamma_0 and Gamma beside the global path",
        detail=f"Sweep: the poses of section 6.2.2 at every whole degree of gamma inside Gamma = "
               f"+-{np.degrees(gamma):.3f} deg (only branch +++ has feasible arm angles there), one waypoint per "
               f"degree, a bound of {_SWEEP_STEP_DEG:g} deg per joint and waypoint; Gamma_0 holds psi = 0 as the "
               f"paper does. Constructed: the PA10's poses along the straight joint-space line from "
               f"{_LINE_START_DEG} to {_LINE_END_DEG} deg ({_LINE_WAYPOINTS} waypoints on branch +++, the line's own "
               f"smallest clearance {own:.3f} deg), a bound of {_LINE_STEP_DEG:g} deg; Gamma_0 holds the arm angle "
               "of its first pose. Gamma uses the targets above on branch +++. Clearance: the smallest distance of a "
               "joint to a limit over the path (negative: outside); the largest step is over all joints and "
               "waypoints; first failure: the first waypoint that breaks a limit (limit) or is reached by a move "
               "over the bound (step), the joint and by how much.")
    writer.text(_walk_words("sweep", sweep_result, sweep_paths) + " "
                + _walk_words(f"constructed line (its own clearance {own:.3f} deg)", line_result, line_paths))
    _timed_paths(writer, chain, [("sweep", sweep_result), ("constructed line", line_result)])
    for name, poses, result, paths, caption in (
            ("paths_sweep", sweep, sweep_result, sweep_paths,
             f"The sweep of section 6.2.2 as a path (waypoint k is gamma = {-limit} + k deg)"),
            ("paths_line", line, line_result, line_paths, "The constructed joint-space line as a path")):
        fig = path_plane_figure(feasible_along_path(chain, poses), result, paths[:3], title=f"PA10-7C: {caption}")
        writer.figure(fig, name, caption,
                      "Green: the exact feasible arm angles of each waypoint and branch; black: the global path "
                      "(redkin.paths.resolve_path), a diamond where it changes branch; dashed: Gamma_0, Gamma and "
                      "greedy tracking, a cross where each first breaks a limit or the bound.")


def _timed_paths(writer: SectionWriter, chain, paths: list[tuple[str, PathResult]]) -> None:
    """The paths above timed within assumed limits of motion, and a seam that needs one reconfiguration stop."""
    from redkin.errors import RedkinError
    from redkin.paths.stops import timed
    from redkin.paths.timing import DEFAULT_RATE

    writer.heading("§6.2.2 extended: timed, and the fewest reconfigurations (redkin)")
    limited = chain.with_motion_limits(velocity=np.full(7, _ASSUMED_SPEED),
                                       acceleration=np.full(7, _ASSUMED_ACCELERATION))
    a, b = _SEAM_JOINT1
    q_seam = np.tile(np.radians(_SEAM_POSTURE_DEG), (_SEAM_WAYPOINTS, 1))
    q_seam[:, 0] = np.linspace(a, b, _SEAM_WAYPOINTS)
    seam = chain.fk(q_seam)
    step = np.radians(_SEAM_STEP_DEG)
    plain = resolve_path(limited, seam, step)
    stopped = resolve_path(limited, seam, step, allow_stops=True)
    assumed = (f"{_ASSUMED_SPEED:g} rad/s and {_ASSUMED_ACCELERATION:g} rad/s^2 on every joint, assumed: the paper "
               "gives no limits of motion, and we hold no maker's figure for the PA10's")
    seam_words = (f"The seam: the tool swept about the base as joint 1 would turn from {np.degrees(a):.1f} to "
                  f"{np.degrees(b):.1f} deg, past its +-90 deg ({_SEAM_WAYPOINTS} waypoints, a bound of "
                  f"{_SEAM_STEP_DEG:g} deg). Without stops: ")
    seam_words += "a continuous path exists. " if plain.failure is None else f"{plain.failure.message}. "
    if stopped.failure is None:
        count = len(stopped.stops)
        seam_words += (f"With stops allowed: {count} stop{'' if count == 1 else 's'}: "
                       + "; ".join(stop.message for stop in stopped.stops) + ".")
    else:
        seam_words += f"With stops allowed too, {stopped.failure.message}."
    rows = []
    try:
        for name, result in paths + [("seam, with stops", stopped)]:
            trajectory = timed(limited, result, DEFAULT_RATE).trajectory
            if trajectory is None:
                continue
            rows.append([name, len(result.q), len(result.stops), trajectory.duration, len(trajectory.t),
                         float(np.abs(trajectory.qd / limited.velocity).max()),
                         float(np.abs(trajectory.qdd / limited.acceleration).max()), trajectory.interpolation])
    except RedkinError as exc:  # the timing extra (toppra) is not installed
        writer.text(f"Timing: {exc}. {seam_words}")
        return
    writer.text(
        "A robot runs a trajectory, not joint values per waypoint. redkin.paths.time_path (redkin path --timed) "
        "times each path with TOPP-RA along the cubic spline through its waypoints (PCHIP where the spline would "
        f"leave a joint's range), within {assumed}, sampled at {DEFAULT_RATE:g} Hz; every sample is checked against "
        "the limits (docs/paths.md). Where no continuous path exists, redkin path --allow-stops returns the "
        "fewest continuous segments joined by reconfiguration stops, where the arm rests and reconfigures. "
        + seam_words)
    writer.table("s6_2_2_timed", ["path", "waypoints", "stops", "duration [s]", "samples", "max |qd| / limit",
                                  "max |qdd| / limit", "joint path"], rows,
                 caption="The paths timed within the assumed limits of motion",
                 detail=f"Limits: {assumed}. The largest |qd| and |qdd| over every sample, relative to the limit "
                        "(at most 1; the solver works 0.1 % inside). Joint path: the cubic spline, or PCHIP where the "
                        "spline would leave a joint's range.")


def build(writer: SectionWriter) -> None:
    writer.text(
        "Closed-form arm-angle inverse kinematics of the 7-DOF S-R-S PA10-7C with the Table 2 joint limits. "
        "Every number of section 6 beside ours (degrees). Our feasible sets are exact unions of arcs computed "
        "from the roots of theta_i(psi) = limit ([000 eqs. 21, 22]), tested against dense sampling with an FK check."
    )
    chain = pa10_7c()
    _section_6_1(writer, chain)
    writer.progress(0.4, "6.1")
    _section_6_2_1(writer, chain)
    writer.progress(0.5, "6.2.1")
    _section_6_2_2(writer, chain)


SECTION = Section(
    key=section_key(__name__),
    title="Paper 000: analytical IK of 7-DOF manipulators with joint limits",
    reference=REFERENCES["000"],
    build=build,
)
