"""How kernels are compiled: cached where numba finds a cache directory, uncached (still working) where not."""

import numba
import pytest
from numba.core import config

from redkin._compiled import kernel


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


def test_a_cache_filled_by_other_kernels_is_emptied(tmp_path, monkeypatch):
    """numba checks a cached kernel against its own file only; redkin's stamp covers every kernel module."""
    import importlib.util

    from redkin import _compiled as compiled

    source = tmp_path / "kernel_module.py"
    source.write_text("def triple(x):\n    return 3.0 * x\n")
    spec = importlib.util.spec_from_file_location("kernel_module", source)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    monkeypatch.setattr(compiled, "_checked", set())
    first = kernel(module.triple)
    assert first(2.0) == 6.0
    cache = tmp_path / "__pycache__"
    assert (cache / compiled._STAMP_NAME).read_text() == compiled._core_digest()
    assert list(cache.glob("*.nbi")) and list(cache.glob("*.nbc"))
    kernel(module.triple)  # the same version in the same process: nothing is dropped
    assert list(cache.glob("*.nbi"))
    (cache / compiled._STAMP_NAME).write_text("another version of the kernels")
    monkeypatch.setattr(compiled, "_checked", set())  # as a new process would
    again = kernel(module.triple)
    assert not list(cache.glob("*.nbi")) and not list(cache.glob("*.nbc"))
    assert (cache / compiled._STAMP_NAME).read_text() == compiled._core_digest()
    assert again(2.0) == 6.0
