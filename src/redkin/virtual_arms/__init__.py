"""Virtual-arm trajectory generation for redundant manipulators (paper 004, Tsuji, Nakayama and Ito).

A redundant arm is described by a set of virtual arms whose end points sit on
its joints and links (:mod:`~redkin.virtual_arms.points`); one subsystem per
virtual arm plans its own end point's goal and computes its own error
gradient from its own forward model (analytic, :mod:`~.analytic`, or learned,
:mod:`~.learned`); the joint trajectory emerges from the dynamics of [004 eqs. 9-13]
(:mod:`~.dynamics`, :mod:`~.generate`); :mod:`~.obstacles` plans the goals
round obstacles period by period (Fig. 8).
"""

from redkin.virtual_arms.analytic import AnalyticModel, task_axes
from redkin.virtual_arms.classify import Classification, classify
from redkin.virtual_arms.clearance import Obstacle, arm_clearance
from redkin.virtual_arms.generate import TrajectoryResult, generate_trajectory
from redkin.virtual_arms.learned import LearnedModel, LearningReport, learn_forward_model
from redkin.virtual_arms.obstacles import ObstacleRun, avoid_obstacles, monitored_points
from redkin.virtual_arms.output_function import OutputFunction
from redkin.virtual_arms.points import VirtualPoint, joints_and_midpoints, parse_point

__all__ = [
    "AnalyticModel",
    "Classification",
    "LearnedModel",
    "LearningReport",
    "Obstacle",
    "ObstacleRun",
    "OutputFunction",
    "TrajectoryResult",
    "VirtualPoint",
    "arm_clearance",
    "avoid_obstacles",
    "classify",
    "generate_trajectory",
    "joints_and_midpoints",
    "learn_forward_model",
    "monitored_points",
    "parse_point",
    "task_axes",
]
