"""The errors redkin raises for input it cannot use, one class per thing a caller handles differently.

Every one is a :class:`ValueError`, so ``except ValueError`` keeps catching
them all; the classes let a caller tell them apart without reading the
message, e.g. skip the unreachable poses of a batch but stop on a broken
robot file::

    try:
        q = ik(arm, poses, psi)
    except UnreachablePoseError as error:
        print(f"pose {error.index} is out of reach ({error.count} in all)")

The command line turns any of them into one line on stderr and exit code 2.
"""

from __future__ import annotations


class RedkinError(ValueError):
    """Input redkin cannot use: a wrong shape, NaN, a non-orthonormal rotation, an out-of-range parameter.

    The base of the classes below; raised as itself where no subclass fits.
    """


class UnreachablePoseError(RedkinError):
    """A target pose whose wrist the arm cannot reach ([000 eq. 11] has no solution).

    Attributes
    ----------
    index : tuple of int
        Batch index of the first unreachable pose (``()`` for a single pose).
    count : int
        How many poses of the batch are unreachable.
    """

    def __init__(self, message: str, index: tuple[int, ...] = (), count: int = 1) -> None:
        super().__init__(message)
        self.index = index
        self.count = count


class NotArmAngleClassError(RedkinError):
    """A chain without arm-angle inverse kinematics: not 7R, or its shoulder or wrist axes do not meet.

    Attributes
    ----------
    chain_name : str
    distance : float or None
        The measured departure from the class where one applies (metres, or
        radians for angles between axes), else ``None``; the message names it.
    """

    def __init__(self, message: str, chain_name: str = "", distance: float | None = None) -> None:
        super().__init__(message)
        self.chain_name = chain_name
        self.distance = distance


class RobotDescriptionError(RedkinError):
    """A robot description that cannot be read: a missing or malformed file, a bad key or value.

    Attributes
    ----------
    path : str
        The file ('' for a description given in memory).
    key : str
        The key, joint or link at fault ('' when the file as a whole is).
    """

    def __init__(self, message: str, path: str = "", key: str = "") -> None:
        super().__init__(message)
        self.path = path
        self.key = key


class SizeLimitError(RedkinError):
    """A requested size beyond the limit redkin states for it (grid resolution, samples, steps).

    Attributes
    ----------
    name : str
    value : float
    maximum : float
    """

    def __init__(self, message: str, name: str = "", value: float = 0.0, maximum: float = 0.0) -> None:
        super().__init__(message)
        self.name = name
        self.value = value
        self.maximum = maximum


class MapStoreError(RedkinError):
    """A workspace map's store that cannot take this run now: another run holds it, or its disk is full.

    Nothing computed is lost either way: the chunks complete so far stay in
    the store, and the same call resumes it once the other run has ended or
    space is free (:mod:`redkin.workspace.store`).

    Attributes
    ----------
    path : str
        The store (or the file being written).
    reason : str
        ``"in use"`` (another run holds the store) or ``"no space"`` (a full disk or quota).
    """

    def __init__(self, message: str, path: str = "", reason: str = "") -> None:
        super().__init__(message)
        self.path = path
        self.reason = reason

    def __reduce__(self) -> tuple:
        """Pickle with the attributes (errors cross processes pickled: multiprocessing, dask.distributed)."""
        return type(self), (str(self), self.path, self.reason)
