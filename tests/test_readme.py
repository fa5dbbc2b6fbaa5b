"""The README as a newcomer reads it: every ```python block runs on its own, as a script, and the examples show
what they say.

Each block runs in a new Python process (``MPLBACKEND=Agg``) in an empty folder of its own, where any file a block
writes (the explorer block's ``pa10.html``) lands; ``examples/iiwa14.urdf`` of the URDF block is the shipped
example (:mod:`redkin.examples`), read from there because the folder has no such file.  The command lines are run
by tests/test_readme_commands.py.  Slow: nine fresh processes, each importing redkin and loading its
compiled kernels.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"


def python_blocks(text: str) -> list[str]:
    """The code of every ```python block, in order."""
    return re.findall(r"^```python\n(.*?)^```", text, flags=re.S | re.M)


BLOCKS = python_blocks(README.read_text(encoding="utf-8"))


def run_script(code: str, folder: Path) -> subprocess.CompletedProcess:
    """``code`` as a script in a new interpreter, in ``folder``."""
    script = folder / "block.py"
    script.write_text(code, encoding="utf-8")
    env = {**os.environ, "MPLBACKEND": "Agg", "PYTHONPATH": str(ROOT / "src")}
    return subprocess.run([sys.executable, str(script)], cwd=folder, env=env, capture_output=True, text=True,
                          timeout=600)


def test_the_readme_has_its_blocks():
    """The extraction itself: the blocks of the sections, each starting with its imports."""
    assert len(BLOCKS) >= 9
    assert all(block.lstrip().startswith(("import ", "from ")) for block in BLOCKS), [b[:40] for b in BLOCKS]


@pytest.mark.slow
@pytest.mark.parametrize("index", range(len(BLOCKS)), ids=[f"block{i + 1}" for i in range(len(BLOCKS))])
def test_every_python_block_runs_alone(tmp_path, index):
    result = run_script(BLOCKS[index], tmp_path)
    assert result.returncode == 0, f"README block {index + 1}:\n{BLOCKS[index]}\n{result.stderr[-2000:]}"
    assert "Traceback" not in result.stderr


@pytest.mark.slow
def test_the_humanoid_example_prints_solutions_within_the_limits(tmp_path):
    """The thesis 001 block printed `ok` with `within_limits` all False: it now prints solutions within the limits,
    checked here against the chain's own limits."""
    (block,) = [b for b in BLOCKS if "humanoid_arm" in b and "ik(" in b]
    check = block + (
        "\nchain = humanoid_arm('right').chain\n"
        "shown = sol.q[sol.within_limits]\n"
        "assert str(sol.status_names()) == 'ok' and len(shown) > 0, sol.within_limits\n"
        "assert all(chain.within_limits(q) for q in shown), shown\n"
        "print('checked', len(shown))\n"
    )
    result = run_script(check, tmp_path)
    assert result.returncode == 0, result.stderr[-2000:]
    assert result.stdout.splitlines()[0].startswith("ok [ True")
    assert result.stdout.strip().endswith("checked 2")


@pytest.mark.slow
def test_the_virtual_arms_example_says_why_a_goal_is_not_met(tmp_path):
    """The block prints 'converged' with joint 3 3.5 cm short; it prints the run's message beside it, and the
    README's words after it match the command line's explanation."""
    (block,) = [b for b in BLOCKS if "generate_trajectory" in b]
    result = run_script(block, tmp_path)
    assert result.returncode == 0, result.stderr[-2000:]
    status, errors = result.stdout.splitlines()[:2]
    assert status.startswith("converged errors settled")
    assert "3.45" in errors or "3.46" in errors
    text = README.read_text(encoding="utf-8")
    assert '"Converged" means the dynamics came to rest' in text and "out of its reach (joint 1 fixed)" in text
