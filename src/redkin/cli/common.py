"""Helpers shared by the command modules: parser, robot and angle arguments, output."""

from __future__ import annotations

import argparse
import json
import re
import sys
from collections.abc import Sequence
from typing import Any, NoReturn

import numpy as np

from redkin._validation import check_rotation
from redkin.chain import SerialChain
from redkin.models import get_robot
from redkin.srs.geometry import pose_from

#: File types of the figures the commands write (matplotlib's writers without extra packages).
IMAGE_SUFFIXES = frozenset({".png", ".pdf", ".svg"})


class UsageError(ValueError):
    """A user mistake on the command line: printed as one line, exit code 2."""


#: Arguments that start with ``-`` but are values, not options: numbers in any float form (``-1e-3``,
#: ``-inf``: argparse alone knows only ``-1`` and ``-.5``) and branches (``-++``, ``--+``, ``---``).
_VALUE_LIKE = re.compile(r"^-(\d|\.\d|inf$|infinity$|nan$)|^[+-]{3}$", re.IGNORECASE)


class Parser(argparse.ArgumentParser):
    """An argument parser whose errors are one line on stderr and exit code 2.

    Values that begin with ``-`` (:data:`_VALUE_LIKE`) are read as values,
    with or without ``=``: ``--branch -++`` and ``--position -1e-3 0 0``.
    """

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = _VALUE_LIKE  # argparse's own hook for "looks like a value"

    def error(self, message: str) -> NoReturn:
        print(f"{self.prog}: error: {message}", file=sys.stderr)
        raise SystemExit(2)


def add_robot_argument(parser: argparse.ArgumentParser) -> None:
    """``ROBOT``: a model name (``redkin robots``), a robot file or a URDF, with ``--base``/``--tip`` links for
    a URDF."""
    parser.add_argument("robot", metavar="ROBOT",
                        help="model name (see `redkin robots`), a .toml/.json robot file, or a .urdf or .xacro file")
    parser.add_argument("--base", metavar="LINK", help="URDF: the link the chain starts at (default: the root link)")
    parser.add_argument("--tip", metavar="LINK", help="URDF: the link the chain ends at (default: the only leaf)")


#: How every command that takes ``--branch`` describes it.
BRANCH_HELP = "signs of q2, q4, q6 in the robot's own joint senses, e.g. +-+ (default +++)"


def add_target_arguments(parser: argparse.ArgumentParser) -> None:
    """``--position X Y Z --rotation R11 ... R33``: a target pose of the tool."""
    parser.add_argument("--position", nargs=3, type=float, required=True, metavar=("X", "Y", "Z"),
                        help="tool position [m]")
    parser.add_argument(
        "--rotation", nargs=9, type=float, required=True, metavar="R",
        help="tool rotation R11 R12 R13 R21 ... R33 (row by row)"
    )


def target_pose(args: argparse.Namespace) -> np.ndarray:
    """The pose of ``--position`` and ``--rotation`` (ValueError for a non-finite position or a non-rotation)."""
    rotation = check_rotation(np.array(args.rotation, dtype=float).reshape(3, 3), "--rotation")
    position = np.array(args.position, dtype=float)
    if not np.all(np.isfinite(position)):
        raise UsageError("--position must be finite numbers")
    return pose_from(position, rotation)


def add_output_flags(parser: argparse.ArgumentParser, degrees: bool = True) -> None:
    """``--json`` and (optionally) ``--deg``."""
    parser.add_argument("--json", action="store_true", help="print machine-readable JSON")
    if degrees:
        parser.add_argument("--deg", action="store_true", help="read and print angles in degrees")


def load_robot(args: argparse.Namespace) -> SerialChain:
    """The chain for the ROBOT, ``--base`` and ``--tip`` arguments (ValueError for an unknown name or a bad file)."""
    return get_robot(args.robot, args.base, args.tip)


def angles_in(values: Sequence[float], degrees: bool) -> np.ndarray:
    """Angles from the command line in radians."""
    array = np.asarray(values, dtype=float)
    return np.radians(array) if degrees else array


def angles_out(values: Any, degrees: bool) -> Any:
    """Angles in radians converted for output (``None`` stays ``None``)."""
    if values is None:
        return None
    array = np.asarray(values, dtype=float)
    return np.degrees(array) if degrees else array


def joint_vector(chain: SerialChain, values: Sequence[float], degrees: bool, name: str = "joint values") -> np.ndarray:
    """Joint values for ``chain`` from the command line, checked for count and finiteness."""
    if len(values) != chain.n:
        raise UsageError(f"{chain.name} has {chain.n} joints, got {len(values)} {name}")
    q = angles_in(values, degrees)
    if not np.all(np.isfinite(q)):
        raise UsageError(f"{name} must be finite numbers")
    return q


def angle_unit(degrees: bool) -> str:
    """The unit of every angle a command prints: ``"deg"`` with ``--deg``, else ``"rad"``."""
    return "deg" if degrees else "rad"


def _to_jsonable(value: Any) -> Any:
    """Numpy arrays and scalars to plain JSON values (rounded-trip exact floats)."""
    if isinstance(value, dict):
        return {str(k): _to_jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_to_jsonable(v) for v in value]
    if isinstance(value, np.ndarray):
        return _to_jsonable(value.tolist())
    if isinstance(value, np.generic):
        return value.item()
    return value


def print_json(value: Any) -> None:
    """Print ``value`` as JSON on stdout."""
    print(json.dumps(_to_jsonable(value), indent=2, allow_nan=False))


def format_matrix(matrix: np.ndarray, digits: int = 6) -> str:
    """A matrix as aligned text rows."""
    rows = np.atleast_2d(matrix)
    return "\n".join("  ".join(f"{v: .{digits}f}" for v in row) for row in rows)


def progress_bar(fraction: float) -> None:
    """Draw a progress bar at ``fraction`` (0..1) over itself on stderr (end it with a newline there)."""
    filled = int(30 * fraction)
    print(f"\r[{'#' * filled}{'.' * (30 - filled)}] {100 * fraction:5.1f}%", end="", file=sys.stderr, flush=True)
