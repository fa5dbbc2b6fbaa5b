"""The README's command lines as a newcomer types them: each runs from an empty folder and succeeds (exit code 0;
a ``$ `` transcript prints what the README shows).

A shell block is a fenced block without a language.  Each of its ``redkin`` lines is a test of its own, run in
this process through :func:`redkin.cli.main.main` in a new empty folder, after the ``python -c`` lines above it in
its block (each a new interpreter: they write the files the line reads); the robot files come from the shipped
examples, :mod:`redkin.examples`.  ``pip install`` and ``apt-get install`` lines are set-up, and
``python -m pytest`` is this suite: they are not run.  A block of program output (``planar-5: converged ...``)
holds no command.  The README's ``redkin reproduce --out report`` is run once per session, as written and from an
empty folder, by the ``full_report`` fixture (tests/conftest.py) that the report's own tests read; here it is only
looked up.  Slow: about six minutes in all on 2 cores, most of it compiling the kernels each command uses (the
workspace maps and ``redkin compile`` take longest).
"""

from __future__ import annotations

import os
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

from redkin.cli.main import main
from tests.conftest import FULL_REPORT_COMMAND

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"

#: First words of the lines that set up (installs) or are this suite or CI's documentation build (.ci/run runs it):
#: not run here.
SET_UP = ("pip install", "apt-get install", "python -m pytest", "python -m mkdocs")


def shell_blocks(text: str) -> list[str]:
    """The text of every fenced block without a language, in order (fences read in pairs, opening and closing)."""
    blocks, language, lines = [], None, []
    for line in (line.strip() for line in text.splitlines()):  # fences in a list item are indented
        if language is None and line.startswith("```"):
            language, lines = line[3:].strip(), []
        elif language is not None and line.strip() == "```":
            if not language:
                blocks.append("\n".join(lines) + "\n")
            language = None
        elif language is not None:
            lines.append(line)
    return blocks


def commands(block: str) -> list[str]:
    """The lines of a block to run, ``$ `` dropped from a transcript's commands; [] for a block of output.

    A line of a block of commands is split at ``&&`` (``pip install -e . && redkin reproduce --out report``).
    """
    lines = [line.strip() for line in block.splitlines() if line.strip()]
    if lines[0].startswith("$ "):
        return [line[2:] for line in lines if line.startswith("$ ")]
    if not lines[0].startswith(("redkin ", "python ", "pip ", "apt-get ")):
        return []
    return [part.strip() for line in lines for part in line.split("&&")]


BLOCKS = [block for block in shell_blocks(README.read_text(encoding="utf-8")) if commands(block)]


def _runnable(block: str) -> list[str]:
    return [line for line in commands(block) if not line.startswith(SET_UP)]


def _transcript(block: str) -> dict[str, str]:
    """A ``$ `` transcript's commands and the output the README shows under each."""
    shown: dict[str, list[str]] = {}
    current = None
    for line in block.strip().splitlines():
        if line.startswith("$ "):
            current = line[2:].strip()
            shown[current] = []
        elif current is not None:
            shown[current].append(line)
    return {command: "\n".join(lines) for command, lines in shown.items()}


def _cases() -> list:
    """One case per ``redkin`` line to run: the block, the line, and the ``python -c`` lines before it in its block
    (they write the files it reads)."""
    cases = []
    for index, block in enumerate(BLOCKS):
        lines = _runnable(block)
        for k, line in enumerate(lines):
            if line.startswith("redkin "):
                makers = [before for before in lines[:k] if before.startswith("python -c ")]
                command = line.split(" #")[0].strip()
                cases.append(pytest.param(block, line, makers, id=f"block{index + 1}-{command[:60]}"))
    return cases


def test_the_readme_has_its_command_blocks():
    """The extraction itself: the set-up blocks, the fk line, a transcript, and no line the test would not run or
    skip knowingly (a ``~`` or ``$(...)`` would need a shell)."""
    lines = [line for block in BLOCKS for line in commands(block)]
    assert len(BLOCKS) >= 20 and "pip install -e ." in lines and FULL_REPORT_COMMAND in lines
    assert any(line.startswith("redkin fk pa10-7c") for line in lines)
    assert any(block.lstrip().startswith("$ ") for block in BLOCKS)
    for line in lines:
        assert line.startswith(("redkin ", "python -c ", *SET_UP)), line
        assert "~" not in line.split("#")[0] and "$(" not in line, line


@pytest.mark.slow
@pytest.mark.parametrize(("block", "line", "makers"), _cases())
def test_every_readme_command_runs_from_an_empty_folder(block, line, makers, tmp_path, monkeypatch, capsys, request):
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("MPLBACKEND", "Agg")
    env = {**os.environ, "PYTHONPATH": str(ROOT / "src")}
    for maker in makers:
        result = subprocess.run([sys.executable, *shlex.split(maker)[1:]], cwd=tmp_path, env=env,
                                capture_output=True, text=True, timeout=600)
        assert result.returncode == 0, f"{maker}\n{result.stderr[-2000:]}"
    if line.split(" #")[0].strip() == FULL_REPORT_COMMAND:
        report = request.getfixturevalue("full_report")
        assert report.name == "report" and (report / "index.html").is_file()
        return
    capsys.readouterr()
    code = main(shlex.split(line, comments=True)[1:])
    out, err = capsys.readouterr()
    shown = _transcript(block) if block.lstrip().startswith("$ ") else {}
    if line in shown:  # a transcript: the README shows its output
        assert out.strip() == shown[line].strip(), f"{line}\nprinted:\n{out}"
        assert code == 1, f"{line}: exit code {code}\n{err}"  # no solution: exit code 1
    else:
        assert code == 0, f"{line}: exit code {code}\n{err[-2000:]}"
