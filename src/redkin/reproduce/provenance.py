"""Where a report comes from: the date it was made, redkin's version and the commit of the source."""

from __future__ import annotations

import subprocess
from datetime import datetime, timezone
from pathlib import Path

from redkin import __version__


def build_info() -> dict[str, str]:
    """``{"date", "version", "commit"}`` for the report's header and ``summary.json``."""
    return {
        "date": datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
        "version": __version__,
        "commit": _source_commit(),
    }


def _source_commit() -> str:
    """The git commit of redkin's source, ``-dirty`` when it has local changes; ``unknown`` outside a checkout."""
    try:
        done = subprocess.run(["git", "describe", "--always", "--dirty", "--abbrev=12"],
                              cwd=Path(__file__).resolve().parent, capture_output=True, text=True, timeout=30)
    except (OSError, subprocess.SubprocessError):
        return "unknown (git not available)"
    commit = done.stdout.strip()
    return commit if done.returncode == 0 and commit else "unknown (not a git checkout)"
