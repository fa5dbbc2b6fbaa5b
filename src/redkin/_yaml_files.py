"""Reading a YAML (or JSON: YAML reads it) file a user wrote: a limits file, a scene; one line naming the file where it
cannot be read."""

from __future__ import annotations

import os
import re
from pathlib import Path
from typing import Any

import yaml

from redkin.errors import RobotDescriptionError


class _Loader(yaml.SafeLoader):
    """PyYAML's safe loader, reading numbers as YAML 1.2 and JSON do: ``1e-09`` and ``5E3`` are floats.

    PyYAML follows YAML 1.1, whose floats need a dot (``1.0e-09``), and reads ``1e-09`` as a string; but that is
    how ``json.dumps`` writes 1e-9, and how people write small margins and radii by hand.
    """


def _integer(loader: _Loader, node: yaml.Node) -> int | float:
    """A YAML integer, or the infinity of its sign where no float holds it (10^400): a file's numbers become floats,
    and the fields refuse what is not finite in their own words, where ``float`` would raise ``OverflowError``."""
    value = loader.construct_yaml_int(node)
    if abs(value) > _LARGEST:
        return float("inf") if value > 0 else float("-inf")
    return value


_LARGEST = 1.7976931348623157e308  # the largest float
_Loader.add_constructor("tag:yaml.org,2002:int", _integer)
_Loader.add_implicit_resolver("tag:yaml.org,2002:float",
                              re.compile(r"^[-+]?(?:\.[0-9]+|[0-9]+(?:\.[0-9]*)?)(?:[eE][-+]?[0-9]+)?$"),
                              list("-+0123456789."))


def read_yaml(file: str | os.PathLike, what: str) -> Any:
    """The data of the YAML or JSON file ``file``, described as ``what`` in errors (``"limits file"``).

    Raises
    ------
    RobotDescriptionError
        For a missing or unreadable file, or one that is not YAML or JSON (with the line of the fault).
    """
    path = Path(file)
    try:
        return yaml.load(path.read_text(), Loader=_Loader)
    except (OSError, UnicodeDecodeError) as exc:
        raise RobotDescriptionError(f"{what} {str(path)!r}: cannot read it ({exc})", str(path)) from None
    except yaml.YAMLError as exc:
        where = getattr(exc, "problem_mark", None)
        line = "" if where is None else f" at line {where.line + 1}"
        raise RobotDescriptionError(f"{what} {str(path)!r}: not YAML or JSON{line}", str(path)) from None
