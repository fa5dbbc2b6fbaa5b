"""redkin: kinematics of redundant robot manipulators."""

from redkin.chain import SerialChain, yoshikawa
from redkin.errors import (
    NotArmAngleClassError,
    RedkinError,
    RobotDescriptionError,
    SizeLimitError,
    UnreachablePoseError,
)
from redkin.models import get_robot, robot_names

__version__ = "0.1.0"

__all__ = [
    "NotArmAngleClassError",
    "RedkinError",
    "RobotDescriptionError",
    "SerialChain",
    "SizeLimitError",
    "UnreachablePoseError",
    "get_robot",
    "robot_names",
    "yoshikawa",
    "__version__",
]
