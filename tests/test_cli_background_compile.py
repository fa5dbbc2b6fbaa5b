"""A command that ran as Python on a fresh cache compiles its kernels in the background (redkin.cli.background_compile):
``redkin compile --section``, the lock that keeps one compile per cache, and the sections each such command names."""

import ast
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

from redkin.cli.background_compile import _ENVIRONMENT, _lock_path, compile_lock, compile_running, start
from redkin.cli.explore import _PAGE_KERNELS, _PAGE_SECTIONS
from redkin.cli.path import _FRANKA_PATH_KERNELS
from redkin.cli.srs import _SELF_MOTION_KERNELS, _SELF_MOTION_SECTIONS
from redkin.warm_up import SECTION_NAMES
from tests.support.cli import run

#: Each command that runs as Python until its kernels are cached: the kernels it checks and the sections it starts.
CALL_SITES = {
    "explorer page, S-R-S": (_PAGE_KERNELS["psi"], _PAGE_SECTIONS["psi"]),
    "explorer page, Franka class": (_PAGE_KERNELS["q7"], _PAGE_SECTIONS["q7"]),
    "path of the Franka class": (_FRANKA_PATH_KERNELS, ("franka", "paths")),
    "ik at an arm angle, nearly S-R-S": (_SELF_MOTION_KERNELS, _SELF_MOTION_SECTIONS),
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
    assert not compile_running()
    with compile_lock() as held:
        assert held and compile_running()
        assert start(["chain"]) is None
        code, out, err = run(capsys, ["compile", "--background", "--section", "chain"])
        assert (code, out, err) == (0, "", "")
        assert not (tmp_path / "fresh").exists()  # compiled nothing
    assert not compile_running() and _lock_path().exists()
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
