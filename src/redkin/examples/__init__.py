"""The example robot files that ship with redkin, and the rule by which a file name finds them.

The folder holds robot descriptions written from the makers' public data: URDFs of KUKA's iiwa 14 (and the
ROS-Industrial one), Franka's Panda and FR3, Rethink's Sawyer, Kinova's Gen3 and Jaco2, UFactory's xArm7 and ABB's
YuMi right arm; the FR3 again as a parametrised ``.xacro`` (``hand:=false`` ends at the flange); a MuJoCo ``.xml``
of the iiwa 14 written as MuJoCo Menagerie writes it; and the PA10-7C as a ``.toml`` robot file.

The rule (:func:`resolve`): a robot file path that does not exist, written as a bare file name (``iiwa14.urdf``)
or as ``examples/NAME`` (as the README and the docs write them), and whose name is one of :func:`names`, reads the
shipped file.  A file that exists is always read as it is, so a user's own ``iiwa14.urdf`` in the working folder
wins; an absolute path, or any other folder, is never looked up here.
"""

from __future__ import annotations

from pathlib import Path

from redkin.errors import RedkinError

__all__ = ["FOLDER", "names", "path", "resolve"]

#: The folder of the shipped example files (inside the installed package).
FOLDER = Path(__file__).resolve().parent

#: The folder name under which the README and the docs write the examples (``examples/iiwa14.urdf``).
_WRITTEN_FOLDER = "examples"


def names() -> list[str]:
    """The file names of the shipped examples, sorted (``fr3.urdf``, ..., ``yumi_right.urdf``)."""
    return sorted(entry.name for entry in FOLDER.iterdir()
                  if entry.is_file() and entry.suffix in (".urdf", ".xacro", ".xml", ".toml", ".json"))


def path(name: str) -> Path:
    """The shipped example file ``name`` (e.g. ``"iiwa14.urdf"``).

    Raises
    ------
    ValueError
        If ``name`` is not one of :func:`names`; the message lists them.
    """
    if name not in names():
        raise RedkinError(f"no example named {name!r}: redkin ships {', '.join(names())}")
    return FOLDER / name


def resolve(file: str | Path) -> Path:
    """The file to read for a robot file path: ``file`` itself, or the shipped example it names.

    Parameters
    ----------
    file : str or Path
        A path as the user wrote it.

    Returns
    -------
    Path
        ``file`` when it exists, is absolute, or is not ``NAME`` or ``examples/NAME`` for a shipped example
        ``NAME``; else the shipped file (see the module docstring).

    Raises
    ------
    RobotDescriptionError
        For ``examples/NAME`` that neither exists nor names a shipped example; the message lists them.
    """
    written = Path(file)
    if written.exists() or written.is_absolute():
        return written
    parts = written.parts
    if len(parts) == 1 or (len(parts) == 2 and parts[0] == _WRITTEN_FOLDER):
        if parts[-1] in names():
            return FOLDER / parts[-1]
        if len(parts) == 2:  # written as one of the examples, but none is called so
            from redkin.errors import RobotDescriptionError

            raise RobotDescriptionError(f"robot file {str(file)!r} does not exist, and redkin ships no example "
                                        f"{parts[-1]!r} (it ships {', '.join(names())})", path=str(file))
    return written
