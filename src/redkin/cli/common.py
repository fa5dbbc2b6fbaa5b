"""Helpers shared by the command modules: parser, robot and angle arguments, output files, printed numbers."""

from __future__ import annotations

import argparse
import json
import os
import re
import sys
import time
import warnings
from collections.abc import Callable, Collection, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, NoReturn

import numpy as np

from redkin._validation import (
    MAX_LENGTH,
    ROTATION_TOLERANCE,
    check_magnitude,
    check_output_directory,
    check_output_file,
    check_quaternion,
    check_rotation,
)

if TYPE_CHECKING:  # the commands' parsers are built from this module: it imports no chain, models or kernels
    from redkin.chain import Reach, SerialChain

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
    """``ROBOT``: a model name (``redkin robots``), a robot file, a URDF or an MJCF file, with ``--base``/``--tip``
    links (bodies, or a site as the tip, of an MJCF file) and ``--xacro-arg``/``--package-path`` for a ``.xacro``."""
    parser.add_argument("robot", metavar="ROBOT",
                        help="model name (see `redkin robots`), a .toml/.json robot file, a .urdf or .xacro file, or "
                             "an MJCF .xml file (the mjcf extra)")
    add_base_tip_arguments(parser)
    add_xacro_arguments(parser)


def add_base_tip_arguments(parser: argparse.ArgumentParser, note: str = "") -> None:
    """``--base`` and ``--tip``, described the same on every command: a URDF's links, an MJCF's bodies (a site as the
    tip); ``note`` is added to both (``"with --show"``)."""
    extra = f"; {note}" if note else ""
    parser.add_argument("--base", metavar="LINK", help="where the chain starts: a URDF link (default: the root link) "
                                                       f"or an MJCF body (default: the world body){extra}")
    parser.add_argument("--tip", metavar="LINK", help="where the chain ends: a URDF link or an MJCF body or site "
                                                      f"(default: the only leaf){extra}")


def add_xacro_arguments(parser: argparse.ArgumentParser) -> None:
    """``--xacro-arg NAME:=VALUE`` and ``--package-path DIR``, both repeatable, for a ``.xacro`` robot."""
    parser.add_argument("--xacro-arg", dest="xacro_args", action="append", type=_xacro_argument, default=[],
                        metavar="NAME:=VALUE",
                        help=".xacro: the value of one of its <xacro:arg> arguments (repeatable; the last of a name "
                             "counts)")
    parser.add_argument("--package-path", dest="package_paths", action="append", default=[], metavar="DIR",
                        help="a folder holding ROS packages (or one package), searched before the folders above the "
                             "file and ROS_PACKAGE_PATH: for a .xacro's $(find PKG), and for the package:// mesh "
                             "files of a URDF's collision shapes (--scene) (repeatable)")


def _xacro_argument(text: str) -> tuple[str, str]:
    """``NAME:=VALUE`` as ``(NAME, VALUE)`` (argparse words an error as one usage line, exit code 2)."""
    name, assign, value = text.partition(":=")
    if not assign or not name.strip():
        raise argparse.ArgumentTypeError(f"expected NAME:=VALUE (as on xacro's command line), got {text!r}")
    return name.strip(), value


def xacro_options(args: argparse.Namespace) -> dict[str, Any]:
    """The keyword arguments of :func:`redkin.models.get_robot` that ``--xacro-arg``/``--package-path`` give."""
    return {"xacro_args": dict(args.xacro_args), "package_paths": list(args.package_paths)}


def add_srs_tolerance_argument(parser: argparse.ArgumentParser) -> None:
    """``--srs-tolerance METRES``: the nearly S-R-S tolerance of :func:`redkin.arms.classify.arm_angle_class`
    (issue 27), on the commands whose work depends on the arm's class; ``args.srs_tolerance`` is ``None`` when not
    given."""
    parser.add_argument("--srs-tolerance", type=_srs_tolerance, metavar="METRES",
                        help="largest departure from S-R-S (metres between axes that must meet; radians for axes off "
                             "perpendicular) of an arm solved as nearly S-R-S through its exact neighbour (default "
                             "0.02; the Kinova Gen3's largest is 12.75 mm)")


def _srs_tolerance(text: str) -> float:
    """The value of ``--srs-tolerance``: a finite number > 0 (argparse words a refusal as one usage line, exit 2)."""
    from redkin.arms.classify import check_tolerance

    try:
        return check_tolerance(text)
    except ValueError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


#: How every command that takes ``--branch`` describes it.
BRANCH_HELP = "signs of q2, q4, q6 in the robot's own joint senses, e.g. +-+ (default +++)"


def add_target_arguments(parser: argparse.ArgumentParser, required: bool = True) -> None:
    """``--position X Y Z`` and ``--rotation R11 ... R33`` or ``--quat W X Y Z``: a target pose of the tool
    (optional where a command takes ``--poses`` instead)."""
    parser.add_argument("--position", nargs=3, type=float, required=required, metavar=("X", "Y", "Z"),
                        help="tool position [m]")
    add_rotation_arguments(parser.add_mutually_exclusive_group(required=required))


#: How far a ``--rotation`` (largest entry of ``R R^T - I``, and ``|det R - 1|``) or a ``--quat`` (``| |q| - 1 |``)
#: may be from a rotation and still be read, as the nearest rotation: it covers a matrix printed with 4 decimals
#: (``fk``'s old 6 are 1e-6 off) and a quaternion printed with 3.  Farther, the input is refused.
_ROTATION_INPUT_TOLERANCE = 1e-3


def add_rotation_arguments(group: argparse._MutuallyExclusiveGroup, frame: str = "tool") -> None:
    """``--rotation R11 ... R33`` and ``--quat W X Y Z`` in ``group`` (which makes them exclusive, and may hold
    other ways to give the orientation); read them with :func:`given_rotation`."""
    near = (f"a matrix up to {_ROTATION_INPUT_TOLERANCE:g} off orthonormal is taken as the nearest rotation, with a "
            "note on stderr")
    group.add_argument("--rotation", nargs=9, type=float, metavar="R",
                       help=f"{frame} rotation matrix R11 R12 R13 R21 ... R33, row by row ({near})")
    group.add_argument("--quat", nargs=4, type=float, metavar=("W", "X", "Y", "Z"),
                       help=f"{frame} rotation as a unit quaternion, scalar first: w x y z (ROS writes x y z w); "
                            f"a norm up to {_ROTATION_INPUT_TOLERANCE:g} off 1 is normalised")


def given_rotation(args: argparse.Namespace) -> np.ndarray | None:
    """The rotation of ``--rotation`` or ``--quat`` (``None`` where neither was given).

    A matrix that is a rotation by the library's own standard (``R R^T = I`` and ``det R = 1`` within 1e-6,
    :data:`redkin._validation.ROTATION_TOLERANCE`) is used as given, every digit of it.  One farther off, up to
    :data:`_ROTATION_INPUT_TOLERANCE`, is replaced by the nearest rotation (:func:`redkin.so3.nearest_rotation`),
    with one line on stderr that says so; a quaternion is normalised, with that line where its norm was more than
    1e-6 off 1.  A reflection (``det R = -1``), NaN, or input farther off is a ValueError of one line.
    """
    from redkin.so3 import nearest_rotation, quaternion_to_matrix

    if args.quat is not None:
        quaternion = check_quaternion(args.quat, "--quat", _ROTATION_INPUT_TOLERANCE)
        norm = float(np.linalg.norm(quaternion))
        if abs(norm - 1.0) > ROTATION_TOLERANCE:
            _note(f"--quat has norm {norm:.9g}: using it normalised to norm 1")
        return quaternion_to_matrix(quaternion / norm)
    if args.rotation is None:
        return None
    matrix = check_rotation(np.reshape(args.rotation, (3, 3)), "--rotation", _ROTATION_INPUT_TOLERANCE)
    deviation = float(np.abs(matrix @ matrix.T - np.eye(3)).max())
    if max(deviation, abs(float(np.linalg.det(matrix)) - 1.0)) <= ROTATION_TOLERANCE:
        return matrix
    rotation = nearest_rotation(matrix)
    _note(f"--rotation is {deviation:#.3g} off orthonormal (largest entry of R R^T - I): using the nearest rotation, "
          f"whose entries differ from it by at most {float(np.abs(rotation - matrix).max()):.3g}")
    return rotation


def _note(text: str) -> None:
    """One line on stderr about how the input was read (stdout stays the result, JSON and all)."""
    print(f"redkin: note: {text}", file=sys.stderr)


def target_pose(args: argparse.Namespace) -> np.ndarray:
    """The pose of ``--position`` and ``--rotation`` or ``--quat`` (ValueError for a non-finite position or a
    non-rotation, :func:`given_rotation`)."""
    from redkin.srs.geometry import pose_from

    rotation = given_rotation(args)
    if args.position is None or rotation is None:
        raise UsageError("the target needs --position X Y Z and --rotation R11 ... R33 or --quat W X Y Z")
    return pose_from(checked_position(args.position), rotation)


def read_poses(file: str, option: str = "--poses") -> np.ndarray:
    """The ``(N, 4, 4)`` poses of a ``--poses`` file: ``.npy``, ``.csv`` or ``.json``
    (:func:`redkin.paths.waypoints.read_poses`), refused in one line that names the option, the file and the fault."""
    from redkin.paths.waypoints import read_poses as read

    try:
        return read(file)
    except ValueError as exc:
        raise UsageError(f"{option}: {exc}") from None


def checked_position(values: Sequence[float], name: str = "--position") -> np.ndarray:
    """A position from the command line: finite, and at most :data:`MAX_LENGTH` metres from the origin in each
    coordinate (a 1e308 m target is refused here rather than reported as a distance of inf m)."""
    position = np.array(values, dtype=float)
    if not np.all(np.isfinite(position)):
        raise UsageError(f"{name} must be finite numbers")
    return check_magnitude(position, name, MAX_LENGTH, "m")


def add_output_flags(parser: argparse.ArgumentParser, degrees: bool = True) -> None:
    """``--json`` and (optionally) ``--deg``."""
    parser.add_argument("--json", action="store_true", help="print machine-readable JSON")
    if degrees:
        parser.add_argument("--deg", action="store_true", help="read and print angles in degrees")


def small_work(small: bool) -> None:
    """A command whose kernels run as Python (``in_python``, :func:`redkin.cli.main._kernels_for`) says here
    whether its work is small: one pose of a closed form without a cell.  Where it is not (a batch, a nearly S-R-S
    arm's self-motion, the numerical solver, a cell's certified sets), numba is loaded and every kernel from here
    on runs compiled (:func:`redkin._compiled.use_compiled`)."""
    if not small:
        from redkin._compiled import use_compiled

        use_compiled()


def _kernels_named(names: Sequence[str]) -> list:
    """The kernels named ``module.function`` in ``names`` (their modules imported here)."""
    import importlib

    return [getattr(importlib.import_module(name.rpartition(".")[0]), name.rpartition(".")[2]) for name in names]


def kernels_compiled(kernels: Sequence[str]) -> bool:
    """Whether the ``kernels`` (``module.function`` names), and every kernel they call, are in numba's cache, or
    numba is loaded (:func:`redkin._compiled.kernels_cached`), told without importing numba."""
    from redkin._compiled import kernels_cached

    return kernels_cached(*_kernels_named(kernels))


def python_until_compiled(kernels: Sequence[str], work: str, sections: Sequence[str]) -> bool:
    """Whether small work that compiled code does faster than Python runs as Python after all, because the
    ``kernels`` it calls (``module.function`` names), or kernels they call, are not in numba's cache yet
    (:func:`redkin._compiled.kernels_cached`): compiling them would cost far more than running them as Python once.
    Where so, the ``sections`` of :mod:`redkin.warm_up` that compile them start compiling in the background
    (:mod:`redkin.cli.background_compile`), and a note on stderr says both of ``work``
    (:func:`compiling_later`)."""
    if kernels_compiled(kernels):
        return False
    print(f"redkin: note: the kernels of {work} are not compiled yet, so it runs as Python (compiled it runs two "
          f"to three times faster); {compiling_later(sections)}", file=sys.stderr)
    return True


def compiled_beside(kernels: Sequence[str], sections: Sequence[str], work: str, first: Callable[[], object]) -> None:
    """Compile large work's kernels in two processes at once: where the ``kernels`` (``module.function`` names) or
    kernels they call are not in numba's cache, start ``redkin compile --background`` of the ``sections`` of
    :mod:`redkin.warm_up` that compile them (:func:`redkin.cli.background_compile.start`), compile here what
    ``first`` calls meanwhile, then wait for that process to end; the work that follows loads what it compiled from
    the cache.  numba compiles serially within a process, so on two free cores the wait is the longer of the two
    compiles, not their sum.  Says so on stderr, naming ``work``.  Where background compiles are off, or one of this
    cache runs already, everything compiles here as it is called."""
    from redkin._compiled import kernels_on_disk
    from redkin.cli.background_compile import start, wait_for_process

    if kernels_on_disk(*_kernels_named(kernels)):
        return

    try:
        pid = start(sections)
    except OSError:
        pid = None
    if pid is None:
        return
    print(f"redkin: note: compiling {work} in a second process beside this one (process {pid}, 'redkin compile "
          + " ".join(f"--section {section!r}" for section in sections) + " --background')", file=sys.stderr)
    first()
    wait_for_process(pid)


def compiling_later(sections: Sequence[str]) -> str:
    """Start compiling the ``sections`` of :mod:`redkin.warm_up` in the background where that is on and no compile of
    the cache runs yet (:func:`redkin.cli.background_compile.start`), and say in words what will make later runs
    compiled."""
    from redkin.cli.background_compile import background_compiles, start
    from redkin.warm_up import expected_seconds

    command = "redkin compile " + " ".join(f"--section {section!r}" for section in sections)
    seconds = f"about {expected_seconds(sections):.0f} s"
    try:
        pid = start(sections)
    except OSError as exc:
        return f"starting '{command}' in the background failed ({exc}); run it once ({seconds}) to make later runs " \
               "compiled"
    if pid is None and background_compiles():  # start found a compile of this cache running
        return ("a 'redkin compile' of this cache is running already (in the background, or yours), and runs after "
                "it ends are compiled")
    if pid is None:
        return f"'{command}' ({seconds}, once) makes later runs compiled"
    return (f"they are compiling in the background now (process {pid}, '{command} --background', {seconds}), "
            "and later runs are compiled")


def load_robot(args: argparse.Namespace) -> SerialChain:
    """The chain for the ROBOT, ``--base``, ``--tip``, ``--xacro-arg`` and ``--package-path`` arguments
    (ValueError for an unknown name or a bad file)."""
    return load_chain(args.robot, args.base, args.tip, **xacro_options(args))


def load_chain(robot: str, base: str | None = None, tip: str | None = None, *,
               xacro_args: Mapping[str, str] | None = None, package_paths: Sequence[str] = ()) -> SerialChain:
    """The chain of a model name, robot file or URDF, refused with one line if its numbers are absurd.

    A file may hold any finite number; a length of 1e308 m overflows the first product of the loader (numpy's
    warnings) or of every command after it.  Overflow while loading is a ValueError that names the file; a length
    beyond :data:`MAX_LENGTH` (``a``, ``d``, base and tool translations) is refused by the chain itself.  A
    ``UserWarning`` of the loader (a xacro argument the file does not know) is passed on, printed after the run.
    """
    from redkin.models import get_robot

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", RuntimeWarning)
        try:
            chain = get_robot(robot, base, tip, xacro_args=xacro_args, package_paths=package_paths)
        except ValueError:
            _refuse_overflow(robot, caught)
            raise
    _refuse_overflow(robot, caught)
    for warning in caught:
        if issubclass(warning.category, UserWarning):
            warnings.warn(warning.message, stacklevel=2)
    return chain


def _refuse_overflow(robot: str, caught: Sequence[warnings.WarningMessage]) -> None:
    numeric = [w for w in caught if issubclass(w.category, RuntimeWarning)]
    if numeric:
        raise UsageError(f"robot {robot!r}: its numbers do not compute ({numeric[0].message}); lengths must be at "
                         f"most {MAX_LENGTH:g} m in magnitude")


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
        raise UsageError(f"{chain.name} has {plural(chain.n, 'joint')}, got {len(values)} {name}")
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
        value = value.item()
    if isinstance(value, float):
        return value + 0.0  # -0.0 prints as 0.0
    return value


def print_json(value: Any) -> None:
    """Print ``value`` as JSON on stdout."""
    print(json.dumps(_to_jsonable(value), indent=2, allow_nan=False))


def fixed(value: float, digits: int = 6, sign: str = "") -> str:
    """``value`` with ``digits`` decimals; a value that rounds to zero prints as ``0.000000``, never ``-0.000000``.

    ``sign`` is the format's sign option: ``" "`` leaves a space where a minus sign would go (aligned columns).
    """
    text = f"{value:{sign}.{digits}f}"
    if text.lstrip().startswith("-") and float(text) == 0.0:
        text = f"{0.0:{sign}.{digits}f}"
    return text


def reach_reason(reach: Reach, index: Any = ()) -> dict[str, Any]:
    """The JSON of a pose's reason (pose ``index`` of ``reach``'s batch): ``{"reason": "out-of-reach", "reach":
    {...}}`` with the distances in metres where the pose is proven out of reach, else ``{"reason": None}``."""
    if not bool(reach.out[index]):
        return {"reason": None}
    return {"reason": "out-of-reach", "reach": {
        "measure": reach.measure, "distance": float(reach.distance[index]), "min": reach.lower, "max": reach.upper,
        "miss": float(reach.miss[index]),
    }}


def out_of_reach(reach: Reach, index: Any = ()) -> str:
    """Why pose ``index`` of ``reach``'s batch has no solution, in one line: ``the pose is out of reach (the
    shoulder-wrist distance is 10.003 m, beyond the reach of 0.93 m by 9.07305 m)``."""
    distance = float(reach.distance[index])
    side = (f"beyond the reach of {reach.upper:.6g} m" if distance > reach.upper else
            f"inside the shortest reach of {reach.lower:.6g} m")
    return f"the pose is out of reach ({reach.measure} is {distance:.6g} m, {side} by {float(reach.miss[index]):.6g} m)"


def plural(count: int, noun: str, many: str | None = None) -> str:
    """``"1 joint"``, ``"7 joints"``: the count and the noun in its right number (``many`` for an irregular
    plural)."""
    return f"{count} {noun if count == 1 else (many or noun + 's')}"


def format_matrix(matrix: np.ndarray, digits: int = 6) -> str:
    """A matrix as aligned text rows."""
    rows = np.atleast_2d(matrix)
    return "\n".join("  ".join(fixed(v, digits, " ") for v in row) for row in rows)


def format_values(values: Any, digits: int = 6) -> str:
    """A vector as aligned text, one space and a sign slot per value."""
    return " ".join(fixed(v, digits, " ") for v in np.ravel(values))


def format_exact(values: Any) -> str:
    """Numbers as Python's ``repr``, separated by spaces: the shortest text that reads back as the same float
    (``0.30700000000000005``, ``6.123233995736766e-17``), so that printed output pasted into an option is the
    number that was printed; ``-0.0`` prints as ``0.0``."""
    return " ".join(repr(float(v) + 0.0) for v in np.ravel(values))


#: Off a terminal, a progress line at each tenth, and one at least this often (seconds) in between.
_PROGRESS_LINE_EVERY = 60.0


class Progress:
    """``progress(fraction, detail="")`` of a long command, on ``stream`` (default stderr).

    On a terminal a bar is redrawn in place, ended by a newline on :meth:`close` once anything was drawn.
    Anywhere else (a file, a pipe, a CI log) ``\\r`` would pile every redraw into one long line, so it prints
    plain lines instead, ``progress: 14/27 chunks (51.9%)`` (``detail`` first where given): one at each tenth, one
    at least every :data:`_PROGRESS_LINE_EVERY` seconds while it moves, and the last.
    """

    def __init__(self, stream: Any = None) -> None:
        self.stream = sys.stderr if stream is None else stream
        self.terminal = bool(getattr(self.stream, "isatty", lambda: False)())
        self.drawn = False
        self.tenths = 0
        self.last = time.monotonic()

    def __call__(self, fraction: float, detail: str = "") -> None:
        if self.terminal:
            self.drawn = True
            filled = int(30 * fraction)
            print(f"\r[{'#' * filled}{'.' * (30 - filled)}] {100 * fraction:5.1f}%", end="", file=self.stream,
                  flush=True)
            return
        tenths, now = int(10 * fraction + 1e-9), time.monotonic()
        if fraction >= 1.0 or tenths > self.tenths or now - self.last >= _PROGRESS_LINE_EVERY:
            self.tenths, self.last = tenths, now
            text = f"{detail} ({100 * fraction:.1f}%)" if detail else f"{100 * fraction:.1f}%"
            print(f"progress: {text}", file=self.stream, flush=True)

    def close(self) -> None:
        """End the bar's line (on a terminal, once anything was drawn)."""
        if self.drawn:
            print(file=self.stream, flush=True)


def add_force_flag(parser: argparse.ArgumentParser) -> None:
    """``--force``: replace output files that exist (without it the command refuses, before any work)."""
    parser.add_argument("--force", action="store_true",
                        help="replace an output file that already exists (without it the command refuses to)")


def output_file(path: str | os.PathLike, option: str, suffixes: Collection[str] | None, force: bool) -> Path:
    """The file an option names, checked before any work is done: ``suffixes`` (lower case, with the dot), a
    folder that exists or can be made and is writable, and no file there already unless ``force``.

    Every command that writes a file goes through here, so that no output is replaced without the user asking
    (``--force``): a refusal costs a re-run with one more flag, a silent overwrite can cost a result.
    """
    file = check_output_file(path, option, suffixes)
    if file.exists():
        if not force:
            raise UsageError(f"{option} {str(file)!r} already exists: add --force to replace it, or choose "
                             "another name")
        _check_replaceable(file, option)
    return file


def output_directory(path: str | os.PathLike, option: str, owned: Sequence[str], force: bool) -> Path:
    """A folder a command writes its files into (made if needed), refused if it already holds one of the
    ``owned`` files of an earlier run, unless ``force``."""
    directory = check_output_directory(path, option)
    earlier = [name for name in owned if (directory / name).exists()]
    if earlier and not force:
        raise UsageError(f"{option} {str(directory)!r} already holds {earlier[0]} of an earlier run: add --force to "
                         "replace it, or choose another folder")
    for name in earlier:
        _check_replaceable(directory / name, option)
    return directory


def _check_replaceable(file: Path, option: str) -> None:
    """Open an existing file for appending (which changes nothing) to learn whether it can be replaced."""
    try:
        with open(file, "ab"):
            pass
    except OSError as exc:
        raise UsageError(f"cannot write to {option} {str(file)!r}: {exc.strerror or exc}") from None


def plus_minus(stream: Any = None) -> str:
    """``"±"``, or ``"+-"`` where the output stream cannot encode it."""
    encoding = getattr(stream or sys.stdout, "encoding", None) or "ascii"
    try:
        "±".encode(encoding)
    except (LookupError, UnicodeEncodeError):
        return "+-"
    return "±"
