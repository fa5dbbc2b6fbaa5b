"""Report section: the robot models, drawn, with their parameter tables."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np

from redkin.models import MODELS
from redkin.plot.arm import draw_arm_2d, draw_arm_3d, set_equal_3d
from redkin.reproduce import Section, section_key
from redkin.reproduce.report import SectionWriter


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
        writer.progress((index + 1) / len(MODELS), name)


def _limit(value: float) -> float | None:
    """A joint limit in degrees, ``None`` for no limit."""
    return float(np.degrees(value)) if np.isfinite(value) else None


SECTION = Section(
    key=section_key(__name__),
    title="Robot models",
    reference="Models of paper 000 (PA10-7C), paper 003 (Barrett WAM), thesis 001 (dual-arm humanoid), "
    "paper 004 (planar arm) and the KUKA LBR iiwa 14 R820 data sheet.",
    build=build,
)
