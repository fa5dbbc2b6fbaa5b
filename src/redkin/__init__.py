"""redkin: kinematics of redundant robot manipulators."""

from redkin.chain import SerialChain, yoshikawa
from redkin.models import get_robot, robot_names

__version__ = "0.1.0"

__all__ = ["SerialChain", "get_robot", "robot_names", "yoshikawa", "__version__"]
