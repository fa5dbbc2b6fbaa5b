"""Report section: the robot models, drawn, with their parameter tables, a Franka case over q7 and a worked cell
(:mod:`redkin.reproduce.cell_case`)."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from redkin.explore import explorer_data, explorer_html
from redkin.franka import BRANCHES, feasible_q7, ik
from redkin.models import MODELS, franka_fr3
from redkin.plot.arm import draw_arm_2d, draw_arm_3d, set_equal_3d
from redkin.plot.franka import plot_q7_curves
from redkin.reproduce import Section, section_key
from redkin.reproduce.cell_case import cell_case
from redkin.reproduce.report import SectionWriter
from redkin.srs import parse_branch

#: The Franka case: the FR3 at its "ready" configuration [rad], and the branch of that configuration drawn.
_FRANKA_READY = np.array([0.0, -np.pi / 4, 0.0, -3 * np.pi / 4, 0.0, np.pi / 2, np.pi / 4])
_FRANKA_BRANCH = "--+"
#: Values of q7 on the figure's grid (before the arc ends are merged in).
_Q7_SAMPLES = 1441


def build(writer: SectionWriter) -> None:
    writer.text(
        "Every named model of redkin with the source of its numbers, drawn at q = 0 and at a "
        "second configuration inside its limits. Angles in degrees, lengths in metres; a dash marks no limit."
    )
    rng = np.random.default_rng(0)
    for index, (name, factory) in enumerate(MODELS.items()):
        chain = factory()
        rows = []
        for i in range(chain.n):
            rows.append([
                i + 1, chain.a[i], np.degrees(chain.alpha[i]), chain.d[i],
                np.degrees(chain.offset[i]), int(chain.sign[i]),
                _limit(chain.lower[i]), _limit(chain.upper[i]),
            ])
        alpha_name = "alpha_i-1" if chain.convention == "mdh" else "alpha_i"
        a_name = "a_i-1" if chain.convention == "mdh" else "a_i"
        writer.heading(name)
        writer.table(
            f"{name}_parameters",
            ["joint", f"{a_name} [m]", f"{alpha_name} [deg]", "d_i [m]", "theta offset [deg]", "sign",
             "lower [deg]", "upper [deg]"],
            rows,
            caption=f"{name}: {'modified' if chain.convention == 'mdh' else 'standard'} DH parameters",
            detail=f"Source: {chain.source}",
        )
        lower = np.where(np.isfinite(chain.lower), chain.lower, -np.pi)
        upper = np.where(np.isfinite(chain.upper), chain.upper, np.pi)
        q_sample = lower + (upper - lower) * rng.uniform(0.3, 0.7, chain.n)
        fig = plt.figure(figsize=(5, 4.5))
        if name.startswith("planar"):
            ax = fig.add_subplot(111)
            draw_arm_2d(ax, chain, np.zeros(chain.n), color="C0", label="q = 0")
            draw_arm_2d(ax, chain, q_sample, color="C1", label="sample q")
            ax.set_aspect("equal")
            ax.set_xlabel("x [m]")
            ax.set_ylabel("y [m]")
        else:
            ax = fig.add_subplot(111, projection="3d")
            draw_arm_3d(ax, chain, np.zeros(chain.n), color="C0", label="q = 0")
            draw_arm_3d(ax, chain, q_sample, color="C1", label="sample q")
            points = np.concatenate([chain.frames(np.zeros(chain.n))[:, :3, 3], chain.frames(q_sample)[:, :3, 3]])
            set_equal_3d(ax, points)
            if name.startswith("humanoid"):
                ax.view_init(elev=15, azim=30, vertical_axis="y")  # the torso axis is +y
        ax.legend(loc="upper left", fontsize=8)
        ax.set_title(name)
        writer.figure(fig, name, f"{name} at q = 0 and at a sample q",
                      f"Sample q = {np.round(np.degrees(q_sample), 1).tolist()} deg.")
        writer.progress((index + 1) / (len(MODELS) + 1), name)
    _franka_case(writer)
    writer.progress((len(MODELS) + 0.5) / (len(MODELS) + 1), "franka-fr3 over q7")
    cell_case(writer)
    writer.progress(1.0, "kuka-iiwa14 in a cell")


def _franka_case(writer: SectionWriter) -> None:
    """The feasible q7 sets of every branch of one FR3 pose, and one branch's joint curves over q7."""
    chain = franka_fr3()
    pose = chain.fk(_FRANKA_READY)
    writer.heading("franka-fr3 over q7 (beyond paper 000)")
    writer.text(
        "Franka-class arms (the Panda, the FR3, the xArm7) are not S-R-S: axis 7 is offset from axis 6 (by 0.088 m "
        "on the FR3), so paper 000's arm angle does not describe their redundancy. redkin takes q7 as the redundancy "
        "parameter instead (docs/franka.md): at a given q7 every branch's solution is in closed form, and the set of "
        "q7 at which a branch exists within the maker's joint limits is found exactly. This is redkin's extension "
        "beyond paper 000: no paper prints these values, so there is nothing to compare them with. The pose is the "
        "FR3's flange at its ready configuration q = (0, -45, 0, -135, 0, 90, 45) deg; the branches are named by the "
        "signs of the shoulder (q2), the elbow and the wrist (cos q5), and the ready configuration lies on branch "
        f"{_FRANKA_BRANCH} at q7 = 45 deg."
    )
    sets = feasible_q7(chain, pose)
    rows = []
    for label, arcs in zip(sets.branches, sets.arcs):
        if not len(arcs):
            rows.append([str(label), "none", None, None, 0.0])
        for k, (start, end) in enumerate(arcs):
            rows.append([str(label), k + 1, float(np.degrees(start)), float(np.degrees(end)),
                         float(np.degrees(end - start))])
    writer.table("franka_q7_sets", ["branch", "arc", "start [deg]", "end [deg]", "width [deg]"], rows,
                 caption="franka-fr3 at its ready configuration: the feasible q7 set of each branch",
                 detail="redkin.franka.feasible_q7: the q7 within joint 7's range "
                        f"[{np.degrees(sets.domain[0]):.3f}, {np.degrees(sets.domain[1]):.3f}] deg at which the branch "
                        "has a solution with every joint within the FR3's limits (franka_description). "
                        "'none': no such q7.")
    index = BRANCHES.index(parse_branch(_FRANKA_BRANCH))
    arcs = sets.arcs[index]
    q7 = np.unique(np.concatenate([np.linspace(*sets.domain, _Q7_SAMPLES), arcs.ravel()]))
    solutions = ik(chain, pose, q7, BRANCHES[index])
    q = np.where(solutions.exists[:, :1], solutions.q[:, 0], np.nan)
    fig, axes = plt.subplots(chain.n, 1, figsize=(6.5, 9), sharex=True)
    plot_q7_curves(axes, q7, q, chain.lower, chain.upper, arcs, sets.domain)
    axes[0].set_title(f"franka-fr3, branch {_FRANKA_BRANCH}: joint values over q7")
    writer.figure(fig, "franka_q7_curves", f"franka-fr3: the joints of branch {_FRANKA_BRANCH} over q7",
                  "Limits dashed red; the feasible q7 set of the branch shaded blue (the rows of the table above). "
                  "Computed with redkin.franka.ik at 1441 values of q7 and the arc ends.")
    writer.page("franka_explore", explorer_html(explorer_data(chain, pose, _FRANKA_BRANCH), degrees=True),
                "Explore this pose live: q7 on a slider, all eight branches")


def _limit(value: float) -> float | None:
    """A joint limit in degrees, ``None`` for no limit."""
    return float(np.degrees(value)) if np.isfinite(value) else None


SECTION = Section(
    key=section_key(__name__),
    title="Robot models",
    reference="Models of paper 000 (PA10-7C), paper 003 (Barrett WAM), thesis 001 (dual-arm humanoid), "
    "paper 004 (planar arm), the KUKA LBR iiwa 14 R820 data sheet and Franka's franka_description; the Franka "
    "case over q7 (docs/franka.md) and the worked cell (docs/collisions.md) are redkin's own.",
    build=build,
)
