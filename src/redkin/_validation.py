"""Input checks used at the public edge of redkin.

Every public function validates what it receives with one of these helpers
and raises :class:`redkin.errors.RedkinError` (a ``ValueError``) with a
message that names the argument, what was expected and what was received;
a size beyond its stated maximum raises :class:`redkin.errors.SizeLimitError`.
Inside the library the data is trusted.
"""

from __future__ import annotations

import errno
import math
import os
import tempfile
from collections.abc import Collection
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from redkin._constants import MAX_LENGTH  # largest length a description or a pose may hold
from redkin.errors import RedkinError, SizeLimitError

#: Tolerance on ``R R^T = I`` (max abs entry) and ``det R = 1`` for rotations.
ROTATION_TOLERANCE = 1e-6
_EYE3 = np.eye(3)
_LAST_ROW = np.array([0.0, 0.0, 0.0, 1.0])
_SMALL_ARRAY = 32


def as_float_array(value: ArrayLike, name: str) -> np.ndarray:
    """Convert ``value`` to a float array, raising ``ValueError`` if it is not numeric: complex numbers (numpy would
    drop their imaginary parts with a warning) and text (numpy would read ``'0.1'`` as a number) are refused."""
    kind = "numeric"
    try:
        array = np.asarray(value)
        if array.dtype.kind == "c":
            kind = "real numbers, not complex ones"
        if array.dtype.kind in "cUSV":
            raise TypeError(array.dtype)
        return array.astype(float, copy=False)
    except (TypeError, ValueError) as exc:
        shown = repr(value) if len(repr(value)) <= 60 else repr(value)[:57] + "..."
        raise RedkinError(f"{name} must be {kind}, got {shown}") from exc


def check_finite(array: np.ndarray, name: str) -> None:
    """Raise ``ValueError`` if ``array`` holds NaN or infinity."""
    # A joint vector or a pose is checked in plain Python: a third of numpy's per-call overhead.
    small = array.size <= _SMALL_ARRAY
    if not (all(map(math.isfinite, array.ravel().tolist())) if small else np.isfinite(array).all()):
        raise RedkinError(f"{name} must be finite, got NaN or infinity")


def check_vectors(value: ArrayLike, length: int, name: str) -> np.ndarray:
    """Return ``value`` as a finite float array of shape ``(..., length)``."""
    array = as_float_array(value, name)
    if array.ndim == 0 or array.shape[-1] != length:
        raise RedkinError(
            f"{name} must have shape (..., {length}), got shape {array.shape}"
        )
    check_finite(array, name)
    return array


def _check_matrices(value: ArrayLike, rows: int, cols: int, name: str) -> np.ndarray:
    """Return ``value`` as a finite float array of shape ``(..., rows, cols)``."""
    array = as_float_array(value, name)
    if array.ndim < 2 or array.shape[-2:] != (rows, cols):
        raise RedkinError(
            f"{name} must have shape (..., {rows}, {cols}), got shape {array.shape}"
        )
    check_finite(array, name)
    return array


def check_rotation(
    value: ArrayLike, name: str = "rotation", tolerance: float = ROTATION_TOLERANCE
) -> np.ndarray:
    """Return ``value`` as rotation matrices of shape ``(..., 3, 3)``.

    Raises ``ValueError`` unless every matrix is finite, orthonormal
    (``max |R R^T - I| <= tolerance``) and proper (``det R > 0``: orthonormal, its determinant is then +1 within
    about 4.5 times the tolerance).
    """
    rotation = _check_matrices(value, 3, 3, name)
    _check_proper_orthonormal(rotation, name, tolerance)
    return rotation


def _check_proper_orthonormal(rotation: np.ndarray, name: str, tolerance: float) -> None:
    """The orthonormality and determinant tests of :func:`check_rotation` on a checked ``(..., 3, 3)`` array.

    An entry of an orthonormal matrix lies in ``[-1, 1]``; a larger one is refused before any product, so that a
    huge entry (1e308) gives the message below and not numpy's overflow warning.
    """
    if rotation.size == 0:
        return
    if rotation.size <= _SMALL_ARRAY:  # one matrix: in plain Python, a third of numpy's per-call cost
        entries = rotation.ravel().tolist()
        largest = max(max(entries), -min(entries))
    else:
        largest = float(np.abs(rotation).max())
    if largest > 1.0 + tolerance:
        raise RedkinError(
            f"{name} must be orthonormal (R R^T = I within {tolerance:g}), "
            f"but it has an entry of magnitude {largest:.3g} (a rotation's entries lie in [-1, 1])"
        )
    deviation = rotation @ np.swapaxes(rotation, -1, -2)
    deviation -= _EYE3
    worst = float(np.abs(deviation).max())
    if worst > tolerance:
        raise RedkinError(
            f"{name} must be orthonormal (R R^T = I within {tolerance:g}), "
            f"largest deviation is {worst:.3g}"
        )
    # Orthonormal within the tolerance, |det R| is 1 within about 4.5 times it (Gershgorin on R R^T), so the
    # determinant only tells a rotation from a reflection: its sign.
    det = np.ravel(np.linalg.det(rotation))
    if float(det.min()) <= 0.0:
        raise RedkinError(f"{name} must be a proper rotation (det = +1), got det = {float(det.min()):.6g}")


def check_quaternion(
    value: ArrayLike, name: str = "quaternion", tolerance: float = ROTATION_TOLERANCE
) -> np.ndarray:
    """Return ``value`` as quaternions of shape ``(..., 4)``.

    Raises ``ValueError`` unless every quaternion is finite and of unit norm
    (``| |q| - 1 | <= tolerance``); the order of the entries is the caller's.
    """
    quaternion = check_vectors(value, 4, name)
    if quaternion.size == 0:
        return quaternion
    norm = np.linalg.norm(quaternion, axis=-1)
    farthest = int(np.argmax(np.abs(norm - 1.0)))
    if abs(float(norm.flat[farthest]) - 1.0) > tolerance:
        raise RedkinError(f"{name} must have norm 1 (within {tolerance:g}), got norm {float(norm.flat[farthest]):.6g}")
    return quaternion


def check_output_array(out: object, shape: tuple[int, ...], name: str = "out") -> np.ndarray:
    """``out`` where a kernel can write float64 results of shape ``shape`` into it in place (a buffer the caller
    reuses across calls, so that a batch pays no fresh allocation and page faults).

    Raises
    ------
    RedkinError
        For anything else: another type, shape or dtype, a strided or read-only array.
    """
    if not isinstance(out, np.ndarray):
        raise RedkinError(f"{name} must be a numpy array, not {type(out).__name__}")
    if out.shape != shape or out.dtype != np.float64:
        raise RedkinError(f"{name} must be a float64 array of shape {shape}, not {out.dtype} of shape {out.shape}")
    if not (out.flags.c_contiguous and out.flags.writeable):
        raise RedkinError(f"{name} must be C-contiguous and writeable (np.empty(shape) is)")
    return out


def check_pose(value: ArrayLike, name: str = "pose", tolerance: float = ROTATION_TOLERANCE) -> np.ndarray:
    """Return ``value`` as homogeneous transforms of shape ``(..., 4, 4)``.

    The rotation block must pass :func:`check_rotation`, the last row must be ``[0, 0, 0, 1]``, and the translation
    be at most :data:`MAX_LENGTH` metres in each coordinate (a pose 1e160 m away made NaN distances).
    """
    pose = _check_matrices(value, 4, 4, name)
    if pose.size and float(np.abs(pose[..., 3, :] - _LAST_ROW).max()) > tolerance:
        raise RedkinError(f"{name} must have last row [0, 0, 0, 1]")
    if pose.size:
        far = max(map(abs, pose[:3, 3].tolist())) if pose.ndim == 2 else np.abs(pose[..., :3, 3]).max()
        if far > MAX_LENGTH:
            raise RedkinError(f"{name} translation must be at most {MAX_LENGTH:g} m in magnitude, got {float(far):g} m")
    _check_proper_orthonormal(pose[..., :3, :3], f"{name} rotation block", tolerance)
    return pose


def check_positive(value: float, name: str) -> float:
    """Return ``value`` as a float, raising ``ValueError`` unless it is finite and > 0."""
    number = float(value)
    if not np.isfinite(number) or number <= 0.0:
        raise RedkinError(f"{name} must be a positive finite number, got {value!r}")
    return number


def check_jacobian_and_twist(
    jacobian: ArrayLike, twist: ArrayLike, one_redundant: bool = False
) -> tuple[np.ndarray, np.ndarray]:
    """Validate Jacobians ``(..., m, n)`` and twists ``(..., m)``; broadcast their leading axes.

    Parameters
    ----------
    one_redundant : bool
        Require ``n = m + 1`` (the cofactor methods of paper 003 assume one
        degree of redundancy, e.g. a 6 x 7 Jacobian).
    """
    jac = as_float_array(jacobian, "jacobian")
    if jac.ndim < 2:
        raise RedkinError(f"jacobian must have shape (..., m, n), got shape {jac.shape}")
    check_finite(jac, "jacobian")
    m, n = jac.shape[-2:]
    if one_redundant and n != m + 1:
        raise RedkinError(f"jacobian must have one more column than rows (e.g. 6 x 7), got {m} x {n}")
    vel = as_float_array(twist, "twist")
    if vel.ndim == 0 or vel.shape[-1] != m:
        raise RedkinError(f"twist must have shape (..., {m}) to match the jacobian, got shape {vel.shape}")
    check_finite(vel, "twist")
    try:
        lead = np.broadcast_shapes(jac.shape[:-2], vel.shape[:-1])
    except ValueError as exc:
        raise RedkinError(
            f"leading axes of jacobian {jac.shape[:-2]} and twist {vel.shape[:-1]} do not broadcast"
        ) from exc
    return np.broadcast_to(jac, lead + (m, n)), np.broadcast_to(vel, lead + (m,))


def check_magnitude(value: ArrayLike, name: str, maximum: float, unit: str = "") -> np.ndarray:
    """Return ``value`` as a finite float array whose entries are at most ``maximum`` in magnitude.

    For numbers that are finite but absurd (a link of 1e308 m): refused with the limit in the message, before
    they overflow in a product.
    """
    array = as_float_array(value, name)
    check_finite(array, name)
    if array.size:
        largest = float(np.abs(array).max())
        if largest > maximum:
            suffix = f" {unit}" if unit else ""
            raise RedkinError(f"{name} must be at most {maximum:g}{suffix} in magnitude, got {largest:g}{suffix}")
    return array


def check_nonnegative(value: float, name: str) -> float:
    """Return ``value`` as a float, raising ``RedkinError`` unless it is finite and >= 0."""
    number = float(value)
    if not np.isfinite(number) or number < 0.0:
        raise RedkinError(f"{name} must be a finite number >= 0, got {value!r}")
    return number


def check_count(value: float, name: str, minimum: int, maximum: int) -> int:
    """Return ``value`` as an int, raising ``RedkinError`` unless it is an integer in ``minimum..maximum``
    (:class:`~redkin.errors.SizeLimitError` above ``maximum``).

    Every size a user can choose (grid resolutions, sample counts, step
    budgets) has a stated ``maximum``, so that no call runs out of memory or
    time without saying so first; the message names the limit.
    """
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise RedkinError(f"{name} must be an integer in {minimum}..{maximum}, got {value!r}") from None
    message = f"{name} must be an integer in {minimum}..{maximum}, got {value!r}"
    if np.isfinite(number) and number > maximum:
        raise SizeLimitError(message, name=name, value=number, maximum=maximum)
    if not np.isfinite(number) or number != int(number) or number < minimum:
        raise RedkinError(message)
    return int(number)


def check_output_directory(path: str | os.PathLike, name: str) -> Path:
    """Create the directory ``path`` (with its parents) if needed and make sure a file can be written in it.

    Called before any work is done, so that an unwritable output fails at
    once with one line instead of after the computation.
    """
    directory = Path(path)
    if directory.exists() and not directory.is_dir():
        raise RedkinError(f"{name} {str(directory)!r} exists and is not a directory")
    try:
        directory.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryFile(dir=directory):
            pass
    except OSError as exc:
        # a folder that is there but takes no file (/proc) says "No such file or directory": say what it is
        reason = "it takes no new files" if exc.errno == errno.ENOENT and directory.is_dir() else exc.strerror or exc
        raise RedkinError(f"cannot write to {name} {str(directory)!r}: {reason}") from None
    return directory


def check_output_file(path: str | os.PathLike, name: str, suffixes: Collection[str] | None = None) -> Path:
    """Check that the file ``path`` can be written (its folder is created if needed), before any work is done.

    ``suffixes`` (lower case, with the dot) restricts the file types.
    """
    file = Path(path)
    if suffixes is not None and file.suffix.lower() not in suffixes:
        raise RedkinError(f"{name} must end in one of {', '.join(sorted(suffixes))}, got {str(file)!r}")
    longest = _longest_name(file.parent)
    if len(os.fsencode(file.name)) > longest:
        raise RedkinError(f"{name}: the file name {file.name[:40]!r}... is {len(os.fsencode(file.name))} bytes long; "
                          f"this file system takes at most {longest}")
    if file.is_dir():
        raise RedkinError(f"{name} {str(file)!r} is a directory, expected a file name")
    check_output_directory(file.parent, name)
    if file.exists() and not os.access(file, os.W_OK):
        raise RedkinError(f"cannot write to {name} {str(file)!r}: permission denied")
    return file


def _longest_name(directory: Path) -> int:
    """The longest file name (bytes) the file system of ``directory`` takes (255 where it does not say)."""
    try:
        return int(os.pathconf(directory, "PC_NAME_MAX"))
    except (OSError, ValueError, AttributeError):  # no pathconf (Windows), or no answer for this name
        return 255
