"""docs/equations.md stays true: its names import, each equation appears once, and each named function cites it.

The citation form in the code is ``[000 eq. 21]``, ``[000 eqs. 13-15, 17-19]``, ``[001 eq. 3.19]`` or
``[001 eqs. 3.8-3.14]``: the paper's number, then equations separated by ``, ``, each one number or a range.
"""

from __future__ import annotations

import importlib
import inspect
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
INDEX = ROOT / "docs" / "equations.md"

#: The numbered equations of each paper (issue 16; the thesis numbers by chapter, as its seed does).
EQUATIONS = {
    "000": [str(k) for k in range(1, 41)],
    "001": [f"2.{k}" for k in range(1, 4)] + [f"3.{k}" for k in range(1, 27)]
    + [f"4.{k}" for k in range(1, 12)] + [f"5.{k}" for k in range(1, 4)],
    "003": [str(k) for k in range(1, 27)],
    "004": [str(k) for k in range(1, 28)],
    # redkin's own derivation of the Franka class (docs/franka.md), cited [F1] .. [F10]
    "F": [f"F{k}" for k in range(1, 11)],
    # redkin's numerical pose IK (docs/numerical-ik.md), cited [N1] .. [N5]
    "N": [f"N{k}" for k in range(1, 6)],
    # redkin's certified self-motion of nearly S-R-S arms (docs/srs.md), cited [C1] .. [C6]
    "C": [f"C{k}" for k in range(1, 7)],
}

HEADING = re.compile(r"^## (\d{3}|F|N|C):")
NAME = re.compile(r"`(redkin(?:\.\w+)+)`")
LINK = re.compile(r"\]\(\.\./(src/redkin/[\w/]+\.py)\)")
CITATION = re.compile(r"\[(\d{3}) eqs?\. ([0-9., -]+?)\]")
#: A citation of our own derivations: ``[F2]``, or a range ``[F1]-[F7]`` (likewise ``[N1]``, ``[C1]``).
OWN_CITATION = re.compile(r"\[([FNC])(\d+)\](?:-\[[FNC](\d+)\])?")


def _rows() -> dict[str, list[list[str]]]:
    """The table rows of each paper's section: ``{paper: [[eq, what, implemented by, notes], ...]}``."""
    rows: dict[str, list[list[str]]] = {}
    paper = None
    for line in INDEX.read_text(encoding="utf-8").splitlines():
        heading = HEADING.match(line)
        if heading:
            paper = heading.group(1)
            rows.setdefault(paper, [])
        elif paper and line.startswith("| ") and not line.startswith("| eq. |"):
            cells = [cell.strip().replace("\\|", "|") for cell in re.split(r"(?<!\\)\|", line.strip()[1:-1])]
            assert len(cells) == 4, f"paper {paper}: a row needs 4 cells, got {len(cells)}: {line}"
            rows[paper].append(cells)
    return rows


ROWS = _rows()


def _resolve(name: str):
    """The object a dotted name ``redkin.module.attribute[.attribute]`` names: the longest importable module,
    then attributes."""
    parts = name.split(".")
    for split in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:split]))
        except ModuleNotFoundError:
            continue
        for attribute in parts[split:]:
            obj = getattr(obj, attribute)
        return obj
    raise ModuleNotFoundError(name)


def _expand(items: str) -> set[str]:
    """``"13-15, 17"`` -> ``{"13", "14", "15", "17"}``; ``"3.8-3.14"`` -> ``{"3.8", ..., "3.14"}``."""
    numbers = set()
    for item in items.split(", "):
        if "-" not in item:
            numbers.add(item)
            continue
        first, last = item.split("-")
        head, _, start = first.rpartition(".")
        last_head, _, end = last.rpartition(".")
        assert head == last_head, f"a range stays within one chapter: {item!r}"
        prefix = f"{head}." if head else ""
        numbers.update(f"{prefix}{k}" for k in range(int(start), int(end) + 1))
    return numbers


def _cited(obj, paper: str) -> set[str]:
    """The equations of ``paper`` that the source of ``obj`` (comments and docstring included) cites."""
    target = getattr(obj, "py_func", obj)  # a compiled kernel: its Python source
    try:
        text = inspect.getsource(target)
    except TypeError:  # a cached property or other descriptor
        text = inspect.getsource(target.func) if hasattr(target, "func") else (target.__doc__ or "")
    if paper in ("F", "N", "C"):
        return {f"{paper}{k}" for m in OWN_CITATION.finditer(text) if m.group(1) == paper
                for k in range(int(m.group(2)), int(m.group(3) or m.group(2)) + 1)}
    return set().union(*(_expand(m.group(2)) for m in CITATION.finditer(text) if m.group(1) == paper))


def test_every_paper_has_a_table():
    assert sorted(ROWS) == sorted(EQUATIONS)


@pytest.mark.parametrize("paper", sorted(EQUATIONS))
def test_every_equation_appears_exactly_once(paper):
    numbers = [row[0] for row in ROWS[paper]]
    duplicates = sorted({n for n in numbers if numbers.count(n) > 1})
    assert not duplicates, f"paper {paper}: equations listed more than once: {duplicates}"
    assert numbers == EQUATIONS[paper], (
        f"paper {paper}: missing {sorted(set(EQUATIONS[paper]) - set(numbers))}, "
        f"extra {sorted(set(numbers) - set(EQUATIONS[paper]))} (or out of order)"
    )


@pytest.mark.parametrize("paper", sorted(EQUATIONS))
def test_every_row_names_code_or_says_not_used(paper):
    for number, _, implemented, notes in ROWS[paper]:
        names = NAME.findall(implemented)
        if implemented == "—":
            assert notes.startswith("not used: "), f"[{paper} eq. {number}] names no code but does not say 'not used: '"
        else:
            assert names, f"[{paper} eq. {number}]: the 'implemented by' cell names no redkin.* function"
            assert not notes.startswith("not used"), f"[{paper} eq. {number}] names code and says 'not used'"


@pytest.mark.parametrize("paper", sorted(EQUATIONS))
def test_every_name_resolves_and_every_link_is_its_file(paper):
    for number, *cells in ROWS[paper]:
        for cell in cells:
            for name in NAME.findall(cell):
                _resolve(name)  # raises if the module or an attribute is gone
        implemented = cells[1]
        linked = set(LINK.findall(implemented))
        for path in linked:
            assert (ROOT / path).is_file(), f"[{paper} eq. {number}]: no file {path}"
        for name in NAME.findall(implemented):
            obj = _resolve(name)
            module = inspect.getmodule(getattr(obj, "py_func", getattr(obj, "func", obj)))
            if module is None:  # a cached property: its owner's module
                module = importlib.import_module(name.rsplit(".", 2)[0])
            source = Path(module.__file__).resolve().relative_to(ROOT).as_posix()
            assert source in linked, f"[{paper} eq. {number}]: {name} lives in {source}, which the row does not link"


@pytest.mark.parametrize("paper", sorted(EQUATIONS))
def test_every_named_function_cites_its_equation(paper):
    missing = []
    for number, _, implemented, _ in ROWS[paper]:
        for name in NAME.findall(implemented):
            if number not in _cited(_resolve(name), paper):
                missing.append(f"{name} does not cite [{paper} eq. {number}]")
    assert not missing, "\n".join(missing)


def test_citation_ranges_expand():
    assert _expand("13-15, 17-19") == {"13", "14", "15", "17", "18", "19"}
    assert _expand("3.8-3.14") == {f"3.{k}" for k in range(8, 15)}
    assert _expand("2.1") == {"2.1"}


BARE = re.compile(r"(?<!\[\d\d\d )\b[Ee]qs?\. ?\d")


def test_the_code_cites_equations_in_one_form():
    """Every equation number in ``src/`` and ``tests/`` is written ``[000 eq. N]``: a bare number names no paper."""
    bare = []
    for path in sorted((ROOT / "src").rglob("*.py")) + sorted((ROOT / "tests").rglob("*.py")):
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            if BARE.search(line):
                bare.append(f"{path.relative_to(ROOT)}:{number}: {line.strip()}")
    assert not bare, "\n".join(bare)
