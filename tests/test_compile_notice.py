"""Compiling is said as it happens (issues 23 and 43): the first compile of a process says so once, on stderr, then
a line counts the kernels compiled, at least every few seconds while one compiles; a filled cache says nothing."""

from __future__ import annotations

import os
import re
import subprocess
import sys
import time

import pytest

from redkin import _compiled

#: A cold FK of the PA10 in a fresh process (the chain's kernels: about ten, a few seconds; ``redkin fk`` itself runs
#: them as Python, without numba), then the kernels it compiled, counted by redkin's own listener.
COMMAND = """
import numpy as np
from redkin import models
from redkin._compiled import on_compile
names = []
on_compile(names.append)
models.pa10_7c().fk(np.zeros(7))
print('compiled', len(names), 0)
"""

PROGRESS = re.compile(r"redkin: (\d+) kernels? compiled in (\d+\.\d) s(, compiling \w+(, about \d+ s left)?)?$")
#: The wait of a kernel the program called, after the notice (``: ``) or on a line of its own.
PLAN = re.compile(r"(\w+) and (\d+) kernels? it calls, about (\d+) s")


def _run(cache: str, **env: str) -> subprocess.CompletedProcess:
    environment = {**os.environ, "NUMBA_CACHE_DIR": cache}
    environment.pop("REDKIN_COMPILE_NOTICE", None)
    environment.update(env)
    return subprocess.run([sys.executable, "-c", COMMAND], env=environment, capture_output=True, text=True,
                          timeout=600)


def _compiled_count(result: subprocess.CompletedProcess) -> int:
    assert result.returncode == 0, result.stderr
    word, count, code = result.stdout.splitlines()[-1].split()
    assert word == "compiled" and code == "0"
    return int(count)


@pytest.mark.slow
def test_a_cold_command_counts_its_kernels_and_a_warm_one_is_silent(tmp_path):
    cold = _run(str(tmp_path))
    compiled = _compiled_count(cold)
    notice, *lines = cold.stderr.splitlines()
    assert notice.startswith("redkin: compiling its kernels for this machine") and str(tmp_path) in notice
    plan = PLAN.search(notice)  # the first kernel called, and the kernels it calls that it compiles
    assert plan and notice.endswith(plan[0] + "...")
    assert 0 < int(plan[2]) + 1 <= compiled and int(plan[3]) >= 0.4 * (int(plan[2]) + 1)
    lines = [line for line in lines if not (line.startswith("redkin: compiling ") and PLAN.fullmatch(line[18:]))]
    assert lines and all(PROGRESS.match(line) for line in lines), cold.stderr
    counts = [int(PROGRESS.match(line)[1]) for line in lines]
    seconds = [float(PROGRESS.match(line)[2]) for line in lines]
    assert counts == sorted(counts) and seconds == sorted(seconds)  # they move forward
    assert counts[-1] == compiled >= 2 and not PROGRESS.match(lines[-1])[3]  # the last: every kernel, done
    assert not re.search(r"[\x00-\x09\x0b-\x1f\x7f]", cold.stderr)  # a log gets whole lines, no control characters
    warm = _run(str(tmp_path))
    assert _compiled_count(warm) == 0 and warm.stderr == ""  # loaded from the cache: not a word


@pytest.mark.slow
def test_the_notice_can_be_turned_off(tmp_path):
    quiet = _run(str(tmp_path), REDKIN_COMPILE_NOTICE="0")
    assert _compiled_count(quiet) >= 2 and quiet.stderr == ""  # it compiled, silently


@pytest.fixture
def progress(monkeypatch):
    """A progress of its own (the process's is off in the tests), saying a line every 0.1 s while compiling."""
    monkeypatch.setattr(_compiled, "PROGRESS_SECONDS", 0.1)
    monkeypatch.setattr(_compiled, "_TICK", 0.02)
    made = _compiled._CompileProgress()
    made.enabled = True
    return made


def test_a_long_compile_is_said_again_while_it_lasts(progress, capsys):
    """A kernel compiling for longer than PROGRESS_SECONDS gets lines from the helper thread, in a log as whole
    lines; the outermost compile's end says the count of every kernel, its callees included."""
    progress.start("redkin.module.outer")
    progress.start("redkin.module.callee")
    progress.end()
    time.sleep(0.5)  # the outer kernel's own passes, after its callee
    progress.end()
    notice, *lines = capsys.readouterr().err.splitlines()
    assert notice.startswith("redkin: compiling its kernels")
    assert len(lines) >= 3  # two or more while the outer kernel compiles, then its end
    assert all(re.match(r"redkin: 1 kernel compiled in \d\.\d s, compiling outer$", line) for line in lines[:-1])
    last = PROGRESS.match(lines[-1])
    assert last and last[1] == "2" and float(last[2]) >= 0.5 and not last[3]
    time.sleep(0.3)  # nothing compiles: the helper says nothing
    assert capsys.readouterr().err == ""


def test_on_a_terminal_the_line_is_redrawn_and_ended_when_compiling_ends(progress, capsys, monkeypatch):
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True)
    monkeypatch.setattr(_compiled, "PROGRESS_SECONDS", 60.0)  # no line from the helper thread here
    progress.start("redkin.module.outer")
    progress.start("redkin.module.callee")
    progress.end()
    progress.end()
    err = capsys.readouterr().err
    notice, line, rest = err.split("\n")
    assert notice.startswith("\rredkin: compiling its kernels") and notice.endswith("\x1b[K")
    assert rest == "" and line.endswith("\x1b[K")  # the last drawing ended by a new line
    drawn = [re.sub(r" in \d+\.\d s", "", part.removesuffix("\x1b[K")) for part in line.split("\r")[1:]]
    assert drawn[:3] == ["redkin: 0 kernels compiled, compiling outer", "redkin: 0 kernels compiled, compiling callee",
                         "redkin: 1 kernel compiled, compiling outer"]
    assert drawn[-1] == "redkin: 2 kernels compiled"


def test_turned_off_it_says_nothing_and_starts_no_thread(progress, capsys):
    progress.enabled = False
    progress.start("redkin.module.outer")
    progress.end()
    assert capsys.readouterr().err == "" and progress.helper_process == 0 and progress.compiled == 1
    assert 0.0 <= progress.seconds < 1.0  # its compile seconds are counted from its start, so a later wait is right


def test_the_wait_counts_the_kernels_a_kernel_calls_that_are_not_compiled(progress, capsys):
    """The plan of an outermost compile names the kernels the called kernel reaches (:func:`_kernels_called`: by
    name, directly or through a module, across modules), less those this process compiled, at SECONDS_PER_KERNEL or
    this process's slower mean; a later outermost compile of 2 s or more says its own."""
    from redkin.franka import _kernels

    reached = {function.__name__ for function in _compiled._kernels_called(_kernels.feasible_poses.py_func)}
    assert {"feasible_poses", "feasible_q7", "solve_q7", "trig_value", "monotone_root", "chain_values",
            "in_limits"} <= reached  # chain_values and in_limits: from redkin.srs._ik_kernels
    assert not reached & {"frames_seven", "as_franka", "run_batch"}  # Python functions, not kernels
    progress.done = {f"redkin.franka._kernels.{name}" for name in ("solve_q7", "trig_value")}
    to_compile = progress._to_compile(_kernels.feasible_poses.py_func)
    uncached = [f for f in to_compile[1:] if f.__name__ not in ("solve_q7", "trig_value")]
    assert to_compile[0].__name__ == "feasible_poses" and len(to_compile) - 1 == len(uncached)
    assert {f.__name__ for f in to_compile} <= reached - {"solve_q7", "trig_value"}
    progress.start("redkin.franka._kernels.feasible_poses", _kernels.feasible_poses.py_func)
    progress.end()
    notice = capsys.readouterr().err.splitlines()[0]
    callees = len(to_compile) - 1
    wait = round(len(to_compile) * _compiled.SECONDS_PER_KERNEL)
    assert notice.endswith(f": feasible_poses and {callees} kernel{'' if callees == 1 else 's'} it calls, "
                           f"about {wait:.0f} s...")
    assert progress.rate() >= _compiled.SECONDS_PER_KERNEL
