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
