"""Entry point of the ``redkin`` command: wires the command modules and maps user mistakes to exit code 2."""

from __future__ import annotations

import argparse
import errno
import gc
import importlib
import os
import sys
import warnings
from collections.abc import Sequence
from contextlib import AbstractContextManager, nullcontext

from redkin import __version__
from redkin.cli.common import Parser

#: Modules with a ``register(subparsers)`` function, in help order.
_COMMAND_MODULES = [
    "redkin.cli.basic",
    "redkin.cli.reproduce",
    "redkin.cli.srs",
    "redkin.cli.path",
    "redkin.cli.explore",
    "redkin.cli.torso_arm",
    "redkin.cli.velocity",
    "redkin.cli.virtual_arms",
    "redkin.cli.workspace",
    "redkin.cli.compile",
]


#: The module of each command, so that a command imports only its own module (``redkin fk`` needs
#: neither matplotlib nor dask); ``tests/test_cli_basic.py`` checks it against the modules' parsers.
_COMMANDS = {
    "robots": "redkin.cli.basic", "fk": "redkin.cli.basic", "jacobian": "redkin.cli.basic",
    "reproduce": "redkin.cli.reproduce", "ik": "redkin.cli.srs", "arm-angles": "redkin.cli.srs",
    "explore": "redkin.cli.explore", "torso-arm": "redkin.cli.torso_arm", "track": "redkin.cli.velocity",
    "virtual-arms": "redkin.cli.virtual_arms", "workspace": "redkin.cli.workspace", "compile": "redkin.cli.compile",
    "path": "redkin.cli.path",
}


def _build_parser(command: str | None = None) -> Parser:
    """The ``redkin`` parser: every command, or only the commands of ``command``'s module if it is one of
    :data:`_COMMANDS`."""
    parser = Parser(
        prog="redkin",
        description="Kinematics of redundant robot manipulators. Angles are radians unless --deg is given.",
    )
    parser.add_argument("--version", action="version", version=f"redkin {__version__}")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in [_COMMANDS[command]] if command in _COMMANDS else _COMMAND_MODULES:
        importlib.import_module(name).register(subparsers)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run ``redkin`` with ``argv`` (default: the process's arguments, as the ``redkin`` program) and return its
    exit code.

    As the program, the objects left when the command ends are frozen (:func:`gc.freeze`) before the interpreter
    exits: its last garbage collection then skips them instead of walking the few hundred thousand objects numba
    creates when a command runs a compiled kernel, about 0.3 s of every such command (a warm ``redkin fk`` spends
    it after printing).  Nothing is lost: the commands close their files and clients themselves, and the exit
    still flushes the output and runs the ``atexit`` functions.  A caller that passes ``argv`` (the tests) keeps
    its collector as it was.
    """
    code = _main(sys.argv[1:] if argv is None else list(argv))
    if argv is None:
        gc.freeze()
    return code


def _main(argv: list[str]) -> int:
    parser = _build_parser(argv[0] if argv else None)
    args = parser.parse_args(argv)
    if getattr(args, "handler", None) is None:
        parser.print_help()
        return 2
    # Warnings (numpy's "overflow encountered in matmul" with its source line) are held back: after a user
    # mistake the one line of the error says what went wrong; after a run each is printed once, as one line.
    with warnings.catch_warnings(record=True) as caught, _kernels_for(args):
        try:
            code = int(args.handler(args) or 0)
        except ValueError as exc:  # user mistakes: one line, exit code 2
            message = str(exc).splitlines()[0] if str(exc) else exc.__class__.__name__
            print(f"redkin: error: {message}", file=sys.stderr)
            return 2
        except BrokenPipeError:  # the reader went away (`redkin ... | head`): stop quietly, as other tools do
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())  # no second error when Python flushes
            return 1
        except OSError as exc:  # the machine, not the user: a full disk, a file removed under us; one line, exit 1
            if exc.errno == errno.ENAMETOOLONG:  # but a name too long for the file system is the user's
                name = str(exc.filename)
                print(f"redkin: error: a file name too long for this system ({len(name)} characters): "
                      f"{name[:40]}...", file=sys.stderr)
                return 2
            if exc.errno in (errno.ENOSPC, errno.EDQUOT):  # the user's output cannot be written: exit 2 as for a
                # folder that cannot take it (the workspace store says so in its own words, MapStoreError)
                where = "" if exc.filename is None else f" writing {str(exc.filename)!r}"
                print(f"redkin: error: no space left on the device{where}; nothing was written: free some and run "
                      "again", file=sys.stderr)
                return 2
            print(f"redkin: error: {exc}", file=sys.stderr)
            return 1
    _print_warnings(caught)
    return code


def _kernels_for(args: argparse.Namespace) -> AbstractContextManager:
    """How the command's kernels run: as Python for the commands that set ``in_python`` (one configuration or one
    pose of a closed form, :func:`redkin.cli.common.small_work`), where loading numba would take longer than the
    arithmetic; compiled otherwise."""
    if not getattr(args, "in_python", False):
        return nullcontext()
    from redkin._compiled import interpreted

    return interpreted()


def _print_warnings(caught: Sequence[warnings.WarningMessage]) -> None:
    """Each distinct warning of a run once, as one line on stderr."""
    seen: set[str] = set()
    for warning in caught:
        text = str(warning.message).splitlines()[0] if str(warning.message) else warning.category.__name__
        if text not in seen:
            seen.add(text)
            print(f"redkin: warning: {text}", file=sys.stderr)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
