"""The optional packages of the workspace maps (the ``workspace`` extra), imported on first use."""

from __future__ import annotations

import importlib
from types import ModuleType

from redkin._extras import missing_extra

#: The one line a plain install prints when a workspace map is asked for.
_INSTALL_HINT = missing_extra("workspace maps need dask, distributed, zarr and xarray", "workspace")


def require(name: str) -> ModuleType:
    """Import the module ``name`` of the ``workspace`` extra, or raise ``ImportError`` with :data:`_INSTALL_HINT`."""
    try:
        return importlib.import_module(name)
    except ImportError as exc:
        raise ImportError(f"{_INSTALL_HINT} ({exc})") from None
