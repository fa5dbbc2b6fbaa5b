"""Reading a YAML (or JSON: YAML reads it) file a user wrote: a limits file, a scene; one line naming the file where it
cannot be read."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import yaml

from redkin.errors import RobotDescriptionError


def read_yaml(file: str | os.PathLike, what: str) -> Any:
    """The data of the YAML or JSON file ``file``, described as ``what`` in errors (``"limits file"``).

    Raises
    ------
    RobotDescriptionError
        For a missing or unreadable file, or one that is not YAML or JSON (with the line of the fault).
    """
    path = Path(file)
    try:
        return yaml.safe_load(path.read_text())
    except (OSError, UnicodeDecodeError) as exc:
        raise RobotDescriptionError(f"{what} {str(path)!r}: cannot read it ({exc})", str(path)) from None
    except yaml.YAMLError as exc:
        where = getattr(exc, "problem_mark", None)
        line = "" if where is None else f" at line {where.line + 1}"
        raise RobotDescriptionError(f"{what} {str(path)!r}: not YAML or JSON{line}", str(path)) from None
