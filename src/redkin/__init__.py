"""redkin: kinematics of redundant robot manipulators.

The public names below are loaded on first use (PEP 562), so that ``import redkin`` and the command line's
``--help`` cost no compiled kernels: ``from redkin import SerialChain`` imports :mod:`redkin.chain` then.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # what type checkers and editors see; at run time :func:`__getattr__` loads them
    from redkin._compiled import interpreted, set_threads, thread_count
    from redkin.arms import Arm, arm
    from redkin.chain import SerialChain, yoshikawa
    from redkin.closed_form import ik
    from redkin.errors import (
        MapStoreError,
        NotArmAngleClassError,
        RedkinError,
        RobotDescriptionError,
        SizeLimitError,
        UnreachablePoseError,
    )
    from redkin.models import get_robot, robot_names

__version__ = "0.1.0"

__all__ = [
    "Arm",
    "MapStoreError",
    "NotArmAngleClassError",
    "RedkinError",
    "RobotDescriptionError",
    "SerialChain",
    "SizeLimitError",
    "UnreachablePoseError",
    "arm",
    "get_robot",
    "ik",
    "interpreted",
    "robot_names",
    "set_threads",
    "thread_count",
    "yoshikawa",
    "__version__",
]

#: The module that defines each public name of :data:`__all__` (``__version__`` is defined here).
_LAZY = {
    "Arm": "redkin.arms",
    "arm": "redkin.arms",
    "MapStoreError": "redkin.errors",
    "NotArmAngleClassError": "redkin.errors",
    "RedkinError": "redkin.errors",
    "RobotDescriptionError": "redkin.errors",
    "SerialChain": "redkin.chain",
    "SizeLimitError": "redkin.errors",
    "UnreachablePoseError": "redkin.errors",
    "get_robot": "redkin.models",
    "ik": "redkin.closed_form",
    "interpreted": "redkin._compiled",
    "robot_names": "redkin.models",
    "set_threads": "redkin._compiled",
    "thread_count": "redkin._compiled",
    "yoshikawa": "redkin.chain",
}


def __getattr__(name: str) -> Any:
    """A public name, imported from its module on first use and kept here (later lookups do not come back)."""
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'redkin' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
