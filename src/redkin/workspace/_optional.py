"""The optional packages of the workspace maps (``pip install 'redkin[workspace]'``), imported on first use."""

from __future__ import annotations

import importlib
from types import ModuleType

#: The one line a plain install prints when a workspace map is asked for.
_INSTALL_HINT = "workspace maps need dask, distributed, zarr and xarray: pip install 'redkin[workspace]'"


def require(name: str) -> ModuleType:
    """Import the module ``name`` of the ``workspace`` extra, or raise ``ImportError`` with :data:`_INSTALL_HINT`."""
    try:
        return importlib.import_module(name)
    except ImportError as exc:
        raise ImportError(f"{_INSTALL_HINT} ({exc})") from None
