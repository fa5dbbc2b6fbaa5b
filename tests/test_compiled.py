"""How kernels are compiled: cached where numba finds a cache directory, uncached (still working) where not."""

import numba
import pytest
from numba.core import config

from redkin.compiled import kernel


def twice(x):
    return 2.0 * x


def test_kernel_caches_where_a_cache_directory_is_writable():
    compiled = kernel(twice)
    assert compiled(1.5) == 3.0
    assert type(compiled._cache).__name__ != "NullCache"


def test_kernel_compiles_without_a_cache_where_none_is_writable(monkeypatch):
    """IPython's locator alone finds nothing for a file: what numba sees with a read-only install and home."""
    monkeypatch.setattr(config, "CACHE_LOCATOR_CLASSES", "IPythonCacheLocator")
    with pytest.raises(RuntimeError, match="no locator available"):
        numba.njit(cache=True)(twice)
    compiled = kernel(parallel=False)(twice)
    assert compiled(1.5) == 3.0
    assert type(compiled._cache).__name__ == "NullCache"
