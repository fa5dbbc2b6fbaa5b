"""The suite cannot flake on a fresh draw: ``python -m pytest`` runs hypothesis derandomized (docs/testing.md).

The profiles are registered in tests/conftest.py: ``redkin`` (loaded there, what the README's command and
``.ci/run`` run) and ``explore`` (``--hypothesis-profile=explore``).  A test's own ``@settings(...)`` inherits the
loaded profile except what it passes, so no test may pass the options that make a run draw anew.
"""

from __future__ import annotations

import ast
import importlib
import sys
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

ROOT = Path(__file__).resolve().parents[1]
TESTS = ROOT / "tests"
#: What ``.ci/run`` and the README run: the README's second set-up command.
TEST_COMMAND = 'pip install -e ".[test]" && python -m pytest'


def _profile_option(request) -> str | None:
    return request.config.getoption("--hypothesis-profile", None)


def test_the_suite_runs_the_reproducible_profile(request):
    if _profile_option(request) not in (None, "redkin"):
        pytest.skip(f"a law of the reproducible profile, not of --hypothesis-profile={_profile_option(request)}")
    assert settings.get_current_profile_name().startswith("redkin")  # "redkin-with-verbose-verbosity" with that option
    current = settings()
    assert current.derandomize is True and current.database is None and current.deadline is None
    assert current.max_examples == 100  # hypothesis's own default: each test's @settings keeps its count


def test_the_explore_profile_draws_fresh_examples_and_keeps_failures():
    explore = settings.get_profile("explore")
    assert explore.derandomize is False and explore.deadline is None
    assert explore.database is not None and explore.max_examples == 100


def test_a_test_draws_the_same_examples_on_every_run(request):
    """The law the profile gives: two runs of one test draw the same examples (with no database to replay)."""
    if _profile_option(request) not in (None, "redkin"):
        pytest.skip(f"a law of the reproducible profile, not of --hypothesis-profile={_profile_option(request)}")
    runs: list[list] = []

    @settings(max_examples=20)
    @given(st.floats(-10, 10), st.integers(0, 1000))
    def law(x, n):
        runs[-1].append((x, n))

    for _ in range(2):
        runs.append([])
        law()
    assert len(runs[0]) == 20 and runs[0] == runs[1]


def test_the_draws_do_not_depend_on_the_numbers_in_our_modules(request, tmp_path, monkeypatch):
    """A module full of new constants in the drawn ranges, imported between two runs, changes nothing: under the
    derandomized profile hypothesis's pool of constants from local source is kept empty (tests/conftest.py), so an
    edit anywhere in src/ or tests/ does not change what an unrelated test draws."""
    if _profile_option(request) not in (None, "redkin"):
        pytest.skip(f"a law of the reproducible profile, not of --hypothesis-profile={_profile_option(request)}")
    runs: list[list] = []

    @settings(max_examples=300)
    @given(st.floats(-10, 10), st.integers(0, 1000))
    def law(x, n):
        runs[-1].append((x, n))

    runs.append([])
    law()
    numbers = [f"X{i} = {i * 0.0137 - 6.1}\nN{i} = {i * 3 + 1}" for i in range(400)]
    (tmp_path / "many_constants_for_hypothesis.py").write_text("\n".join(numbers) + "\n", encoding="utf-8")
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.delitem(sys.modules, "many_constants_for_hypothesis", raising=False)
    importlib.import_module("many_constants_for_hypothesis")  # a local module (not site-packages or stdlib)
    runs.append([])
    law()
    assert len(runs[0]) == 300 and runs[0] == runs[1]


def _settings_calls() -> list[tuple[str, int, ast.Call]]:
    """Every ``settings(...)``, ``register_profile``/``load_profile`` and ``@seed(...)`` call in the test modules."""
    calls = []
    for path in sorted(TESTS.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Call):
                name = node.func.attr if isinstance(node.func, ast.Attribute) else getattr(node.func, "id", "")
                if name == "seed" and not isinstance(node.func, ast.Name):  # numpy's seed(...), not hypothesis's
                    continue
                if name in ("settings", "register_profile", "load_profile", "seed"):
                    calls.append((f"{path.relative_to(ROOT)}:{node.lineno}", name, node))
    return calls


def test_no_test_overrides_what_makes_the_run_reproducible():
    """No ``@settings`` turns derandomize off or brings a database back, no ``@seed`` or positional parent settings
    object stands in for the profile, and only tests/conftest.py registers or loads a profile."""
    calls = _settings_calls()
    assert len([c for c in calls if c[1] == "settings"]) >= 100  # the scan finds the suite's decorators
    wrong = []
    for where, name, call in calls:
        if name in ("register_profile", "load_profile"):
            if not where.startswith("tests/conftest.py:"):
                wrong.append(f"{where}: {name} outside tests/conftest.py")
            continue
        if name == "seed":
            wrong.append(f"{where}: @seed (the profile's derandomize fixes the draw)")
            continue
        if call.args:
            wrong.append(f"{where}: settings with a parent object")
        for keyword in call.keywords:
            if keyword.arg == "database" or keyword.arg is None:
                wrong.append(f"{where}: settings({keyword.arg or '**'}=...)")
            elif keyword.arg == "derandomize" and not (isinstance(keyword.value, ast.Constant)
                                                       and keyword.value.value is True):
                wrong.append(f"{where}: settings(derandomize={ast.unparse(keyword.value)})")
    assert wrong == []


def test_ci_runs_the_readmes_test_command_with_the_default_profile():
    """``.ci/run`` runs the README's command as it is, with no profile option or seed of its own."""
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8")
    assert TEST_COMMAND in readme and TEST_COMMAND in ci
    assert "hypothesis" not in ci.lower()
