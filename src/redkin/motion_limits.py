"""Limits of motion from a file: each joint's velocity, acceleration and jerk limit, for timing a path.

A URDF carries a speed limit per joint (``<limit velocity=...>``) and nothing of acceleration or jerk; a timed
trajectory needs both speed and acceleration (:func:`redkin.paths.time_path`).  A limits file gives them, in one of
two forms (YAML; JSON, a subset of YAML, reads too):

* redkin's own, one list per limit in joint order, or one number for every joint; values in rad/s, rad/s^2 and
  rad/s^3, or in degrees with ``degrees=True`` (``redkin path --deg``)::

      velocity: [2.175, 2.175, 2.175, 2.175, 2.61, 2.61, 2.61]
      acceleration: [15, 7.5, 10, 12.5, 15, 20, 20]
      jerk: 5000                 # optional, as any of the three

* MoveIt's ``joint_limits.yaml``, keyed by the description's joint names (always radians, as MoveIt reads it); a
  limit counts where its ``has_..._limits`` flag is true::

      joint_limits:
        panda_joint1: {has_velocity_limits: true, max_velocity: 2.175,
                       has_acceleration_limits: true, max_acceleration: 3.75}

A limit the file leaves out keeps the chain's own (the description's speed limits, a model's data sheet).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np

from redkin._yaml_files import read_yaml
from redkin.chain import SerialChain
from redkin.errors import RobotDescriptionError

#: The limits a file may give, redkin's keys, with MoveIt's key and flag for each.
_MOVEIT_KEYS = {"velocity": ("max_velocity", "has_velocity_limits"),
                "acceleration": ("max_acceleration", "has_acceleration_limits"),
                "jerk": ("max_jerk", "has_jerk_limits")}


def read_motion_limits(file: str | os.PathLike, chain: SerialChain, degrees: bool = False) -> SerialChain:
    """The chain with the limits of motion that a limits file gives (see the module's docstring for the forms).

    Parameters
    ----------
    file : str or PathLike
        A YAML or JSON limits file.
    chain : SerialChain
        The arm: its joint count, and its joint names for MoveIt's form.
    degrees : bool
        Read redkin's form in deg/s, deg/s^2 and deg/s^3 (MoveIt's form is always in radians).

    Returns
    -------
    SerialChain
        A copy with the file's limits; each limit the file leaves out is the chain's own.

    Raises
    ------
    RobotDescriptionError
        For a missing or unreadable file, an unknown key, a joint the chain does not have, a list of the wrong
        length, or a value that is not a positive number (one line naming the file and the entry).
    """
    path = Path(file)
    data = read_yaml(path, "limits file")
    if not isinstance(data, dict) or not data:
        raise RobotDescriptionError(f"limits file {str(path)!r}: expected a mapping with velocity, acceleration or "
                                    "jerk (or MoveIt's joint_limits)", str(path))
    if "joint_limits" in data:
        limits = _moveit_form(data, chain, str(path))
    else:
        scale = np.pi / 180.0 if degrees else 1.0
        limits = {key: _per_joint(value, chain.n, key, str(path)) * scale for key, value in data.items()
                  if _known(key, str(path))}
    return chain.with_motion_limits(**limits)


def _known(key: Any, path: str) -> bool:
    if key not in _MOVEIT_KEYS:
        raise RobotDescriptionError(f"limits file {path!r}: unknown key {key!r} (the keys are velocity, "
                                    "acceleration and jerk, or MoveIt's joint_limits)", path, str(key))
    return True


def _per_joint(value: Any, n: int, key: str, path: str) -> np.ndarray:
    """One positive number per joint from a list of ``n`` or a single number."""
    values = value if isinstance(value, list) else [value] * n
    if len(values) != n:
        raise RobotDescriptionError(f"limits file {path!r}: {key} has {len(values)} entries; the arm has {n} joints",
                                    path, key)
    for index, entry in enumerate(values):
        _check_number(entry, f"{key}[{index}]", path)
    return np.array(values, dtype=float)


def _check_number(entry: Any, name: str, path: str) -> None:
    if isinstance(entry, bool) or not isinstance(entry, (int, float)) or not entry > 0 or not np.isfinite(entry):
        raise RobotDescriptionError(f"limits file {path!r}: {name} must be a positive number, got {entry!r}",
                                    path, name)


def _moveit_form(data: dict, chain: SerialChain, path: str) -> dict[str, np.ndarray]:
    """The limits of MoveIt's ``joint_limits.yaml`` (other top-level keys, such as its default scaling factors, and
    joints beyond the chain's, such as a gripper's, are skipped); a joint the file does not name keeps the chain's
    limits."""
    joints = data["joint_limits"]
    if not isinstance(joints, dict):
        raise RobotDescriptionError(f"limits file {path!r}: joint_limits must map joint names to their limits", path)
    limits = {key: getattr(chain, key).copy() for key in _MOVEIT_KEYS}
    named = [name for name in joints if name in chain.joint_names]
    if not named:
        raise RobotDescriptionError(f"limits file {path!r}: joint_limits names none of the arm's joints "
                                    f"({', '.join(chain.joint_names)})", path, "joint_limits")
    for name in named:
        entry = joints[name]
        if not isinstance(entry, dict):
            raise RobotDescriptionError(f"limits file {path!r}: joint_limits.{name} must be a mapping", path, name)
        index = chain.joint_names.index(name)
        for key, (value_key, flag) in _MOVEIT_KEYS.items():
            if not isinstance(entry.get(flag, False), bool):  # YAML's "yes" in quotes, or 1: neither says true
                raise RobotDescriptionError(f"limits file {path!r}: joint_limits.{name}.{flag} must be true or false, "
                                            f"got {entry[flag]!r}", path, name)
            if entry.get(flag) is True and value_key in entry:
                _check_number(entry[value_key], f"joint_limits.{name}.{value_key}", path)
                limits[key][index] = float(entry[value_key])
    return limits
