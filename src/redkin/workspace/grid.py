"""The box of positions of a workspace map and its division into chunks."""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from redkin._constants import WORKSPACE_MAX_CHUNKS as MAX_CHUNKS  # most chunks of a map
from redkin._constants import WORKSPACE_MAX_ORIENTATIONS as MAX_ORIENTATIONS  # most orientations of a map
from redkin._constants import WORKSPACE_MAX_POSES as MAX_POSES  # most poses of a map
from redkin._constants import WORKSPACE_MAX_RESOLUTION as MAX_RESOLUTION  # most grid points per axis
from redkin._validation import MAX_LENGTH, as_float_array, check_count, check_magnitude
from redkin.errors import RedkinError, SizeLimitError

#: Poses one chunk aims at (positions x orientations): 8^3 positions at 500 orientations, 16 MB of
#: ``measure`` and about 0.7 s of one core per chunk, 13 824 chunks (Dask tasks, marker files) for the
#: 1 cm iiwa map instead of the 110 592 of 4^3-position chunks.
CHUNK_POSES = 262_144


@dataclass(frozen=True)
class WorkspaceGrid:
    """Grid points ``x, y, z`` (metres) of an axis-aligned box, cut into cubes of ``chunk`` points per axis.

    Attributes
    ----------
    extent : tuple of float
        ``(xmin, xmax, ymin, ymax, zmin, zmax)``, metres.
    resolution : int
        Points per axis, ends included.
    chunk : int
        Points per axis of a chunk (the last chunk of an axis may be shorter).
    """

    extent: tuple[float, ...]
    resolution: int
    chunk: int

    @property
    def axes(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The coordinates ``x, y, z`` of the grid, each of length ``resolution``."""
        lo, hi = self.extent[0::2], self.extent[1::2]
        return tuple(np.linspace(a, b, self.resolution) for a, b in zip(lo, hi))  # type: ignore[return-value]

    @property
    def chunk_counts(self) -> tuple[int, int, int]:
        """Chunks along x, y and z."""
        count = -(-self.resolution // self.chunk)
        return (count, count, count)

    def chunk_indices(self) -> list[tuple[int, int, int]]:
        """Every chunk's index ``(i, j, k)``, in C order."""
        ni, nj, nk = self.chunk_counts
        return list(itertools.product(range(ni), range(nj), range(nk)))

    def chunk_slices(self, index: tuple[int, int, int]) -> tuple[slice, slice, slice]:
        """The grid slices of chunk ``index`` along x, y, z."""
        return tuple(slice(i * self.chunk, min((i + 1) * self.chunk, self.resolution)) for i in index)  # type: ignore[return-value]

    def chunk_positions(self, index: tuple[int, int, int]) -> np.ndarray:
        """Positions of chunk ``index``, shape ``(nx, ny, nz, 3)``, metres."""
        coordinates = [axis[s] for axis, s in zip(self.axes, self.chunk_slices(index))]
        return np.stack(np.meshgrid(*coordinates, indexing="ij"), axis=-1)


def workspace_grid(extent: ArrayLike, resolution: int, orientations: int, chunk: int | None = None) -> WorkspaceGrid:
    """A checked :class:`WorkspaceGrid`.

    Parameters
    ----------
    extent : array_like, shape (6,)
        ``xmin, xmax, ymin, ymax, zmin, zmax`` in metres, each minimum below its maximum.
    resolution : int
        Points per axis, ``2..MAX_RESOLUTION``.
    orientations : int
        Orientations per position (sizes the default chunk); grid points times orientations at most
        ``MAX_POSES``.
    chunk : int, optional
        Points per axis of a chunk, ``1..resolution``, cutting the grid into at most ``MAX_CHUNKS`` chunks; default:
        the largest cube of at most :data:`CHUNK_POSES` poses.

    Raises
    ------
    ValueError
        Naming the argument that is malformed or out of range; :class:`~redkin.errors.SizeLimitError` for more
        poses or chunks than those limits.
    """
    box = as_float_array(extent, "extent").reshape(-1)
    if box.shape != (6,):
        raise RedkinError(f"extent must have 6 numbers (xmin xmax ymin ymax zmin zmax), got {box.size}")
    check_magnitude(box, "extent", MAX_LENGTH, "m")  # finite but absurd (1e308) overflows the grid's steps
    for axis, (lo, hi) in zip("xyz", box.reshape(3, 2)):
        if not lo < hi:
            raise RedkinError(f"extent: {axis}min must be below {axis}max, got {lo:g} and {hi:g}")
    m = check_count(resolution, "resolution", 2, MAX_RESOLUTION)
    orientations = check_count(orientations, "orientations", 1, MAX_ORIENTATIONS)
    poses = m**3 * orientations
    if poses > MAX_POSES:
        raise SizeLimitError(f"{m}^3 grid points x {int(orientations)} orientations are {poses:.3g} poses, more than "
                             f"{MAX_POSES:.0e} (a size too large to compute): lower the resolution or the "
                             "orientations", "poses", poses, MAX_POSES)
    if chunk is None:
        edge = int(np.floor((CHUNK_POSES / max(int(orientations), 1)) ** (1.0 / 3.0) + 1e-9))
        chunk = min(max(edge, 1), m)
    grid = WorkspaceGrid(tuple(float(v) for v in box), m, check_count(chunk, "chunk", 1, m))
    chunks = grid.chunk_counts[0] ** 3
    if chunks > MAX_CHUNKS:
        raise SizeLimitError(f"chunks of {grid.chunk}^3 grid points cut the {m}^3 grid into {chunks:.3g} chunks, more "
                             f"than {MAX_CHUNKS:.0e}: give a larger chunk", "chunks", chunks, MAX_CHUNKS)
    return grid
