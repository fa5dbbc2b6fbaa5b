"""A command that ran as Python on a fresh cache compiles its kernels in the background (redkin.cli.background_compile):
``redkin compile --section``, the lock that keeps one compile per cache, and the sections each such command names;
and a nearly S-R-S arm's path, compiled from its first call, compiles in two processes at once
(``redkin.cli.common.compiled_beside``)."""

import ast
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from redkin.cli.background_compile import (
    _ENVIRONMENT,
    OverTime,
    _compile_running,
    _lock_path,
    compile_lock,
    start,
    within_seconds,
)
from redkin.cli.cell import CELL_SETS_KERNELS, CELL_SETS_SECTIONS
from redkin.cli.explore import _PAGE_KERNELS, _PAGE_SECTIONS
from redkin.cli.path import (
    _BESIDE_KERNELS,
    _BESIDE_SECTIONS,
    _CELL_PATH_KERNELS,
    _FRANKA_PATH_KERNELS,
    _FRANKA_PATH_SECTIONS,
)
from redkin.cli.srs import (
    _NEARLY_SETS_KERNELS,
    _NEARLY_SETS_SECTIONS,
    _SELF_MOTION_KERNELS,
    _SELF_MOTION_SECTIONS,
)
from redkin.warm_up import SECTION_NAMES
from tests.support.cli import run

#: Each command that runs as Python until its kernels are cached: the kernels it checks and the sections it starts.
CALL_SITES = {
    "explorer page, S-R-S": (_PAGE_KERNELS["psi"], _PAGE_SECTIONS["psi"]),
    "explorer page, Franka class": (_PAGE_KERNELS["q7"], _PAGE_SECTIONS["q7"]),
    "path of the Franka class": (_FRANKA_PATH_KERNELS, _FRANKA_PATH_SECTIONS),
    "ik at an arm angle, nearly S-R-S": (_SELF_MOTION_KERNELS, _SELF_MOTION_SECTIONS),
    "arm-angles, nearly S-R-S": (_NEARLY_SETS_KERNELS, _NEARLY_SETS_SECTIONS),
    "collision-free sets, S-R-S": (CELL_SETS_KERNELS["psi"], CELL_SETS_SECTIONS["psi"]),
    "collision-free sets, Franka class": (CELL_SETS_KERNELS["q7"], CELL_SETS_SECTIONS["q7"]),
    "path in a cell": ((*CELL_SETS_KERNELS["psi"], *_CELL_PATH_KERNELS), (*CELL_SETS_SECTIONS["psi"], "paths")),
    "path of a nearly S-R-S arm, beside it": (_BESIDE_KERNELS["nearly"], _BESIDE_SECTIONS["nearly"]),
    "path in a cell, beside it": (_BESIDE_KERNELS["in a cell"], _BESIDE_SECTIONS["in a cell"]),
}


def _python(code: str, environment: dict[str, str]) -> object:
    """The value a fresh process prints last (``repr``), run with ``environment`` over this one's."""
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                            env={**os.environ, **environment}, timeout=900)
    return ast.literal_eval(result.stdout.splitlines()[-1])


@pytest.mark.parametrize("site", sorted(CALL_SITES))
def test_the_sections_a_command_starts_call_every_kernel_it_checks(site):
    """Running the sections a command names (``redkin compile --section``'s work) calls each kernel whose cache
    entry the command checks before it runs compiled: so once the background compile ends, it finds them all.
    Told in a fresh process on the ambient cache by the kernels' numba overloads after the sections ran."""
    kernels, sections = CALL_SITES[site]
    assert set(sections) <= set(SECTION_NAMES)
    code = "\n".join([
        "import importlib",
        "from redkin._compiled import use_compiled",
        "from redkin.warm_up import warm_up",
        "use_compiled()",
        f"warm_up(sections={sections!r})",
        f"names = {kernels!r}",
        "found = [getattr(importlib.import_module(n.rpartition('.')[0]), n.rpartition('.')[2]) for n in names]",
        "print([n for n, k in zip(names, found) if not getattr(k, 'overloads', None)])",
    ])
    assert _python(code, {}) == []


def test_compile_of_one_section_compiles_it_alone_into_the_cache(tmp_path, capsys):
    """``redkin compile --section chain`` on a fresh NUMBA_CACHE_DIR runs that section only, and leaves the chain's
    kernels cached there; an unknown section is refused with one line."""
    fresh = {"NUMBA_CACHE_DIR": str(tmp_path / "fresh")}
    out = _python("\n".join([
        "import contextlib, io",
        "from redkin.cli.main import main",
        "out = io.StringIO()",
        "with contextlib.redirect_stdout(out):",
        "    code = main(['compile', '--section', 'chain', '--processes', '1', '--json'])",
        "print((code, out.getvalue()))",
    ]), fresh)
    code, text = out
    assert code == 0 and [section["name"] for section in json.loads(text)["sections"]] == ["chain"]
    cached = ("redkin._chain_kernels.frames", "redkin._chain_kernels.jacobian")
    assert _python("from redkin.cli.common import kernels_compiled\n"
                   f"print((kernels_compiled({cached!r}), kernels_compiled({_FRANKA_PATH_KERNELS!r})))",
                   fresh) == (True, False)
    code, _, err = run(capsys, ["compile", "--section", "no such section"])
    assert code == 2 and len(err.strip().splitlines()) == 1 and "invalid choice" in err


def test_one_compile_per_cache(tmp_path, monkeypatch, capsys):
    """While a process holds the cache's compile lock, another ``redkin compile --background`` of it does nothing, and
    no command starts one; once the lock is free, :func:`start` starts one (that exits here at once, the lock held
    again by the test when it looks)."""
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path / "fresh"))
    monkeypatch.setenv(_ENVIRONMENT, "1")
    assert not _compile_running()
    with compile_lock() as held:
        assert held and _compile_running()
        assert start(["chain"]) is None
        code, out, err = run(capsys, ["compile", "--background", "--section", "chain"])
        assert (code, out, err) == (0, "", "")
        assert [path.name for path in (tmp_path / "fresh").rglob("*")] == ["redkin-compile.lock"]  # compiled nothing
    assert not _compile_running() and _lock_path().exists()
    monkeypatch.setenv(_ENVIRONMENT, "0")
    assert start(["chain"]) is None


@pytest.mark.slow
def test_an_explorer_page_run_as_python_compiles_its_kernels_in_the_background(tmp_path):
    """On a fresh cache with background compiles on, ``explore`` on the iiwa14 runs as Python, says it started
    ``redkin compile --background`` of its sections and names the process; once that ends, the page's kernels are
    cached and the same command runs compiled."""
    fresh = {"NUMBA_CACHE_DIR": str(tmp_path / "fresh"), _ENVIRONMENT: "1"}
    argv = ["explore", "kuka-iiwa14", "--q", "0.3", "0.6", "0.1", "-1.2", "0.2", "0.8", "0.1"]
    code = "\n".join([
        "import contextlib, io, sys",
        "from redkin.cli.main import main",
        "err = io.StringIO()",
        "with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):",
        "    code = main({argv!r})",
        "print((code, 'numba' in sys.modules, err.getvalue()))",
    ])
    status, compiled, err = _python(code.format(argv=[*argv, "--out", str(tmp_path / "a.html")]), fresh)
    assert (status, compiled) == (0, False) and "runs as Python" in err
    assert "compiling in the background now (process " in err
    pid = int(err.split("(process ")[1].split(",")[0])
    _wait_for_other(pid, 600)
    assert _python("from redkin.cli.common import kernels_compiled\n"
                   f"print(kernels_compiled({_PAGE_KERNELS['psi']!r}))", fresh) is True
    status, compiled, err = _python(code.format(argv=[*argv, "--out", str(tmp_path / "b.html")]), fresh)
    assert (status, compiled, err) == (0, True, "")
    assert (tmp_path / "a.html").read_text() == (tmp_path / "b.html").read_text()


def _wait_for_other(pid: int, seconds: float) -> None:
    """Wait until process ``pid`` (not a child of this one: its parent has ended) has ended, for at most ``seconds``
    (a zombie has ended: the container's first process may not reap orphans)."""
    end = time.monotonic() + seconds
    stat = Path(f"/proc/{pid}/stat")
    while time.monotonic() < end:
        try:
            if stat.read_text().rpartition(")")[2].split()[0] == "Z":
                return
        except OSError:  # gone
            return
        time.sleep(0.2)
    os.kill(pid, 9)
    pytest.fail(f"the background compile {pid} did not end in {seconds} s")


def test_within_seconds_stops_python_work_in_time_and_puts_the_handler_back():
    """A Python loop is stopped by :class:`OverTime` after the time, not before; work that ends in time is not; the
    previous ``SIGALRM`` handler and a quiet timer are back after either."""
    import signal

    before = signal.getsignal(signal.SIGALRM)
    start_time = time.monotonic()
    with pytest.raises(OverTime), within_seconds(0.3):
        while True:
            pass
    assert time.monotonic() - start_time >= 0.3
    with within_seconds(5.0):
        total = sum(range(1000))
    assert total == 499500 and signal.getsignal(signal.SIGALRM) is before
    assert signal.getitimer(signal.ITIMER_REAL) == (0.0, 0.0)


def _nearly_arm_angles(seconds: float, capsys) -> tuple[str, str, bool, str]:
    """``arm-angles --json`` of one Gen3 pose in a fresh process on the ambient cache, with its kernels taken as not
    cached (the fresh-cache case, without the minute of compiling) and a compile running in the background taken as
    started: run as Python for at most ``seconds``.  Returns that process's JSON and stderr, whether it ended with
    numba loaded (the compiled run), and the JSON of the same command in this process (compiled)."""
    pose = ["--position", "0.08199414787611689", "-0.038629829126462185", "1.0553268325600618", "--quat",
            "0.943956742111449", "0.04961524895985603", "0.08989862028824464", "-0.31369130393311984"]
    argv = ["arm-angles", "kinova-gen3", *pose, "--json"]
    code = "\n".join([
        "import contextlib, io, sys",
        "import redkin.cli.srs as srs",
        "srs.kernels_compiled = lambda kernels: False",
        "srs.background_compiles = lambda: True",
        "srs.compiling_later = lambda sections: 'compiling in the background (stand-in)'",
        f"srs._PYTHON_SECONDS = {seconds!r}",
        "from redkin.cli.main import main",
        "out, err = io.StringIO(), io.StringIO()",
        "with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):",
        f"    status = main({argv!r})",
        "print((status, out.getvalue(), err.getvalue(), 'numba' in sys.modules))",
    ])
    status, out, err, compiled = _python(code, {})
    assert status == 0
    here_status, here, _ = run(capsys, argv)
    assert here_status == 0
    return out, err, compiled, here


@pytest.mark.slow
def test_a_nearly_pose_runs_as_python_while_its_kernels_compile_and_gives_the_compiled_answer(capsys):
    """``arm-angles`` on a Gen3 pose whose kernels are not cached runs as Python (10-15 s), says so, and prints the
    JSON the compiled command prints, number for number."""
    out, err, compiled, here = _nearly_arm_angles(300.0, capsys)
    assert not compiled and "so it runs as Python for up to 300 s" in err and "stand-in" in err
    assert json.loads(out) == json.loads(here)


def test_a_nearly_pose_over_its_python_time_waits_for_the_compile_and_runs_compiled(capsys):
    """Past its time as Python, ``arm-angles`` says so, waits for the compile (none runs here) and answers compiled,
    as the compiled command does."""
    out, err, compiled, here = _nearly_arm_angles(0.3, capsys)
    assert compiled and "still running as Python after 0 s" in err
    assert json.loads(out) == json.loads(here)


def _spawned(seconds: float) -> int:
    """The process id of a child of this process that sleeps ``seconds``."""
    return os.posix_spawn("/bin/sleep", ["sleep", str(seconds)], dict(os.environ))


def _ended(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return True
    return False


def test_compiled_beside_compiles_here_while_the_other_process_runs_then_waits_for_it(monkeypatch, capsys):
    """Where the kernels are not on disk, :func:`compiled_beside` starts the sections' compile, says so naming the
    process, runs ``first`` while that process runs, and returns once it has ended (reaped); where they are on disk,
    or no compile could be started, it does nothing of this (everything then compiles in this process)."""
    import redkin._compiled
    import redkin.cli.background_compile as background
    from redkin.cli.common import compiled_beside

    started: list[tuple[str, ...]] = []
    children: list[int] = []

    def start(sections):
        started.append(tuple(sections))
        children.append(_spawned(0.5))
        return children[-1]

    monkeypatch.setattr(background, "start", start)
    monkeypatch.setattr(redkin._compiled, "kernels_on_disk", lambda *kernels: False)
    seen: list[bool] = []
    kernels, sections = _BESIDE_KERNELS["nearly"], _BESIDE_SECTIONS["nearly"]
    compiled_beside(kernels, sections, "the test's kernels", lambda: seen.append(_ended(children[-1])))
    err = capsys.readouterr().err
    assert started == [sections] and seen == [False]  # first ran while the other process did
    assert f"compiling the test's kernels in a second process beside this one (process {children[-1]}," in err
    assert _ended(children[-1])  # waited for and reaped, not a zombie
    monkeypatch.setattr(background, "start", lambda sections: None)
    compiled_beside(kernels, sections, "the test's kernels", lambda: seen.append(True))
    monkeypatch.setattr(redkin._compiled, "kernels_on_disk", lambda *kernels: True)
    monkeypatch.setattr(background, "start", start)
    compiled_beside(kernels, sections, "the test's kernels", lambda: seen.append(True))
    assert seen == [False] and len(started) == 1 and capsys.readouterr().err == ""


#: Each path that compiles from its first call in two processes: its robot, key poses' tool position, the extra
#: arguments, and the kernels its own process must not compile (the second process's).  An S-R-S arm's path in a
#: cell runs as Python up to 400 waypoints while its kernels are not cached (the key poses 0.05 m apart: 501 at
#: --step 0.0001).
BESIDE = {
    "nearly S-R-S": ("kinova-gen3", [0.3, 0.0, 0.6], ["--step", "0.01"], ("traced", "sweep")),
    "Franka class in a cell": ("franka-panda", [0.45, 0.0, 0.4], ["--step", "0.01", "--scene", "{cell}"],
                               ("clearances", "sweep")),
    "S-R-S in a cell": ("kuka-iiwa14", [0.5, 0.0, 0.4], ["--step", "0.0001", "--scene", "{cell}"],
                        ("clearances", "sweep")),
}


@pytest.mark.slow
@pytest.mark.parametrize("case", sorted(BESIDE))
def test_a_first_path_compiles_in_two_processes(tmp_path, case):
    """On a fresh cache with background compiles on, a first ``path`` on a nearly S-R-S arm (or in a cell, of the
    Franka class or an S-R-S arm) compiles the certified self-motion's (the distances') and the search's kernels in a
    second process while it compiles the IK's (the q7 sets', the limit sets'): it says so, compiles none of the
    second process's kernels itself (the sections' calls compile them with the path's own types, so it loads them
    from the cache), and prints the path the command prints on the ambient cache."""
    robot, position, extra, elsewhere = BESIDE[case]
    keys = [np.eye(4), np.eye(4)]
    for key in keys:
        key[:3, :3] = [[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]]
        key[:3, 3] = position
    keys[1][1, 3] -= 0.05
    (tmp_path / "keys.json").write_text(json.dumps([key.tolist() for key in keys]))
    (tmp_path / "cell.yaml").write_text("margin: 0.01\nobstacles:\n  - {name: table, type: box, center: [0.5, 0, "
                                        "-0.05], size: [0.6, 0.8, 0.1]}\n")
    argv = ["path", robot, "--through", str(tmp_path / "keys.json"), "--max-step", "0.1", "--json",
            *(argument.format(cell=tmp_path / "cell.yaml") for argument in extra)]
    code = "\n".join([
        "import contextlib, io",
        "from redkin.cli.main import main",
        "out, err = io.StringIO(), io.StringIO()",
        "with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):",
        f"    status = main({argv!r})",
        "print((status, out.getvalue(), err.getvalue()))",
    ])
    status, out, err = _python(code, {"NUMBA_CACHE_DIR": str(tmp_path / "fresh"), _ENVIRONMENT: "1",
                                      "REDKIN_COMPILE_NOTICE": "1"})
    assert status == 0 and "in a second process beside this one (process " in err
    assert "kernels compiled in" in err  # this process compiled the rest, with its notices on
    for kernel in elsewhere:
        assert f"compiling {kernel}" not in err
    here_status, here, _ = _python(code, {})
    assert here_status == 0 and json.loads(out) == json.loads(here)
