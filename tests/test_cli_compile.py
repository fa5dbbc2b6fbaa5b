"""``redkin compile``: every compiled path called once, the sections' times and the cache named (issue 23)."""

from __future__ import annotations

import json

import pytest

from redkin.cli.main import main
from redkin.warm_up import _SECTIONS


@pytest.mark.slow
def test_compile_runs_every_section_and_names_the_cache(capsys):
    assert main(["compile", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert [section["name"] for section in out["sections"]] == [name for name, _ in _SECTIONS]
    assert all(section["wall_s"] >= 0.0 and section["cpu_s"] >= 0.0 for section in out["sections"])
    assert out["cache"] and out["kernels_compiled"] >= 0
    assert main(["compile"]) == 0  # text: one line per section, then what it did and where the cache is
    captured = capsys.readouterr()
    lines = captured.out.strip().splitlines()
    assert len(lines) == len(_SECTIONS) + 1 and "cache:" in lines[-1]
    assert captured.err.count("compiling: ") == len(_SECTIONS)  # progress on stderr, one line per section
    assert main(["compile", "--quiet"]) == 0 and capsys.readouterr().err == ""


@pytest.mark.slow
def test_compiling_in_several_processes_leaves_every_kernel_in_the_cache():
    """``redkin compile --processes 2`` hands the sections to two new processes, which write one cache: a process
    that then calls every compiled path compiles nothing (a lost index entry, or a cache one process emptied under
    the other, would be compiled again here).  On the suite's cache, filled or not."""
    import os
    import subprocess
    import sys

    def compile_json(processes: int) -> dict:
        result = subprocess.run([sys.executable, "-m", "redkin.cli.main", "compile", "--quiet", "--json",
                                 "--processes", str(processes)], capture_output=True, text=True, check=True,
                                env=dict(os.environ))
        return json.loads(result.stdout)

    parallel = compile_json(2)
    assert parallel["processes"] == 2 and [section["name"] for section in parallel["sections"]] == \
        [name for name, _ in _SECTIONS]
    again = compile_json(1)
    assert again["processes"] == 1 and again["kernels_compiled"] == 0 and again["cache"] == parallel["cache"]


def test_a_section_another_calls_again_is_handed_out_just_before_it():
    """With several processes, a section whose kernels a longer section calls again on the way goes to a process
    just before that one (the longer one then loads them, instead of a second process compiling them at once):
    in the order :func:`redkin.warm_up.warm_up` hands sections out, each such pair is adjacent, the called first."""
    from redkin.warm_up import _CALLED_AGAIN_BY, SECTION_NAMES, _handed_out_by

    order = sorted(SECTION_NAMES, key=lambda name: (-_handed_out_by(name), SECTION_NAMES.index(name)))
    for called, caller in _CALLED_AGAIN_BY.items():
        assert order.index(caller) == order.index(called) + 1, order


@pytest.mark.parametrize("processes", ["0", "-1"])
def test_compile_refuses_fewer_than_one_process(capsys, processes):
    with pytest.raises(SystemExit) as stop:
        raise SystemExit(main(["compile", "--processes", processes]))
    assert stop.value.code == 2
    assert capsys.readouterr().err.strip() == f"redkin: error: --processes must be at least 1, got {processes}"


#: In a fresh process: every compiled path called once (what ``redkin compile`` runs), then each redkin kernel's
#: compiled signatures, as (kernel, [argument types as text], [literal argument positions], key without mutability).
_SIGNATURES = r"""
import sys
import numba
from numba.core import types
from redkin.warm_up import warm_up
from redkin._compiled import set_compile_notice
set_compile_notice(False)
warm_up()
seen = set()
for name, module in sorted(sys.modules.items()):
    if not name.startswith("redkin"):
        continue
    for value in vars(module).values():
        if isinstance(value, numba.core.registry.CPUDispatcher) and id(value) not in seen:
            seen.add(id(value))
            kernel = value.py_func.__module__ + "." + value.py_func.__qualname__
            for signature in value.signatures:
                literal = [k for k, t in enumerate(signature) if isinstance(t, types.Literal)]
                plain = tuple(str(t.copy(readonly=False)) if isinstance(t, types.Array) else str(t) for t in signature)
                print(repr((kernel, [str(t) for t in signature], literal, plain)))
"""


@pytest.mark.slow
def test_every_kernel_compiles_once_per_argument_type(tmp_path):
    """Issue 42: a constant passed from one kernel to another is a literal type to numba (``f(x, 0)`` compiles ``f``
    for ``Literal[int](0)``, again for ``4``, and again for ``int64``), and a read-only array is another type than a
    writeable one; each costs a whole compile of the callee and its callees.  After every compiled path has run,
    no kernel has a literal argument type, and no two of a kernel's signatures differ only in an array's
    mutability (the Franka kernels' float and complex twins are two argument types, on purpose).

    The process compiles every kernel into an empty cache (about 2 minutes on 2 cores): a kernel loaded from a
    filled cache brings its callees' code along without compiling them, and their signatures would not be seen.
    """
    import ast
    import os
    import subprocess
    import sys

    environment = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path))
    result = subprocess.run([sys.executable, "-c", _SIGNATURES], capture_output=True, text=True, check=True,
                            env=environment)
    rows = [ast.literal_eval(line) for line in result.stdout.splitlines() if line.startswith("(")]
    assert len({kernel for kernel, *_ in rows}) > 200  # every kernel, callees too, was compiled here and seen
    assert [(kernel, types) for kernel, types, literal, _ in rows if literal] == []
    kept: dict = {}
    for kernel, types, _, plain in rows:
        kept.setdefault((kernel, plain), []).append(types)
    assert {key: found for key, found in kept.items() if len(found) > 1} == {}
