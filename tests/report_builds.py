"""The full reproduction report, built once per test session and shared by the tests that read it.

Building every section takes about a minute; the section tests and the
browser tests read the same files instead of building them twice.  Tests
must not change them.
"""

from __future__ import annotations

import atexit
import functools
import shutil
import tempfile
from pathlib import Path

from redkin import reproduce


@functools.lru_cache(maxsize=None)
def full_report() -> Path:
    """The folder of ``redkin reproduce`` with every section (index.html, summary.json, figures, explorers)."""
    folder = Path(tempfile.mkdtemp(prefix="redkin-report-"))
    atexit.register(shutil.rmtree, folder, True)
    reproduce.run(folder)
    return folder
