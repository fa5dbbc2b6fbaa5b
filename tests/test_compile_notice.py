"""The first compile of a process says so, once, on stderr (issue 23); a filled cache says nothing."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

FIRST_CALL = """
import numpy as np
from redkin._compiled import on_compile
from redkin.models import kuka_iiwa14
names = []
on_compile(names.append)
chain = kuka_iiwa14()
chain.fk(np.zeros(7)); chain.jacobian(np.zeros(7))
print(len(names), ' '.join(sorted(set(names))))
"""


def _run(cache: str, **env: str) -> subprocess.CompletedProcess:
    environment = {**os.environ, "NUMBA_CACHE_DIR": cache, **env}
    environment.pop("REDKIN_COMPILE_NOTICE", None)
    environment.update(env)
    return subprocess.run([sys.executable, "-c", FIRST_CALL], env=environment, capture_output=True, text=True,
                          timeout=600)


@pytest.mark.slow
def test_a_fresh_cache_is_announced_once_and_a_filled_one_is_silent(tmp_path):
    cold = _run(str(tmp_path))
    assert cold.returncode == 0, cold.stderr
    lines = [line for line in cold.stderr.splitlines() if line]
    assert len(lines) == 1 and lines[0].startswith("redkin: compiling its kernels for this machine")
    assert str(tmp_path) in lines[0]  # says where the cache went
    count, names = cold.stdout.split(maxsplit=1)
    assert int(count) >= 2 and "redkin._chain_kernels.frames" in names and "redkin._chain_kernels.jacobian" in names
    warm = _run(str(tmp_path))
    assert warm.returncode == 0 and warm.stderr == "" and warm.stdout.startswith("0")  # loaded: no compile at all


@pytest.mark.slow
def test_the_notice_can_be_turned_off(tmp_path):
    quiet = _run(str(tmp_path), REDKIN_COMPILE_NOTICE="0")
    assert quiet.returncode == 0 and quiet.stderr == ""
    assert int(quiet.stdout.split()[0]) >= 2  # it compiled, silently
