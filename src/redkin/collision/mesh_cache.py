"""The covers of mesh files kept on disk (issue 40): a maker's URDF names its meshes in every command, and covering
them takes seconds (:mod:`redkin.collision.mesh_cover`), so each cover is computed once per file.

A cover is found by a digest of the file's bytes, its scale, the kind (capsules for the arm's links, boxes for a
scene's obstacles) and the source of the covering modules, so that an edited mesh, another scale or another version
of the fit is computed afresh.  It is kept as JSON under ``mesh-covers`` in redkin's cache folder
(:mod:`redkin._disk_cache`: a folder that cannot be written, or a file that cannot be read back, only costs the
time).
"""

from __future__ import annotations

import functools
import hashlib
from pathlib import Path

import numpy as np
from numpy.typing import ArrayLike

from redkin._disk_cache import keep, kept
from redkin.collision import _mesh_kernels, mesh_cover, mesh_files
from redkin.collision.mesh_cover import MeshBox, MeshCapsule, covering_boxes, covering_capsules
from redkin.collision.mesh_files import read_mesh

#: The folder of the covers in redkin's cache (:mod:`redkin._disk_cache`).
_KIND = "mesh-covers"


def covered_capsules(path: Path, scale: ArrayLike | None = None, least: int = 1) -> list[MeshCapsule]:
    """:func:`redkin.collision.mesh_cover.covering_capsules` of the mesh file (scaled; at least ``least`` capsules
    where the mesh can be cut so), from the cache where it is there (module docstring)."""
    key = _key(path, scale, "capsules" if least == 1 else f"capsules, at least {least}")
    found = _cached(key)
    if found is not None:
        return [MeshCapsule(np.array(c["a"]), np.array(c["b"]), c["radius"], c["reach"]) for c in found]
    capsules = covering_capsules(*read_mesh(path, scale), least=least)
    keep(_KIND, key, [{"a": c.a.tolist(), "b": c.b.tolist(), "radius": float(c.radius), "reach": float(c.reach)}
                      for c in capsules])
    return capsules


def covered_boxes(path: Path, scale: ArrayLike | None = None) -> list[MeshBox]:
    """:func:`redkin.collision.mesh_cover.covering_boxes` of the mesh file (scaled), from the cache where it is
    there (module docstring)."""
    key = _key(path, scale, "boxes")
    found = _cached(key)
    if found is not None:
        return [MeshBox(np.array(b["center"]), np.array(b["size"]), np.array(b["rotation"]), b["reach"])
                for b in found]
    boxes = covering_boxes(*read_mesh(path, scale))
    keep(_KIND, key, [{"center": b.center.tolist(), "size": b.size.tolist(), "rotation": b.rotation.tolist(),
                       "reach": float(b.reach)} for b in boxes])
    return boxes


def _key(path: Path, scale: ArrayLike | None, kind: str) -> str | None:
    """The cover's name: the digest of what it depends on (``None`` for a file that cannot be read)."""
    try:
        content = path.read_bytes()
    except OSError:
        return None
    factors = np.ones(3) if scale is None else np.asarray(scale, dtype=float).reshape(-1)
    digest = hashlib.sha256(content)
    digest.update(f"{kind} {factors.tolist()} {_code_digest()}".encode())
    return digest.hexdigest()


@functools.cache
def _code_digest() -> str:
    """A digest of the reading and covering modules' source: another reading or fit is another cover."""
    digest = hashlib.sha256()
    for module in (mesh_files, mesh_cover, _mesh_kernels):
        digest.update(Path(str(module.__file__)).read_bytes())
    return digest.hexdigest()[:16]


def _cached(key: str | None) -> list[dict] | None:
    """The kept cover named ``key`` (:func:`_key`), or ``None`` where there is none that reads back."""
    found = kept(_KIND, key)
    return found if isinstance(found, list) and found else None

