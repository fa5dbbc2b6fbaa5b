"""Results kept on disk between runs: what costs a command seconds and depends only on files or numbers it is given
(a mesh's covering capsules, :mod:`redkin.collision.mesh_cache`; a nearly S-R-S arm's model error,
:func:`redkin.srs.conventions.model_error`) is computed once per machine and read back after.

Each result is a JSON file named by a digest of everything it depends on (the caller's key), in a folder of its
kind under ``$REDKIN_CACHE_DIR``, else ``$XDG_CACHE_HOME/redkin``, else ``~/.cache/redkin``.  JSON writes floats as
Python does, so they read back exactly.  A folder that cannot be written, or a file that cannot be read back, only
costs the time: the result is computed again.
"""

from __future__ import annotations

import json
import os
import tempfile
from pathlib import Path
from typing import Any


def cache_folder(kind: str) -> Path:
    """The folder of results of ``kind`` (module docstring)."""
    if os.environ.get("REDKIN_CACHE_DIR"):
        root = Path(os.environ["REDKIN_CACHE_DIR"])
    elif os.environ.get("XDG_CACHE_HOME"):
        root = Path(os.environ["XDG_CACHE_HOME"]) / "redkin"
    else:
        root = Path.home() / ".cache" / "redkin"
    return root / kind


def kept(kind: str, key: str | None) -> Any | None:
    """The result of ``kind`` kept as ``key``, or ``None`` where there is none that reads back as JSON."""
    if key is None:
        return None
    try:
        return json.loads((cache_folder(kind) / f"{key}.json").read_text())
    except (OSError, ValueError):
        return None


def keep(kind: str, key: str | None, result: Any) -> None:
    """Keep ``result`` (JSON) as ``key`` (written whole, then renamed into place); nothing where the folder cannot be
    written."""
    if key is None:
        return
    folder = cache_folder(kind)
    part: Path | None = None
    try:
        folder.mkdir(parents=True, exist_ok=True)
        with tempfile.NamedTemporaryFile("w", dir=folder, suffix=".part", delete=False) as file:
            part = Path(file.name)
            json.dump(result, file)
        os.replace(part, folder / f"{key}.json")
    except OSError:
        if part is not None:
            part.unlink(missing_ok=True)
